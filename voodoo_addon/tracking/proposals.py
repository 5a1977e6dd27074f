"""Start poses for the modal fit when the extrapolated one fits badly.

Two sources of evidence that survive motion the pyramid cannot bridge (a 40 px jump at
8 fps, motion blur, a turn of 15 degrees between frames):

- :class:`MotionProposal` -- textured points of the blob followed from the previous frame by
  pyramidal Lucas-Kanade, kept when the backward track returns to where they started
  (forward-backward error, Kalal et al. 2010);
- :class:`FeatureMatcher` -- SIFT features of the template matched in the frame (for a blob
  that was lost, or a track gone wrong).

Both end in :class:`PointFit`: the point correspondences become a parameter vector -- a
similarity from RANSAC, then the mode amplitudes by regularised least squares on the
inliers -- which the coarse-to-fine fit then refines on the whole texture.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..blob.model import ActiveBlob
from .params import ParamLayout, node_positions, rotation, similarity_from_matrix

#: Fewest agreeing points accepted as evidence.
MIN_POINTS = 8
#: Forward-backward error (pixels) above which a followed point is dropped.
FB_ERROR = 1.5
#: Points followed from frame to frame.
MAX_POINTS = 160
#: Features are searched for in at most this many pixels along the longer side of the
#: frame, or of the box around where the blob was (about twice its size, so the blob still
#: spans half of it).
SEARCH_SIDE = 400
NEAR_SIDE = 240
#: SIFT's contrast threshold (OpenCV's default). To find a *lost* doll (or one whose fit is
#: too poor to be sure of it, see ``Tracker._feature_start``) it is halved, down to the
#: least, while the template gives fewer than :data:`TEMPLATE_FEATURES` keypoints: on faint
#: fur the default finds 2-5, too few to ever match, and a furry doll once lost was never
#: found again. A doll fitting fairly keeps the default: its fits start near it, and the
#: faint features' starts taken there put a turned half of ``plush_flip`` 25-30 px off.
CONTRAST = 0.04
LEAST_CONTRAST = 0.005
TEMPLATE_FEATURES = 64


def grey8(image: np.ndarray) -> np.ndarray:
    """uint8 grey of a uint8 or float [0, 1] RGB picture."""
    img = np.asarray(image)
    if img.dtype != np.uint8:
        clean = np.nan_to_num(img, nan=0.0, posinf=1.0, neginf=0.0)
        img = (np.clip(clean, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)
    return cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)


class PointFit:
    """Parameters that carry the blob's rest points onto observed positions.

    Parameters
    ----------
    blob : ActiveBlob
    layout : ParamLayout
    rest : (n, 2) float64
        Rest positions of the points (inside the blob).
    """

    def __init__(self, blob: ActiveBlob, layout: ParamLayout, rest: np.ndarray):
        self.blob = blob
        self.layout = layout
        self.rest = np.asarray(rest, np.float64)
        tri, weights = locate(blob, self.rest)
        self.triangle, self.weights = tri, weights
        nodes = blob.triangles[tri]  # (n, 3)
        k = layout.n_modes
        phi = blob.modes[:, :k].reshape(-1, 2, k)  # (m, 2, k)
        # Point displacement per unit mode amplitude: (n, 2, k).
        self.fields = np.einsum("nj,njdk->ndk", weights, phi[nodes])
        self.penalty = blob.mode_stiffness[:k]

    def positions(self, a: np.ndarray) -> np.ndarray:
        """Where the points are under parameters ``a`` (n, 2)."""
        nodes = node_positions(
            a,
            self.layout,
            self.blob.vertices,
            self.blob.modes[:, : self.layout.n_modes],
            self.blob.centre,
        )
        corner = nodes[self.blob.triangles[self.triangle]]
        return np.einsum("nj,njd->nd", self.weights, corner)

    def fit(
        self,
        idx: np.ndarray,
        target: np.ndarray,
        sim: np.ndarray,
        prior: np.ndarray,
        strength: float = 0.3,
    ) -> np.ndarray:
        """Parameters with similarity ``sim`` whose points ``idx`` land nearest ``target``.

        Parameters
        ----------
        idx : (n,) int
            Which points were observed.
        target : (n, 2) float64
            Where.
        sim : (4,) float64
            The similarity (translate-x, translate-y, rotate, log scale).
        prior : (P,) float64
            Parameters whose modes the fit is pulled towards (and whose other entries it
            keeps), with weight ``strength`` times each mode's stiffness.
        """
        lay = self.layout
        out = np.array(prior, dtype=np.float64)
        out[:4] = sim
        k = lay.n_modes
        if not k or len(idx) < MIN_POINTS:
            return out
        c = self.blob.centre
        s = np.exp(sim[3])
        # Observed local shape: undo the similarity.
        local = (target - c - sim[:2]) @ rotation(sim[2]) / s  # (n, 2)
        base = self.rest[idx] - c
        jac = self.fields[idx].reshape(-1, k)  # (2n, k)
        rhs = (local - base).ravel()
        reg = strength * len(idx) * self.penalty / max(float(self.penalty.mean()), 1e-12)
        lhs = jac.T @ jac + np.diag(reg + 1e-9)
        a0 = prior[lay.modes]
        try:
            out[lay.modes] = np.linalg.solve(lhs, jac.T @ rhs + reg * a0)
        except np.linalg.LinAlgError:
            out[lay.modes] = a0
        return out


def locate(blob: ActiveBlob, points: np.ndarray):
    """Containing triangle (n,) and barycentric weights (n, 3) of rest points.

    Points outside the mesh get the nearest triangle's (clipped) weights.
    """
    v = blob.vertices[blob.triangles]  # (t, 3, 2)
    a, b, c = v[:, 0], v[:, 1], v[:, 2]
    e1, e2 = b - a, c - a
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]  # (t,)
    d = points[:, None, :] - a[None]  # (n, t, 2)
    l1 = (d[..., 0] * e2[:, 1] - d[..., 1] * e2[:, 0]) / det
    l2 = (e1[:, 0] * d[..., 1] - e1[:, 1] * d[..., 0]) / det
    lam = np.stack([1.0 - l1 - l2, l1, l2], axis=-1)  # (n, t, 3)
    worst = lam.min(axis=-1)  # (n, t): >= 0 inside
    tri = worst.argmax(axis=1)
    w = np.clip(lam[np.arange(len(points)), tri], 0.0, 1.0)
    w /= w.sum(axis=1, keepdims=True)
    return tri, w


class MotionProposal:
    """The blob's motion from the previous frame, from textured points followed by LK.

    Parameters
    ----------
    blob : ActiveBlob
    layout : ParamLayout
    """

    def __init__(self, blob: ActiveBlob, layout: ParamLayout):
        tex = grey8(blob.texture)
        mask = np.zeros(tex.shape, np.uint8)
        poly = np.round(blob.contour - blob.texture_origin).astype(np.int32)
        cv2.fillPoly(mask, [poly], 255)
        mask = cv2.erode(mask, np.ones((5, 5), np.uint8))
        spacing = max(4.0, 0.6 * np.sqrt(blob.n_pixels / MAX_POINTS))
        pts = cv2.goodFeaturesToTrack(tex, MAX_POINTS, 0.01, spacing, mask=mask, blockSize=7)
        pts = np.zeros((0, 2)) if pts is None else pts.reshape(-1, 2).astype(np.float64)
        self.fit = PointFit(blob, layout, pts + blob.texture_origin)
        self.size = blob.frame_size

    def __len__(self) -> int:
        return len(self.fit.rest)

    def propose(
        self, previous: np.ndarray, frame: np.ndarray, a_prev: np.ndarray, margin: float = 64.0
    ):
        """Parameters for ``frame`` from the points' motion since ``previous`` (or None)."""
        if len(self) < MIN_POINTS:
            return None
        p = self.fit.positions(a_prev)
        w, h = self.size
        inside = (p[:, 0] >= 0) & (p[:, 1] >= 0) & (p[:, 0] <= w - 1) & (p[:, 1] <= h - 1)
        if np.count_nonzero(inside) < MIN_POINTS:
            return None
        idx = np.nonzero(inside)[0]
        p = p[idx]
        lo = np.maximum(np.floor(p.min(axis=0) - margin), 0).astype(int)
        hi = np.minimum(np.ceil(p.max(axis=0) + margin) + 1, [w, h]).astype(int)
        x0, y0 = lo
        x1, y1 = hi
        g0 = grey8(previous[y0:y1, x0:x1])
        g1 = grey8(frame[y0:y1, x0:x1])
        src = (p - lo).astype(np.float32).reshape(-1, 1, 2)
        crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 20, 0.03)
        fwd, st1, _ = cv2.calcOpticalFlowPyrLK(
            g0, g1, src, None, winSize=(21, 21), maxLevel=4, criteria=crit
        )
        back, st2, _ = cv2.calcOpticalFlowPyrLK(
            g1, g0, fwd, None, winSize=(21, 21), maxLevel=4, criteria=crit
        )
        fb = np.linalg.norm((back - src).reshape(-1, 2), axis=1)
        good = (st1.ravel() > 0) & (st2.ravel() > 0) & (fb < FB_ERROR)
        if np.count_nonzero(good) < MIN_POINTS:
            return None
        before = p[good]
        after = fwd.reshape(-1, 2)[good].astype(np.float64) + lo
        return fit_motion(self.fit, idx[good], before, after, a_prev)


