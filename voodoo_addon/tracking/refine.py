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

import numpy as np

from ..blob.mesh import mesh_edges
from . import kernels
from .evaluation import Evaluation, sample
from .folding import FoldGuard
from .params import ParamLayout, rotation

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
#: When the caller keeps the offsets only above some confidence (``needed``), the iterate
#: after this many steps is judged: if its confidence is more than :data:`STILL_TO_GAIN`
#: short of it, the rest of the steps are not made. On the clip suite (753 runs of the bag,
#: the crumpled sheet and five more clips) the steps after the second added at most 0.025
#: to the confidence, and every run that was kept had its needed gain within 0.014 after
#: two steps; about half of the runs the bag does not keep stop there.
JUDGED_AFTER = 2
STILL_TO_GAIN = 0.03


def hold(confidence: float, power: float = HOLD_POWER) -> float:
    """How firmly the offsets are held, given how well the modes alone fit.

    Where the modes explain the frame (their confidence is high), local freedom only fits
    noise; where they fall short (a crumple), the nodes get the freedom to follow. A
    ``power`` below :data:`HOLD_POWER` moves the hold towards 1: less firm above a
    confidence of 0.5 (where the local stage's *opening* rule uses it), firmer below.
    """
    c = min(max(confidence, 0.05), 0.95)
    return (c / (1.0 - c)) ** power


