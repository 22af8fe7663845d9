# Implicit objects authored in Blender: an object's isotrace field in its
# own frame, and its Boolean modifiers on other isotrace objects as CSG.
import json
import math

# Fields whose axis is y in isotrace (torus ring in xz, cylinder and cone
# along y, the heart's y up) turn so that it is the object's Z, as in Blender.
Y_TO_Z = {"axis": [1, 0, 0], "angle": 90}
OPERATIONS = {"DIFFERENCE": "difference", "UNION": "union", "INTERSECT": "intersection"}


class FieldError(Exception):
    """An object's field cannot be described; the message names the object."""


def is_field_object(obj):
    return getattr(obj, "isotrace", None) is not None and obj.isotrace.field_kind != "NONE"


def local_field(obj):
    """The field of `obj` in its own frame (a description, JSON-ready)."""
    s = obj.isotrace
    if s.field_kind == "PRIMITIVE":
        p = s.primitive
        if p == "sphere":
            return {"type": "sphere", "radius": s.radius}
        if p == "box":
            size = list(s.size)
            if 2 * s.rounding > min(size):
                raise FieldError(f'object "{obj.name}": box rounding {s.rounding} exceeds half its shortest edge')
            return {"type": "box", "size": size, "rounding": s.rounding}
        if p == "ellipsoid":
            return {"type": "ellipsoid", "radii": [0.5 * v for v in s.size]}
        if p == "octahedron":
            return {"type": "octahedron", "size": s.radius}
        if p == "capsule":
            return {"type": "capsule", "from": [0, 0, -0.5 * s.height], "to": [0, 0, 0.5 * s.height], "radius": s.radius}
        if p == "torus":
            shape = {"type": "torus", "major": s.major_radius, "minor": s.minor_radius}
        elif p == "cylinder":
            shape = {"type": "cylinder", "radius": s.radius, "height": s.height}
        else:
            shape = {"type": "cone", "radius": s.radius, "top_radius": s.top_radius, "height": s.height}
        return {"type": "transform", "rotate": Y_TO_Z, "of": shape}
    if s.field_kind == "PRESET":
        return {"type": "transform", "rotate": Y_TO_Z, "of": {"type": "polynomial", "preset": s.preset}}
    if s.field_kind == "TEXT":
        if s.text is None:
            raise FieldError(f'object "{obj.name}": its isotrace field names no text block')
        try:
            return json.loads(s.text.as_string())
        except json.JSONDecodeError as e:
            raise FieldError(f'object "{obj.name}": text "{s.text.name}" line {e.lineno}, column {e.colno}: {e.msg}') from e
    raise FieldError(f'object "{obj.name}" has no isotrace field')


def decomposed(matrix, name, warnings):
    """An isotrace transform (scale, rotate, translate) equal to `matrix`; a
    warning when it shears, which such a transform cannot hold."""
    location, rotation, scale = matrix.decompose()
    axis, angle = rotation.to_axis_angle()
    if min(abs(v) for v in scale) <= 0:
        raise FieldError(f'object "{name}" has a zero scale')
    recomposed = _compose(location, rotation, scale)
    if max(abs(recomposed[i][j] - matrix[i][j]) for i in range(3) for j in range(4)) > 1e-5 * max(1.0, max(abs(v) for v in scale)):
        warnings.append(f'object "{name}": its transform shears, which an isotrace field transform cannot; the shear is dropped')
    transform = {"translate": list(location), "scale": [abs(v) for v in scale]}
    if abs(angle) > 1e-12:
        transform["rotate"] = {"axis": list(axis), "angle": math.degrees(angle)}
    return transform


def _compose(location, rotation, scale):
    from mathutils import Matrix
    return Matrix.Translation(location) @ rotation.to_matrix().to_4x4() @ Matrix.Diagonal((*scale, 1.0))


def object_field(obj, warnings, visiting=()):
    """The field `obj` shows in its own frame: its field combined with the
    isotrace objects of its Boolean modifiers, in order."""
    if obj.name in visiting:
        raise FieldError(f'object "{obj.name}": its Boolean modifiers form a cycle')
    field = local_field(obj)
    inverse = obj.matrix_world.inverted_safe()
    for modifier in obj.modifiers:
        if not modifier.show_render:
            continue
        if modifier.type != "BOOLEAN":
            warnings.append(f'object "{obj.name}": modifier "{modifier.name}" ({modifier.type}) does not apply to an '
                            'isotrace field and is ignored')
            continue
        operand = modifier.object if modifier.operand_type == "OBJECT" else None
        if operand is None or not is_field_object(operand):
            warnings.append(f'object "{obj.name}": Boolean "{modifier.name}" needs an isotrace object as its operand; '
                            'it is ignored')
            continue
        other = object_field(operand, warnings, visiting + (obj.name,))
        placed = dict(decomposed(inverse @ operand.matrix_world, operand.name, warnings), type="transform", of=other)
        operation = OPERATIONS[modifier.operation]
        if obj.isotrace.blend_radius > 0:
            field = {"type": "smooth_" + operation, "radius": obj.isotrace.blend_radius, "of": [field, placed]}
        else:
            field = {"type": operation, "of": [field, placed]}
    return field
