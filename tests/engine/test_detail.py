"""Detail strengthened on faint dolls: the pictures compared, how much, and a confidence that
means the same with it."""

import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.calibration import judge
from voodoo_addon.devtools.clips import read_clip
from voodoo_addon.devtools.folds import fold_suite
from voodoo_addon.devtools.synthetic import Pose, foam_scene
from voodoo_addon.errors import VoodooError
from voodoo_addon.media.images import blur, to_float_rgb
from voodoo_addon.tracking import Tracker, TrackerOptions
from voodoo_addon.tracking.pictures import (
    FAINT,
    FAINT_DETAIL,
    FINE_FAINT,
    detail_for,
    doll_fine_contrast,
    emphasise,
    fine_contrast,
)

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


def _inside(h=96, w=128):
    inside = np.zeros((h, w), bool)
    inside[16:-16, 20:-20] = True
    return inside


def test_the_fine_contrast_is_the_dolls_own_detail():
    """A flat doll on a dark backdrop has none: the outline's edge adds nothing. A fine
    checker on it has about its amplitude."""
    inside = _inside()
    flat = np.where(inside, 0.6, 0.1).astype(np.float32)[..., None].repeat(3, axis=2)
    assert fine_contrast(flat, inside) < 1e-4
    y, x = np.mgrid[0 : inside.shape[0], 0 : inside.shape[1]]
    checker = np.where((x // 2 + y // 2) % 2, 0.05, -0.05).astype(np.float32)
    assert fine_contrast(flat + checker[..., None], inside) == pytest.approx(0.05, rel=0.2)
    assert fine_contrast(flat, np.zeros_like(inside)) == 0.0


def test_fur_dyed_in_patches_is_strengthened_by_its_faint_fine_detail():
    """Large soft patches of colour over a faint pile vary as much as a print does (a
    standard deviation of 0.2, above the faint bound): by their fine detail they are fur,
    strengthened fully. A print of sharp-edged squares with the same contrast is not."""
    rng = np.random.default_rng(0)
    inside = _inside()
    h, w = inside.shape
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    phase = np.array([0.0, 2.0, 4.0], np.float32)
    patches = np.sin(x[..., None] / 14.0 + phase) * np.cos(y[..., None] / 12.0 + phase)
    patches *= 0.2 / patches[inside].std()
    pile = 0.006 * rng.standard_normal((h, w, 3)).astype(np.float32)
    fur = 0.5 + patches + pile
    assert np.std(fur[inside]) > FAINT[1]
    assert detail_for(fur[inside]) == 0.0
    assert fine_contrast(fur, inside) < FINE_FAINT[0]
    assert detail_for(fur[inside], fine_contrast(fur, inside)) == FAINT_DETAIL
    squares = np.where((x.astype(int) // 8 + y.astype(int) // 8) % 2, 0.2, -0.2).astype(np.float32)
    printed = blur((0.5 + squares)[..., None].repeat(3, axis=2), 1.2)  # as a blob's texture
    assert np.std(printed[inside]) > FAINT[1]
    assert fine_contrast(printed, inside) > FINE_FAINT[1]
    assert detail_for(printed[inside], fine_contrast(printed, inside)) == 0.0
    # faint overall, whatever its fine detail: the contrast overall decides
    assert detail_for(0.5 + 0.2 * (printed[inside] - 0.5), 1.0) == FAINT_DETAIL


#: Renders whose dolls are fur or plush, and printed ones with the least fine contrast
#: (BENCHMARKS.md, *Fur dyed in patches*): plush_nod's and shag_tail_turn's colours
#: vary as much as a print's (0.133, 0.148).
FURRY = ("plush_nod", "shag_tail_turn", "plush_flip", "tail_turn")
PRINTED = ("kraft_bag_squeeze", "denim_corner_tuck", "fold_squeeze")


@pytest.mark.slow
def test_every_furry_render_is_strengthened_and_no_printed_one():
    clips = {c.name: c for c in fold_suite() if c.name in FURRY + PRINTED}
    assert set(clips) == set(FURRY + PRINTED)
    for name, clip in clips.items():
        frames, outline, _ = read_clip(clip)
        blob = build_blob(to_float_rgb(frames[0]), outline)
        fitter = Tracker(blob).fitter
        fine = doll_fine_contrast(blob, fitter.base)
        if name in FURRY:
            assert fine < FINE_FAINT[0] and fitter.detail == FAINT_DETAIL, (name, fine)
        else:
            assert fine > FINE_FAINT[1] and fitter.detail == 0.0, (name, fine)


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
