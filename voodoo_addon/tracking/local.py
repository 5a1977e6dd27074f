"""What the tracker carries besides the parameters: node offsets, a crease, the look.

The modal fit gives a frame's parameters (the similarity and the named modes). Three more
things link one frame to the next, and :class:`LocalStage` holds them:

- the **node offsets** of the local stage (:mod:`.refine`), for what the modes cannot bend,
  kept only when they explain the frame clearly better;
- the **crease** being followed (:mod:`.creases`), tried when even the offsets leave much
  unexplained, and forgotten when the doll is explained well again;
- the **appearance** the next frame is compared with: the template mixed with this frame's
  look by how far its fit fell short (:meth:`LocalStage.adapt`).
"""

from __future__ import annotations

import numpy as np

from . import kernels
from .refine import HOLD_POWER

#: No local stage in a frame where the doll moved more than this (pixels): such a frame is
#: smeared by motion blur, which the nodes would bend to fit.
REFINE_MOTION = 12.0
#: The local stage's offsets are kept only when they raise the confidence by this much:
#: small gains are mostly the nodes bending to fit noise or motion blur.
REFINE_GAIN = 0.05
#: A part *just back* in view (``HiddenPart.returning``) is still opening, at angles the
#: modes cannot bend to: there, when the modal fit explains the doll at least
#: :data:`OPENING_ABOVE`, the offsets are kept when they gain :data:`OPENING_GAIN`, and held
#: with :data:`OPENING_HOLD_POWER` instead of the usual power (see ``refine.hold``). On
#: ``samples/folds/tail_turn`` a few frames after its tail came back (frames 59-63), offsets
#: started from the renderer's nodes stayed 0.6-1.2 px from them at a higher confidence
#: than the local stage reached from the last frame's (1.2-2.1 px, gaining 0.02-0.05 on the
#: modes alone): the comparison was right, the offsets were held too firmly to get there.
#: The bar on the modal fit keeps the looser offsets from a doll that came back in the
#: wrong place, which they would hold there (BENCHMARKS.md, *A part just back held less
#: firmly while it opens*).
OPENING_ABOVE = 0.7
OPENING_GAIN = 0.03
OPENING_HOLD_POWER = 0.5
#: The part out of view is shown pressed towards its edge (``CreaseSearch.pressed``) when
#: that explains the doll at least this much better than the shape the fit left it in.
PRESS_GAIN = 0.02
#: A quality is at most 1, so above this the offsets could never gain :data:`REFINE_GAIN`:
#: the local stage is not run (a frame that fits this well is common on clean footage).
HOPELESS_ABOVE = 1.0 - REFINE_GAIN
#: When the fit (with the local stage) explains the doll less well than this, creases
#: through it are tried (see :mod:`.creases`).
CREASE_BELOW = 0.6
#: A crease search that found nothing is not made again until the fit is worse by this.
CREASE_DROP = 0.1
#: The template's least share in the appearance a frame is compared with (see
#: :meth:`LocalStage.adapt`): however far the surface's look has drifted, the first frame
#: keeps this much say, so that errors cannot pile up unchecked.
MIN_ANCHOR = 0.05


