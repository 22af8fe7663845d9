# A Blender scene (an evaluated depsgraph) as an isotrace scene folder:
# scene.json and one PLY file per mesh and material slot. Meshes that
# several objects or instances show are written once and placed by their
# transforms (isotrace instances them). Coordinates stay Blender's (Z up).
import json
import math
import os
import re
import sys
from array import array

from mathutils import Matrix, Vector

from . import fields, materials, metaballs

GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "FONT"}

# Blender's equirectangular maps put +X at the centre column, Y = +1 at a
# quarter, and Z up; isotrace's put -z at the centre, +x at three quarters
# and y up (docs/scene-format.md, lights): this rotation turns one into the other.
WORLD_FROM_ISOTRACE_MAP = Matrix(((0, 0, -1), (-1, 0, 0), (0, 1, 0)))


class ExportError(Exception):
    """The scene cannot be exported; the message says what to change."""


class Exported:
    def __init__(self, scene_path, warnings, object_names, width, height):
        self.scene_path = scene_path
        self.warnings = warnings
        self.object_names = object_names  # isotrace object index -> Blender object name
        self.width, self.height = width, height


def rows(matrix):
    return [list(matrix[i]) for i in range(4)]


def safe_file_name(name):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)[:80] or "mesh"


def write_ply(path, positions, triangles, uvs=None):
    """A binary PLY of float positions (x, y, z, ...), texture coordinates
    (s, t, ...) when given, and triangles (a, b, c, ...)."""
    count = len(positions) // 3
    if uvs is not None:
        interleaved = array("f", bytes(4 * 5 * count))
        for k in range(3):
            interleaved[k::5] = positions[k::3]
        interleaved[3::5], interleaved[4::5] = uvs[0::2], uvs[1::2]
        positions = interleaved
    if sys.byteorder != "little":
        positions, triangles = array("f", positions), array("i", triangles)
        positions.byteswap()
        triangles.byteswap()
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {count}\nproperty float x\nproperty float y\nproperty float z\n"
              + ("property float s\nproperty float t\n" if uvs is not None else "")
              + f"element face {len(triangles) // 3}\nproperty list uchar int vertex_indices\nend_header\n")
    raw = triangles.tobytes()
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(positions.tobytes())
        f.write(b"".join(b"\x03" + raw[i:i + 12] for i in range(0, len(raw), 12)))


def compacted(positions, triangles, corner_uvs=None):
    """The vertices `triangles` use (one per vertex and texture coordinate:
    UV seams split vertices), and the triangles renumbered to them; with
    `corner_uvs` (u, v per triangle corner) also the vertices' uvs."""
    index = {}
    kept, uvs = array("f"), array("f")
    renumbered = array("i", bytes(4 * len(triangles)))
    for k, v in enumerate(triangles):
        key = v if corner_uvs is None else (v, corner_uvs[2 * k], corner_uvs[2 * k + 1])
        new = index.get(key)
        if new is None:
            new = index[key] = len(index)
            kept.extend(positions[3 * v:3 * v + 3])
            if corner_uvs is not None:
                uvs.extend(corner_uvs[2 * k:2 * k + 2])
        renumbered[k] = new
    return kept, renumbered, (uvs if corner_uvs is not None else None)


