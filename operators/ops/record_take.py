import bpy

from .common import needs
from .take_loop import TakeLoop


class VOODOO_OT_record_take(TakeLoop, bpy.types.Operator):
    """Record a take from the clip or camera, posing the target live; Esc stops and keeps it"""

    bl_idname = "voodoo.record_take"
    bl_label = "Record Take"
    bl_options = {"REGISTER", "UNDO"}

    live = True

    both_ways: bpy.props.BoolProperty(
        name="Both Ways",
        description=(
            "When the take ends, track it again backwards from its end (the clip, or the "
            "camera's footage) and keep, frame by frame, the surer pass (mixing the two where "
            "they are about as sure): parts that fold or turn away and come back are found "
            "sooner"
        ),
    )

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "blob", "source")

    def invoke(self, context, event):
        return self.start(context, both_ways=self.both_ways)

    def execute(self, context):
        # Without an event loop (scripts, background) record the whole source at once.
        return bpy.ops.voodoo.track_clip(both_ways=self.both_ways)


classes = (VOODOO_OT_record_take,)