class LocalStage:
    """The offsets, crease and adapted appearance of one tracked doll.

    Parameters
    ----------
    fitter : CoarseToFineFitter
        Runs the local stage and the crease search, and holds the crease's line.
    layout : ParamLayout
    options : TrackerOptions
    """

    def __init__(self, fitter, layout, options):
        self.fitter = fitter
        self.layout = layout
        self.options = options
        self.reset()

    def reset(self) -> None:
        #: (m, 2) node offsets in the blob's rest frame, or None.
        self.offsets = None
        #: The offsets of the mesh the frame's result shows: :attr:`offsets`, with the part
        #: out of view pressed towards its edge (see :meth:`show`).
        self.shown = None
        #: (n, 3) float32 appearance the next frame's finest level is compared with, or None
        #: for the blob's template.
        self.template = None
        self._crease_futile = np.inf
        self.fitter.creases.forget()

    def lose(self, offsets) -> None:
        """The doll was lost this frame.

        The offsets go back to what they were before it (``offsets``), the crease is
        forgotten and the next frame is compared with the blob's own template.
        """
        self.offsets = offsets
        self.shown = offsets
        self.template = None
        self.fitter.creases.forget()

    def run(self, fit, state: np.ndarray, opening: bool = False):
        """The local stage (node offsets) when the modal fit leaves much unexplained.

        ``state`` is the last frame's parameters; ``opening``: a part of the doll has just
        come back in view (see :data:`OPENING_ABOVE`). Returns the frame's (Quality, visible
        triangles, the local stage's finest evaluation or None). The offsets carry over to
        the next frame; after a good modal fit they are dropped (but for a crease being
        followed, which the modal fit started from).

        Only a frame the offsets explain gives an evaluation, so only such a frame adapts
        the appearance (:meth:`adapt`). Adapting on the modal fit's comparison too was
        tried: on the fold clips of ``samples/folds`` the mean error went from 2.74 / 0.99 /
        3.65 px to 2.83 / 1.38 / 5.17 px, with 5 frames of the turned tail lost.
        """
        moved = np.linalg.norm(fit.params[:2] - state[:2])
        if (
            fit.confidence >= self.options.refine_below
            or fit.pictures is None
            or moved > REFINE_MOTION
        ):
            self.offsets = self.kept_base(fit.params)  # the crease followed, if any
            return fit.quality, fit.visible, None
        start = np.zeros_like(self.fitter.blob.vertices) if self.offsets is None else self.offsets
        gain, power, hopeless = REFINE_GAIN, HOLD_POWER, HOPELESS_ABOVE
        if opening and fit.confidence >= OPENING_ABOVE:
            gain, power, hopeless = OPENING_GAIN, OPENING_HOLD_POWER, 1.0 - OPENING_GAIN
        out, needed = None, fit.confidence + gain
        if fit.confidence < hopeless:
            out = self.fitter.refine(fit, start, self.template, needed, power)
        if out is None or out[1].value < needed:
            self.offsets = self.kept_base(fit.params)
            quality, visible, ev = fit.quality, fit.visible, None
        else:
            self.offsets, quality, ev = out
            visible = ev.triangle_weight > 0
        creases = self.fitter.creases
        if quality.value >= CREASE_BELOW:
            creases.forget()
            self._crease_futile = np.inf
            return quality, visible, ev
        if creases.line is None and quality.value >= self._crease_futile:
            return quality, visible, ev
        base = start if self.offsets is None else self.offsets
        needed = quality.value + REFINE_GAIN
        found = self.fitter.crease(fit, base, self.template, needed)
        if found is None or found[1].value < needed:
            # No crease helps: none is looked for again until the fit gets worse.
            self._crease_futile = quality.value - CREASE_DROP
            creases.forget()
            return quality, visible, ev
        self.offsets, quality, ev, creases.line = found
        return quality, ev.triangle_weight > 0, ev

    def show(self, fit, quality, away) -> None:
        """The mesh this frame's result shows (:attr:`shown`), once the doll was found.

        ``quality``: the frame's, with the local stage; ``away`` (t,) bool or None: the part
        out of view in the last frame. Held in the shape it was last seen in, a part turned
        away or folded under hangs over whatever lies beyond it, and comes back in view far
        from where it shows; it is shown pressed towards its edge with the part in view
        when that explains the doll :data:`PRESS_GAIN` better (``CreaseSearch.pressed``).
        Only the mesh shown: the fits, the parameters and the offsets carried to the next
        frame are left as they are. Carried on, the pressed part pulled the part in view
        after it through the offsets' smoothness, and parts came back later
        (BENCHMARKS.md, *The part out of view shown pressed towards its edge*).
        """
        self.shown = self.offsets
        if away is None or fit.pictures is None or quality.value > 1.0 - PRESS_GAIN:
            return  # (a value is at most 1: no press could be shown)
        base = np.zeros_like(self.fitter.blob.vertices) if self.offsets is None else self.offsets
        found = self.fitter.creases.pressed(fit.params, fit.pictures, base, away)
        if found is not None and found[1] >= quality.value + PRESS_GAIN:
            self.shown = found[0]

    def kept_base(self, a: np.ndarray) -> np.ndarray | None:
        """The base offsets the fit started from, or None when there were none.

        Pulled back as far as needed for no triangle to fold on the fitted modes.
        """
        base = self.fitter.base_offsets
        if base is None:
            return None
        return self.fitter.guard.shape_step(self.fitter.refiner.bare(a), base) * base

    def adapt(self, ev, a, confidence: float) -> None:
        """The appearance to compare the next frame with (see :data:`MIN_ANCHOR`).

        The finest level's pixels as this frame showed them (its global lighting undone),
        mixed with the template by how far this frame's fit fell short of it; pixels that
        were not seen keep the template.
        """
        below = self.options.adapt_below
        anchor = 1.0 if below <= 0 else min(1.0, confidence / below)
        level = self.fitter.levels[0].level
        if anchor >= 1.0 or ev is None:
            self.template = None
            return
        anchor = max(anchor, MIN_ANCHOR)
        c, b = self.layout.channel_gain_offset(a)  # none: 1 and 0
        t0 = level.template
        mixed = np.empty_like(t0)
        samples = np.ascontiguousarray(ev.samples, np.float32)
        kernels.mix_look(t0, samples, ev.use, np.array(c, float), np.array(b, float), anchor, mixed)
        self.template = mixed
