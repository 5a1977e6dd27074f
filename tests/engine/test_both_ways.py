"""A recorded take tracked both ways: backward from its end, merged with the forward pass
frame by frame (takes.both_ways)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.camera import CAMERAS
from voodoo_addon.devtools.folds import (
    HELDOUT_FOLDS2,
    HELDOUT_FOLDS3,
    HELDOUT_FOLDS6,
    fold_clips,
    open_fold_clip,
    run_fold_clip,
)
from voodoo_addon.devtools.scenarios import scenario_take
from voodoo_addon.errors import VoodooError
from voodoo_addon.media.sources import ArraySource
from voodoo_addon.takes.both_ways import (
    FADE,
    TIE,
    backward_frames,
    backward_share,
    found_again,
    frames_backward,
    merge,
    sure_rows,
    track_backward,
    track_both_ways,
)
from voodoo_addon.takes.dolls import track_dolls
from voodoo_addon.takes.take import Take
from voodoo_addon.tracking import TrackerOptions
from voodoo_addon.tracking import tracker as tracker_module
from voodoo_addon.tracking.pictures import detail_for
from voodoo_addon.tracking.troupe import Troupe

T, M, TRI, P = 30, 4, 2, 3


def _take(x, conf, lost=None) -> Take:
    """A hand-made take: every node at (x[i], 0) on frame i, parameters (x[i], 0, 0)."""
    x = np.asarray(x, float)
    lost = np.zeros(len(x), bool) if lost is None else np.asarray(lost, bool)
    verts = np.zeros((len(x), M, 2))
    verts[:, :, 0] = x[:, None]
    params = np.zeros((len(x), P))
    params[:, 0] = x
    return Take(
        vertices=verts,
        triangles=np.array([[0, 1, 2], [1, 2, 3]], np.int32),
        params=params,
        confidence=np.broadcast_to(np.asarray(conf, float), x.shape).copy(),
        lost=lost,
        param_names=np.array(["translate-x", "translate-y", "rotate"]),
        frame_indices=np.arange(len(x)),
        times=np.arange(len(x)) / 30.0,
        fps=30.0,
        iterations=np.full(len(x), 3, np.int64),
        visible=np.repeat(~lost[:, None], TRI, axis=1),
    )


def test_the_surer_pass_is_kept_and_a_change_is_spread_over_frames():
    """The forward pass is surer on the first half, the backward one on the second: the
    merge follows each where it is surer, and goes from one to the other in steps no larger
    than a :data:`FADE`-th of where they disagree."""
    conf_f = np.r_[np.full(15, 0.9), np.full(15, 0.3)]
    fwd, bwd = _take(np.zeros(T), conf_f), _take(np.full(T, 10.0), 1.2 - conf_f)
    both = merge(fwd, bwd)
    x = both.params[:, 0]
    assert np.all(x[:10] == 0.0) and np.all(x[-10:] == 10.0)
    assert np.all(np.diff(x) >= 0) and np.diff(x).max() <= 10.0 / FADE + 1e-9
    np.testing.assert_allclose(both.vertices[:, :, 0], np.repeat(x[:, None], M, axis=1))
    assert np.all((both.confidence >= 0.3) & (both.confidence <= 0.9))
    assert not both.lost.any()
    np.testing.assert_array_equal(both.iterations, np.full(T, 6))
    np.testing.assert_array_equal(both.frame_indices, fwd.frame_indices)


def test_a_frame_one_pass_lost_is_the_other_pass_as_it_is():
    """Where the forward pass lost the doll (its held pose) and the backward one did not,
    the backward pass is taken whole, however sure the forward pass was around it."""
    lost = np.zeros(T, bool)
    lost[12:15] = True
    fwd = _take(np.where(lost, 99.0, 0.0), 0.95, lost)
    bwd = _take(np.full(T, 1.0), 0.5)
    both = merge(fwd, bwd)
    share = backward_share(fwd, bwd)
    assert np.all(share[lost] == 1.0)
    np.testing.assert_array_equal(both.params[lost, 0], np.ones(3))
    assert not both.lost.any()
    assert both.visible[lost].all()
    # Before the loss, the surer forward pass. After it, the forward pass has just found
    # the whole doll again: the backward pass, which kept it, is taken for AGAIN_FRAMES
    # frames; then the surer forward pass again.
    assert np.all(both.params[:8, 0] == 0.0)
    np.testing.assert_array_equal(found_again(fwd)[15:25], np.ones(10))
    assert np.all(both.params[15:21, 0] == 1.0) and np.all(both.params[-3:, 0] == 0.0)


def test_a_part_just_found_again_is_counted_in_each_pass_s_own_direction_of_time():
    """Three of six triangles out of view on frames 5-7: forward, they are found again on
    frames 8-17 (the :data:`AGAIN_FRAMES` after); backward, on frames 4 down to 0."""
    take = _take(np.zeros(20), 0.9)
    visible = np.ones((20, 6), bool)
    visible[5:8, :3] = False
    take = Take(**{**take.__dict__, "visible": visible})
    forward = np.zeros(20)
    forward[8:18] = 0.5
    backward = np.zeros(20)
    backward[:5] = 0.5
    np.testing.assert_array_equal(found_again(take), forward)
    np.testing.assert_array_equal(found_again(take, backward=True), backward)


def test_passes_about_as_sure_are_mixed_in_proportion():
    """Equal scores mix the two passes half and half; a backward pass a quarter of
    :data:`TIE` surer weighs five eighths; one :data:`TIE` surer or more is taken as it is."""
    fwd = _take(np.zeros(T), 0.8)
    for gap, weight in ((0.0, 0.5), (TIE / 4, 0.625), (TIE, 1.0), (0.2, 1.0)):
        both = merge(fwd, _take(np.full(T, 8.0), 0.8 + gap))
        np.testing.assert_allclose(both.params[:, 0], np.full(T, 8.0 * weight))
        np.testing.assert_allclose(both.vertices[:, :, 0], np.full((T, M), 8.0 * weight))


def test_two_equal_passes_merge_to_themselves():
    fwd = _take(np.linspace(0, 5, T), np.linspace(0.2, 0.9, T))
    both = merge(fwd, fwd)
    np.testing.assert_array_equal(both.vertices, fwd.vertices)
    np.testing.assert_array_equal(both.params, fwd.params)
    np.testing.assert_array_equal(both.lost, fwd.lost)


def test_passes_over_other_frames_or_blobs_are_refused():
    fwd = _take(np.zeros(T), 0.5)
    with pytest.raises(VoodooError, match="same frames"):
        merge(fwd, _take(np.zeros(T - 1), 0.5))
    other = _take(np.zeros(T), 0.5)
    other = Take(**{**other.__dict__, "param_names": np.array(["a", "b", "c"])})
    with pytest.raises(VoodooError, match="different blobs"):
        merge(fwd, other)


def test_a_file_is_read_backwards_a_chunk_at_a_time():
    frames = [np.full((4, 5, 3), i, np.uint8) for i in range(11)]
    got = list(frames_backward(ArraySource(frames), 2, 10, chunk=4))
    assert [f.index for f in got] == list(range(10, 1, -1))
    assert [int(f.pixels[0, 0, 0]) for f in got] == list(range(10, 1, -1))


def test_a_camera_cannot_be_read_backwards():
    source = ArraySource([np.zeros((4, 5, 3), np.uint8)] * 3)
    source.live = True
    with pytest.raises(VoodooError, match="camera"):
        next(frames_backward(source, 0, 2))


def test_a_take_that_ends_with_the_doll_gone_is_searched_backwards_from_its_end():
    """A take that ends with the doll gone (grey frames, lost forward): the backward pass
    starts on the last frame searching around the last pose found surely; the doll stays
    lost on the grey frames, is found on the first frame it is back, and is found both ways
    before."""
    frames, contour, _ = scenario_take("translate", 14, (320, 240), blob_pixels=5000)
    grey = np.full_like(frames[0], 0.5)
    frames = list(frames) + [grey] * 4
    troupe = Troupe({"doll": build_blob(frames[0], contour)})
    forward = track_dolls(troupe, ArraySource(frames))
    assert forward["doll"].lost[-4:].all() and not forward["doll"].lost[:14].any()
    assert sure_rows(forward) == {"doll": 13}
    assert backward_frames(forward) == 18
    back = track_backward(troupe, ArraySource(frames), forward)["doll"]
    assert back.lost[-4:].all() and not back.lost[:14].any()
    both = track_both_ways(troupe, ArraySource(frames), forward)["doll"]
    assert not both.lost[:14].any() and both.lost[-4:].all()
    np.testing.assert_array_equal(both.frame_indices, np.arange(18))
    assert np.abs(both.vertices[:14] - forward["doll"].vertices[:14]).max() < 0.5


def test_a_doll_left_at_a_doubtful_pose_is_searched_for_from_the_end():
    """A take whose last frames are followed at a doubtful pose (forward confidence under
    :data:`SURE`, here a pose put 12 px off by hand): the backward pass does not start from
    that pose but searches around the last sure one, finds the doll where it is, and the
    merge keeps the backward pass there."""
    frames, contour, _ = scenario_take("translate", 16, (320, 240), blob_pixels=5000)
    troupe = Troupe({"doll": build_blob(frames[0], contour)})
    forward = track_dolls(troupe, ArraySource(frames))["doll"]
    params, verts, conf = forward.params.copy(), forward.vertices.copy(), forward.confidence.copy()
    params[-4:, 0] += 12.0  # the last four frames 12 px off to the right...
    verts[-4:, :, 0] += 12.0
    conf[-4:] = 0.4  # ...at a doubtful confidence
    doubtful = replace(forward, params=params, vertices=verts, confidence=conf)
    assert sure_rows({"doll": doubtful}) == {"doll": 11}
    both = track_both_ways(troupe, ArraySource(frames), {"doll": doubtful})["doll"]
    assert not both.lost.any()
    assert np.abs(both.vertices[-2:] - forward.vertices[-2:]).max() < 0.5  # found again


def test_a_take_that_skips_frames_is_tracked_backwards_on_every_frame_between():
    """A camera's take keeps one frame per scene frame (here every other one, and two
    skipped together once), while its footage holds every frame: the backward pass tracks
    every frame between the take's first and last, and returns the take's own rows."""
    frames, contour, _ = scenario_take("translate", 16, (320, 240), blob_pixels=5000)
    troupe = Troupe({"doll": build_blob(frames[0], contour)})
    every = track_dolls(troupe, ArraySource(frames))["doll"]
    rows = np.array([0, 2, 4, 6, 9, 11, 13, 15])
    kept = Take(**{
        **every.__dict__,
        **{k: getattr(every, k)[rows] for k in ("vertices", "params", "confidence", "lost",
                                                "frame_indices", "times", "iterations",
                                                "visible")},
    })  # fmt: skip
    forward = {"doll": kept}
    assert backward_frames(forward) == 16
    done = []
    back = track_backward(troupe, ArraySource(frames), forward, done.append)["doll"]
    assert done[-1] == 16  # every frame between was tracked...
    np.testing.assert_array_equal(back.frame_indices, rows)  # ...the take's rows returned
    np.testing.assert_array_equal(back.times, kept.times)
    assert not back.lost.any()
    assert np.abs(back.vertices - kept.vertices).max() < 0.5
    both = track_both_ways(troupe, ArraySource(frames), forward)["doll"]
    np.testing.assert_array_equal(both.frame_indices, rows)

    shuffled = Take(**{**kept.__dict__, "frame_indices": rows[[0, 2, 1, 3, 4, 5, 6, 7]]})
    with pytest.raises(VoodooError, match="not in order"):
        track_backward(troupe, ArraySource(frames), {"doll": shuffled})
    beyond = Take(**{**kept.__dict__, "frame_indices": rows + 10})
    with pytest.raises(VoodooError, match="could not be read again"):
        track_backward(troupe, ArraySource(frames), {"doll": beyond})


def test_a_take_never_surely_found_is_not_tracked_backwards():
    lost = np.ones(T, bool)
    with pytest.raises(VoodooError, match="never has 'doll' found"):
        track_backward(None, None, {"doll": _take(np.zeros(T), 0.9, lost)})
    assert sure_rows({"doll": _take(np.zeros(T), 0.4)}) == {"doll": None}
    assert backward_frames({"doll": _take(np.zeros(T), 0.4)}) == 0


#: The held-out renders the forward pass alone falls short on (BENCHMARKS.md): frames of
#: the turned toy lost while most of it is seen, and the nodding plush further off than
#: DIS's nodes on one machine.
SHORT_ALONE = ["toy_tail_lift", "plush_nod"]


@pytest.mark.slow
@pytest.mark.parametrize("name", SHORT_ALONE)
def test_both_ways_a_recorded_fold_keeps_the_doll_where_the_forward_pass_falls_short(name):
    """Tracked both ways, these renders lose no frame while a third of the doll is in view,
    fold nothing, are nearer than KLT and DIS, and their modes jump no more than one of
    the two passes alone."""
    clip = next(
        c for c in fold_clips(HELDOUT_FOLDS2) + fold_clips(HELDOUT_FOLDS3) if c.name == name
    )
    rows = {r["tracker"]: r for r in run_fold_clip(clip, ("ours", "both", "klt", "dis"))}
    both, ours = rows["both"], rows["ours"]
    brief = {k: v for k, v in both.items() if not isinstance(v, list)}
    assert both["folded_fraction"] == 0.0
    assert both["lost_in_third"] == 0, brief
    assert both["error_px"] < min(rows["klt"]["error_px"], rows["dis"]["error_px"]), brief
    # The crossfade makes no jump of its own: the largest is one of the two passes' at most
    # (the forward pass's with NumPy 2.3; the backward pass's on frame 69 of toy_tail_lift
    # since faint dolls are compared with their detail strengthened, 2.39 px against the
    # forward pass's 1.77, NumPy 1.26).
    assert both["mode_jump_px"] <= max(ours["mode_jump_px"], both["backward_mode_jump_px"]), brief


def _minky():
    return next(c for c in fold_clips(HELDOUT_FOLDS6) if c.name == "minky_tail_swing")


@pytest.mark.slow
def test_both_ways_a_plush_turned_past_edge_on_is_followed_nearer():
    """The sixth held-out batch's plush, lifted by its corner past edge-on. Before the
    tracker kept the pose a fit ran far off from (test_folds), the forward pass took a
    wrong place there and lost 17 frames while most of it was seen; now it loses none
    (3.48 px, NumPy 1.26). Tracked both ways, no frame is lost either, the nodes are nearer
    than the forward pass's (2.72 px) and than KLT's and DIS's, and the crossfade makes no
    jump larger than the two passes' own."""
    rows = {r["tracker"]: r for r in run_fold_clip(_minky(), ("ours", "both", "klt", "dis"))}
    both, ours = rows["both"], rows["ours"]
    brief = {k: v for k, v in both.items() if not isinstance(v, list)}
    assert both["folded_fraction"] == 0.0 and both["lost_in_third"] == 0, brief
    assert both["error_px"] < ours["error_px"], brief
    assert both["error_px"] < min(rows["klt"]["error_px"], rows["dis"]["error_px"]), brief
    assert both["mode_jump_px"] <= max(ours["mode_jump_px"], both["backward_mode_jump_px"]), brief


