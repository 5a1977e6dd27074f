"""Many poses or meshes ranked at once: each evaluation's residual, to the last bit.

The grid search of the coarse level and the crease candidates of the local stage compare
dozens of warps of one frame and keep only which fits best. They are ranked in one pass
(``evaluation.residuals``); these tests hold that pass to the numbers the evaluations
themselves give, on and partly off the picture, behind a known cover, with compressed
triangles and with an adapted look. A level's fit reads its nodes as the frame nodes times
the level's scale; one test holds those to ``Level.nodes`` too.
"""

from __future__ import annotations

import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.scenarios import scenario_take
from voodoo_addon.tracking import Tracker
from voodoo_addon.tracking.evaluation import Cover, evaluate, residuals
from voodoo_addon.tracking.warp import CpuWarp

SIZE = (320, 240)


@pytest.fixture(scope="module")
def tracked():
    """A tracker one frame into a take that bends and turns, and the next frame."""
    frames, contour, _ = scenario_take("mixed", 4, SIZE, blob_pixels=5000)
    tracker = Tracker(build_blob(frames[0], contour))
    tracker.track(frames[1])
    return tracker, frames[2]


def _grid(a, reach=60.0, count=7):
    poses = []
    for dy in np.linspace(-reach, reach, count):
        for dx in np.linspace(-reach, reach, count):
            pose = a.copy()
            pose[0] += dx
            pose[1] += dy
            poses.append(pose)
    return poses


def _one_by_one(step, poses, org, box, least):
    out = []
    for a in poses:
        ev = step.evaluate(a, org, box)
        use = None if ev is None else np.count_nonzero(ev.use)
        out.append(np.inf if ev is None or use < least * len(step.level) else ev.residual)
    return np.array(out)


def _bound(tracker, frame, step):
    fitter = tracker.fitter
    fitter.forget()
    images, origin = fitter.pyramid(frame, [tracker.state], True)
    return fitter._bind(step, images, origin)


@pytest.mark.parametrize("bent", [False, True])
def test_a_coarse_grid_ranked_at_once_gives_each_evaluations_residual(tracked, bent):
    """Translations reaching off the picture (inf where an evaluation would be None or
    compare too little), on a pose with compressed triangles too."""
    tracker, frame = tracked
    step = tracker.fitter.levels[-1]
    assert not step.level.finest
    a = tracker.state.copy()
    if bent:
        modes = tracker.layout.modes
        a[modes] = 0.0
        a[modes.start] = 0.6 * tracker.blob.length  # squeezes part of the doll flat
        assert step.hidden(a) is not None
    poses = _grid(a, reach=float(max(SIZE)))
    org, box = _bound(tracker, frame, step)
    want = _one_by_one(step, poses, org, box, 0.5)
    assert np.isfinite(want).any() and not np.isfinite(want).all()
    np.testing.assert_array_equal(step.residuals(poses, org, box), want)


def test_a_grid_behind_a_known_cover_gives_each_evaluations_residual(tracked):
    tracker, frame = tracked
    step = tracker.fitter.levels[-1]
    nodes = tracker.nodes(tracker.state)
    lo = np.floor(nodes.min(axis=0)).astype(int)
    mask = np.zeros((60, 80), bool)
    mask[:, :40] = True
    step.cover = Cover(mask, origin=tuple(lo))
    try:
        poses = _grid(tracker.state, reach=20.0, count=5)
        org, box = _bound(tracker, frame, step)
        want = _one_by_one(step, poses, org, box, 0.5)
        np.testing.assert_array_equal(step.residuals(poses, org, box), want)
    finally:
        step.cover = None


