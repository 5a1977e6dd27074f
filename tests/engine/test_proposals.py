"""Start poses from followed points and from features, when the prediction misses."""

import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.synthetic import Pose, foam_scene
from voodoo_addon.tracking.params import ParamLayout, node_positions
from voodoo_addon.tracking.proposals import (
    TEMPLATE_FEATURES,
    FeatureMatcher,
    MotionProposal,
    PointFit,
)

SIZE = (320, 240)


@pytest.fixture(scope="module")
def scene_blob():
    scene, contour = foam_scene(*SIZE, 6000)
    rest = scene.render(Pose(), noise=0.005, rng=np.random.default_rng(0))
    blob = build_blob(rest, contour)
    layout = ParamLayout(tuple(str(s) for s in blob.labels), "channel")
    return scene, blob, layout, rest


def _nodes(blob, layout, a):
    return node_positions(a, layout, blob.vertices, blob.modes, blob.centre)


def test_point_fit_recovers_parameters_from_exact_points(scene_blob):
    _, blob, layout, _ = scene_blob
    rng = np.random.default_rng(1)
    rest = blob.pixel_coords[rng.choice(blob.n_pixels, 60, replace=False)]
    fit = PointFit(blob, layout, rest)
    truth = layout.identity()
    truth[:4] = (12.0, -7.0, 0.3, 0.1)
    truth[layout.modes][:3] = (3.0, -2.0, 1.5)
    truth[layout.modes.start : layout.modes.start + 3] = (3.0, -2.0, 1.5)
    seen = fit.positions(truth)
    got = fit.fit(np.arange(60), seen, truth[:4], layout.identity(), strength=1e-9)
    err = np.linalg.norm(_nodes(blob, layout, got) - _nodes(blob, layout, truth), axis=1)
    assert err.max() < 0.05


@pytest.mark.parametrize("jump", [(30.0, 0.0, 0.0), (-25.0, 20.0, 0.2), (35.0, -10.0, -0.25)])
def test_points_followed_from_the_last_frame_bridge_a_big_jump(scene_blob, jump):
    scene, blob, layout, rest = scene_blob
    pose = Pose(tx=jump[0], ty=jump[1], theta=jump[2], deform={"bend-x": 0.06})
    frame = scene.render(pose, noise=0.005, rng=np.random.default_rng(2))
    proposal = MotionProposal(blob, layout)
    assert len(proposal) >= 40
    a = proposal.propose(rest, frame, layout.identity())
    assert a is not None
    truth = scene.forward(pose, blob.vertices)
    err = np.linalg.norm(_nodes(blob, layout, a) - truth, axis=1)
    assert err.mean() < 2.5, err.mean()  # within the pyramid's reach: the fit finishes it


def test_no_proposal_when_the_points_cannot_be_followed(scene_blob):
    _, blob, layout, rest = scene_blob
    noise = np.random.default_rng(3).uniform(0, 1, rest.shape).astype(np.float32)
    assert MotionProposal(blob, layout).propose(rest, noise, layout.identity()) is None


def test_features_find_a_turned_and_moved_blob(scene_blob):
    scene, blob, layout, _ = scene_blob
    pose = Pose(tx=-40.0, ty=25.0, theta=2.0)  # far and turned: no prediction would reach it
    frame = scene.render(pose, noise=0.005, rng=np.random.default_rng(4))
    guess = FeatureMatcher(blob, layout).guess(frame, layout.identity())
    assert guess is not None
    err = np.linalg.norm(_nodes(blob, layout, guess) - scene.forward(pose, blob.vertices), axis=1)
    assert err.mean() < 3.0, err.mean()


def _faint(image):
    """The picture with a tenth of its contrast, as faint fur shows its pattern."""
    return (0.5 + 0.1 * (np.asarray(image) - 0.5)).astype(np.float32)


