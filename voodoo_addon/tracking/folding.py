"""Keeping the mesh from folding: every triangle's area stays within bounds of its rest area.

The modal shape is ``L(a) = X - c + Phi a`` (the similarity only turns and scales it, which
never folds a triangle). Along a step ``a + tau d`` each triangle's signed area is a
quadratic in ``tau``, so the largest step that keeps every area between ``low`` and ``high``
times its rest area is a closed form per triangle: the first crossing of either bound
(Smith & Schaefer 2015, "Bijective parameterization with free boundaries", the locally
injective line search). Updates, predictions and proposals are all cut to that step, so no
triangle ever inverts or collapses.
"""

from __future__ import annotations

import numpy as np

from . import kernels

#: Smallest and largest modal area of a triangle, as a fraction of its rest area. A surface
#: turning away from the camera is compressed down to ``MIN_AREA`` (and its triangles are
#: then hidden, see ``decomposition``), never inverted.
MIN_AREA = 0.05
MAX_AREA = 8.0
#: A triangle compressed below this fraction of its rest area is seen too obliquely to
#: compare with the template (foreshortened, or turning away): it is *hidden* and leaves the
#: solve until it opens up again.
HIDE_AREA = 0.25
#: Steps that reach a bound stop this fraction of the way, so a triangle approaches it
#: geometrically instead of landing on it.
BACKOFF = 0.9


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


class FoldGuard:
    """Area bounds of a blob's triangles under its elastic modes.

    Parameters
    ----------
    vertices : (m, 2) float64
        Rest nodes.
    triangles : (t, 3) int
    modes : (2m, k) float64
        Mode fields (node-interleaved x, y).
    low, high : float
        Area bounds as fractions of the rest area.
    """

    def __init__(self, vertices, triangles, modes, low: float = MIN_AREA, high: float = MAX_AREA):
        v = np.asarray(vertices, np.float64)
        tri = np.ascontiguousarray(triangles, dtype=np.int64)  # the kernels' layout
        self.triangles = tri
        k = modes.shape[1]
        phi = np.asarray(modes, np.float64).reshape(-1, 2, k)  # (m, 2, k)
        self._rest_edges = np.stack([v[tri[:, 1]] - v[tri[:, 0]], v[tri[:, 2]] - v[tri[:, 0]]])
        self.e1, self.e2 = self._rest_edges  # (t, 2) each
        # Edge change per unit mode amplitude, flattened for one matrix product: (2t*2, k).
        d1 = phi[tri[:, 1]] - phi[tri[:, 0]]
        d2 = phi[tri[:, 2]] - phi[tri[:, 0]]
        self._d = np.concatenate([d1, d2], axis=0).reshape(-1, k)
        self.n_tri = len(tri)
        self.rest = 0.5 * _cross(self.e1, self.e2)  # signed (one sign for the whole mesh)
        self.low = low * self.rest
        self.high = high * self.rest
        self._sign = np.sign(self.rest)

    def _edges(self, amplitudes: np.ndarray):
        g = (self._d @ amplitudes).reshape(2, self.n_tri, 2)
        return g[0], g[1]

    def ratios(self, amplitudes: np.ndarray) -> np.ndarray:
        """Modal area over rest area (t,) at these mode amplitudes."""
        g1, g2 = self._edges(amplitudes)
        return 0.5 * _cross(self.e1 + g1, self.e2 + g2) / self.rest

    def valid(self, amplitudes: np.ndarray) -> bool:
        """Every triangle within the bounds."""
        r = self.ratios(amplitudes)
        return bool(np.all(r >= self.low / self.rest) and np.all(r <= self.high / self.rest))

    def max_step(self, amplitudes: np.ndarray, step: np.ndarray) -> float:
        """Largest ``tau`` in [0, 1] keeping every triangle within bounds along the step.

        ``amplitudes`` must be valid. Returns 1 when the whole step is safe, else
        :data:`BACKOFF` times the first bound crossing.
        """
        if not np.any(step):
            return 1.0
        e = self._rest_edges + (self._d @ amplitudes).reshape(2, self.n_tri, 2)
        return self._bounded(e.ravel(), self._d @ step)

    def shape_ratios(self, shape: np.ndarray) -> np.ndarray:
        """Area over rest area (t,) of a local shape given node by node (m, 2)."""
        e1, e2 = self._shape_edges(shape)
        return 0.5 * _cross(e1, e2) / self.rest

    def shape_step(self, shape: np.ndarray, step: np.ndarray) -> float:
        """:meth:`max_step` for node offsets: ``shape`` (m, 2) moving by ``step`` (m, 2)."""
        if not np.any(step):
            return 1.0
        e, g = np.empty(4 * self.n_tri), np.empty(4 * self.n_tri)
        kernels.edges(np.ascontiguousarray(shape, dtype=np.float64), self.triangles, e)
        kernels.edges(np.ascontiguousarray(step, dtype=np.float64), self.triangles, g)
        return self._bounded(e, g)

    def _bounded(self, e: np.ndarray, g: np.ndarray) -> float:
        """The step along edge changes ``g`` from edges ``e`` (4t each, both edges' x and y).

        Along a step the signed area is ``A + B tau + C tau^2``; for tau in [0, 1] it moves
        by at most ``|B| + |C|``, so most steps are far from both bounds and need no
        roots. Otherwise each triangle's first crossing of either bound is a closed form
        (:func:`.kernels.bounded_step`).
        """
        return kernels.bounded_step(e, g, self._sign, self.low, self.high, BACKOFF)

    def _shape_edges(self, shape: np.ndarray):
        t = self.triangles
        return shape[t[:, 1]] - shape[t[:, 0]], shape[t[:, 2]] - shape[t[:, 0]]

    def clamp(self, amplitudes: np.ndarray) -> np.ndarray:
        """The amplitudes if valid, else the furthest valid point towards them from rest."""
        amplitudes = np.asarray(amplitudes, np.float64)
        if self.valid(amplitudes):
            return amplitudes
        return self.max_step(np.zeros_like(amplitudes), amplitudes) * amplitudes
