"""Automatic outlines: GrabCut around a point or in a box, then contour following."""

from __future__ import annotations

import numpy as np
import pytest

from voodoo_addon.blob.outline import signed_area, validate_contour
from voodoo_addon.blob.segment import mask_contour, segment_contour, segment_mask
from voodoo_addon.devtools.synthetic import Pose, foam_scene
from voodoo_addon.errors import VoodooError


@pytest.fixture(scope="module", params=[(320, 240, 8000, 0), (400, 300, 14000, 3)])
def scene_frame(request):
    w, h, px, seed = request.param
    scene, _ = foam_scene(w, h, px, seed=seed)
    return scene.render(Pose()), scene.mask > 0.5


def _iou(a, b):
    return np.count_nonzero(a & b) / np.count_nonzero(a | b)


def _bbox(mask, pad):
    ys, xs = np.nonzero(mask)
    return (xs.min() - pad, ys.min() - pad, xs.max() + pad, ys.max() + pad)


def test_segment_from_a_point(scene_frame):
    frame, truth = scene_frame
    h, w = truth.shape
    mask = segment_mask(frame, point=((w - 1) / 2, (h - 1) / 2))
    assert mask.shape == truth.shape and mask.dtype == bool
    assert _iou(mask, truth) > 0.9


def test_segment_from_an_off_centre_point(scene_frame):
    frame, truth = scene_frame
    ys, xs = np.nonzero(truth)
    # A point on the object, a third of the way from its centre to its left edge.
    cx, cy = xs.mean(), ys.mean()
    x = cx - (cx - xs.min()) / 3
    assert truth[int(cy), int(x)]
    assert _iou(segment_mask(frame, point=(x, cy)), truth) > 0.9


@pytest.mark.parametrize("pad", [6, 20])
def test_segment_from_a_box(scene_frame, pad):
    frame, truth = scene_frame
    mask = segment_mask(frame, box=_bbox(truth, pad))
    assert _iou(mask, truth) > 0.9


def test_box_corners_in_any_order(scene_frame):
    frame, truth = scene_frame
    x0, y0, x1, y1 = _bbox(truth, 10)
    assert _iou(segment_mask(frame, box=(x1, y1, x0, y0)), truth) > 0.9


def test_point_on_the_background_raises(scene_frame):
    frame, _ = scene_frame
    with pytest.raises(VoodooError, match="background"):
        segment_mask(frame, point=(12, 12))


@pytest.mark.parametrize(
    "kwargs",
    [
        {},
        {"point": (100, 100), "box": (10, 10, 200, 200)},
        {"point": (-5, 10)},
        {"point": (10, 10_000)},
        {"box": (100, 100, 103, 103)},
    ],
    ids=["neither", "both", "point-left", "point-below", "tiny-box"],
)
def test_bad_requests_raise(scene_frame, kwargs):
    frame, _ = scene_frame
    with pytest.raises(VoodooError):
        segment_mask(frame, **kwargs)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"box": (10, np.nan, 200, 200)},
        {"box": (10, 10, np.inf, 200)},
        {"point": (np.nan, 100)},
        {"point": (100, -np.inf)},
        {"box": (10, 10, 200)},
        {"point": ("a", "b")},
    ],
    ids=["box-nan", "box-inf", "point-nan", "point-inf", "box-three-numbers", "point-text"],
)
def test_unusable_numbers_in_the_request_give_a_clear_error(scene_frame, kwargs):
    frame, _ = scene_frame
    with pytest.raises(VoodooError, match=r"(?i)(point|box).*(NaN|infinite|numbers)"):
        segment_contour(frame, **kwargs)


def test_segment_contour_is_a_valid_outline(scene_frame):
    frame, truth = scene_frame
    h, w = truth.shape
    contour = segment_contour(frame, point=((w - 1) / 2, (h - 1) / 2))
    assert contour.ndim == 2 and contour.shape[1] == 2 and len(contour) >= 8
    np.testing.assert_array_equal(validate_contour(contour, frame_size=(w, h)), contour)
    assert signed_area(contour) < 0  # counter-clockwise on screen
    assert abs(signed_area(contour)) == pytest.approx(np.count_nonzero(truth), rel=0.1)


def test_mask_contour_of_a_known_rectangle():
    mask = np.zeros((100, 120), bool)
    mask[20:60, 30:100] = True
    c = mask_contour(mask)
    # Pixel centres of the border pixels: a 69 x 39 rectangle of corners.
    assert {tuple(p) for p in c} == {(30, 20), (99, 20), (99, 59), (30, 59)}


def test_mask_contour_keeps_the_largest_region():
    mask = np.zeros((100, 120), bool)
    mask[10:20, 10:20] = True
    mask[40:90, 40:110] = True
    c = mask_contour(mask)
    assert c[:, 0].min() >= 40 and c[:, 1].min() >= 40


def test_mask_contour_of_an_empty_mask_raises():
    with pytest.raises(VoodooError):
        mask_contour(np.zeros((50, 50), bool))
