"""One comparison of the warped frame with the template, and which of it to trust.

:func:`evaluate` warps the frame back onto the template at a parameter vector (``W^-1(I, a)``
of Eq. 12), takes the difference -- with the lighting of every patch projected out (see
:mod:`.photometry`) or the paper's global brightness and contrast undone -- turns it into the
Eq. 16 robust values, and decides which triangles take part in the solve:

- *off the picture*: fewer than half of a triangle's pixels land on the frame;
- *hidden*: the triangle is compressed so much (foreshortened, turning away) that its
  pixels cannot be compared (the caller says which);
- *occluded* (finest level only): its robust error is far above the median triangle's, or
  its lighting patch correlates poorly with the template while the typical patch correlates
  well (a hand over it, a card: no lighting change makes them look like the template).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .level import Level
from .norms import RobustNorm
from .params import ParamLayout
from .warp import WarpBackend

_ONES3 = np.ones(3, dtype=np.float32)
#: Once the fit is good (the median lighting patch correlates with the template above
#: :data:`ALIGNED_CORRELATION`), a patch that correlates below :data:`OCCLUDED_CORRELATION`
#: is covered by something.
ALIGNED_CORRELATION = 0.7
OCCLUDED_CORRELATION = 0.5
#: Occlusion is only believed when it leaves at least this much of the seen blob.
MAX_OCCLUDED = 0.5
#: Per-channel robust error at which the compared residual saturates: the Lorentzian's value
#: at three sigma (an error that large counts the same, however large).
LOSS_CAP = float(np.log1p(4.5))


@dataclass
class Evaluation:
    """One evaluation of the warp at one level.

    Attributes
    ----------
    samples : (n, 3) float32
        The frame at the warped template pixels.
    dbar : (n, 3) float32
        Robust differences (Eq. 16), lighting removed.
    valid : (n,) bool
        Inside the picture.
    use : (n,) bool
        Taken into the solve (valid, not hidden, not occluded).
    triangle_weight : (t,) float64
        1 for the triangles that take part, 0 for the others.
    residual : float
        Mean robust error, capped per pixel, over the pixels that can be seen.
    weighted : bool
        Some pixels are left out (``use`` is not all true).
    """

    samples: np.ndarray
    dbar: np.ndarray
    valid: np.ndarray
    use: np.ndarray
    triangle_weight: np.ndarray
    residual: float
    weighted: bool

    @property
    def occluded(self) -> float:
        """Fraction of the level's pixels left out of the solve."""
        if not self.weighted:
            return 0.0
        return 1.0 - float(np.count_nonzero(self.use)) / len(self.use)


def _robust(norm: RobustNorm, d: np.ndarray):
    """Eq. 16 ``dbar = sign(d) sqrt(rho(d))`` and the per-pixel loss ``sum_c rho``."""
    rho = norm.rho(d)
    dbar = np.sqrt(rho)
    np.copysign(dbar, d, out=dbar)
    return dbar, rho @ _ONES3  # summed over channels (faster than .sum(axis=1))


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
    hidden: np.ndarray | None = None,
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
        A triangle whose mean robust error exceeds ``outlier_factor * max(median, floor)``
        is occluded (full resolution only).
    nodes : (m, 2) float64, optional
        ``level.nodes(a)`` when the caller has them.
    hidden : (t,) bool, optional
        Triangles known to be hidden (turned away from the camera): left out.

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
        valid = None
    else:
        valid = (x >= 0) & (y >= 0) & (x <= box[0]) & (y <= box[1])
        if np.count_nonzero(valid) < 0.15 * n:
            return None
    samples = backend.sample(level.geometry, nodes - origin, pos)
    d = _difference(level, layout, a, samples)
    patches = level.patches
    valid_all = valid is None
    if valid_all:
        valid = level.all_valid
    mask = valid if hidden is None else valid & ~hidden[level.triangle]
    correlation = None
    if patches is not None:
        d, correlation = patches.project(d, None if mask is level.all_valid else mask)
    dbar, loss = _robust(norm, d)

    nt = level.n_triangles
    size = level.triangle_size
    count = size if valid_all else np.bincount(level.triangle, weights=valid, minlength=nt)
    seen = (count >= 0.5 * size) & (size > 0)
    if hidden is not None:
        seen &= ~hidden
    weight = seen.astype(np.float64)
    use = mask
    # Occlusion only at full resolution: on coarse levels a triangle that is merely
    # misaligned looks occluded, and dropping it loses the texture that would align it.
    if level.index == 0 and seen.any():
        r_tri = np.bincount(level.triangle, weights=loss * mask, minlength=nt)
        r_tri /= np.maximum(count, 1.0)
        limit = outlier_factor * max(float(np.median(r_tri[seen])), floor)
        out = seen & (r_tri > limit)
        if correlation is not None:
            out |= seen & _uncorrelated(correlation)[level.patch_of_triangle]
        if out.any() and size[out].sum() <= MAX_OCCLUDED * size[seen].sum():
            weight[out] = 0.0
    if not weight[size > 0].all():
        use = use & (weight[level.triangle] > 0)
    if use is not mask and patches is not None:
        # The lighting of the patches that lost pixels is fitted again without them.
        d, _ = patches.project(_difference(level, layout, a, samples), use)
        dbar, loss = _robust(norm, d)
    weighted = use is not level.all_valid
    if weighted and np.count_nonzero(use) < 0.05 * n:
        return None
    # The error that iterations compare: a capped loss over every pixel that can be seen,
    # whichever of them the solve uses, so that estimates stay comparable while pixels
    # come and go.
    capped = np.minimum(loss, LOSS_CAP * _ONES3.sum())
    residual = float(capped.mean() if mask is level.all_valid else capped[mask].mean())
    return Evaluation(samples, dbar, valid, use, weight, residual, weighted)


def _difference(level: Level, layout: ParamLayout, a: np.ndarray, samples: np.ndarray):
    """``I0 - (S - b) / c``: template minus frame with the global lighting undone (Eq. 4)."""
    if layout.photometric == "none":
        return level.template - samples
    c, b = layout.channel_gain_offset(a)
    d = np.multiply(samples, (1.0 / c).astype(np.float32))
    np.subtract(level.template, d, out=d)
    d += (b / c).astype(np.float32)
    return d


def _uncorrelated(correlation: np.ndarray) -> np.ndarray:
    """Patches that do not correlate while the typical patch does (NaN: never)."""
    known = np.isfinite(correlation)
    if not known.any() or float(np.median(correlation[known])) < ALIGNED_CORRELATION:
        return np.zeros(len(correlation), bool)
    return known & (np.nan_to_num(correlation, nan=1.0) < OCCLUDED_CORRELATION)
