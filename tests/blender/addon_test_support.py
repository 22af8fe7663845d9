# Shared by the Blender tests: install and enable the add-on from its zip,
# build the test scenes, render, read images.
import math
import os
import subprocess

from array import array

import addon_utils
import bpy
from mathutils import Vector

FOLDER = os.environ["ISOTRACE_TEST_FOLDER"]
BINARY = os.environ["ISOTRACE_BINARY"]


def install_addon():
    bpy.ops.preferences.addon_install(filepath=os.environ["ISOTRACE_ADDON_ZIP"], overwrite=True)
    addon_utils.enable("isotrace_blender", default_set=True, handle_error=None)
    import isotrace_blender  # noqa: F401  (fails the test when enabling failed)
    return isotrace_blender


def empty_scene(width=80, height=60):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Factory settings come with the add-on disabled again.
    addon_utils.enable("isotrace_blender", default_set=True, handle_error=None)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGB"  # as isotrace writes them, for isotrace compare
    scene.view_settings.view_transform = "Standard"
    return scene


def look_at(obj, target):
    direction = Vector(target) - obj.location
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


def add_camera(scene, location, target, lens=35.0):
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.lens = lens
    camera.location = location
    look_at(camera, target)
    scene.collection.objects.link(camera)
    scene.camera = camera
    return camera


def principled(name, base=(0.8, 0.8, 0.8), metallic=0.0, roughness=0.5, transmission=0.0, ior=1.45, specular=0.5,
               emission=None):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    node = material.node_tree.nodes["Principled BSDF"]
    node.inputs["Base Color"].default_value = (*base, 1.0)
    node.inputs["Metallic"].default_value = metallic
    node.inputs["Roughness"].default_value = roughness
    node.inputs["Transmission"].default_value = transmission
    node.inputs["IOR"].default_value = ior
    node.inputs["Specular"].default_value = specular
    if emission is not None:
        node.inputs["Emission"].default_value = (*emission, 1.0)
        node.inputs["Emission Strength"].default_value = 1.0
    return material


def add_mesh(scene, operator, material, **kwargs):
    operator(**kwargs)
    obj = bpy.context.active_object
    obj.data.materials.append(material)
    return obj


def add_light(scene, name, kind, location, energy, target=(0, 0, 0), **settings):
    light = bpy.data.lights.new(name, kind)
    light.energy = energy
    for key, value in settings.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(name, light)
    obj.location = location
    look_at(obj, target)
    scene.collection.objects.link(obj)
    return obj


def add_metaball_family(scene, material, resolution=0.1):
    """Blob and Blob.001: a ball, a capsule, a cube and a negative ball."""
    first = bpy.data.metaballs.new("Blob")
    first.threshold = 0.6
    first.render_resolution = resolution
    first.resolution = resolution
    ball = first.elements.new()
    ball.co, ball.radius = (0, 0, 0.9), 1.0
    capsule = first.elements.new(type="CAPSULE")
    capsule.co, capsule.radius, capsule.size_x = (0.9, 0, 0.9), 0.6, 0.5
    capsule.rotation = Vector((0, 0, 1)).rotation_difference(Vector((0, 1, 1)).normalized())
    hollow = first.elements.new()
    hollow.co, hollow.radius, hollow.use_negative = (0, -0.7, 1.2), 0.8, True
    first.materials.append(material)
    basis = bpy.data.objects.new("Blob", first)
    scene.collection.objects.link(basis)
    second = bpy.data.metaballs.new("Blob.001")
    cube = second.elements.new(type="CUBE")
    cube.co, cube.radius = (0, 0, 0), 0.6
    cube.size_x, cube.size_y, cube.size_z = 0.3, 0.2, 0.25
    member = bpy.data.objects.new("Blob.001", second)
    member.location = (-0.8, 0.3, 0.7)
    member.scale = (1.2, 1.0, 0.9)
    scene.collection.objects.link(member)
    return basis, member


def add_carved_box(scene, material, location):
    """An isotrace box minus an isotrace sphere, by a Boolean modifier."""
    carved = bpy.data.objects.new("Carved", bpy.data.meshes.new("Carved"))
    carved.location = location
    carved.isotrace.field_kind = "PRIMITIVE"
    carved.isotrace.primitive = "box"
    carved.isotrace.size = (1.2, 1.2, 1.2)
    carved.data.materials.append(material)
    cutter = bpy.data.objects.new("Cutter", bpy.data.meshes.new("Cutter"))
    cutter.location = (location[0] + 0.4, location[1] - 0.4, location[2] + 0.4)
    cutter.isotrace.field_kind = "PRIMITIVE"
    cutter.isotrace.primitive = "sphere"
    cutter.isotrace.radius = 0.7
    cutter.hide_render = True
    for obj in (carved, cutter):
        scene.collection.objects.link(obj)
    boolean = carved.modifiers.new("Cut", "BOOLEAN")
    boolean.operation = "DIFFERENCE"
    boolean.object = cutter
    return carved, cutter


def set_world_color(scene, color, strength=1.0):
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*color, 1.0)
    background.inputs["Strength"].default_value = strength
    scene.world = world


def render_to(scene, name):
    scene.render.filepath = os.path.join(FOLDER, name)
    bpy.ops.render.render(write_still=True)
    return scene.render.filepath + ".exr"


class Picture:
    """An image's RGB as floats (rows bottom first, as Blender stores them)."""

    def __init__(self, path):
        image = bpy.data.images.load(path, check_existing=False)
        self.width, self.height = image.size
        rgba = array("f", bytes(4 * 4 * self.width * self.height))
        image.pixels.foreach_get(rgba)
        bpy.data.images.remove(image)
        self.rgb = array("f", (v for i, v in enumerate(rgba) if i % 4 != 3))

    def channel(self, c):
        return self.rgb[c::3]

    def mean(self):
        return sum(self.rgb) / len(self.rgb)


def read_rgb(path):
    return Picture(path)


def isotrace(*arguments):
    return subprocess.run([BINARY, *arguments], capture_output=True, text=True)


def render_keeping_export(scene, name, folder):
    """Renders through the add-on, keeping the scene it exports in `folder`."""
    os.environ["ISOTRACE_BLENDER_KEEP_EXPORT"] = folder
    try:
        return render_to(scene, name)
    finally:
        del os.environ["ISOTRACE_BLENDER_KEEP_EXPORT"]
