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
        tri = np.asarray(triangles)
        self.triangles = tri
        k = modes.shape[1]
        phi = np.asarray(modes, np.float64).reshape(-1, 2, k)  # (m, 2, k)
        self.e1 = v[tri[:, 1]] - v[tri[:, 0]]  # (t, 2)
        self.e2 = v[tri[:, 2]] - v[tri[:, 0]]
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
        e1g, e2g = self._edges(amplitudes)
        return self._bounded(self.e1 + e1g, self.e2 + e2g, *self._edges(step))

    def shape_ratios(self, shape: np.ndarray) -> np.ndarray:
        """Area over rest area (t,) of a local shape given node by node (m, 2)."""
        e1, e2 = self._shape_edges(shape)
        return 0.5 * _cross(e1, e2) / self.rest

    def shape_step(self, shape: np.ndarray, step: np.ndarray) -> float:
        """:meth:`max_step` for node offsets: ``shape`` (m, 2) moving by ``step`` (m, 2)."""
        if not np.any(step):
            return 1.0
        return self._bounded(*self._shape_edges(shape), *self._shape_edges(step))

    def _shape_edges(self, shape: np.ndarray):
        t = self.triangles
        return shape[t[:, 1]] - shape[t[:, 0]], shape[t[:, 2]] - shape[t[:, 0]]

    def _bounded(self, e1, e2, g1, g2) -> float:
        """The step along edge changes (g1, g2) from edges (e1, e2) that keeps the bounds."""
        # Signed area along the step: A + B tau + C tau^2 (times the rest sign, so the
        # bounds read low <= area <= high for either orientation of the mesh).
        s = self._sign
        a0 = s * 0.5 * _cross(e1, e2)
        b = s * 0.5 * (_cross(e1, g2) + _cross(g1, e2))
        c = s * 0.5 * _cross(g1, g2)
        # For tau in [0, 1] the area moves by at most |B| + |C|: most steps are far from
        # both bounds and need no roots.
        reach = np.abs(b) + np.abs(c)
        if np.all(a0 - s * self.low > reach) and np.all(s * self.high - a0 > reach):
            return 1.0
        tau = min(
            _first_crossing(a0 - s * self.low, b, c),  # area - low stays >= 0
            _first_crossing(s * self.high - a0, -b, -c),  # high - area stays >= 0
        )
        return 1.0 if tau >= 1.0 else BACKOFF * tau

    def clamp(self, amplitudes: np.ndarray) -> np.ndarray:
        """The amplitudes if valid, else the furthest valid point towards them from rest."""
        amplitudes = np.asarray(amplitudes, np.float64)
        if self.valid(amplitudes):
            return amplitudes
        return self.max_step(np.zeros_like(amplitudes), amplitudes) * amplitudes


def _first_crossing(f0: np.ndarray, f1: np.ndarray, f2: np.ndarray) -> float:
    """Smallest ``tau`` in [0, 1] where some ``f0 + f1 tau + f2 tau^2`` reaches 0 (else 1).

    ``f0 >= 0`` (up to rounding) for every entry. The roots are taken in the form that
    does not cancel (``q = -(f1 + sign(f1) sqrt(disc)) / 2``, roots ``q / f2`` and
    ``f0 / q``), so a triangle sitting on its bound is seen leaving it at once.
    """
    f0 = np.maximum(f0, 0.0)
    # On the bound and heading out: no step at all.
    if np.any((f0 <= 1e-12 * (1.0 + np.abs(f1))) & ((f1 < 0) | ((f1 == 0) & (f2 < 0)))):
        return 0.0
    disc = f1 * f1 - 4.0 * f2 * f0
    real = disc >= 0
    sq = np.sqrt(np.where(real, disc, 0.0))
    q = -0.5 * (f1 + np.where(f1 >= 0, sq, -sq))
    r1 = np.divide(q, f2, out=np.full_like(q, np.inf), where=np.abs(f2) > 1e-300)
    r2 = np.divide(f0, q, out=np.full_like(q, np.inf), where=np.abs(q) > 1e-300)
    r1 = np.where(real & (r1 > 0), r1, np.inf)
    r2 = np.where(real & (r2 > 0), r2, np.inf)
    tau = min(float(r1.min(initial=np.inf)), float(r2.min(initial=np.inf)))
    return min(1.0, tau)
