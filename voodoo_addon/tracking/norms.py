"""Error norms for registration (paper §5.1).

A norm here is used the paper's way (Eq. 16): each difference value ``e`` is replaced by
``sign(e) sqrt(rho(e, sigma))`` in both the basis and the difference image, so ordinary least
squares on the transformed values minimises ``sum rho``-like energy with outliers tamed.
"""

from __future__ import annotations

import abc

import numpy as np


class RobustNorm(abc.ABC):
    """``rho(e, sigma)`` and the Eq. 16 transform."""

    @property
    @abc.abstractmethod
    def key(self) -> tuple:
        """Hashable identity (used to cache solvers)."""

    @abc.abstractmethod
    def rho(self, e: np.ndarray) -> np.ndarray:
        """Per-value energy ``rho(e, sigma)``."""

    def transform(self, e: np.ndarray) -> np.ndarray:
        """``sign(e) sqrt(rho(e, sigma))`` elementwise (Eq. 16), same dtype as ``e``."""
        return np.copysign(np.sqrt(self.rho(e)), e)


class LorentzianNorm(RobustNorm):
    """``rho(e, sigma) = log(1 + e^2 / (2 sigma^2))`` (Eq. 9).

    Parameters
    ----------
    sigma : float
        Expected spread of inlier differences, in image units (images are in [0, 1]). No
        default here: the tracker's is :attr:`TrackerOptions.sigma`.
    """

    def __init__(self, sigma: float):
        if not sigma > 0:
            raise ValueError("sigma must be positive")
        self.sigma = float(sigma)
        self._k = 1.0 / (2.0 * self.sigma**2)

    @property
    def key(self) -> tuple:
        return ("lorentzian", self.sigma)

    def rho(self, e: np.ndarray) -> np.ndarray:
        out = np.square(e)
        out *= e.dtype.type(self._k)
        return np.log1p(out, out=out)


class QuadraticNorm(RobustNorm):
    """``rho(e, sigma) = e^2 / (2 sigma^2)``: plain least squares (the Gaussian-noise optimum)."""

    def __init__(self, sigma: float):
        self.sigma = float(sigma)
        self._k = 1.0 / (2.0 * self.sigma**2)

    @property
    def key(self) -> tuple:
        return ("quadratic", self.sigma)

    def rho(self, e: np.ndarray) -> np.ndarray:
        return e * e * e.dtype.type(self._k)
