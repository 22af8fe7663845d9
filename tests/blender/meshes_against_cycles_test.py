# The same Blender scene of meshes rendered by Cycles and by isotrace (the
# add-on's export): diffuse, glass and mirror surfaces under area, sun,
# point and spot lights and a coloured world, both unbiased, with box pixel
# filters and no clamping. Their images must agree to within their noise:
# image means per channel within four standard errors, and the mean FLIP
# between the renderers no more than between two seeds of one renderer.
import json
import math
import os
import sys
import time
import unittest

import bpy

import addon_test_support as support

SAMPLES = 256
WIDTH, HEIGHT = 64, 48


def node_material(name, kind, **inputs):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    shader = nodes.new(kind)
    for key, value in inputs.items():
        shader.inputs[key].default_value = value
    material.node_tree.links.new(shader.outputs[0], nodes["Material Output"].inputs["Surface"])
    return material


def environment_map():
    """A 64 x 32 latitude-longitude EXR whose colour tells the direction:
    red across the azimuth, green down from the zenith, a bright patch."""
    path = os.path.join(support.FOLDER, "sky.exr")
    if not os.path.exists(path):
        image = bpy.data.images.new("Sky", 64, 32, float_buffer=True)
        pixels = []
        for row in range(32):  # bottom row first
            for column in range(64):
                bright = 4.0 if 40 <= column < 46 and 20 <= row < 25 else 0.0
                pixels += [0.1 + 0.6 * column / 63 + bright, 0.1 + 0.5 * row / 31 + bright, 0.3 + bright, 1.0]
        image.pixels = pixels
        image.filepath_raw = path
        image.file_format = "OPEN_EXR"
        image.save()
    return path


