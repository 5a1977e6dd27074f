"""Several dolls in one take: one tracker per doll on the same frames, overlaps resolved.

``Troupe({"left": blob_a, "right": blob_b}).track(frame)`` registers every doll to the frame
and returns one :class:`~.tracker.TrackResult` per doll, by name. The frame is decoded once
(by the caller) and each tracker converts only the region around its own doll, so tracking
several dolls costs the sum of tracking each alone.

Dolls may touch and cross. Where two registered meshes overlap in the picture, the frame
shows one of them: the doll *in front* is the one whose template correlates better with the
frame's pixels there. The triangles of the doll behind that lie under the front doll's mesh
are marked not visible (covered: their shape is the last one seen, as for a hand over them),
never lost or folded because of it. When texture cannot tell (both flat there), the order of
the last frame that could tell is kept.
"""

from __future__ import annotations

from dataclasses import replace
from itertools import combinations

import cv2
import numpy as np

from ..blob.model import ActiveBlob
from ..errors import VoodooError
from .evaluation import Cover
from .options import TrackerOptions
from .tracker import Tracker, TrackResult

#: Template pixels correlated per doll to decide which one is in front (an even subsample).
ORDER_SAMPLES = 1500
#: The overlap must hold this many template pixels of each doll to be judged at all.
ORDER_MIN_PIXELS = 30
#: One doll is in front when its correlation beats the other's by this much; otherwise the
#: order already known is kept.
ORDER_MARGIN = 0.05
#: The cover of a doll in front reaches past its mesh by this many pixels at least, and by
#: this share of its length: an outline lies inside the object's edge, and the pixels along
#: the edge mix the two dolls.
COVER_MARGIN = 3
COVER_GROWTH = 0.04
#: A doll behind gets a cover when the front doll's box comes this close (pixels) to where
#: it was in the last frame: nearer than a frame's motion can bring them together.
COVER_REACH = 64.0
#: Sub-pixel bits for rasterising a mesh's footprint.
_SHIFT = 2


def doll_names(names) -> list[str]:
    """Check doll names: non-empty, distinct (after trimming); the cleaned names."""
    out = [str(n).strip() for n in names]
    if not out:
        raise VoodooError("A take needs at least one doll.")
    if any(not n for n in out):
        raise VoodooError("Every doll needs a name.")
    seen = set()
    for n in out:
        if n in seen:
            raise VoodooError(f"Two dolls are named {n!r}; give each doll its own name.")
        seen.add(n)
    return out


