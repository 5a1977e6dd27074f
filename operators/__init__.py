"""The Blender layer: settings, operators, panels and the clip overlay.

Thin by design: it turns Blender data into engine calls and engine results into Blender
data. ``storage`` owns what is kept in the .blend, ``pixels`` every pixel convention,
``clips`` movie clips and masks, ``apply``/``animation`` the take's action, ``recorder`` a
take being recorded, ``drawing`` the overlay and ``gpu_warp`` the GPU warp backend.
Classes register in the order below and unregister in reverse.
"""

import bpy

from . import drawing, ops, props, ui

classes = props.classes + ops.classes + ui.classes


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    props.register()
    drawing.register()


def unregister():
    drawing.unregister()
    props.unregister()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
