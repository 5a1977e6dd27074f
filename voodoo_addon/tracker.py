"""The active-blob tracker: robust difference decomposition, coarse to fine (paper §5).

``Tracker(blob).track(frame)`` registers the blob's template to one frame and returns a
:class:`TrackResult`. Everything that depends only on the template (the difference bases, their
regularised pseudo-inverses, block Gram matrices) is computed once per pyramid level and set
of free parameters; a tracking iteration is one warp, one Eq. 16 transform and one small
matrix-vector product.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .blob import ActiveBlob
from .errors import VoodooError
from .images import blur
from .levels import LazyPyramid, Level, Solver
from .norms import LorentzianNorm, RobustNorm
from .params import ParamLayout, compose, node_positions
from .reacquire import FeatureMatcher
from .residuals import Evaluation, confidence, evaluate, solve
from .warp import CpuWarp, WarpBackend

#: Coarse grid search around each seed pose, coarsest-level pixels.
SEARCH_RADIUS = 6
SEARCH_STEP = 3
#: An update that changes a lighting term by more than this is not converged.
PHOTOMETRIC_TOLERANCE = 2e-3


@dataclass(frozen=True)
class TrackerOptions:
    """Tracker settings; the defaults work without tuning.

    Attributes
    ----------
    sigma : float
        Scale of the Lorentzian norm (Eq. 9), image units.
    gamma : float
        Weight of the modal-stiffness prior (Eq. 10) against the mean robust error.
    photometric : {"channel", "global", "none"}
        Brightness/contrast model (Eq. 4). Per channel by default: webcams re-balance white
        and lamps are coloured, so the three channels drift independently.
    max_levels : int
        Pyramid levels at most (coarse to fine).
    min_level_pixels : int
        A coarser level is only used while its blob keeps this many pixels.
    max_iterations : int
        Iteration cap per level and frame.
    tolerance : float
        Stop when the robust residual improves by less than this fraction.
    step_tolerance : float
        ... or when an update moves the nodes by less than this many pixels RMS (finest
        level; coarser levels stop at a quarter of their pixel).
    fine_capture : float
        A frame starts at the finest level and drops to the coarse levels only when the
        first update there moves the nodes by more than this many pixels RMS.
    pixel_budget : int or None
        Template pixels used at full resolution at most (an even subsample beyond).
    block_grid : int
        Blocks per side for occlusion rejection.
    outlier_factor : float
        A block whose mean robust error exceeds this many times the median block's is
        treated as occluded for the iteration.
    lost_below : float
        A frame whose confidence falls below this is lost.
    reacquire_above : float
        While lost, a frame must reach this confidence to count as found again.
    predict : bool
        Extrapolate the motion of the last two frames to start each frame.
    features : bool
        Re-acquire a lost blob by matching SIFT features against the template.
    """

    sigma: float = 0.15
    gamma: float = 1e-5
    photometric: str = "channel"
    max_levels: int = 3
    min_level_pixels: int = 300
    max_iterations: int = 8
    tolerance: float = 1e-2
    step_tolerance: float = 0.06
    fine_capture: float = 1.0
    pixel_budget: int | None = 20000
    block_grid: int = 6
    outlier_factor: float = 4.0
    lost_below: float = 0.35
    reacquire_above: float = 0.5
    predict: bool = True
    features: bool = True


@dataclass(frozen=True)
class TrackResult:
    """One frame's registration.

    Attributes
    ----------
    params : (P,) float64
        Parameter vector (see :mod:`voodoo_addon.params`); the last good one when lost.
    nodes : (m, 2) float64
        Mesh nodes in the frame, pixel coordinates.
    confidence : float
        In [0, 1]: template/frame correlation times the visible fraction.
    lost : bool
        True when the blob was not found in this frame (``params`` are then held).
    iterations : int
        Warps evaluated for this frame over all levels.
    residual : float
        Mean robust error per template pixel at the finest level.
    occluded : float
        Fraction of template pixels rejected as occluded or off the frame.
    reacquired : bool
        True on the first good frame after a loss.
    """

    params: np.ndarray
    nodes: np.ndarray
    confidence: float
    lost: bool
    iterations: int
    residual: float
    occluded: float
    reacquired: bool = False
    warnings: tuple = field(default=(), compare=False)


class Tracker:
    """Tracks one active blob through frames.

    Parameters
    ----------
    blob : ActiveBlob
    backend : WarpBackend, optional
        Defaults to :class:`~voodoo_addon.warp.CpuWarp`.
    options : TrackerOptions, optional
    norm : RobustNorm, optional
        Defaults to the Lorentzian of ``options.sigma``.
    frozen : iterable of str
        Parameter names held fixed (e.g. ``{"rotate"}`` to track bending with rotation fixed).
    """

    def __init__(
        self,
        blob: ActiveBlob,
        backend: WarpBackend | None = None,
        options: TrackerOptions | None = None,
        norm: RobustNorm | None = None,
        frozen=(),
    ):
        self.blob = blob
        self.options = opt = options or TrackerOptions()
        self.backend = backend or CpuWarp()
        self.norm = norm or LorentzianNorm(opt.sigma)
        self.layout = ParamLayout(tuple(str(s) for s in blob.labels), opt.photometric)
        self.levels = [Level(blob, 0, self.layout, opt.pixel_budget, opt.block_grid)]
        while len(self.levels) < opt.max_levels:
            # Coarse levels only need to bring the fine level into range: a quarter of the
            # budget per level down keeps them cheap on big blobs.
            budget = opt.pixel_budget and opt.pixel_budget // 4 ** len(self.levels)
            nxt = Level(blob, len(self.levels), self.layout, budget, opt.block_grid)
            if len(nxt) < opt.min_level_pixels:
                break
            self.levels.append(nxt)
        self.frame_size = tuple(int(v) for v in blob.frame_size)
        self._floor = 3.0 * float(self.norm.rho(np.array([self.norm.sigma / 2]))[0])
        self._matcher = FeatureMatcher(blob) if opt.features else None
        lay = self.layout
        self._photometric = np.r_[lay.brightness, lay.contrast].astype(np.int64)
        self.set_frozen(frozen)
        self.reset()

    # ------------------------------------------------------------------ state

    @property
    def parameter_names(self) -> tuple:
        return self.layout.names

    def set_frozen(self, names) -> None:
        """Hold the named parameters at their current values from now on."""
        idx = set()
        for name in names:
            try:
                idx.add(self.layout.index(name))
            except KeyError as exc:
                raise VoodooError(str(exc.args[0])) from None
        self.frozen = frozenset(idx)
        for level in self.levels:  # precompute the bases now, not on the first frame
            self._solver(level)

    def reset(self, params: np.ndarray | None = None) -> None:
        """Start over from ``params`` (default: the capture pose)."""
        a = self.layout.identity() if params is None else np.asarray(params, dtype=np.float64)
        if a.shape != (self.layout.size,) or not np.isfinite(a).all():
            raise VoodooError("reset() needs a finite parameter vector of the tracker's size.")
        self.state = a.copy()
        self._prev = None
        self.last_good = a.copy()
        self.lost = False
        self._last_residual = None

    def active(self, level: int) -> np.ndarray:
        """Free parameters at a pyramid level.

        The coarsest of several levels estimates the similarity and lighting only (a few
        hundred pixels cannot pin down local bending, and free modes there absorb
        misalignment on weakly textured dolls); intermediate levels add the lowest modes.
        """
        lay = self.layout
        coarsest = level == len(self.levels) - 1 and level > 0
        keep_modes = 0 if coarsest else lay.n_modes >> level
        out = [k for k in range(lay.size) if k not in self.frozen]
        return np.array(
            [k for k in out if not (lay.modes.start + keep_modes <= k < lay.modes.stop)],
            dtype=np.int64,
        )

    def _solver(self, level: Level) -> Solver:
        return level.solver(
            self.backend,
            self.active(level.index),
            self.norm,
            self.options.gamma,
            self.blob.stiffness_penalty,
        )

    def nodes(self, a: np.ndarray) -> np.ndarray:
        """Mesh nodes (m, 2) in frame pixels for parameters ``a``."""
        return node_positions(
            a,
            self.layout,
            self.blob.vertices,
            self.blob.modes[:, : self.layout.n_modes],
            self.blob.centre,
        )

    # ------------------------------------------------------------------ public

    def track(self, frame: np.ndarray) -> TrackResult:
        """Register the blob to one frame.

        Parameters
        ----------
        frame : (H, W, 3) float32
            RGB in [0, 1], the capture frame's size.

        Returns
        -------
        TrackResult
        """
        frame = self._check_frame(frame)
        opt = self.options
        was_lost = self.lost
        start = self.last_good if was_lost else self._predict()
        need = opt.reacquire_above if was_lost else opt.lost_below
        a, conf, info = self._register(frame, start, wide=was_lost)
        warnings = []
        # Before giving up: a wide search from the last good pose, then from features.
        for fallback in (self._wide_start, self._feature_start):
            if conf >= need:
                break
            start2 = fallback(frame, was_lost)
            if start2 is None:
                continue
            a2, c2, i2 = self._register(frame, start2, wide=True)
            i2["iterations"] += info["iterations"]
            if c2 > conf:
                a, conf, info = a2, c2, i2
        if conf >= need:
            self._last_residual = info["residual"]
            self._prev = None if was_lost else self.state.copy()
            self.state = a
            self.last_good = a.copy()
            self.lost = False
            params = a
        else:
            self.lost = True
            self.state = self.last_good.copy()
            self._prev = None
            params = self.last_good.copy()
            warnings.append("The blob is lost: holding its last good pose.")
        return TrackResult(
            params=params.copy(),
            nodes=self.nodes(params),
            confidence=float(conf),
            lost=self.lost,
            iterations=int(info["iterations"]),
            residual=float(info["residual"]),
            occluded=float(info["occluded"]),
            reacquired=bool(was_lost and not self.lost),
            warnings=tuple(warnings),
        )

    # ------------------------------------------------------------------ internals

    def _wide_start(self, frame, was_lost):
        """The last good pose (already searched wide when the blob was lost)."""
        return None if was_lost else self.last_good

    def _feature_start(self, frame, was_lost):
        """A pose from SIFT matches against the template, frozen parameters kept."""
        if self._matcher is None:
            return None
        guess = self._matcher.guess(frame, self.blob.centre, self.last_good)
        if guess is not None:
            frozen = list(self.frozen)
            guess[frozen] = self.last_good[frozen]
        return guess

    def _check_frame(self, frame: np.ndarray) -> np.ndarray:
        frame = np.asarray(frame)
        if frame.ndim != 3 or frame.shape[2] != 3:
            raise VoodooError(f"A frame must be an RGB picture; got shape {frame.shape}.")
        if frame.dtype != np.float32:
            raise VoodooError("Frames must be float32 RGB in [0, 1] (see images.to_float_rgb).")
        h, w = frame.shape[:2]
        if (w, h) != self.frame_size:
            raise VoodooError(
                f"This frame is {w}x{h} but the blob was built on a {self.frame_size[0]}x"
                f"{self.frame_size[1]} frame; use the same camera mode or clip."
            )
        return frame

    def _predict(self) -> np.ndarray:
        a = self.state.copy()
        if self.options.predict and self._prev is not None:
            lay = self.layout
            vel = self.state - self._prev
            a[:4] += vel[:4]
            a[lay.modes] += vel[lay.modes]
        return a

    def _frame_pyramid(self, frame: np.ndarray, poses, wide: bool):
        """Blurred pyramid of the region around the blob at ``poses`` (all of it when wide)."""
        h, w = frame.shape[:2]
        align = 2 ** (len(self.levels) - 1)
        if wide:
            x0 = y0 = 0
            x1, y1 = w, h
        else:
            nodes = np.vstack([self.nodes(a) for a in poses])
            lo, hi = nodes.min(axis=0), nodes.max(axis=0)
            margin = max(0.15 * float((hi - lo).max()), 8.0 * align)
            x0 = int(np.clip(np.floor((lo[0] - margin) / align) * align, 0, w))
            y0 = int(np.clip(np.floor((lo[1] - margin) / align) * align, 0, h))
            x1 = int(np.clip(np.ceil(hi[0] + margin) + 1, 0, w))
            y1 = int(np.clip(np.ceil(hi[1] + margin) + 1, 0, h))
            if x1 - x0 < 8 or y1 - y0 < 8:
                return None
        roi = blur(np.ascontiguousarray(frame[y0:y1, x0:x1]), self.blob.blur_sigma)
        return LazyPyramid(roi), np.array([x0, y0], float)

    def _register(self, frame: np.ndarray, start: np.ndarray, wide: bool):
        """Register from ``start``; returns (params, confidence, info).

        1. Unless searching wide, the finest level is tried first: when the prediction was
           good that is all a frame needs.
        2. Otherwise coarse to fine from the prediction and from the unpredicted pose (the
           motion may have reversed), keeping the better.
        3. If that still fits much worse than the last frame did (or the search is wide), a
           grid search over translations at the coarsest level seeds one more descent.
        """
        info = {"iterations": 0, "residual": np.inf, "occluded": 1.0}
        if not np.isfinite(start).all():
            return start, 0.0, info
        seeds = [start]
        if not wide and not np.allclose(self.state, start):
            seeds.append(self.state)
        pyr = self._frame_pyramid(frame, seeds, wide)
        if pyr is None:
            return start, 0.0, info
        images, origin = pyr
        known = self._last_residual
        limit = 3.0 * known if known is not None and not wide else 0.0
        best = None
        if not wide and len(self.levels) > 1:
            a, last, its = self._iterate(self.levels[0], images[0], start, origin, bail=limit)
            info["iterations"] += its
            if last is not None:
                best = (a, last)
        if best is None:
            for seed in seeds:
                best = self._better(best, self._descend(images, origin, seed, wide, info))
                if best is not None and best[1].residual <= limit:
                    break
            if best is None or best[1].residual > limit:
                top = self.levels[-1]
                seed, its = self._coarse_search(top, images[top.index], origin, seeds)
                info["iterations"] += its
                best = self._better(best, self._descend(images, origin, seed, wide, info))
        if best is None or not self._plausible(best[0]):
            return start, 0.0, info
        a, last = best
        info["residual"] = last.residual
        if last.weighted:
            info["occluded"] = 1.0 - float(np.count_nonzero(last.use)) / len(last.use)
        else:
            info["occluded"] = 0.0
        return a, confidence(self.levels[0], last), info

    @staticmethod
    def _better(a, b):
        """The (params, evaluation) pair with the lower finest-level residual."""
        if a is None:
            return b
        if b is None:
            return a
        return b if b[1].residual < a[1].residual else a

    def _descend(self, images, origin, start, wide: bool, info: dict):
        """Coarse to fine from ``start``; (params, finest evaluation) or None."""
        a, last = start.copy(), None
        for level in reversed(self.levels):
            cap = self.options.max_iterations * (3 if wide and level.index else 1)
            a, last, its = self._iterate(level, images[level.index], a, origin, cap=cap)
            info["iterations"] += its
            if last is None:
                return None
        return a, last

    def _coarse_search(self, level: Level, image, origin, seeds):
        """The best start among seed poses shifted on a grid, by robust residual.

        Evaluated at the coarsest level only (a few hundred pixels), this widens the capture
        range of the pyramid to about :data:`SEARCH_RADIUS` coarse pixels around each seed,
        enough for a reversal of 15 px/frame motion on smooth, photo-like textures.

        Returns (params, evaluations).
        """
        self._solver(level)  # may build a basis (which binds the template) first
        self.backend.bind(image)
        org = (origin * level.scale).astype(np.float32)
        box = np.array([image.shape[1] - 1, image.shape[0] - 1], dtype=np.float32)
        offsets = np.arange(-SEARCH_RADIUS, SEARCH_RADIUS + 1, SEARCH_STEP) / level.scale
        best, best_res, its = seeds[0], np.inf, 0
        for seed in seeds:
            for dy in offsets:
                for dx in offsets:
                    a = seed.copy()
                    a[0] += dx
                    a[1] += dy
                    ev = self._evaluate(level, a, org, box)
                    its += 1
                    if ev is None or np.count_nonzero(ev.use) < 0.5 * len(level):
                        continue
                    if ev.residual < best_res:
                        best, best_res = a, ev.residual
        return best.copy(), its

    def _iterate(self, level: Level, image, a, origin, cap=None, bail=None):
        """Iterate difference decomposition at one level.

        Returns (params, last evaluation or None, evaluations). With ``bail`` (a residual),
        gives up (returning None) when the first update is too large for this level
        (``fine_capture``) while the residual there is above ``bail``: the prediction missed.
        """
        opt = self.options
        solver = self._solver(level)  # may build a basis (which binds the template) first
        self.backend.bind(image)
        org = (origin * level.scale).astype(np.float32)
        box = np.array([image.shape[1] - 1, image.shape[0] - 1], dtype=np.float32)
        tol = opt.step_tolerance if level.index == 0 else 0.25 / level.scale
        act = solver.active
        best_a, best = a, None
        nodes_a = self.nodes(a)
        its = 0
        full = level.index == 0  # level nodes are frame nodes: reuse them
        for _ in range(cap or opt.max_iterations):
            ev = self._evaluate(level, a, org, box, nodes_a if full else None)
            its += 1
            if ev is None:
                break
            if best is not None:
                if ev.residual > best.residual and ev.weighted == best.weighted:
                    break  # got worse: keep the previous estimate
                gain = (best.residual - ev.residual) / max(best.residual, 1e-12)
                best_a, best = a, ev
                if gain < opt.tolerance:
                    break
            else:
                best_a, best = a, ev
            delta_act = solve(solver, level, ev, a[act])
            if not np.isfinite(delta_act).all():
                break
            delta = np.zeros_like(a)
            delta[act] = delta_act
            new = compose(a, delta, self.layout)
            nodes_new = self.nodes(new)
            step = float(np.sqrt(((nodes_new - nodes_a) ** 2).sum(axis=1).mean()))
            if bail is not None and its == 1 and step > opt.fine_capture and ev.residual > bail:
                return a, None, its
            a, nodes_a = new, nodes_new
            lighting = np.abs(delta[self._photometric]).max(initial=0.0)
            if step < tol and lighting < PHOTOMETRIC_TOLERANCE:
                best_a = a
                break
        return best_a, best, its

    def _plausible(self, a: np.ndarray) -> bool:
        if not np.isfinite(a).all():
            return False
        if not -3.0 < a[3] < 3.0:  # scale within 0.05x .. 20x
            return False
        amp = a[self.layout.modes]
        return bool(np.all(np.abs(amp) < 0.6 * self.blob.length))

    def _evaluate(self, level: Level, a, origin, box, nodes=None) -> Evaluation | None:
        return evaluate(
            level,
            a,
            origin,
            box,
            self.backend,
            self.norm,
            self.layout,
            self.options.outlier_factor,
            self._floor,
            nodes,
        )
