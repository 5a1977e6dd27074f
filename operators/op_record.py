import bpy

from ..voodoo_addon.errors import VoodooError
from . import overlay
from .apply import attention_message
from .recorder import Recorder


def _report_finish(op, info) -> None:
    msg = f"Take {info['take']!r}: {info['frames']} frames"
    if info.get("applied"):
        msg += f", applied as action {info['action'].name!r}"
    else:
        msg += " (stored with the blob; set a target and Apply Take)"
    op.report({"INFO"}, msg)
    if info["lost"]:
        lost = info["lost"]
        op.report(
            {"WARNING"},
            f"The blob was lost in {len(lost)} frame(s) (first {lost[0]}); "
            "those frames are not keyed.",
        )
    note = attention_message(info.get("attention"))
    if note:
        op.report({"WARNING"}, note)


class VOODOO_OT_record_take(bpy.types.Operator):
    """Record a take from the clip or camera, posing the target live; Esc stops and keeps it"""

    bl_idname = "voodoo.record_take"
    bl_label = "Record Take"
    bl_options = {"REGISTER", "UNDO"}

    _timer = None
    _recorder = None

    def invoke(self, context, event):
        try:
            self._recorder = Recorder(context, live=True)
        except VoodooError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        wm = context.window_manager
        fps = self._recorder.source.fps
        self._timer = wm.event_timer_add(1.0 / min(max(fps, 1.0), 120.0), window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0, 100)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        # Without an event loop (scripts, background) record the whole source at once.
        return bpy.ops.voodoo.track_clip()

    def modal(self, context, event):
        if event.type == "ESC":
            return self._end(context)
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        try:
            more = self._recorder.step()
        except VoodooError as exc:
            self.report({"ERROR"}, str(exc))
            self.cancel(context)
            return {"CANCELLED"}
        context.window_manager.progress_update(int(100 * self._recorder.progress))
        overlay.tag_redraw(context)
        if context.area is not None:
            context.area.header_text_set(
                f"Recording {self._recorder.take_name}: "
                f"{len(self._recorder.rows)} frames (Esc stops)"
            )
        return {"RUNNING_MODAL"} if more else self._end(context)

    def _end(self, context):
        self._remove_timer(context)
        try:
            info = self._recorder.finish()
        except VoodooError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        _report_finish(self, info)
        return {"FINISHED"}

    def _remove_timer(self, context):
        wm = context.window_manager
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        wm.progress_end()
        if context.area is not None:
            context.area.header_text_set(None)
        overlay.tag_redraw(context)

    def cancel(self, context):
        """Stop without keeping anything (errors, or Blender closing the operator)."""
        self._remove_timer(context)
        if self._recorder is not None:
            self._recorder.close()


class VOODOO_OT_track_clip(bpy.types.Operator):
    """Track the whole clip in one go (scripts, batch, background) and apply the take"""

    bl_idname = "voodoo.track_clip"
    bl_label = "Track Whole Clip"
    bl_options = {"REGISTER", "UNDO"}

    max_frames: bpy.props.IntProperty(name="Frames", description="0: to the end", min=0)
    resume: bpy.props.BoolProperty(
        name="Resume", description="Continue the last take from the frame after it ended"
    )

    def execute(self, context):
        resume = context.scene.voodoo.last_take if self.resume else None
        if self.resume and not resume:
            self.report({"ERROR"}, "There is no take to resume yet.")
            return {"CANCELLED"}
        try:
            rec = Recorder(context, max_frames=self.max_frames or None, live=False, resume=resume)
        except VoodooError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        try:
            while rec.step():
                pass
            info = rec.finish()
        except VoodooError as exc:
            rec.close()
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        _report_finish(self, info)
        return {"FINISHED"}


classes = (VOODOO_OT_record_take, VOODOO_OT_track_clip)