def test_a_lost_doll_of_faint_texture_is_found_by_fainter_features():
    """SIFT's default finds too few keypoints on a faint template to match at all; a lost
    doll is searched for by fainter ones, a doll not lost keeps the default (and so does a
    lost one whose template has enough)."""
    scene, contour = foam_scene(*SIZE, 6000)
    rest = _faint(scene.render(Pose(), noise=0.0005, rng=np.random.default_rng(0)))
    blob = build_blob(rest, contour)
    layout = ParamLayout(tuple(str(s) for s in blob.labels), "channel")
    pose = Pose(tx=-40.0, ty=25.0, theta=2.0)
    frame = _faint(scene.render(pose, noise=0.0005, rng=np.random.default_rng(4)))
    matcher = FeatureMatcher(blob, layout)
    assert len(matcher._template(False)[1]) < TEMPLATE_FEATURES
    assert matcher.guess(frame, layout.identity()) is None
    assert len(matcher._template(True)[1]) >= TEMPLATE_FEATURES
    guess = matcher.guess(frame, layout.identity(), lost=True)
    assert guess is not None
    err = np.linalg.norm(_nodes(blob, layout, guess) - scene.forward(pose, blob.vertices), axis=1)
    assert err.mean() < 3.0, err.mean()


def test_a_lost_doll_of_rich_texture_is_matched_as_one_not_lost(scene_blob):
    _, blob, _, _ = scene_blob
    matcher = FeatureMatcher(blob, ParamLayout(tuple(str(s) for s in blob.labels), "channel"))
    assert len(matcher._template(False)[1]) >= TEMPLATE_FEATURES
    np.testing.assert_array_equal(matcher._template(True)[1], matcher._template(False)[1])


def test_the_template_keypoints_are_made_ahead_and_are_those_made_on_demand():
    """A tracker's matcher makes its template's keypoints, plain and faint, on the helper
    thread while the first frames are tracked: the first search does not pay for them,
    and they are the very keypoints a matcher makes when asked."""
    from concurrent.futures import ThreadPoolExecutor

    scene, contour = foam_scene(*SIZE, 6000)
    rest = _faint(scene.render(Pose(), noise=0.0005, rng=np.random.default_rng(0)))
    blob = build_blob(rest, contour)
    layout = ParamLayout(tuple(str(s) for s in blob.labels), "channel")
    ahead, asked = FeatureMatcher(blob, layout), FeatureMatcher(blob, layout)
    with ThreadPoolExecutor(1) as helper:
        ahead.prepare(helper)
    assert set(ahead._made) == {False, True}  # made without a search asking
    for lost in (False, True):
        np.testing.assert_array_equal(ahead._template(lost)[1], asked._template(lost)[1])
        np.testing.assert_array_equal(ahead._template(lost)[2], asked._template(lost)[2])


def test_features_detected_ahead_give_the_guess_made_on_demand(scene_blob, monkeypatch):
    """The frame's features detected on a helper thread ahead of the search give the very
    guess the search makes when it detects them itself; a guess asked with another box (or
    after the detection was dropped) detects again on its own thread."""
    import threading
    from concurrent.futures import ThreadPoolExecutor

    scene, blob, layout, _ = scene_blob
    pose = Pose(tx=-12.0, ty=8.0, theta=0.4)
    frame = scene.render(pose, noise=0.005, rng=np.random.default_rng(6))
    box, other = (20, 10, 300, 230), (0, 0, 320, 240)
    near = layout.identity()
    on_demand = FeatureMatcher(blob, layout).guess(frame, near, box)
    assert on_demand is not None
    where = []
    detect = FeatureMatcher._detect

    def traced(frame, box, detector):
        where.append(threading.current_thread().name)
        return detect(frame, box, detector)

    monkeypatch.setattr(FeatureMatcher, "_detect", staticmethod(traced))
    matcher = FeatureMatcher(blob, layout)
    with ThreadPoolExecutor(1, thread_name_prefix="helper") as helper:
        matcher.look_ahead(helper, frame, box)
        np.testing.assert_array_equal(matcher.guess(frame, near, box), on_demand)
        assert len(where) == 1 and where[0].startswith("helper")
        matcher.look_ahead(helper, frame, other)  # another box: the guess detects again
        np.testing.assert_array_equal(matcher.guess(frame, near, box), on_demand)
        assert len(where) == 3 and where[2] == threading.current_thread().name
        matcher.look_ahead(helper, frame, box)
        matcher.drop_ahead(wait=False)
        np.testing.assert_array_equal(matcher.guess(frame, near, box), on_demand)
    assert matcher._ahead is None and matcher._ending is None
