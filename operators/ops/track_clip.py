import bpy

from ...voodoo_addon.errors import VoodooError
from ..recorder import Recorder
from .common import needs, reports_errors, settings
from .take_loop import TakeLoop, run_to_end


class VOODOO_OT_track_clip(TakeLoop, bpy.types.Operator):
    """Track the whole clip as fast as it goes and apply the take; Esc stops and keeps it"""

    bl_idname = "voodoo.track_clip"
    bl_label = "Track Whole Clip"
    bl_options = {"REGISTER", "UNDO"}

    live = False
    tick_seconds = 0.1

    max_frames: bpy.props.IntProperty(name="Frames", description="0: to the end", min=0)
    resume: bpy.props.BoolProperty(
        name="Resume", description="Continue the last take from the frame after it ended"
    )
    both_ways: bpy.props.BoolProperty(
        name="Both Ways",
        description=(
            "Then track the clip again backwards from the end and keep, frame by frame, the "
            "surer pass (mixing the two where they are about as sure): parts that fold or "
            "turn away and come back are found sooner (twice the time)"
        ),
    )

    @classmethod
    def poll(cls, context):
        return needs(cls, context, "blob", "source")

    def _options(self, context) -> dict:
        last = settings(context).last_take
        if self.resume and not last:
            raise VoodooError("There is no take to resume yet.")
        return {
            "max_frames": self.max_frames or None,
            "resume": last if self.resume else None,
            "both_ways": self.both_ways,
        }

    @reports_errors
    def invoke(self, context, event):
        return self.start(context, **self._options(context))

    @reports_errors
    def execute(self, context):
        recorder = Recorder(context, live=False, **self._options(context))
        return run_to_end(self, context, recorder)


classes = (VOODOO_OT_track_clip,)
