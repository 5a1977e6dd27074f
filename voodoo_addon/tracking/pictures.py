"""Frames as the tracker reads them: only the region around the blob, blurred, in a pyramid.

Frames arrive whole (uint8 from a camera or a video, or float); only the region the blob can
reach is converted to float and blurred like the template (paper §7), then taken down a
lazy pyramid.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..images import blur


def to_float(pixels: np.ndarray) -> np.ndarray:
    """A frame region as float32 RGB in [0, 1] (uint8 RGB or float RGB in)."""
    if pixels.dtype == np.uint8:
        out = pixels.astype(np.float32)
        out *= np.float32(1.0 / 255.0)
        return out
    out = np.ascontiguousarray(pixels, dtype=np.float32)
    if not np.isfinite(out).all():
        out = np.nan_to_num(out, nan=0.0, posinf=1.0, neginf=0.0)
    return out


def crop(frame: np.ndarray, box, sigma: float) -> np.ndarray:
    """The blurred float picture of ``frame[y0:y1, x0:x1]`` (box = (x0, y0, x1, y1))."""
    x0, y0, x1, y1 = box
    return blur(to_float(frame[y0:y1, x0:x1]), sigma)


class FramePyramid:
    """Level pictures of a frame region, built on demand (most frames need level 0 only).

    Parameters
    ----------
    image : (h, w, 3) float32
        The blurred region at full resolution.
    """

    def __init__(self, image: np.ndarray):
        self._levels = [image]

    def __getitem__(self, level: int) -> np.ndarray:
        while len(self._levels) <= level:
            self._levels.append(cv2.pyrDown(self._levels[-1]))
        return self._levels[level]
