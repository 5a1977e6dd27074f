"""Finite-element model of the blob on Gaussian interpolants, and its vibration modes.

Nodal vectors are stored interleaved: ``U = (u_0, v_0, u_1, v_1, ...)`` (length 2m), i.e. an
(m, 2) displacement array flattened in C order.

Normalisation (so that numbers mean the same for every blob size):

* mass ``M = (1/A) * integral H^T H dA`` -- an M-unit mode has an RMS displacement of one
  pixel over the blob, so a modal amplitude *is* an RMS displacement in pixels;
* stiffness ``K = (L^2/A) * integral B^T C B dA`` with ``L`` the blob's RMS radius and plane
  stress ``C`` (Young's modulus 1, Poisson ratio ``nu``) -- ``w^2`` is dimensionless and the
  same for a scaled copy of the blob.

The integrals are quadratures over the blob's pixel centres (the honest choice for a
bounded region).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from .interpolants import GaussianInterpolant

#: Quadrature points are thinned to at most this many (every k-th pixel) for speed.
MAX_QUADRATURE_POINTS = 12000


def plane_stress(poisson: float) -> np.ndarray:
    """Plane-stress elasticity matrix (3, 3) for Young's modulus 1.

    Strain order ``(e_xx, e_yy, g_xy)``.
    """
    nu = poisson
    return np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, 0.5 * (1.0 - nu)]]) / (
        1.0 - nu * nu
    )


def quadrature_points(pixels: np.ndarray) -> np.ndarray:
    """Every k-th pixel centre, so that at most :data:`MAX_QUADRATURE_POINTS` remain."""
    step = max(1, int(np.ceil(len(pixels) / MAX_QUADRATURE_POINTS)))
    return pixels[::step]


def rms_radius(points: np.ndarray) -> float:
    """Root-mean-square distance of points (n, 2) from their centroid."""
    return float(np.sqrt(((points - points.mean(axis=0)) ** 2).sum(axis=1).mean()))


def assemble(
    interp: GaussianInterpolant, quad: np.ndarray, poisson: float = 0.3
) -> tuple[np.ndarray, np.ndarray]:
    """Mass and stiffness matrices.

    Parameters
    ----------
    interp : GaussianInterpolant
        Interpolants on the m nodes.
    quad : (q, 2) float64
        Quadrature points covering the blob uniformly (pixel centres), equal weights.
    poisson : float
        Poisson ratio of the plane-stress material.

    Returns
    -------
    M, K : (2m, 2m) float64
        Symmetric; M positive definite, K positive semi-definite with the rigid motions
        (two translations, the linearised rotation) in its null space.
    """
    m = len(interp.nodes)
    h = interp(quad)  # (q, m)
    hx, hy = interp.gradient(quad)  # (q, m) each
    n_q = len(quad)
    length2 = rms_radius(quad) ** 2
    c = plane_stress(poisson)
    ms = h.T @ h / n_q  # scalar mass (m, m)
    xx, yy = hx.T @ hx / n_q, hy.T @ hy / n_q
    xy = hx.T @ hy / n_q
    k_uu = c[0, 0] * xx + c[2, 2] * yy
    k_vv = c[1, 1] * yy + c[2, 2] * xx
    k_uv = c[0, 1] * xy + c[2, 2] * xy.T
    mass = np.zeros((2 * m, 2 * m))
    stiff = np.zeros((2 * m, 2 * m))
    mass[0::2, 0::2] = ms
    mass[1::2, 1::2] = ms
    stiff[0::2, 0::2] = k_uu
    stiff[1::2, 1::2] = k_vv
    stiff[0::2, 1::2] = k_uv
    stiff[1::2, 0::2] = k_uv.T
    stiff *= length2
    # Symmetrise round-off.
    return 0.5 * (mass + mass.T), 0.5 * (stiff + stiff.T)


def similarity_fields(nodes: np.ndarray, centre: np.ndarray, length: float) -> np.ndarray:
    """Nodal fields of the infinitesimal similarity about ``centre``.

    Returns
    -------
    (2m, 4) float64
        Columns: translate-x, translate-y, rotate (``(-y, x) / L``), scale (``(x, y) / L``),
        interleaved layout, un-normalised.
    """
    d = (nodes - centre) / length
    m = len(nodes)
    f = np.zeros((m, 2, 4))
    f[:, 0, 0] = 1.0
    f[:, 1, 1] = 1.0
    f[:, 0, 2], f[:, 1, 2] = -d[:, 1], d[:, 0]
    f[:, 0, 3], f[:, 1, 3] = d[:, 0], d[:, 1]
    return f.reshape(2 * m, 4)


def m_orthonormalize(fields: np.ndarray, mass: np.ndarray) -> np.ndarray:
    """Gram-Schmidt (twice, for stability) of the columns of ``fields`` in the M inner product."""
    out = np.array(fields, dtype=np.float64)
    for _ in range(2):
        for j in range(out.shape[1]):
            v = out[:, j]
            for i in range(j):
                v = v - (out[:, i] @ mass @ v) * out[:, i]
            out[:, j] = v / np.sqrt(v @ mass @ v)
    return out


@dataclass(frozen=True)
class Modes:
    """Result of the modal analysis.

    Attributes
    ----------
    constrained : (2m, c) float64
        M-orthonormal fields the elastic modes are kept M-orthogonal to (the exact rigid
        fields, and the scale field when it is separated).
    shapes : (2m, k) float64
        Elastic modes, M-orthonormal, ordered by increasing stiffness.
    mode_stiffness : (k,) float64
        ``w_j^2`` of each elastic mode: its regularisation penalty ``psi_j^2`` (Eq. 10).
    """

    constrained: np.ndarray
    shapes: np.ndarray
    mode_stiffness: np.ndarray


def polynomial_fields(
    nodes: np.ndarray, centre: np.ndarray, length: float, degree: int
) -> np.ndarray:
    """Nodal fields ``(x^p y^q, 0)`` and ``(0, x^p y^q)`` with ``p + q == degree``.

    Coordinates are normalised about ``centre`` by ``length``.

    Returns
    -------
    (2m, 2 (degree + 1)) float64, interleaved layout.
    """
    d = (nodes - centre) / length
    cols = []
    for p in range(degree, -1, -1):
        mono = d[:, 0] ** p * d[:, 1] ** (degree - p)
        for comp in (0, 1):
            f = np.zeros_like(d)
            f[:, comp] = mono
            cols.append(f.ravel())
    return np.column_stack(cols)


def _complement(fields: np.ndarray, basis: np.ndarray, mass: np.ndarray) -> np.ndarray:
    """M-orthonormal basis of the part of ``fields`` M-orthogonal to ``basis`` (M-orthonormal)."""
    if basis.shape[1]:
        fields = fields - basis @ (basis.T @ mass @ fields)
    gram = fields.T @ mass @ fields
    w, v = np.linalg.eigh(0.5 * (gram + gram.T))
    keep = w > 1e-9 * max(w.max(), 1e-300)
    return fields @ (v[:, keep] / np.sqrt(w[keep]))


def ritz(mass: np.ndarray, stiff: np.ndarray, trial: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rayleigh-Ritz in the span of M-orthonormal ``trial`` vectors (2m, t).

    Returns
    -------
    shapes : (2m, t) float64
        M-orthonormal, K-orthogonal, by increasing stiffness.
    stiffness : (t,) float64
        Their Rayleigh quotients ``w^2``.
    """
    kt = trial.T @ stiff @ trial
    mt = trial.T @ mass @ trial
    w2, y = scipy.linalg.eigh(0.5 * (kt + kt.T), 0.5 * (mt + mt.T))
    return trial @ y, np.maximum(w2, 0.0)


