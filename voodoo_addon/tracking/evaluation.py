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

Within the triangles kept, single pixels whose robust error is far off (*outliers*, found at
the same time) leave the solve too: fingertips over part of a faintly textured triangle raise
its mean error too little for the triangle test, yet pull the nodes off the doll.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import kernels
from .level import Level
from .norms import RobustNorm
from .params import ParamLayout
from .warp import WarpBackend, remap_points

#: Once the fit is good (the patches in view correlate with the template, see
#: ``_coverable``), a patch that correlates below :data:`OCCLUDED_CORRELATION` is covered
#: by something.
ALIGNED_CORRELATION = 0.7
OCCLUDED_CORRELATION = 0.5
#: Global brightness and contrast changes smaller than this are not undone (half a grey
#: level of an 8-bit picture).
LIGHTING_EPS = 1.0 / 512

#: Occlusion found while the typical patch correlates may leave out at most this much of
#: the seen blob...
MAX_OCCLUDED = 0.5
#: ...and when only the best third of the patches correlate, but above
#: :data:`IN_VIEW_CORRELATION`, the rest may be left out as folded away or covered, down to
#: this share of the blob (on the picture, not turned away) in view: the part in view is
#: still registered on its own. With less in view, nothing is left out.
MIN_IN_VIEW = 1.0 / 3.0
IN_VIEW_CORRELATION = 0.85
#: Per-channel robust error at which the compared residual saturates: the Lorentzian's value
#: at three sigma (an error that large counts the same, however large).
LOSS_CAP = float(np.log1p(4.5))
#: Single pixels of the kept triangles whose robust error is above the tracker's pixel limit
#: (``TrackerOptions.pixel_outlier``) are left out too -- fingertips over the edge of a
#: triangle, a crease's shadow -- but only when at least this many of them are, and this
#: share of the level's pixels: a handful of outliers is noise the norm already bounds.
MIN_OUTLIERS = 20
OUTLIER_SHARE = 0.002
_ONES3 = np.ones(3, dtype=np.float32)
_ZEROS3 = np.zeros(3, dtype=np.float32)


