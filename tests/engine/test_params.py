"""Parameter vector: exact similarity composition, node positions, photometric terms."""

from __future__ import annotations

import numpy as np
import pytest

from voodoo_addon.tracking.params import (
    SIMILARITY,
    ParamLayout,
    compose,
    node_positions,
    rotation,
    similarity_from_matrix,
)

CENTRE = np.array([150.0, 110.0])
LABELS = ("bend-x", "shear", "stretch-x")


def _matrix(p, centre=CENTRE):
    """2x3 matrix of y = c + t + s R(theta) (x - c)."""
    a = np.exp(p[3]) * rotation(p[2])
    return np.column_stack([a, centre + p[:2] - a @ centre])


def _random_similarity(rng, theta_range=np.pi):
    return np.array(
        [
            rng.uniform(-80, 80),
            rng.uniform(-80, 80),
            rng.uniform(-theta_range, theta_range),
            rng.uniform(-0.7, 0.7),
        ]
    )


def test_rotation_matrix():
    r = rotation(0.7)
    np.testing.assert_allclose(r @ r.T, np.eye(2), atol=1e-15)
    assert np.linalg.det(r) == pytest.approx(1.0)
    # y down: a positive angle takes +x towards +y (clockwise on screen).
    np.testing.assert_allclose(rotation(np.pi / 2) @ [1.0, 0.0], [0.0, 1.0], atol=1e-15)


@pytest.mark.parametrize("seed", range(5))
def test_similarity_matrix_round_trip(seed):
    p = _random_similarity(np.random.default_rng(seed))
    np.testing.assert_allclose(similarity_from_matrix(_matrix(p), CENTRE), p, atol=1e-10)


def test_angle_is_unwrapped_near_the_hint():
    p = np.array([3.0, -2.0, 7.0, 0.2])  # more than a full turn
    q = similarity_from_matrix(_matrix(p), CENTRE, theta_near=6.5)
    np.testing.assert_allclose(q, p, atol=1e-10)
    q0 = similarity_from_matrix(_matrix(p), CENTRE)
    assert q0[2] == pytest.approx(7.0 - 2 * np.pi)


@pytest.mark.parametrize("bad", [np.zeros((2, 3)), np.array([[1.0, 0.0, np.nan], [0.0, 1.0, 0.0]])])
def test_degenerate_matrix_raises(bad):
    with pytest.raises(ValueError):
        similarity_from_matrix(bad, CENTRE)


@pytest.mark.parametrize("seed", range(8))
def test_compose_similarity_equals_matrix_product(seed):
    rng = np.random.default_rng(seed)
    lay = ParamLayout(LABELS, "none")
    a = np.zeros(lay.size)
    d = np.zeros(lay.size)
    a[:4] = _random_similarity(rng)
    d[:4] = _random_similarity(rng, theta_range=0.5)
    out = compose(a, d, lay)
    # W_new(x) = W_a(W_delta(x)): matrix product A_a A_d.
    ma, md = _matrix(a), _matrix(d)
    prod = np.column_stack([ma[:, :2] @ md[:, :2], ma[:, :2] @ md[:, 2] + ma[:, 2]])
    expected = similarity_from_matrix(prod, CENTRE, theta_near=a[2])
    np.testing.assert_allclose(out[:4], expected, atol=1e-9)
    np.testing.assert_allclose(_matrix(out), prod, atol=1e-9)


def test_compose_node_positions_with_zero_modes(blob):
    rng = np.random.default_rng(3)
    lay = ParamLayout(tuple(blob.labels), "channel")
    a, d = lay.identity(), lay.identity()
    a[:4] = _random_similarity(rng)
    d[:4] = _random_similarity(rng, 0.3)

    def nodes(p):
        return node_positions(p, lay, blob.vertices, blob.modes, blob.centre)

    def apply(p, x):
        return blob.centre + p[:2] + np.exp(p[3]) * (x - blob.centre) @ rotation(p[2]).T

    np.testing.assert_allclose(nodes(compose(a, d, lay)), apply(a, apply(d, blob.vertices)))


def test_many_small_updates_make_a_full_turn():
    lay = ParamLayout((), "none")
    a = lay.identity()
    step = lay.identity()
    step[2] = 2 * np.pi / 36
    step[3] = np.log(2.0) / 36
    for _ in range(36):
        a = compose(a, step, lay)
    assert a[2] == pytest.approx(2 * np.pi)  # continuous, not wrapped
    assert np.exp(a[3]) == pytest.approx(2.0)
    np.testing.assert_allclose(a[:2], 0.0, atol=1e-9)  # rotation about the pivot


def test_node_positions(blob):
    lay = ParamLayout(tuple(blob.labels), "global")
    a = lay.identity()
    np.testing.assert_allclose(
        node_positions(a, lay, blob.vertices, blob.modes, blob.centre), blob.vertices
    )
    a[:2] = [5.0, -3.0]
    np.testing.assert_allclose(
        node_positions(a, lay, blob.vertices, blob.modes, blob.centre),
        blob.vertices + [5.0, -3.0],
    )
    a = lay.identity()
    a[lay.modes.start + 1] = 2.0
    a[3] = np.log(1.5)
    expected = blob.centre + 1.5 * (blob.vertices - blob.centre + 2.0 * blob.mode_shape(1))
    np.testing.assert_allclose(
        node_positions(a, lay, blob.vertices, blob.modes, blob.centre), expected
    )


@pytest.mark.parametrize("photometric", ["channel", "global"])
def test_photometric_compose(photometric):
    # frame = c I0 + b; composing delta then a gives c = c_a c_d, b = b_a + c_a b_d.
    rng = np.random.default_rng(1)
    lay = ParamLayout(LABELS, photometric)
    a = rng.normal(0, 0.2, lay.size)
    d = rng.normal(0, 0.2, lay.size)
    ca, ba = lay.channel_gain_offset(a)
    cd, bd = lay.channel_gain_offset(d)
    c, b = lay.channel_gain_offset(compose(a, d, lay))
    np.testing.assert_allclose(c, ca * cd)
    np.testing.assert_allclose(b, ba + ca * bd)
    # Elastic amplitudes add.
    np.testing.assert_allclose(compose(a, d, lay)[lay.modes], a[lay.modes] + d[lay.modes])


@pytest.mark.parametrize(
    "photometric, extra",
    [("channel", 6), ("global", 2), ("none", 0)],
)
def test_layout(photometric, extra):
    lay = ParamLayout(LABELS, photometric)
    assert lay.size == 4 + len(LABELS) + extra == len(lay.names)
    assert lay.names[:4] == SIMILARITY
    assert lay.names[lay.modes] == LABELS
    assert lay.brightness.stop - lay.brightness.start == extra // 2
    assert lay.contrast.stop == lay.size
    assert lay.index("rotate") == 2
    assert lay.index("shear") == 5
    np.testing.assert_array_equal(lay.identity(), np.zeros(lay.size))
    c, b = lay.channel_gain_offset(lay.identity())
    np.testing.assert_array_equal(c, np.ones(3))
    np.testing.assert_array_equal(b, np.zeros(3))
    with pytest.raises(KeyError):
        lay.index("rotation")
