"""Robust difference decomposition at one pyramid level (paper §5, Eq. 11-16).

:class:`DifferenceDecomposition` is the per-level algorithm: given a picture, a start and the
parameters left free, it iterates *warp the picture back onto the template, compare, solve
for the update* until the robust error stops improving, and returns a :class:`LevelFit`.
Everything that depends only on the template is computed once per set of free parameters
(:class:`~.solver.Solver`); an iteration is one warp and comparison
(:func:`~.evaluation.evaluate`), one elementwise transform and one small matrix-vector
product (:func:`~.solver.solve`), with the update cut so that no triangle folds
(:mod:`.folding`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .evaluation import Evaluation, evaluate, residuals
from .folding import HIDE_AREA, FoldGuard
from .level import Level
from .norms import RobustNorm
from .params import ParamLayout, compose
from .solver import Solver, build_solver, solve
from .warp import WarpBackend

#: An update that changes a lighting term by more than this is not converged.
PHOTOMETRIC_TOLERANCE = 2e-3


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
    pixel_limit : float
        Robust error (summed over the channels) above which a single pixel of a kept
        triangle is an outlier (full resolution only; see :func:`~.evaluation.evaluate`).
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
        pixel_limit: float = 0.0,
    ):
        self.level = level
        self.pixel_limit = pixel_limit
        self.guard = guard
        self.layout = layout
        self.backend = backend
        self.norm = norm
        self.gamma = float(gamma)
        self.penalties = penalties
        self.outlier_factor = outlier_factor
        self.floor = floor
        self._nodes = node_positions
        #: What is known to cover the blob in the frame being fitted (see ``Cover``).
        self.cover = None
        self._solvers: dict[tuple, Solver] = {}
        self._photometric = np.r_[layout.brightness, layout.contrast].astype(np.int64)

    @property
    def index(self) -> int:
        return self.level.index

    def on(self, level: Level) -> DifferenceDecomposition:
        """The same algorithm, with the same settings, on another raster of this level."""
        return DifferenceDecomposition(
            level,
            self.layout,
            self.backend,
            self.norm,
            self.gamma,
            self.penalties,
            self.outlier_factor,
            self.floor,
            self._nodes,
            self.guard,
            self.pixel_limit,
        )

    def solver(self, active) -> Solver:
        """The precomputed solve for ``active`` parameters (cached per set)."""
        key = active.tobytes() if isinstance(active, np.ndarray) else None
        if key in self._solvers:
            return self._solvers[key]
        active = np.asarray(sorted(active), dtype=np.int64)
        key = active.tobytes()
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

    def evaluate(
        self, a, org, box, nodes=None, occluded=None, template=None, outliers=None
    ) -> Evaluation | None:
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
            template,
            self.cover,
            outliers,
            self.pixel_limit,
        )

    def residuals(self, poses, org, box, least: float = 0.5) -> np.ndarray:
        """The residual of :meth:`evaluate` at each of ``poses`` (K,), to rank them.

        Inf where the evaluation is None or uses fewer than ``least`` of the level's pixels.
        The poses differ in their translation only. A coarse level ranks them all at once
        (:func:`~.evaluation.residuals`, the same numbers); the finest, which tests
        occlusion, one by one.
        """
        if self.level.finest:
            evs = [self.evaluate(a, org, box) for a in poses]
            least *= len(self.level)
            return np.array(
                [np.inf if ev is None or np.count_nonzero(ev.use) < least else ev.residual
                 for ev in evs]
            )  # fmt: skip
        return residuals(
            self.level, poses[0], self.level.translated_nodes(poses), org, box, self.backend,
            self.norm, self.layout, self.hidden(poses[0]), self.cover, None, least,
        )  # fmt: skip

    def fit(
        self,
        image,
        a,
        origin,
        active,
        stopping: Stopping,
        cap=None,
        bail=None,
        anchor=None,
        template=None,
        covered=None,
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
        template : (n, 3) float32, optional
            What the pixels are compared with instead of the level's template.
        covered : (t,) bool, optional
            Triangles to leave out as covered, instead of testing for occlusion.
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
        # The level's nodes are the frame's times its scale, a power of two: the same numbers
        # as ``level.nodes(a)`` (every product and sum scales exactly), for one product.
        scale = level.scale
        # Found once per fit, on the first evaluation close enough to tell (unless given):
        # the occluded triangles and the outlying pixels of the others.
        occluded, outliers = covered, None
        for _ in range(cap or stopping.max_iterations):
            nodes = nodes_a if scale == 1.0 else nodes_a * scale
            ev = self.evaluate(a, org, box, nodes, occluded, template, outliers)
            its += 1
            if ev is None:
                break
            if occluded is None:
                occluded, outliers = ev.occluded_triangles, ev.outliers
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
