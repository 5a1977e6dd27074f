"""Dense outlines (thousands of points, from a mask or a traced contour).

The self-crossing check must say yes to every simple polygon and no to every crossing or
touching one, in time and memory that grow like n log n; a blob must build from such an
outline.
"""

from __future__ import annotations

import re
import time
import tracemalloc
from itertools import combinations

import cv2
import numpy as np
import pytest

from voodoo_addon.blob.build import MAX_OUTLINE_CORNERS, build_blob
from voodoo_addon.blob.crossing import first_crossing
from voodoo_addon.blob.outline import validate_contour
from voodoo_addon.errors import VoodooError


def wobbly_circle(n: int, centre=(320.0, 240.0), radius=150.0) -> np.ndarray:
    """A closed, simple, wobbly outline of n points (edges ~0.1 px at n = 10000)."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = radius * (1 + 0.03 * np.sin(37 * t)) + 1.5 * np.sin(211 * t)
    return np.column_stack([centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)])


def _where(message: str) -> np.ndarray:
    m = re.search(r"near \((-?[\d.]+), (-?[\d.]+)\)", message)
    assert m, message
    return np.array([float(m.group(1)), float(m.group(2))])


def _measured(fn, *args):
    tracemalloc.start()
    t0 = time.perf_counter()
    try:
        out = fn(*args)
    finally:
        seconds = time.perf_counter() - t0
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
    return out, seconds, peak / 2**20


def test_ten_thousand_point_outline_is_valid_quickly_and_in_little_memory():
    pts = wobbly_circle(10_000)
    out, seconds, peak_mb = _measured(validate_contour, pts)
    assert len(out) == 10_000
    assert seconds < 5.0
    assert peak_mb < 50.0


def test_pixel_outline_of_a_mask_is_valid():
    mask = np.zeros((480, 640), np.uint8)
    cv2.ellipse(mask, (320, 240), (300, 200), 15, 0, 360, 1, -1)
    cv2.circle(mask, (320, 240), 60, 0, -1)  # no hole: the outer border only below
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    pts = contours[0].reshape(-1, 2).astype(np.float64)
    assert len(pts) > 1000  # the ellipse runs off the frame: its border follows the edge
    assert len(validate_contour(pts, frame_size=(640, 480))) == len(pts)


@pytest.mark.parametrize("k", [0, 2_346, 9_998])
def test_one_local_loop_in_a_dense_outline_is_found_and_located(k):
    pts = wobbly_circle(10_000)
    pts[[k, k + 1]] = pts[[k + 1, k]]  # a tiny loop between points k-1 and k+2
    # (where the curve turns one way from k-1 to k+2, which is true here by the definition)
    assert _meet(*(tuple(pts[i]) for i in (k - 1, k, k + 1, (k + 2) % len(pts))))
    with pytest.raises(VoodooError, match="crosses itself") as err:
        validate_contour(pts)
    assert np.linalg.norm(_where(str(err.value)) - pts[k]) < 1.0


def test_swapped_neighbours_at_an_inflection_make_no_loop_and_are_accepted():
    # At an inflection (the curve's turn changes sign between k-1 and k+2) the swap makes
    # a thin zig-zag, not a loop: the outline is still simple and the check says so.
    k = 2_345
    pts = wobbly_circle(10_000)
    pts[[k, k + 1]] = pts[[k + 1, k]]
    assert not _meet(*(tuple(pts[i]) for i in (k - 1, k, k + 1, k + 2)))
    assert len(validate_contour(pts)) == 10_000


def test_figure_eight_crossing_is_found_and_located():
    t = np.linspace(0, 2 * np.pi, 10_000, endpoint=False) + 1e-3
    pts = np.column_stack([320 + 200 * np.sin(t), 240 + 100 * np.sin(t) * np.cos(t)])
    with pytest.raises(VoodooError, match="crosses itself") as err:
        validate_contour(pts)
    assert np.linalg.norm(_where(str(err.value)) - (320, 240)) < 1.0


def test_dense_outline_touching_itself_is_refused():
    pts = wobbly_circle(4_000)
    # A dent that reaches exactly onto the far side's vertex.
    pts[1_000] = pts[3_000]
    with pytest.raises(VoodooError, match="touches itself|crosses itself") as err:
        validate_contour(pts)
    assert np.linalg.norm(_where(str(err.value)) - pts[3_000]) < 1e-6


# --------------------------------------------------------- against brute force, exactly


def _orient(a, b, c) -> int:
    d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return int(d > 0) - int(d < 0)


def _on(a, b, c) -> bool:
    return min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= c[1] <= max(a[1], b[1])


def _meet(a, b, c, d) -> bool:
    o1, o2, o3, o4 = _orient(a, b, c), _orient(a, b, d), _orient(c, d, a), _orient(c, d, b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return (
        (o1 == 0 and _on(a, b, c))
        or (o2 == 0 and _on(a, b, d))
        or (o3 == 0 and _on(c, d, a))
        or (o4 == 0 and _on(c, d, b))
    )


def _brute_force_is_simple(pts: list[tuple[int, int]]) -> bool:
    """Integer arithmetic, every pair of edges: the definition, slowly."""
    n = len(pts)
    edges = [(pts[i], pts[(i + 1) % n]) for i in range(n)]
    for i, j in combinations(range(n), 2):
        (a, b), (c, d) = edges[i], edges[j]
        if j == i + 1 or (i == 0 and j == n - 1):  # adjacent: meet only at the shared vertex
            shared, far_i, far_j = (b, a, d) if j == i + 1 else (a, b, c)
            if _orient(shared, far_i, far_j) == 0 and (
                _on(shared, far_i, far_j) or _on(shared, far_j, far_i)
            ):
                return False
        elif _meet(a, b, c, d):
            return False
    return True


@pytest.mark.parametrize("seed", range(6))
def test_crossing_check_agrees_with_brute_force_on_degenerate_polygons(seed):
    # Small integer grids: collinear edges, repeated vertices, vertical and horizontal
    # edges and T-junctions are the rule here, not the exception.
    rng = np.random.default_rng(seed)
    checked = 0
    for _ in range(400):
        n = int(rng.integers(3, 10))
        raw = rng.integers(0, 5, size=(n, 2))
        keep = np.r_[True, np.any(raw[1:] != raw[:-1], axis=1)]
        pts = raw[keep]
        if len(pts) > 1 and (pts[0] == pts[-1]).all():
            pts = pts[:-1]
        if len(pts) < 3:
            continue
        expected = _brute_force_is_simple([tuple(map(int, p)) for p in pts])
        found = first_crossing(pts.astype(np.float64))
        assert (found is None) == expected, pts.tolist()
        if found is not None:
            # The reported edges really meet (or fold onto each other).
            i, j = found.edges
            assert i != j
        checked += 1
    assert checked > 300


def test_crossing_check_agrees_with_brute_force_on_random_float_polygons():
    rng = np.random.default_rng(7)
    for _ in range(300):
        n = int(rng.integers(3, 12))
        pts = rng.uniform(0, 10, size=(n, 2))
        expected = _brute_force_is_simple([tuple(map(float, p)) for p in pts])
        assert (first_crossing(pts) is None) == expected


# ------------------------------------------------------------------ building from them


def test_blob_builds_from_a_dense_outline():
    rng = np.random.default_rng(0)
    frame = rng.uniform(0, 1, (480, 640, 3)).astype(np.float32)
    pts = wobbly_circle(10_000)
    blob, seconds, _ = _measured(build_blob, frame, pts)
    assert len(blob.contour) <= MAX_OUTLINE_CORNERS
    assert blob.n_modes == 20
    assert np.isfinite(blob.modes).all()
    assert seconds < 30.0


def test_outline_that_stays_dense_after_simplification_is_coarsened_with_a_warning():
    rng = np.random.default_rng(1)
    frame = rng.uniform(0, 1, (480, 640, 3)).astype(np.float32)
    t = np.linspace(0, 2 * np.pi, 20_000, endpoint=False)
    r = 180 + 3.0 * np.sin(2_000 * t)  # a fine zig-zag 6 px deep: no tolerance band holds it
    pts = np.column_stack([320 + r * np.cos(t), 240 + r * np.sin(t)])
    blob = build_blob(frame, pts)
    assert len(blob.contour) <= MAX_OUTLINE_CORNERS
    assert any("simplified" in w for w in blob.warnings), blob.warnings
    assert blob.n_nodes < 1000
