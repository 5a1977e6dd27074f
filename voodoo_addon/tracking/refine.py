"""The local stage: node offsets on top of the modal fit, for what the modes cannot bend.

Twenty smooth fields cannot follow a sheet crumpling into creases. After the modal fit the
mesh nodes may move on their own, by offsets ``U`` (m, 2) in the blob's rest frame::

    V = c + t + s R (X - c + Phi a + U)

found by robust Gauss-Newton on the same comparison as the fit (lighting patches projected
out, covered and turned-away triangles left out): the frame's gradient at each template
pixel, spread to its triangle's nodes by the barycentric weights, gives the Jacobian; a
Lorentzian gives the weights (IRLS). The offsets are held smooth by the mesh's graph
Laplacian and small by a ridge, carried from frame to frame in the rest frame (so they turn
and scale with the doll), and cut so that no triangle folds. They move the tracked mesh
only: the parameters -- the similarity and the named modes that drive the character --
are the modal fit's.
"""

from __future__ import annotations

import cv2
import numpy as np

from .evaluation import Evaluation
from .folding import FoldGuard
from .params import ParamLayout, rotation
from .warp import REMAP_ROW

#: Pixels the normal equations are summed over (an even subsample of the level's).
NORMAL_PIXELS = 6000
#: Gauss-Newton iterations at most per frame.
ITERATIONS = 5
#: Smoothness of the offsets (graph Laplacian), relative to the data's mean curvature.
SMOOTH = 0.02
#: Pull of the offsets towards none (the modal fit), relative likewise.
RIDGE = 0.002
#: How fast the hold on the offsets grows with the modal fit's confidence (see hold).
HOLD_POWER = 1.0
#: Stop when the offsets change by less than this (level-0 pixels RMS over the nodes).
TOLERANCE = 0.05


