"""Judging a track without ground truth: texture consistency, folded and lost frames.

A correct track carries every surface point of the first frame to where that point is in
frame ``t``. Pull frame ``t`` back through the tracked mesh onto the first frame's mesh
(piecewise affine) and the picture should look like the first frame again, up to lighting.
:func:`texture_consistency` compares the two by local normalised cross-correlation (NCC) in
small windows, on the textured pixels only (a flat patch says nothing about alignment), so
smooth lighting changes do not count and misregistration does. A mesh that folds over itself
can still score well (a fold hides the pixels that would disagree), so the folded frames are
counted separately: :func:`folded_triangles`.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from ..blob.mesh import TriMesh, rasterize, triangle_areas

#: Side of the NCC window, pixels.
WINDOW = 15
#: A pixel is textured when the grey level's standard deviation in its window exceeds this.
MIN_TEXTURE_STD = 0.03
#: A triangle whose area falls below this fraction of its first-frame area (or turns over)
#: counts as folded.
FOLD_AREA_RATIO = 0.01


def grey(image: np.ndarray) -> np.ndarray:
    """Luma (H, W) float32 in [0, 1] of RGB (H, W, 3): uint8, or float in [0, 1]."""
    img = np.asarray(image)
    if img.dtype == np.uint8:
        return cv2.cvtColor(img, cv2.COLOR_RGB2GRAY).astype(np.float32) * np.float32(1 / 255)
    return cv2.cvtColor(img.astype(np.float32), cv2.COLOR_RGB2GRAY)


def folded_triangles(vertices: np.ndarray, rest: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Which triangles are inverted or collapsed relative to the rest mesh.

    Parameters
    ----------
    vertices : (m, 2) float64
        Nodes in the frame being judged.
    rest : (m, 2) float64
        Nodes in the reference frame.
    triangles : (t, 3) int

    Returns
    -------
    (t,) bool
        True where the signed area has turned over, or shrunk below
        :data:`FOLD_AREA_RATIO` of the rest area relative to the median triangle (so a
        blob that shrinks as a whole is not collapsed), and for non-finite nodes.
    """
    ref = triangle_areas(rest, triangles)
    now = triangle_areas(vertices, triangles)
    ratio = now / np.where(np.abs(ref) > 1e-12, ref, 1e-12)
    typical = np.median(ratio) if np.isfinite(ratio).all() else np.nan
    return ~(ratio >= FOLD_AREA_RATIO * max(typical, 0.0)) | ~(ratio > 0)  # NaN: folded


@dataclass(frozen=True)
class Consistency:
    """Scores of one track (see :func:`score_track`).

    Attributes
    ----------
    per_frame : (T,) float64
        Mean local NCC over the textured pixels seen in each frame, in [-1, 1]; NaN where no
        textured pixel of the reference lands on the picture.
    seen : (T,) float64
        Fraction of the textured reference pixels that land on the picture.
    folded : (T,) bool
        A triangle is inverted or collapsed in this frame.
    lost : (T,) bool
        The tracker flagged the frame lost.
    """

    per_frame: np.ndarray
    seen: np.ndarray
    folded: np.ndarray
    lost: np.ndarray

    @property
    def mean(self) -> float:
        v = self.per_frame[1:]
        v = v[np.isfinite(v)]
        return float(v.mean()) if len(v) else float("nan")

    @property
    def p10(self) -> float:
        """10th percentile over frames (the bad frames' level)."""
        v = self.per_frame[1:]
        v = v[np.isfinite(v)]
        return float(np.percentile(v, 10)) if len(v) else float("nan")

    @property
    def folded_fraction(self) -> float:
        return float(np.mean(self.folded))

    @property
    def lost_fraction(self) -> float:
        return float(np.mean(self.lost))

    def summary(self) -> dict:
        return {
            "consistency_mean": round(self.mean, 4),
            "consistency_p10": round(self.p10, 4),
            "folded_fraction": round(self.folded_fraction, 4),
            "lost_fraction": round(self.lost_fraction, 4),
        }

    def report(self, take) -> dict:
        """The summary with every frame's figures (JSON-ready) for ``take``, the track scored."""
        out = {"frames": len(take), **self.summary()}
        per_frame = self.per_frame
        out["per_frame"] = [None if not np.isfinite(v) else round(float(v), 4) for v in per_frame]
        out["folded"] = self.folded.astype(int).tolist()
        out["lost"] = self.lost.astype(int).tolist()
        return out


