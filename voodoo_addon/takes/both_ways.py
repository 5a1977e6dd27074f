"""A recorded take tracked both ways: forward as recorded, then backward from its end.

Live, the tracker has only the frames so far. When a folded or turned part comes back it
shows first as a sliver, edge-on, and the tracker must find it again from that; it can also
lose the doll for a few frames while it does. A recorded take has its end as well: tracked
backwards from its last frame, the returning part is a part *leaving* view, and the tracker
follows it from where it is well seen. Each pass is better on other frames, so
:func:`merge` keeps, frame by frame, the pass whose fit is surer:

- the confidences are compared averaged over :data:`WINDOW` frames (one frame's confidence
  is noisy, and a pass picked for one frame only would flicker), each less a doubt on a
  part the pass has just found again (:data:`AGAIN_DOUBT`);
- where the two scores lie within :data:`TIE` of each other the passes are mixed instead,
  in proportion (half and half at equal scores): a few hundredths of confidence do not
  tell which pass is nearer, and the mean of the two is no further off than they are on
  average;
- a change from one pass to the other is spread over :data:`FADE` frames (the nodes and the
  parameters crossfade), so the mode values stay continuous where the two passes disagree;
- where one pass lost the doll and the other did not, the other is taken as it is.

On the fold renders (``samples/folds`` and the held-out batches, ``python -m
voodoo_addon.devtools.folds --trackers ours both``), clean, redrawn and through a camera,
this lowers the node error on 156 of 162 tracks and the largest mode jump on average, and
all but one of the 53 frames lost while a third of the doll is in view are found
(BENCHMARKS.md, *A recorded take tracked both ways*). It costs a second tracking of the
take, so it is for recorded takes (``voodoo track --both-ways``), never the live stream.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import replace

import numpy as np

from ..errors import VoodooError
from ..media.sources import FrameSource
from ..tracking.troupe import Troupe
from .dolls import track_dolls
from .take import Take

#: Frames the two passes' confidences are averaged over before they are compared.
WINDOW = 5
#: Frames a change from one pass to the other is spread over.
FADE = 5
#: Where the two passes' scores lie within this of each other, neither is picked: they are
#: mixed, half and half at equal scores, all of the surer one at this far apart. Scores a
#: few hundredths apart say little about which pass is nearer the doll, and the mean of two
#: poses is never further off than the two are on average: ``paper_half_fold``'s frames
#: 46-48 score 0.31 forward and 0.33-0.34 backward, the passes 1.86-1.91 and 1.51-1.83 px
#: off, and mixed 1.32-1.42 px off, where the backward pass alone was taken before.
TIE = 0.05
#: A part a pass has just found again, after a fold or a turn, is placed worse than by a
#: pass that followed it as it left view, though its confidence may be as high: the whole
#: doll's quality hardly falls for a part a few pixels off (sheet_foldover's flap: 0.87-0.98
#: with the flap 2-8 px off). Each pass's confidence is lowered by :data:`AGAIN_DOUBT`
#: times the share of the triangles it sees that it did not see on one of the
#: :data:`AGAIN_FRAMES` frames before (in its own direction of time).
AGAIN_FRAMES = 10
AGAIN_DOUBT = 0.5
#: Frames read at a time when reading a file backwards (each chunk from one seek).
CHUNK = 32
#: The backward pass starts from a doll's pose on the take's last frame only when it was
#: found there at least this surely. A take often ends with the doll put down or out of
#: the picture, or followed at a wrong pose after a turn (a low-contrast plush left 12 px
#: off at 0.46 to the end): such a doll is searched for first, around its last pose found
#: this surely, as a lost doll is.
SURE = 0.5


def frames_backward(source: FrameSource, first: int, last: int, chunk: int = CHUNK) -> Iterator:
    """The frames ``last`` down to ``first`` of a file, read a chunk at a time from a seek.

    Raises VoodooError for a camera (its past frames are gone) or a frame that cannot be
    read again.
    """
    if source.live:
        raise VoodooError(
            "A camera's take cannot be tracked backwards: record it to a file, then track the file."
        )
    end = last + 1
    while end > first:
        start = max(first, end - chunk)
        source.seek(start)
        frames = []
        for _ in range(end - start):
            frame = source.read()
            if frame is None:
                raise VoodooError(
                    f"Frame {start + len(frames)} could not be read again to track the take "
                    "backwards (the file is damaged or changed)."
                )
            frames.append(frame)
        yield from reversed(frames)
        end = start


def track_backward(
    troupe: Troupe,
    source: FrameSource,
    forward: dict[str, Take],
    progress: Callable[[int], None] | None = None,
) -> dict[str, Take]:
    """Every doll tracked from the end of its forward take back to its start.

    The pass starts on the take's last frame. A doll found there at least :data:`SURE`
    surely starts from its pose there; any other doll (put down, out of the picture, or
    followed at a doubtful pose) is searched for first, as a lost one, around its last
    pose found that surely (:func:`sure_rows`), and is lost backwards until a frame finds
    it. The takes returned are in forward order, row for row with ``forward``.

    Every frame of the source between the take's first frame and its last is tracked, also
    those the take skips: a camera's take keeps one frame per scene frame, while its footage
    holds every frame the camera gave (:func:`backward_frames` of them, for a progress bar).

    Raises VoodooError when a doll is never found that surely (nothing to search around),
    or when the take's frames are not frames of ``source`` in order.
    """
    indices = np.asarray(next(iter(forward.values())).frame_indices)
    sure = sure_rows(forward)
    never = [name for name, row in sure.items() if row is None]
    if never:
        raise VoodooError(
            f"The take never has {never[0]!r} found at a confidence of {SURE} or more: "
            "there is nothing to track it backwards from."
        )
    if np.any(np.diff(indices) <= 0):
        raise VoodooError("The take's frames are not in order: it cannot be tracked backwards.")
    last = len(indices) - 1
    troupe.reset()
    for name, take in forward.items():
        troupe.trackers[name].reset(take.params[sure[name]], search=sure[name] < last)
    first_index, last_index = int(indices[0]), int(indices[-1])
    back = track_dolls(troupe, _Backwards(source, first_index, last_index), progress)
    out = {}
    for name, take in forward.items():
        got = _rows(back[name], slice(None, None, -1))  # forward order
        if not np.array_equal(got.frame_indices, np.arange(first_index, last_index + 1)):
            raise VoodooError(
                "The source did not give the take's frames again: it cannot be tracked "
                "backwards from it."
            )
        got = _rows(got, indices - first_index)  # the take's own frames
        out[name] = replace(got, times=take.times)
    return out


def backward_frames(forward: dict[str, Take]) -> int:
    """How many frames :func:`track_backward` reads for ``forward`` (0: it cannot start)."""
    if any(row is None for row in sure_rows(forward).values()):
        return 0
    indices = next(iter(forward.values())).frame_indices
    return max(int(indices[-1]) - int(indices[0]) + 1, 0)


class _Backwards:
    """Frames ``first`` to ``last`` of ``source``, read backwards (:func:`frames_backward`).

    What :func:`~.dolls.track_dolls` takes for a source: it iterates it and reads its fps.
    """

    def __init__(self, source: FrameSource, first: int, last: int):
        self.fps = source.fps
        self._span = (source, first, last)

    def __iter__(self):
        return frames_backward(*self._span)


def sure_rows(forward: dict[str, Take]) -> dict[str, int | None]:
    """Each doll's last row found at least :data:`SURE` surely (None: none), by name."""
    out = {}
    for name, take in forward.items():
        rows = np.flatnonzero(~take.lost & (take.confidence >= SURE))
        out[name] = int(rows[-1]) if len(rows) else None
    return out


