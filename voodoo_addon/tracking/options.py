"""The tracker's settings (see :class:`TrackerOptions`)."""

from __future__ import annotations

from dataclasses import dataclass

from ..checks import finite, whole
from ..errors import VoodooError

#: The lighting models :attr:`TrackerOptions.lighting` may name.
LIGHTING = ("local", "channel", "global", "none")
#: Norm scales the tracker takes (images are in [0, 1]; below, 1 / sigma^2 overflows).
SIGMA_RANGE = (1e-4, 10.0)
#: Stiffness weights it takes (beyond, the modes cannot move and the solve is singular).
GAMMA_RANGE = (0.0, 1e6)
#: The most the detail may be strengthened (beyond, the comparison is all noise).
MAX_DETAIL = 20.0


@dataclass(frozen=True)
class TrackerOptions:
    """Tracker settings; the defaults work without tuning.

    Attributes
    ----------
    sigma : float
        Scale of the Lorentzian norm (Eq. 9), image units.
    gamma : float
        Weight of the modal-stiffness prior (Eq. 10) against the mean robust error.
    lighting : {"local", "channel", "global", "none"}
        How lighting changes are absorbed. "local" (default): a grey gain and bias per
        lighting patch, projected out of every comparison (see :mod:`.photometry`), plus the
        paper's brightness and contrast per channel (Eq. 4) for white balance. The others
        use the paper's model alone -- per channel, once for all channels -- or nothing.
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
    outlier_factor : float
        A triangle whose mean robust error exceeds this many times the median triangle's
        is treated as occluded for the iteration.
    pixel_outlier : float
        When above 0, a pixel of the triangles kept whose robust error (Eq. 9, summed over
        the three channels) exceeds this is left out of the solve too, when enough are
        (fingertips over part of a triangle). 2.0 is one channel about 3.6 sigma off, or
        all three about 1.4 sigma. Off (0) by default: at 2.0 a hand pressing on a faintly
        textured doll no longer pushes the mesh off it, but crumpled paper and fast, blurred
        motion are followed less well (BENCHMARKS.md, *Folds and turns*).
    lost_below : float
        A frame is lost when the part of the doll in view matches below this: its
        confidence without the factor for how much of the doll is in view
        (``Quality.matched``), so a doll is never lost because part of it is hidden.
    reacquire_above : float
        While lost, a frame must reach this confidence to count as found again.
    predict : bool
        Extrapolate the motion of the last two frames to start each frame.
    propose_below : float
        When the extrapolated start fits worse than this, textured points followed from the
        previous frame propose another start (see :mod:`.proposals`).
    refine_below : float
        When the modal fit's confidence is below this, the local stage moves the nodes on
        their own (see :mod:`.refine`); 0 turns it off.
    adapt_below : float
        When a frame's confidence is below this, the next frame is compared with a mix of
        the template and this frame's look (the template's share is the confidence over
        this, at least :data:`~.local.MIN_ANCHOR`); 0 turns it off.
    features : bool
        Re-acquire a lost blob by matching SIFT features against the template.
    detail : float or None
        Template and frames are compared with their detail finer than
        :data:`~.pictures.DETAIL_SIGMA` pixels strengthened by this much
        (:func:`~.pictures.emphasise`); 0 compares them as they are. None (default): as
        much as the doll's texture needs (:func:`~.pictures.detail_for`): a faint one
        (plush, fur, felt) is strengthened, a printed one is compared as it is.
    """

    sigma: float = 0.15
    gamma: float = 1e-5
    lighting: str = "local"
    max_levels: int = 3
    min_level_pixels: int = 300
    max_iterations: int = 8
    tolerance: float = 1e-2
    step_tolerance: float = 0.15
    fine_capture: float = 1.0
    pixel_budget: int | None = 20000
    outlier_factor: float = 8.0
    pixel_outlier: float = 0.0
    lost_below: float = 0.15
    reacquire_above: float = 0.3
    predict: bool = True
    propose_below: float = 0.6
    refine_below: float = 0.97
    adapt_below: float = 0.97
    features: bool = True
    detail: float | None = None

    def __post_init__(self):
        """Refuse NaN, infinity and out-of-range settings by name (a VoodooError)."""
        if self.lighting not in LIGHTING:
            raise VoodooError(
                f"Unknown lighting model {self.lighting!r}; use one of {', '.join(LIGHTING)}."
            )
        numbers = {
            "sigma": finite(self.sigma, "the norm's scale (sigma)", *SIGMA_RANGE),
            "gamma": finite(self.gamma, "the stiffness weight (gamma)", *GAMMA_RANGE),
            "max_levels": whole(self.max_levels, "the number of pyramid levels", 1, 16),
            "min_level_pixels": whole(self.min_level_pixels, "the pixels of a coarse level", 0),
            "max_iterations": whole(self.max_iterations, "the iterations per level", 1),
            "tolerance": finite(self.tolerance, "the residual tolerance", 0.0),
            "step_tolerance": finite(self.step_tolerance, "the step tolerance", 0.0),
            "fine_capture": finite(self.fine_capture, "the fine capture distance", 0.0),
            "outlier_factor": finite(self.outlier_factor, "the outlier factor", 0.0, low_open=True),
            "pixel_outlier": finite(self.pixel_outlier, "the pixel outlier limit", 0.0),
        }
        if self.detail is not None:
            numbers["detail"] = finite(self.detail, "the detail emphasis", 0.0, MAX_DETAIL)
        if self.pixel_budget is not None:
            numbers["pixel_budget"] = whole(self.pixel_budget, "the pixel budget", 0)
        for name, what in _THRESHOLDS.items():
            numbers[name] = finite(getattr(self, name), what, 0.0, 1.0)
        for name, value in numbers.items():
            object.__setattr__(self, name, value)


_THRESHOLDS = {
    "lost_below": "the confidence below which the blob is lost",
    "reacquire_above": "the confidence that finds a lost blob again",
    "propose_below": "the confidence below which other starts are proposed",
    "refine_below": "the confidence below which the local stage runs",
    "adapt_below": "the confidence below which the appearance adapts",
}