class Troupe:
    """Tracks several active blobs through the same frames.

    Parameters
    ----------
    blobs : mapping of str to ActiveBlob
        The dolls by name (the order is kept), all built on frames of one size.
    options : TrackerOptions, optional
        The same for every doll.
    frozen : mapping of str to iterable of str, optional
        Parameters held fixed, per doll.
    trackers : mapping of str to Tracker, optional
        Configured trackers to use instead (e.g. with another warp backend).
    """

    def __init__(self, blobs, options: TrackerOptions | None = None, frozen=None, trackers=None):
        blobs = dict(blobs)
        self.names = doll_names(blobs)
        self.blobs = dict(zip(self.names, blobs.values(), strict=True))
        sizes = {tuple(int(v) for v in b.frame_size) for b in self.blobs.values()}
        if len(sizes) > 1:
            raise VoodooError("The dolls were outlined on frames of different sizes.")
        frozen = frozen or {}
        given = dict(trackers or {})
        self.trackers = {
            n: given.get(n) or Tracker(b, options=options, frozen=frozen.get(n, ()))
            for n, b in self.blobs.items()
        }
        self._footprints = {n: _Template(b) for n, b in self.blobs.items()}
        #: The doll in front, for each pair whose order is known.
        self._front: dict[frozenset, str] = {}
        #: Each doll's nodes in the last frame.
        self._last: dict[str, np.ndarray] = {}

    def __len__(self) -> int:
        return len(self.names)

    def reset(self) -> None:
        """Every doll starts over from its capture pose."""
        for tracker in self.trackers.values():
            tracker.reset()
        self._front.clear()
        self._last.clear()

    def track(self, frame: np.ndarray) -> dict[str, TrackResult]:
        """Register every doll to one frame; each doll's result by name.

        Dolls known to be in front are registered first; a doll behind one of them then
        leaves out what that one covers in this frame (see :class:`~.evaluation.Cover`).
        """
        frame = np.asarray(frame)
        if len(self.names) == 1:
            name = self.names[0]
            return {name: self.trackers[name].track(frame)}
        results: dict[str, TrackResult] = {}
        for name in self._depth_order():
            near = self._last.get(name)
            fronts = [
                f
                for f in results
                if self.in_front(f, name) == f
                and not results[f].lost
                and near is not None
                and _boxes_meet(results[f].nodes, near, COVER_REACH)
            ]
            cover = self._cover(frame.shape[:2], [results[f] for f in fronts], fronts)
            results[name] = self.trackers[name].track(frame, cover)
        results = self._resolve_overlaps(frame, results)
        for name, r in results.items():
            self._last[name] = r.nodes
        return {name: results[name] for name in self.names}

    def _depth_order(self) -> list[str]:
        """The dolls, those in front of more others first (the given order otherwise)."""
        ahead = dict.fromkeys(self.names, 0)
        for front in self._front.values():
            ahead[front] += 1
        return sorted(self.names, key=lambda n: -ahead[n])

    def _cover(self, shape, results, names) -> Cover | None:
        """The frame pixels under the meshes of ``results``, grown by a margin; None if none."""
        if not results:
            return None
        grows = [max(COVER_MARGIN, int(round(COVER_GROWTH * self.blobs[n].length))) for n in names]
        pad = max(grows) + 1
        nodes = np.vstack([r.nodes for r in results])
        h, w = shape
        x0, y0 = np.clip(np.floor(nodes.min(axis=0)).astype(int) - pad, 0, [w, h])
        x1, y1 = np.clip(np.ceil(nodes.max(axis=0)).astype(int) + pad + 1, 0, [w, h])
        if x1 <= x0 or y1 <= y0:
            return None
        mask = np.zeros((y1 - y0, x1 - x0), np.uint8)
        for r, name, grow in zip(results, names, grows, strict=True):
            one = np.zeros_like(mask)
            tri = self._footprints[name].triangles
            polys = np.round((r.nodes[tri] - [x0, y0]) * (1 << _SHIFT)).astype(np.int32)
            cv2.fillPoly(one, list(polys), 1, lineType=cv2.LINE_8, shift=_SHIFT)
            kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * grow + 1, 2 * grow + 1))
            mask |= cv2.dilate(one, kernel)
        return Cover(mask.astype(bool), (x0, y0)) if mask.any() else None

    def in_front(self, a: str, b: str) -> str | None:
        """The name of whichever of ``a`` and ``b`` was last seen in front, if known."""
        return self._front.get(frozenset((a, b)))

    # ------------------------------------------------------------------ overlaps

    def _resolve_overlaps(self, frame, results):
        covered = {n: None for n in results}
        for a, b in combinations(self.names, 2):
            ra, rb = results[a], results[b]
            if ra.lost or rb.lost or not _boxes_meet(ra.nodes, rb.nodes):
                continue
            ta, tb = self._footprints[a], self._footprints[b]
            in_b = ta.pixels_inside(ra.nodes, rb.nodes, tb.triangles)
            in_a = tb.pixels_inside(rb.nodes, ra.nodes, ta.triangles)
            if in_a is None and in_b is None:
                continue
            front = self._order(frame, a, b, ra, rb, in_b, in_a)
            if front is None:
                continue
            behind = b if front == a else a
            under = self._footprints[behind].triangles_inside(
                results[behind].nodes, results[front].nodes, self._footprints[front].triangles
            )
            if under.any():
                covered[behind] = under if covered[behind] is None else covered[behind] | under
        for name, under in covered.items():
            if under is not None:
                r = results[name]
                results[name] = replace(r, visible=r.visible & ~under)
        return results

    def _order(self, frame, a, b, ra, rb, a_pixels, b_pixels) -> str | None:
        """Which of two overlapping dolls the frame shows where they overlap."""
        key = frozenset((a, b))
        known = self._front.get(key)
        ca = self._footprints[a].correlation(frame, ra.nodes, a_pixels)
        cb = self._footprints[b].correlation(frame, rb.nodes, b_pixels)
        if ca is not None and cb is not None and abs(ca - cb) >= ORDER_MARGIN:
            known = a if ca > cb else b
        elif known is None and (ca is not None or cb is not None):
            known = a if (cb is None or (ca is not None and ca >= cb)) else b
        if known is not None:
            self._front[key] = known
        return known


