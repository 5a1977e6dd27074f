"""The precomputed least squares of one pyramid level, and the update it gives (Eq. 14-16).

:func:`build_solver` turns a level's basis of difference images into everything an
iteration needs: the Eq. 16 transform of the basis, the regularised pseudo-inverse with the
Eq. 10 stiffness prior, and per-triangle Gram matrices for the weighted solve used when
part of the blob is covered, off the picture or turned away. :func:`solve` gives the
parameter update of one evaluation.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from . import kernels
from .evaluation import Evaluation
from .level import Level
from .norms import RobustNorm
from .warp import WarpBackend

#: Weight of the pull of hidden triangles back to their rest shape, relative to the pull of
#: their pixels if they were seen (see :func:`solve`).
REOPEN = 0.3


@dataclass(eq=False)
class Solver:
    """Precomputed least squares for one level and one set of active parameters.

    Attributes
    ----------
    active : (p,) int64
        Indices into the parameter vector.
    update : (p, 3n) float32
        ``N (Bbar^T Bbar + Gamma)^-1 Bbar^T``: maps the robust difference image to ``da``.
    prior : (p, p) float64
        ``N (Bbar^T Bbar + Gamma)^-1 gamma' N^T Psi^2``: the regularisation pull on ``a``.
    jacobian : (p, 3n) float32
        Difference basis collapsed per parameter (least-squares slope over the four steps),
        for the weighted solve used when parts of the blob are occluded or off the frame;
        stored a parameter per row, so that its product with a difference image reads it
        in order.
    triangle_gram : (t, p, p) float64
        ``J_k^T J_k`` of the pixels of every triangle.
    penalty : (p, p) float64
        ``gamma' Psi^2 + ridge`` for the weighted solve.
    reg : (p,) float64
        ``gamma' psi_j^2`` (zero for unregularised parameters).
    modal : (p,) bool
        Which active parameters are elastic modes.
    modal_gram : (t, q, q) float64
        ``triangle_gram`` restricted to the modes (q of them).
    """

    active: np.ndarray
    update: np.ndarray
    prior: np.ndarray
    jacobian: np.ndarray
    triangle_gram: np.ndarray
    penalty: np.ndarray
    reg: np.ndarray
    modal: np.ndarray
    modal_gram: np.ndarray

    @cached_property
    def modal_block(self) -> slice | None:
        """The modes among the active parameters, as a slice (they are consecutive)."""
        at = np.flatnonzero(self.modal)
        return slice(int(at[0]), int(at[-1]) + 1) if len(at) else None


def build_solver(
    level: Level,
    backend: WarpBackend,
    active: np.ndarray,
    norm: RobustNorm,
    gamma: float,
    penalties: np.ndarray,
) -> Solver:
    """The Eq. 14-16 least squares of ``level`` for the ``active`` parameters.

    Parameters
    ----------
    level : Level
    backend : WarpBackend
        Warps the template to make the difference basis.
    active : (p,) int64
    norm : RobustNorm
        Its Eq. 16 transform is applied to the basis.
    gamma : float
        Weight of the modal-stiffness prior (Eq. 10) against the mean robust error.
    penalties : (k,) float64
        ``psi_j^2`` of each elastic mode.
    """
    b, nmat = level.basis(backend, active)
    bbar = norm.transform(b)  # Eq. 16
    rows = bbar.shape[0]
    # Regularisation (Eq. 10): gamma * mean robust error is matched by gamma' on the sums.
    psi2 = np.zeros(len(active))
    lay = level.layout
    for j, k in enumerate(active):
        if lay.modes.start <= k < lay.modes.stop:
            psi2[j] = penalties[k - lay.modes.start]
    gam = gamma * rows
    modal = (active >= lay.modes.start) & (active < lay.modes.stop)
    # Collapsed basis (least-squares slope over the steps) for the weighted solve.
    denom = (nmat**2).sum(axis=1)  # (p,)
    jac = bbar @ nmat.T / denom
    # J_k^T J_k per triangle: the outer products of the rows, summed per triangle.
    rows_tri = np.repeat(level.triangle, 3)
    order = np.argsort(rows_tri, kind="stable")
    bounds = np.searchsorted(rows_tri[order], np.arange(level.n_triangles + 1))
    jsorted = jac[order]
    tri_gram = np.zeros((level.n_triangles, len(active), len(active)))
    for k in range(level.n_triangles):
        jk = jsorted[bounds[k] : bounds[k + 1]]
        if len(jk):
            tri_gram[k] = jk.T @ jk
    jgram = tri_gram.sum(axis=0)
    scale = np.trace(jgram) / len(jgram)
    # With lighting patches, a change of all three channels' brightness (or contrast) at
    # once is a patch's grey bias (gain): invisible after the projection. Pin those sums.
    gauge = np.zeros((len(active), len(active)))
    if level.patches is not None:
        for group in (lay.brightness, lay.contrast):
            sel = np.isin(active, np.arange(lay.size)[group]).astype(float)
            gauge += np.outer(sel, sel)
    gauge *= 10.0 * scale
    gram = bbar.T @ bbar
    ridge = 1e-6 * np.trace(gram) / len(gram)
    lhs = gram + nmat.T @ (gam * np.diag(psi2) + gauge) @ nmat + ridge * np.eye(len(gram))
    inv_lhs = np.linalg.inv(lhs)
    update = nmat @ inv_lhs @ bbar.T
    prior = nmat @ inv_lhs @ (gam * nmat.T * psi2[None, :])
    penalty = np.diag(gam * psi2) + gauge + 1e-6 * scale * np.eye(len(active))
    return Solver(
        active=active,
        update=np.ascontiguousarray(update, dtype=np.float32),
        prior=prior,
        jacobian=np.ascontiguousarray(jac.T, dtype=np.float32),
        triangle_gram=tri_gram,
        penalty=penalty,
        reg=gam * psi2,
        modal=modal,
        modal_gram=np.ascontiguousarray(tri_gram[:, modal][:, :, modal]),
    )


def solve(
    solver: Solver, level: Level, ev: Evaluation, a_act: np.ndarray, anchor=None
) -> np.ndarray:
    """Parameter update (active parameters) from one evaluation.

    Unweighted: the precomputed ``N B+`` of Eq. 14-15 with the Eq. 10 prior. Weighted
    (occlusion, hidden triangles, blob partly off the picture): the same least squares on the
    collapsed basis restricted to the used pixels, with the Gram matrix assembled from
    per-triangle Gram matrices minus the rows of the dropped pixels of kept triangles.

    A triangle that is not seen keeps its local shape: its Gram matrix, restricted to the
    modes, stays in the system as a pull of the modes towards ``anchor`` (the last frame's
    shape), so a covered or off-picture part follows the similarity and the seen parts'
    bending instead of drifting where no pixel holds it. A *hidden* triangle (compressed
    by a surface turning away) is pulled towards its rest shape instead, by
    :data:`REOPEN` of that weight: where the surface really is folded, the seen parts
    around the fold hold it; where it has come back, nothing does, and it opens again.
    """
    if not ev.weighted:
        return solver.update @ ev.dbar.ravel() - solver.prior @ a_act
    gram = _weighted_sum(ev.triangle_weight, solver.triangle_gram)
    rows = np.empty(3 * len(ev.use), np.int64)
    k = kernels.dropped_rows(ev.triangle_weight, level.triangle, ev.use, rows)
    if k:
        jg = np.empty((len(solver.jacobian), k))
        kernels.gather_columns(solver.jacobian, rows[:k], jg)
        gram = gram - jg @ jg.T
    dbar = ev.dbar if level.patches is not None else ev.dbar * ev.use[:, None]
    rhs = solver.jacobian @ dbar.ravel()  # (the patch projection zeroes unused pixels)
    rhs = rhs - solver.reg * a_act
    unseen = 1.0 - ev.triangle_weight
    m = solver.modal_block
    if anchor is not None and m is not None and unseen.any():
        hidden = ev.hidden
        held = unseen if hidden is None else unseen * ~hidden
        hold = _weighted_sum(held, solver.modal_gram)
        target = hold @ (anchor[m] - a_act[m])
        if hidden is not None:
            reopen = REOPEN * _weighted_sum(hidden.astype(np.float64), solver.modal_gram)
            hold = hold + reopen
            target = target - reopen @ a_act[m]
        gram[m, m] += hold
        rhs[m] += target
    try:
        return np.linalg.solve(gram + solver.penalty, rhs)
    except np.linalg.LinAlgError:
        return np.zeros_like(a_act)


def _weighted_sum(weights: np.ndarray, grams: np.ndarray) -> np.ndarray:
    """``sum_k weights[k] grams[k]`` (q, q) of per-triangle matrices ``grams`` (t, q, q)."""
    q = grams.shape[1]
    return np.dot(weights[None], grams.reshape(-1, q * q)).reshape(q, q)
