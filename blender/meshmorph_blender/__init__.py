"""meshmorph for Blender: shape keys carried to another character
(deformation transfer) and as-rigid-as-possible in-betweens, on meshmorph's
Python package. View3D > Sidebar > meshmorph."""

bl_info = {
    "name": "meshmorph",
    "description": "Transfer shape keys to a character of any topology; as-rigid-as-possible in-betweens",
    "author": "The meshmorph authors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > meshmorph",
    "category": "Animation",
}

import bpy

from . import operators, panel, wheels

CLASSES = panel.CLASSES + operators.CLASSES


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.meshmorph = bpy.props.PointerProperty(type=panel.MeshmorphSettings)
    try:
        wheels.load()  # unpacked now, not at the first click; a failure is reported by each operator
    except ImportError:
        pass


def unregister():
    del bpy.types.Scene.meshmorph
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
