"""Tracking a whole source into a take, and the take's file (the command-line contract)."""

from __future__ import annotations

import io
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..archive import check_arrays, header, load_npz, require
from ..blob.model import ActiveBlob
from ..checks import whole
from ..errors import VoodooError, read_file, write_file
from ..media.sources import FrameSource
from ..tracking import Tracker

TAKE_KIND = "voodoo-take"
TAKE_VERSION = 2
#: Versions this code reads as one doll's take (version 1 had no per-triangle visibility).
READABLE_VERSIONS = (1, 2)
#: The version of a file holding several dolls' takes (see :mod:`.dolls`).
SEVERAL_VERSION = 3


@dataclass(frozen=True, eq=False)
class Take:
    """The tracked motion of one blob through a source.

    Attributes
    ----------
    vertices : (T, m, 2) float64
        Mesh nodes in every frame, pixel coordinates (OpenCV convention).
    triangles : (t, 3) int32
    params : (T, P) float64
        Parameter vectors (see :mod:`voodoo_addon.tracking.params`); held at the last good value on
        lost frames.
    confidence : (T,) float64
        In [0, 1].
    lost : (T,) bool
    param_names : (P,) str
        Names of the parameters ("translate-x", ..., mode labels, photometric terms).
    frame_indices : (T,) int64
        Source frame of each row.
    times : (T,) float64
        Seconds (file: index / fps; camera: capture time).
    fps : float
    iterations : (T,) int64
    visible : (T, t) bool
        Triangles seen in each frame (the others were off the picture, covered or turned
        away, and kept their last seen shape).
    """

    vertices: np.ndarray
    triangles: np.ndarray
    params: np.ndarray
    confidence: np.ndarray
    lost: np.ndarray
    param_names: np.ndarray
    frame_indices: np.ndarray
    times: np.ndarray
    fps: float
    iterations: np.ndarray
    visible: np.ndarray

    def __len__(self) -> int:
        return len(self.params)

    def in_view(self) -> np.ndarray:
        """Per frame, the share of the doll's triangles in view (T,); 0 where it was lost.

        The same share the live stream sends (``/view``, see
        :func:`~voodoo_addon.stream.view_share`).
        """
        if not self.visible.shape[1]:
            return np.zeros(len(self))
        return np.where(self.lost, 0.0, self.visible.mean(axis=1))

    @classmethod
    def from_results(cls, results, triangles, param_names, frame_indices, times, fps) -> Take:
        """A take from the tracker's per-frame results.

        Parameters
        ----------
        results : sequence of TrackResult
        triangles : (t, 3) int
        param_names : sequence of str
        frame_indices, times : sequence (T,)
            Source frame and time of each result.
        fps : float
        """
        if not len(results):
            raise VoodooError("No frame was tracked; there is no take.")
        n_tri = len(triangles)
        return cls(
            vertices=np.stack([r.nodes for r in results]),
            triangles=np.asarray(triangles).copy(),
            params=np.stack([r.params for r in results]),
            confidence=np.array([r.confidence for r in results], dtype=np.float64),
            lost=np.array([r.lost for r in results], dtype=bool),
            param_names=np.array(param_names, dtype=str),
            frame_indices=np.asarray(frame_indices, dtype=np.int64),
            times=np.asarray(times, dtype=np.float64),
            fps=float(fps),
            iterations=np.array([r.iterations for r in results], dtype=np.int64),
            visible=np.stack(
                [
                    np.zeros(n_tri, bool) if r.visible is None else r.visible.astype(bool)
                    for r in results
                ]
            ),
        )

    def extended(self, more: Take) -> Take:
        """The take followed by ``more`` (a resumed recording of the same blob)."""
        if not np.array_equal(self.triangles, more.triangles) or list(self.param_names) != list(
            more.param_names
        ):
            raise VoodooError("The takes belong to different blobs; they cannot be joined.")
        return Take(
            vertices=np.concatenate([self.vertices, more.vertices]),
            triangles=self.triangles,
            params=np.concatenate([self.params, more.params]),
            confidence=np.concatenate([self.confidence, more.confidence]),
            lost=np.concatenate([self.lost, more.lost]),
            param_names=self.param_names,
            frame_indices=np.concatenate([self.frame_indices, more.frame_indices]),
            times=np.concatenate([self.times, more.times]),
            fps=self.fps,
            iterations=np.concatenate([self.iterations, more.iterations]),
            visible=np.concatenate([self.visible, more.visible]),
        )