def _rows(take: Take, rows: slice | np.ndarray) -> Take:
    """The take's rows ``rows`` (a slice or row numbers)."""
    per_row = ("vertices", "params", "confidence", "lost", "frame_indices", "times")
    per_row += ("iterations", "visible")
    return replace(take, **{k: getattr(take, k)[rows] for k in per_row})


def _mean(x: np.ndarray, width: int) -> np.ndarray:
    """Running mean over ``width`` frames, the ends held (same length)."""
    if width <= 1 or len(x) < 2:
        return x.astype(np.float64)
    pad = width // 2
    padded = np.pad(x.astype(np.float64), (pad, width - 1 - pad), mode="edge")
    return np.convolve(padded, np.ones(width) / width, mode="valid")


def found_again(take: Take, backward: bool = False) -> np.ndarray:
    """Per frame, the share (T,) of the doll a pass has just found again.

    The triangles it sees that it did not see on one of the :data:`AGAIN_FRAMES` frames
    before (after, for a backward pass: before in its own time).
    """
    unseen = ~np.asarray(take.visible, bool)
    if backward:
        unseen = unseen[::-1]
    counts = np.vstack([np.zeros((1, unseen.shape[1]), np.int64), np.cumsum(unseen, axis=0)])
    rows = np.arange(len(unseen))
    gone = (counts[rows] - counts[np.maximum(rows - AGAIN_FRAMES, 0)]) > 0
    share = (gone & ~unseen).mean(axis=1)
    return share[::-1] if backward else share


