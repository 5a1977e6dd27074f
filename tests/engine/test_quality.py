"""Judging a track: texture consistency, folds, losses, the check command and the confidence."""

import json

import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.cli import main
from voodoo_addon.devtools.scenarios import scenario_take
from voodoo_addon.devtools.synthetic import Pose, foam_scene, write_frames
from voodoo_addon.takes.take import Take, save_take
from voodoo_addon.tracking import Tracker
from voodoo_addon.tracking.quality import folded_triangles, score_track

SIZE = (320, 240)


@pytest.fixture(scope="module")
def take():
    frames, contour, truth = scenario_take("bend", frames=12, size=SIZE)
    blob = build_blob(frames[0], contour)
    truths = np.array([truth(i, blob.vertices) for i in range(len(frames))])
    return frames, blob, truths


def test_the_true_mesh_is_consistent_and_a_wrong_one_is_not(take):
    frames, blob, truths = take
    right = score_track(frames, truths, blob.triangles)
    assert right.mean > 0.9 and right.p10 > 0.85
    assert right.folded_fraction == 0.0 and right.lost_fraction == 0.0
    shifted = truths + np.array([4.0, 0.0])  # 4 px off in every frame after the first
    shifted[0] = truths[0]
    wrong = score_track(frames, shifted, blob.triangles)
    assert wrong.mean < 0.5 * right.mean


def test_a_fold_is_counted_even_where_the_texture_agrees(take):
    frames, blob, truths = take
    verts = truths.copy()
    tri = blob.triangles[len(blob.triangles) // 2]
    for i in range(3, 6):  # push one node across its opposite edge
        a, b, c = verts[i, tri]
        verts[i, tri[0]] = b + c - a
    score = score_track(frames, verts, blob.triangles)
    np.testing.assert_array_equal(np.nonzero(score.folded)[0], [3, 4, 5])
    assert score.folded_fraction == pytest.approx(3 / len(frames))


def test_folded_triangles_ignores_a_uniform_shrink(take):
    _, blob, _ = take
    rest = blob.vertices
    small = blob.centre + 0.05 * (rest - blob.centre)  # far away, not collapsed
    assert not folded_triangles(small, rest, blob.triangles).any()
    flipped = rest * np.array([-1.0, 1.0])  # mirrored: every triangle turned over
    assert folded_triangles(flipped, rest, blob.triangles).all()
    nan = rest.copy()
    nan[0] = np.nan
    assert folded_triangles(nan, rest, blob.triangles).any()


def _write_take(tmp_path, frames, blob, vertices, lost=None):
    t = len(vertices)
    video = tmp_path / "clip.avi"
    write_frames(video, frames)
    take = Take(
        vertices=vertices,
        triangles=blob.triangles,
        params=np.zeros((t, 4)),
        confidence=np.ones(t),
        lost=np.zeros(t, bool) if lost is None else lost,
        param_names=np.array(["translate-x", "translate-y", "rotate", "scale"]),
        frame_indices=np.arange(t),
        times=np.arange(t) / 30.0,
        fps=30.0,
        iterations=np.ones(t, np.int64),
        visible=np.ones((t, len(blob.triangles)), bool),
    )
    path = tmp_path / "take.npz"
    save_take(path, take)
    return video, path


def test_check_command_reports_the_scores(take, tmp_path, capsys):
    frames, blob, truths = take
    lost = np.zeros(len(frames), bool)
    lost[7] = True
    video, path = _write_take(tmp_path, frames, blob, truths, lost)
    assert main(["check", str(video), str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["frames"] == len(frames)
    assert out["consistency_mean"] > 0.9 and out["folded_fraction"] == 0.0
    assert out["lost_fraction"] == pytest.approx(1 / len(frames), abs=1e-4)
    assert len(out["per_frame"]) == len(frames) and out["lost"][7] == 1
    assert main(["check", str(video), str(path), "--per-frame"]) == 0
    text = capsys.readouterr().out
    assert "texture consistency mean" in text and len(text.splitlines()) == len(frames) + 2


def test_check_refuses_a_video_that_is_not_the_takes(take, tmp_path, capsys):
    frames, blob, truths = take
    video, path = _write_take(tmp_path, frames[:5], blob, truths)  # the clip is too short
    assert main(["check", str(video), str(path)]) == 2
    assert "has no frame 5" in capsys.readouterr().err


# ----------------------------------------------------------------------- the confidence


@pytest.fixture(scope="module")
def foam():
    scene, contour = foam_scene(*SIZE, 6000)
    rest = scene.render(Pose(), noise=0.01, rng=np.random.default_rng(0))
    return scene, build_blob(rest, contour)


def test_confidence_falls_when_the_mesh_sits_off_its_texture(foam):
    """Held at the last pose while the doll moved: the confidence says it is wrong."""
    scene, blob = foam
    tracker = Tracker(blob)
    right = tracker.fitter.fit(
        scene.render(Pose(), noise=0.01), [tracker.layout.identity()], False, None
    )
    assert right.confidence > 0.95
    for shift in (3.0, 6.0, 18.0):  # 18 px: one square of the painted grid
        frame = scene.render(Pose(tx=shift), noise=0.01)
        ev_fit = tracker.fitter.levels[0]
        pyr, origin = tracker.fitter.pyramid(frame, [tracker.layout.identity()], False)
        org, box = ev_fit.bind(pyr[ev_fit.index], origin)
        ev = ev_fit.evaluate(tracker.layout.identity(), org, box)
        q = tracker.fitter.quality(ev, tracker.layout.identity())
        assert q.value < 0.6, (shift, q)


def test_confidence_stays_high_under_lighting_that_varies_across_the_doll(foam):
    scene, blob = foam
    c = scene.centre
    pose = Pose(
        shade=(c[0] - 20, c[1], 30.0, 0.4),
        glint=(c[0] + 25, c[1] - 10, 12.0, 0.5),
        channel_gain=(1.2, 1.0, 0.85),
    )
    res = Tracker(blob).track(scene.render(pose, noise=0.01))
    assert not res.lost and res.confidence > 0.7
    err = np.linalg.norm(res.nodes - scene.forward(pose, blob.vertices), axis=1)
    assert err.mean() < 0.5