@pytest.mark.slow
def test_both_ways_a_take_that_ends_at_a_wrong_pose_is_found_again_from_its_end(monkeypatch):
    """The same plush through the dim camera (seed 1): the forward pass slides 13 px off as
    the tail turns away, loses 10-15 frames while most of it is seen, and ends at a wrong
    pose, never back under a pixel (7.65 px with NumPy 1.26, 14.43 with NumPy 2.3). The
    backward pass does not start from such a pose: it searches for the doll on the last
    frame, finds it, and follows it back through the turn (2.06 and 2.50 px, no frame lost).
    (This was the redrawn plush, seed 0, until the forward pass stopped ending at a wrong
    pose there: since a doll lost while half turned away is found again by the half in
    view, it is 1.33 px off and both ways 1.39 with NumPy 1.26. Since a poor fit also tries
    the capture pose as a start, the forward pass comes back here too, from frame 75; that
    trial is switched off below, so that the take still ends at a wrong pose.)"""
    monkeypatch.setattr(tracker_module, "HOME_EVERY", 10**9)
    camera = replace(CAMERAS["dim"], seed=1)
    # The detail strengthened as the doll's contrast overall says (2.9x), as measured: at
    # 5x, the default since its fine contrast counts too, the forward pass comes back on
    # this draw (under a pixel 3 frames after the tail shows).
    _, blob, _ = open_fold_clip(_minky(), camera)
    options = TrackerOptions(detail=detail_for(blob.template))
    rows = {
        r["tracker"]: r
        for r in run_fold_clip(_minky(), ("ours", "both"), options=options, camera=camera)
    }
    both, ours = rows["both"], rows["ours"]
    brief = {k: v for k, v in both.items() if not isinstance(v, list)}
    assert ours["recovery_frames"] is None, {k: v for k, v in ours.items() if k != "frame_error"}
    assert both["lost_in_third"] == 0 and both["recovery_frames"] is not None, brief
    assert both["error_px"] < 0.5 * ours["error_px"], brief
