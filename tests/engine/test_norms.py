"""Robust norms: the Lorentzian of Eq. 9 and its Eq. 16 transform."""

from __future__ import annotations

import numpy as np
import pytest

from voodoo_addon.tracking.norms import LorentzianNorm, QuadraticNorm, RobustNorm

_POS = np.geomspace(1e-6, 5.0, 1000)
E = np.concatenate([-_POS[::-1], [0.0], _POS])  # exactly symmetric about 0


@pytest.mark.parametrize("sigma", [0.02, 0.08, 0.15, 1.0])
def test_lorentzian_transform_formula(sigma):
    norm = LorentzianNorm(sigma)
    # log1p: log(1 + x) without the round-off of forming 1 + x for tiny x.
    rho = np.log1p(E**2 / (2.0 * sigma**2))
    np.testing.assert_allclose(norm.rho(E), rho, rtol=1e-12)
    np.testing.assert_allclose(norm.transform(E), np.sign(E) * np.sqrt(rho), rtol=1e-12)


@pytest.mark.parametrize("sigma", [0.02, 0.15, 1.0])
def test_lorentzian_transform_is_odd_and_monotone(sigma):
    t = LorentzianNorm(sigma).transform(E)
    np.testing.assert_array_equal(t, -t[::-1])  # E is symmetric about 0
    assert (np.diff(t) > 0).all()
    assert LorentzianNorm(sigma).transform(np.array([0.0]))[0] == 0.0


def test_lorentzian_tames_outliers():
    # Growth ~ sqrt(log|e|): a 100x larger error weighs far less than 100x more.
    norm = LorentzianNorm(0.1)
    small, big = norm.transform(np.array([0.1, 10.0]))
    assert big / small < 5.0
    q = QuadraticNorm(0.1).transform(np.array([0.1, 10.0]))
    assert q[1] / q[0] == pytest.approx(100.0)


def test_near_zero_the_lorentzian_is_quadratic():
    e = np.array([1e-4, -3e-4])
    sigma = 0.15
    np.testing.assert_allclose(
        LorentzianNorm(sigma).transform(e), e / (np.sqrt(2.0) * sigma), rtol=1e-6
    )


@pytest.mark.parametrize("norm", [LorentzianNorm(0.1), QuadraticNorm(0.1)])
def test_transform_keeps_float32(norm):
    e = np.linspace(-1, 1, 11, dtype=np.float32)
    out = norm.transform(e)
    assert out.dtype == np.float32
    assert out.shape == e.shape


def test_quadratic_transform_is_linear():
    np.testing.assert_allclose(QuadraticNorm(0.5).transform(E), E / (np.sqrt(2.0) * 0.5))


def test_keys_identify_the_norm():
    assert LorentzianNorm(0.1).key == LorentzianNorm(0.1).key
    assert LorentzianNorm(0.1).key != LorentzianNorm(0.2).key
    assert LorentzianNorm(0.1).key != QuadraticNorm(0.1).key
    hash(LorentzianNorm(0.1).key)


@pytest.mark.parametrize("sigma", [0.0, -1.0])
def test_lorentzian_needs_positive_sigma(sigma):
    with pytest.raises(ValueError):
        LorentzianNorm(sigma)


def test_robust_norm_is_abstract():
    with pytest.raises(TypeError):
        RobustNorm()
