"""Gaussian interpolants on the mesh nodes (paper §6-7, after Sclaroff's modal matching).

``h(x) = [g(x), p(x)] A^-1[:, :m]`` with Gaussians ``g_k(x) = exp(-|x - X_k|^2 / (2 s^2))``
augmented by the linear polynomials ``p(x) = (1, x, y)`` under the usual side conditions
``sum_k c_k = 0, sum_k c_k X_k = 0``. Then

* ``h_i(X_j) = delta_ij`` (interpolation), and
* constant and linear fields are reproduced *exactly* everywhere (``sum_i h_i(x) = 1``,
  ``sum_i h_i(x) X_i = x``), so translations and the linearised rotation carry zero strain
  energy; plain Gaussian interpolants only approximate them (docs/design.md, *Data flow*,
  step 4).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..errors import VoodooError


class GaussianInterpolant:
    """Interpolation matrix ``H(x)`` of a node set, evaluable at arbitrary points (Eq. 17).

    Parameters
    ----------
    nodes : (m, 2) float64
        Node positions ``X_j``.
    width : float, optional
        Gaussian standard deviation ``s`` in the nodes' units. By default
        ``width_factor`` times the mean nearest-neighbour distance.
    width_factor : float
        Used when ``width`` is not given.
    """

    def __init__(self, nodes: np.ndarray, width: float | None = None, width_factor: float = 1.0):
        self.nodes = np.asarray(nodes, dtype=np.float64)
        m = len(self.nodes)
        if m < 3:
            raise VoodooError("Gaussian interpolants need at least 3 nodes.")
        if width is None:
            dist, _ = cKDTree(self.nodes).query(self.nodes, k=2)
            width = width_factor * float(dist[:, 1].mean())
        if not np.isfinite(width) or width <= 0:
            raise VoodooError("The nodes coincide; the interpolant has no width.")
        self.width = float(width)
        # Centre and scale the polynomial part for conditioning.
        self._origin = self.nodes.mean(axis=0)
        self._scale = float(np.abs(self.nodes - self._origin).max()) or 1.0
        g = self._gauss(self.nodes)  # (m, m)
        p = self._poly(self.nodes)  # (m, 3)
        if np.linalg.matrix_rank(p, tol=1e-9) < 3:
            raise VoodooError(
                "The nodes lie on a line; the interpolant needs a 2-D region. Outline an area."
            )
        a = np.zeros((m + 3, m + 3))
        a[:m, :m] = g
        a[:m, m:] = p
        a[m:, :m] = p.T
        if np.linalg.cond(a) > 1e12:
            raise VoodooError(
                "The interpolation system is singular (nodes nearly coincide); outline a "
                "larger region or use larger triangles."
            )
        inv = np.linalg.inv(a)
        self._coef = inv[:, :m]  # (m+3, m): maps nodal values to [c; a]

    def _gauss(self, x: np.ndarray) -> np.ndarray:
        d2 = ((x[:, None, :] - self.nodes[None, :, :]) ** 2).sum(axis=2)
        return np.exp(-d2 / (2.0 * self.width**2))

    def _poly(self, x: np.ndarray) -> np.ndarray:
        xn = (x - self._origin) / self._scale
        return np.column_stack([np.ones(len(x)), xn])

    def __call__(self, points: np.ndarray) -> np.ndarray:
        """Interpolation matrix at points.

        Parameters
        ----------
        points : (n, 2) float64

        Returns
        -------
        (n, m) float64
            ``H[p, i] = h_i(points[p])``; a nodal field ``U`` (m, d) maps to ``H @ U``.
        """
        points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        return np.hstack([self._gauss(points), self._poly(points)]) @ self._coef

    def gradient(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Spatial derivatives ``(dH/dx, dH/dy)`` at points, each (n, m)."""
        points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        g = self._gauss(points)  # (n, m)
        diff = points[:, None, :] - self.nodes[None, :, :]  # (n, m, 2)
        out = []
        for axis in range(2):
            dg = -diff[:, :, axis] / self.width**2 * g
            dp = np.zeros((len(points), 3))
            dp[:, 1 + axis] = 1.0 / self._scale
            out.append(np.hstack([dg, dp]) @ self._coef)
        return out[0], out[1]

    def displace(self, points: np.ndarray, nodal: np.ndarray) -> np.ndarray:
        """Displacement at points (n, 2) of a nodal displacement field (m, 2): ``H @ U``."""
        return self(points) @ nodal
