# The add-on renders a Blender scene of meshes, a metaball family with a
# negative element, an implicit CSG subtraction, area, sun, point and spot
# lights and Principled materials (diffuse, metal, glass); its image is bit
# for bit that of `isotrace render` run on the scene it exported.
import json
import math
import os
import sys
import unittest

import bpy
import addon_test_support as support


def build_scene():
    scene = support.empty_scene(80, 60)
    scene.render.engine = "ISOTRACE"
    settings = scene.isotrace
    settings.samples, settings.max_depth, settings.threads, settings.seed = 4, 6, 2, 3
    support.add_camera(scene, (0.5, -8.0, 3.5), (0, 0, 0.8))
    white = support.principled("White", (0.8, 0.8, 0.8), specular=0.0)
    metal = support.principled("Gold", (0.9, 0.7, 0.3), metallic=1.0, roughness=0.3)
    glass = support.principled("Glass", transmission=1.0, roughness=0.0, ior=1.45)
    plastic = support.principled("Red plastic", (0.7, 0.1, 0.1), roughness=0.4)
    support.add_mesh(scene, bpy.ops.mesh.primitive_plane_add, white, size=20)
    support.add_mesh(scene, bpy.ops.mesh.primitive_cube_add, metal, size=0.8, location=(-2.6, 0.5, 0.4))
    sphere = support.add_mesh(scene, bpy.ops.mesh.primitive_uv_sphere_add, glass, radius=0.5, location=(-1.2, -1.5, 0.5))
    bpy.ops.object.shade_smooth()
    support.add_metaball_family(scene, plastic)
    support.add_carved_box(scene, metal, (2.3, 0.0, 0.7))
    support.add_light(scene, "Area", "AREA", (0, -1, 5), 400, size=2.0)
    support.add_light(scene, "Sun", "SUN", (3, -2, 6), 1.5)
    support.add_light(scene, "Point", "POINT", (-3, -3, 3), 300, shadow_soft_size=0.0)
    support.add_light(scene, "Spot", "SPOT", (3, -3, 4), 500, target=(2.3, 0, 0.7), spot_size=math.radians(40),
                      spot_blend=0.3, shadow_soft_size=0.0)
    support.set_world_color(scene, (0.05, 0.06, 0.08))
    return scene, sphere


class RenderEngineTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.addon = support.install_addon()

    def test_render_equals_a_direct_isotrace_render_of_the_exported_scene(self):
        scene, _ = build_scene()
        export = os.path.join(support.FOLDER, "export")
        through_blender = support.render_keeping_export(scene, "through_blender", export)
        with open(os.path.join(export, "scene.json")) as f:
            exported = json.load(f)
        # What the scene holds reached the file: traced fields, not meshes,
        # for the metaballs and the CSG subtraction.
        types = {name: field["type"] for name, field in exported["fields"].items()}
        self.assertEqual(types.get("metaballs Blob"), "blobby")
        self.assertEqual(types.get("object Carved"), "difference")
        blobs = exported["fields"]["metaballs Blob"]["blobs"]
        self.assertEqual(len(blobs), 4)
        self.assertEqual(sum(b["weight"] < 0 for b in blobs), 1)
        self.assertEqual(sorted(l["type"] for l in exported["lights"]), ["directional", "environment", "point", "quad", "spot"])
        self.assertEqual(sorted(m["type"] for m in exported["materials"].values()),
                         ["conductor", "dielectric", "diffuse", "plastic"])
        self.assertNotIn("Cutter", [o["name"] for o in exported["objects"]])  # hidden in renders
        # Smooth faces are smooth, flat ones flat.
        self.assertEqual({o["smooth"] for o in exported["objects"] if o["name"] == "Sphere"}, {True})
        self.assertEqual({o["smooth"] for o in exported["objects"] if o["name"] == "Cube"}, {False})
        # Blender's own polygonization of the metaballs is not exported beside them.
        self.assertEqual([o for o in exported["objects"] if o["name"].startswith("Blob") and "field" not in o], [])
        direct = os.path.join(support.FOLDER, "direct.exr")
        run = support.isotrace("render", os.path.join(export, "scene.json"), "-o", direct, "--seed", "3",
                               "--threads", "2", "--no-preview", "-q")
        self.assertEqual(run.returncode, 0, run.stderr)
        a, b = support.read_rgb(through_blender), support.read_rgb(direct)
        self.assertEqual((a.width, a.height), (80, 60))
        self.assertGreater(a.mean(), 0.01)
        differing = sum(x != y for x, y in zip(a.rgb, b.rgb))
        self.assertEqual(differing, 0, "values that differ between the two images")
        self.assertEqual(len(a.rgb), len(b.rgb))

    def test_aovs_fill_blenders_passes(self):
        try:
            import OpenImageIO
        except ImportError:
            self.skipTest("python3-openimageio is not installed: the add-on fills only the Combined pass")
        scene, _ = build_scene()
        layer = scene.view_layers[0]
        layer.use_pass_z = layer.use_pass_normal = layer.use_pass_diffuse_color = True
        scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
        export = os.path.join(support.FOLDER, "export_aov")
        through_blender = support.render_keeping_export(scene, "aov", export)
        direct = os.path.join(support.FOLDER, "direct_aov.exr")
        run = support.isotrace("render", os.path.join(export, "scene.json"), "-o", direct, "--seed", "3",
                               "--aov", "depth,normal,albedo,id,steps", "--no-preview", "-q")
        self.assertEqual(run.returncode, 0, run.stderr)

        def channels(path):
            image = OpenImageIO.ImageBuf(path)
            names = list(image.spec().channelnames)
            pixels = image.get_pixels(OpenImageIO.FLOAT)
            return {name: pixels[:, :, i] for i, name in enumerate(names)}

        blender, isotrace = channels(through_blender), channels(direct)
        pairs = {"ViewLayer.Depth.Z": "Z", "ViewLayer.Normal.X": "N.X", "ViewLayer.Normal.Z": "N.Z",
                 "ViewLayer.DiffCol.R": "albedo.R", "ViewLayer.DiffCol.B": "albedo.B",
                 "ViewLayer.isotrace Object.X": "id", "ViewLayer.isotrace Steps.X": "steps",
                 "ViewLayer.Combined.G": "G"}
        for ours, theirs in pairs.items():
            self.assertIn(ours, blender, sorted(blender))
            self.assertTrue((blender[ours] == isotrace[theirs]).all(), ours)
        self.assertGreater(float(isotrace["steps"].max()), 0.0)
        self.assertGreater(float(isotrace["albedo.R"].max()), 0.1)

    def test_instances_share_one_mesh(self):
        scene = support.empty_scene(64, 48)
        scene.render.engine = "ISOTRACE"
        scene.isotrace.samples = 4
        support.add_camera(scene, (0, -12, 6), (0, 0, 0))
        grey = support.principled("Grey", specular=0.0)
        parts = bpy.data.collections.new("Parts")  # not in the scene: only its instances are
        bpy.ops.mesh.primitive_cube_add(size=0.5)
        cube = bpy.context.active_object
        cube.data.materials.append(grey)
        scene.collection.objects.unlink(cube)
        parts.objects.link(cube)
        for i in range(40):
            holder = bpy.data.objects.new(f"Instance {i}", None)
            holder.instance_type = "COLLECTION"
            holder.instance_collection = parts
            holder.location = ((i % 8) - 3.5, (i // 8) - 2.0, 0.0)
            holder.rotation_euler = (0.0, 0.0, 0.3 * i)
            scene.collection.objects.link(holder)
        support.set_world_color(scene, (1.0, 1.0, 1.0))
        folder = os.path.join(support.FOLDER, "instances")
        exported = self.addon.export.export_scene(bpy.context.evaluated_depsgraph_get(), folder)
        with open(exported.scene_path) as f:
            objects = json.load(f)["objects"]
        self.assertEqual(len(objects), 40)
        self.assertEqual(len({o["mesh"] for o in objects}), 1)  # one file, placed 40 times
        self.assertEqual(len(os.listdir(os.path.join(folder, "meshes"))), 1)
        # The same 40 cubes made real objects: the same image within noise.
        instanced = support.read_rgb(support.render_to(scene, "instanced"))
        bpy.ops.object.select_all(action="DESELECT")
        for holder in [o for o in scene.objects if o.instance_type == "COLLECTION"]:
            holder.select_set(True)
        bpy.context.view_layer.objects.active = scene.objects["Instance 0"]
        bpy.ops.object.duplicates_make_real()
        copies = self.addon.export.export_scene(bpy.context.evaluated_depsgraph_get(), os.path.join(support.FOLDER, "copies"))
        with open(copies.scene_path) as f:
            self.assertEqual(len(json.load(f)["objects"]), 40)
        real = support.read_rgb(support.render_to(scene, "real"))
        self.assertAlmostEqual(instanced.mean(), real.mean(), delta=2e-3)
        self.assertGreater(sum(abs(a - b) < 1e-3 for a, b in zip(instanced.rgb, real.rgb)), 0.98 * len(real.rgb))

    def test_image_textures_follow_the_uvs(self):
        scene = support.empty_scene(48, 48)
        scene.render.engine = "ISOTRACE"
        scene.isotrace.samples, scene.isotrace.pixel_filter = 16, "BOX"
        support.add_camera(scene, (0, 0, 4), (0, 0, 0), lens=50)
        # A 2 x 2 image: red and green on the top row, blue and white below.
        image = bpy.data.images.new("Quadrants", 2, 2)
        image.pixels = [0, 0, 1, 1, 1, 1, 1, 1,  # bottom row: blue, white
                        1, 0, 0, 1, 0, 1, 0, 1]  # top row: red, green
        image.filepath_raw = os.path.join(support.FOLDER, "quadrants.png")
        image.file_format = "PNG"
        image.save()
        material = support.principled("Textured", specular=0.0)
        nodes = material.node_tree.nodes
        texture = nodes.new("ShaderNodeTexImage")
        texture.image = image
        texture.interpolation = "Closest"
        material.node_tree.links.new(texture.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
        plane = support.add_mesh(scene, bpy.ops.mesh.primitive_plane_add, material, size=2.0)
        plane.rotation_euler = (0, 0, math.radians(90))  # the UVs turn with it
        support.set_world_color(scene, (1.0, 1.0, 1.0))
        folder = os.path.join(support.FOLDER, "textured")
        exported = self.addon.export.export_scene(bpy.context.evaluated_depsgraph_get(), folder)
        with open(exported.scene_path) as f:
            albedo = json.load(f)["materials"]["Textured"]["albedo"]
        self.assertEqual((albedo["type"], albedo["mapping"], albedo["color_space"]), ("image", "uv", "srgb"))
        picture = support.read_rgb(support.render_to(scene, "textured"))

        def quadrant(right, top):
            # Rows are stored bottom first; the plane fills the middle of the frame.
            x, y = (30 if right else 17), (30 if top else 17)
            i = 3 * (y * picture.width + x)
            return picture.rgb[i:i + 3]

        # Turned a quarter to the left, the image's top row runs down its left side.
        red, green = quadrant(False, False), quadrant(False, True)
        blue, white = quadrant(True, False), quadrant(True, True)
        self.assertGreater(red[0], 5 * red[2], red[:])
        self.assertGreater(green[1], 5 * green[0], green[:])
        self.assertGreater(blue[2], 5 * blue[0], blue[:])
        self.assertGreater(min(white), 0.5, white[:])

    def test_preview_mesh_is_the_polygonized_field(self):
        scene = support.empty_scene()
        ball = bpy.data.objects.new("Ball", bpy.data.meshes.new("Ball"))
        ball.isotrace.field_kind = "PRIMITIVE"
        ball.isotrace.primitive = "torus"
        ball.isotrace.major_radius, ball.isotrace.minor_radius = 0.8, 0.2
        scene.collection.objects.link(ball)
        bpy.context.view_layer.objects.active = ball
        self.assertEqual(bpy.ops.isotrace.update_preview(), {"FINISHED"})
        vertices = [v.co for v in ball.data.vertices]
        self.assertGreater(len(vertices), 100)
        # A ring about the object's Z axis: radii from 0.6 to 1.0, heights within 0.2.
        radii = [math.hypot(v.x, v.y) for v in vertices]
        self.assertAlmostEqual(min(radii), 0.6, delta=0.02)
        self.assertAlmostEqual(max(radii), 1.0, delta=0.02)
        self.assertAlmostEqual(max(abs(v.z) for v in vertices), 0.2, delta=0.02)


if __name__ == "__main__":
    result = unittest.main(argv=[sys.argv[0]], exit=False).result
    sys.exit(0 if result.wasSuccessful() else 1)
