"""Closed contours: validation and tolerance-band simplification (paper §7).

A contour is a closed polygon in pixel coordinates (OpenCV convention: origin at the centre
of the top-left pixel, x right, y down), stored without repeating the first point, and
oriented counter-clockwise *as seen on screen* (y down), i.e. with a negative signed area in
the (x, y) algebra below. Everything that builds meshes from user input goes through
:func:`validate_contour` first, so a bad sketch never reaches the triangulator.
"""

from __future__ import annotations

import heapq
import json
from pathlib import Path

import cv2
import numpy as np

from ..errors import VoodooError
from .crossing import first_crossing

#: Polygons smaller than this many square pixels cannot carry a texture worth tracking.
MIN_AREA_PX = 50.0


def signed_area(points: np.ndarray) -> float:
    """Shoelace area of a closed polygon.

    Parameters
    ----------
    points : (n, 2) float64
        Vertices, first point not repeated.

    Returns
    -------
    float
        Positive when the vertices run counter-clockwise in a y-up frame.
    """
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def validate_contour(
    points, frame_size: tuple[int, int] | None = None, min_area: float = MIN_AREA_PX
) -> np.ndarray:
    """Check a user polygon and return it cleaned and oriented.

    Parameters
    ----------
    points : array_like (n, 2)
        Polygon vertices in pixel coordinates; the closing point may be repeated.
    frame_size : (width, height), optional
        When given, every point must lie on the frame (within half a pixel of its border).
    min_area : float
        Smallest acceptable area in square pixels.

    Returns
    -------
    (k, 2) float64
        Distinct consecutive vertices, counter-clockwise on screen.

    Raises
    ------
    VoodooError
        With a message that says how to fix the outline.
    """
    try:
        pts = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise VoodooError(f"The contour is not a list of [x, y] points ({exc}).") from None
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise VoodooError(
            f"The contour must be a list of [x, y] points; got an array of shape {pts.shape}."
        )
    if not np.isfinite(pts).all():
        raise VoodooError("The contour has NaN or infinite coordinates; redraw the outline.")
    # Drop consecutive duplicates (including a repeated closing point).
    keep = np.ones(len(pts), dtype=bool)
    if len(pts) > 1:
        keep[1:] = np.any(np.abs(np.diff(pts, axis=0)) > 1e-9, axis=1)
    pts = pts[keep]
    if len(pts) > 1 and np.allclose(pts[0], pts[-1], atol=1e-9):
        pts = pts[:-1]
    n_distinct = len(np.unique(np.round(pts, 9), axis=0))
    if n_distinct < 3:
        raise VoodooError(
            f"The contour has {n_distinct} distinct point(s); outline the region with at "
            "least 3 points around it."
        )
    if frame_size is not None:
        w, h = frame_size
        outside = (
            (pts[:, 0] < -0.5) | (pts[:, 1] < -0.5) | (pts[:, 0] > w - 0.5) | (pts[:, 1] > h - 0.5)
        )
        if outside.any():
            x, y = pts[np.argmax(outside)]
            raise VoodooError(
                f"Contour point ({x:.1f}, {y:.1f}) lies outside the {w}x{h} frame; keep the "
                "outline inside the picture."
            )
    hit = first_crossing(pts)
    if hit is not None:
        (i, j), (x, y) = hit.edges, hit.point
        raise VoodooError(
            f"The contour {'touches' if hit.touching else 'crosses'} itself near "
            f"({x:.1f}, {y:.1f}) (edges {i} and {j} of {len(pts)}); redraw it as a simple "
            "loop that neither crosses nor touches itself."
        )
    area = signed_area(pts)
    if abs(area) < min_area:
        raise VoodooError(
            f"The contour encloses only {abs(area):.1f} square pixels (at least {min_area:g} "
            "are needed); outline a larger region of the object."
        )
    # y points down on screen, so a positive shoelace area is clockwise on screen.
    if area > 0:
        pts = pts[::-1].copy()
    return pts


