# What goes wrong stays an error message and leaves Blender usable: a node
# tree the exporter cannot map warns and renders; a missing binary, a
# failing render and a cancelled render each end with a message, and the
# next render works.
import os
import sys
import time
import unittest

import bpy

import addon_test_support as support


def small_scene():
    scene = support.empty_scene(32, 24)
    scene.render.engine = "ISOTRACE"
    scene.isotrace.samples = 1
    support.add_camera(scene, (0, -5, 1), (0, 0, 0))
    support.add_mesh(scene, bpy.ops.mesh.primitive_cube_add, support.principled("Grey"), size=1.0)
    support.set_world_color(scene, (1.0, 1.0, 1.0))
    return scene


class BadCases(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.addon = support.install_addon()

    def setUp(self):
        self.engine = self.addon.engine
        self.engine.REPORTS.clear()

    def reports(self, level):
        return [message for kind, message in self.engine.REPORTS if kind == level]

    def render_works(self):
        self.engine.REPORTS.clear()
        path = support.render_to(small_scene(), "after")
        self.assertEqual(self.reports("ERROR"), [])
        self.assertGreater(support.read_rgb(path).mean(), 0.05)

    def test_unmappable_node_tree_warns_and_renders(self):
        scene = small_scene()
        toon = bpy.data.materials.new("Toon")
        toon.use_nodes = True
        toon.diffuse_color = (0.2, 0.4, 0.9, 1.0)
        nodes = toon.node_tree.nodes
        nodes.remove(nodes["Principled BSDF"])
        shader = nodes.new("ShaderNodeBsdfToon")
        toon.node_tree.links.new(shader.outputs[0], nodes["Material Output"].inputs["Surface"])
        cube = bpy.data.objects["Cube"]
        cube.data.materials.clear()
        cube.data.materials.append(toon)
        path = support.render_to(scene, "toon")
        self.assertTrue(any('material "Toon"' in w for w in self.reports("WARNING")), self.engine.REPORTS)
        self.assertEqual(self.reports("ERROR"), [])
        self.assertGreater(support.read_rgb(path).mean(), 0.05)

    def render_with_binary(self, binary):
        """Renders with ISOTRACE_BINARY set to `binary`; returns the one error
        reported. A script sees the engine's error report as an exception;
        the user sees it in the status bar."""
        saved = os.environ["ISOTRACE_BINARY"]
        os.environ["ISOTRACE_BINARY"] = binary
        try:
            with self.assertRaises(RuntimeError):
                bpy.ops.render.render()
        finally:
            os.environ["ISOTRACE_BINARY"] = saved
        errors = self.reports("ERROR")
        self.assertEqual(len(errors), 1, self.engine.REPORTS)
        return errors[0]

    def test_missing_binary_is_one_message(self):
        self.assertIn("/nonexistent/isotrace", self.render_with_binary("/nonexistent/isotrace"))
        self.render_works()

    def test_too_old_binary_is_one_message(self):
        old = os.path.join(support.FOLDER, "old-isotrace")
        with open(old, "w") as f:
            f.write("#!/bin/sh\necho 'isotrace 0.1.0 (numeric mode double, avx2 kernels)'\n")
        os.chmod(old, 0o755)
        error = self.render_with_binary(old)
        self.assertIn("0.1.0", error)
        self.assertIn("too old", error)
        self.render_works()

    def test_failing_render_names_the_object(self):
        scene = small_scene()
        text = bpy.data.texts.new("bad field")
        text.write('{"type": "sphere", "radius": -1}')
        ball = bpy.data.objects.new("Bad ball", bpy.data.meshes.new("Bad ball"))
        ball.isotrace.field_kind = "TEXT"
        ball.isotrace.text = text
        scene.collection.objects.link(ball)
        with self.assertRaises(RuntimeError):
            bpy.ops.render.render()
        errors = self.reports("ERROR")
        self.assertEqual(len(errors), 1, self.engine.REPORTS)
        self.assertIn("Bad ball", errors[0])
        self.assertIn("radius", errors[0])
        self.render_works()

    def test_cancelling_ends_the_process(self):
        # Esc in Blender makes test_break() true: the same path, driven here
        # by a render far longer than the wait.
        scene = small_scene()
        scene.render.resolution_x, scene.render.resolution_y = 640, 480
        scene.isotrace.samples = 4096
        folder = os.path.join(support.FOLDER, "cancel")
        os.makedirs(folder, exist_ok=True)
        exported = self.addon.export.export_scene(bpy.context.evaluated_depsgraph_get(), folder)
        started = time.monotonic()
        outcome = self.engine.run_process(
            [os.environ["ISOTRACE_BINARY"], "render", exported.scene_path, "-o", os.path.join(folder, "x.exr")],
            exported.object_names, progress=lambda fraction: None, cancelled=lambda: time.monotonic() > started + 1.0)
        self.assertEqual(outcome.status, "cancelled")
        self.assertLess(time.monotonic() - started, 20.0)
        self.assertFalse(os.path.exists(os.path.join(folder, "x.exr")))
        self.render_works()


if __name__ == "__main__":
    result = unittest.main(argv=[sys.argv[0]], exit=False).result
    sys.exit(0 if result.wasSuccessful() else 1)