@pytest.mark.parametrize("adapted", [False, True])
def test_meshes_ranked_at_once_give_each_evaluations_residual(tracked, adapted):
    """Meshes of any shape on the finest level's pixels, nothing tested for occlusion (as
    the crease candidates are judged), against the template or an adapted look."""
    tracker, frame = tracked
    step = tracker.fitter.levels[0]
    level = step.level
    rng = np.random.default_rng(3)
    a = tracker.state
    base = tracker.nodes(a) * level.scale
    meshes = [base + rng.normal(0.0, 1.5, base.shape) for _ in range(12)]
    meshes.append(base + 400.0)  # off the picture: None, so inf
    look = None
    if adapted:
        look = np.clip(level.template + rng.normal(0, 0.02, level.template.shape), 0, 1)
        look = look.astype(np.float32)
    org, box = _bound(tracker, frame, step)
    none = np.zeros(level.n_triangles, bool)
    want = []
    for v in meshes:
        ev = evaluate(
            level, a, org, box, step.backend, step.norm, step.layout, step.outlier_factor,
            step.floor, v, None, none, look, None,
        )  # fmt: skip
        want.append(np.inf if ev is None else ev.residual)
    got = residuals(level, a, meshes, org, box, step.backend, step.norm, step.layout, template=look)
    assert np.isinf(got[-1]) and np.isfinite(got[:-1]).all()
    np.testing.assert_array_equal(got, np.array(want))


def test_sampling_many_warps_at_once_gives_each_warps_samples(tracked):
    tracker, frame = tracked
    level = tracker.fitter.levels[1].level
    backend = CpuWarp()
    backend.bind(np.ascontiguousarray(frame[::2, ::2], dtype=np.float32))
    poses = _grid(tracker.state, reach=10.0, count=3)
    nodes = [level.nodes(a) for a in poses]
    places = [level.positions(a, v) for a, v in zip(poses, nodes, strict=True)]
    many = backend.sample_many(level.geometry, nodes, places)
    for got, v, p in zip(many, nodes, places, strict=True):
        np.testing.assert_array_equal(got, backend.sample(level.geometry, v, p))


def test_translated_poses_share_their_shape_and_give_the_same_nodes(tracked):
    tracker, _ = tracked
    level = tracker.fitter.levels[1].level
    poses = _grid(tracker.state, reach=7.3, count=3)
    turned = tracker.state.copy()
    turned[2] += 0.3  # not a translation: its own shape
    poses.append(turned)
    for got, a in zip(level.translated_nodes(poses), poses, strict=True):
        np.testing.assert_array_equal(got, level.nodes(a))


@pytest.mark.parametrize("based", [False, True])
def test_every_levels_nodes_are_the_frame_nodes_times_its_scale_to_the_bit(tracked, based):
    """A level's fit samples at the frame nodes times the level's scale (a power of two), not
    at ``Level.nodes``: the same numbers, for bent, turned, scaled poses and on top of base
    offsets (a crease being followed)."""
    tracker, _ = tracked
    fitter = tracker.fitter
    rng = np.random.default_rng(7)
    base = rng.normal(0.0, 3.0, tracker.blob.vertices.shape) if based else None
    fitter.set_base(base)
    try:
        for _ in range(40):
            a = tracker.state + rng.normal(0.0, 1.0, tracker.state.shape) * rng.choice(
                [0.01, 0.3, 3.0]
            )
            for step in fitter.levels:
                scale = step.level.scale
                assert np.log2(scale) == round(np.log2(scale))
                np.testing.assert_array_equal(step._nodes(a) * scale, step.level.nodes(a))
    finally:
        fitter.set_base(None)


def test_the_grid_search_keeps_the_first_best_pose_and_never_one_without_a_number(
    tracked, monkeypatch
):
    """Across its starts the grid keeps the first pose of least residual, as comparing them
    one by one did; a residual that is not a number is never the best."""
    tracker, frame = tracked
    fitter = tracker.fitter
    step = fitter.levels[-1]
    ranked = iter(
        [
            np.array([np.nan, 3.0, 2.0, 2.0] + [5.0] * 21),
            np.array([2.0, np.nan, 1.5] + [1.5] * 22),
        ]
    )
    monkeypatch.setattr(step, "residuals", lambda poses, org, box: next(ranked))
    fitter.forget()
    images, origin = fitter.pyramid(frame, [tracker.state], False)
    seeds = [tracker.state.copy(), tracker.state.copy()]
    seeds[1][0] += 40.0
    best, evaluations = fitter._grid_search(images, origin, seeds)
    assert evaluations == 50
    offsets = np.arange(-6, 7, 3) / step.level.scale
    want = seeds[1].copy()
    want[0] += offsets[2]  # the third pose of the second start: dy first, then dx
    want[1] += offsets[0]
    np.testing.assert_array_equal(best, want)