class _Exporter:
    def __init__(self, depsgraph, folder):
        self.depsgraph = depsgraph
        self.scene = depsgraph.scene
        self.folder = folder
        self.warnings = []
        self.materials = {}
        self.fields = {}
        self.objects = []
        self.object_names = []
        self.lights = []
        self.mesh_files = {}  # mesh key -> [(file, slot, smooth)]

    # ---- materials -------------------------------------------------------

    def material_name(self, material):
        if material is None:
            self.materials.setdefault(materials.DEFAULT_NAME, materials.DEFAULT_MATERIAL)
            return materials.DEFAULT_NAME
        if material.name not in self.materials:
            self.materials[material.name] = materials.convert_material(material, self.warnings)
        return material.name

    def slot_material(self, obj, slot):
        slots = obj.material_slots
        return self.material_name(slots[slot].material if slot < len(slots) else None)

    # ---- geometry --------------------------------------------------------

    def add_object(self, description, name):
        description["name"] = name
        self.objects.append(description)
        self.object_names.append(name)

    def mesh_object(self, obj, world):
        # Objects without modifiers share their data's mesh; instances share
        # their object's.
        key = ("object:" + obj.original.name) if len(obj.modifiers) else ("data:" + obj.data.original.name)
        with_uvs = any(materials.uses_uvs(self.materials[self.slot_material(obj, slot)])
                       for slot in range(max(1, len(obj.material_slots))))
        key += ":uv" if with_uvs else ""
        if key not in self.mesh_files:
            self.mesh_files[key] = self.write_mesh(obj, key, with_uvs)
        for file, slot, smooth in self.mesh_files[key]:
            self.add_object({"mesh": file, "material": self.slot_material(obj, slot), "smooth": smooth,
                             "drop_degenerate": True, "transform": {"matrix": rows(world)}}, obj.name)

    def write_mesh(self, obj, key, with_uvs):
        mesh = obj.to_mesh()
        corner_uvs = None
        try:
            mesh.calc_loop_triangles()
            count = len(mesh.loop_triangles)
            positions = array("f", bytes(4 * 3 * len(mesh.vertices)))
            mesh.vertices.foreach_get("co", positions)
            triangles = array("i", bytes(4 * 3 * count))
            mesh.loop_triangles.foreach_get("vertices", triangles)
            slots = array("i", bytes(4 * count))
            mesh.loop_triangles.foreach_get("material_index", slots)
            smooth = [False] * count
            mesh.loop_triangles.foreach_get("use_smooth", smooth)
            layer = next((l for l in mesh.uv_layers if l.active_render), None) if with_uvs else None
            if with_uvs and layer is None:
                self.warnings.append(f'object "{obj.name}" has image textures placed by UVs but no UV map')
            if layer is not None:
                loops = array("i", bytes(4 * 3 * count))
                mesh.loop_triangles.foreach_get("loops", loops)
                loop_uvs = array("f", bytes(4 * 2 * len(layer.data)))
                layer.data.foreach_get("uv", loop_uvs)
                corner_uvs = array("f", bytes(4 * 2 * len(loops)))
                corner_uvs[0::2] = array("f", (loop_uvs[2 * l] for l in loops))
                corner_uvs[1::2] = array("f", (loop_uvs[2 * l + 1] for l in loops))
        finally:
            obj.to_mesh_clear()
        files = []
        os.makedirs(os.path.join(self.folder, "meshes"), exist_ok=True)
        # One file per material slot and shading: smooth faces get isotrace's
        # smooth normals, flat ones their own.
        for slot, smoothed in sorted({(slots[t], bool(smooth[t])) for t in range(count)}):
            file = f"meshes/{safe_file_name(key)}_{len(self.mesh_files)}_{slot}{'_smooth' if smoothed else ''}.ply"
            chosen = [t for t in range(count) if slots[t] == slot and bool(smooth[t]) == smoothed]
            if len(chosen) == count and corner_uvs is None:
                vertices, faces, uvs = positions, triangles, None
            else:
                picked, picked_uvs = array("i"), array("f")
                for t in chosen:
                    picked.extend(triangles[3 * t:3 * t + 3])
                    if corner_uvs is not None:
                        picked_uvs.extend(corner_uvs[6 * t:6 * t + 6])
                vertices, faces, uvs = compacted(positions, picked, picked_uvs if corner_uvs is not None else None)
            write_ply(os.path.join(self.folder, file), vertices, faces, uvs)
            files.append((file, slot, smoothed))
        return files

    def field_object(self, obj, world):
        name = "object " + obj.original.name
        if name not in self.fields:
            try:
                self.fields[name] = fields.object_field(obj.original, self.warnings)
            except fields.FieldError as e:
                raise ExportError(str(e)) from e
        self.add_object({"field": name, "material": self.slot_material(obj, 0), "transform": {"matrix": rows(world)}},
                        obj.name)

    def metaball_objects(self, members):
        for family, (basis, group) in metaballs.metaball_families(members).items():
            field = metaballs.family_field(group)
            if field is None:
                continue
            name = "metaballs " + family
            self.fields[name] = field
            self.add_object({"field": name, "material": self.slot_material(basis, 0)}, basis.name)

    # ---- lights, camera, world -------------------------------------------

    def light(self, obj, world):
        data = obj.data
        color = Vector(data.color)
        linear = world.to_3x3()
        position = list(world.translation)
        down = (linear @ Vector((0, 0, -1))).normalized()
        if data.type in {"POINT", "SPOT"}:
            if data.shadow_soft_size > 0:
                self.warnings.append(f'light "{obj.name}": its radius {data.shadow_soft_size:g} is ignored '
                                     '(isotrace point and spot lights are points)')
            intensity = list(color * (data.energy / (4 * math.pi)))
            if data.type == "POINT":
                return {"type": "point", "position": position, "intensity": intensity}
            return {"type": "spot", "position": position, "direction": list(down), "intensity": intensity,
                    "cone_angle": min(math.degrees(data.spot_size), 180.0), "blend": data.spot_blend}
        if data.type == "SUN":
            if data.angle > math.radians(1.0):
                self.warnings.append(f'light "{obj.name}": its angle {math.degrees(data.angle):.3g} degrees is ignored '
                                     '(isotrace directional lights are parallel)')
            return {"type": "directional", "direction": list(down), "irradiance": list(color * data.energy)}
        if data.type == "AREA":
            # Cycles 3.4 gives an area light of power P the radiance P / (4 A)
            # (its eval_fac, 0.25 / area), not P / (pi A).
            size_y = data.size_y if data.shape in {"RECTANGLE", "ELLIPSE"} else data.size
            ex, ey = linear @ Vector((data.size, 0, 0)), linear @ Vector((0, size_y, 0))
            if data.spread < math.pi - 1e-6:
                self.warnings.append(f'light "{obj.name}": its spread is ignored (isotrace area lights are Lambertian)')
            center = world.translation
            if data.shape in {"SQUARE", "RECTANGLE"}:
                area = ex.cross(ey).length
                return {"type": "quad", "corner": list(center - 0.5 * ex - 0.5 * ey), "edge1": list(ey),
                        "edge2": list(ex), "radiance": list(color * (data.energy / (4.0 * area)))}
            rx, ry = 0.5 * ex.length, 0.5 * ey.length
            if abs(rx - ry) > 1e-6 * max(rx, ry):
                self.warnings.append(f'light "{obj.name}": an ellipse is exported as the disk of the same area')
            radius = math.sqrt(rx * ry)
            area = math.pi * radius * radius
            return {"type": "disk", "center": list(center), "normal": list(-ex.cross(ey).normalized()),
                    "radius": radius, "radiance": list(color * (data.energy / (4.0 * area)))}
        self.warnings.append(f'light "{obj.name}": type {data.type} is not supported and is skipped')
        return None

    def camera(self, width, height):
        camera = self.scene.camera
        if camera is None:
            raise ExportError("the scene has no camera")
        camera = camera.evaluated_get(self.depsgraph)
        data = camera.data
        if data.type != "PERSP":
            raise ExportError(f'camera "{camera.name}": only perspective cameras are supported, not {data.type}')
        if data.shift_x or data.shift_y:
            self.warnings.append(f'camera "{camera.name}": lens shift is ignored')
        m = camera.matrix_world
        linear = m.to_3x3()
        eye = m.translation
        forward = (linear @ Vector((0, 0, -1))).normalized()
        up = (linear @ Vector((0, 1, 0))).normalized()
        fit = data.sensor_fit
        if fit == "AUTO":
            fit, sensor = ("HORIZONTAL" if width >= height else "VERTICAL"), data.sensor_width
        else:
            sensor = data.sensor_width if fit == "HORIZONTAL" else data.sensor_height
        tan_half = 0.5 * sensor / data.lens
        if fit == "HORIZONTAL":
            tan_half *= height / width
        description = {"from": list(eye), "up": list(up), "fov": math.degrees(2 * math.atan(tan_half))}
        focus = 1.0
        if data.dof.use_dof:
            focus = data.dof.focus_distance
            if data.dof.focus_object is not None:
                focus = max((data.dof.focus_object.matrix_world.translation - eye).dot(forward), 1e-6)
            description["aperture"] = data.lens * 1e-3 / data.dof.aperture_fstop
            description["focus_distance"] = max(focus, 1e-6)
        description["to"] = list(eye + forward * max(focus, 1e-6))
        return description

    def world(self):
        world = self.scene.world
        if world is None:
            return None
        if not world.use_nodes or world.node_tree is None:
            return {"type": "environment", "radiance": list(world.color)}
        output = next((n for n in world.node_tree.nodes if n.type == "OUTPUT_WORLD" and n.is_active_output), None)
        socket = output.inputs.get("Surface") if output else None
        if socket is None or not socket.is_linked:
            return None
        background = socket.links[0].from_node
        if background.type != "BACKGROUND":
            self.warnings.append(f'world "{world.name}": node {background.type} cannot be mapped; the world is black')
            return None
        strength = background.inputs["Strength"].default_value
        color_socket = background.inputs["Color"]
        if color_socket.is_linked:
            texture = color_socket.links[0].from_node
            image = getattr(texture, "image", None)
            if texture.type == "TEX_ENVIRONMENT" and image is not None:
                path = os.path.abspath(bpy_path_abspath(image.filepath, image))
                if os.path.isfile(path):
                    if texture.inputs["Vector"].is_linked:
                        self.warnings.append(f'world "{world.name}": the environment texture\'s mapping is ignored')
                    axis, angle = WORLD_FROM_ISOTRACE_MAP.to_quaternion().to_axis_angle()
                    return {"type": "environment", "file": path, "scale": strength,
                            "rotate": {"axis": list(axis), "angle": math.degrees(angle)}}
                self.warnings.append(f'world "{world.name}": image "{image.name}" is not a file on disk; '
                                     'the world uses its colour')
            else:
                self.warnings.append(f'world "{world.name}": its colour comes from a {texture.type} node, which cannot '
                                     'be mapped; the world uses the colour set in the Background node')
        return {"type": "environment", "radiance": [c * strength for c in list(color_socket.default_value)[:3]]}

    # ---- the scene ---------------------------------------------------------

    def run(self):
        scene = self.scene
        render = scene.render
        width = max(1, int(render.resolution_x * render.resolution_percentage / 100))
        height = max(1, int(render.resolution_y * render.resolution_percentage / 100))
        settings = scene.isotrace
        camera = self.camera(width, height)
        metaball_members = []
        for instance in self.depsgraph.object_instances:
            obj = instance.object
            world = instance.matrix_world.copy()
            if obj.original.type == "META":
                # A family's basis also comes as Blender's polygonization of
                # it (a mesh instance); the elements are traced instead.
                if obj.type == "META":
                    metaball_members.append((obj, world))
            elif obj.type == "LIGHT":
                light = self.light(obj, world)
                if light:
                    self.lights.append(light)
            elif fields.is_field_object(obj):
                self.field_object(obj, world)
            elif obj.type in GEOMETRY_TYPES:
                self.mesh_object(obj, world)
        self.metaball_objects(metaball_members)
        environment = self.world()
        if environment:
            self.lights.append(environment)
        description = {
            "camera": camera,
            "film": {"width": width, "height": height, "spp": settings.samples,
                     "filter": ({"type": "box", "radius": 0.5} if settings.pixel_filter == "BOX"
                                else {"type": "gaussian", "radius": 1.5, "sigma": 0.5})},
            "integrator": {"type": settings.integrator, "max_depth": settings.max_depth},
            "materials": self.materials,
            "fields": self.fields,
            "objects": self.objects,
            "lights": self.lights,
        }
        path = os.path.join(self.folder, "scene.json")
        with open(path, "w") as f:
            json.dump(description, f, indent=1)
        return Exported(path, self.warnings, self.object_names, width, height)


def bpy_path_abspath(path, image):
    import bpy
    return bpy.path.abspath(path, library=image.library)


def export_scene(depsgraph, folder):
    """Writes the scene into `folder`; returns an Exported."""
    return _Exporter(depsgraph, folder).run()