def scene_for(engine, seed, portrait=False):
    scene = support.empty_scene(*((HEIGHT, WIDTH) if portrait else (WIDTH, HEIGHT)))
    scene.render.engine = engine
    camera = support.add_camera(scene, (0.5, -7.0, 3.0), (0, 0, 0.6))
    grey = node_material("Grey", "ShaderNodeBsdfDiffuse", Color=(0.6, 0.6, 0.6, 1))
    red = node_material("Red", "ShaderNodeBsdfDiffuse", Color=(0.7, 0.15, 0.1, 1))
    glass = node_material("Glass", "ShaderNodeBsdfGlass", IOR=1.45, Roughness=0.0)
    mirror = node_material("Mirror", "ShaderNodeBsdfGlossy", Color=(0.8, 0.8, 0.8, 1), Roughness=0.0)
    support.add_mesh(scene, bpy.ops.mesh.primitive_plane_add, grey, size=16)
    support.add_mesh(scene, bpy.ops.mesh.primitive_cube_add, red, size=1.0, location=(-1.6, 0.4, 0.5))
    support.add_mesh(scene, bpy.ops.mesh.primitive_ico_sphere_add, glass, radius=0.6, subdivisions=3, location=(0.2, -0.8, 0.6))
    support.add_mesh(scene, bpy.ops.mesh.primitive_cube_add, mirror, size=0.9, location=(1.8, 0.6, 0.45))
    # Blender's lights do not occlude, isotrace's area lights are surfaces
    # that do: the quad is placed where it shadows no sunlight on the view
    # and hides little sky.
    support.add_light(scene, "Area", "AREA", (0, -1, 5), 400, size=1.2)
    support.add_light(scene, "Sun", "SUN", (6, 1, 3), 1.0)
    support.add_light(scene, "Point", "POINT", (-3, -2, 2.5), 150, shadow_soft_size=0.0)
    support.add_light(scene, "Spot", "SPOT", (3, -3, 3), 300, target=(1.8, 0.6, 0.45), spot_size=math.radians(35),
                      spot_blend=0.4, shadow_soft_size=0.0)
    support.set_world_color(scene, (0.15, 0.18, 0.25))
    if portrait:
        # The sensor fits the taller side, the lens is wide open on the
        # red cube, and the world is an image.
        camera.data.dof.use_dof = True
        camera.data.dof.focus_object = bpy.data.objects["Cube"]
        camera.data.dof.aperture_fstop = 1.4
        tree = scene.world.node_tree
        texture = tree.nodes.new("ShaderNodeTexEnvironment")
        texture.image = bpy.data.images.load(environment_map())
        tree.links.new(texture.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    if engine == "CYCLES":
        c = scene.cycles
        c.device, c.samples, c.seed, c.use_denoising, c.use_adaptive_sampling = "CPU", SAMPLES, seed, False, False
        c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 7
        c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
        c.blur_glossy, c.light_sampling_threshold = 0.0, 0.0
        c.pixel_filter_type, c.filter_width = "BOX", 1.0
        scene.render.threads_mode, scene.render.threads = "FIXED", 2
    else:
        s = scene.isotrace
        s.samples, s.seed, s.max_depth, s.threads, s.pixel_filter = SAMPLES, seed, 8, 2, "BOX"
    return scene


def render(engine, seed, portrait=False):
    started = time.monotonic()
    name = f"{engine}_{seed}" + ("_portrait" if portrait else "")
    picture = support.read_rgb(support.render_to(scene_for(engine, seed, portrait), name))
    return picture, time.monotonic() - started


def standard_error_of_mean(a, b, c):
    """From two renders of different seeds: the per-pixel variance of one
    render is (a - b)^2 / 2, so its mean's variance is their sum / n^2."""
    x, y = a.channel(c), b.channel(c)
    return math.sqrt(sum((p - q) ** 2 / 2 for p, q in zip(x, y))) / len(x)


def flip(a, b):
    run = support.isotrace("compare", a, b, "--metric", "flip", "--fail", "1", "--json")
    if run.returncode not in (0, 1):
        raise AssertionError(run.stderr)
    return json.loads(run.stdout)["flip"]["mean"]


class MeshesAgainstCycles(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        support.install_addon()

    def test_images_agree_within_noise(self):
        self.compare(portrait=False)

    def test_portrait_depth_of_field_and_environment_map_agree_within_noise(self):
        self.compare(portrait=True)

    def compare(self, portrait):
        (c1, c_time), (c2, _) = render("CYCLES", 1, portrait), render("CYCLES", 2, portrait)
        (i1, i_time), (i2, _) = render("ISOTRACE", 1, portrait), render("ISOTRACE", 2, portrait)
        suffix = "_portrait" if portrait else ""
        path = lambda engine, seed: os.path.join(support.FOLDER, f"{engine}_{seed}{suffix}.exr")
        flip_cycles = flip(path("CYCLES", 2), path("CYCLES", 1))
        flip_isotrace = flip(path("ISOTRACE", 2), path("ISOTRACE", 1))
        flip_between = flip(path("ISOTRACE", 1), path("CYCLES", 1))
        print(f"time: Cycles {c_time:.2f} s, isotrace {i_time:.2f} s (whole render, {WIDTH}x{HEIGHT}, {SAMPLES} spp)")
        print(f"mean FLIP: Cycles vs Cycles {flip_cycles:.4f}, isotrace vs isotrace {flip_isotrace:.4f}, "
              f"isotrace vs Cycles {flip_between:.4f}")
        for c, name in enumerate("RGB"):
            mc, mi = sum(c1.channel(c)) / len(c1.channel(c)), sum(i1.channel(c)) / len(i1.channel(c))
            se = math.hypot(standard_error_of_mean(c1, c2, c), standard_error_of_mean(i1, i2, c))
            print(f"{name}: Cycles {mc:.4f}, isotrace {mi:.4f}, difference {mi - mc:+.4f}, "
                  f"standard error {se:.4f} ({abs(mi - mc) / se:.1f} sigma)")
            self.assertLess(abs(mi - mc), 4 * se, f"channel {name}")
        self.assertLessEqual(flip_between, 1.2 * max(flip_cycles, flip_isotrace))


if __name__ == "__main__":
    result = unittest.main(argv=[sys.argv[0]], exit=False).result
    sys.exit(0 if result.wasSuccessful() else 1)
