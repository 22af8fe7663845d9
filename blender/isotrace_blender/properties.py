# Settings the add-on keeps in .blend files: render settings on the scene,
# the isotrace field of an object, and the binary's path as a preference.
import bpy
from bpy.props import EnumProperty, FloatProperty, FloatVectorProperty, IntProperty, PointerProperty, StringProperty

from . import registration

ADDON_NAME = __package__


class IsotracePreferences(bpy.types.AddonPreferences):
    bl_idname = ADDON_NAME
    binary: StringProperty(name="isotrace binary", subtype="FILE_PATH",
                           description="Path of the isotrace program (empty: ISOTRACE_BINARY, then the PATH)")

    def draw(self, context):
        self.layout.prop(self, "binary")


def preferred_binary(context):
    addon = context.preferences.addons.get(ADDON_NAME)
    return addon.preferences.binary if addon else ""


class IsotraceRenderSettings(bpy.types.PropertyGroup):
    samples: IntProperty(name="Samples", default=64, min=1, max=1 << 20, description="Samples per pixel")
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed of the render")
    integrator: EnumProperty(name="Integrator", default="path",
                             items=[("path", "Path", "Unidirectional path tracing with next-event estimation"),
                                    ("whitted", "Whitted", "Direct light, mirrors and glass only: a quick preview")])
    max_depth: IntProperty(name="Max Depth", default=12, min=1, max=100000, description="Bounces, 1 = direct light only")
    threads: IntProperty(name="Threads", default=0, min=0, max=4096, description="Render threads (0: all cores)")
    pixel_filter: EnumProperty(name="Pixel Filter", default="GAUSSIAN",
                               items=[("GAUSSIAN", "Gaussian", "Gaussian of sigma 0.5 pixels over 1.5 pixels"),
                                      ("BOX", "Box", "Each sample counts for its own pixel only")])


FIELD_KINDS = [
    ("NONE", "None", "A plain Blender object"),
    ("PRIMITIVE", "Primitive", "An analytic primitive with its parameters"),
    ("PRESET", "Algebraic", "An algebraic surface preset"),
    ("TEXT", "Description", "A field description (JSON) from a text block"),
]

PRIMITIVES = [
    ("sphere", "Sphere", ""), ("box", "Box", ""), ("torus", "Torus", ""), ("cylinder", "Cylinder", ""),
    ("cone", "Cone", ""), ("capsule", "Capsule", ""), ("ellipsoid", "Ellipsoid", ""), ("octahedron", "Octahedron", ""),
]

PRESETS = [
    ("tangle", "Tangle cube", "Goursat's tangle cube, genus 5"),
    ("heart", "Heart", "Taubin's heart"),
    ("decocube", "Decocube", "Genus 13"),
    ("pretzel2", "Pretzel (2 holes)", ""),
    ("pretzel4", "Pretzel (4 holes)", ""),
]


class IsotraceObjectSettings(bpy.types.PropertyGroup):
    field_kind: EnumProperty(name="Field", items=FIELD_KINDS, default="NONE",
                             description="Render this object as an implicit surface traced by isotrace")
    primitive: EnumProperty(name="Primitive", items=PRIMITIVES, default="sphere")
    radius: FloatProperty(name="Radius", default=1.0, min=1e-6, soft_max=100, unit="LENGTH")
    size: FloatVectorProperty(name="Size", default=(2.0, 2.0, 2.0), min=1e-6, size=3, unit="LENGTH",
                              description="Box: its edges; ellipsoid: its diameters")
    rounding: FloatProperty(name="Rounding", default=0.0, min=0.0, unit="LENGTH", description="Box edge rounding")
    major_radius: FloatProperty(name="Major Radius", default=1.0, min=1e-6, unit="LENGTH")
    minor_radius: FloatProperty(name="Minor Radius", default=0.25, min=1e-6, unit="LENGTH")
    height: FloatProperty(name="Height", default=2.0, min=1e-6, unit="LENGTH", description="Along the object's Z axis")
    top_radius: FloatProperty(name="Top Radius", default=0.0, min=0.0, unit="LENGTH", description="Cone: radius at the top")
    preset: EnumProperty(name="Surface", items=PRESETS, default="tangle")
    text: PointerProperty(name="Text", type=bpy.types.Text, description="A text block holding a field description (JSON)")
    blend_radius: FloatProperty(name="Boolean Blend", default=0.0, min=0.0, unit="LENGTH",
                                description="Blend radius of this object's Boolean modifiers on isotrace fields "
                                            "(0: sharp CSG)")
    preview_resolution: IntProperty(name="Preview Resolution", default=64, min=8, max=1024,
                                    description="Cells along the longest side of the viewport polygonization")


CLASSES = (IsotracePreferences, IsotraceRenderSettings, IsotraceObjectSettings)


def register():
    registration.register_classes(CLASSES)
    bpy.types.Scene.isotrace = PointerProperty(type=IsotraceRenderSettings)
    bpy.types.Object.isotrace = PointerProperty(type=IsotraceObjectSettings)


def unregister():
    del bpy.types.Object.isotrace
    del bpy.types.Scene.isotrace
    registration.unregister_classes(CLASSES)
