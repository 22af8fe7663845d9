# The render engine: F12 and `blender -b file.blend -E ISOTRACE -f 1`.
# It exports the scene to a temporary folder, runs `isotrace render` there
# with its progress in Blender's progress bar (Esc ends the process), and
# loads the EXR into the render result.
import os
import re
import subprocess
import tempfile
import threading
import time

import bpy

from . import binary, export, properties

PROGRESS = re.compile(r"render:\s+(\d+)%")
OBJECT_POINTER = re.compile(r"/objects/(\d+)")


# Every message the engine reported, newest last: what Blender shows in its
# status bar and info log, kept for scripts and tests.
REPORTS = []


class Outcome:
    def __init__(self, status, warnings=(), errors=()):
        self.status = status  # "ok", "failed" or "cancelled"
        self.warnings, self.errors = list(warnings), list(errors)


def run_process(command, object_names, progress, cancelled):
    """Runs isotrace, passing its progress on and ending it when `cancelled()`."""
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines = []

    def read(stream):
        for line in stream:
            lines.append(line.rstrip("\n"))
            match = PROGRESS.search(line)
            if match:
                progress(int(match.group(1)) / 100.0)

    readers = [threading.Thread(target=read, args=(s,), daemon=True) for s in (process.stdout, process.stderr)]
    for reader in readers:
        reader.start()
    try:
        while process.poll() is None:
            if cancelled():
                process.terminate()
                try:
                    process.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()
                return Outcome("cancelled")
            time.sleep(0.05)
    finally:
        for reader in readers:
            reader.join(timeout=5)
        process.stdout.close()
        process.stderr.close()
    warnings = [with_object_names(l, object_names) for l in lines if l.startswith("warning:")]
    if process.returncode != 0:
        errors = [l for l in lines if "error" in l] or lines[-3:]
        message = " ".join(with_object_names(l, object_names) for l in errors)
        return Outcome("failed", warnings, [f"isotrace render failed (exit {process.returncode}): {message}"])
    return Outcome("ok", warnings)


class IsotraceRenderEngine(bpy.types.RenderEngine):
    bl_idname = "ISOTRACE"
    bl_label = "isotrace"
    bl_use_preview = False
    bl_use_postprocess = True

    def tell(self, kind, message):
        REPORTS.append((kind, message))
        self.report({kind}, message)

    def render(self, depsgraph):
        scene = depsgraph.scene
        try:
            program = binary.find_binary(properties.preferred_binary(bpy.context))
            binary.check_version(program)
        except binary.BinaryError as e:
            self.tell("ERROR", str(e))
            return
        keep = os.environ.get("ISOTRACE_BLENDER_KEEP_EXPORT", "")
        folder = keep if keep else tempfile.mkdtemp(prefix="isotrace-blender-")
        os.makedirs(folder, exist_ok=True)
        try:
            self.update_stats("", "isotrace: exporting the scene")
            try:
                exported = export.export_scene(depsgraph, folder)
            except export.ExportError as e:
                self.tell("ERROR", f"isotrace: {e}")
                return
            for warning in exported.warnings:
                self.tell("WARNING", f"isotrace: {warning}")
            image = os.path.join(folder, "render.exr")
            settings = scene.isotrace
            command = [program, "render", exported.scene_path, "-o", image, "--seed", str(settings.seed), "--no-preview"]
            if settings.threads:
                command += ["--threads", str(settings.threads)]
            self.update_stats("", "isotrace: rendering")
            outcome = run_process(command, exported.object_names, self.update_progress, self.test_break)
            for warning in outcome.warnings:
                self.tell("WARNING", "isotrace: " + warning)
            for error in outcome.errors:
                self.tell("ERROR", error)
            if outcome.status == "cancelled":
                self.tell("INFO", "isotrace: render cancelled")
            if outcome.status == "ok" and os.path.isfile(image):
                result = self.begin_result(0, 0, exported.width, exported.height)
                result.layers[0].load_from_file(image)
                self.end_result(result)
        finally:
            if not keep:
                _remove_tree(folder)


def with_object_names(message, names):
    """isotrace names objects by their place (/objects/3); add Blender's name."""
    def name(match):
        index = int(match.group(1))
        return match.group(0) + (f' (object "{names[index]}")' if index < len(names) else "")
    return OBJECT_POINTER.sub(name, message)


def _remove_tree(folder):
    import shutil
    shutil.rmtree(folder, ignore_errors=True)


# Blender's own panels that apply to isotrace too (camera, lights, materials
# in their Cycles-independent form, output and dimensions).
COMPATIBLE_PANELS = (
    "RENDER_PT_format", "RENDER_PT_dimensions", "RENDER_PT_output", "RENDER_PT_color_management",
    "DATA_PT_lens", "DATA_PT_camera", "DATA_PT_camera_dof", "DATA_PT_camera_dof_aperture",
    "DATA_PT_light", "DATA_PT_EEVEE_light", "DATA_PT_spot", "DATA_PT_metaball", "DATA_PT_mball_texture_space",
    "DATA_PT_metaball_element", "MATERIAL_PT_preview", "EEVEE_MATERIAL_PT_context_material",
    "EEVEE_MATERIAL_PT_surface", "WORLD_PT_context_world", "EEVEE_WORLD_PT_surface",
)


def compatible_panels():
    for name in COMPATIBLE_PANELS:
        panel = getattr(bpy.types, name, None)
        if panel is not None and hasattr(panel, "COMPAT_ENGINES"):
            yield panel


def register():
    bpy.utils.register_class(IsotraceRenderEngine)
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.add(IsotraceRenderEngine.bl_idname)


def unregister():
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.discard(IsotraceRenderEngine.bl_idname)
    bpy.utils.unregister_class(IsotraceRenderEngine)
