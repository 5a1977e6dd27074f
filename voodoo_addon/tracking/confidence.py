"""How well a registration fits: the per-frame quality.

The quality is a *local* correlation: template and warped frame are correlated triangle by
triangle and channel by channel (each with its own mean and contrast, so shading that varies
across the surface does not count), and the correlations are averaged with the template's
texture as weight (a flat triangle says nothing about alignment). A mesh that sits a few
pixels off its texture decorrelates every textured triangle, whatever the lighting; a mesh
in the right place keeps them high even when part of the blob is covered, as long as enough
of it is seen.

Correlating each channel on its own is blind to colour: a pattern that repeats (a grid
painted in coloured squares) correlates as well one square off. So the correlation is
multiplied by a *colour agreement*: how well the triangles' mean colours (their chroma,
after the global white balance the fit found is undone) match the template's.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import kernels
from .decomposition import Evaluation
from .level import Level
from .params import ParamLayout
from .warp import padded, remap_points

#: Pixels the quality is computed on (an even subsample of the level's).
QUALITY_SAMPLES = 1000
#: A triangle-channel needs this many pixels for its correlation to count.
MIN_PIXELS = 6
#: Below this fraction of the textured blob in view (on the picture, not turned away, not
#: covered), the quality falls in proportion...
FULL_VIEW = 0.6
#: ...and below this fraction it is 0: too little is in view to register the doll (the
#: tracker calls it lost). Less than ``evaluation.MIN_IN_VIEW`` (a third), so that a doll
#: a third of which is in view is still followed.
LEAST_VIEW = 0.2
#: A triangle correlating below this with the template fits poorly (``Quality.poor``).
POOR_CORRELATION = 0.5


@dataclass(frozen=True)
class Quality:
    """One frame's quality.

    Attributes
    ----------
    value : float
        In [0, 1]: texture-weighted mean local correlation of the triangles on the picture
        and not turned away (covered ones included), times the colour agreement and the
        view factor. How well the fit explains the whole doll: what the tracker weighs its
        starts and its local stage by.
    correlation : float
        The mean local correlation alone, in [-1, 1].
    seen : float
        Fraction of the textured blob compared (on the picture, not turned away).
    colour : float
        The colour agreement, in [0, 1].
    in_view : float
        In [0, 1]: the same for the part in view only -- the triangles the fit kept, not
        those it found covered, folded under or turned away -- with the view factor of
        ``share``, and 0 below :data:`LEAST_VIEW`. The frame's confidence.
    share : float
        Fraction of the textured blob in view.
    poor : (t,) bool or None
        Textured triangles in view that do not correlate with the template (below
        :data:`POOR_CORRELATION`): covered, or the fit is off there.
    poor_share : float
        Their fraction of the textured blob.
    left_out_correlation : float
        The texture-weighted mean local correlation of the triangles compared but not kept
        (the fit left them out as covered); NaN when there are none.
    """

    value: float
    correlation: float
    seen: float
    colour: float
    in_view: float = 0.0
    share: float = 0.0
    poor: np.ndarray | None = field(default=None, compare=False, repr=False)
    poor_share: float = 0.0
    left_out_correlation: float = float("nan")

    @property
    def matched(self) -> float:
        """How well the part in view matches: ``in_view`` without the view factor.

        0 below :data:`LEAST_VIEW`. The tracker decides that the doll is lost on this, not
        on ``in_view``: a part hidden lowers the confidence, but never loses the doll while
        what is in view matches.
        """
        if self.share < LEAST_VIEW:
            return 0.0
        return self.in_view / min(1.0, self.share / FULL_VIEW)


class QualityMeter:
    """Measures :class:`Quality` on the evaluations of one level.

    Parameters
    ----------
    level : Level
        Usually the finest.
    """

    def __init__(self, level: Level, layout: ParamLayout):
        self.layout = layout
        n = len(level)
        self.step = max(1, n // QUALITY_SAMPLES)
        self.n_tri = level.n_triangles
        self._triangle = level.triangle
        tri = level.triangle[:: self.step]
        t = level.plain_template[:: self.step].astype(np.float64)  # (n', 3)
        self.channels = t.shape[1]
        self.key = (tri[:, None] * self.channels + np.arange(self.channels)).ravel()
        self.t = t.ravel()
        self.size = self.n_tri * self.channels
        ones = np.ones_like(self.t)
        count, mean, var = self._stats(ones, self.t)
        ok = count >= MIN_PIXELS
        # Texture weight of each triangle-channel: its pixels times its contrast, the
        # contrast capped at the median so that a few high-contrast spots do not rule.
        cap = float(np.median(var[ok])) if ok.any() else 0.0
        self.weight = np.where(ok, count * np.minimum(var, cap), 0.0)
        self.total = float(self.weight.sum())
        # The chroma of each triangle: its mean colour minus its grey, (t, c).
        self._chroma_t = _chroma(mean.reshape(self.n_tri, self.channels))

    @property
    def triangle_share(self) -> np.ndarray:
        """(t,) float64: each triangle's share of the textured blob (summing to 1, or 0)."""
        w = self.weight.reshape(self.n_tri, self.channels).sum(axis=1)
        return w / self.total if self.total > 0 else w

    def _stats(self, w, x):
        count = np.bincount(self.key, weights=w, minlength=self.size)
        s = np.bincount(self.key, weights=w * x, minlength=self.size)
        ss = np.bincount(self.key, weights=w * x * x, minlength=self.size)
        mean = s / np.maximum(count, 1.0)
        return count, mean, np.maximum(ss / np.maximum(count, 1.0) - mean * mean, 0.0)

    def __call__(self, ev: Evaluation, a: np.ndarray, plain: np.ndarray | None = None) -> Quality:
        """The quality of the evaluation ``ev``, made at parameters ``a``.

        ``plain``: the picture ``ev`` sampled, as read, when the fit compared it with its
        detail strengthened (:func:`.pictures.emphasise`); the quality is measured on the
        colours as they are, so that it means the same with or without.
        """
        # Every triangle on the picture and not turned away is judged for ``value`` -- the
        # ones the fit left out as covered too: a fit that explains half of the doll and
        # calls the other half covered has not shown that it is right. ``in_view`` judges
        # the part the fit kept: a fold or a hand hiding part of the doll lowers it only
        # through the view factor, and calling the rest covered needs the part in view to
        # fit well first (see ``evaluation._coverable``).
        compared = ev.valid if ev.hidden is None else ev.valid & ~ev.hidden[self._triangle]
        if plain is None:
            samples = ev.samples[:: self.step]
        else:
            at = ev.positions[:, : len(compared) : self.step]
            pos = np.zeros((2, padded(at.shape[1])), np.float32)
            pos[:, : at.shape[1]] = at
            samples = remap_points(plain, pos)[: at.shape[1]]
        return self.measure(samples, compared[:: self.step], a, ev.triangle_weight)

    def measure(self, samples, compared, a, kept=None) -> Quality:
        """The quality from the frame's colours at the meter's own pixels.

        ``samples`` (n', 3) and ``compared`` (n',) bool: every :attr:`step`-th pixel of the
        level (on the picture and not turned away). ``kept`` (t,): the triangles the fit
        kept (``Evaluation.triangle_weight``); without it ``in_view`` is ``value``.
        """
        s = samples.astype(np.float64)
        lay = self.layout
        if lay.photometric != "none":
            b, log_c = a[lay.brightness], a[lay.contrast]
            if np.abs(log_c).max() > 1e-3 or np.abs(b).max() > 1e-3:
                s = (s - b) / np.exp(log_c)
        t = self.t
        sums = np.empty((6, self.size))
        use = np.repeat(compared.astype(np.float64), self.channels)
        kernels.channel_sums(self.key, t, s.ravel(), use, sums)
        count, t_sum, t_sq, s_sum, s_sq, cross = sums
        mt = t_sum / np.maximum(count, 1.0)
        vt = np.maximum(t_sq / np.maximum(count, 1.0) - mt * mt, 0.0)
        ms = s_sum / np.maximum(count, 1.0)
        vs = np.maximum(s_sq / np.maximum(count, 1.0) - ms * ms, 0.0)
        cov = cross / np.maximum(count, 1.0) - mt * ms
        den = np.sqrt(vt * vs)
        ok = (count >= MIN_PIXELS) & (den > 1e-9) & (self.weight > 0)
        ncc = np.full(self.size, np.nan)
        ncc[ok] = np.clip(cov[ok] / den[ok], -1.0, 1.0)
        w = np.where(ok, self.weight, 0.0)
        seen = float(w.sum()) / self.total if self.total > 0 else 0.0
        if not ok.any() or self.total <= 0:
            return Quality(0.0, 0.0, seen, 1.0)
        weighed = w[ok] * ncc[ok]
        corr = float(weighed.sum() / w[ok].sum())
        by_tri = np.zeros(self.size)  # the triangle-channels that are not ok weigh nothing
        by_tri[ok] = weighed
        by_tri = by_tri.reshape(self.n_tri, self.channels).sum(axis=1)
        tri_w = w.reshape(self.n_tri, self.channels).sum(axis=1)
        poor = (tri_w > 0) & (by_tri < POOR_CORRELATION * tri_w)
        poor_share = float(tri_w[poor].sum()) / self.total
        colour = self._colour_agreement(ms.reshape(self.n_tri, self.channels), count)
        value = max(corr, 0.0) * colour * min(1.0, seen / FULL_VIEW)
        kept = None if kept is None else kept > 0
        if kept is None or kept.all():
            return Quality(float(value), corr, seen, colour, float(value), seen, poor, poor_share)
        w = w * np.repeat(kept, self.channels)
        share = float(w.sum()) / self.total
        if share < LEAST_VIEW:
            return Quality(float(value), corr, seen, colour, 0.0, share, poor, poor_share)
        corr_kept = float((w[ok] * ncc[ok]).sum() / w[ok].sum())
        in_view = max(corr_kept, 0.0) * colour * min(1.0, share / FULL_VIEW)
        out_w = float(tri_w.sum() - w.sum())  # the triangles compared but not kept
        out = (weighed.sum() - (w[ok] * ncc[ok]).sum()) / out_w if out_w > 0 else np.nan
        return Quality(
            float(value), corr, seen, colour, float(in_view), share, poor, poor_share, float(out)
        )

    def _colour_agreement(self, frame_mean: np.ndarray, count: np.ndarray) -> float:
        """In [0, 1]: 1 when every coloured triangle has the template's chroma.

        The cosine of template and frame chroma per triangle, weighted by how coloured the
        template is there (grey triangles say nothing), mapped from [-1, 1] to [0, 1].
        """
        ct = self._chroma_t
        cs = frame_mean - frame_mean.sum(axis=1)[:, None] / self.channels
        seen = count.reshape(self.n_tri, self.channels)[:, 0]
        strength = (ct * ct).sum(axis=1)
        w = seen * strength
        norm = np.sqrt(strength * (cs * cs).sum(axis=1))
        ok = (w > 0) & (norm > 1e-12)
        if not ok.any() or w[ok].sum() <= 0:
            return 1.0
        cos = (ct[ok] * cs[ok]).sum(axis=1) / norm[ok]
        agree = float((w[ok] * cos).sum() / w[ok].sum())
        return min(max(0.5 * (1.0 + agree), 0.0), 1.0)


def _chroma(colours: np.ndarray) -> np.ndarray:
    """Colours (t, c) minus their grey (mean over the channels)."""
    return colours - colours.mean(axis=1, keepdims=True)
