# The viewport shows an isotrace object as its polygonization: `isotrace
# polygonize` of the object's field (with its Boolean operands), read back
# into the object's mesh.
import json
import os
import subprocess
import tempfile

import bpy

from . import binary, fields, properties, registration


def read_off(path):
    """Vertices and faces of an OFF file as isotrace writes it."""
    with open(path) as f:
        words = f.read().split()
    if not words or words[0] != "OFF":
        raise ValueError(f"{path}: not an OFF file")
    vertex_count, face_count = int(words[1]), int(words[2])
    at = 4
    vertices = []
    for _ in range(vertex_count):
        vertices.append((float(words[at]), float(words[at + 1]), float(words[at + 2])))
        at += 3
    faces = []
    for _ in range(face_count):
        n = int(words[at])
        faces.append(tuple(int(w) for w in words[at + 1:at + 1 + n]))
        at += 1 + n
    return vertices, faces


def polygonize(obj, program, warnings):
    """The object's field polygonized in its own frame: (vertices, faces)."""
    with tempfile.TemporaryDirectory(prefix="isotrace-preview-") as folder:
        scene = os.path.join(folder, "field.json")
        with open(scene, "w") as f:
            json.dump({"fields": {"shown": fields.object_field(obj, warnings)}}, f)
        mesh = os.path.join(folder, "preview.off")
        run = subprocess.run([program, "polygonize", scene, "--field", "shown", "-o", mesh, "--resolution",
                              str(obj.isotrace.preview_resolution)], capture_output=True, text=True)
        if run.returncode != 0:
            raise RuntimeError((run.stderr or run.stdout).strip())
        return read_off(mesh)


class ISOTRACE_OT_update_preview(bpy.types.Operator):
    """Replace the object's mesh by the polygonization of its isotrace field"""
    bl_idname = "isotrace.update_preview"
    bl_label = "Update Preview Mesh"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and fields.is_field_object(obj)

    def execute(self, context):
        obj = context.active_object
        warnings = []
        try:
            program = binary.find_binary(properties.preferred_binary(context))
            binary.check_version(program)
            # The preview is the object's own field: its Boolean modifiers
            # show their operands' previews in the viewport as Blender does.
            saved = [(m, m.show_render) for m in obj.modifiers]
            for modifier, _ in saved:
                modifier.show_render = False
            try:
                vertices, faces = polygonize(obj, program, warnings)
            finally:
                for modifier, shown in saved:
                    modifier.show_render = shown
        except (binary.BinaryError, fields.FieldError, RuntimeError, ValueError) as e:
            self.report({"ERROR"}, f"isotrace: {e}")
            return {"CANCELLED"}
        for w in warnings:
            self.report({"WARNING"}, f"isotrace: {w}")
        mesh = obj.data
        mesh.clear_geometry()
        mesh.from_pydata(vertices, [], faces)
        mesh.update()
        for polygon in mesh.polygons:
            polygon.use_smooth = True
        return {"FINISHED"}


CLASSES = (ISOTRACE_OT_update_preview,)


def register():
    registration.register_classes(CLASSES)


def unregister():
    registration.unregister_classes(CLASSES)