def take_to_bytes(take: Take) -> bytes:
    """Serialise a take as ``.npz`` bytes (no pickles).

    Holds the contract's ``vertices``, ``triangles``, ``params``, ``confidence`` and
    ``mode_labels`` (the parameter names), plus ``lost``, ``frame_indices``, ``times``,
    ``fps``, ``iterations`` and a format header.
    """
    buf = io.BytesIO()
    np.savez_compressed(
        buf,
        format_kind=np.array(TAKE_KIND),
        format_version=np.array(TAKE_VERSION),
        **take_arrays(take),
    )
    return buf.getvalue()


def take_arrays(take: Take) -> dict[str, np.ndarray]:
    """A take's arrays as its file names them (without the format header)."""
    return {
        "vertices": take.vertices,
        "triangles": take.triangles,
        "params": take.params,
        "confidence": take.confidence,
        "mode_labels": take.param_names.astype(str),
        "lost": take.lost,
        "frame_indices": take.frame_indices,
        "times": take.times,
        "fps": np.array(take.fps),
        "iterations": take.iterations,
        "visible": take.visible,
    }


#: Every array of a take file: kind and shape (names are sizes that must agree).
_SPEC = {
    "vertices": ("float", ("T", "m", 2)),
    "triangles": ("int", ("t", 3)),
    "params": ("float", ("T", "P")),
    "confidence": ("float", ("T",)),
    "mode_labels": ("str", ("P",)),
    "lost": ("bool", ("T",)),
    "frame_indices": ("int", ("T",)),
    "times": ("float", ("T",)),
    "fps": ("float", ()),
    "iterations": ("int", ("T",)),
}


def take_from_bytes(data: bytes, source: str = "the take data") -> Take:
    """Inverse of :func:`take_to_bytes`.

    Raises
    ------
    VoodooError
        If the bytes are not a take of a version this code reads, or its arrays are damaged
        (missing, of the wrong kind or shape, NaN, not fitting together).
    """
    d = load_npz(data, source, "Voodoo take")
    is_take, version = header(d, TAKE_KIND)
    if is_take and version == SEVERAL_VERSION:
        names = ", ".join(str(n) for n in d["dolls"]) if "dolls" in d else "several dolls"
        raise VoodooError(
            f"{source} holds several dolls ({names}); read it as a take of several dolls "
            "(voodoo_addon.takes.dolls.load_takes)."
        )
    if not is_take or version not in READABLE_VERSIONS:
        raise VoodooError(f"{source} is not a Voodoo take of version {TAKE_VERSION}.")
    return take_from_arrays(d, version, source)


def take_from_arrays(d, version: int, source: str) -> Take:
    """One doll's take from its file's arrays (see :func:`take_arrays`), checked."""
    spec = dict(_SPEC, visible=("bool", ("T", "t"))) if version >= 2 else _SPEC
    size = check_arrays(d, spec, source)
    require(size["T"] >= 1, source, "no frames")
    tri = d["triangles"]
    require(len(tri) == 0 or (tri.min() >= 0 and tri.max() < size["m"]), source, "bad triangles")
    conf = d["confidence"]
    require(((conf >= 0) & (conf <= 1)).all(), source, "confidence outside 0..1")
    require(float(d["fps"]) > 0 and (d["frame_indices"] >= 0).all(), source, "bad frame times")
    if "visible" in spec:
        visible = d["visible"]
    else:  # version 1: every triangle of every tracked frame
        visible = np.repeat(~d["lost"][:, None], size["t"], axis=1)
    return Take(
        vertices=d["vertices"],
        triangles=tri,
        params=d["params"],
        confidence=conf,
        lost=d["lost"],
        param_names=d["mode_labels"],
        frame_indices=d["frame_indices"],
        times=d["times"],
        fps=float(d["fps"]),
        iterations=d["iterations"],
        visible=visible,
    )