class ConsistencyJudge:
    """Scores frames of a track against its reference frame.

    Parameters
    ----------
    reference : (H, W, 3) float32
        The first frame (the one the mesh was drawn on).
    vertices : (m, 2) float64
        The mesh nodes on the reference frame.
    triangles : (t, 3) int
    window : int
        NCC window side, pixels (odd).
    """

    def __init__(self, reference, vertices, triangles, window: int = WINDOW):
        self.rest = np.asarray(vertices, dtype=np.float64)
        self.triangles = np.asarray(triangles)
        self.window = int(window) | 1
        pix = rasterize(TriMesh(self.rest, self.triangles, np.zeros(len(self.rest), bool)))
        self.pixels = pix
        h, w = reference.shape[:2]
        keep = (
            (pix.coords[:, 0] >= 0)
            & (pix.coords[:, 1] >= 0)
            & (pix.coords[:, 0] <= w - 1)
            & (pix.coords[:, 1] <= h - 1)
        )
        self._keep = keep
        xy = pix.coords[keep].astype(np.int64)
        lo = xy.min(axis=0)
        self._lo = lo
        self._shape = tuple((xy.max(axis=0) - lo + 1)[::-1])  # (rows, cols)
        self._rc = (xy[:, 1] - lo[1], xy[:, 0] - lo[0])
        ref = self._canvas(grey(reference)[xy[:, 1], xy[:, 0]])
        inside = self._canvas(np.ones(len(xy), np.float32))
        self._ref = ref
        self._inside = inside
        mean, std, full = self._local_stats(ref, inside)
        self._textured = (std >= MIN_TEXTURE_STD) & full & (inside > 0)

    def _canvas(self, values: np.ndarray) -> np.ndarray:
        out = np.zeros(self._shape, np.float32)
        out[self._rc] = values
        return out

    def _box(self, img: np.ndarray) -> np.ndarray:
        k = self.window
        return cv2.boxFilter(img, -1, (k, k), normalize=False, borderType=cv2.BORDER_CONSTANT)

    def _local_stats(self, img, mask):
        n = self._box(mask)
        s = self._box(img * mask)
        s2 = self._box(img * img * mask)
        safe = np.maximum(n, 1.0)
        mean = s / safe
        var = np.maximum(s2 / safe - mean * mean, 0.0)
        return mean, np.sqrt(var), n >= 0.5 * self.window**2

    def pull_back(self, frame: np.ndarray, vertices: np.ndarray):
        """Frame ``t`` sampled at the reference pixels' tracked positions.

        Returns
        -------
        values : (rows, cols) float32
            Grey level at each reference pixel of the canvas (0 outside the mesh).
        on_frame : (rows, cols) bool
            The reference pixel lands on the picture.
        """
        v = np.asarray(vertices, dtype=np.float64)
        tri = self.triangles[self.pixels.triangle[self._keep]]
        wts = self.pixels.weights[self._keep]
        pos = np.einsum("nk,nkd->nd", wts, v[tri]).astype(np.float32)
        h, w = frame.shape[:2]
        finite = np.isfinite(pos).all(axis=1)
        pos[~finite] = -10.0
        on = finite & (pos[:, 0] >= 0) & (pos[:, 1] >= 0) & (pos[:, 0] <= w - 1)
        on &= pos[:, 1] <= h - 1
        map_x = np.full(self._shape, -10.0, np.float32)
        map_y = np.full(self._shape, -10.0, np.float32)
        map_x[self._rc], map_y[self._rc] = pos[:, 0], pos[:, 1]
        vals = cv2.remap(
            grey(frame), map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT
        )
        return vals, self._canvas(on.astype(np.float32)) > 0

    def score(self, frame: np.ndarray, vertices: np.ndarray) -> tuple[float, float]:
        """(mean local NCC over the textured pixels seen, fraction of them seen)."""
        img, on = self.pull_back(frame, vertices)
        mask = on.astype(np.float32)
        n = self._box(mask)
        safe = np.maximum(n, 1.0)
        ma = self._box(self._ref * mask) / safe
        mb = self._box(img * mask) / safe
        cab = self._box(self._ref * img * mask) / safe - ma * mb
        vaa = self._box(self._ref * self._ref * mask) / safe - ma * ma
        vbb = self._box(img * img * mask) / safe - mb * mb
        den = np.sqrt(np.maximum(vaa, 0.0) * np.maximum(vbb, 0.0))
        ncc = np.where(den > 1e-6, cab / np.maximum(den, 1e-6), 0.0)
        use = self._textured & (mask > 0) & (n >= 0.5 * self.window**2)
        n_tex = int(np.count_nonzero(self._textured))
        if n_tex == 0:
            return float("nan"), 0.0
        seen = float(np.count_nonzero(use)) / n_tex
        if not use.any():
            return float("nan"), seen
        return float(np.clip(ncc[use], -1.0, 1.0).mean()), seen


