"""Robust difference decomposition at one pyramid level (paper §5, Eq. 11-16).

:class:`DifferenceDecomposition` is the per-level algorithm: given a picture, a start and the
parameters left free, it iterates *warp the picture back onto the template, compare, solve
for the update* until the robust error stops improving, and returns a :class:`LevelFit`.
Everything that depends only on the template -- the basis of difference images, its
Eq. 16 transform and regularised pseudo-inverse, per-triangle Gram matrices -- is computed once
per set of free parameters (:class:`Solver`); an iteration is one warp, one elementwise
transform and one small matrix-vector product.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .evaluation import Evaluation, evaluate
from .folding import HIDE_AREA, FoldGuard
from .level import Level
from .norms import RobustNorm
from .params import ParamLayout, compose
from .warp import WarpBackend

#: Weight of the pull of hidden triangles back to their rest shape, relative to the pull of
#: their pixels if they were seen (see :func:`solve`).
REOPEN = 0.3
#: An update that changes a lighting term by more than this is not converged.
PHOTOMETRIC_TOLERANCE = 2e-3


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
    jacobian : (3n, p) float32
        Difference basis collapsed per parameter (least-squares slope over the four steps),
        for the weighted solve used when parts of the blob are occluded or off the frame.
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
        jacobian=np.ascontiguousarray(jac, dtype=np.float32),
        triangle_gram=tri_gram,
        penalty=penalty,
        reg=gam * psi2,
        modal=modal,
        modal_gram=np.ascontiguousarray(tri_gram[:, modal][:, :, modal]),
    )


@dataclass(frozen=True)
class LevelFit:
    """What one level's iterations found.

    Attributes
    ----------
    params : (P,) float64
        The best parameters seen.
    evaluation : Evaluation or None
        Their evaluation; None when the blob could not be compared (off the picture) or the
        iterations gave up (``bailed``).
    iterations : int
        Warps evaluated.
    bailed : bool
        The first update was too large for this level (see :meth:`DifferenceDecomposition.fit`).
    """

    params: np.ndarray
    evaluation: Evaluation | None
    iterations: int
    bailed: bool = False


@dataclass(frozen=True)
class Stopping:
    """When the iterations of one level stop.

    Attributes
    ----------
    max_iterations : int
    tolerance : float
        Relative improvement of the robust error below which the level has converged.
    step_tolerance : float
        Node motion (level-0 pixels RMS) below which the finest level has converged; coarser
        levels stop at a quarter of their own pixel.
    fine_capture : float
        With ``bail``, the first update may move the nodes at most this much (pixels RMS).
    """

    max_iterations: int = 8
    tolerance: float = 1e-2
    step_tolerance: float = 0.06
    fine_capture: float = 1.0


class DifferenceDecomposition:
    """The registration algorithm at one pyramid level.

    Parameters
    ----------
    level : Level
    layout : ParamLayout
    backend : WarpBackend
    norm : RobustNorm
    gamma : float
        Modal-stiffness prior weight (Eq. 10).
    penalties : (k,) float64
        ``psi_j^2`` of each mode.
    outlier_factor : float
        A triangle whose mean robust error exceeds this many times the median triangle's is
        left out of the solve (full resolution only).
    floor : float
        Robust error below which a triangle is never an outlier.
    node_positions : callable
        ``a -> (m, 2)`` nodes in level-0 pixels (to measure the step).
    guard : FoldGuard, optional
        Cuts every update so that no triangle folds (see :mod:`.folding`).
    """

    def __init__(
        self,
        level: Level,
        layout: ParamLayout,
        backend: WarpBackend,
        norm: RobustNorm,
        gamma: float,
        penalties: np.ndarray,
        outlier_factor: float,
        floor: float,
        node_positions,
        guard: FoldGuard | None = None,
    ):
        self.level = level
        self.guard = guard
        self.layout = layout
        self.backend = backend
        self.norm = norm
        self.gamma = float(gamma)
        self.penalties = penalties
        self.outlier_factor = outlier_factor
        self.floor = floor
        self._nodes = node_positions
        self._solvers: dict[tuple, Solver] = {}
        self._photometric = np.r_[layout.brightness, layout.contrast].astype(np.int64)

    @property
    def index(self) -> int:
        return self.level.index

    def solver(self, active) -> Solver:
        """The precomputed solve for ``active`` parameters (cached per set)."""
        active = np.asarray(sorted(active), dtype=np.int64)
        key = tuple(active)
        if key not in self._solvers:
            self._solvers[key] = build_solver(
                self.level, self.backend, active, self.norm, self.gamma, self.penalties
            )
        return self._solvers[key]

    def bind(self, image: np.ndarray, origin: np.ndarray):
        """Make ``image`` (level pixels, top-left at level-0 pixel ``origin``) the target.

        Returns the (origin, box) pair :meth:`evaluate` takes.
        """
        self.backend.bind(image)
        org = (origin * self.level.scale).astype(np.float32)
        box = np.array([image.shape[1] - 1, image.shape[0] - 1], dtype=np.float32)
        return org, box

    def hidden(self, a: np.ndarray) -> np.ndarray | None:
        """Triangles compressed below :data:`~.folding.HIDE_AREA` at ``a`` (None: none)."""
        if self.guard is None or not self.layout.n_modes:
            return None
        hid = self.guard.ratios(a[self.layout.modes]) < HIDE_AREA
        return hid if hid.any() else None

    def evaluate(self, a, org, box, nodes=None, occluded=None) -> Evaluation | None:
        """Warp, sample and compare at ``a`` on the bound picture."""
        return evaluate(
            self.level,
            a,
            org,
            box,
            self.backend,
            self.norm,
            self.layout,
            self.outlier_factor,
            self.floor,
            nodes,
            self.hidden(a),
            occluded,
        )

    def fit(
        self, image, a, origin, active, stopping: Stopping, cap=None, bail=None, anchor=None
    ) -> LevelFit:
        """Iterate difference decomposition from ``a`` on ``image``.

        Parameters
        ----------
        image : (h, w, 3) float32
            The picture at this level's scale.
        a : (P,) float64
            Start.
        origin : (2,) float64
            Level-0 pixel of the picture's top-left corner.
        active : (p,) int64
            Free parameters.
        stopping : Stopping
        cap : int, optional
            Iterations at most (``stopping.max_iterations`` by default).
        bail : float, optional
            Give up (``bailed``) when the first update moves the nodes by more than
            ``stopping.fine_capture`` while the robust error is above ``bail``: the start
            is too far off for this level.
        anchor : (P,) float64, optional
            The modes that triangles no pixel sees are held at (default ``a``): the last
            frame's shape, not an extrapolation of it.
        """
        solver = self.solver(active)  # may build a basis (which binds the template) first
        org, box = self.bind(image, origin)
        level = self.level
        tol = stopping.step_tolerance if level.finest else 0.25
        tol /= level.scale  # level-0 pixels: a fraction of this level's pixel
        act = solver.active
        best_a, best = a, None
        anchor = (a if anchor is None else anchor)[solver.active]
        nodes_a = self._nodes(a)
        its = 0
        full = level.index == 0  # level nodes are frame nodes: reuse them
        occluded = None  # found once per fit, on the first evaluation close enough to tell
        for _ in range(cap or stopping.max_iterations):
            ev = self.evaluate(a, org, box, nodes_a if full else None, occluded)
            its += 1
            if ev is None:
                break
            if occluded is None:
                occluded = ev.occluded_triangles
            if best is not None:
                if ev.residual > best.residual and ev.weighted == best.weighted:
                    break  # got worse: keep the previous estimate
                gain = (best.residual - ev.residual) / max(best.residual, 1e-12)
                best_a, best = a, ev
                if gain < stopping.tolerance:
                    break
            else:
                best_a, best = a, ev
            delta_act = solve(solver, level, ev, a[act], anchor)
            if not np.isfinite(delta_act).all():
                break
            delta = np.zeros_like(a)
            delta[act] = delta_act
            if self.guard is not None:
                modes = self.layout.modes
                delta[modes] *= self.guard.max_step(a[modes], delta[modes])
            new = compose(a, delta, self.layout)
            nodes_new = self._nodes(new)
            step = float(np.sqrt(((nodes_new - nodes_a) ** 2).sum(axis=1).mean()))
            missed = bail is not None and step > stopping.fine_capture and ev.residual > bail
            if its == 1 and missed:
                return LevelFit(a, None, its, bailed=True)
            a, nodes_a = new, nodes_new
            lighting = np.abs(delta[self._photometric]).max(initial=0.0)
            if step < tol and lighting < PHOTOMETRIC_TOLERANCE:
                best_a = a
                break
        return LevelFit(best_a, best, its)


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
    gram = np.tensordot(ev.triangle_weight, solver.triangle_gram, axes=1)
    gone = np.nonzero((ev.triangle_weight[level.triangle] > 0) & ~ev.use)[0]
    if len(gone):
        rows = (3 * gone[:, None] + np.arange(3)).ravel()
        jg = solver.jacobian[rows].astype(np.float64)
        gram = gram - jg.T @ jg
    rhs = solver.jacobian.T @ (ev.dbar * ev.use[:, None]).ravel()
    rhs = rhs - solver.reg * a_act
    unseen = 1.0 - ev.triangle_weight
    m = solver.modal
    if anchor is not None and m.any() and unseen.any():
        hidden = ev.hidden
        held = unseen if hidden is None else unseen * ~hidden
        hold = np.tensordot(held, solver.modal_gram, axes=1)
        target = hold @ (anchor[m] - a_act[m])
        if hidden is not None:
            reopen = REOPEN * np.tensordot(hidden.astype(np.float64), solver.modal_gram, axes=1)
            hold = hold + reopen
            target = target - reopen @ a_act[m]
        gram[np.ix_(m, m)] += hold
        rhs[m] += target
    try:
        return np.linalg.solve(gram + solver.penalty, rhs)
    except np.linalg.LinAlgError:
        return np.zeros_like(a_act)