def save_take(path, take: Take) -> None:
    """Write a take to an ``.npz`` file (see :func:`take_to_bytes`)."""
    write_file(path, take_to_bytes(take), "take")


def load_take(path) -> Take:
    """Read a take written by :func:`save_take`."""
    return take_from_bytes(read_file(path, "take"), source=str(path))


class ProgressBar:
    """A one-line progress bar on stderr (redrawn in place on a terminal)."""

    def __init__(self, total: int | None, label: str = "tracking", stream=None):
        self.total = total
        self.label = label
        self.stream = stream or sys.stderr
        self._t0 = time.perf_counter()
        self._last = -1.0
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def __call__(self, done: int) -> None:
        now = time.perf_counter()
        final = self.total is not None and done >= self.total
        if not final and now - self._last < (0.2 if self._tty else 2.0):
            return
        self._last = now
        rate = done / max(now - self._t0, 1e-9)
        if self.total:
            frac = min(done / self.total, 1.0)
            bar = "#" * int(30 * frac) + "-" * (30 - int(30 * frac))
            text = f"{self.label} [{bar}] {done}/{self.total} frames, {rate:.0f} fps"
        else:
            text = f"{self.label}: {done} frames, {rate:.0f} fps"
        end = "\n" if final or not self._tty else ""
        self.stream.write(("\r" if self._tty else "") + text + end)
        self.stream.flush()


def track_source(
    blob: ActiveBlob,
    source: FrameSource,
    tracker: Tracker | None = None,
    progress: Callable[[int], None] | None = None,
    limit: int | None = None,
) -> Take:
    """Track every frame of a source.

    Parameters
    ----------
    blob : ActiveBlob
    source : FrameSource
        Read from its current position to its end (or ``limit`` frames).
    tracker : Tracker, optional
        A configured tracker (a default one otherwise).
    progress : callable, optional
        Called with the number of frames done.
    limit : int, optional
        Stop after this many frames (needed for live cameras); at least 1.

    Returns
    -------
    Take
    """
    if limit is not None:
        limit = whole(limit, "the number of frames to track", 1)
    tracker = tracker or Tracker(blob)
    results, indices, times = [], [], []
    for frame in source:
        results.append(tracker.track(frame.pixels))
        indices.append(frame.index)
        times.append(frame.time)
        if progress is not None:
            progress(len(results))
        if limit is not None and len(results) >= limit:
            break
    if not results:
        raise VoodooError("The source gave no frames to track.")
    return Take.from_results(
        results, blob.triangles, tracker.parameter_names, indices, times, source.fps
    )


def missing_frames(
    source: FrameSource, take: Take, limit: int | None = None, name: str = "the source"
) -> str | None:
    """A warning when a file gave fewer frames than it announced (truncated, damaged).

    Parameters
    ----------
    source : FrameSource
        The source the take was tracked from (its frame count as announced).
    take : Take
    limit : int, optional
        The number of frames that was asked for.
    name : str
        The source's name in the message.

    Returns
    -------
    str or None
        None when every expected frame was tracked, or the source does not say how many it
        has (a camera).
    """
    if source.count is None or source.live or not len(take):
        return None
    expected = source.count - int(take.frame_indices[0])
    if limit is not None:
        expected = min(expected, limit)
    if len(take) >= expected:
        return None
    return (
        f"{name}: {expected} frames expected, {len(take)} read (the file ends early or is "
        f"damaged); the take has the {len(take)} frames read."
    )
