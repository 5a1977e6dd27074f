"""The modal loop shared by Record Take and Track Whole Clip.

Timer ticks step the recorder (Blender stays responsive and shows progress); Esc stops and
keeps the take; an error keeps what was recorded before it. Nothing recorded is ever dropped:
until the take is stored, the recorder's journal holds it on disk.
"""

import time

import bpy

from ...voodoo_addon.errors import VoodooError
from ...voodoo_addon.takes.take import ProgressBar
from .. import drawing
from ..animation import attention_message
from ..recorder import Recorder

#: Fastest timer a modal take asks for (Hz).
MAX_RATE = 120.0
#: Seconds a timer tick may track for while frames wait (a 30 fps camera's frame time).
CATCH_UP = 1.0 / 30.0


def status_line(rec) -> str:
    """The header's line during a take: frames, live rate and latency, what Esc does."""
    text = f"{len(rec.rows)} frames"
    if rec.rate:
        text += f", tracking {rec.rate:.0f} fps, latency {1000 * rec.latency:.0f} ms"
    if rec.behind:
        text += f", {rec.behind} to catch up"
    if rec.source.live and rec.recording:
        return text + " (Esc stops recording; the frames recorded are all tracked)"
    if rec.source.live and rec.behind:
        return text + " -- completing the take (Esc keeps what is tracked so far)"
    return text + " (Esc stops and keeps)"


def report_finish(op, info) -> None:
    msg = f"Take {info['take']!r}: {info['frames']} frames"
    actions = info.get("actions") or {}
    if len(actions) > 1:
        msg += ", applied as actions " + ", ".join(repr(a.name) for a in actions.values())
    elif info.get("applied"):
        msg += f", applied as action {info['action'].name!r}"
    else:
        msg += " (stored with the blob; set a target and Apply Take)"
    op.report({"INFO"}, msg)
    for note in info.get("notes", ()):
        op.report({"WARNING"}, note)
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


def keep_after_error(op, recorder, exc) -> None:
    """Report an error that stopped a take, keeping what was recorded before it."""
    try:
        kept = recorder.keep()
    except VoodooError as again:
        op.report({"ERROR"}, f"{exc} (and the take could not be stored: {again})")
        return
    where = f"; the {len(recorder.rows)} frames before it are kept as take {kept!r}" if kept else ""
    op.report({"ERROR"}, f"{exc}{where}")


def run_to_end(op, context, recorder) -> set:
    """Track a whole source without an event loop (scripts, background), with progress."""
    wm = context.window_manager
    wm.progress_begin(0, 100)
    bar = ProgressBar(recorder.max_frames or recorder.source.count) if bpy.app.background else None
    try:
        while recorder.step(wait=True):
            wm.progress_update(int(100 * recorder.progress))
            if bar is not None:
                bar(len(recorder.rows))
        info = recorder.finish()
    except VoodooError as exc:
        keep_after_error(op, recorder, exc)
        return {"CANCELLED"}
    finally:
        wm.progress_end()
    report_finish(op, info)
    return {"FINISHED"}


class TakeLoop:
    """Mixin of the modal take operators: ``live`` poses the stand-in every frame; without
    it each timer tick tracks frames for up to ``tick_seconds``.
    """

    live = True
    tick_seconds = 0.0
    _timer = None
    _recorder = None

    def start(self, context, **kwargs) -> set:
        try:
            self._recorder = Recorder(context, live=self.live, **kwargs)
        except VoodooError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        wm = context.window_manager
        rate = MAX_RATE if not self.live else min(max(self._recorder.source.fps, 1.0), MAX_RATE)
        self._timer = wm.event_timer_add(1.0 / rate, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0, 100)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        rec = self._recorder
        if event.type == "ESC":
            if rec.source.live and rec.recording:
                # The camera stops; the frames it gave are still tracked, with progress
                # (a second Esc keeps what is tracked by then).
                rec.stop_recording()
                return {"RUNNING_MODAL"}
            return self._end(context)
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        # Behind the camera, a tick tracks for up to a frame's time to catch up.
        budget = max(self.tick_seconds, CATCH_UP if rec.behind else 0.0)
        until = time.perf_counter() + budget
        try:
            more = rec.step()
            while more and time.perf_counter() < until:
                more = rec.step()
        except VoodooError as exc:
            self._stop_timer(context)
            keep_after_error(self, rec, exc)
            return {"CANCELLED"}
        context.window_manager.progress_update(int(100 * rec.progress))
        drawing.tag_redraw(context)
        if context.area is not None:
            context.area.header_text_set(f"{self.bl_label} {rec.take_name}: {status_line(rec)}")
        return {"RUNNING_MODAL"} if more else self._end(context)

    def _end(self, context):
        self._stop_timer(context)
        try:
            info = self._recorder.finish()
        except VoodooError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        report_finish(self, info)
        return {"FINISHED"}

    def _stop_timer(self, context):
        wm = context.window_manager
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        wm.progress_end()
        if context.area is not None:
            context.area.header_text_set(None)
        drawing.tag_redraw(context)

    def cancel(self, context):
        """Blender ends the operator (file closed, window gone): keep what was recorded."""
        self._stop_timer(context)
        if self._recorder is not None:
            try:
                self._recorder.keep()
            except (VoodooError, ReferenceError):
                self._recorder.close()  # the journal stays on disk for Recover Takes
