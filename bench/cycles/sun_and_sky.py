# The scene of scenes/sun_and_sky.json, built and rendered by Cycles (Debian's
# Blender 3.4) for bench/sun_and_sky_efficiency.sh:
#   blender -b --factory-startup -noaudio -P bench/cycles/sun_and_sky.py -- \
#       OUT.exr SPP SEED MAP.exr
# isotrace is y-up and Blender z-up: a point (x, y, z) is (x, -z, y) here.
# The ball is a smooth-shaded UV sphere of 256 x 128 segments (Cycles has no
# analytic sphere), both materials are Lambertian (Diffuse BSDF, roughness
# 0), paths stop after max_depth - 1 = 4 bounces of any kind (Cycles counts
# the camera hit's direct light as bounce 0), pixels are box-filtered, and
# adaptive sampling and denoising are off. Prints the render call's seconds.
import math
import sys
import time

import bpy
from mathutils import Vector

out, spp, seed, sky = sys.argv[sys.argv.index("--") + 1:][:4]


def blender_point(p):
    return Vector((p[0], -p[2], p[1]))


scene = bpy.context.scene
for obj in list(scene.objects):
    bpy.data.objects.remove(obj, do_unlink=True)

render = scene.render
render.engine = "CYCLES"
render.resolution_x = render.resolution_y = 256
render.resolution_percentage = 100
render.threads_mode = "FIXED"
render.threads = 2
render.filepath = out
render.image_settings.file_format = "OPEN_EXR"
render.image_settings.color_depth = "32"
render.image_settings.exr_codec = "ZIP"
scene.view_settings.view_transform = "Standard"

cycles = scene.cycles
cycles.device = "CPU"
cycles.samples = int(spp)
cycles.seed = int(seed)
cycles.use_adaptive_sampling = False
cycles.use_denoising = False
cycles.max_bounces = cycles.diffuse_bounces = cycles.glossy_bounces = cycles.transmission_bounces = 4
cycles.pixel_filter_type = "BOX"
cycles.filter_width = 1.0
cycles.use_auto_tile = False

camera_data = bpy.data.cameras.new("camera")
camera_data.sensor_fit = "VERTICAL"
camera_data.angle = math.radians(35)
camera = bpy.data.objects.new("camera", camera_data)
scene.collection.objects.link(camera)
camera.location = blender_point((0, 1.6, 6))
camera.rotation_euler = (blender_point((0, 0.8, 0)) - camera.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = camera


def diffuse(name, albedo):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    bsdf = nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
    return material


bpy.ops.mesh.primitive_uv_sphere_add(segments=256, ring_count=128, radius=1.0, location=blender_point((0, 1, 0)))
ball = bpy.context.active_object
bpy.ops.object.shade_smooth()
ball.data.materials.append(diffuse("white", 0.8))

bpy.ops.mesh.primitive_plane_add(size=40.0, location=(0, 0, 0))
bpy.context.active_object.data.materials.append(diffuse("ground", 0.5))

world = bpy.data.worlds.new("sky")
scene.world = world
world.use_nodes = True
nodes = world.node_tree.nodes
nodes.clear()
texture = nodes.new("ShaderNodeTexEnvironment")
texture.image = bpy.data.images.load(sky)
texture.interpolation = "Linear"
background = nodes.new("ShaderNodeBackground")
background.inputs["Strength"].default_value = 1.0
output = nodes.new("ShaderNodeOutputWorld")
world.node_tree.links.new(texture.outputs["Color"], background.inputs["Color"])
world.node_tree.links.new(background.outputs["Background"], output.inputs["Surface"])

start = time.perf_counter()
bpy.ops.render.render(write_still=True)
print("cycles_seconds %.4f" % (time.perf_counter() - start))