def score_track(frames, vertices, triangles, lost=None) -> Consistency:
    """Texture consistency, folds and losses of a whole track.

    Parameters
    ----------
    frames : iterable of (H, W, 3) float32
        The tracked frames, the reference first.
    vertices : (T, m, 2) float64
        Tracked nodes per frame (row 0 on the reference).
    triangles : (t, 3) int
    lost : (T,) bool, optional
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    judge = None
    scores, seen = [], []
    for i, frame in enumerate(frames):
        if i >= len(vertices):
            break
        if judge is None:
            judge = ConsistencyJudge(frame, vertices[0], triangles)
        s, f = judge.score(frame, vertices[i])
        scores.append(s)
        seen.append(f)
    t = len(scores)
    rest = vertices[0]
    folded = np.array([folded_triangles(vertices[i], rest, triangles).any() for i in range(t)])
    lost = np.zeros(t, bool) if lost is None else np.asarray(lost[:t], dtype=bool)
    return Consistency(np.array(scores), np.array(seen), folded, lost)


def check_take(source, take) -> Consistency:
    """Score a take against the video it was tracked on.

    Parameters
    ----------
    source : FrameSource
        Read from the take's first frame on; the frames the take holds are picked out.
    take : Take

    Raises
    ------
    VoodooError
        When the video ends before the take does or its frames are not the take's size.
    """
    from ..errors import VoodooError

    wanted = {int(i): row for row, i in enumerate(take.frame_indices)}
    frames = [None] * len(take)
    start = int(np.min(take.frame_indices))
    source.seek(start)
    last = int(np.max(take.frame_indices))
    for frame in source:
        if frame.index in wanted:
            frames[wanted[frame.index]] = frame.pixels
        if frame.index >= last:
            break
    missing = [int(take.frame_indices[i]) for i, f in enumerate(frames) if f is None]
    if missing:
        raise VoodooError(
            f"The video has no frame {missing[0]} of the take ({len(missing)} missing): "
            "is it the clip the take was tracked on?"
        )
    h, w = frames[0].shape[:2]
    span = np.ptp(take.vertices[np.isfinite(take.vertices).all(axis=(1, 2))], axis=(0, 1))
    if take.vertices[..., 0].min() > w + span[0] or take.vertices[..., 1].min() > h + span[1]:
        raise VoodooError("The take's mesh lies outside this video; is it the right clip?")
    return score_track(frames, take.vertices, take.triangles, take.lost)
