"""The Blender layer: properties, operators, panels and the clip overlay.

Thin by design: it turns Blender data into engine calls and engine results into Blender
data. Classes register in the order below and unregister in reverse.
"""

import bpy

from . import (
    op_apply,
    op_build,
    op_capture,
    op_contour_auto,
    op_contour_clear,
    op_contour_mask,
    op_contour_sketch,
    op_modes,
    op_record,
    op_smooth,
    overlay,
    props,
    ui_clip,
    ui_modes,
    ui_view3d,
)

_modules = (
    props,
    op_capture,
    op_contour_mask,
    op_contour_auto,
    op_contour_sketch,
    op_contour_clear,
    op_build,
    op_record,
    op_apply,
    op_modes,
    op_smooth,
    ui_modes,
    ui_clip,
    ui_view3d,
)
classes = tuple(cls for mod in _modules for cls in mod.classes)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    props.register()
    overlay.register()


def unregister():
    overlay.unregister()
    props.unregister()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
