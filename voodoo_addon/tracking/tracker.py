"""The active-blob tracker: one blob followed from frame to frame (paper §5).

``Tracker(blob).track(frame)`` returns a :class:`TrackResult`. The tracker owns what links
frames together -- the prediction of the next pose, the decision that the blob is lost, and
finding it again -- and leaves the registration of one frame to
:class:`~voodoo_addon.tracking.fitter.CoarseToFineFitter`.
"""

from __future__ import annotations

from concurrent.futures import Future, ThreadPoolExecutor, wait
from dataclasses import dataclass, field

import numpy as np

from ..blob.model import ActiveBlob
from ..errors import VoodooError
from ..threads import cores, single_blas_thread
from .evaluation import Cover
from .fitter import CoarseToFineFitter, Fit
from .hidden import (
    FOLLOW_TIMES,
    HELD_SLACK,
    OPEN_LEFT_OUT,
    RETURN_GAIN,
    RETURN_SLACK,
    SETTLE_BELOW,
    SETTLE_GAIN,
    SETTLE_GLANCE,
    HiddenPart,
    WayOut,
    at_rest,
    follows_on,
    left_out,
    opens_better,
    returned,
    shows_more,
    still_hidden,
)
from .local import LocalStage
from .norms import LorentzianNorm, RobustNorm
from .options import TrackerOptions
from .params import ParamLayout
from .pictures import checked_frame
from .proposals import FeatureMatcher, MotionProposal
from .warp import CpuWarp, WarpBackend

#: Below this confidence a frame whose points were followed still looks for the template's
#: features (SIFT, the costliest start); between it and ``propose_below`` the points' start
#: is enough.
FEATURES_BELOW = 0.45
#: A feature start that fits no better than the other starts was futile: the next frames
#: look for features again only once their fit is worse by this much, or after
#: :data:`FUTILE_FRAMES` frames. A doll folded or turned away shows too few of its features;
#: when it opens again they show, though the fit of the wrong pose it was left in need not
#: get any worse (``plush_flip`` through a webcam: 20-30 px off at a steady 0.2 for 40
#: frames while the template's features would have found it at 0.9).
FUTILE_DROP = 0.02
FUTILE_FRAMES = 8
#: A search made again (:data:`FUTILE_FRAMES`) is taken only when its fit is surer by this.
AGAIN_GAIN = 0.15
#: A fit below :data:`FEATURES_BELOW` tries the pose the doll was captured in as a start,
#: every this many frames at most (see ``Tracker._from_home``); taken when it is surer by
#: :data:`AGAIN_GAIN`. Every poor frame: +21% iterations over the fold renders and the clip
#: suite, where it was never taken; every fourth: +5.6%.
HOME_EVERY = 4
#: A fit below this is made once more against the blob's own template, not the look adapted
#: on the last frame. A furry patch turned away fits its adapted look at 0.33-0.47 where the
#: look was mixed with the doll's back; against its own template the fit finds the part
#: coming back (``samples/heldout_folds2/plush_nod``: 3.33 -> 1.86 px). At 0.3 (only fits
#: too poor to find a lost doll) the plush stays 12-20 px off for 8 frames; at 0.6 the sixth
#: batch's renders, clean and redrawn, lose 32 frames instead of 18.
OWN_LOOK_BELOW = 0.45
#: A fit below ``reacquire_above`` whose nodes moved more than this many RMS radii from the
#: last frame's is taken for lost (see ``Tracker._found``); as many times this after frames
#: that kept the pose held still. A fit below ``propose_below`` that far off has the last
#: frame's pose judged on the frame as it is, and kept when it fits better (``_track``).
LEAP = 0.15


@dataclass(frozen=True)
class TrackResult:
    """One frame's registration.

    Attributes
    ----------
    params : (P,) float64
        Parameter vector (see :mod:`voodoo_addon.tracking.params`); the last good one when lost.
    nodes : (m, 2) float64
        Mesh nodes in the frame, pixel coordinates.
    confidence : float
        In [0, 1]: the fit's quality on the part of the doll in view -- the local
        correlation of template and frame, texture-weighted, times a factor that falls when
        less than 60% of the textured doll is in view and is 0 under 20% (see
        :mod:`.confidence`, ``Quality.in_view``).
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
    visible : (t,) bool
        Triangles seen in this frame; the others are off the picture, covered, or turned
        away (their shape is the last one seen), or fit poorly next to such a part (see
        :meth:`.hidden.HiddenPart.seen`). All false when lost.
    """

    params: np.ndarray
    nodes: np.ndarray
    confidence: float
    lost: bool
    iterations: int
    residual: float
    occluded: float
    reacquired: bool = False
    visible: np.ndarray | None = field(default=None, compare=False)
    warnings: tuple = field(default=(), compare=False)


