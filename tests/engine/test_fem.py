"""Finite-element model on Gaussian interpolants and its modes."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

from voodoo_addon.blob.fem import (
    MAX_QUADRATURE_POINTS,
    assemble,
    m_orthonormalize,
    modal_analysis,
    plane_stress,
    polynomial_fields,
    rms_radius,
    select_modes,
    similarity_fields,
)
from voodoo_addon.blob.interpolants import GaussianInterpolant
from voodoo_addon.blob.labels import field_matrix

BLOBS = ["blob", "fe_blob", "fe_blob_scale"]


@pytest.fixture(params=BLOBS)
def any_blob(request):
    return request.getfixturevalue(request.param)


def _rel(a, b):
    return np.abs(a - b).max() / max(np.abs(b).max(), 1e-300)


def test_plain_fe_modes_solve_the_generalised_eigenproblem(fe_blob):
    # poly_degree=0, only rigid motions separated: K phi = w^2 M phi exactly.
    k, m, phi, w2 = fe_blob.stiffness, fe_blob.mass, fe_blob.modes, fe_blob.mode_stiffness
    assert fe_blob.constrained.shape[1] == 3
    lhs, rhs = k @ phi, m @ phi * w2
    assert _rel(lhs, rhs) < 1e-9


def test_fe_modes_are_the_lowest_eigenvectors(fe_blob):
    w_all = scipy.linalg.eigh(fe_blob.stiffness, fe_blob.mass, eigvals_only=True)
    # Three rigid zeros, then the elastic spectrum the blob kept.
    assert np.abs(w_all[:3]).max() < 1e-9 * w_all[3]
    np.testing.assert_allclose(fe_blob.mode_stiffness, w_all[3 : 3 + fe_blob.n_modes], rtol=1e-8)


def test_scale_separated_fe_modes_solve_the_projected_problem(fe_blob_scale):
    b = fe_blob_scale
    k, m, phi, w2, r = b.stiffness, b.mass, b.modes, b.mode_stiffness, b.constrained
    assert r.shape[1] == 4
    proj = np.eye(len(m)) - r @ r.T @ m  # M-orthogonal projector off the constrained fields
    assert _rel(proj.T @ k @ phi, m @ phi * w2) < 1e-9


def test_modes_are_m_orthonormal_and_k_orthogonal(any_blob):
    phi, w2 = any_blob.modes, any_blob.mode_stiffness
    np.testing.assert_allclose(phi.T @ any_blob.mass @ phi, np.eye(phi.shape[1]), atol=1e-9)
    pkp = phi.T @ any_blob.stiffness @ phi
    np.testing.assert_allclose(pkp, np.diag(w2), atol=1e-9 * w2.max())


def test_modes_are_m_orthogonal_to_the_constrained_fields(any_blob):
    r, m, phi = any_blob.constrained, any_blob.mass, any_blob.modes
    np.testing.assert_allclose(r.T @ m @ r, np.eye(r.shape[1]), atol=1e-9)
    assert np.abs(r.T @ m @ phi).max() < 1e-9


def test_stiffness_increases_and_is_positive(any_blob):
    w2 = any_blob.mode_stiffness
    assert any_blob.n_modes == 20
    assert (w2 > 0).all()
    assert (np.diff(w2) >= 0).all()


def test_rigid_fields_carry_no_strain_energy(any_blob):
    r, k = any_blob.constrained, any_blob.stiffness
    rigid = np.diag(r[:, :3].T @ k @ r[:, :3])
    assert np.abs(rigid).max() < 1e-9 * any_blob.mode_stiffness.min()


def test_constrained_fields_are_the_similarity_fields(any_blob):
    # Column order: translate-x, translate-y, rotate (and scale).
    r = any_blob.constrained.reshape(any_blob.n_nodes, 2, -1)
    d = any_blob.vertices - any_blob.centre
    assert np.ptp(r[:, 0, 0]) < 1e-9 and np.abs(r[:, 1, 0]).max() < 1e-9
    assert np.ptp(r[:, 1, 1]) < 1e-9 and np.abs(r[:, 0, 1]).max() < 1e-9
    rot = r[:, :, 2]
    # (-y, x) up to normalisation and a translation component (zero: centre is the centroid).
    ratio = rot[:, 1] / np.where(np.abs(d[:, 0]) > 1, d[:, 0], np.nan)
    ratio = ratio[np.isfinite(ratio)]
    assert np.ptp(ratio) < 1e-6 * np.abs(ratio).mean()


def test_mass_is_rms_displacement_over_the_blob(any_blob):
    # An M-unit mode moves the blob's pixels by 1 px RMS (fem.py's normalisation).
    assert any_blob.n_pixels <= MAX_QUADRATURE_POINTS  # quadrature over every pixel
    h = any_blob.interpolant(any_blob.pixel_coords)
    for j in range(any_blob.n_modes):
        u = h @ any_blob.mode_shape(j)
        assert np.sqrt((u**2).sum(axis=1).mean()) == pytest.approx(1.0, rel=1e-8)


def test_scale_field_energy_is_plane_stress_bulk_value(fe_blob_scale):
    # Unit isotropic strain (x, y)/L, M-normalised (L is the RMS radius of the same pixels):
    # energy = L^2 [1 1] C [1 1]^T / L^2 = 2 / (1 - nu).
    nu = fe_blob_scale.poisson
    s = fe_blob_scale.constrained[:, 3]
    assert s @ fe_blob_scale.stiffness @ s == pytest.approx(2.0 / (1.0 - nu), rel=1e-8)


def test_constant_strain_energies(blob):
    # Linear fields are exact, so their energies are closed-form: K = (L^2/A) int B^T C B dA.
    nu, length2 = blob.poisson, blob.length**2
    c = plane_stress(nu)
    d = blob.vertices - blob.centre
    stretch = np.column_stack([d[:, 0], 0 * d[:, 1]]).ravel()  # e_xx = 1
    shear = np.column_stack([d[:, 1], d[:, 0]]).ravel()  # g_xy = 2
    k = blob.stiffness
    assert stretch @ k @ stretch == pytest.approx(length2 * c[0, 0], rel=1e-8)
    assert shear @ k @ shear == pytest.approx(4.0 * length2 * c[2, 2], rel=1e-8)
    assert c[0, 0] == pytest.approx(1.0 / (1.0 - nu**2))


def test_mass_and_stiffness_are_symmetric_definite(blob):
    m, k = blob.mass, blob.stiffness
    np.testing.assert_array_equal(m, m.T)
    np.testing.assert_array_equal(k, k.T)
    assert np.linalg.eigvalsh(m).min() > 0
    ev = np.linalg.eigvalsh(k)
    assert ev.min() > -1e-10 * ev.max()


def test_matrices_are_invariant_to_blob_size(blob):
    # A copy of the blob twice as large gives the same M and K (normalised FE, fem.py).
    nodes, quad = blob.vertices, blob.pixel_coords[::3]
    m1, k1 = assemble(GaussianInterpolant(nodes), quad, 0.3)
    m2, k2 = assemble(GaussianInterpolant(2.0 * nodes + 7.0), 2.0 * quad + 7.0, 0.3)
    np.testing.assert_allclose(m2, m1, atol=1e-9 * np.abs(m1).max())
    np.testing.assert_allclose(k2, k1, atol=1e-9 * np.abs(k1).max())


def test_default_basis_holds_every_quadratic_field_exactly(blob):
    # poly_degree=3: all polynomial fields of degree <= 2 are in span(constrained, modes).
    span = np.column_stack([blob.constrained, blob.modes])
    m = blob.mass
    fields = np.column_stack(
        [polynomial_fields(blob.vertices, blob.centre, blob.length, k) for k in (0, 1, 2)]
    )
    resid = fields - span @ (span.T @ m @ fields)
    norm = np.sqrt(np.einsum("ij,ij->j", resid, m @ resid))
    full = np.sqrt(np.einsum("ij,ij->j", fields, m @ fields))
    assert (norm < 1e-8 * full).all()


def test_plain_fe_basis_does_not_hold_bending_exactly(fe_blob):
    # The contrast that motivates the tiered basis (fem.select_modes docstring).
    names, fields = field_matrix(fe_blob.vertices, fe_blob.centre, fe_blob.length)
    f = fields[:, names.index("bend-x")]
    span = np.column_stack([fe_blob.constrained, fe_blob.modes])
    r = f - span @ (span.T @ fe_blob.mass @ f)
    assert np.sqrt(r @ fe_blob.mass @ r) > 1e-3 * np.sqrt(f @ fe_blob.mass @ f)


# ------------------------------------------------------------------------- unit pieces


def test_similarity_fields_layout():
    nodes = np.array([(0.0, 0.0), (2.0, 0.0), (0.0, 4.0)])
    f = similarity_fields(nodes, centre=np.array([1.0, 1.0]), length=2.0)
    assert f.shape == (6, 4)
    f = f.reshape(3, 2, 4)
    np.testing.assert_array_equal(f[:, :, 0], [[1, 0]] * 3)
    np.testing.assert_array_equal(f[:, :, 1], [[0, 1]] * 3)
    d = (nodes - 1.0) / 2.0
    np.testing.assert_allclose(f[:, :, 2], np.column_stack([-d[:, 1], d[:, 0]]))
    np.testing.assert_allclose(f[:, :, 3], d)


def test_m_orthonormalize(blob):
    rng = np.random.default_rng(0)
    raw = rng.normal(size=(blob.mass.shape[0], 5))
    q = m_orthonormalize(raw, blob.mass)
    np.testing.assert_allclose(q.T @ blob.mass @ q, np.eye(5), atol=1e-10)
    # Same span (Gram-Schmidt is triangular).
    coef = np.linalg.lstsq(q, raw, rcond=None)[0]
    np.testing.assert_allclose(q @ coef, raw, atol=1e-8 * np.abs(raw).max())


def test_modal_analysis_and_select_modes_agree_without_polynomials(blob):
    sim = similarity_fields(blob.vertices, blob.centre, blob.length)
    full = modal_analysis(blob.mass, blob.stiffness, sim)
    sel = select_modes(blob.mass, blob.stiffness, sim, 6, poly_degree=0)
    np.testing.assert_allclose(sel.mode_stiffness, full.mode_stiffness[:6], rtol=1e-9)
    assert full.shapes.shape == (len(blob.mass), len(blob.mass) - 4)


def test_rms_radius():
    pts = np.array([(1.0, 0.0), (-1.0, 0.0), (0.0, 3.0), (0.0, -3.0)])
    assert rms_radius(pts) == pytest.approx(np.sqrt(5.0))
    assert rms_radius(pts + 100) == pytest.approx(np.sqrt(5.0))
