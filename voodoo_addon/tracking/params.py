"""The tracker's parameter vector and the warp it stands for.

Layout of ``a`` (all in the capture frame's pixel units)::

    0  translate-x   pixels
    1  translate-y   pixels
    2  rotate        radians, about the blob centroid, continuous (not wrapped)
    3  scale         natural log of the isotropic scale
    4..4+k-1         elastic mode amplitudes, pixels RMS over the blob
    then             photometric terms (paper Eq. 4): brightness offsets and log-contrast gains,
                     per RGB channel ("channel"), one of each ("global"), or none

Node positions for ``a`` (Eq. 3 composed with an exact similarity)::

    V = c + t + s R(theta) (X - c + Phi a_modes)

Updates compose (see :func:`compose`): the similarity by matrix product, so the doll can turn
through 360 degrees or change scale 4x without ever leaving the linear range of the basis.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

SIMILARITY = ("translate-x", "translate-y", "rotate", "scale")
PHOTOMETRIC = {
    "channel": (
        "brightness-r",
        "brightness-g",
        "brightness-b",
        "contrast-r",
        "contrast-g",
        "contrast-b",
    ),
    "global": ("brightness", "contrast"),
    "none": (),
}


@dataclass(frozen=True)
class ParamLayout:
    """Where each parameter lives in ``a``.

    Its derived figures (``names``, ``modes``, ...) are made once, on first reading: the
    tracker reads them a few dozen times in every iteration.

    Parameters
    ----------
    mode_labels : tuple of str
        Elastic mode names.
    photometric : {"channel", "global", "none"}
    """

    mode_labels: tuple
    photometric: str = "channel"

    @cached_property
    def n_modes(self) -> int:
        return len(self.mode_labels)

    @cached_property
    def names(self) -> tuple:
        return SIMILARITY + tuple(self.mode_labels) + PHOTOMETRIC[self.photometric]

    @cached_property
    def size(self) -> int:
        return len(self.names)

    @cached_property
    def modes(self) -> slice:
        return slice(4, 4 + self.n_modes)

    @cached_property
    def brightness(self) -> slice:
        n = len(PHOTOMETRIC[self.photometric]) // 2
        return slice(4 + self.n_modes, 4 + self.n_modes + n)

    @cached_property
    def contrast(self) -> slice:
        n = len(PHOTOMETRIC[self.photometric]) // 2
        return slice(4 + self.n_modes + n, 4 + self.n_modes + 2 * n)

    @classmethod
    def from_names(cls, mode_labels, names) -> ParamLayout:
        """The layout whose parameter names are ``names`` (those of a take).

        Raises
        ------
        ValueError
            If no layout of these mode labels has exactly these names.
        """
        labels = tuple(str(x) for x in mode_labels)
        names = tuple(str(x) for x in names)
        for photometric in PHOTOMETRIC:
            layout = cls(labels, photometric)
            if layout.names == names:
                return layout
        raise ValueError("the parameter names do not belong to these modes")

    def identity(self) -> np.ndarray:
        """The parameters of the capture frame: no motion, no lighting change."""
        return np.zeros(self.size)

    def index(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise KeyError(f"no parameter named {name!r}; have {', '.join(self.names)}") from None

    def channel_gain_offset(self, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per-channel contrast ``c`` (3,) and brightness ``b`` (3,): frame ~ c * I0 + b."""
        if self.photometric == "none":
            return np.ones(3), np.zeros(3)
        b = np.broadcast_to(a[self.brightness], 3)
        c = np.exp(np.broadcast_to(a[self.contrast], 3))
        return c, b


def rotation(theta: float) -> np.ndarray:
    """2x2 rotation matrix (y down: positive angles turn clockwise on screen)."""
    co, si = np.cos(theta), np.sin(theta)
    return np.array([[co, -si], [si, co]])


def node_positions(
    a: np.ndarray, layout: ParamLayout, vertices, modes, centre, offsets=None
) -> np.ndarray:
    """Warped node positions ``V`` (m, 2) for parameters ``a``.

    Parameters
    ----------
    a : (P,) float64
    layout : ParamLayout
    vertices : (m, 2) float64
    modes : (2m, k) float64
    centre : (2,) float64
    offsets : (m, 2) float64, optional
        Node offsets of the local stage, in the rest frame (see :mod:`.refine`).
    """
    return centre + a[:2] + placed_shape(a, layout, vertices, modes, centre, offsets)


def placed_shape(a: np.ndarray, layout: ParamLayout, vertices, modes, centre, offsets=None):
    """:func:`node_positions` less ``centre + a[:2]``: the shape turned and scaled (m, 2).

    Poses that differ in their translation only share it (``node_positions`` adds the
    translation last, so the nodes are the same numbers either way).
    """
    local = vertices - centre
    if offsets is not None:
        local = local + offsets
    if layout.n_modes:
        local = local + (modes @ a[layout.modes]).reshape(-1, 2)
    return np.exp(a[3]) * local @ rotation(a[2]).T


def compose(a: np.ndarray, delta: np.ndarray, layout: ParamLayout) -> np.ndarray:
    """Apply an update found in the template frame: ``W_new(x) = W_a(W_delta(x))``.

    The similarity composes exactly (translation ``t + s R dt``, angle and log-scale add);
    elastic amplitudes add (their first-order composition); the photometric model
    ``frame = c I0 + b`` composes as ``c <- c exp(dc)``, ``b <- b + c db``.
    """
    out = a + delta
    s = np.exp(a[3])
    out[:2] = a[:2] + s * rotation(a[2]) @ delta[:2]
    if layout.photometric != "none":
        c = np.exp(a[layout.contrast])
        out[layout.brightness] = a[layout.brightness] + c * delta[layout.brightness]
    return out


def similarity_from_matrix(mat: np.ndarray, centre: np.ndarray, theta_near: float = 0.0):
    """Similarity parameters (tx, ty, theta, log s) of a 2x3 matrix ``y = A x + b``.

    The angle is unwrapped to lie within pi of ``theta_near``.

    Raises
    ------
    ValueError
        If the matrix is not a proper similarity (non-finite or zero scale).
    """
    a = np.asarray(mat, dtype=np.float64)
    s = float(np.sqrt(abs(np.linalg.det(a[:, :2]))))
    if not np.isfinite(a).all() or s <= 1e-6:
        raise ValueError("degenerate similarity")
    theta = float(np.arctan2(a[1, 0], a[0, 0]))
    theta += 2 * np.pi * np.round((theta_near - theta) / (2 * np.pi))
    t = a[:, :2] @ centre + a[:, 2] - centre
    return np.array([t[0], t[1], theta, np.log(s)])