def _point_segment_distance(pts: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of each point (k, 2) from the segment a-b."""
    ab = b - a
    denom = float(ab @ ab)
    if denom == 0.0:
        return np.linalg.norm(pts - a, axis=1)
    t = np.clip((pts - a) @ ab / denom, 0.0, 1.0)
    return np.linalg.norm(pts - (a + t[:, None] * ab), axis=1)


def _subdivide(points: np.ndarray, tol: float) -> list[int]:
    """Recursive subdivision (Douglas-Peucker) of an open polyline; kept indices."""
    keep = [0, len(points) - 1]
    stack = [(0, len(points) - 1)]
    while stack:
        i, j = stack.pop()
        if j <= i + 1:
            continue
        d = _point_segment_distance(points[i + 1 : j], points[i], points[j])
        k = int(np.argmax(d))
        if d[k] > tol:
            m = i + 1 + k
            keep.append(m)
            stack.extend([(i, m), (m, j)])
    return sorted(keep)


def _span_deviation(points: np.ndarray, i: int, j: int) -> float:
    """Largest distance from the chord i-j of the points strictly between i and j.

    Indices run cyclically over the original polygon.
    """
    n = len(points)
    idx = np.arange(i + 1, j if j > i else j + n) % n
    if len(idx) == 0:
        return 0.0
    return float(_point_segment_distance(points[idx], points[i], points[j]).max())


def _merge(points: np.ndarray, keep: list[int], tol: float) -> list[int]:
    """Tolerance-band merging on a cyclic list of kept original indices.

    A vertex is dropped when every original point its two chords stood for lies within
    ``tol`` of the chord joining its neighbours; the vertex with the smallest such deviation
    goes first (a heap), and only its neighbours' deviations change: O(k log k) for k
    vertices, however many are dropped.
    """
    k = len(keep)
    prev = [(i - 1) % k for i in range(k)]
    succ = [(i + 1) % k for i in range(k)]
    alive, version = [True] * k, [0] * k

    def deviation(i: int) -> float:
        return _span_deviation(points, keep[prev[i]], keep[succ[i]])

    heap = [(deviation(i), i, 0) for i in range(k)]
    heapq.heapify(heap)
    left = k
    while left > 3 and heap:
        dev, i, v = heapq.heappop(heap)
        if not alive[i] or v != version[i]:
            continue  # dropped, or its deviation changed since
        if dev > tol:
            break
        alive[i], left = False, left - 1
        a, b = prev[i], succ[i]
        succ[a], prev[b] = b, a
        for j in (a, b):
            version[j] += 1
            heapq.heappush(heap, (deviation(j), j, version[j]))
    return [keep[i] for i in range(k) if alive[i]]


def simplify_contour(points: np.ndarray, tolerance: float = 1.0) -> np.ndarray:
    """Tolerance-band simplification of a closed polygon (paper §7, after Jain et al.).

    Recursive subdivision (Douglas-Peucker, the loop split at vertex 0 and the vertex farthest
    from it) keeps the vertices needed for a band of half-width ``tolerance``; a merging pass
    then drops any vertex whose neighbours' chord still keeps every original point within the
    band. Every original point ends within ``tolerance`` of the result.

    Parameters
    ----------
    points : (n, 2) float64
        Closed polygon, first point not repeated.
    tolerance : float
        Band half-width in pixels.

    Returns
    -------
    (k, 2) float64
        The simplified polygon, k >= 3.
    """
    pts = np.asarray(points, dtype=np.float64)
    n = len(pts)
    if n <= 3 or tolerance <= 0:
        return pts.copy()
    far = int(np.argmax(np.linalg.norm(pts - pts[0], axis=1)))
    if far == 0:
        return pts[:3].copy()
    first = _subdivide(pts[: far + 1], tolerance)
    loop = np.vstack([pts[far:], pts[:1]])
    second = [(far + i) % n for i in _subdivide(loop, tolerance)]
    keep = sorted(set(first) | set(second))
    return pts[_merge(pts, keep, tolerance)]


def resample_contour(points: np.ndarray, spacing: float) -> np.ndarray:
    """Insert vertices so that no edge of the closed polygon is longer than ``spacing``.

    Parameters
    ----------
    points : (n, 2) float64
    spacing : float
        Longest allowed edge, pixels.

    Returns
    -------
    (k, 2) float64
    """
    out = []
    n = len(points)
    for i in range(n):
        a, b = points[i], points[(i + 1) % n]
        pieces = max(1, int(np.ceil(np.linalg.norm(b - a) / spacing)))
        t = np.arange(pieces)[:, None] / pieces
        out.append(a + t * (b - a))
    return np.vstack(out)


def load_contour_json(path) -> np.ndarray:
    """Read ``{"points": [[x, y], ...]}`` (the command-line contract).

    Raises
    ------
    VoodooError
        If the file is missing or is not that shape.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise VoodooError(f"Contour file {path} does not exist.") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise VoodooError(f"Contour file {path} is not readable JSON ({exc}).") from None
    if not isinstance(data, dict) or "points" not in data:
        raise VoodooError(f'Contour file {path} must hold {{"points": [[x, y], ...]}}.')
    return _as_points(data["points"], path)


def contour_name(path) -> str:
    """A doll's name for an outline file: its ``"name"``, else the file's name.

    The file's name loses ``.json`` and ``.contour`` (``left.contour.json`` is ``left``).
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        data = None
    if isinstance(data, dict) and isinstance(data.get("name"), str) and data["name"].strip():
        return data["name"].strip()
    name = path.name.removesuffix(".json").removesuffix(".contour")
    return name or "doll"


def check_apart(outlines: dict) -> None:
    """Outlines of several dolls on one frame must not overlap (each pixel is one doll's).

    Parameters
    ----------
    outlines : mapping of str to (k, 2) array
        Each doll's outline (closed polygon), pixel coordinates.

    Raises
    ------
    VoodooError
        Naming the first two dolls whose outlines overlap or cross.
    """
    names = list(outlines)
    polys = [np.asarray(outlines[n], np.float64) for n in names]
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            a, b = polys[i], polys[j]
            lo = np.floor(np.minimum(a.min(axis=0), b.min(axis=0))).astype(int) - 1
            hi = np.ceil(np.maximum(a.max(axis=0), b.max(axis=0))).astype(int) + 1
            w, h = (hi - lo + 1).tolist()
            if w * h > 64_000_000:
                continue
            masks = []
            for poly in (a, b):
                m = np.zeros((h, w), np.uint8)
                cv2.fillPoly(m, [np.round((poly - lo) * 4).astype(np.int32)], 1, shift=2)
                masks.append(m)
            if np.count_nonzero(masks[0] & masks[1]):
                raise VoodooError(
                    f"The outlines of {names[i]!r} and {names[j]!r} overlap: each doll needs "
                    "a region of its own. Outline them apart (they may touch and cross later, "
                    "while tracking)."
                )


def _as_points(raw, path) -> np.ndarray:
    try:
        return np.asarray(raw, dtype=np.float64)
    except (TypeError, ValueError):
        raise VoodooError(
            f'Contour file {path}: "points" must be a list of [x, y] numbers.'
        ) from None


def save_contour_json(path, points: np.ndarray) -> None:
    """Write a contour in the command-line format."""
    Path(path).write_text(json.dumps({"points": np.asarray(points).round(3).tolist()}))
