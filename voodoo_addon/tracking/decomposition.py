"""Robust difference decomposition at one pyramid level (paper §5, Eq. 11-16).

:class:`DifferenceDecomposition` is the per-level algorithm: given a picture, a start and the
parameters left free, it iterates *warp the picture back onto the template, compare, solve
for the update* until the robust error stops improving, and returns a :class:`LevelFit`.
Everything that depends only on the template -- the basis of difference images, its
Eq. 16 transform and regularised pseudo-inverse, per-block Gram matrices -- is computed once
per set of free parameters (:class:`Solver`); an iteration is one warp, one elementwise
transform and one small matrix-vector product.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .level import Level
from .norms import RobustNorm
from .params import ParamLayout, compose
from .warp import WarpBackend

_ONES3 = np.ones(3, dtype=np.float32)
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
    block_gram : (n_blocks, p, p) float64
        ``J_b^T J_b`` of every pixel block.
    penalty : (p, p) float64
        ``gamma' Psi^2 + ridge`` for the weighted solve.
    reg : (p,) float64
        ``gamma' psi_j^2`` (zero for unregularised parameters).
    """

    active: np.ndarray
    update: np.ndarray
    prior: np.ndarray
    jacobian: np.ndarray
    block_gram: np.ndarray
    penalty: np.ndarray
    reg: np.ndarray


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
    gram = bbar.T @ bbar
    ridge = 1e-6 * np.trace(gram) / len(gram)
    lhs = gram + gam * nmat.T @ (psi2[:, None] * nmat) + ridge * np.eye(len(gram))
    inv_lhs = np.linalg.inv(lhs)
    update = nmat @ inv_lhs @ bbar.T
    prior = nmat @ inv_lhs @ (gam * nmat.T * psi2[None, :])
    # Collapsed basis (least-squares slope over the steps) for the weighted solve.
    denom = (nmat**2).sum(axis=1)  # (p,)
    jac = bbar @ nmat.T / denom
    pix_block = np.repeat(level.block, 3)
    block_gram = np.zeros((level.n_blocks, len(active), len(active)))
    for blk in range(level.n_blocks):
        jb = jac[pix_block == blk]
        block_gram[blk] = jb.T @ jb
    jgram = block_gram.sum(axis=0)
    penalty = np.diag(gam * psi2) + 1e-6 * np.trace(jgram) / len(jgram) * np.eye(len(active))
    return Solver(
        active=active,
        update=np.ascontiguousarray(update, dtype=np.float32),
        prior=prior,
        jacobian=np.ascontiguousarray(jac, dtype=np.float32),
        block_gram=block_gram,
        penalty=penalty,
        reg=gam * psi2,
    )