def modal_analysis(mass: np.ndarray, stiff: np.ndarray, constraints: np.ndarray) -> Modes:
    """Elastic modes M-orthogonal to the given fields.

    Solves ``Z^T K Z y = w^2 Z^T M Z y`` on a basis Z of the M-orthogonal complement of the
    constraint fields, so ``phi = Z y`` satisfies ``P^T K phi = w^2 M phi`` with the
    M-orthogonal projector ``P = I - R R^T M``; when the constraints are exactly K's null
    space (rigid motions only) that is ``K phi = w^2 M phi``.

    Parameters
    ----------
    mass, stiff : (2m, 2m) float64
    constraints : (2m, c) float64
        Fields to separate (e.g. :func:`similarity_fields`).

    Returns
    -------
    Modes
    """
    r = m_orthonormalize(constraints, mass)
    # Basis of {x : R^T M x = 0}: the right-singular vectors beyond rank.
    _, _, vt = np.linalg.svd((mass @ r).T)
    z = vt[r.shape[1] :].T  # (2m, 2m - c)
    kr = z.T @ stiff @ z
    mr = z.T @ mass @ z
    w2, y = scipy.linalg.eigh(0.5 * (kr + kr.T), 0.5 * (mr + mr.T))
    shapes = z @ y
    return Modes(constrained=r, shapes=shapes, mode_stiffness=np.maximum(w2, 0.0))