class _Template:
    """A doll's template pixels and mesh, for footprints and correlations in a frame."""

    def __init__(self, blob: ActiveBlob):
        self.triangles = np.asarray(blob.triangles, np.int64)
        tri = np.asarray(blob.pixel_triangle, np.int64)
        step = max(1, len(tri) // ORDER_SAMPLES)
        self.corner = self.triangles[tri[::step]]  # (n, 3) node indices
        self.weights = np.asarray(blob.pixel_weights, np.float64)[::step]
        grey = np.asarray(blob.template, np.float64)[::step].mean(axis=1)
        self.grey = grey
        self.textured = float(grey.std()) > 1e-3
        self.pixel_of_triangle = tri[::step]

    def positions(self, nodes: np.ndarray) -> np.ndarray:
        """(n, 2) frame positions of the sampled template pixels for mesh ``nodes``."""
        return np.einsum("nk,nkd->nd", self.weights, nodes[self.corner])

    def pixels_inside(self, nodes, other_nodes, other_triangles):
        """Sampled pixels lying under another mesh (bool (n,)), or None when too few."""
        inside = _inside_mesh(self.positions(nodes), other_nodes, other_triangles)
        return inside if np.count_nonzero(inside) >= ORDER_MIN_PIXELS else None

    def triangles_inside(self, nodes, other_nodes, other_triangles) -> np.ndarray:
        """(t,) bool: this mesh's triangles whose centre lies under the other mesh."""
        centres = nodes[self.triangles].mean(axis=1)
        return _inside_mesh(centres, other_nodes, other_triangles)

    def correlation(self, frame, nodes, pixels) -> float | None:
        """Correlation of the template with the frame over ``pixels`` (None: cannot tell)."""
        if pixels is None or not self.textured:
            return None
        pos = self.positions(nodes)[pixels].astype(np.float32)
        t = self.grey[pixels]
        if t.std() < 1e-3:
            return None
        grey = frame.astype(np.float32).mean(axis=2) if frame.ndim == 3 else frame
        s = cv2.remap(
            np.ascontiguousarray(grey, dtype=np.float32),
            pos[:, None, 0].copy(),
            pos[:, None, 1].copy(),
            cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_REPLICATE,
        )[:, 0].astype(np.float64)
        if s.std() < 1e-6:
            return None
        return float(np.corrcoef(t, s)[0, 1])


def _boxes_meet(p: np.ndarray, q: np.ndarray, reach: float = 0.0) -> bool:
    """Whether the boxes of two point sets meet, or come within ``reach`` pixels."""
    lo = np.maximum(p.min(axis=0), q.min(axis=0))
    hi = np.minimum(p.max(axis=0), q.max(axis=0))
    return bool((lo <= hi + reach).all())


def _inside_mesh(points: np.ndarray, nodes: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """(k,) bool: the points that lie in one of the mesh's triangles (rasterised)."""
    lo = np.floor(nodes.min(axis=0)).astype(int) - 1
    hi = np.ceil(nodes.max(axis=0)).astype(int) + 1
    w, h = (hi - lo + 1).tolist()
    out = np.zeros(len(points), bool)
    if w <= 0 or h <= 0 or w * h > 16_000_000:
        return out
    mask = np.zeros((h, w), np.uint8)
    polys = np.round((nodes[triangles] - lo) * (1 << _SHIFT)).astype(np.int32)
    cv2.fillPoly(mask, list(polys), 1, lineType=cv2.LINE_8, shift=_SHIFT)
    ij = np.round(points - lo).astype(int)
    ok = (ij[:, 0] >= 0) & (ij[:, 1] >= 0) & (ij[:, 0] < w) & (ij[:, 1] < h)
    out[ok] = mask[ij[ok, 1], ij[ok, 0]] > 0
    return out
