"""Finding a lost blob again: SIFT features of the template matched against the frame."""

from __future__ import annotations

import cv2
import numpy as np

from ..blob import ActiveBlob
from .params import similarity_from_matrix

#: Fewest RANSAC inliers accepted as a sighting.
MIN_INLIERS = 8


def _gray8(image: np.ndarray) -> np.ndarray:
    clean = np.nan_to_num(image, nan=0.0, posinf=1.0, neginf=0.0)
    return cv2.cvtColor((np.clip(clean, 0, 1) * 255).astype(np.uint8), cv2.COLOR_RGB2GRAY)


class FeatureMatcher:
    """Similarity guess for a blob from feature matches (used only while it is lost).

    Parameters
    ----------
    blob : ActiveBlob
        Its texture crop and outline give the template keypoints (computed lazily).
    """

    def __init__(self, blob: ActiveBlob):
        self.blob = blob
        self._template = None
        self._detector = None

    def _prepare(self):
        if self._template is not None:
            return
        self._detector = cv2.SIFT_create(nfeatures=800)
        tex = self.blob.texture
        mask = np.zeros(tex.shape[:2], np.uint8)
        poly = np.round(self.blob.contour - self.blob.texture_origin).astype(np.int32)
        cv2.fillPoly(mask, [poly], 255)
        kp, desc = self._detector.detectAndCompute(_gray8(tex), mask)
        pts = np.array([k.pt for k in kp], dtype=np.float32).reshape(-1, 2)
        self._template = (pts + self.blob.texture_origin.astype(np.float32), desc)

    def guess(self, frame: np.ndarray, centre: np.ndarray, near: np.ndarray):
        """Parameters with the similarity found in ``frame`` and the rest of ``near``.

        Returns
        -------
        (P,) float64 or None
            None when too few features agree.
        """
        self._prepare()
        pts_t, desc_t = self._template
        if desc_t is None or len(pts_t) < MIN_INLIERS:
            return None
        kp, desc = self._detector.detectAndCompute(_gray8(frame), None)
        if desc is None or len(kp) < MIN_INLIERS:
            return None
        pairs = cv2.BFMatcher(cv2.NORM_L2).knnMatch(desc_t, desc, k=2)
        good = [m[0] for m in pairs if len(m) == 2 and m[0].distance < 0.75 * m[1].distance]
        if len(good) < MIN_INLIERS:
            return None
        src = pts_t[[m.queryIdx for m in good]]
        dst = np.array([kp[m.trainIdx].pt for m in good], dtype=np.float32)
        mat, inliers = cv2.estimateAffinePartial2D(
            src, dst, method=cv2.RANSAC, ransacReprojThreshold=3.0, maxIters=2000
        )
        if mat is None or inliers is None or int(inliers.sum()) < MIN_INLIERS:
            return None
        try:
            sim = similarity_from_matrix(mat, centre, theta_near=float(near[2]))
        except ValueError:
            return None
        out = np.array(near, dtype=np.float64)
        out[:4] = sim
        n_modes = self.blob.n_modes
        out[4 : 4 + n_modes] = 0.0
        return out