def select_modes(
    mass: np.ndarray,
    stiff: np.ndarray,
    constraints: np.ndarray,
    n_modes: int,
    nodes: np.ndarray | None = None,
    centre: np.ndarray | None = None,
    length: float = 1.0,
    poly_degree: int = 0,
) -> Modes:
    """The ``n_modes`` elastic modes the tracker uses.

    With ``poly_degree == 0`` these are the lowest FE vibration modes (the paper's choice).
    With ``poly_degree = d > 0`` the modes are chosen in tiers -- the polynomial displacement
    fields of degree <= 2, then of degree 3, ... up to ``d`` (each tier by its Rayleigh-Ritz
    stiffness), then the FE modes of what is left -- and a final Rayleigh-Ritz step on the
    chosen span makes them M-orthonormal, K-orthogonal and ordered by stiffness.

    Why: a hand squeezing foam applies smooth loads, whose static response is low-order
    polynomial (constant strain, pure bending, ...). Free-vibration modes spread such fields
    over many modes: 14 FE modes leave a 1 px node error on a 14 px bend of an 8.5k-pixel blob,
    the tiered basis none (see BENCHMARKS.md).

    Parameters
    ----------
    mass, stiff : (2m, 2m) float64
    constraints : (2m, c) float64
        Fields kept out of the modes (the similarity fields).
    n_modes : int
    nodes, centre, length
        Needed for polynomial tiers.
    poly_degree : int

    Returns
    -------
    Modes
    """
    r = m_orthonormalize(constraints, mass)
    chosen = np.zeros((len(mass), 0))
    stiffness = np.zeros(0)
    tiers = []
    if poly_degree >= 1:
        tiers.append(np.column_stack([polynomial_fields(nodes, centre, length, k) for k in (1, 2)]))
        tiers += [polynomial_fields(nodes, centre, length, k) for k in range(3, poly_degree + 1)]
    for fields in tiers:
        if chosen.shape[1] >= n_modes:
            break
        trial = _complement(fields, np.column_stack([r, chosen]), mass)
        if trial.shape[1] == 0:
            continue
        shapes, w2 = ritz(mass, stiff, trial)
        take = n_modes - chosen.shape[1]
        chosen = np.column_stack([chosen, shapes[:, :take]])
        stiffness = np.concatenate([stiffness, w2[:take]])
    if chosen.shape[1] < n_modes:
        rest = modal_analysis(mass, stiff, np.column_stack([r, chosen]))
        take = n_modes - chosen.shape[1]
        chosen = np.column_stack([chosen, rest.shapes[:, :take]])
        stiffness = np.concatenate([stiffness, rest.mode_stiffness[:take]])
    if poly_degree >= 1 and chosen.shape[1]:
        chosen, stiffness = ritz(mass, stiff, chosen)
    return Modes(constrained=r, shapes=chosen, mode_stiffness=stiffness)
