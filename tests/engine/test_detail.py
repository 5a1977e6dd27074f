"""Detail strengthened on faint dolls: the pictures compared, how much, and a confidence that
means the same with it."""

import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.calibration import judge
from voodoo_addon.devtools.synthetic import Pose, foam_scene
from voodoo_addon.errors import VoodooError
from voodoo_addon.tracking import Tracker, TrackerOptions
from voodoo_addon.tracking.pictures import FAINT, FAINT_DETAIL, detail_for, emphasise

SIZE = (320, 240)


def _ramp_and_checker(amplitude=0.05):
    """A picture lit by a smooth ramp on the left, a fine checker on it on the right."""
    h, w = 64, 128
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    ramp = 0.3 + 0.4 * x / w
    checker = amplitude * np.where((x.astype(int) // 2 + y.astype(int) // 2) % 2, 1.0, -1.0)
    checker[:, : w // 2] = 0.0
    return np.repeat((ramp + checker)[..., None], 3, axis=2).astype(np.float32), ramp


def test_emphasise_strengthens_fine_detail_and_leaves_smooth_shading():
    picture, ramp = _ramp_and_checker()
    out = emphasise(picture, 4.0)
    assert out.dtype == np.float32 and out.shape == picture.shape
    # A linear ramp is its own blur: away from the border it is left as it was.
    np.testing.assert_allclose(out[20:44, 20:44, 0], ramp[20:44, 20:44], atol=1e-4)
    # The checker (2-pixel squares, far finer than the 3-pixel scale) is about 5x as strong.
    fine = picture[20:44, 84:108, 0] - ramp[20:44, 84:108]
    got = out[20:44, 84:108, 0] - ramp[20:44, 84:108]
    gain = float((got * fine).sum() / (fine * fine).sum())
    assert 4.0 < gain <= 5.0


def test_no_detail_leaves_the_picture_itself():
    picture, _ = _ramp_and_checker()
    assert emphasise(picture, 0.0) is picture


def test_only_a_faint_texture_has_its_detail_strengthened():
    rng = np.random.default_rng(0)
    noise = rng.standard_normal((5000, 3)).astype(np.float32)
    low, high = FAINT
    assert detail_for(0.5 + 0.5 * low * noise) == pytest.approx(FAINT_DETAIL, rel=0.05)
    assert detail_for(0.5 + 1.5 * high * noise) == 0.0
    between = [detail_for(0.5 + c * noise) for c in np.linspace(low, high, 5)]
    assert all(a >= b for a, b in zip(between[:-1], between[1:], strict=True))
    assert 0.0 < between[2] < FAINT_DETAIL


def test_the_detail_setting_is_checked():
    with pytest.raises(VoodooError, match="detail"):
        TrackerOptions(detail=float("nan"))
    with pytest.raises(VoodooError, match="detail"):
        TrackerOptions(detail=-1.0)
    assert TrackerOptions().detail is None  # as much as the texture needs


def test_a_printed_doll_is_compared_as_it_is():
    """The painted foam of the synthetic takes has plenty of contrast: nothing changes."""
    scene, contour = foam_scene(*SIZE, 6000)
    blob = build_blob(scene.render(Pose(), noise=0.01, rng=np.random.default_rng(0)), contour)
    assert Tracker(blob).fitter.detail == 0.0


@pytest.fixture(scope="module")
def faint():
    """A foam doll painted at a quarter of its contrast, and frames of it."""
    scene, contour = foam_scene(*SIZE, 6000)
    scene.texture = (0.5 + 0.25 * (scene.texture - scene.texture.mean())).astype(np.float32)
    blob = build_blob(scene.render(Pose(), noise=0.01, rng=np.random.default_rng(0)), contour)
    return scene, blob


def test_a_faint_doll_has_its_detail_strengthened(faint):
    _, blob = faint
    assert Tracker(blob).fitter.detail > 0.0
    assert Tracker(blob, options=TrackerOptions(detail=0.0)).fitter.detail == 0.0


@pytest.mark.parametrize("shift", [0.0, 2.0, 4.0, 8.0])
def test_the_confidence_means_the_same_with_the_detail_strengthened(faint, shift):
    """The fits compare the pictures with their detail strengthened; the confidence is
    measured on the colours as they are, so that its thresholds (lost, found again, the
    local stage) mean what they meant: on the same frame at the same pose it agrees with
    the tracker's that compares the colours as they are."""
    scene, blob = faint
    frame = scene.render(Pose(tx=shift), noise=0.01, rng=np.random.default_rng(1))
    at_rest = Tracker(blob).layout.identity()
    strong = judge(Tracker(blob), frame, at_rest)
    plain = judge(Tracker(blob, options=TrackerOptions(detail=0.0)), frame, at_rest)
    assert strong == pytest.approx(plain, abs=0.03)
    if shift == 0.0:
        assert strong > 0.9
    if shift >= 4.0:
        assert strong < 0.6


def test_the_part_left_out_is_measured_apart(faint):
    """``Quality.left_out_correlation``: how well the triangles a fit left out as covered
    still correlate with the template, on the colours as they are -- a part merely
    misaligned somewhat, a part under something else not at all (the *shown* fit is made
    only for the first, ``hidden.left_out``)."""
    scene, blob = faint
    frame = scene.render(Pose(), noise=0.01, rng=np.random.default_rng(1))
    tracker = Tracker(blob)
    a = tracker.layout.identity()
    centroids = blob.vertices[blob.triangles].mean(axis=1)
    left = centroids[:, 0] < np.median(centroids[:, 0])
    seen = tracker.fitter.hold(frame, a, covered=left).quality
    assert seen.share == pytest.approx(0.5, abs=0.1)
    assert seen.left_out_correlation > 0.8
    # the left half under a card of another texture
    card = np.random.default_rng(2).random(frame.shape[:2])[..., None].astype(np.float32)
    x = int(np.median(centroids[:, 0]))
    covered = frame.copy()
    covered[:, :x] = 0.45 + 0.1 * card[:, :x]
    under = tracker.fitter.hold(covered, a, covered=left).quality
    assert abs(under.left_out_correlation) < 0.15
    assert np.isnan(tracker.fitter.hold(frame, a).quality.left_out_correlation)
