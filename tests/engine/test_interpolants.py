"""Gaussian interpolants: h_i(X_j) = delta_ij, exact constant and linear fields, gradients."""

from __future__ import annotations

import numpy as np
import pytest

from voodoo_addon.blob.interpolants import GaussianInterpolant
from voodoo_addon.blob.mesh import triangulate
from voodoo_addon.blob.outline import validate_contour
from voodoo_addon.devtools.synthetic import ellipse_contour
from voodoo_addon.errors import VoodooError


def _mesh_nodes():
    return triangulate(validate_contour(ellipse_contour((160.0, 120.0), 60.0, 40.0))).vertices


def _random_nodes(seed=0, n=40):
    return np.random.default_rng(seed).uniform([20, 30], [220, 150], size=(n, 2))


NODE_SETS = {"mesh": _mesh_nodes, "random": _random_nodes}


def _points_around(nodes, seed=1, n=200):
    lo, hi = nodes.min(axis=0), nodes.max(axis=0)
    pad = 0.2 * (hi - lo)
    return np.random.default_rng(seed).uniform(lo - pad, hi + pad, size=(n, 2))


@pytest.fixture(params=list(NODE_SETS), scope="module")
def nodes(request):
    return NODE_SETS[request.param]()


@pytest.mark.parametrize("width_factor", [0.5, 1.0, 1.5])
def test_interpolates_at_the_nodes(nodes, width_factor):
    h = GaussianInterpolant(nodes, width_factor=width_factor)
    # Wider Gaussians condition G worse; 1e-6 is still "exactly delta_ij".
    np.testing.assert_allclose(h(nodes), np.eye(len(nodes)), atol=1e-6)


def test_default_width_is_mean_nearest_neighbour_distance(nodes):
    d = np.linalg.norm(nodes[:, None] - nodes[None], axis=2)
    np.fill_diagonal(d, np.inf)
    h = GaussianInterpolant(nodes, width_factor=1.3)
    assert h.width == pytest.approx(1.3 * d.min(axis=1).mean())
    assert GaussianInterpolant(nodes, width=7.0).width == 7.0


@pytest.mark.parametrize("width_factor", [0.7, 1.0, 1.5])
def test_reproduces_constant_and_linear_fields(nodes, width_factor):
    h = GaussianInterpolant(nodes, width_factor=width_factor)
    pts = _points_around(nodes)
    hp = h(pts)
    assert hp.shape == (len(pts), len(nodes))
    np.testing.assert_allclose(hp.sum(axis=1), 1.0, atol=1e-8)
    np.testing.assert_allclose(hp @ nodes, pts, atol=1e-6)
    # Any affine displacement field u(x) = A x + b is carried exactly.
    a = np.array([[0.3, -1.2], [0.8, 0.1]])
    b = np.array([4.0, -2.5])
    np.testing.assert_allclose(h.displace(pts, nodes @ a.T + b), pts @ a.T + b, atol=1e-6)


def test_does_not_reproduce_a_quadratic_field_exactly(nodes):
    # The exactness above is not vacuous: a curved field is only approximated between nodes.
    h = GaussianInterpolant(nodes)
    pts = _points_around(nodes)
    f = lambda p: ((p - 120.0) ** 2).sum(axis=1)  # noqa: E731
    err = np.abs(h(pts) @ f(nodes) - f(pts)).max()
    assert err > 1e-3


def test_gradient_matches_finite_differences(nodes):
    h = GaussianInterpolant(nodes)
    pts = _points_around(nodes, seed=2, n=50)
    eps = 1e-4 * h.width
    gx, gy = h.gradient(pts)
    fx = (h(pts + [eps, 0]) - h(pts - [eps, 0])) / (2 * eps)
    fy = (h(pts + [0, eps]) - h(pts - [0, eps])) / (2 * eps)
    scale = np.abs(fx).max()
    np.testing.assert_allclose(gx, fx, atol=1e-6 * scale)
    np.testing.assert_allclose(gy, fy, atol=1e-6 * scale)


def test_gradient_of_linear_fields_is_exact(nodes):
    h = GaussianInterpolant(nodes)
    pts = _points_around(nodes, seed=3)
    gx, gy = h.gradient(pts)
    np.testing.assert_allclose(gx.sum(axis=1), 0.0, atol=1e-8)
    np.testing.assert_allclose(gy.sum(axis=1), 0.0, atol=1e-8)
    np.testing.assert_allclose(gx @ nodes, np.tile([1.0, 0.0], (len(pts), 1)), atol=1e-6)
    np.testing.assert_allclose(gy @ nodes, np.tile([0.0, 1.0], (len(pts), 1)), atol=1e-6)


def test_translation_invariant(nodes):
    h1 = GaussianInterpolant(nodes)
    h2 = GaussianInterpolant(nodes + [100.0, -40.0])
    pts = _points_around(nodes)
    np.testing.assert_allclose(h1(pts), h2(pts + [100.0, -40.0]), atol=1e-8)


def test_accepts_a_single_point():
    nodes = _random_nodes()
    h = GaussianInterpolant(nodes)
    assert h(nodes[3]).shape == (1, len(nodes))
    np.testing.assert_allclose(h(nodes[3])[0], np.eye(len(nodes))[3], atol=1e-8)


@pytest.mark.parametrize(
    "bad",
    [
        np.array([(0.0, 0.0), (1.0, 1.0)]),
        np.array([(5.0, 5.0)] * 6),
    ],
    ids=["two-nodes", "coincident"],
)
def test_degenerate_nodes_raise(bad):
    with pytest.raises(VoodooError):
        GaussianInterpolant(bad)


def test_collinear_nodes_raise():
    # The linear part (1, x, y) is rank-deficient on a line: the docstring promises an error
    # rather than an interpolant that silently fails to reproduce constants off the line.
    t = np.arange(10.0)
    with pytest.raises(VoodooError):
        GaussianInterpolant(np.column_stack([t, 2 * t]))