def fit_motion(fit: PointFit, idx, before, after, a_prev):
    """Compose a RANSAC similarity of ``before -> after`` with ``a_prev``; fit the modes."""
    mat, inl = cv2.estimateAffinePartial2D(
        before.astype(np.float32),
        after.astype(np.float32),
        method=cv2.RANSAC,
        ransacReprojThreshold=3.0,
        maxIters=500,
        confidence=0.99,
    )
    if mat is None or inl is None or int(inl.sum()) < MIN_POINTS:
        return None
    keep = inl.ravel() > 0
    c = fit.blob.centre
    a_mat = mat[:, :2]
    s_new = float(np.sqrt(abs(np.linalg.det(a_mat))))
    if not np.isfinite(mat).all() or s_new <= 1e-6:
        return None
    theta = float(np.arctan2(mat[1, 0], mat[0, 0]))
    sim = np.empty(4)
    # y = A x + b applied to V = c + t + s R L:  t' = A (c + t) + b - c.
    sim[:2] = a_mat @ (c + a_prev[:2]) + mat[:, 2] - c
    sim[2] = a_prev[2] + theta
    sim[3] = a_prev[3] + np.log(s_new)
    return fit.fit(idx[keep], after[keep], sim, a_prev)


class FeatureMatcher:
    """Pose of the blob from SIFT features of the template matched in a frame.

    Parameters
    ----------
    blob : ActiveBlob
        Its texture crop and outline give the template keypoints (computed lazily).
    layout : ParamLayout
    """

    def __init__(self, blob: ActiveBlob, layout: ParamLayout):
        self.blob = blob
        self.layout = layout
        self._made = {}  # lost (bool) -> (detector, points, descriptors, PointFit)
        self._making = None  # the keypoints being made ahead (see prepare)
        self._ahead = None  # (frame, box, detector, Future) of look_ahead
        self._ending = None  # a detection dropped while it ran (see drop_ahead)

    def prepare(self, executor) -> None:
        """Make the template's keypoints, plain and faint, on ``executor`` ahead of need.

        Detecting them took 53-73 ms on the clips measured (the faint ones of a furry doll
        are sought at several contrasts); made when the first search asks, they fall on the
        frame where the doll is folding or lost. They are the same keypoints whenever they
        are made.
        """
        if self._making is None and not self._made:
            self._making = executor.submit(self._make, True)

    def _template(self, lost: bool):
        """The detector and the template's keypoints for a doll lost or not (made once)."""
        if self._making is not None:
            making, self._making = self._making, None
            making.result()
        return self._make(lost)

    def _make(self, lost: bool):
        """:meth:`_template` itself.

        A lost doll shares the plain template when it has :data:`TEMPLATE_FEATURES`
        keypoints; otherwise fainter ones are sought (:data:`CONTRAST`).
        """
        if lost in self._made:
            return self._made[lost]
        if lost:
            plain = self._make(False)
            if len(plain[1]) >= TEMPLATE_FEATURES:
                self._made[lost] = plain
                return plain
        tex = self.blob.texture
        mask = np.zeros(tex.shape[:2], np.uint8)
        poly = np.round(self.blob.contour - self.blob.texture_origin).astype(np.int32)
        cv2.fillPoly(mask, [poly], 255)
        contrast = CONTRAST
        while True:
            if lost:
                contrast = max(0.5 * contrast, LEAST_CONTRAST)
            detector = cv2.SIFT_create(nfeatures=800, contrastThreshold=contrast)
            kp, desc = detector.detectAndCompute(grey8(tex), mask)
            if not lost or len(kp) >= TEMPLATE_FEATURES or contrast <= LEAST_CONTRAST:
                break
        pts = np.array([k.pt for k in kp], dtype=np.float64).reshape(-1, 2)
        pts += self.blob.texture_origin
        fit = PointFit(self.blob, self.layout, pts) if len(pts) else None
        self._made[lost] = (detector, pts, desc, fit)
        return self._made[lost]

    def guess(self, frame: np.ndarray, near: np.ndarray, box=None, lost: bool = False):
        """Parameters with the similarity found in ``frame``, the modes fitted to the matches.

        ``box`` (x0, y0, x1, y1) limits the search to a region of the frame (a blob that is
        not lost is near where it was); by default the whole frame is searched. ``lost``:
        search as for a lost doll -- fainter features if its template has too few
        (:data:`CONTRAST`).

        Returns
        -------
        (P,) float64 or None
            None when too few features agree. Entries other than the similarity and modes
            are those of ``near``.
        """
        detector, pts_t, desc_t, fit = self._template(lost)
        if desc_t is None or fit is None or len(pts_t) < MIN_POINTS:
            self.drop_ahead()
            return None
        found = self._looked_ahead(frame, box, detector)
        if found is None:
            found = self._detect(frame, box, detector)
        kp, desc, shrink, (x0, y0) = found
        if desc is None or len(kp) < MIN_POINTS:
            return None
        pairs = cv2.BFMatcher(cv2.NORM_L2).knnMatch(desc_t, desc, k=2)
        good = [m[0] for m in pairs if len(m) == 2 and m[0].distance < 0.75 * m[1].distance]
        if len(good) < MIN_POINTS:
            return None
        idx = np.array([m.queryIdx for m in good])
        dst = np.array([kp[m.trainIdx].pt for m in good], dtype=np.float64)
        dst = (dst + 0.5) / shrink - 0.5 + (x0, y0)
        mat, inliers = cv2.estimateAffinePartial2D(
            pts_t[idx].astype(np.float32),
            dst.astype(np.float32),
            method=cv2.RANSAC,
            ransacReprojThreshold=4.0,
            maxIters=2000,
        )
        if mat is None or inliers is None or int(inliers.sum()) < MIN_POINTS:
            return None
        try:
            sim = similarity_from_matrix(mat, self.blob.centre, theta_near=float(near[2]))
        except ValueError:
            return None
        keep = inliers.ravel() > 0
        prior = np.array(near, dtype=np.float64)
        prior[self.layout.modes] = 0.0
        return fit.fit(idx[keep], dst[keep], sim, prior)

    def look_ahead(self, executor, frame: np.ndarray, box=None, lost: bool = False) -> None:
        """Detect the features of ``frame`` (in ``box``) on ``executor`` for the next :meth:`guess`.

        The detection is most of a guess's time (about 6 of 8 ms near a doll): made on a
        helper thread while the tracker fits its other starts, it is ready when the search
        asks. A guess with other arguments detects again itself; the features are the same
        whichever thread detects them. :meth:`drop_ahead` forgets them.
        """
        self.drop_ahead()
        detector, pts_t, desc_t, fit = self._template(lost)
        if desc_t is None or fit is None or len(pts_t) < MIN_POINTS:
            return  # a template too faint to match: the guess gives up before detecting
        job = executor.submit(self._detect, frame, box, detector)
        self._ahead = (frame, None if box is None else tuple(box), detector, job)

    def drop_ahead(self, wait: bool = True) -> None:
        """Forget a detection made ahead; ``wait`` for one that has begun to end.

        Without ``wait``, one already begun is left to end on its own (its features are
        never used) and is waited for by the next call that looks ahead, guesses or drops
        with ``wait``, before the detector is used again.
        """
        if self._ahead is not None:
            ahead, self._ahead = self._ahead, None
            if not ahead[3].cancel():
                self._ending = ahead[3]
        if wait and self._ending is not None:
            ending, self._ending = self._ending, None
            ending.result()

    def _looked_ahead(self, frame, box, detector):
        """The detection made ahead for these arguments, or None (see :meth:`look_ahead`)."""
        if self._ahead is None:
            self.drop_ahead()  # one left running from an earlier frame: the detector is shared
            return None
        ahead, self._ahead = self._ahead, None
        found = ahead[3].result()
        same = ahead[0] is frame and ahead[2] is detector
        return found if same and ahead[1] == (None if box is None else tuple(box)) else None

    @staticmethod
    def _detect(frame, box, detector):
        """(keypoints, descriptors, shrink, (x0, y0)) of ``frame`` in ``box``."""
        x0 = y0 = 0
        if box is not None:
            x0, y0, x1, y1 = (int(v) for v in box)
            frame = frame[y0:y1, x0:x1]
        grey = grey8(frame)
        # SIFT is scale-invariant: a large region is searched at a lower resolution.
        shrink = min(1.0, (SEARCH_SIDE if box is None else NEAR_SIDE) / max(grey.shape))
        if shrink < 1.0:
            grey = cv2.resize(grey, None, fx=shrink, fy=shrink, interpolation=cv2.INTER_AREA)
        kp, desc = detector.detectAndCompute(grey, None)
        return kp, desc, shrink, (x0, y0)