def backward_share(forward: Take, backward: Take) -> np.ndarray:
    """Per frame, the weight (T,) in [0, 1] of the backward pass in the merge.

    Each pass's confidence less :data:`AGAIN_DOUBT` times the share of the doll it has just
    found again (:func:`found_again`; a lost frame counts -1) is averaged over
    :data:`WINDOW` frames. The weight is 1 where the backward pass scores :data:`TIE` or
    more higher, 0 where the forward one does, in proportion between (a half at equal
    scores), and crossfaded over :data:`FADE` frames; exactly 0 or 1 where one pass lost the
    doll and the other did not.
    """
    doubt_f = AGAIN_DOUBT * found_again(forward)
    doubt_b = AGAIN_DOUBT * found_again(backward, backward=True)
    score_f = _mean(np.where(forward.lost, -1.0, forward.confidence - doubt_f), WINDOW)
    score_b = _mean(np.where(backward.lost, -1.0, backward.confidence - doubt_b), WINDOW)
    share = _mean(np.clip(0.5 + (score_b - score_f) / (2.0 * TIE), 0.0, 1.0), FADE)
    share = np.where(forward.lost & ~backward.lost, 1.0, share)
    return np.where(backward.lost & ~forward.lost, 0.0, share)


def merge(forward: Take, backward: Take) -> Take:
    """One take from two passes over the same frames (see the module's list)."""
    if len(forward) != len(backward) or not np.array_equal(
        forward.frame_indices, backward.frame_indices
    ):
        raise VoodooError("The two passes do not cover the same frames; they cannot be merged.")
    if list(forward.param_names) != list(backward.param_names):
        raise VoodooError("The two passes belong to different blobs; they cannot be merged.")
    w = backward_share(forward, backward)
    back = w >= 0.5

    def mixed(f: np.ndarray, b: np.ndarray) -> np.ndarray:
        shape = (-1,) + (1,) * (f.ndim - 1)
        return (1.0 - w).reshape(shape) * f + w.reshape(shape) * b

    return Take(
        vertices=mixed(forward.vertices, backward.vertices),
        triangles=forward.triangles,
        params=mixed(forward.params, backward.params),
        confidence=mixed(forward.confidence, backward.confidence),
        lost=np.where(back, backward.lost, forward.lost),
        param_names=forward.param_names,
        frame_indices=forward.frame_indices,
        times=forward.times,
        fps=forward.fps,
        iterations=forward.iterations + backward.iterations,
        visible=np.where(back[:, None], backward.visible, forward.visible),
    )


def track_both_ways(
    troupe: Troupe,
    source: FrameSource,
    forward: dict[str, Take],
    progress: Callable[[int], None] | None = None,
) -> dict[str, Take]:
    """The forward takes merged with a backward pass over the same frames (see :func:`merge`)."""
    backward = track_backward(troupe, source, forward, progress)
    return {name: merge(take, backward[name]) for name, take in forward.items()}
