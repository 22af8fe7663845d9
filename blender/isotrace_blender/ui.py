# Panels: render settings, and an object's isotrace field.
import bpy

from . import registration


class IsotracePanel:
    COMPAT_ENGINES = {"ISOTRACE"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class RENDER_PT_isotrace(IsotracePanel, bpy.types.Panel):
    bl_label = "isotrace"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"

    def draw(self, context):
        settings = context.scene.isotrace
        layout = self.layout
        layout.use_property_split = True
        for name in ("samples", "seed", "integrator", "max_depth", "threads", "pixel_filter"):
            layout.prop(settings, name)


class OBJECT_PT_isotrace_field(IsotracePanel, bpy.types.Panel):
    bl_label = "isotrace Field"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.object is not None and context.object.type in {"MESH", "EMPTY"}

    def draw(self, context):
        s = context.object.isotrace
        layout = self.layout
        layout.use_property_split = True
        layout.prop(s, "field_kind")
        if s.field_kind == "PRIMITIVE":
            layout.prop(s, "primitive")
            shown = {"sphere": ("radius",), "box": ("size", "rounding"), "torus": ("major_radius", "minor_radius"),
                     "cylinder": ("radius", "height"), "cone": ("radius", "top_radius", "height"),
                     "capsule": ("radius", "height"), "ellipsoid": ("size",), "octahedron": ("radius",)}[s.primitive]
            for name in shown:
                layout.prop(s, name)
        elif s.field_kind == "PRESET":
            layout.prop(s, "preset")
        elif s.field_kind == "TEXT":
            layout.prop(s, "text")
        if s.field_kind != "NONE":
            layout.prop(s, "blend_radius")
            layout.prop(s, "preview_resolution")
            layout.operator("isotrace.update_preview")


CLASSES = (RENDER_PT_isotrace, OBJECT_PT_isotrace_field)


def register():
    registration.register_classes(CLASSES)


def unregister():
    registration.unregister_classes(CLASSES)
