"""A take being recorded.

The modal operators forward timer ticks to :meth:`Recorder.step`; scripts and the tests call
it in a loop (the bpy module has no event loop). Every tracked frame also goes to a journal
file at once (:mod:`voodoo_addon.takes.journal`), so a crash or a killed Blender loses none of
the take: Recover Takes stores it from there.
"""

import time
from contextlib import ExitStack

import bpy

from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.media.footage import Footage
from ..voodoo_addon.media.prefetch import PENDING, Prefetcher
from ..voodoo_addon.media.sources import CaptureSource, open_source
from ..voodoo_addon.stream import OscSender
from ..voodoo_addon.takes.both_ways import backward_frames, track_both_ways
from ..voodoo_addon.takes.take import ProgressBar
from ..voodoo_addon.tracking import Tracker
from ..voodoo_addon.tracking.troupe import Troupe
from . import drawing
from .clips import active_clip, open_clip, scene_frame
from .doll_run import DollRun, alive, check_dolls, unique_name
from .dolls import doll_settings
from .gpu_warp import make_backend
from .storage import footage_dir, recoverable_journals

#: Journals of the takes being recorded in this session (not "interrupted").
_recording: set = set()


def _frozen(s) -> list:
    """Names of the rigid parameters the animator froze."""
    pairs = (
        ("translate-x", s.freeze_translation),
        ("translate-y", s.freeze_translation),
        ("rotate", s.freeze_rotation),
        ("scale", s.freeze_scale),
    )
    return [name for name, on in pairs if on]


