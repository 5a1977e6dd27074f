"""Contours: validation of user outlines, tolerance-band simplification, JSON files."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from voodoo_addon.blob.outline import (
    load_contour_json,
    resample_contour,
    save_contour_json,
    signed_area,
    simplify_contour,
    validate_contour,
)
from voodoo_addon.errors import VoodooError

SQUARE = [(10.0, 10.0), (60.0, 10.0), (60.0, 60.0), (10.0, 60.0)]

BAD_CONTOURS = {
    "empty": np.zeros((0, 2)),
    "two-points": [(0, 0), (30, 30)],
    "three-points-two-distinct": [(0, 0), (30, 30), (0, 0)],
    "all-same": [(5, 5)] * 6,
    "collinear": [(0, 0), (10, 10), (20, 20), (40, 40)],
    "collinear-back-and-forth": [(0, 0), (40, 0), (20, 0)],
    "tiny-area": [(0, 0), (5, 0), (5, 5), (0, 5)],  # 25 px^2 < 50
    "bow-tie": [(0, 0), (50, 50), (50, 0), (0, 50)],
    "figure-eight": [(0, 0), (40, 0), (40, 40), (80, 40), (80, 80), (40, 80), (40, 40), (0, 40)],
    "crossing-star": [
        (50 + 40 * np.cos(t), 50 + 40 * np.sin(t)) for t in np.arange(5) * 4 * np.pi / 5
    ],
    "touching-vertex": [(0, 0), (40, 0), (20, 20), (40, 40), (0, 40), (20, 20)],
    "spike": [(0, 0), (40, 0), (40, 40), (20, 40), (20, 70), (20, 50), (0, 40)],
    "nan": [(0, 0), (50, 0), (np.nan, 50), (0, 50)],
    "inf": [(0, 0), (50, 0), (50, np.inf), (0, 50)],
    "wrong-shape-3d": np.zeros((5, 3)),
    "wrong-shape-flat": np.arange(10.0),
    "ragged": [[0, 0], [50, 0, 1], [50, 50]],
    "not-numbers": [["a", "b"], ["c", "d"], ["e", "f"]],
}


@pytest.mark.parametrize("points", BAD_CONTOURS.values(), ids=BAD_CONTOURS.keys())
def test_bad_contours_raise(points):
    with pytest.raises(VoodooError):
        validate_contour(points)


@pytest.mark.parametrize(
    "point", [(-1.0, 20.0), (20.0, -0.6), (320.0, 20.0), (20.0, 239.6), (1e6, 1e6)]
)
def test_points_off_the_frame_raise(point):
    pts = [(20.0, 20.0), (100.0, 20.0), (100.0, 100.0), point]
    with pytest.raises(VoodooError, match="outside"):
        validate_contour(pts, frame_size=(320, 240))


def test_points_on_the_frame_border_are_accepted():
    # Pixel centres run 0..W-1; the picture's edge is half a pixel beyond them.
    pts = [(-0.5, -0.5), (319.5, -0.5), (319.5, 239.5), (-0.5, 239.5)]
    out = validate_contour(pts, frame_size=(320, 240))
    assert len(out) == 4


@pytest.mark.parametrize("reverse", [False, True])
def test_orientation_is_normalised(reverse):
    pts = np.array(SQUARE)[::-1] if reverse else np.array(SQUARE)
    out = validate_contour(pts)
    # Counter-clockwise on screen (y down) is a negative shoelace area in (x, y).
    assert signed_area(out) < 0
    assert abs(signed_area(out)) == pytest.approx(2500.0)
    assert {tuple(p) for p in out} == {tuple(p) for p in SQUARE}


def test_closing_point_and_consecutive_duplicates_dropped():
    pts = [SQUARE[0], SQUARE[1], SQUARE[1], SQUARE[2], SQUARE[3], SQUARE[3], SQUARE[0]]
    out = validate_contour(pts)
    assert out.shape == (4, 2)
    assert out.dtype == np.float64
    assert {tuple(p) for p in out} == {tuple(p) for p in SQUARE}


def test_min_area_is_a_parameter():
    small = [(0, 0), (5, 0), (5, 5), (0, 5)]
    assert len(validate_contour(small, min_area=20.0)) == 4
    with pytest.raises(VoodooError):
        validate_contour(small, min_area=30.0)


def test_concave_polygon_is_valid():
    l_shape = [(0, 0), (100, 0), (100, 40), (40, 40), (40, 100), (0, 100)]
    out = validate_contour(l_shape)
    assert abs(signed_area(out)) == pytest.approx(100 * 40 + 40 * 60)


def test_signed_area_of_known_triangle():
    tri = np.array([(0.0, 0.0), (4.0, 0.0), (0.0, 3.0)])
    assert signed_area(tri) == pytest.approx(6.0)
    assert signed_area(tri[::-1]) == pytest.approx(-6.0)


# ------------------------------------------------------------------------- simplification


def _noisy_circle(seed: int, n: int = 400, noise: float = 1.0):
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 60 + rng.normal(0, noise, n)
    return np.column_stack([100 + r * np.cos(t), 100 + r * np.sin(t)])


def _pixel_chain():
    mask = np.zeros((240, 320), np.uint8)
    cv2.ellipse(mask, (160, 120), (90, 50), 20, 0, 360, 1, -1)
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    return contours[0].reshape(-1, 2).astype(np.float64)


@pytest.mark.parametrize("tolerance", [0.5, 1.0, 2.0, 3.0])
@pytest.mark.parametrize("shape", ["pixel-chain", "noisy-circle-0", "noisy-circle-1"])
def test_simplify_keeps_every_point_within_the_band(shape, tolerance, poly_distance):
    pts = _pixel_chain() if shape == "pixel-chain" else _noisy_circle(int(shape[-1]))
    out = simplify_contour(pts, tolerance)
    assert 3 <= len(out) < len(pts)
    dist = poly_distance(pts, out)
    assert dist.max() <= tolerance + 1e-9, (
        f"original point {np.argmax(dist)} is {dist.max():.3f} px from the simplified "
        f"polygon (tolerance {tolerance})"
    )


@pytest.mark.parametrize("tolerance", [0.5, 1.5])
def test_simplify_keeps_a_subset_of_the_points(tolerance):
    pts = _pixel_chain()
    out = simplify_contour(pts, tolerance)
    original = {tuple(p) for p in pts}
    assert all(tuple(p) in original for p in out)


def test_simplify_larger_tolerance_gives_fewer_points():
    pts = _pixel_chain()
    counts = [len(simplify_contour(pts, tol)) for tol in (0.5, 1.0, 2.0, 4.0)]
    assert counts == sorted(counts, reverse=True)
    assert counts[0] > counts[-1]


def test_simplify_of_a_polygon_is_still_valid():
    out = simplify_contour(_pixel_chain(), 1.5)
    validate_contour(out, frame_size=(320, 240))


def test_simplify_leaves_a_polygon_without_redundant_points_alone():
    square = np.array(SQUARE)
    np.testing.assert_array_equal(simplify_contour(square, 1.0), square)


def test_simplify_drops_collinear_midpoints():
    square = np.array(SQUARE)
    dense = resample_contour(square, 5.0)
    out = simplify_contour(dense, 0.5)
    assert {tuple(p) for p in out} == {tuple(p) for p in square}


@pytest.mark.parametrize("spacing", [3.0, 7.5, 20.0])
def test_resample_limits_edge_length_and_keeps_corners(spacing):
    square = np.array(SQUARE)
    out = resample_contour(square, spacing)
    edges = np.linalg.norm(np.roll(out, -1, axis=0) - out, axis=1)
    assert edges.max() <= spacing + 1e-9
    assert {tuple(p) for p in square} <= {tuple(p) for p in out}
    assert signed_area(out) == pytest.approx(signed_area(square))


# ------------------------------------------------------------------------- JSON


def test_json_round_trip(tmp_path):
    pts = _noisy_circle(3, n=30)
    path = tmp_path / "c.json"
    save_contour_json(path, pts)
    back = load_contour_json(path)
    assert back.shape == pts.shape
    np.testing.assert_allclose(back, pts, atol=5e-4)


@pytest.mark.parametrize(
    "text",
    [
        "{not json",
        "[[0, 0], [1, 1], [2, 0]]",
        '{"pts": [[0, 0], [10, 0], [10, 10]]}',
        '{"points": "abc"}',
        '{"points": [[0, 0], [10, "x"], [10, 10]]}',
        '{"points": [[0, 0], [10, 0, 5], [10, 10]]}',
        "",
    ],
)
def test_bad_json_raises(tmp_path, text):
    path = tmp_path / "c.json"
    path.write_text(text)
    with pytest.raises(VoodooError):
        validate_contour(load_contour_json(path))


def test_missing_json_raises(tmp_path):
    with pytest.raises(VoodooError, match="does not exist"):
        load_contour_json(tmp_path / "nope.json")


def test_binary_json_raises(tmp_path):
    path = tmp_path / "c.json"
    path.write_bytes(b"\xff\xfe\x00garbage\x80")
    with pytest.raises(VoodooError):
        load_contour_json(path)
