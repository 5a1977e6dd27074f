"""Coarse-to-fine registration of a blob to one frame (paper §5.2, §7).

:class:`CoarseToFineFitter` owns the blob's pyramid levels, one
:class:`~voodoo_addon.tracking.decomposition.DifferenceDecomposition` per level, and the
choice of which parameters each level may move. :meth:`CoarseToFineFitter.fit` registers
from a start pose and returns a :class:`Fit`; it knows nothing of earlier frames (that is the
tracker's business).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..blob.model import ActiveBlob
from .confidence import Quality, QualityMeter
from .creases import CreaseSearch
from .decomposition import DifferenceDecomposition, Evaluation, LevelFit, Stopping
from .folding import FoldGuard
from .level import Level
from .norms import RobustNorm
from .params import ParamLayout, node_positions
from .pictures import FramePictures, base_level, detail_for, doll_fine_contrast
from .refine import HOLD_POWER, LocalRefiner
from .warp import WarpBackend

#: Coarse grid search around each seed pose, coarsest-level pixels.
SEARCH_RADIUS = 6
SEARCH_STEP = 3
#: Iterations at most at the finest level of a *trial* fit (see :meth:`CoarseToFineFitter.fit`).
TRIAL_ITERATIONS = 3


@dataclass(frozen=True)
class Fit:
    """One frame's registration from one start.

    Attributes
    ----------
    params : (P,) float64
    confidence : float
        ``Quality.value``: how well the whole doll is explained; 0 when nothing could be
        fitted.
    iterations : int
        Warps evaluated over all levels.
    residual : float
        Mean robust error per used pixel at the finest level (inf when nothing fitted).
    occluded : float
        Fraction of the finest level's pixels left out of the solve.
    quality : Quality or None
        The finest level's local correlation (None when nothing fitted).
    visible : (t,) bool or None
        The triangles the finest level compared (not off the picture, hidden or occluded).
    pictures : (FramePyramid, origin) or None
        The frame as the fit read it (for the local stage).
    covered : (t,) bool or None
        The triangles the fit was told to leave out as covered (None: it tested).
    """

    params: np.ndarray
    confidence: float
    iterations: int
    residual: float = np.inf
    occluded: float = 1.0
    quality: Quality | None = None
    visible: np.ndarray | None = None
    pictures: tuple | None = None
    covered: np.ndarray | None = None

    @property
    def in_view(self) -> float:
        """The quality of the part in view (see ``Quality.in_view``); 0 when nothing fitted."""
        return 0.0 if self.quality is None else self.quality.in_view


class CoarseToFineFitter:
    """Registers a blob to frames, coarse to fine.

    Parameters
    ----------
    blob : ActiveBlob
    layout : ParamLayout
    backend : WarpBackend
    norm : RobustNorm
    options : TrackerOptions
        Pyramid, budget, prior and stopping settings (see
        :class:`~voodoo_addon.tracking.tracker.TrackerOptions`).
    """

    def __init__(self, blob: ActiveBlob, layout: ParamLayout, backend: WarpBackend, norm, options):
        self.blob = blob
        self.layout = layout
        self.backend = backend
        self.norm: RobustNorm = norm
        self.options = opt = options
        self.stopping = Stopping(
            opt.max_iterations, opt.tolerance, opt.step_tolerance, opt.fine_capture
        )
        patches = opt.lighting == "local"
        self.base = base_level(blob.n_pixels, opt.pixel_budget)
        #: How much the detail of template and frames is strengthened in the comparisons.
        if opt.detail is None:
            detail = detail_for(blob.template, doll_fine_contrast(blob, self.base))
        else:
            detail = opt.detail
        self.detail = detail
        levels = [Level(blob, self.base, layout, opt.pixel_budget, patches, detail)]
        levels[0].finest = True
        while len(levels) < opt.max_levels:
            # Coarse levels only need to bring the fine level into range: a quarter of the
            # budget per level down keeps them cheap on big blobs.
            budget = opt.pixel_budget and opt.pixel_budget // 4 ** len(levels)
            nxt = Level(blob, self.base + len(levels), layout, budget, patches, detail)
            if len(nxt) < opt.min_level_pixels:
                break
            levels.append(nxt)
        floor = 3.0 * float(norm.rho(np.array([norm.sigma / 2]))[0])
        self.guard = FoldGuard(blob.vertices, blob.triangles, blob.modes[:, : layout.n_modes])
        self.levels = [
            DifferenceDecomposition(
                lv,
                layout,
                backend,
                norm,
                opt.gamma,
                blob.mode_stiffness,
                opt.outlier_factor,
                floor,
                self.nodes,
                self.guard,
                opt.pixel_outlier,
            )
            for lv in levels
        ]
        self._base = None
        self._no_offsets = np.zeros_like(blob.vertices)  # read only: the modal mesh
        self.pictures = FramePictures(blob.blur_sigma, self.base, len(self.levels), detail)
        # The coarse levels' fits and grid searches of the frame being fitted (see
        # :meth:`_level_fit`), by what they start from; dropped with the frame's pictures.
        self._coarse: dict = {}
        self.frozen: frozenset = frozenset()
        self._active: dict = {}
        self._anchor = None
        self._template = None
        self._covered = None
        self.quality = QualityMeter(levels[0], layout)
        self.refiner = LocalRefiner(
            self.levels[0], blob, layout, self.guard, norm.sigma, self.nodes, self.quality
        )
        self.creases = CreaseSearch(self.refiner, blob)

    def forget(self) -> None:
        """Drop what was read of the last frame: call it before a new frame.

        A camera may hand over the same buffer with new pixels.
        """
        self.pictures.forget()
        self._coarse = {}

    def set_cover(self, cover) -> None:
        """What covers the blob in the next frames (a ``Cover``, or None: nothing known)."""
        self._coarse = {}
        for step in (*self.levels, self.refiner.sub_step, self.creases.step):
            if step is not None:
                step.cover = cover

    def nodes(self, a: np.ndarray, offsets: np.ndarray | None = None) -> np.ndarray:
        """Mesh nodes (m, 2) in frame pixels for ``a`` and local offsets.

        The offsets default to the base offsets (see :meth:`set_base`).
        """
        return node_positions(
            a,
            self.layout,
            self.blob.vertices,
            self.blob.modes[:, : self.layout.n_modes],
            self.blob.centre,
            self._base if offsets is None else offsets,
        )

    def modal_nodes(self, a: np.ndarray) -> np.ndarray:
        """The modal mesh (m, 2) of ``a`` in frame pixels: no local offsets, no crease."""
        return self.nodes(a, self._no_offsets)

    @property
    def base_offsets(self) -> np.ndarray | None:
        """The offsets the modal fit works on top of (see :meth:`set_base`)."""
        return self._base

    def set_base(self, offsets) -> None:
        """Node offsets (m, 2, rest frame) the modal fit works on top of, or None.

        While a crease is followed its offsets are most of the doll's shape; a fit that
        started from the modes alone would start far off.
        """
        self._base = offsets
        self._coarse = {}
        for step in self.levels:
            lv = step.level
            lv.offsets = None if offsets is None else offsets * lv.scale

    def unfolded(self, a: np.ndarray) -> np.ndarray:
        """``a`` with its modes pulled towards rest as far as needed to fold nothing."""
        modes = self.layout.modes
        if self.guard.valid(a[modes]):
            return a
        out = a.copy()
        out[modes] = self.guard.clamp(a[modes])
        return out

    def set_frozen(self, indices) -> None:
        """Hold these parameter indices; precompute every level's solver for the rest."""
        self.frozen = frozenset(indices)
        self._active = {}
        self._coarse = {}
        for step in self.levels:
            step.solver(self.active(step.index))

    def active(self, level: int) -> np.ndarray:
        """Free parameters at a pyramid level (see :meth:`_free`), cached."""
        if level not in self._active:
            self._active[level] = self._free(level)
        return self._active[level]

    def _free(self, level: int) -> np.ndarray:
        """Free parameters at a pyramid level.

        The coarsest of several levels estimates the similarity and lighting only (a few
        hundred pixels cannot pin down local bending, and free modes there absorb
        misalignment on weakly textured dolls); intermediate levels add the lowest modes.
        """
        lay = self.layout
        rank = level - self.base  # 0: the finest level used
        coarsest = rank == len(self.levels) - 1 and rank > 0
        keep_modes = 0 if coarsest else lay.n_modes >> rank
        out = [k for k in range(lay.size) if k not in self.frozen]
        return np.array(
            [k for k in out if not (lay.modes.start + keep_modes <= k < lay.modes.stop)],
            dtype=np.int64,
        )

    # ------------------------------------------------------------------ frames

    def pyramid(self, frame: np.ndarray, poses, wide: bool, nodes=None):
        """Blurred pyramid of the region around the blob at ``poses`` (all of it when wide).

        ``nodes`` (m, 2): frame nodes to cover besides those of the poses.

        Returns (FramePyramid, origin (2,) float64) or None when the region is empty.
        """
        if wide:
            return self.pictures.whole(frame)
        nodes = np.vstack([self.nodes(a) for a in poses] + ([] if nodes is None else [nodes]))
        return self.pictures.around(frame, nodes)

    # ------------------------------------------------------------------ fitting

    def fit(
        self,
        frame,
        seeds,
        wide: bool,
        known_residual: float | None,
        anchor=None,
        template=None,
        checked: bool = False,
        covered=None,
        trial: bool = False,
        worth: float | None = None,
    ) -> Fit:
        """Register from the best of ``seeds`` (the first is the preferred start).

        ``anchor`` holds the shape of what no pixel sees (see
        :meth:`DifferenceDecomposition.fit`); by default the first seed. ``template`` (n, 3)
        is what the finest level's pixels are compared with instead of the blob's template
        (the coarse levels always use the template). ``checked``: the seeds and the anchor
        are known to fold nothing (the tracker's own states and predictions). ``covered``
        (t,) bool: triangles the finest level leaves out as covered instead of testing.
        ``trial``: a start from a fit's own pose, taken only if it beats that fit (the
        rest shape, when a hidden part may be back; the fit's own pose with nothing left
        out, when a part left out may only be misaligned): one descent, at most
        :data:`TRIAL_ITERATIONS` at the finest level, no search over translations; with
        ``worth``, a trial whose coarse levels end at a pose that :meth:`glance` puts below
        that confidence goes no further (its fit then finds nothing).

        1. Unless searching wide, the finest level is tried first from ``seeds[0]``: when
           the prediction was good that is all a frame needs.
        2. Otherwise coarse to fine from each seed, keeping the best.
        3. If that still fits much worse than ``known_residual`` (or the search is wide), a
           grid search over translations at the coarsest level seeds one more descent.
        """
        start = seeds[0]
        fail = Fit(start, 0.0, 0)
        seeds = [a if checked else self.unfolded(a) for a in seeds if np.isfinite(a).all()]
        if not seeds:
            return fail
        pyr = self.pyramid(frame, seeds, wide)
        if pyr is None:
            return fail
        images, origin = pyr
        if anchor is None:
            anchor = seeds[0]
        self._anchor = anchor if checked else self.unfolded(anchor)
        self._template = template
        self._covered = covered
        limit = 3.0 * known_residual if known_residual is not None and not wide else 0.0
        its = 0
        best = None
        if trial:
            best = self._descend(
                images, origin, seeds[0], wide, fine_cap=TRIAL_ITERATIONS, worth=worth
            )
            its = best.iterations
        elif not wide and len(self.levels) > 1:
            res = self._level_fit(self.levels[0], images, origin, seeds[0], bail=limit)
            its += res.iterations
            if res.evaluation is not None:
                best = res
        if best is None:
            for seed in seeds:
                res = self._descend(images, origin, seed, wide)
                its += res.iterations
                best = _better(best, res)
                if best.evaluation is not None and best.evaluation.residual <= limit:
                    break
            if best.evaluation is None or best.evaluation.residual > limit:
                seed, n = self._coarse_search(images, origin, seeds)
                res = self._descend(images, origin, seed, wide)
                its += n + res.iterations
                best = _better(best, res)
        ev = best.evaluation
        if ev is None or not self._plausible(best.params):
            return Fit(start, 0.0, its)
        return self._judged(best.params, ev, its, pyr, covered)

    def hold(self, frame, a: np.ndarray, template=None, covered=None) -> Fit:
        """The pose ``a`` judged on ``frame`` as it is, without moving it (one comparison).

        What the doll would be if it had not moved since the last frame. When a fold or a
        turn leaves every start poor, the fits can run off to a place that explains the doll
        less well than the pose they started near (a tail turning back: 0.07 where the last
        pose keeps 0.45 of the part in view, ``samples/folds/tail_turn``).
        """
        pyr = self.pyramid(frame, [a], False)
        if pyr is None:
            return Fit(a, 0.0, 0)
        step = self.levels[0]
        org, box = self._bind(step, *pyr)
        ev = step.evaluate(a, org, box, occluded=covered, template=template)
        if ev is None:
            return Fit(a, 0.0, 1)
        return self._judged(a, ev, 1, pyr, covered)

    def _judged(self, a, ev: Evaluation, its: int, pyr, covered) -> Fit:
        """The fit at ``a`` whose finest comparison is ``ev``, with its quality."""
        q = self.quality(ev, a, pyr[0].judged(self.base))
        visible = ev.triangle_weight > 0
        return Fit(a, q.value, its, ev.residual, ev.occluded_share, q, visible, pyr, covered)

    def _bind(self, step: DifferenceDecomposition, images, origin):
        """Bind ``step``'s picture for :meth:`DifferenceDecomposition.evaluate` (org, box)."""
        step.solver(self.active(step.index))  # may build a basis (which binds the template)
        return step.bind(images[step.index], origin)

    def refine(self, fit: Fit, offsets: np.ndarray, template=None, needed=None, power=HOLD_POWER):
        """The local stage from ``offsets`` (m, 2) on a fit's frame (see :mod:`.refine`).

        ``power``: how the hold on the offsets grows with the fit's confidence
        (:func:`.refine.hold`). Returns (offsets, quality, evaluation), or None when nothing
        could be compared (or the offsets cannot reach the confidence ``needed``).
        """
        return self.refiner.run(
            fit.params,
            fit.confidence,
            fit.pictures,
            offsets,
            template,
            fit.covered,
            needed,
            power,
        )

    def glance(self, fit: Fit, a: np.ndarray) -> float:
        """The confidence (``Quality.value``) the pose ``a`` would have on ``fit``'s frame.

        Read on the quality meter's own pixels only (see ``LocalRefiner.value``): the same
        number as :meth:`hold` gives, for a fifth of its time and with no occlusion test,
        so many poses can be ranked and only the best one judged in full.
        """
        return self._glance(fit.pictures, a)

    def _glance(self, pictures, a: np.ndarray) -> float:
        """:meth:`glance` on the frame's pictures ``(images, origin)``."""
        images, origin = pictures
        refiner = self.refiner
        step = refiner.step_
        org, box = step.bind(images[step.index], origin)
        nodes = self.modal_nodes(a) * refiner.level.scale
        return refiner.value(a, org, box, nodes, step.hidden(a), images.judged(step.index))

    def crease(self, fit: Fit, offsets: np.ndarray, template=None, needed=None):
        """Crease offsets from ``offsets`` (m, 2) on a fit's frame (see :mod:`.creases`).

        Returns (offsets, quality, evaluation, line), or None (also when the offsets cannot
        reach the confidence ``needed``).
        """
        return self.creases.search(fit.params, fit.pictures, offsets, template, fit.covered, needed)

    def _level_fit(self, step: DifferenceDecomposition, images, origin, a, cap=None, bail=None):
        """``step``'s fit from ``a`` on the frame's ``images``.

        A coarse level compares with the blob's own template and tests no cover, so its fit
        depends only on the start, the cap, the bail and the anchor: the fits of one frame
        that start alike (the fit made again against the template, a descent from a seed
        the grid search kept) share it instead of iterating again, and it counts no
        iterations the second time.
        """
        finest = step.level.finest
        key = None
        if not finest:
            key = ("fit", step.index, id(images), a.tobytes(), cap, bail, self._anchor.tobytes())
            kept = self._coarse.get(key)
            if kept is not None and kept[0] is images:
                res = kept[1]
                return LevelFit(res.params.copy(), res.evaluation, 0, res.bailed)
        res = step.fit(
            images[step.index],
            a,
            origin,
            self.active(step.index),
            self.stopping,
            cap,
            bail,
            self._anchor,
            self._template if finest else None,
            self._covered if finest else None,
        )
        if key is not None:
            self._coarse[key] = (images, res)  # the pictures kept: their id stays theirs
        return res

    def _descend(self, images, origin, start, wide: bool, fine_cap=None, worth=None) -> LevelFit:
        """Coarse to fine from ``start``; the finest level's fit (``fine_cap``: its cap).

        ``worth``: the confidence the coarse levels' pose must :meth:`glance` at for the
        finest level to be fitted; below it the descent gives up (no evaluation).
        """
        a, its = start.copy(), 0
        for step in reversed(self.levels):
            cap = self.options.max_iterations * (3 if wide and step.index > self.base else 1)
            if step.level.finest:
                if fine_cap is not None:
                    cap = min(cap, fine_cap)
                if worth is not None and self._glance((images, origin), a) < worth:
                    return LevelFit(start, None, its)
            res = self._level_fit(step, images, origin, a, cap=cap)
            its += res.iterations
            if res.evaluation is None:
                return LevelFit(start, None, its)
            a = res.params
        return LevelFit(res.params, res.evaluation, its)

    def _coarse_search(self, images, origin, seeds):
        """The best start among seed poses shifted on a grid, by robust residual.

        Evaluated at the coarsest level only (a few hundred pixels), this widens the capture
        range of the pyramid to about :data:`SEARCH_RADIUS` coarse pixels around each seed,
        enough for a reversal of 15 px/frame motion on smooth, photo-like textures.

        Returns (params, evaluations); a search made before on the frame's ``images`` from
        the same seeds gives its pose again and counts no evaluations.
        """
        key = ("grid", id(images), tuple(seed.tobytes() for seed in seeds))
        kept = self._coarse.get(key)
        if kept is not None and kept[0] is images:
            return kept[1].copy(), 0
        best, its = self._grid_search(images, origin, seeds)
        self._coarse[key] = (images, best)
        return best.copy(), its

    def _grid_search(self, images, origin, seeds):
        """:meth:`_coarse_search` itself."""
        top = self.levels[-1]
        org, box = self._bind(top, images, origin)
        scale = top.level.scale
        offsets = np.arange(-SEARCH_RADIUS, SEARCH_RADIUS + 1, SEARCH_STEP) / scale
        best, best_res, its = seeds[0], np.inf, 0
        for seed in seeds:
            poses = []
            for dy in offsets:
                for dx in offsets:
                    a = seed.copy()
                    a[0] += dx
                    a[1] += dy
                    poses.append(a)
            res = np.nan_to_num(top.residuals(poses, org, box), nan=np.inf)  # NaN: never best
            its += len(poses)
            k = int(np.argmin(res))  # the first of the best, as one by one
            if res[k] < best_res:
                best, best_res = poses[k], res[k]
        return best.copy(), its

    def _plausible(self, a: np.ndarray) -> bool:
        if not np.isfinite(a).all():
            return False
        if not -3.0 < a[3] < 3.0:  # scale within 0.05x .. 20x
            return False
        amp = a[self.layout.modes]
        return bool(np.all(np.abs(amp) < 0.6 * self.blob.length))


def _better(a: LevelFit | None, b: LevelFit) -> LevelFit:
    """The fit with the lower finest-level residual (one that found nothing loses)."""
    if a is None or a.evaluation is None:
        return b
    if b.evaluation is None:
        return a
    return b if b.evaluation.residual < a.evaluation.residual else a
