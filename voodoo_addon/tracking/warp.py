"""Warp backends: resample a picture at the template pixels of a deformed mesh.

This is ``W^-1(I, a)`` of the paper (Eq. 12): the mesh nodes move to ``nodes``, every template
pixel follows its triangle (piecewise-affine, precomputed barycentric weights), and the picture
is sampled bilinearly there. The engine ships a CPU backend (OpenCV ``remap``); the Blender
layer plugs in a GPU backend that draws the textured triangles with the ``gpu`` module. Both
implement :class:`WarpBackend`.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass

import cv2
import numpy as np


@dataclass(frozen=True, eq=False)
class WarpGeometry:
    """What a backend needs to know about one template raster (one pyramid level).

    Attributes
    ----------
    vertices : (m, 2) float64
        Template mesh nodes in this raster's pixel coordinates.
    triangles : (t, 3) int32
    coords : (n, 2) float64
        Template pixel centres (integers) in this raster.
    triangle : (n,) int32
        Containing triangle of each template pixel.
    weights : (n, 3) float64
        Barycentric coordinates of each template pixel.
    """

    vertices: np.ndarray
    triangles: np.ndarray
    coords: np.ndarray
    triangle: np.ndarray
    weights: np.ndarray


#: ``cv2.remap`` wants maps narrower than 32767 columns: long point lists are folded into rows
#: of at most this many.
REMAP_ROW = 8192


class WarpBackend(abc.ABC):
    """Samples the bound picture at the template pixels of a warped mesh."""

    #: Short name shown in the interface and the benchmark.
    name = "abstract"

    @abc.abstractmethod
    def bind(self, image: np.ndarray) -> None:
        """Make ``image`` (H, W, 3) float32 the picture that :meth:`sample` reads."""

    #: Whether :meth:`sample` reads ``nodes`` (the tracker skips computing them otherwise).
    needs_nodes = True

    @abc.abstractmethod
    def sample(self, geometry: WarpGeometry, nodes, positions: np.ndarray) -> np.ndarray:
        """Colours of the template pixels under the warp.

        Parameters
        ----------
        geometry : WarpGeometry
        nodes : (m, 2) float64 or None
            Warped node positions in the bound picture's pixel coordinates (None when
            ``needs_nodes`` is False).
        positions : (2, n_pad) float32
            The same warp evaluated at the template pixels: x in row 0, y in row 1, padded
            to ``n_pad >= n`` columns (see :func:`padded`).
            Backends that rasterise triangles themselves may ignore it.

        Returns
        -------
        (n, 3) float32
            Bilinear samples; points off the picture read the nearest border pixel.
        """

    def sample_many(self, geometry: WarpGeometry, nodes, positions) -> list[np.ndarray]:
        """:meth:`sample` of each of several warps (lists of ``nodes`` and ``positions``)."""
        return [self.sample(geometry, v, p) for v, p in zip(nodes, positions, strict=True)]

    def close(self) -> None:  # noqa: B027 - optional hook
        """Release resources (GPU textures, ...)."""


class CpuWarp(WarpBackend):
    """Bilinear sampling with ``cv2.remap`` at precomputed pixel positions."""

    name = "cpu"
    needs_nodes = False

    def __init__(self):
        self._image = None

    def bind(self, image: np.ndarray) -> None:
        self._image = image

    def sample(self, geometry: WarpGeometry, nodes, positions: np.ndarray) -> np.ndarray:
        return remap_points(self._image, positions)[: len(geometry.coords)]

    def sample_many(self, geometry: WarpGeometry, nodes, positions) -> list[np.ndarray]:
        # One remap of every warp's points, each folded as remap_points folds it: the same
        # bilinear samples, in one call.
        n_pad = positions[0].shape[1]
        rows = _rows(n_pad)
        maps = np.stack(positions).reshape(len(positions), 2, rows, n_pad // rows)
        out = cv2.remap(
            self._image,
            np.ascontiguousarray(maps[:, 0]).reshape(-1, n_pad // rows),
            np.ascontiguousarray(maps[:, 1]).reshape(-1, n_pad // rows),
            interpolation=cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_REPLICATE,
        ).reshape(len(positions), n_pad, -1)
        n = len(geometry.coords)
        return [samples[:n] for samples in out]


def _rows(n: int) -> int:
    """Rows the remap map of ``n`` points is folded into (at most :data:`REMAP_ROW` wide)."""
    return max(1, -(-n // REMAP_ROW))


def padded(n: int) -> int:
    """Columns of a position array for ``n`` points: as few as fill equal rows.

    The rows are as many as :data:`REMAP_ROW` asks for and no wider than needed, so at most
    one point per row is padding (rows of the full width padded 17.8k points to 24.6k).
    """
    rows = _rows(n)
    return rows * -(-n // rows)


def remap_points(image: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """Bilinear samples (n_pad, c) of ``image`` at ``positions`` (2, n_pad), border repeated."""
    n_pad = positions.shape[1]
    rows = _rows(n_pad)
    shape = (rows, n_pad // rows)
    out = cv2.remap(
        image,
        positions[0].reshape(shape),
        positions[1].reshape(shape),
        interpolation=cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_REPLICATE,
    )
    return out.reshape(n_pad, -1)
