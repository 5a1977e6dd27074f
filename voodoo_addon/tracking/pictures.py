"""Frames as the tracker reads them: only the region around the blob, blurred, in a pyramid.

Frames arrive whole (uint8 from a camera or a video, or float); only the region the blob can
reach is read. It is blurred like the template (paper §7) and taken down the pyramid to the
finest level the tracker uses -- in 8 bits when the frame is 8-bit, which is several times
faster than in float and loses nothing a camera did not already round -- and converted to
float there.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..media.images import blur


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
    """

    def __init__(self, region: np.ndarray, sigma: float, base: int = 0):
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

    def __getitem__(self, level: int) -> np.ndarray:
        if level < self.base:
            raise IndexError(f"level {level} is finer than the base level {self.base}")
        for k in range(self.base + 1, level + 1):
            if k not in self._levels:
                self._levels[k] = cv2.pyrDown(self._levels[k - 1])
        return self._levels[level]
