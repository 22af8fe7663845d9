# isotrace for Blender: a render engine that exports the scene to an
# isotrace scene folder and runs `isotrace render`. Metaballs become blobby
# fields and objects with an isotrace field, with their Boolean modifiers,
# become CSG trees: both are traced exactly rather than polygonized.
bl_info = {
    "name": "isotrace",
    "author": "isotrace developers",
    "version": (0, 2, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Render Engine > isotrace",
    "description": "Render with isotrace: metaballs and implicit CSG traced exactly",
    "category": "Render",
}

if "bpy" in locals():
    import importlib

    for module in (properties, engine, operators, ui):  # noqa: F821 (reload in Blender)
        importlib.reload(module)
else:
    from . import properties, engine, operators, ui

import bpy  # noqa: E402,F401


def register():
    properties.register()
    engine.register()
    operators.register()
    ui.register()


def unregister():
    ui.unregister()
    operators.unregister()
    engine.unregister()
    properties.unregister()