class Tracker:
    """Tracks one active blob through frames.

    Parameters
    ----------
    blob : ActiveBlob
    backend : WarpBackend, optional
        Defaults to :class:`~voodoo_addon.tracking.warp.CpuWarp`.
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
        photometric = "channel" if opt.lighting == "local" else opt.lighting
        self.layout = ParamLayout(tuple(str(s) for s in blob.labels), photometric)
        with single_blas_thread():
            self.fitter = CoarseToFineFitter(blob, self.layout, self.backend, self.norm, opt)
        self.frame_size = tuple(int(v) for v in blob.frame_size)
        self._matcher = FeatureMatcher(blob, self.layout) if opt.features else None
        self._motion = MotionProposal(blob, self.layout)
        # Follows points and detects a poor frame's features beside the fit, and makes the
        # template's features ahead of need.
        self._helper = ThreadPoolExecutor(1, thread_name_prefix="voodoo-points")
        if self._matcher is not None:
            self._matcher.prepare(self._helper)
        self._second_core = cores() > 1  # else nothing is detected ahead (_features_ahead)
        share = self.fitter.quality.triangle_share
        self._hidden = HiddenPart(blob.vertices, blob.triangles, share)
        self._way = WayOut(self.fitter.modal_nodes)
        self._nothing = np.zeros(len(blob.triangles), bool)  # leave no triangle out
        self._local = LocalStage(self.fitter, self.layout, opt)
        self.set_frozen(frozen)
        self.reset()

    # ------------------------------------------------------------------ state

    @property
    def parameter_names(self) -> tuple:
        return self.layout.names

    @property
    def levels(self):
        """The blob's pyramid levels (finest first)."""
        return [step.level for step in self.fitter.levels]

    def set_frozen(self, names) -> None:
        """Hold the named parameters at their current values from now on."""
        idx = set()
        for name in names:
            try:
                idx.add(self.layout.index(name))
            except KeyError as exc:
                raise VoodooError(str(exc.args[0])) from None
        self.frozen = frozenset(idx)
        with single_blas_thread():
            self.fitter.set_frozen(idx)  # precompute the bases now, not on the first frame

    def reset(self, params: np.ndarray | None = None, search: bool = False) -> None:
        """Start over from ``params`` (default: the capture pose).

        ``search``: the doll is to be found first, as one that was lost there: the next
        frames search for it around ``params`` (and the rest shape) until one finds it.
        """
        a = self.layout.identity() if params is None else np.asarray(params, dtype=np.float64)
        if a.shape != (self.layout.size,) or not np.isfinite(a).all():
            raise VoodooError("reset() needs a finite parameter vector of the tracker's size.")
        self.state = a.copy()
        self._prev = None
        self.last_good = a.copy()
        self.lost = bool(search)
        self._last_residual = None
        self._previous = None
        self._futile = np.inf
        self._futile_age = 0
        self._home_age = 0  # frames since the capture pose was last tried (see _from_home)
        self._points_likely = False
        self._stale = 0  # frames in a row that kept the pose held still
        self._local.reset()
        self.fitter.set_base(None)
        self._hidden.forget()
        self._way.forget()

    @property
    def appearance(self) -> np.ndarray | None:
        """The look (n, 3) the next frame's finest level is compared with (read only).

        None for the blob's own template (see ``LocalStage.adapt``).
        """
        return self._local.template

    def nodes(self, a: np.ndarray, offsets: np.ndarray | None = None) -> np.ndarray:
        """Mesh nodes (m, 2) in frame pixels for parameters ``a`` (and local offsets)."""
        return self.fitter.nodes(a, offsets)

    # ------------------------------------------------------------------ public

    def track(self, frame: np.ndarray, cover: Cover | None = None) -> TrackResult:
        """Register the blob to one frame.

        Parameters
        ----------
        frame : (H, W, 3) uint8 or float32
            RGB (uint8, or float in [0, 1]), the capture frame's size. Only the region
            around the blob is converted. The tracker keeps a reference to the frame until
            the next call (to follow points from it): do not write into it meanwhile.
        cover : Cover, optional
            Pixels of this frame where something known is in front of the blob (another
            doll, see :class:`~.troupe.Troupe`): the blob's pixels there count as off the
            picture -- neither compared nor counted against the fit.

        Returns
        -------
        TrackResult
        """
        frame = checked_frame(frame, self.frame_size)
        self.fitter.forget()  # a camera may refill the same buffer
        self.fitter.set_cover(cover)
        with single_blas_thread():
            pending = self._follow_ahead(frame)
            try:
                return self._track(frame, pending)
            finally:
                if pending is not None:
                    wait([pending])  # it reads the frames: done before they are handed back
                if self._matcher is not None:
                    self._matcher.drop_ahead(wait=False)  # one still running ends by itself

    def _follow_ahead(self, frame: np.ndarray) -> Future | None:
        """Start following the points since the last frame on a helper thread.

        Only when the last frame's fit was poor enough to ask for them: this one likely
        will too (see :meth:`_motion_start`), and on a second core they are ready when the
        fit is. What they give does not depend on when they are followed.
        """
        if self.lost or not self._points_likely or self._previous is None:
            return None
        return self._helper.submit(self._motion.propose, self._previous, frame, self.state.copy())

    def _track(self, frame: np.ndarray, pending: Future | None = None) -> TrackResult:
        opt = self.options
        was_lost = self.lost
        self._futile_age += 1
        need = opt.reacquire_above if was_lost else opt.lost_below
        # While a crease is followed, the modal fit starts from the creased shape.
        following = not was_lost and self.fitter.creases.line is not None
        self.fitter.set_base(self._local.offsets if following else None)
        if was_lost:
            seeds = [self.last_good, at_rest(self.last_good, self.layout, self.frozen)]
            home = self._capture_pose()
            if not any(np.array_equal(home, seed) for seed in seeds):
                seeds.append(home)
            fit = self._fit(frame, seeds, wide=True)
        else:
            pred = self._predict()
            seeds = [pred] if np.array_equal(pred, self.state) else [pred, self.state]
            fit = self._fit(frame, seeds, wide=False, checked=True)
        its = fit.iterations
        # The look adapted on the last frame carries that frame's misfit: a part the fit
        # trailed (a tail turning away faster than the mesh followed) was mixed in with what
        # lay behind it, and that can pull the next fit off the doll. A poor fit is made
        # once more against the blob's own template (see :data:`OWN_LOOK_BELOW`).
        if not was_lost and fit.confidence < OWN_LOOK_BELOW and self._local.template is not None:
            own = self._fit(frame, seeds, checked=True, adapted=False)
            fit, its = self._better(fit, own, its)
        # The prediction fits badly: where textured points went since the last frame; then,
        # if no points could be followed or the fit is still poor, where the template's
        # features are in this one (the costliest start: a merely mediocre fit, as on a
        # surface the modes cannot quite follow, does not call for it).
        tried_features = False
        self._points_likely = not was_lost and fit.confidence < opt.propose_below
        if self._points_likely:
            self._features_ahead(frame, fit)
            guess = self._motion_start(frame, pending)
            if guess is not None:
                fit, its = self._better(fit, self._fit(frame, [guess]), its)
            below = opt.propose_below if guess is None else FEATURES_BELOW
            again = self._futile <= fit.confidence and self._futile_age >= FUTILE_FRAMES
            if self._searches(fit, below):
                tried_features = True
                fit, its = self._search_features(frame, fit, its, again)
        self._home_age += 1
        if not was_lost and fit.confidence < FEATURES_BELOW and self._home_age >= HOME_EVERY:
            self._home_age = 0
            fit, its = self._from_home(frame, fit, its)
        if not was_lost:
            fit, its = self._hidden_part(frame, fit, its)
        # No fit finds the doll, or the best one ran far off to fit poorly there: the doll
        # may simply not have moved, and the fits ran off from near it (see
        # ``CoarseToFineFitter.hold``).
        held = None
        finds = self._finds(fit)
        ran_off = not was_lost and fit.confidence < opt.propose_below and self._leap(fit) > LEAP
        if ran_off or not finds:
            template = None if was_lost else self._local.template
            held = self.fitter.hold(frame, self.state, template, self._hidden.triangles)
            its += held.iterations
            if not (finds or self._finds(held)) and self._hidden.triangles is None:
                held, its = self._held_in_part(frame, held, template, its)
            if self._finds(held) and (not finds or held.confidence > fit.confidence):
                fit = held
        # Before giving up: a wide search from the last good pose, then from features.
        for fallback in (self._wide_start, self._feature_start):
            if fit.in_view >= need or (tried_features and fallback == self._feature_start):
                break
            start2 = fallback(frame, was_lost)
            if start2 is not None:
                fit, its = self._better(fit, self._fit(frame, [start2], wide=True), its)
        warnings = []
        conf, visible = fit.in_view, fit.visible
        if fit.confidence >= opt.propose_below or fit.in_view < need:
            self._futile = np.inf  # fitting well again, or lost: features may help again
        # The local stage and creases run before the verdict: a doll folding faster than the
        # modes can bend is not lost when they explain it.
        kept = self._local.offsets
        refined = None
        if fit.quality is not None and (not was_lost or fit.in_view >= opt.lost_below):
            refined = self._local.run(fit, self.state, self._hidden.returning)
        if refined is not None and self._found(fit, refined[0]):
            quality, visible, ev = refined
            conf = quality.in_view
            self._local.adapt(ev, fit.params, quality.value)
            self._local.show(fit, quality, self._hidden.triangles)
            a = fit.params
            self._last_residual = fit.residual
            self._prev = None if was_lost else self.state.copy()
            self.state = a
            self.last_good = a.copy()
            self.lost = False
            params = a
            self._hidden.remember(quality.share, visible)
            self._way.record(a, quality.share, quality.in_view)
            visible = self._hidden.seen(visible, quality.poor)
            self._stale = self._stale + 1 if fit is held else 0
        else:
            self._local.lose(kept)
            self.lost = True
            self.state = self.last_good.copy()
            self._prev = None
            params = self.last_good.copy()
            visible = None
            self._hidden.lose()
            self._way.forget()
            self._stale = 0
            warnings.append("The blob is lost: holding its last good pose.")
        self.fitter.set_base(None)
        nodes = self.nodes(params, self._local.shown)
        self._previous = frame
        return TrackResult(
            params=params.copy(),
            nodes=nodes,
            confidence=float(conf),
            lost=self.lost,
            iterations=int(its),
            residual=float(fit.residual),
            occluded=float(fit.occluded),
            reacquired=bool(was_lost and not self.lost),
            visible=self._visible(visible),
            warnings=tuple(warnings),
        )

    # ------------------------------------------------------------------ internals

    def _visible(self, visible) -> np.ndarray:
        if self.lost or visible is None:
            return np.zeros(len(self.blob.triangles), bool)
        return np.array(visible, dtype=bool)

    def _found(self, fit: Fit, refined) -> bool:
        """Whether this frame's fit finds the doll (else it is lost).

        The part in view matching well enough (``lost_below``, judged without the view
        factor: ``Quality.matched``) near where the doll was, or as sure as a re-acquisition
        (``reacquire_above``) anywhere: a fit whose modal mesh lies more than :data:`LEAP`
        RMS radii from the last frame's (or, while lost, the last good one's) must be as
        sure as one that finds a lost doll again. When a fold or a turn leaves every start
        poor, one of them can fit a wrong place just above ``lost_below``, and the track
        would go on from there; a doll lost while folded is found again where it was as soon
        as it fits there. A doll whose part in view matches is not lost for the part that is
        not: ``tail_turn`` through the dim camera (seed 0), its tail held turned away and 42%
        of it in view, was lost for 11 frames at a confidence of 0.14-0.15 with the view
        factor, and is followed through them without it (3.48 -> 3.32 px over the clip).

        After frames that kept the pose held still (no fit found the doll, the pose before
        did, see ``CoarseToFineFitter.hold``), that pose is as many frames behind a doll
        that moved on, and the leap allowed is :data:`LEAP` for each of those frames and
        this one: a sheet folding steadily at a fit of 0.29 was refused frame after frame
        and then lost for 8 frames behind a pose held still for five
        (``samples/heldout_folds3/shirt_fold_print``, redrawn with half a grey level of
        noise). Not while lost: a lost doll is found again only near where it was.
        """
        opt = self.options
        if max(fit.quality.matched, refined.matched) < opt.lost_below:
            return False
        sure = max(fit.in_view, refined.in_view)
        if sure >= opt.reacquire_above:
            return True
        frames = 1 if self.lost else 1 + self._stale
        return self._leap(fit) <= LEAP * frames

    def _leap(self, fit: Fit) -> float:
        """How far the fit's modal mesh lies from the last frame's, in RMS blob radii."""
        moved = self.fitter.modal_nodes(fit.params) - self.fitter.modal_nodes(self.state)
        return float(np.sqrt((moved**2).sum(axis=1).mean())) / self.blob.length

    def _fit(
        self,
        frame,
        seeds,
        wide=False,
        checked=False,
        covered=None,
        adapted=True,
        trial=False,
        worth=None,
        anchor=None,
    ) -> Fit:
        """The fitter's fit; ``adapted``: against the look adapted on the last frame.

        ``anchor``: the shape what no pixel sees is held at (default: the last frame's).
        """
        if self.lost:
            anchor = None
        elif anchor is None:
            anchor = self.state
        template = self._local.template if adapted and not wide else None
        return self.fitter.fit(
            frame,
            seeds,
            wide,
            self._last_residual,
            anchor,
            template,
            checked,
            covered,
            trial,
            worth,
        )

    @staticmethod
    def _better(fit: Fit, other: Fit, its: int):
        """The fit with the higher confidence, and the iterations of both."""
        return (other if other.confidence > fit.confidence else fit), its + other.iterations

    def _hidden_part(self, frame, fit: Fit, its: int):
        """The fits a part out of view asks for, and the way back; (fit, iterations).

        See :mod:`.hidden`: *still hidden*, *shown*, *opening*, *following on*, *settled back*
        and *back*.
        """
        opt = self.options
        covered = self._hidden.covered(fit.quality)
        if fit.in_view < opt.propose_below and covered is not None:
            held = self._fit(frame, [fit.params], covered=covered)
            its += held.iterations
            if still_hidden(fit, held) or self._rescues(held, fit):
                fit = held
        if self.fitter.detail > 0 and self._hidden.away and left_out(fit):
            shown = self._fit(frame, [fit.params], covered=self._nothing, trial=True)
            its += shown.iterations
            if shown.confidence > fit.confidence:
                # Judged as any fit is: what is covered at that pose is left out again.
                again = self.fitter.hold(frame, shown.params, self._local.template)
                its += again.iterations
                if shows_more(fit, again) and not self._rescues(fit, again):
                    fit = again
        if self._hidden.away and left_out(fit, OPEN_LEFT_OUT):
            fit, its = self._opening(frame, fit, its)
        if self._way.open and fit.confidence < opt.propose_below:
            fit, its = self._way_back(frame, fit, its)
        if self._hidden.returning and fit.confidence < opt.refine_below and follows_on(fit):
            fit, its = self._follow_on(frame, fit, its)
        if self._hidden.back and fit.confidence < SETTLE_BELOW:
            fit, its = self._settled(frame, fit, its)
        if self._hidden.triangles is not None and fit.confidence < opt.refine_below:
            fit, its = self._from_rest(frame, fit, its)
        return fit, its

    def _from_rest(self, frame, fit: Fit, its: int):
        """The *back* trial: from the rest shape at the fit's pose; (fit, iterations).

        Not made when less than :data:`~.hidden.RETURN_GAIN` of the doll out of view in the
        last frame lies on the picture now (``HiddenPart.on_picture``): no shape brings what
        is off the picture back into view, and the trial is taken only when it brings that
        much back. On the clip suite's ``occluded_exit``, a street map a third of which
        leaves the frame and comes back, 20 of its 48 trials were made while the part out of
        view lay off the picture, about 5 ms each; none of the 48 was taken, and every track
        of the clip suite and the fold renders is the same without them.
        """
        if self._hidden.on_picture(self.nodes(fit.params), self.frame_size) < RETURN_GAIN:
            return fit, its
        rest = at_rest(fit.params, self.layout, self.frozen)
        back = self._fit(frame, [rest], trial=True, worth=fit.confidence - RETURN_SLACK)
        return self._kept(fit, back, its, returned(fit, back, self._hidden.triangles))

    def _kept(self, fit: Fit, other: Fit, its: int, passes: bool):
        """``other`` where it ``passes`` and does not lose a doll ``fit`` finds; else ``fit``.

        Returns (fit, iterations), ``other``'s counted.
        """
        its += other.iterations
        return (other if passes and not self._rescues(fit, other) else fit), its

    def _opening(self, frame, fit: Fit, its: int):
        """The last frame's pose fitted again, what it leaves out held at rest; (fit, its).

        See :mod:`.hidden`. A trial, from the last frame's pose: from the fit's own, already
        settled, its few iterations at the finest level do not move it.
        """
        rest = at_rest(self.state, self.layout, self.frozen)
        opened = self._fit(frame, [self.state], trial=True, anchor=rest)
        return self._kept(fit, opened, its, opens_better(fit, opened))

    def _follow_on(self, frame, fit: Fit, its: int):
        """The fit made again with what it leaves out held at its own shape; (fit, its).

        See :mod:`.hidden`. What a fit leaves out as covered is held at the last frame's
        shape, and a part coming back is no longer there: after
        ``samples/heldout_folds3/toy_tail_lift`` brought its tail back (frame 64), the fits
        of frames 74-77 left 5-9% of the doll out and stopped 1.1-1.3 px off at 0.73-0.83,
        where the renderer's shape explained the doll at 0.77-0.85, and the track came under
        a pixel only on frame 79. Each fit made again from its own pose holds that part where
        the last one put it, nearer to where the rest of the doll has gone: the track is
        under a pixel from frame 74 (1.29 -> 0.92 px there; NumPy 1.26, while with NumPy 2.3
        the tail comes back another way, its left-out part correlating too little for this
        fit). plush_flip's half is under a pixel 2-3 frames sooner on both lines.
        """
        for _ in range(FOLLOW_TIMES):
            on = self._fit(frame, [fit.params], checked=True, anchor=fit.params)
            kept, its = self._kept(fit, on, its, opens_better(fit, on))
            if kept is fit:
                break
            fit = kept
        return fit, its

    def _settled(self, frame, fit: Fit, its: int):
        """A trial from the rest shape at the fit's pose, once a part that was away is back.

        See :mod:`.hidden`. ``samples/heldout_folds7/shag_tail_turn``'s doll is back at its
        rest shape by frame 88 of the clean render, yet the track stayed 1.8-2.4 px off to
        frame 95: its modal fit 3.7-4.2 px off at about 0.72, the local stage's offsets making
        up the rest (0.86-0.88). Fitted from the rest shape, the doll is 0.22-0.29 px off at
        0.90-0.91. Made only when that shape glances within :data:`~.hidden.SETTLE_GLANCE` of
        the fit: on the real bag clip, whose hands cover a quarter of it now and then, it
        glances 0.15-0.36 below and the trial, made on most frames after the first cover,
        cost 44% more iterations. Taken when :data:`~.hidden.SETTLE_GAIN` surer, or in the
        first frames after the part came back (``HiddenPart.returning``), when it may still
        be opening, :data:`AGAIN_GAIN` surer, as a search made again must be: with the lower
        bar there ``plush_nod`` redrawn (seed 1) settled at rest on frame 60 while its top was
        still opening, 7-10 px off on frames 61-63 where it had been 1.2-2.6. Its coarse
        levels must glance the gain less :data:`~.hidden.RETURN_SLACK` above the fit to go
        on. (fit, iterations).
        """
        rest = at_rest(fit.params, self.layout, self.frozen)
        if np.array_equal(rest, fit.params) or fit.pictures is None:
            return fit, its
        if self.fitter.glance(fit, rest) < fit.confidence - SETTLE_GLANCE:
            return fit, its
        gain = AGAIN_GAIN if self._hidden.returning else SETTLE_GAIN
        return self._tried_again(frame, fit, its, rest, gain)

    def _held_in_part(self, frame, held: Fit, template, its: int):
        """The pose held still, judged on the part in view when the whole doll loses it.

        Its poorly fitting triangles, when they are a large part of the doll on one side of
        it (``HiddenPart.covered``), are left out as a part turned away. (fit, iterations).
        """
        covered = self._hidden.covered(held.quality)
        if covered is None:
            return held, its
        again = self.fitter.hold(frame, self.state, template, covered)
        return (again if self._finds(again) else held), its + again.iterations

    def _way_back(self, frame, fit: Fit, its: int):
        """The pose of the way out that explains the frame best, if it beats ``fit``.

        See :class:`~.hidden.WayOut`. The poses nearest the fit are ranked by
        ``CoarseToFineFitter.glance``, and the best is judged as any fit is
        (``CoarseToFineFitter.hold``): taken when it explains the whole doll better and
        the part in view at most :data:`~.hidden.HELD_SLACK` worse, and better than the last
        frame's pose held still (while the part is still away, the pose of the way out it
        looks most like is often the one it had just before it went: ``plush_nod``'s top,
        turned away, was 2.67 px off on average without that check, 1.86 with, as without
        the way back). Where it is not taken it is fitted (:meth:`_fitted_back`).
        (fit, iterations).
        """
        if fit.pictures is None or fit.visible is None or not np.any(fit.visible):
            return fit, its
        seen = np.unique(self.blob.triangles[np.asarray(fit.visible, bool)])
        here = self.fitter.modal_nodes(fit.params)
        poses = [self._keep_frozen(self._way.path[j].copy()) for j in self._way.nearest(here, seen)]
        looks = [self.fitter.glance(fit, pose) for pose in poses]
        pose = poses[int(np.argmax(looks))]
        if max(looks) <= fit.confidence - RETURN_SLACK:
            return fit, its
        if max(looks) <= fit.confidence - HELD_SLACK:
            return self._fitted_back(frame, fit, pose, its)  # too far below to be held
        back = self.fitter.hold(frame, pose, self._local.template)
        its += back.iterations
        if not shows_more(fit, back) or self._rescues(fit, back):
            return self._fitted_back(frame, fit, pose, its)
        still = self.fitter.hold(frame, self.state, self._local.template)
        its += still.iterations
        return (fit if still.confidence >= back.confidence else back), its

    def _fitted_back(self, frame, fit: Fit, pose, its: int):
        """The way back's pose fitted, when held as it was it does not beat ``fit``.

        A trial from the pose; taken when it brings the part out of view back as the
        fit from the rest shape must (:func:`~.hidden.returned`). The pose held as it was
        is a few pixels off a part coming back: on ``samples/heldout_folds/plush_flip``
        redrawn with half a grey level of noise (seed 3) it explained the doll less well
        than a fit leaving the returning half out (0.42 against 0.32 on the whole doll, but
        0.42 against 0.60 on the part in view), and the half crept back 1.8 px a frame
        from 31 px off; fitted from that pose it is 2.5 px off at 0.65. It is made for a
        pose that glances too far below the fit to be held, too, down to
        :data:`~.hidden.RETURN_SLACK` below, as the rest-shape trial is (plush_flip through
        the webcam: 0.49 against 0.53, and 2.0 px off at 0.74 fitted, where the fit was
        10.8 px off). (fit, iterations).
        """
        fitted = self._fit(frame, [pose], trial=True)
        return self._kept(fit, fitted, its, returned(fit, fitted, self._hidden.triangles))

    def _from_home(self, frame, fit: Fit, its: int):
        """A trial from the capture pose (:meth:`_capture_pose`), when it beats a poor fit.

        A track that slid off a faint doll can stay off it, found at a low confidence, while
        every start lies near where it went: ``samples/heldout_folds6/minky_tail_swing``
        through the dim camera (seed 1) sat 12-13 px off the doll from frame 47 to the end
        at 0.3-0.4, where the doll, its tail swung back, fitted at 0.6-0.7. A doll held up
        to a camera is mostly held near where it was captured: fitted from there, it was
        0.5-0.8 px off at 0.67-0.73 from frame 75 on. A trial (its coarse levels must glance
        at :data:`AGAIN_GAIN` less :data:`~.hidden.RETURN_SLACK` above the fit to go on),
        taken when it is surer by :data:`AGAIN_GAIN`, as a search made again must be.
        (fit, iterations).
        """
        home = self._capture_pose()
        if np.array_equal(home, self.state):
            return fit, its
        return self._tried_again(frame, fit, its, home)

    def _tried_again(self, frame, fit: Fit, its: int, start, gain: float = AGAIN_GAIN):
        """A trial from ``start``, taken when ``gain`` surer than ``fit``.

        Its coarse levels must glance ``gain`` less :data:`~.hidden.RETURN_SLACK` above the
        fit to go on. (fit, iterations).
        """
        worth = fit.confidence + gain - RETURN_SLACK
        trial = self._fit(frame, [start], trial=True, worth=worth)
        return self._kept(fit, trial, its, trial.confidence > fit.confidence + gain)

    def _capture_pose(self) -> np.ndarray:
        """Where and how the doll was captured, at rest: a lost doll is looked for there too.

        The last good pose need not be near the doll at all: a track that slid off a faint
        doll leaves it wherever it ended (a furry doll through a dim camera shrank to a
        third of its size over 15 frames, ``samples/heldout_folds6/minky_tail_swing`` at
        seed 1, and stayed lost while the doll lay flat where it was captured, 55 px
        away). The animator's natural way to get the doll found is to hold it where it was
        captured. The lighting and the frozen parameters are the last good pose's.
        """
        home = self.layout.identity()
        kept = [k for k in range(self.layout.size) if k >= self.layout.modes.stop]
        kept += list(self.frozen)
        home[kept] = self.last_good[kept]
        return home

    def _rescues(self, fit: Fit, other: Fit) -> bool:
        """``fit`` finds the doll in this frame and ``other`` would lose it."""
        return self._finds(fit) and not self._finds(other)

    def _finds(self, fit: Fit) -> bool:
        """:meth:`_found` on the fit's own quality (a fit without one finds nothing)."""
        return fit.quality is not None and self._found(fit, fit.quality)

    def _features_ahead(self, frame, fit: Fit) -> None:
        """Detect the frame's features on the helper thread when the search is likely to ask.

        That is when the fit is already poor enough for it before the points' start is
        fitted (which can only make it better): over the 24 clean fold renders, 132 of the
        133 searches that detected features found them detected ahead, and 16 detections
        were made for nothing. The fit from the points' start runs meanwhile; the search
        finds the features detected (see ``FeatureMatcher.look_ahead``). The same features
        either way: the track does not change. Only with a second core to run it: pinned to
        one, the detection competed with the fit it was to run beside, and
        ``fleece_tail_raise``'s 95th percentile went from 33-34 to 40 ms.
        """
        if self._matcher is None or not self._second_core or not self._searches(fit):
            return
        faint = fit.in_view < self.options.reacquire_above
        self._matcher.look_ahead(self._helper, frame, self._near_box(frame), lost=faint)

    def _searches(self, fit: Fit, below: float = FEATURES_BELOW) -> bool:
        """Whether a fit this poor asks for the template's features (see ``_search_features``).

        Below ``below``, and worse than the last futile search's fit, or :data:`FUTILE_FRAMES`
        frames after it.
        """
        if fit.confidence >= below:
            return False
        return fit.confidence < self._futile or self._futile_age >= FUTILE_FRAMES

    def _search_features(self, frame, fit: Fit, its: int, again: bool):
        """The fit from the template's features, when it beats ``fit``; (fit, iterations).

        Features that find nothing better are futile: they are not looked for again until
        the fit is :data:`FUTILE_DROP` worse, or :data:`FUTILE_FRAMES` frames later
        (``again``). A search made again looks for faint features too when the plain ones
        give no start and the doll fits less surely than a re-acquisition must; its fit is
        taken only when it is surer by :data:`AGAIN_GAIN`, and when it is not, the futile
        mark stays as it was: near a part still turned away, a feature start fitting a hair
        better places that part worse.
        """
        opt = self.options
        self._futile_age = 0
        faint = fit.in_view < opt.reacquire_above
        guess = self._feature_start(frame, faint=faint)
        if guess is None and again and not faint and fit.confidence < opt.reacquire_above:
            guess = self._feature_start(frame, faint=True)
        other = None if guess is None else self._fit(frame, [guess])
        if other is not None:
            its += other.iterations
            if other.confidence > fit.confidence + (AGAIN_GAIN if again else 0.0):
                self._futile = np.inf
                return other, its
        if not again:
            self._futile = fit.confidence - FUTILE_DROP
        return fit, its

    def _keep_frozen(self, guess: np.ndarray) -> np.ndarray:
        frozen = list(self.frozen)
        guess[frozen] = self.state[frozen]
        return guess

    def _motion_start(self, frame, pending: Future | None = None):
        """A pose from the points followed since the previous frame, frozen parameters kept.

        ``pending``: the same, started on the helper thread (see :meth:`_follow_ahead`).
        """
        if self._previous is None:
            return None
        if pending is not None:
            guess = pending.result()
        else:
            guess = self._motion.propose(self._previous, frame, self.state)
        return None if guess is None else self._keep_frozen(guess)

    def _wide_start(self, frame, was_lost):
        """The last good pose (already searched wide when the blob was lost)."""
        return None if was_lost else self.last_good

    def _feature_start(self, frame, was_lost=False, faint=False):
        """A pose from SIFT matches against the template, frozen parameters kept.

        A blob that is not lost is searched for around where it was (twice its size); a
        lost one in the whole frame, by fainter features if its template has too few.
        ``faint``: fainter features for a blob not lost too, whose fit in this frame is less
        sure than a re-acquisition must be. Without them a furry doll found again in the
        wrong place is never corrected: on ``samples/heldout_folds3/toy_tail_lift`` the
        modes drifted to 40 px off and 1.5x too large while the local stage's offsets kept
        the doll found at confidence 0.3, for 30 frames.
        """
        if self._matcher is None:
            return None
        box = None if was_lost else self._near_box(frame)
        guess = self._matcher.guess(frame, self.last_good, box, lost=was_lost or faint)
        if guess is not None:
            frozen = list(self.frozen)
            guess[frozen] = self.last_good[frozen]
        return guess

    def _near_box(self, frame):
        """(x0, y0, x1, y1): where a doll not lost is searched for, about twice its size.

        None when that is under 32 pixels a side on the frame.
        """
        nodes = self.nodes(self.last_good)
        lo, hi = nodes.min(axis=0), nodes.max(axis=0)
        pad = 0.5 * (hi - lo) + 32.0
        h, w = frame.shape[:2]
        x0, y0 = np.maximum(np.floor(lo - pad), 0).astype(int)
        x1, y1 = np.minimum(np.ceil(hi + pad), [w, h]).astype(int)
        return (x0, y0, x1, y1) if x1 - x0 >= 32 and y1 - y0 >= 32 else None

    def _predict(self) -> np.ndarray:
        a = self.state.copy()
        if self.options.predict and self._prev is not None:
            lay = self.layout
            vel = self.state - self._prev
            a[:4] += vel[:4]
            modes = lay.modes
            a[modes] += self.fitter.guard.max_step(a[modes], vel[modes]) * vel[modes]
        return a
