# Blender materials as isotrace materials. The Principled BSDF maps by its
# dominant lobe: emission, transmission (glass), metallic (conductor), then
# a plastic (diffuse base under a clear coat of the IOR that Blender's
# specular gives) or, without specular, a diffuse surface. Roughness is
# perceptual roughness in both. What cannot be mapped falls back to the
# material's base (viewport) colour, with a warning naming the material.
import math
import os

import bpy

DEFAULT_NAME = "isotrace default"
SMOOTH_ROUGHNESS = 0.032
LINEAR_SPACES = {"Non-Color", "Linear", "Linear ACES", "Raw", "XYZ"}  # isotrace treats alpha = r^2 below 0.001 as smooth
DEFAULT_MATERIAL = {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}


def _value(node, name):
    socket = node.inputs.get(name)
    if socket is None:
        return None
    value = socket.default_value
    try:
        return [float(v) for v in value][:3]
    except TypeError:
        return float(value)


def _linked(node, names):
    return [n for n in names if node.inputs.get(n) is not None and node.inputs[n].is_linked]


def _surface_node(material):
    if not material.use_nodes or material.node_tree is None:
        return None
    for node in material.node_tree.nodes:
        if node.type == "OUTPUT_MATERIAL" and node.is_active_output:
            socket = node.inputs.get("Surface")
            if socket is not None and socket.is_linked:
                return socket.links[0].from_node
    return None


def _clamp01(color):
    return [min(max(c, 0.0), 1.0) for c in color]


def _ior_from_specular(specular):
    # Blender: normal-incidence reflectance F0 = 0.08 specular (0.5 -> IOR 1.5).
    f0 = min(max(0.08 * specular, 1e-6), 0.99)
    root = math.sqrt(f0)
    return min((1 + root) / (1 - root), 10.0)


def _image_texture(node, socket_name, name, warnings, scalar=False):
    """The isotrace image texture an Image Texture node gives the socket
    (placed by the mesh's UVs), or None with a warning."""
    socket = node.inputs[socket_name]
    source = socket.links[0].from_node if socket.is_linked else None
    if source is None or source.type != "TEX_IMAGE" or source.image is None:
        return None
    image = source.image
    path = bpy.path.abspath(image.filepath, library=image.library)
    if not os.path.isfile(path):
        warnings.append(f'material "{name}": image "{image.name}" of its {socket_name} is not a file on disk '
                        '(packed or generated); its value is used instead')
        return None
    if source.inputs["Vector"].is_linked:
        warnings.append(f'material "{name}": the mapping of its {socket_name} image is ignored (the UVs are used)')
    if scalar and not (image.depth in (8, 16) and not image.is_float):
        warnings.append(f'material "{name}": its {socket_name} image "{image.name}" is not one grey channel; '
                        'its value is used instead')
        return None
    space = "linear" if image.colorspace_settings.name in LINEAR_SPACES else "srgb"
    return {"type": "image", "file": os.path.abspath(path), "mapping": "uv", "color_space": space}


def _principled(node, name, warnings):
    base = _clamp01(_value(node, "Base Color"))
    roughness = min(max(_value(node, "Roughness"), 0.0), 1.0)
    base = _image_texture(node, "Base Color", name, warnings) or base
    roughness = _image_texture(node, "Roughness", name, warnings, scalar=True) or roughness
    emission = _value(node, "Emission") or [0.0, 0.0, 0.0]
    strength = _value(node, "Emission Strength")
    strength = 1.0 if strength is None else strength
    textured = [s for s in _linked(node, ["Base Color", "Roughness", "Metallic", "Transmission", "Normal", "Emission"])
                if not (s == "Base Color" and isinstance(base, dict)) and not (s == "Roughness" and isinstance(roughness, dict))]
    if textured:
        warnings.append(f'material "{name}": inputs driven by other nodes ({", ".join(textured)}) are not exported; '
                        'their values as set in the Principled BSDF are used')
    if max(emission) * strength > 0:
        return {"type": "emissive", "radiance": [c * strength for c in emission]}
    metallic, transmission = _value(node, "Metallic"), _value(node, "Transmission")
    for label, value in (("metallic", metallic), ("transmission", transmission)):
        if 0.0 < value < 1.0:
            warnings.append(f'material "{name}": {label} {value:g} is exported as {1 if value >= 0.5 else 0} '
                            '(isotrace materials are one lobe)')
    if transmission >= 0.5:
        ior = _value(node, "IOR")
        return {"type": "dielectric", "ior": min(max(ior, 1.0001), 10.0), "roughness": roughness, "transmittance": base}
    if metallic >= 0.5:
        reflectance = base if isinstance(base, dict) else [min(c, 0.999) for c in base]
        return {"type": "conductor", "reflectance": reflectance, "roughness": roughness}
    specular = _value(node, "Specular")
    if specular <= 0:
        return {"type": "diffuse", "albedo": base}
    return {"type": "plastic", "albedo": base, "ior": max(_ior_from_specular(specular), 1.0001), "roughness": roughness}


def convert_material(material, warnings):
    """The isotrace description of a Blender material."""
    name = material.name
    node = _surface_node(material)
    if node is not None:
        if node.type == "BSDF_PRINCIPLED":
            return _principled(node, name, warnings)
        if node.type == "BSDF_DIFFUSE":
            return {"type": "diffuse", "albedo": _clamp01(_value(node, "Color"))}
        if node.type == "EMISSION":
            strength = _value(node, "Strength")
            return {"type": "emissive", "radiance": [c * strength for c in _value(node, "Color")]}
        if node.type == "BSDF_GLASS":
            return {"type": "dielectric", "ior": min(max(_value(node, "IOR"), 1.0001), 10.0),
                    "roughness": min(max(_value(node, "Roughness"), 0.0), 1.0),
                    "transmittance": _clamp01(_value(node, "Color"))}
        if node.type == "BSDF_GLOSSY":
            # Blender's Glossy has no Fresnel term: smooth, it is a mirror
            # of its colour at every angle; rough, the nearest is a conductor.
            color, roughness = _clamp01(_value(node, "Color")), min(max(_value(node, "Roughness"), 0.0), 1.0)
            if roughness < SMOOTH_ROUGHNESS:
                return {"type": "mirror", "reflectance": color}
            return {"type": "conductor", "reflectance": [min(c, 0.999) for c in color], "roughness": roughness}
        warnings.append(f'material "{name}": its surface node "{node.name}" ({node.type}) cannot be mapped; '
                        'it is rendered diffuse in its viewport colour')
    elif material.use_nodes:
        warnings.append(f'material "{name}" has no surface shader; it is rendered diffuse in its viewport colour')
    return {"type": "diffuse", "albedo": _clamp01(list(material.diffuse_color)[:3])}


def uses_uvs(description):
    """Whether a material description holds a texture placed by UVs."""
    if isinstance(description, dict):
        return description.get("mapping") == "uv" or any(uses_uvs(v) for v in description.values())
    return False
