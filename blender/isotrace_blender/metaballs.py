# Blender metaballs as isotrace blobby fields with the same surface.
# Blender's density (mball_tessellate.cc, densfunc) is, per element,
# s (1 - r^2 / R^2)^3 with r measured in the element's own frame from a
# point (ball, ellipsoid: the frame scaled by the sizes), a segment
# (capsule), a rectangle (plane) or a box (cube), stiffness s at most 10 and
# negative for negative elements; the surface is where the sum reaches the
# threshold. All metaball objects named Name, Name.001, ... form one family
# whose elements are summed, with the threshold and material of the family's
# basis (the one named Name).
import re

from mathutils import Matrix

FAMILY_NAME = re.compile(r"^(.*?)(?:\.(\d+))?$")
MAX_STIFFNESS = 10.0  # Blender clamps stiffness here too


def family_of(name):
    """(family name, number): "Mball.002" -> ("Mball", 2), "Mball" -> ("Mball", -1)."""
    match = FAMILY_NAME.match(name)
    return match.group(1), int(match.group(2)) if match.group(2) else -1


def element_blob(element, world):
    """One element as a blob of the poly6 kernel, in world space."""
    frame = world @ Matrix.Translation(element.co) @ element.rotation.to_matrix().to_4x4()
    axes = [frame.col[i].xyz for i in range(3)]
    blob = {"center": list(frame.translation), "radius": element.radius,
            "weight": min(element.stiffness, MAX_STIFFNESS) * (-1.0 if element.use_negative else 1.0)}
    kind = element.type
    if kind == "ELLIPSOID":
        axes = [axes[0] * element.size_x, axes[1] * element.size_y, axes[2] * element.size_z]
    elif kind == "CAPSULE":
        blob["half_size"] = [element.size_x, 0.0, 0.0]
    elif kind == "PLANE":
        blob["half_size"] = [element.size_x, element.size_y, 0.0]
    elif kind == "CUBE":
        blob["half_size"] = [element.size_x, element.size_y, element.size_z]
    blob["axes"] = [list(a) for a in axes]
    return blob


def metaball_families(objects):
    """{family: (basis object, [(object, world matrix), ...])} of the metaball
    objects among `objects` (evaluated objects with their world matrices)."""
    families = {}
    for obj, world in objects:
        name, number = family_of(obj.name)
        families.setdefault(name, []).append((number, obj.name, obj, world))
    result = {}
    for name, members in families.items():
        members.sort(key=lambda m: (m[0], m[1]))
        result[name] = (members[0][2], [(m[2], m[3]) for m in members])
    return result


def family_field(members):
    """The blobby field of one family's visible elements, or None when it has none."""
    basis = members[0][0]
    blobs = []
    for obj, world in members:
        if any(abs(v) < 1e-12 for v in world.to_scale()):
            continue  # Blender skips metaballs of zero scale
        blobs.extend(element_blob(e, world) for e in obj.data.elements if not e.hide)
    if not blobs:
        return None
    return {"type": "blobby", "kernel": "poly6", "threshold": max(basis.data.threshold, 1e-6), "blobs": blobs}
