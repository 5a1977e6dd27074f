import bpy

from .common import needs
from .take_loop import TakeLoop


class VOODOO_OT_record_take(TakeLoop, bpy.types.Operator):
    """Record a take from the clip or camera, posing the target live; Esc stops and keeps it"""

    bl_idname = "voodoo.record_take"
    bl_label = "Record Take"
    bl_options = {"REGISTER", "UNDO"}

    live = True

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "blob", "source")

    def invoke(self, context, event):
        return self.start(context)

    def execute(self, context):
        # Without an event loop (scripts, background) record the whole source at once.
        return bpy.ops.voodoo.track_clip()


classes = (VOODOO_OT_record_take,)