@dataclass
class Evaluation:
    """One evaluation of the warp at one level.

    Attributes
    ----------
    samples : (n, 3) float32
        The frame at the warped template pixels.
    rho : (n, 3) float32
        The robust values of the differences (Eq. 16), lighting removed.
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
    occluded : (t,) bool or None
        The triangles this evaluation found occluded (None when it did not look).
    hidden : (t,) bool or None
        The triangles left out as hidden (compressed), as given.
    difference : (n, 3) float32
        Template minus frame with the lighting removed, before the robust transform.
    outliers : (n,) bool or None
        Single pixels of the kept triangles left out (found by this evaluation or given).
    positions : (2, n_pad) float32 or None
        Where the pixels were sampled on the bound picture (see :meth:`Level.positions`).
    """

    samples: np.ndarray
    rho: np.ndarray
    valid: np.ndarray
    use: np.ndarray
    triangle_weight: np.ndarray
    residual: float
    weighted: bool
    occluded_triangles: np.ndarray | None = None
    hidden: np.ndarray | None = None
    difference: np.ndarray | None = None
    outliers: np.ndarray | None = None
    positions: np.ndarray | None = None
    _dbar: np.ndarray | None = field(default=None, repr=False)

    @property
    def dbar(self) -> np.ndarray:
        """Robust differences (n, 3) float32, ``sign(d) sqrt(rho(d))`` (Eq. 16).

        Made when first read: the local stage's iterations read only the difference.
        """
        if self._dbar is None:
            out = np.sqrt(self.rho)
            self._dbar = np.copysign(out, self.difference, out=out)
        return self._dbar

    @property
    def occluded_share(self) -> float:
        """Fraction of the level's pixels left out of the solve."""
        if not self.weighted:
            return 0.0
        return 1.0 - float(np.count_nonzero(self.use)) / len(self.use)


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
    occluded: np.ndarray | None = None,
    template: np.ndarray | None = None,
    cover: Cover | None = None,
    outliers: np.ndarray | None = None,
    pixel_limit: float = 0.0,
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
    occluded : (t,) bool, optional
        Triangles already found occluded in this frame: left out, and no new test is made.
    template : (n, 3) float32, optional
        What the pixels are compared with instead of the level's template (an appearance
        adapted to recent frames, see ``Tracker``).
    cover : Cover, optional
        Frame pixels where something known is in front (another doll): the template pixels
        landing there count as off the picture.
    outliers : (n,) bool, optional
        Pixels already found to be outliers in this frame (with ``occluded``): left out.
    pixel_limit : float
        With the occlusion test, pixels of the kept triangles whose robust error (summed
        over the channels) exceeds this are outliers (see :data:`MIN_OUTLIERS`); 0: none.

    Returns
    -------
    Evaluation or None
        None when too little of the blob is on the picture to compare.
    """
    n = len(level)
    if nodes is None:
        nodes = level.nodes(a)
    found = sample(level, a, origin, box, backend, nodes, cover)
    if found is None:
        return None
    samples, valid, positions = found
    valid_all = valid is None
    if valid_all:
        valid = level.all_valid
    mask = valid if hidden is None else _of_triangles(level, valid, ~hidden)
    compare = _Comparison(level, layout, norm, a, samples, template)

    nt = level.n_triangles
    size = level.triangle_size
    if valid_all:
        count = size
    else:
        count = np.empty(nt)
        kernels.count_per_triangle(valid, level.triangle, count)
    seen = (count >= 0.5 * size) & (size > 0)
    if hidden is not None:
        seen &= ~hidden
    weight = seen.astype(np.float64)
    # Occlusion only at full resolution and once the fit is close (the patches in view
    # correlate): on coarse levels, or early in the iterations, a triangle that is
    # merely misaligned looks occluded, and dropping it loses the texture that would align it.
    detected = None
    if occluded is not None:
        weight[occluded] = 0.0
    if occluded is None and level.finest and seen.any():
        compare(mask, correlate=True)
        most = _coverable(compare.correlation)
        if most > 0.0:
            r_tri = compare.triangle_loss / np.maximum(count, 1.0)
            limit = outlier_factor * max(float(np.median(r_tri[seen])), floor)
            out = seen & (r_tri > limit)
            if compare.correlation is not None:
                low = compare.correlation < OCCLUDED_CORRELATION  # NaN (untextured): not low
                out |= seen & low[level.patch_of_triangle]
            if not out.any() or size[out].sum() > most * size[seen].sum():
                out[:] = False
            weight[out] = 0.0
            detected = out
        use = _used(level, mask, weight)
        if most > 0.0 and pixel_limit > 0.0:
            bad = use & (compare.loss > pixel_limit)  # the loss of the first comparison
            if np.count_nonzero(bad) >= max(MIN_OUTLIERS, OUTLIER_SHARE * n):
                use = use & ~bad
                outliers = bad
        if use is not mask and level.patches is not None:
            # The lighting of the patches that lost pixels is fitted again without them.
            compare(use, correlate=False)
    else:
        use = _used(level, mask, weight)
        if outliers is not None:
            use = use & ~outliers
        # With lighting patches, the pixels left out are fitted without at once (what
        # comparing all and then again without them would give).
        compare(use if level.patches is not None else mask, correlate=False)
    weighted = use is not level.all_valid
    if weighted and np.count_nonzero(use) < 0.05 * n:
        return None
    # The error that iterations compare: a capped loss over every pixel that can be seen,
    # whichever of them the solve uses, so that estimates stay comparable while pixels
    # come and go.
    n_mask = n if mask is level.all_valid else np.count_nonzero(mask)
    residual = compare.capped / max(n_mask, 1)
    return Evaluation(
        samples,
        compare.rho,
        valid,
        use,
        weight,
        residual,
        weighted,
        detected,
        hidden,
        compare.diff,
        outliers,
        positions,
    )


def sample(level: Level, a, origin, box, backend: WarpBackend, nodes, cover=None, picture=None):
    """The frame at the level's pixels warped by ``a`` (``nodes``: ``level.nodes(a)``).

    Returns (samples (n, 3) float32, valid (n,) bool or None when every pixel is on the
    picture and not covered, positions (2, n_pad) on the picture), or None when fewer than
    15% are. The arguments are :func:`evaluate`'s; ``picture``, when given, is sampled
    instead of the one bound to ``backend`` (the same region of the frame, shown otherwise).
    """
    n = len(level)
    pos, valid, on = _placed(level, a, origin, box, nodes, cover)
    if on < 0.15 * n:
        return None
    if picture is not None:
        return remap_points(picture, pos)[:n], valid, pos
    return backend.sample(level.geometry, nodes - origin, pos), valid, pos


def _placed(level: Level, a, origin, box, nodes, cover):
    """Where the level's pixels land on the picture under ``nodes``, and which are on it.

    Returns (positions (2, n_pad), valid (n,) bool or None when every pixel is on the
    picture and not covered, how many are). The arguments are :func:`sample`'s.
    """
    n = len(level)
    pos = level.positions(a, nodes)
    pos -= origin[:, None]
    valid = np.empty(n, bool)
    on = kernels.on_picture(pos, box[0], box[1], valid)
    if on == n:
        valid = None
    if cover is not None:
        free = cover.free(pos[0, :n] + origin[0], pos[1, :n] + origin[1], level.scale)
        if free is not None:
            valid = free if valid is None else valid & free
            on = np.count_nonzero(valid)
    return pos, valid, on


def residuals(
    level: Level,
    a: np.ndarray,
    nodes,
    origin: np.ndarray,
    box: np.ndarray,
    backend: WarpBackend,
    norm: RobustNorm,
    layout: ParamLayout,
    hidden: np.ndarray | None = None,
    cover: Cover | None = None,
    template: np.ndarray | None = None,
    least: float = 0.0,
) -> np.ndarray:
    """:func:`evaluate`'s residual at many meshes at once, to rank them.

    For each of ``nodes`` ((m, 2) level coordinates), the same number as
    ``evaluate(level, a, origin, box, ..., nodes, hidden, no_triangle, template,
    cover).residual``: nothing tested for occlusion (as on a coarse level, or with the
    occluded triangles given as none), ``a`` giving the global lighting. Inf where that
    evaluation would be None or use fewer than ``least`` of the level's pixels. The frame is
    sampled at every mesh in one call (:meth:`.warp.WarpBackend.sample_many`), and nothing
    is kept of the comparisons but their residuals: 40-70% of the time of as many
    evaluations.

    Returns
    -------
    (K,) float64
    """
    n = len(level)
    out = np.full(len(nodes), np.inf)
    places, valids = [], []
    for v in nodes:
        pos, valid, on = _placed(level, a, origin, box, v, cover)
        places.append(pos)
        valids.append(False if on < 0.15 * n else valid)  # False: evaluate() gives None
    keep = [k for k, valid in enumerate(valids) if valid is not False]
    if not keep:
        return out
    found = backend.sample_many(
        level.geometry, [nodes[k] - origin for k in keep], [places[k] for k in keep]
    )
    compare, whole = None, None
    for k, samples in zip(keep, found, strict=True):
        valid = valids[k]
        if valid is None and whole is not None:
            mask, use, n_mask = whole  # every pixel on the picture: as the last such mesh
        else:
            mask, use, n_mask = _compared(level, valid, hidden)
            if valid is None:
                whole = mask, use, n_mask
        if use is not level.all_valid and np.count_nonzero(use) < max(least, 0.05) * n:
            continue
        if compare is None:
            compare = _Comparison(level, layout, norm, a, samples, template)
        else:
            compare.samples = np.ascontiguousarray(samples, dtype=np.float32)
        compare(use if level.patches is not None else mask, correlate=False)
        out[k] = compare.capped / max(n_mask, 1)
    return out


def _compared(level: Level, valid: np.ndarray | None, hidden: np.ndarray | None):
    """The pixels :func:`evaluate` compares on a coarse level (mask, use, mask's count)."""
    if valid is None:
        valid, count = level.all_valid, level.triangle_size
    else:
        count = np.empty(level.n_triangles)
        kernels.count_per_triangle(valid, level.triangle, count)
    mask = valid if hidden is None else _of_triangles(level, valid, ~hidden)
    seen = (count >= 0.5 * level.triangle_size) & (level.triangle_size > 0)
    if hidden is not None:
        seen &= ~hidden
    use = _used(level, mask, seen.astype(np.float64))
    return mask, use, len(mask) if mask is level.all_valid else np.count_nonzero(mask)


class Cover:
    """Frame pixels where something known is in front of the blob (another doll).

    Parameters
    ----------
    mask : (h, w) bool
        True where the blob is covered, frame pixels from ``origin``.
    origin : (x, y) int
        The frame pixel of ``mask[0, 0]``; outside the mask nothing is covered.
    """

    def __init__(self, mask: np.ndarray, origin=(0, 0)):
        self.mask = np.ascontiguousarray(mask, dtype=bool)
        self.origin = (int(origin[0]), int(origin[1]))

    def free(self, x: np.ndarray, y: np.ndarray, scale: float) -> np.ndarray | None:
        """Of level pixels (x, y) at ``scale``, those not covered; None when none is."""
        h, w = self.mask.shape
        fx = np.rint(x / scale).astype(np.intp) - self.origin[0]
        fy = np.rint(y / scale).astype(np.intp) - self.origin[1]
        if fx.max() < 0 or fx.min() >= w or fy.max() < 0 or fy.min() >= h:
            return None
        inside = (fx >= 0) & (fx < w) & (fy >= 0) & (fy < h)
        free = np.ones(len(fx), bool)
        free[inside] = ~self.mask[fy[inside], fx[inside]]
        return None if free.all() else free


class _Comparison:
    """Template against the sampled frame, for a mask of pixels.

    The difference with the lighting removed, its Eq. 16 robust values and the per-pixel
    loss (:mod:`.kernels`). Calling it again with another mask refits the lighting patches
    on that mask.
    """

    def __init__(self, level: Level, layout: ParamLayout, norm: RobustNorm, a, samples, template):
        self.level = level
        self.norm = norm
        self.samples = np.ascontiguousarray(samples, dtype=np.float32)
        self.template = level.template if template is None else template
        gain, bias = _ONES3, _ZEROS3
        if layout.photometric != "none":
            b, c = np.empty(3), np.empty(3)
            b[:], c[:] = a[layout.brightness], a[layout.contrast]  # one value or three
            np.exp(c, out=c)
            # A global lighting within half an 8-bit grey level of none is not undone.
            if np.abs(c - 1.0).max() >= LIGHTING_EPS or np.abs(b).max() >= LIGHTING_EPS:
                gain, bias = (1.0 / c).astype(np.float32), (b / c).astype(np.float32)
        self.gain, self.bias = gain, bias
        n = len(samples)
        self.diff = np.empty((n, 3), np.float32)
        self.triangle_loss = np.empty(level.n_triangles)
        self.correlation = None
        self.capped = 0.0

    def __call__(self, mask: np.ndarray, correlate: bool) -> None:
        level = self.level
        if level.patches is None:
            kernels.difference(self.samples, self.template, self.gain, self.bias, self.diff)
        else:
            args = (self.template, self.samples, self.gain, self.bias, mask)
            correlation = level.patches.compare(*args, out=self.diff)[1]
            if correlate:
                self.correlation = correlation
        # Eq. 16 in NumPy: its vectorised log is several times faster than a compiled
        # scalar loop's.
        self.rho = self.norm.rho(self.diff)
        self.loss = self.rho @ _ONES3  # summed over channels (faster than .sum(axis=1))
        self.capped = kernels.masked_loss(
            self.loss, mask, level.triangle, 3 * LOSS_CAP, self.triangle_loss
        )


def _used(level: Level, mask: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """The masked pixels of the triangles with weight (``mask`` itself when all have)."""
    if weight[level.triangle_size > 0].all():
        return mask
    return _of_triangles(level, mask, weight > 0)


def _of_triangles(level: Level, mask: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """The pixels of ``mask`` (n,) whose triangle is kept (``keep`` (t,) bool)."""
    out = np.empty(len(mask), bool)
    kernels.of_triangles(mask, keep, level.triangle, out)
    return out


def _coverable(correlation) -> float:
    """How much of the seen blob may be called covered, from how well the patches correlate.

    The typical patch correlates (above :data:`ALIGNED_CORRELATION`): the fit is close, and
    up to :data:`MAX_OCCLUDED` of the blob may be covered. Or only the best
    :data:`MIN_IN_VIEW` of the patches correlate, but they do closely (above
    :data:`IN_VIEW_CORRELATION`): the rest is folded away or covered, and up to all but
    that third may be. Otherwise 0: the fit is not close enough to tell covered from
    misaligned. Without lighting patches: :data:`MAX_OCCLUDED`.
    """
    if correlation is None:
        return MAX_OCCLUDED
    known = np.sort(correlation[np.isfinite(correlation)])
    if not len(known):
        return 0.0
    if _median(known) >= ALIGNED_CORRELATION:
        return MAX_OCCLUDED
    if _quantile(known, 1.0 - MIN_IN_VIEW) >= IN_VIEW_CORRELATION:
        return 1.0 - MIN_IN_VIEW
    return 0.0


def _median(ordered: np.ndarray) -> float:
    """``np.median`` of an ascending array (n,), n > 0, the same number without its overhead."""
    n = len(ordered)
    half = n // 2
    if n % 2:
        return float(ordered[half])
    return float((ordered[half - 1] + ordered[half]) / 2.0)


def _quantile(ordered: np.ndarray, q: float) -> float:
    """``np.quantile(ordered, q)`` (linear) of an ascending array (n,), n > 0, the same number.

    The virtual index ``(n - 1) q`` and NumPy's interpolation between its neighbours, which
    takes the upper neighbour as base from a weight of one half on.
    """
    n = len(ordered)
    virtual = (n - 1) * q
    below = math.floor(virtual)
    lo, hi = ordered[min(max(below, 0), n - 1)], ordered[min(max(below + 1, 0), n - 1)]
    gamma = virtual - below
    diff = hi - lo
    return float(hi - diff * (1.0 - gamma) if gamma >= 0.5 else lo + diff * gamma)
