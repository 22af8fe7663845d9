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

try:  # Debian: python3-openimageio and python3-numpy; without them only Combined is filled
    import numpy
    import OpenImageIO
except ImportError:
    numpy = OpenImageIO = None

PROGRESS = re.compile(r"render:\s+(\d+)%")
OBJECT_POINTER = re.compile(r"/objects/(\d+)")


# isotrace's AOVs as Blender's passes: (pass, view-layer switch, channels,
# channel letters, kind, --aov name, the EXR's channels).
STANDARD_PASSES = (
    ("Depth", "use_pass_z", "Z", "VALUE", "depth", ("Z",)),
    ("Normal", "use_pass_normal", "XYZ", "VECTOR", "normal", ("N.X", "N.Y", "N.Z")),
    ("DiffCol", "use_pass_diffuse_color", "RGB", "COLOR", "albedo", ("albedo.R", "albedo.G", "albedo.B")),
)
# The others, always there as named passes: the object isotrace found first
# in the pixel (its index among the exported objects) and sphere-tracing steps.
NAMED_PASSES = (("isotrace Object", "id", "id"), ("isotrace Steps", "steps", "steps"))


def wanted_passes(view_layer):
    """(pass name, --aov name, EXR channels) of the passes to fill."""
    if OpenImageIO is None:
        return []
    passes = [(name, aov, channels) for name, switch, _, _, aov, channels in STANDARD_PASSES
              if getattr(view_layer, switch)]
    return passes + [(name, aov, (channel,)) for name, aov, channel in NAMED_PASSES]


def fill_passes(layer, image, passes):
    """Copies the EXR's colour (alpha 1) and AOV channels into the layer's passes."""
    source = OpenImageIO.ImageInput.open(image)
    if source is None:
        raise RuntimeError(f"cannot read {image}: {OpenImageIO.geterror()}")
    try:
        spec = source.spec()
        pixels = source.read_image(0, 0, 0, spec.nchannels, "float")
    finally:
        source.close()
    names = list(spec.channelnames)
    rows = pixels[::-1]  # Blender's rows run bottom up
    rgba = numpy.ones(rows.shape[:2] + (4,), dtype=numpy.float32)
    rgba[:, :, :3] = rows[:, :, [names.index(c) for c in "RGB"]]
    # foreach_set takes the (pixels, channels) array whole: 4 ms at 1080p, where
    # assigning rect costs about a second.
    layer.passes.find_by_name("Combined", "").rect.foreach_set(rgba.reshape(-1, 4))
    for name, _, channels in passes:
        render_pass = layer.passes.find_by_name(name, "")
        if render_pass is not None:
            columns = [names.index(c) for c in channels]
            render_pass.rect.foreach_set(numpy.ascontiguousarray(rows[:, :, columns]).reshape(-1, len(columns)))


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

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        if OpenImageIO is None:
            return
        for name, switch, letters, kind, _, _ in STANDARD_PASSES:
            if getattr(renderlayer, switch):
                self.register_pass(scene, renderlayer, name, len(letters), letters, kind)
        for name, _, _ in NAMED_PASSES:
            self.register_pass(scene, renderlayer, name, 1, "X", "VALUE")

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
            passes = wanted_passes(depsgraph.view_layer)
            if passes:
                command += ["--aov", ",".join(aov for _, aov, _ in passes)]
            for name, _, channels in passes:
                if name.startswith("isotrace"):
                    self.add_pass(name, len(channels), "X")
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
                try:
                    if passes:
                        fill_passes(result.layers[0], image, passes)
                    else:
                        result.layers[0].load_from_file(image)
                except (RuntimeError, ValueError, OSError) as e:
                    self.tell("ERROR", f"isotrace: cannot load the rendered image: {e}")
                finally:
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