def sample_gradients(grad_image: np.ndarray, positions: np.ndarray, n: int) -> np.ndarray:
    """The derivatives (n, 3, 2) at warped template pixels.

    ``positions`` (2, n_pad) as :meth:`Level.positions` gives them, in the picture's pixels.
    """
    n_pad = positions.shape[1]
    cols = min(n_pad, REMAP_ROW)
    shape = (n_pad // cols, cols)
    out = cv2.remap(
        grad_image,
        positions[0].reshape(shape),
        positions[1].reshape(shape),
        interpolation=cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_REPLICATE,
    ).reshape(-1, 6)[:n]
    return out.reshape(n, 2, 3).transpose(0, 2, 1)


def hold(confidence: float) -> float:
    """How firmly the offsets are held, given how well the modes alone fit.

    Where the modes explain the frame (their confidence is high), local freedom only fits
    noise; where they fall short (a crumple), the nodes get the freedom to follow.
    """
    c = min(max(confidence, 0.05), 0.95)
    return (c / (1.0 - c)) ** HOLD_POWER


def graph_laplacian(n_nodes: int, triangles: np.ndarray) -> np.ndarray:
    """``D - A`` (m, m) of the mesh's edge graph."""
    e = np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    lap = np.zeros((n_nodes, n_nodes))
    lap[e[:, 0], e[:, 1]] = lap[e[:, 1], e[:, 0]] = -1.0
    lap[np.diag_indices(n_nodes)] = -lap.sum(axis=1)
    return lap


class LocalRefiner:
    """Node offsets on the finest level's comparison.

    Parameters
    ----------
    step : DifferenceDecomposition
        The finest level the tracker uses (its comparison is the one refined).
    blob : ActiveBlob
    layout : ParamLayout
    guard : FoldGuard
    sigma : float
        Scale of the Lorentzian weights (image units).
    nodes : callable
        ``(a, offsets) -> (m, 2)`` frame nodes.
    quality : QualityMeter
    """

    def __init__(
        self, step, blob, layout: ParamLayout, guard: FoldGuard, sigma: float, nodes, quality
    ):
        level = step.level
        self.step_ = step
        self.level = level
        self.layout = layout
        self.guard = guard
        self.sigma = float(sigma)
        self._nodes = nodes
        self._quality = quality
        self._vertices, self._centre = blob.vertices, blob.centre
        self._modes = blob.modes[:, : layout.n_modes]
        m = len(level.vertices)
        self.m = m
        # The normal equations are summed over an even subsample of the pixels (a few dozen
        # per node pin its motion down as well as hundreds do), taken triangle by triangle
        # so that every triangle's sums are one reduceat.
        step = max(1, len(level) // NORMAL_PIXELS)
        picked = np.arange(0, len(level), step)
        picked = picked[np.argsort(level.triangle[picked], kind="stable")]
        self.pick = picked
        tri_of = level.triangle[picked]
        self._starts = np.r_[0, np.nonzero(np.diff(tri_of))[0] + 1]
        tris = tri_of[self._starts]  # the triangles that have picked pixels
        corners = level.geometry.triangles[tris]  # (t', 3)
        w = level.geometry.weights[picked]  # (n', 3)
        # Products of corner weights, (n', 9): pair (j, k) of the pixel's three corners.
        self._pair_weights = np.stack(
            [w[:, j] * w[:, k] for j in range(3) for k in range(3)], 1
        ).astype(np.float32)
        self.weights = w
        # Where each triangle's (pair, entry) sum goes in the (3, m, m) Hessian entries.
        pair_nodes = np.stack(
            [corners[:, j] * m + corners[:, k] for j in range(3) for k in range(3)], 1
        )  # (t', 9)
        self._bins = (pair_nodes[:, :, None] + np.arange(3) * m * m).ravel()  # (t' * 9 * 3,)
        self._corners = corners.ravel()  # (t' * 3,)
        lap = graph_laplacian(m, level.geometry.triangles)
        self.laplacian = np.kron(lap, np.eye(2))  # (2m, 2m), x and y interleaved

    def gradients(self, image: np.ndarray) -> np.ndarray:
        """The level picture's x and y derivatives, stacked (h, w, 6) float32."""
        gx = cv2.Sobel(image, cv2.CV_32F, 1, 0, ksize=3, scale=1.0 / 8.0)
        gy = cv2.Sobel(image, cv2.CV_32F, 0, 1, ksize=3, scale=1.0 / 8.0)
        return np.ascontiguousarray(np.concatenate([gx, gy], axis=2))

    def normal_equations(self, ev: Evaluation, grads: np.ndarray):
        """``J^T W J`` (2m, 2m) and ``J^T W r`` (2m,) for the node positions (level pixels).

        ``grads`` (n, 3, 2): the frame's derivatives at the warped template pixels.
        """
        m = self.m
        d = ev.difference[self.pick]  # (n', 3): template - frame
        w = 1.0 / (1.0 + d * d * np.float32(0.5 / self.sigma**2))  # Lorentzian IRLS weights
        w *= ev.use[self.pick, None]
        g = grads[self.pick]  # (n', 3, 2)
        gx = np.ascontiguousarray(g[:, :, 0])
        gy = np.ascontiguousarray(g[:, :, 1])
        wgx, wgy = w * gx, w * gy
        entries = np.stack(  # (n', 3): the pixel's xx, xy, yy curvature
            [
                np.einsum("nc,nc->n", wgx, gx),
                np.einsum("nc,nc->n", wgx, gy),
                np.einsum("nc,nc->n", wgy, gy),
            ],
            axis=1,
        )
        rx = np.einsum("nc,nc->n", wgx, d).astype(np.float64)  # r = t - s, dr/dx = -g
        ry = np.einsum("nc,nc->n", wgy, d).astype(np.float64)
        # Per triangle: sum over its pixels of (corner-pair weight) x (entry): (t', 9, 3).
        pw = self._pair_weights
        per_tri = np.stack(
            [np.add.reduceat(pw * entries[:, e : e + 1], self._starts, axis=0) for e in range(3)],
            axis=2,
        )
        acc = np.bincount(self._bins, weights=per_tri.ravel(), minlength=3 * m * m)
        acc = acc.reshape(3, m, m)
        hess = np.empty((m, 2, m, 2))
        hess[:, 0, :, 0] = acc[0]
        hess[:, 0, :, 1] = acc[1]
        hess[:, 1, :, 0] = acc[1]
        hess[:, 1, :, 1] = acc[2]
        # The right-hand side the same way: per triangle and corner, then per node.
        bw = self.weights
        rhs = np.add.reduceat(
            np.concatenate([bw * rx[:, None], bw * ry[:, None]], axis=1), self._starts, axis=0
        )  # (t', 6): x for the three corners, then y
        grad = np.stack(
            [
                np.bincount(self._corners, weights=rhs[:, :3].ravel(), minlength=m),
                np.bincount(self._corners, weights=rhs[:, 3:].ravel(), minlength=m),
            ],
            axis=1,
        )
        return hess.reshape(2 * m, 2 * m), grad.ravel()

    def run(self, a, confidence, pictures, offsets, template=None):
        """Refine the node offsets on a fit's frame, from ``offsets`` (m, 2).

        Parameters
        ----------
        a : (P,) float64
            The modal fit.
        confidence : float
            Its confidence (how firmly the offsets are held, see :func:`hold`).
        pictures : (FramePyramid, origin)
            The frame as the fit read it.
        offsets : (m, 2) float64
            Where to start (the last frame's), rest frame, level-0 pixels.
        template : (n, 3) float32, optional
            What the pixels are compared with instead of the template.

        Returns
        -------
        (offsets, Quality, Evaluation) of the best iterate, or None.
        """
        images, origin = pictures
        step, level = self.step_, self.level
        held = hold(confidence)
        org, box = step.bind(images[step.index], origin)
        grad_image = self.gradients(images[step.index])
        bare = self._vertices - self._centre  # the modal shape X - c + Phi a
        if self.layout.n_modes:
            bare = bare + (self._modes @ a[self.layout.modes]).reshape(-1, 2)
        # The offsets carried from the last frame sit on this frame's modal shape: pull them
        # back as far as needed for no triangle to fold there.
        u = self.guard.shape_step(bare, offsets) * offsets
        best, occluded = None, None
        for _ in range(ITERATIONS):
            nodes = self._nodes(a, u) * level.scale
            ev = step.evaluate(a, org, box, nodes, occluded, template=template)
            if ev is None:
                break
            if occluded is None:
                occluded = ev.occluded_triangles
            if best is not None and ev.residual >= best[1].residual:
                break
            best = (u, ev)
            pos = level.positions(a, nodes) - org[:, None]
            grads = sample_gradients(grad_image, pos, len(level))
            du = self.step(ev, grads, a, u, bare + u, held)
            u = u + du
            if np.sqrt((du**2).sum(axis=1).mean()) < TOLERANCE:
                nodes = self._nodes(a, u) * level.scale
                ev = step.evaluate(a, org, box, nodes, occluded, template=template)
                if ev is not None and ev.residual < best[1].residual:
                    best = (u, ev)
                break
        if best is None:
            return None
        u, ev = best
        return u, self._quality(ev, a), ev

    def step(self, ev: Evaluation, grads, a, offsets, shape, held=1.0) -> np.ndarray:
        """One Gauss-Newton step of the offsets (m, 2), level-0 pixels, rest frame.

        ``held`` multiplies the regularisers. The step is cut so that no triangle
        folds.
        """
        hess, grad = self.normal_equations(ev, grads)
        scale = np.trace(hess) / len(hess)
        if not scale > 0:
            return np.zeros_like(offsets)
        f = self.level.scale
        s = np.exp(a[3]) * f  # level pixels per rest-frame pixel
        rot = rotation(a[2])
        # Regularisers on the offsets, written for the frame-level node motion
        # dV = s R dU: |L (U + dU)|^2 and |U + dU|^2 become s^-2 terms.
        u_frame = (offsets @ rot.T).ravel() * s
        reg = held * scale * (SMOOTH * self.laplacian + RIDGE * np.eye(len(hess)))
        lhs = hess + reg
        rhs = grad - reg @ u_frame
        try:
            dv = np.linalg.solve(lhs, rhs).reshape(-1, 2)
        except np.linalg.LinAlgError:
            return np.zeros_like(offsets)
        du = (dv @ rot) / s  # back to the rest frame, level-0 pixels
        tau = self.guard.shape_step(shape, du)
        return tau * du
