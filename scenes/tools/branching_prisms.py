#!/usr/bin/env python3
"""Normal constraints of a recursively branching structure of triangular
prisms, after the branching figure of Turk and O'Brien (1999): a trunk whose
top splits into two thinner prisms, three levels deep. Prints the "normals"
rows of scenes/variational_figures.json."""
import json
import math


def rotate_z(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1], v[2])


def prism(base, axis_angle, length, radius, rows, level):
    # Axis direction in the x-y plane, tilted from +y by axis_angle.
    axis = rotate_z((0.0, 1.0, 0.0), axis_angle)
    top = tuple(base[i] + length * axis[i] for i in range(3))
    # Branches start inside their parent's top, so only the trunk has a bottom ring.
    ends = ((0, base), (1, top)) if level == 0 else ((1, top),)
    for end, centre in ends:
        for k in range(3):
            a = 2 * math.pi * k / 3 + (math.pi / 3 if level % 2 else 0.0) + end * 0.2
            radial = rotate_z((math.cos(a), 0.0, math.sin(a)), axis_angle)
            p = tuple(centre[i] + radius * radial[i] for i in range(3))
            cap = -1.0 if end == 0 else 1.0
            n = tuple(radial[i] + 0.5 * cap * axis[i] for i in range(3))
            norm = math.sqrt(sum(x * x for x in n))
            rows.append([round(x, 6) for x in p] + [round(x / norm, 6) for x in n])
    if level < 2:
        for side in (-1, 1):
            prism(top, axis_angle + side * 0.6, 0.75 * length, 0.7 * radius, rows, level + 1)


rows = []
prism((0.0, -1.0, 0.0), 0.0, 1.0, 0.28, rows, 0)
print(json.dumps(rows))