class Recorder:
    """Tracks a source frame by frame into a take and shows it live on the target.

    Parameters
    ----------
    context : bpy.types.Context
    max_frames : int, optional
        Stop after this many frames (a live camera stops after ``camera_seconds``).
    live : bool
        Move the scene to each tracked frame and pose a stand-in of the target there.
    resume : str, optional
        Name of a stored take of a clip to continue: tracking starts on the frame after its
        last one, from its last pose, and the take grows (e.g. after reopening the file).
    both_ways : bool
        When the take is kept, track the clip's frames again backwards from its end and
        keep, frame by frame, the surer pass, or a mix of the two where they are about as
        sure (:mod:`voodoo_addon.takes.both_ways`); a camera's take is tracked backwards on
        its footage, every frame the camera gave.

    Raises
    ------
    VoodooError
        No blob, no clip or camera, an unreadable clip, a frame size that does not match the
        blob, or a target that is not a mesh. Nothing is left open or changed then.
    """

    def __init__(
        self,
        context,
        max_frames: int | None = None,
        live: bool = True,
        resume: str | None = None,
        both_ways: bool = False,
    ):
        scene = context.scene
        s = scene.voodoo
        self.scene = scene
        self.live = live
        self.both_ways = both_ways
        listed = doll_settings(s)
        self.dolls = [DollRun(name, d, len(listed) > 1) for name, d in listed]
        check_dolls(self.dolls)
        self.notes: list[str] = []
        self.rows = []  # (source index, time, scene frame, {doll name: TrackResult})
        if resume:
            for doll in self.dolls:
                doll.resume(resume)
        self.footage = self.clip = None  # a camera's Footage, the clip
        with ExitStack() as stack:
            self._open_source(context, s, max_frames, stack)
            for doll in self.dolls:
                size = tuple(int(v) for v in doll.blob.frame_size)
                if tuple(self.source.size) != size:
                    which = f"blob of doll {doll.name!r}" if doll.several else "blob"
                    raise VoodooError(
                        f"The source is {self.source.size[0]}x{self.source.size[1]} but the "
                        f"{which} was built on a {size[0]}x{size[1]} frame; capture and "
                        "build again."
                    )
            self.backend, self.backend_note = make_backend(s.warp)
            stack.callback(self.backend.close)
            for doll in self.dolls:
                doll.tracker = Tracker(doll.blob, backend=self.backend, frozen=_frozen(s))
                if doll.previous is not None:
                    doll.tracker.reset(doll.previous.take.params[-1])
            self.troupe = Troupe(
                {d.name: d.blob for d in self.dolls},
                trackers={d.name: d.tracker for d in self.dolls},
            )
            self.take_name = resume or unique_name(self.dolls, s.take_name or "Take")
            for doll in self.dolls:
                fps = self.source.fps
                journal = doll.open_journal(self.take_name, fps, self.rest_frame, resume)
                stack.callback(journal.close)
                _recording.add(journal.path)
                stack.callback(_recording.discard, journal.path)
            if s.source == "CAMERA":
                self._open_writer(stack)
            if live:
                for doll in self.dolls:
                    if doll.target is not None:
                        doll.prepare_preview()
                        stack.callback(doll.drop_preview)
            stack.callback(drawing.live_state.clear)
            self.stream = self._open_stream(s)
            if self.stream is not None:
                stack.callback(self.stream.close)
            # Last, once nothing can fail: frames are read (and a camera's footage written)
            # on a second thread from here on, every one of them, however far behind the
            # tracker falls.
            write = self.footage.write if self.footage is not None else None
            self.feed = Prefetcher(self.source, limit=self.max_frames, on_frame=write)
            stack.callback(self.feed.close)
            self._resources = stack.pop_all()
        #: Frames tracked per second (recent), and seconds from a frame's arrival to its
        #: result, for the panel.
        self.rate = 0.0
        self.latency = 0.0
        self._last_tracked = None

    # The first doll, as a take of one doll has it (scripts and the panels use these).
    @property
    def blob_mesh(self):
        return self.dolls[0].blob_mesh

    @property
    def blob(self):
        return self.dolls[0].blob

    @property
    def target(self):
        return self.dolls[0].target

    @property
    def tracker(self):
        return self.dolls[0].tracker

    @property
    def previous(self):
        return self.dolls[0].previous

    def _open_source(self, context, s, max_frames, stack) -> None:
        scene = self.scene
        if s.source == "CAMERA":
            if self.previous is not None:
                raise VoodooError("Only takes of a movie clip can be resumed.")
            self.source = stack.enter_context(open_source(int(s.camera_index)))
            fps = scene.render.fps / scene.render.fps_base
            self.max_frames = max_frames or max(1, round(s.camera_seconds * self.source.fps))
            start_frame = scene.frame_current
            self.rest_frame = start_frame
            self._frame_of = lambda fr: start_frame + int(round(fr.time * fps))
            return
        self.clip = active_clip(context)
        self.source = stack.enter_context(open_clip(self.clip))
        start = max(0, min(s.capture_index, (self.source.count or 1) - 1))
        self.rest_frame = scene_frame(self.clip, s.capture_index)
        if self.previous is not None:
            start = int(self.previous.take.frame_indices[-1]) + 1
            self.rest_frame = self.previous.rest_frame
            if self.source.count is not None and start >= self.source.count:
                raise VoodooError(
                    f"Take {self.previous.name!r} already reaches the end of the clip."
                )
        self.source.seek(start)
        self.max_frames = max_frames
        self._frame_of = lambda fr: scene_frame(self.clip, fr.index)

    # ------------------------------------------------------------------ per frame

    def step(self, wait: bool | None = None) -> bool:
        """Track the next frame. Returns False when the take is complete.

        ``wait`` for the next frame to arrive; by default a clip's frames are waited for and
        a camera's are not (the step then tracks nothing and returns True).

        A target deleted during the take ends it (the take is kept); a stand-in deleted
        during the take only ends the live preview.
        """
        for doll in self.dolls:
            if doll.target is not None and not alive(doll.target):
                doll.target = None  # the stand-in goes when the recorder closes
                self.notes.append("The target was deleted during the take; recording stopped.")
                return False
        if self.max_frames is not None and len(self.rows) >= self.max_frames:
            return False
        # A camera is not waited for (Blender stays responsive); a clip is read ahead.
        frame = self.feed.read(wait=not self.source.live if wait is None else wait)
        if frame is PENDING:
            return True
        if frame is None:
            return False
        results = self.troupe.track(frame.pixels)
        self._measure()
        f = self._frame_of(frame)
        if self.rows and self.rows[-1][2] == f:  # two camera frames in one scene frame
            self.rows.pop()
        self.rows.append((frame.index, frame.time, f, results))
        for doll in self.dolls:
            res = results[doll.name]
            doll.journal.add(res, frame.index, frame.time, f)
            if self.stream is not None:
                doll.send(self.stream, frame, res)
        first = results[self.dolls[0].name]
        drawing.live_state.update(
            nodes=first.nodes,
            triangles=self.blob.triangles,
            lost=first.lost,
            meshes=[(results[d.name].nodes, d.blob.triangles, results[d.name].lost,
                     results[d.name].visible) for d in self.dolls],
            rate=self.rate,
            latency=self.latency,
            behind=self.behind,
        )  # fmt: skip
        # Behind the camera, the live view skips to the newest frames; the take does not.
        if self.live and self.behind <= 1:
            self.scene.frame_set(f)
            for doll in self.dolls:
                if not results[doll.name].lost:
                    doll.pose(results[doll.name].params, self.notes)
        return self.max_frames is None or len(self.rows) < self.max_frames

    def _open_stream(self, s):
        """The OSC sender when streaming is on; a bad target is a note, not an error."""
        if not s.osc_send:
            return None
        try:
            sender = OscSender(s.osc_target, bundle=s.osc_bundle)
        except VoodooError as exc:
            self.notes.append(f"{exc} The take was recorded without streaming.")
            return None
        for doll in self.dolls:
            doll.prepare_stream()
        return sender

    def _measure(self) -> None:
        now = time.monotonic()
        if self.feed.arrived is not None:
            self.latency = now - self.feed.arrived
        if self._last_tracked is not None:
            dt = max(now - self._last_tracked, 1e-6)
            self.rate = 1.0 / dt if not self.rate else 0.9 * self.rate + 0.1 / dt
        self._last_tracked = now

    @property
    def behind(self) -> int:
        """Camera frames recorded but not tracked yet (a clip's read-ahead does not count)."""
        return self.feed.backlog if self.source.live else 0

    @property
    def recording(self) -> bool:
        """The source is still being read (frames may still come)."""
        return self.feed.reading

    def stop_recording(self) -> None:
        """Read no further frame; the frames read already are still tracked."""
        self.feed.stop_reading()

    @property
    def progress(self) -> float:
        total = self.max_frames or self.source.count
        if self.source.live and not self.feed.reading:
            total = len(self.rows) + self.behind  # recording ended: what is left to track
        return min(len(self.rows) / total, 1.0) if total else 0.0

    # ------------------------------------------------------------------ footage

    def _open_writer(self, stack):
        path = footage_dir() / f"{bpy.path.clean_name(self.take_name)}.avi"
        self.footage = stack.enter_context(Footage(path, self.source.fps, self.source.size))

    # ------------------------------------------------------------------ end

    def close(self) -> None:
        """Release the source, the warp, the footage and the stand-in; the journal stays
        on disk until the take is stored, so nothing recorded is lost.
        """
        self._resources.close()

    def keep(self) -> str | None:
        """Store what was recorded with the blob (no apply); returns the take's name."""
        if self.stream is not None:
            self.notes += self.stream.warnings
        left = self.behind
        if left and self.footage is not None:
            self.notes.append(
                f"{left} recorded frame(s) were not tracked (stopped while completing the "
                f"take); the footage {self.footage.path.name} holds every frame."
            )
        self.close()
        if not self.rows:
            for doll in self.dolls:
                doll.journal.discard()
            return None
        takes = self._tracked_both_ways() if self.both_ways else {}
        fps = self.source.fps
        for doll in self.dolls:
            doll.keep(self.take_name, self.rows, self.rest_frame, fps, takes.get(doll.name))
        self.scene.voodoo.last_take = self.take_name
        return self.take_name

    def _tracked_both_ways(self) -> dict:
        """Each doll's take merged with a backward pass, by name.

        The backward pass reads the clip again, or a camera's footage (which holds every
        frame the camera gave, the take one per scene frame). Empty, with a note, when
        there is nothing to read again or it cannot be read: the take is then kept as
        tracked.
        """
        if self.clip is None and (self.footage is None or not self.footage.path.exists()):
            self.notes.append(
                "Both Ways needs a movie clip or the camera's footage: the take was kept "
                "as tracked."
            )
            return {}
        s = self.scene.voodoo
        forward = {d.name: d.take_of(self.rows, self.source.fps) for d in self.dolls}
        total = max(backward_frames(forward), 1)
        wm = bpy.context.window_manager
        bar = ProgressBar(total, "backwards") if bpy.app.background else None

        def progress(done: int) -> None:
            wm.progress_update(int(100 * done / total))
            if bar is not None:
                bar(done)

        backend, _ = make_backend(s.warp)
        wm.progress_begin(0, 100)
        try:
            trackers = {
                d.name: Tracker(d.blob, backend=backend, frozen=_frozen(s)) for d in self.dolls
            }
            troupe = Troupe({d.name: d.blob for d in self.dolls}, trackers=trackers)
            if self.clip is not None:
                reread = open_clip(self.clip)
            else:
                reread = CaptureSource(str(self.footage.path))  # a video file, whatever the camera
            with reread as source:
                return track_both_ways(troupe, source, forward, progress)
        except VoodooError as exc:
            self.notes.append(f"{exc} The take was kept as tracked forward.")
            return {}
        finally:
            wm.progress_end()
            backend.close()

    def finish(self) -> dict:
        """Store the take with each doll's blob and apply it to each doll's target (if any).

        Returns
        -------
        dict
            ``take`` (name), ``frames`` (tracked now), ``lost`` (scene frames not keyed, of
            any doll), ``applied`` (bool), ``action`` (the first applied doll's) and
            ``actions`` (every applied doll's, by doll), ``clip`` (the footage clip for camera
            takes), ``notes``.
        """
        if self.keep() is None:
            raise VoodooError("No frame was tracked; nothing to keep.")
        info = {
            "take": self.take_name,
            "frames": len(self.rows),
            "lost": [],
            "applied": False,
            "actions": {},
            "notes": self.notes,
        }
        if self.footage is not None and self.footage.path.exists():
            clip = bpy.data.movieclips.load(str(self.footage.path))
            clip.frame_start = self.rows[0][2]
            info["clip"] = clip
        lost, attention = set(), []
        for doll in self.dolls:
            out = doll.apply(self.scene, self.take_name)
            if out is None:
                continue
            info["actions"][doll.name] = out["action"]
            info.setdefault("action", out["action"])
            lost.update(out["lost"])
            attention += out["attention"] or []
            info["applied"] = True
        if info["applied"]:
            info.update(lost=sorted(lost), attention=attention)
        return info


def recording_now() -> bool:
    """A take is being recorded in this session."""
    return bool(_recording)


def interrupted_takes() -> list:
    """(journal path, blob mesh) of takes an interrupted recording left on disk."""
    return [(p, m) for p, m in recoverable_journals() if p not in _recording]