@dataclass
class Evaluation:
    """One evaluation of the warp at one level."""

    samples: np.ndarray  # (n, 3) float32
    dbar: np.ndarray  # (n, 3) float32 robust differences
    valid: np.ndarray  # (n,) bool: inside the picture
    use: np.ndarray  # (n,) bool: taken into the solve (valid, not occluded)
    block_weight: np.ndarray  # (n_blocks,) 0/1
    residual: float
    weighted: bool

    @property
    def occluded(self) -> float:
        """Fraction of the level's pixels left out of the solve."""
        if not self.weighted:
            return 0.0
        return 1.0 - float(np.count_nonzero(self.use)) / len(self.use)


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
        A block whose mean robust error exceeds this many times the median block's is
        left out of the solve (full resolution only).
    floor : float
        Robust error below which a block is never an outlier.
    node_positions : callable
        ``a -> (m, 2)`` nodes in level-0 pixels (to measure the step).
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
    ):
        self.level = level
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

    def evaluate(self, a, org, box, nodes=None) -> Evaluation | None:
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
        )

    def fit(self, image, a, origin, active, stopping: Stopping, cap=None, bail=None) -> LevelFit:
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
        """
        solver = self.solver(active)  # may build a basis (which binds the template) first
        org, box = self.bind(image, origin)
        level = self.level
        tol = stopping.step_tolerance if level.index == 0 else 0.25 / level.scale
        act = solver.active
        best_a, best = a, None
        nodes_a = self._nodes(a)
        its = 0
        full = level.index == 0  # level nodes are frame nodes: reuse them
        for _ in range(cap or stopping.max_iterations):
            ev = self.evaluate(a, org, box, nodes_a if full else None)
            its += 1
            if ev is None:
                break
            if best is not None:
                if ev.residual > best.residual and ev.weighted == best.weighted:
                    break  # got worse: keep the previous estimate
                gain = (best.residual - ev.residual) / max(best.residual, 1e-12)
                best_a, best = a, ev
                if gain < stopping.tolerance:
                    break
            else:
                best_a, best = a, ev
            delta_act = solve(solver, level, ev, a[act])
            if not np.isfinite(delta_act).all():
                break
            delta = np.zeros_like(a)
            delta[act] = delta_act
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


def evaluate(
    level: Level,
    a: np.ndarray,
    origin: np.ndarray,
    box: np.ndarray,
    backend: WarpBackend,
    norm: RobustNorm,
    layout: ParamLayout,
    outlier_factor: float,
    floor: float,
    nodes: np.ndarray | None = None,
) -> Evaluation | None:
    """Warp, sample and compare at ``a``: the robust difference image (Eq. 12, 16).

    Parameters
    ----------
    level : Level
    a : (P,) float64
        Parameters.
    origin : (2,) float32
        Level pixel of the bound picture's top-left corner.
    box : (2,) float32
        Largest valid (x, y) in the bound picture.
    backend, norm, layout
        The tracker's warp backend, norm and parameter layout.
    outlier_factor, floor : float
        A block whose mean robust error exceeds ``outlier_factor * max(median, floor)`` is
        occluded (full resolution only).
    nodes : (m, 2) float64, optional
        ``level.nodes(a)`` when the caller has them.

    Returns
    -------
    Evaluation or None
        None when too little of the blob is on the picture to compare.
    """
    n = len(level)
    if nodes is None:
        nodes = level.nodes(a)
    pos = level.positions(a, nodes)
    pos -= origin[:, None]
    x, y = pos[0, :n], pos[1, :n]
    if x.min() >= 0 and y.min() >= 0 and x.max() <= box[0] and y.max() <= box[1]:
        valid, n_valid = None, n
    else:
        valid = (x >= 0) & (y >= 0) & (x <= box[0]) & (y <= box[1])
        n_valid = int(np.count_nonzero(valid))
        if n_valid < 0.15 * n:
            return None
    samples = backend.sample(level.geometry, nodes - origin, pos)
    c, b = layout.channel_gain_offset(a)
    inv_c = (1.0 / c).astype(np.float32)
    # d = I0 - (S - b) / c, then Eq. 16: dbar = sign(d) sqrt(rho(d)).
    d = np.multiply(samples, inv_c)
    np.subtract(level.template, d, out=d)
    d += (b / c).astype(np.float32)
    rho = norm.rho(d)
    dbar = np.sqrt(rho)
    np.copysign(dbar, d, out=dbar)
    loss = rho @ _ONES3  # per pixel, summed over channels (faster than .sum(axis=1))
    valid_all = valid is None
    if valid_all:
        valid = level.all_valid
    nb = level.n_blocks
    if valid_all:
        r_block = np.bincount(level.block, weights=loss, minlength=nb) / level.block_size
        seen = np.ones(nb, dtype=bool)
    else:
        vcount = np.bincount(level.block, weights=valid, minlength=nb)
        vsum = np.bincount(level.block, weights=loss * valid, minlength=nb)
        seen = vcount >= 0.5 * level.block_size
        r_block = np.where(seen, vsum / np.maximum(vcount, 1.0), 0.0)
    weight = seen.astype(np.float64)
    use = valid
    # Occlusion rejection only at full resolution: on coarse levels a block that is merely
    # misaligned looks occluded, and dropping it loses the texture that would align it.
    if seen.any() and level.index == 0:
        med = float(np.median(r_block[seen]))
        limit = outlier_factor * max(med, floor)
        out = seen & (r_block > limit)
        if out.any() and out.sum() <= 0.5 * seen.sum():
            weight[out] = 0.0
            # Something covers part of the blob: also drop its stray pixels from the
            # blocks that stay (their rows come out of the Gram matrix exactly).
            use = valid & (weight[level.block] > 0) & (loss <= limit)
    if use is valid and not weight.all():
        use = valid & (weight[level.block] > 0)
    weighted = use is not level.all_valid
    if weighted:
        n_use = int(np.count_nonzero(use))
        if n_use == 0:
            return None
        residual = float(loss[use].mean())
    else:
        residual = float(loss.mean())
    return Evaluation(samples, dbar, valid, use, weight, residual, weighted)


def solve(solver: Solver, level: Level, ev: Evaluation, a_act: np.ndarray) -> np.ndarray:
    """Parameter update (active parameters) from one evaluation.

    Unweighted: the precomputed ``N B+`` of Eq. 14-15 with the Eq. 10 prior. Weighted
    (occlusion, blob partly off the picture): the same least squares on the collapsed
    basis restricted to the used pixels, with the Gram matrix assembled from per-block
    Gram matrices minus the rows of the dropped pixels of kept blocks.
    """
    if not ev.weighted:
        return solver.update @ ev.dbar.ravel() - solver.prior @ a_act
    gram = np.tensordot(ev.block_weight, solver.block_gram, axes=1)
    gone = np.nonzero((ev.block_weight[level.block] > 0) & ~ev.use)[0]
    if len(gone):
        rows = (3 * gone[:, None] + np.arange(3)).ravel()
        jg = solver.jacobian[rows].astype(np.float64)
        gram = gram - jg.T @ jg
    rhs = solver.jacobian.T @ (ev.dbar * ev.use[:, None]).ravel()
    rhs = rhs - solver.reg * a_act
    try:
        return np.linalg.solve(gram + solver.penalty, rhs)
    except np.linalg.LinAlgError:
        return np.zeros_like(a_act)
