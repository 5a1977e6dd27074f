"""Automatic outlines: segment the object around a point or a box, follow its border (§7).

Textured foam defeats thresholds and flood fills (its paint *is* edges), so the region is cut
with GrabCut's colour models; the border of the region is then followed with OpenCV's
``findContours`` and simplified with the tolerance band of :mod:`voodoo_addon.contour`.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..checks import finite_array
from ..errors import VoodooError
from .outline import simplify_contour, validate_contour

#: Work on pictures no larger than this (longer side), for speed.
WORK_SIZE = 480


def _grabcut_rect(img8: np.ndarray, rect, iterations: int = 5) -> np.ndarray:
    mask = np.zeros(img8.shape[:2], np.uint8)
    bgd, fgd = np.zeros((1, 65)), np.zeros((1, 65))
    cv2.grabCut(img8, mask, rect, bgd, fgd, iterations, cv2.GC_INIT_WITH_RECT)
    return (mask == cv2.GC_FGD) | (mask == cv2.GC_PR_FGD)


def _clean(mask: np.ndarray, seed) -> np.ndarray:
    """Open/close, keep the component containing the seed (or the largest), fill holes."""
    k = max(3, int(round(min(mask.shape) / 120)) | 1)
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))
    m = cv2.morphologyEx(mask.astype(np.uint8), cv2.MORPH_OPEN, kernel)
    m = cv2.morphologyEx(m, cv2.MORPH_CLOSE, kernel)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(m, connectivity=4)
    if n <= 1:
        return np.zeros_like(mask, dtype=bool)
    sx, sy = int(round(seed[0])), int(round(seed[1]))
    lab = labels[sy, sx] if 0 <= sy < m.shape[0] and 0 <= sx < m.shape[1] else 0
    if lab == 0:
        lab = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
    region = (labels == lab).astype(np.uint8)
    # Fill holes: everything not reachable from the border through the background.
    contours, _ = cv2.findContours(region, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    filled = np.zeros_like(region)
    cv2.drawContours(filled, contours, -1, 1, thickness=-1)
    return filled.astype(bool)


def segment_mask(frame: np.ndarray, point=None, box=None) -> np.ndarray:
    """Object mask (H, W) bool around a point or inside a box.

    Parameters
    ----------
    frame : (H, W, 3) float32
    point : (x, y), optional
        A point on the object. The frame's border is taken as background.
    box : (x0, y0, x1, y1), optional
        A box around the object.
    """
    if (point is None) == (box is None):
        raise VoodooError("Give either a point on the object or a box around it.")
    if point is not None:
        point = finite_array(point, "the point on the object", (2,))
    if box is not None:
        box = finite_array(box, "the box around the object", (4,))
    h, w = frame.shape[:2]
    f = min(1.0, WORK_SIZE / max(h, w))
    small = cv2.resize(frame, (int(round(w * f)), int(round(h * f))), interpolation=cv2.INTER_AREA)
    img8 = cv2.cvtColor((np.clip(small, 0, 1) * 255).astype(np.uint8), cv2.COLOR_RGB2BGR)
    sh, sw = img8.shape[:2]
    if box is not None:
        x0, y0, x1, y1 = (float(v) * f for v in box)
        x0, x1 = sorted((x0, x1))
        y0, y1 = sorted((y0, y1))
        x0, y0 = max(0, int(x0)), max(0, int(y0))
        x1, y1 = min(sw - 1, int(np.ceil(x1))), min(sh - 1, int(np.ceil(y1)))
        if x1 - x0 < 8 or y1 - y0 < 8:
            raise VoodooError("The box is too small; drag a box around the whole object.")
        mask = _grabcut_rect(img8, (x0, y0, x1 - x0, y1 - y0))
        seed = ((x0 + x1) / 2, (y0 + y1) / 2)
    else:
        px, py = float(point[0]) * f, float(point[1]) * f
        if not (0 <= px < sw and 0 <= py < sh):
            raise VoodooError(f"The point ({point[0]:.0f}, {point[1]:.0f}) is outside the frame.")
        seed = (px, py)
        # The frame's border is the background model: cut everything that differs from it,
        # keep the piece under the point, then cut again in a box around that piece.
        m = max(2, int(0.02 * max(sw, sh)))
        first = _grabcut_rect(img8, (m, m, sw - 2 * m, sh - 2 * m))
        n, labels = cv2.connectedComponents(first.astype(np.uint8), connectivity=4)
        lab = labels[int(py), int(px)]
        if lab == 0:
            raise VoodooError(
                "The point is on the background; click on the object itself or drag a box."
            )
        ys, xs = np.nonzero(labels == lab)
        pad = 0.1 * max(np.ptp(xs), np.ptp(ys)) + 4
        x0, y0 = max(0, int(xs.min() - pad)), max(0, int(ys.min() - pad))
        x1, y1 = min(sw - 1, int(xs.max() + pad)), min(sh - 1, int(ys.max() + pad))
        mask = _grabcut_rect(img8, (x0, y0, x1 - x0, y1 - y0))
    mask = _clean(mask, seed)
    if not mask.any():
        raise VoodooError(
            "No object found there; click on the object itself or drag a box around it."
        )
    if f != 1.0:
        mask = cv2.resize(mask.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST) > 0
    return mask


def mask_contour(mask: np.ndarray, tolerance: float = 1.5) -> np.ndarray:
    """Outline of the largest region of a mask: contour following, then simplification.

    Returns
    -------
    (k, 2) float64
        A validated contour (pixel centres of the region's border pixels, simplified).
    """
    m = np.ascontiguousarray(mask.astype(np.uint8))
    contours, _ = cv2.findContours(m, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    if not contours:
        raise VoodooError("The mask is empty: nothing to outline.")
    big = max(contours, key=cv2.contourArea).reshape(-1, 2).astype(np.float64)
    if len(big) < 3:
        raise VoodooError("The region is too small to outline.")
    pts = simplify_contour(big, tolerance)
    return validate_contour(pts, frame_size=(mask.shape[1], mask.shape[0]))


def segment_contour(frame: np.ndarray, point=None, box=None, tolerance: float = 1.5) -> np.ndarray:
    """Automatic outline of the object at a point or in a box (see :func:`segment_mask`)."""
    return mask_contour(segment_mask(frame, point=point, box=box), tolerance)
