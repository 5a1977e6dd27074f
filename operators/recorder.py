"""A take being recorded.

The modal operator forwards timer ticks to :meth:`Recorder.step`; the batch operator and the
tests call it in a loop (the bpy module has no event loop).
"""

from pathlib import Path

import bpy
import numpy as np

from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.media.images import to_uint8_bgr
from ..voodoo_addon.media.sources import open_source
from ..voodoo_addon.takes.rig import Rig, fit_mapping
from ..voodoo_addon.takes.take import Take
from ..voodoo_addon.tracking import Tracker
from . import overlay
from .apply import apply_take, check_target, layout_for, rest_vertices, shape_for_mode
from .frames import active_clip, open_clip, scene_frame
from .gpu_warp import make_backend
from .store import load_blob, load_take, store_take, unique_take_name

FOOTAGE_DIR = "voodoo_footage"


class Recorder:
    """Tracks a source frame by frame into a take and shows it live on the target.

    Parameters
    ----------
    context : bpy.types.Context
    max_frames : int, optional
        Stop after this many frames (a live camera stops after ``camera_seconds``).
    live : bool
        Move the scene to each tracked frame and pose the target there (off for batch).
    resume : str, optional
        Name of a stored take of a clip to continue: tracking starts on the frame after its
        last one, from its last pose (e.g. after reopening the file).

    Raises
    ------
    VoodooError
        No blob, no clip or camera, an unreadable clip, a frame size that does not match the
        blob, or a target that is not a mesh.
    """

    def __init__(
        self, context, max_frames: int | None = None, live: bool = True, resume: str | None = None
    ):
        scene = context.scene
        s = scene.voodoo
        self.scene = scene
        self.live = live
        self.blob_mesh = s.blob
        self.blob = load_blob(s.blob)
        self.target = s.target
        if self.target is not None:
            check_target(self.target)
            fit_mapping(self.blob, rest_vertices(self.target), s.axes)  # fail before tracking
        self.clip = None
        resume_from = None
        self.writer = None
        self.footage = None
        if s.source == "CAMERA":
            self.source = open_source(int(s.camera_index))
            fps = scene.render.fps / scene.render.fps_base
            self.max_frames = max_frames or max(1, round(s.camera_seconds * self.source.fps))
            self.start_frame = scene.frame_current
            self._frame_of = lambda fr: self.start_frame + int(round(fr.time * fps))
        else:
            self.clip = active_clip(context)
            self.source = open_clip(self.clip)
            start = max(0, min(s.capture_index, (self.source.count or 1) - 1))
            if resume:
                previous = load_take(self.blob_mesh, resume)
                start = int(previous.frame_indices[-1]) + 1
                resume_from = previous.params[-1]
                if self.source.count is not None and start >= self.source.count:
                    self.source.close()
                    raise VoodooError(f"Take {resume!r} already reaches the end of the clip.")
            self.source.seek(start)
            self.max_frames = max_frames
            self._frame_of = lambda fr: scene_frame(self.clip, fr.index)
        size = tuple(int(v) for v in self.blob.frame_size)
        if tuple(self.source.size) != size:
            self.source.close()
            raise VoodooError(
                f"The source is {self.source.size[0]}x{self.source.size[1]} but the blob was "
                f"built on a {size[0]}x{size[1]} frame; capture and build again."
            )
        self.backend, self.backend_note = make_backend(s.warp)
        frozen = [
            name
            for name, on in (
                ("translate-x", s.freeze_translation),
                ("translate-y", s.freeze_translation),
                ("rotate", s.freeze_rotation),
                ("scale", s.freeze_scale),
            )
            if on
        ]
        self.tracker = Tracker(self.blob, backend=self.backend, frozen=frozen)
        if resume_from is not None:
            self.tracker.reset(resume_from)
        self.take_name = unique_take_name(self.blob_mesh, s.take_name or "Take")
        self.rows = []  # (source index, time, scene frame, TrackResult)
        self._preview = None
        if self.target is not None and live:
            self._prepare_preview()
        if s.source == "CAMERA":
            self._open_writer()

    # ------------------------------------------------------------------ per frame

    def step(self) -> bool:
        """Track the next frame. Returns False when the take is complete.

        Raises
        ------
        VoodooError
            When the target was deleted during the take.
        """
        if self.target is not None:
            try:
                self.target.name  # noqa: B018 - raises once the object is gone
            except ReferenceError:
                self.target = None
                raise VoodooError(
                    "The target was deleted during the take; recording stopped."
                ) from None
        if self.max_frames is not None and len(self.rows) >= self.max_frames:
            return False
        frame = self.source.read()
        if frame is None:
            return False
        if self.writer is not None:
            self.writer.write(to_uint8_bgr(frame.pixels))
        res = self.tracker.track(frame.pixels)
        f = self._frame_of(frame)
        if self.rows and self.rows[-1][2] == f:  # two camera frames in one scene frame
            self.rows.pop()
        self.rows.append((frame.index, frame.time, f, res))
        overlay.live_state.update(nodes=res.nodes, triangles=self.blob.triangles, lost=res.lost)
        if self.live:
            self.scene.frame_set(f)
            if self._preview is not None and not res.lost:
                self._pose(res.params)
        return self.max_frames is None or len(self.rows) < self.max_frames

    @property
    def progress(self) -> float:
        total = self.max_frames or self.source.count
        return len(self.rows) / total if total else 0.0

    # ------------------------------------------------------------------ live preview

    def _prepare_preview(self):
        """Pose a stand-in copy of the target live; the target stays untouched (hidden).

        The copy goes away when the take ends; only then is the target animated.
        """
        s = self.scene.voodoo
        src = self.target
        copy = src.copy()
        copy.data = src.data.copy()
        copy.name = f"{src.name} (recording)"
        copy.animation_data_clear()
        if copy.data.shape_keys is not None:
            copy.data.shape_keys.animation_data_clear()
        for coll in src.users_collection:
            coll.objects.link(copy)
        src.hide_set(True)
        rest = rest_vertices(copy)
        modes = [m for m in s.modes if m.enabled and m.index < self.blob.n_modes]
        use = (s.apply_location, s.apply_rotation, s.apply_scale)
        rig = Rig(self.blob, self.tracker.layout, rest, s.axes, [m.index for m in modes], use)
        keys = [
            shape_for_mode(copy, self.blob_mesh, m, rig.offsets[i], rest)
            for i, m in enumerate(modes)
        ]
        self._preview = (copy, rig, keys, np.array(copy.matrix_basis))

    def _pose(self, params):
        from mathutils import Matrix

        copy, rig, keys, rest_matrix = self._preview
        values, transform = rig.pose(params)
        for kb, value in zip(keys, values, strict=True):
            kb.value = float(np.clip(value, kb.slider_min, kb.slider_max))
        copy.matrix_basis = Matrix((rest_matrix @ transform).tolist())

    def _drop_preview(self):
        if self._preview is None:
            return
        copy = self._preview[0]
        self._preview = None
        mesh = copy.data
        bpy.data.objects.remove(copy)
        if mesh.users == 0:
            bpy.data.meshes.remove(mesh)
        try:
            self.target.hide_set(False)
        except (ReferenceError, AttributeError, RuntimeError):
            pass

    # ------------------------------------------------------------------ footage

    def _open_writer(self):
        import cv2

        base = Path(bpy.path.abspath("//")) if bpy.data.filepath else Path(bpy.app.tempdir)
        folder = base / FOOTAGE_DIR
        folder.mkdir(parents=True, exist_ok=True)
        self.footage = folder / f"{bpy.path.clean_name(self.take_name)}.avi"
        w, h = self.source.size
        self.writer = cv2.VideoWriter(
            str(self.footage), cv2.VideoWriter_fourcc(*"MJPG"), self.source.fps, (w, h)
        )

    # ------------------------------------------------------------------ end

    def close(self) -> None:
        """Release the source, the warp and the live stand-in; nothing else changes."""
        self._drop_preview()
        self.source.close()
        self.backend.close()
        if self.writer is not None:
            self.writer.release()
            self.writer = None
        overlay.live_state.clear()

    def finish(self) -> dict:
        """Store the take with the blob and apply it to the target (if any).

        Returns
        -------
        dict
            ``take`` (name), ``frames`` (tracked), ``lost`` (scene frames not keyed),
            ``applied`` (bool), ``clip`` (the footage clip for camera takes).
        """
        self.close()
        if not self.rows:
            raise VoodooError("No frame was tracked; nothing to keep.")
        take = Take.from_results(
            [r for *_, r in self.rows],
            self.blob.triangles,
            self.tracker.parameter_names,
            [i for i, *_ in self.rows],
            [t for _, t, *_ in self.rows],
            self.source.fps,
        )
        layout_for(self.blob, take)  # sanity: the layout must round-trip
        store_take(self.blob_mesh, self.take_name, take)
        frames = self.blob_mesh.get("voodoo_take_frames")
        if frames is None:
            self.blob_mesh["voodoo_take_frames"] = {}
            frames = self.blob_mesh["voodoo_take_frames"]
        frames[self.take_name] = [int(f) for *_, f, _ in self.rows]
        self.scene.voodoo.last_take = self.take_name
        info = {"take": self.take_name, "frames": len(self.rows), "lost": [], "applied": False}
        if self.footage is not None and self.footage.exists():
            clip = bpy.data.movieclips.load(str(self.footage))
            clip.frame_start = self.rows[0][2]
            info["clip"] = clip
        if self.target is not None:
            out = apply_take(self.scene, self.target, self.blob_mesh, self.take_name)
            info.update(
                lost=out["lost"], applied=True, action=out["action"], attention=out["attention"]
            )
        return info
