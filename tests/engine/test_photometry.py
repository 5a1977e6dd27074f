"""Lighting patches: per-patch grey gain and bias projected out of the comparison."""

import numpy as np
import pytest

from voodoo_addon.tracking.photometry import PATCH_PIXELS, Patches, group_triangles


@pytest.fixture
def patches():
    rng = np.random.default_rng(0)
    template = rng.uniform(0.1, 0.9, (300, 3)).astype(np.float32)
    patch = np.repeat(np.arange(6), 50)
    return Patches(patch, template), template, patch


def test_a_grey_gain_and_bias_per_patch_vanish(patches):
    p, t, patch = patches
    gain = np.array([0.5, 1.3, 0.9, 2.0, 0.7, 1.1])[patch][:, None]
    bias = np.array([0.1, -0.05, 0.0, -0.3, 0.2, 0.05])[patch][:, None]
    frame = (gain * t + bias).astype(np.float32)
    d, corr = p.project(t - frame)
    assert np.abs(d).max() < 1e-5
    np.testing.assert_allclose(corr, 1.0, atol=1e-5)
    # ... also when fitted on part of the pixels only
    mask = np.random.default_rng(1).uniform(size=len(t)) > 0.3
    d, corr = p.project(t - frame, mask)
    assert np.abs(d).max() < 1e-5 and (d[~mask] == 0).all()


def test_colour_changes_are_not_lighting(patches):
    """A patch whose colour changes (red to blue) is not explained by a grey gain."""
    p, t, patch = patches
    frame = t.copy()
    frame[patch == 2] = frame[patch == 2][:, ::-1]  # swap red and blue there
    d, corr = p.project(t - frame)
    assert np.abs(d[patch == 2]).max() > 0.1
    assert np.abs(d[patch != 2]).max() < 1e-6
    assert corr[2] < 0.9 and (np.delete(corr, 2) > 0.999).all()


def test_a_flat_occluder_does_not_correlate(patches):
    p, t, patch = patches
    frame = t.copy()
    frame[patch == 4] = 0.5  # a grey card
    _, corr = p.project(t - frame)
    assert np.isnan(corr[4]) or corr[4] < 0.1


def test_masked_and_unmasked_projections_agree(patches):
    p, t, _ = patches
    d = np.random.default_rng(2).normal(0, 0.1, t.shape).astype(np.float32)
    a, ca = p.project(d)
    b, cb = p.project(d, np.ones(len(t), bool))
    np.testing.assert_allclose(a, b, atol=1e-5)
    np.testing.assert_allclose(ca, cb, atol=1e-5)


def test_projected_basis_is_blind_to_lighting(patches):
    p, t, patch = patches
    basis = np.random.default_rng(3).normal(size=(len(t), 3, 4))
    pb = p.project_basis(basis)
    for k in range(6):
        sel = patch == k
        dev = t[sel] - t[sel].mean()
        assert np.abs(pb[sel].sum(axis=(0, 1))).max() < 1e-9  # no grey bias left
        assert np.abs((pb[sel] * dev[:, :, None]).sum(axis=(0, 1))).max() < 1e-6  # no gain


def test_pixels_must_come_grouped(patches):
    _, t, patch = patches
    with pytest.raises(ValueError):
        Patches(patch[::-1].copy()[np.r_[1:300, 0]], t)


def test_triangles_gather_into_patches_of_enough_pixels():
    rng = np.random.default_rng(4)
    centroids = rng.uniform(0, 100, (200, 2))
    pixel_triangle = rng.integers(0, 200, 10000)  # 50 pixels a triangle on average
    patch = group_triangles(centroids, pixel_triangle, 1.0)
    assert patch.min() == 0 and len(np.unique(patch)) == patch.max() + 1
    sizes = np.bincount(patch, weights=np.bincount(pixel_triangle, minlength=200))
    assert sizes.min() >= 0.5 * max(PATCH_PIXELS, 10000 / 32)