def graph_laplacian(n_nodes: int, triangles: np.ndarray) -> np.ndarray:
    """``D - A`` (m, m) of the mesh's edge graph."""
    e = mesh_edges(triangles)
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
        # The iterations compare and sum the normal equations on an even subsample of the
        # pixels (a few dozen per node pin its motion down as well as hundreds do); only the
        # offsets they settle on are judged on every pixel.
        sub, self.rows = level.every(len(level) // NORMAL_PIXELS)
        self.sub_step = step.on(sub)
        # The quality meter's own pixels: the confidence of an iterate without comparing
        # all of the level (see :data:`JUDGED_AFTER`).
        self._probe = level.every(quality.step, patches=False)[0]
        self.pick = np.arange(len(sub), dtype=np.int64)
        self._corners = sub.corners
        self._weights = sub.weights.astype(np.float64)
        self._picked = sub.weights  # float32, for positions
        self._regulariser = None  # SMOOTH * Laplacian + RIDGE * I, made on first use
        self._k = 0.5 / self.sigma**2
        lap = graph_laplacian(m, level.geometry.triangles)
        self.laplacian = np.kron(lap, np.eye(2))  # (2m, 2m), x and y interleaved

    def bare(self, a: np.ndarray) -> np.ndarray:
        """The modal shape ``X - c + Phi a`` (m, 2), rest frame, level-0 pixels."""
        bare = self._vertices - self._centre
        if self.layout.n_modes:
            bare = bare + (self._modes @ a[self.layout.modes]).reshape(-1, 2)
        return bare

    def sample_gradients(self, image: np.ndarray, nodes: np.ndarray, origin) -> np.ndarray:
        """The picture's derivatives (n', 6) at the picked pixels of the mesh on ``nodes``.

        Central differences of bilinear samples one pixel to either side (the picture is
        blurred like the template already, so they need no smoothing of their own): four
        samples per pixel instead of filtering the whole picture. ``nodes`` (m, 2) in level
        pixels, ``origin`` the picture's top-left corner there. Columns: the x derivative of
        each channel, then the y derivative.
        """
        n = len(self.pick)
        pos = np.empty((2, n), np.float32)
        kernels.positions(self._corners, self._picked, nodes, *map(float, origin), pos)
        out = np.empty((n, 2 * image.shape[2]), np.float32)
        kernels.gradients(image, pos, out)
        return out

    def normal_equations(self, ev: Evaluation, grads: np.ndarray):
        """``J^T W J`` (2m, 2m) and ``J^T W r`` (2m,) for the node positions (level pixels).

        ``grads`` (n', 6): the frame's derivatives at the picked pixels
        (:meth:`sample_gradients`); Lorentzian IRLS weights (see
        :func:`.kernels.normal_equations`).
        """
        m = self.m
        hess = np.empty((m, 2, m, 2))
        grad = np.empty((m, 2))
        kernels.normal_equations(
            self.pick,
            ev.difference,
            ev.use,
            grads,
            self._corners,
            self._weights,
            self._k,
            hess,
            grad,
        )
        return hess.reshape(2 * m, 2 * m), grad.ravel()

    def run(
        self,
        a,
        confidence,
        pictures,
        offsets,
        template=None,
        covered=None,
        needed=None,
        power=HOLD_POWER,
    ):
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
        covered : (t,) bool, optional
            Triangles to leave out as covered, instead of testing for occlusion.
        needed : float, optional
            The confidence below which the caller will not keep the offsets: a run that
            is still far from it after :data:`JUDGED_AFTER` steps stops there (None).
        power : float
            How the hold on the offsets grows with ``confidence`` (see :func:`hold`).

        Returns
        -------
        (offsets, Quality, Evaluation) of the best iterate, or None.
        """
        images, origin = pictures
        step, level = self.step_, self.level
        held = hold(confidence, power)
        org, box = step.bind(images[step.index], origin)
        image = images[step.index]
        plain = images.judged(step.index)  # what the confidence is measured on, if not image
        bare = self.bare(a)
        # The offsets carried from the last frame sit on this frame's modal shape: pull them
        # back as far as needed for no triangle to fold there.
        u = self.guard.shape_step(bare, offsets) * offsets
        sub_template = None if template is None else np.ascontiguousarray(template[self.rows])
        best, occluded, outliers = None, covered, None

        def compare(u):
            nodes = self._nodes(a, u) * level.scale
            ev = self.sub_step.evaluate(
                a, org, box, nodes, occluded, template=sub_template, outliers=outliers
            )
            return nodes, ev

        for steps in range(ITERATIONS):
            nodes, ev = compare(u)
            if ev is None:
                break
            if occluded is None:
                occluded, outliers = ev.occluded_triangles, ev.outliers
            if best is not None and ev.residual >= best[1].residual:
                break
            best = (u, ev)
            if steps == JUDGED_AFTER and needed is not None:
                if self.value(a, org, box, nodes, ev.hidden, plain) < needed - STILL_TO_GAIN:
                    return None
            grads = self.sample_gradients(image, nodes, org)
            du = self.step(ev, grads, a, u, bare + u, held)
            u = u + du
            if np.sqrt((du**2).sum(axis=1).mean()) < TOLERANCE:
                ev = compare(u)[1]
                if ev is not None and ev.residual < best[1].residual:
                    best = (u, ev)
                break
        if best is None:
            return None
        u = best[0]
        nodes = self._nodes(a, u) * level.scale
        ev = step.evaluate(a, org, box, nodes, occluded, template=template)
        if ev is None:
            return None
        return u, self._quality(ev, a, plain), ev

    def value(self, a, org, box, nodes, hidden, plain=None) -> float:
        """The confidence (``Quality.value``) the full comparison would give at ``nodes``.

        Read on the quality meter's own pixels only: the same number for a tenth of the
        work. ``org`` and ``box`` as the finest level is bound, ``nodes`` in its pixels,
        ``hidden`` (t,) bool or None the triangles turned away at ``a`` (``Evaluation.hidden``),
        ``plain`` the picture to read instead of the bound one (``FramePyramid.judged``).
        """
        step = self.step_
        found = sample(self._probe, a, org, box, step.backend, nodes, self.sub_step.cover, plain)
        if found is None:
            return 0.0
        samples, valid, _ = found
        compared = np.ones(len(self._probe), bool) if valid is None else valid
        if hidden is not None:
            compared = compared & ~hidden[self._probe.triangle]
        return self._quality.measure(samples, compared, a).value

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
        if self._regulariser is None:
            self._regulariser = SMOOTH * self.laplacian + RIDGE * np.eye(len(hess))
        reg = (held * scale) * self._regulariser
        lhs = hess + reg
        rhs = grad - reg @ u_frame
        try:
            dv = np.linalg.solve(lhs, rhs).reshape(-1, 2)
        except np.linalg.LinAlgError:
            return np.zeros_like(offsets)
        du = (dv @ rot) / s  # back to the rest frame, level-0 pixels
        tau = self.guard.shape_step(shape, du)
        return tau * du
