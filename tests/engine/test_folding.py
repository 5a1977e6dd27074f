"""The fold guard: no step, prediction or proposal ever inverts or collapses a triangle."""

import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.scenarios import scenario_take
from voodoo_addon.tracking import kernels
from voodoo_addon.tracking.folding import BACKOFF, MAX_AREA, MIN_AREA, FoldGuard


def _first_crossing(f0, f1, f2):
    """The first crossing in [0, 1] of one quadratic, as the guard's kernel takes it."""
    return max(0.0, min(1.0, kernels._crossing(float(f0), float(f1), float(f2))))


@pytest.fixture(scope="module")
def blob():
    frames, contour, _ = scenario_take("translate", frames=1, size=(320, 240))
    return build_blob(frames[0], contour)


@pytest.fixture(scope="module")
def guard(blob):
    return FoldGuard(blob.vertices, blob.triangles, blob.modes)


def _areas(blob, amplitudes):
    v = blob.deformed(amplitudes)[blob.triangles]
    e1, e2 = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    return 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def test_ratios_match_the_deformed_mesh(blob, guard):
    rest = _areas(blob, np.zeros(blob.n_modes))
    a = np.random.default_rng(1).normal(0, 3.0, blob.n_modes)
    np.testing.assert_allclose(guard.ratios(a), _areas(blob, a) / rest, rtol=1e-9)
    np.testing.assert_allclose(guard.ratios(np.zeros(blob.n_modes)), 1.0)


@pytest.mark.parametrize("seed", range(20))
def test_any_step_is_cut_to_stay_within_the_bounds(blob, guard, seed):
    rng = np.random.default_rng(seed)
    a = np.zeros(blob.n_modes)
    for _ in range(10):
        step = rng.normal(0, 40.0, blob.n_modes)  # wild: most would fold the mesh
        tau = guard.max_step(a, step)
        assert 0.0 <= tau <= 1.0
        # Every point along the (cut) step keeps every triangle within the bounds.
        for t in np.linspace(0.0, tau, 9):
            r = guard.ratios(a + t * step)
            assert r.min() >= MIN_AREA - 1e-9 and r.max() <= MAX_AREA + 1e-9
        a = a + tau * step
    assert guard.valid(a)


def test_a_safe_step_is_taken_whole_and_a_fold_stops_short(blob, guard):
    a = np.zeros(blob.n_modes)
    assert guard.max_step(a, np.full(blob.n_modes, 0.1)) == 1.0
    fold = np.zeros(blob.n_modes)
    fold[0] = 1.0
    # Walk the first mode until a triangle reaches the lower bound: the step stops at
    # BACKOFF of the crossing.
    far = 1000.0 * fold
    tau = guard.max_step(a, far)
    assert tau < 1.0
    crossing = tau / BACKOFF
    r = guard.ratios(crossing * far)
    assert np.isclose(r.min(), MIN_AREA, atol=1e-6) or np.isclose(r.max(), MAX_AREA, atol=1e-6)


def test_clamp_pulls_a_folded_shape_back_towards_rest(blob, guard):
    bad = np.random.default_rng(3).normal(0, 200.0, blob.n_modes)
    assert not guard.valid(bad)
    fixed = guard.clamp(bad)
    assert guard.valid(fixed)
    # Along the same direction, no further than needed.
    cos = fixed @ bad / (np.linalg.norm(fixed) * np.linalg.norm(bad))
    assert cos > 0.999
    good = np.full(blob.n_modes, 0.05)
    np.testing.assert_array_equal(guard.clamp(good), good)


@pytest.mark.parametrize(
    "f0, f1, f2, want",
    [
        (1.0, -1.0, 0.0, 1.0),  # linear, reaches 0 at tau = 1
        (1.0, -4.0, 0.0, 0.25),
        (1.0, 1.0, 0.0, 1.0),  # moving away: never
        (1.0, 0.0, -4.0, 0.5),  # concave quadratic
        (1.0, -3.0, 2.0, 0.5),  # roots 0.5 and 1
        (1.0, 0.0, 1.0, 1.0),  # convex, no root
        (0.0, -1.0, 0.0, 0.0),  # on the bound and leaving: no step
    ],
)
def test_first_crossing(f0, f1, f2, want):
    got = _first_crossing(f0, f1, f2)
    assert got == pytest.approx(want)


def test_a_triangle_on_its_bound_leaving_it_stops_the_step():
    """Rounding: a triangle exactly on the bound must not slip through (it once did)."""
    got = _first_crossing(7.1e-15, -12.13, -0.3576)
    assert got < 1e-12


def _numpy_step(guard, e1, e2, g1, g2):
    """The guard's step in plain NumPy, every triangle at once (what the kernel must give)."""

    def cross(u, v):
        return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]

    s = guard._sign
    a0 = s * 0.5 * cross(e1, e2)
    b = s * 0.5 * (cross(e1, g2) + cross(g1, e2))
    c = s * 0.5 * cross(g1, g2)
    if np.all(a0 - s * guard.low > np.abs(b) + np.abs(c)) and np.all(
        s * guard.high - a0 > np.abs(b) + np.abs(c)
    ):
        return 1.0
    roots = [_first_crossing(*f) for f in zip(a0 - s * guard.low, b, c, strict=True)] + [
        _first_crossing(*f) for f in zip(s * guard.high - a0, -b, -c, strict=True)
    ]
    tau = min(roots)
    return 1.0 if tau >= 1.0 else BACKOFF * tau


def test_the_compiled_step_is_the_numpy_one(blob, guard):
    """Both ways the kernel reads edges (modes, node offsets) give the NumPy step: exactly
    from node offsets, to rounding from modes (their edges are summed another way)."""
    rng = np.random.default_rng(0)
    tri = blob.triangles
    got = []
    for scale in (0.1, 1.0, 5.0, 20.0, 60.0, 200.0) * 3:
        a = guard.clamp(rng.normal(0, 30.0, blob.n_modes))
        step = rng.normal(0, scale, blob.n_modes)
        shape = blob.deformed(a) - blob.centre
        g = blob.deformed(step) - blob.vertices
        edges = [shape[tri[:, k]] - shape[tri[:, 0]] for k in (1, 2)]
        moves = [g[tri[:, k]] - g[tri[:, 0]] for k in (1, 2)]
        want = _numpy_step(guard, *edges, *moves)
        assert guard.shape_step(shape, g) == want
        assert guard.max_step(a, step) == pytest.approx(want, rel=1e-9)
        got.append(want)
    assert 1.0 in got and min(got) < 0.5  # whole steps and cut ones were both met
