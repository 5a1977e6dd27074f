"""Frames as the tracker reads them: only the region around the blob, blurred, in a pyramid.

Frames arrive whole (uint8 from a camera or a video, or float); only the region the blob can
reach is read. It is blurred like the template (paper §7) and taken down the pyramid to the
finest level the tracker uses -- in 8 bits when the frame is 8-bit, which is several times
faster than in float and loses nothing a camera did not already round -- and converted to
float there. :class:`FramePictures` keeps the pyramids of the frame being fitted: the fits of
one frame from the same region (a second start, a fit made again against the template)
share one.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from ..errors import VoodooError
from ..media.images import blur

#: A blob is tracked on the finest pyramid level where it keeps fewer than this many times
#: the pixel budget (see :func:`base_level`).
BASE_FACTOR = 2.0
#: The region read around the blob reaches this share of its size beyond its nodes (and at
#: least 8 pixels of the coarsest level).
MARGIN = 0.15
#: Scale (pixels of each pyramid level) below which :func:`emphasise` strengthens detail.
DETAIL_SIGMA = 3.0
#: A texture whose contrast (the standard deviation of the template's colours, in [0, 1])
#: is below the first has its detail strengthened by :data:`FAINT_DETAIL`; above the second,
#: not at all; in between, in proportion (see :func:`detail_for`).
FAINT = (0.09, 0.13)
FAINT_DETAIL = 5.0
#: A texture whose *fine* contrast (:func:`fine_contrast`: what is left of its colours once
#: blurred at :data:`DETAIL_SIGMA`) is below the first is strengthened by
#: :data:`FAINT_DETAIL` too, whatever its contrast overall; above the second, not for this;
#: in between, in proportion. Fur and plush come to 0.006-0.012, printed dolls and the real
#: bag to 0.037-0.095 (0.030 through a dim camera's blur; BENCHMARKS.md, *Fur dyed in
#: patches*).
FINE_FAINT = (0.015, 0.025)


def pyramid(image: np.ndarray, levels: int) -> list[np.ndarray]:
    """``[image, pyrDown(image), ...]`` with ``levels`` entries."""
    out = [image]
    for _ in range(levels - 1):
        out.append(cv2.pyrDown(out[-1]))
    return out


def emphasise(picture: np.ndarray, detail: float, sigma: float = DETAIL_SIGMA) -> np.ndarray:
    """``picture`` with its detail finer than ``sigma`` pixels made ``1 + detail`` times as strong.

    ``picture + detail (picture - blur(picture))``, float32; ``detail`` 0 returns it as it is.
    """
    if detail <= 0:
        return picture
    smooth = blur(picture, sigma)
    out = picture - smooth
    out *= np.float32(detail)
    out += picture
    return out


def detail_for(template: np.ndarray, fine: float | None = None) -> float:
    """How much to strengthen the detail of a doll with the template colours ``template``.

    On a faint texture -- plush, fur, felt: little contrast -- the shading of a doll
    turning under a lamp changes more of each pixel's colour than the texture does, and
    what a patch's gain and bias cannot absorb pulls the fit off by pixels; the fine
    texture, which shading hardly touches, is what places it (BENCHMARKS.md, *Detail on
    faint dolls*). A printed texture is placed by its own contrast, and strengthening its
    detail would only weigh motion blur and creases more.

    Contrast overall misses fur dyed in patches, or lit across by a lamp: its colours
    vary as much as a print's (a standard deviation of 0.13-0.15), while its fine texture
    is as faint as any plush's. ``fine`` (:func:`fine_contrast` of the doll's texture)
    tells those apart; the doll is strengthened as much as the fainter of the two says.
    """
    contrast = float(np.std(template))
    strength = _faint(contrast, FAINT)
    if fine is not None:
        strength = max(strength, _faint(fine, FINE_FAINT))
    return FAINT_DETAIL * strength


def _faint(contrast: float, bounds) -> float:
    """1 below ``bounds[0]``, 0 above ``bounds[1]``, linear in between."""
    low, high = bounds
    return min(max((high - contrast) / (high - low), 0.0), 1.0)


def fine_contrast(texture: np.ndarray, inside: np.ndarray, sigma: float = DETAIL_SIGMA) -> float:
    """The root mean square of ``texture``'s detail finer than ``sigma`` pixels, inside.

    ``texture`` (h, w, c) float; ``inside`` (h, w) bool: the doll's pixels. The blur is
    taken over the doll's pixels alone (normalised by the blurred mask), so the outline's
    edge against the background adds nothing.
    """
    mask = inside.astype(np.float32)
    if not mask.any():
        return 0.0
    spread = blur(mask, sigma)
    smooth = blur(texture * mask[..., None], sigma) / np.maximum(spread, 1e-6)[..., None]
    detail = (texture - smooth)[inside]
    return float(np.sqrt(np.mean(detail * detail)))


def doll_fine_contrast(blob, base: int = 0) -> float:
    """:func:`fine_contrast` of ``blob``'s texture on pyramid level ``base``.

    The level the doll is tracked on (:func:`base_level`): the comparison strengthens the
    detail finer than :data:`DETAIL_SIGMA` pixels of that level, whose texture is this one
    (``level.Level``'s plain texture).
    """
    texture = pyramid(blob.texture, base + 1)[-1]
    local = np.round((blob.pixel_coords - blob.texture_origin) / 2.0**base).astype(np.int64)
    local = np.clip(local, 0, np.array(texture.shape[1::-1]) - 1)
    inside = np.zeros(texture.shape[:2], bool)
    inside[local[:, 1], local[:, 0]] = True
    return fine_contrast(texture, inside)


def to_float(pixels: np.ndarray) -> np.ndarray:
    """A frame region as float32 RGB in [0, 1] (uint8 RGB or float RGB in)."""
    if pixels.dtype == np.uint8:
        out = pixels.astype(np.float32)
        out *= np.float32(1.0 / 255.0)
        return out
    out = np.asarray(pixels, dtype=np.float32)  # a view when already float32
    if not np.isfinite(out.sum(dtype=np.float64)):  # one pass: NaN or inf spoil the sum
        out = np.nan_to_num(out, nan=0.0, posinf=1.0, neginf=0.0)
    return out


def checked_frame(frame, size: tuple) -> np.ndarray:
    """``frame`` as an array, checked to be uint8 or float32 RGB of ``size`` (w, h).

    Raises
    ------
    VoodooError
        Naming what is wrong with it.
    """
    frame = np.asarray(frame)
    if frame.ndim != 3 or frame.shape[2] != 3:
        raise VoodooError(f"A frame must be an RGB picture; got shape {frame.shape}.")
    if frame.dtype not in (np.uint8, np.float32):
        raise VoodooError("Frames must be uint8 RGB, or float32 RGB in [0, 1].")
    h, w = frame.shape[:2]
    if (w, h) != tuple(size):
        raise VoodooError(
            f"This frame is {w}x{h} but the blob was built on a {size[0]}x"
            f"{size[1]} frame; use the same camera mode or clip."
        )
    return frame


class FramePyramid:
    """Level pictures of a frame region, built on demand (most frames need one level only).

    Parameters
    ----------
    region : (h, w, 3) uint8 or float32
        The frame region, full resolution, unblurred.
    sigma : float
        The template's blur, full-resolution pixels.
    base : int
        The finest level used: the region is blurred, then halved ``base`` times.
    detail : float
        Every level's picture is given to the fits with its detail strengthened by this
        (:func:`emphasise`), as the template is.
    """

    def __init__(self, region: np.ndarray, sigma: float, base: int = 0, detail: float = 0.0):
        img = region
        if img.dtype != np.uint8:
            img = to_float(img)
        # Halving first and blurring at the base level by the template's blur in base-level
        # pixels is the template's blur-then-halve up to the order of two low-pass filters,
        # at a quarter of the cost per level.
        for _ in range(base):
            img = cv2.pyrDown(img)
        img = blur(img, sigma / 2**base)
        self.base = base
        if img.dtype == np.uint8:
            img = to_float(img)
        self._levels = {base: img}
        self.detail = detail
        self._shown: dict[int, np.ndarray] = {}

    def __getitem__(self, level: int) -> np.ndarray:
        out = self._shown.get(level)
        if out is None:
            out = self._shown[level] = emphasise(self.plain(level), self.detail)
        return out

    def judged(self, level: int) -> np.ndarray | None:
        """The picture the confidence is measured on at ``level``, if not the fits' one.

        :meth:`plain` when the fits compare it with its detail strengthened, else None.
        """
        return self.plain(level) if self.detail > 0 else None

    def plain(self, level: int) -> np.ndarray:
        """The picture of ``level`` as read (blurred), without :func:`emphasise`."""
        if level < self.base:
            raise IndexError(f"level {level} is finer than the base level {self.base}")
        for k in range(self.base + 1, level + 1):
            if k not in self._levels:
                self._levels[k] = cv2.pyrDown(self._levels[k - 1])
        return self._levels[level]


class FramePictures:
    """The pyramids of the frame being fitted, one per region read, until the next frame.

    Parameters
    ----------
    sigma : float
        The template's blur, full-resolution pixels.
    base : int
        The finest level used (see :func:`base_level`).
    n_levels : int
        The levels used from ``base`` on: a region starts on a pixel of the coarsest.
    detail : float
        See :class:`FramePyramid`.
    """

    def __init__(self, sigma: float, base: int, n_levels: int, detail: float = 0.0):
        self.sigma = sigma
        self.detail = detail
        self.base = base
        self.align = 2 ** (base + n_levels - 1)
        self.forget()

    def forget(self) -> None:
        """Drop the pyramids kept.

        Call it before a new frame: a camera may hand over the same buffer with new pixels.
        """
        self._frame = None
        self._kept: dict[tuple, FramePyramid] = {}

    def whole(self, frame: np.ndarray):
        """(FramePyramid, origin) of the whole frame."""
        h, w = frame.shape[:2]
        return self._region(frame, (0, 0, w, h))

    def around(self, frame: np.ndarray, nodes: np.ndarray):
        """(FramePyramid, origin) of the region around ``nodes`` (m, 2) frame pixels.

        None when the nodes are not finite or the region is (nearly) off the frame.
        """
        if not np.isfinite(nodes).all():
            return None
        h, w = frame.shape[:2]
        align = self.align
        (lx, ly), (hx, hy) = nodes.min(axis=0).tolist(), nodes.max(axis=0).tolist()
        margin = max(MARGIN * max(hx - lx, hy - ly), 8.0 * align)
        x0 = min(max(math.floor((lx - margin) / align) * align, 0), w)
        y0 = min(max(math.floor((ly - margin) / align) * align, 0), h)
        x1 = min(max(math.ceil(hx + margin) + 1, 0), w)
        y1 = min(max(math.ceil(hy + margin) + 1, 0), h)
        if x1 - x0 < 8 or y1 - y0 < 8:
            return None
        return self._region(frame, (x0, y0, x1, y1))

    def _region(self, frame: np.ndarray, box: tuple):
        if frame is not self._frame:
            self.forget()
            self._frame = frame
        pyr = self._kept.get(box)
        if pyr is None:
            x0, y0, x1, y1 = box
            pyr = self._kept[box] = FramePyramid(
                frame[y0:y1, x0:x1], self.sigma, self.base, self.detail
            )
        return pyr, np.array(box[:2], float)


def base_level(n_pixels: int, budget: int | None) -> int:
    """The finest pyramid level worth tracking a blob of ``n_pixels`` on.

    A blob much bigger than the pixel budget is subsampled anyway, so reading, blurring and
    sampling the frame at full resolution buys nothing: track it on the level where it has
    at most :data:`BASE_FACTOR` times the budget (a 1080p close-up at half resolution).
    """
    if not budget:
        return 0
    base = 0
    while n_pixels / 4 ** (base + 1) >= BASE_FACTOR * budget:
        base += 1
    return base
