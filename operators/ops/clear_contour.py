import bpy

from .. import drawing
from .common import settings


class VOODOO_OT_clear_contour(bpy.types.Operator):
    """Forget the outline"""

    bl_idname = "voodoo.clear_contour"
    bl_label = "Clear Outline"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        settings(context).contour.clear()
        drawing.tag_redraw(context)
        return {"FINISHED"}


classes = (VOODOO_OT_clear_contour,)
