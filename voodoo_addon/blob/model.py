"""The active blob (paper §4, §7) and its file: mesh, Gaussian-interpolant FE modes, template.

:class:`ActiveBlob` holds everything the tracker and the character mapping need;
``blob_to_bytes``/``blob_from_bytes`` (and ``save_blob``/``load_blob`` for files) persist it
as a pickle-free ``.npz`` with a format version. :mod:`.build` makes one from an outline.
"""

from __future__ import annotations

import io
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..archive import check_arrays, header, load_npz, require
from ..errors import VoodooError, read_file, write_file
from .interpolants import GaussianInterpolant
from .mesh import PixelSet, TriMesh

FORMAT_KIND = "voodoo-active-blob"
FORMAT_VERSION = 1


@dataclass(frozen=True, eq=False)
class ActiveBlob:
    """Everything known about one tracked region.

    Attributes
    ----------
    contour : (k, 2) float64
        Simplified outline, pixel coordinates of the capture frame.
    vertices : (m, 2) float64
        Mesh nodes ``X``.
    triangles : (t, 3) int32
    boundary : (m,) bool
    centre : (2,) float64
        Centroid of the blob's pixels: the similarity transform's pivot.
    length : float
        RMS radius of the blob's pixels: the unit of the normalised fields.
    width : float
        Gaussian interpolant width ``s``, pixels.
    poisson : float
    mass, stiffness : (2m, 2m) float64
        FE mass and stiffness matrices M and K (normalised as in :mod:`voodoo_addon.blob.fem`).
    constrained : (2m, c) float64
        M-orthonormal exact fields: translate-x, translate-y, rotate and (when separated)
        scale.
    modes : (2m, k) float64
        Elastic modes, M-orthonormal, increasing stiffness, sign fixed by the label.
    mode_stiffness : (k,) float64
        ``w_j^2`` per mode: the regularisation penalty ``psi_j^2`` of Eq. 10.
    labels : (k,) str
        Readable mode names.
    label_match : (k,) float64
        How well each label fits (1 = exactly the named field).
    texture : (h, w, 3) float32
        Blurred RGB crop of the capture frame around the blob.
    texture_origin : (2,) int64
        Frame pixel (x, y) of the crop's top-left pixel.
    frame_size : (2,) int64
        Capture frame (width, height).
    blur_sigma : float
    pixel_coords : (n, 2) float64
        Template pixel centres inside the mesh, frame coordinates.
    pixel_triangle : (n,) int32
    pixel_weights : (n, 3) float64
        Barycentric coordinates of each template pixel in its triangle.
    """

    contour: np.ndarray
    vertices: np.ndarray
    triangles: np.ndarray
    boundary: np.ndarray
    centre: np.ndarray
    length: float
    width: float
    poisson: float
    mass: np.ndarray
    stiffness: np.ndarray
    constrained: np.ndarray
    modes: np.ndarray
    mode_stiffness: np.ndarray
    labels: np.ndarray
    label_match: np.ndarray
    texture: np.ndarray
    texture_origin: np.ndarray
    frame_size: np.ndarray
    blur_sigma: float
    pixel_coords: np.ndarray
    pixel_triangle: np.ndarray
    pixel_weights: np.ndarray
    warnings: tuple = field(default=(), compare=False)

    @property
    def n_nodes(self) -> int:
        return len(self.vertices)

    @property
    def n_modes(self) -> int:
        return self.modes.shape[1]

    @property
    def n_pixels(self) -> int:
        return len(self.pixel_coords)

    @cached_property
    def interpolant(self) -> GaussianInterpolant:
        """``H(x)`` of this blob's nodes (paper Eq. 17)."""
        return GaussianInterpolant(self.vertices, width=self.width)

    @cached_property
    def pixels(self) -> PixelSet:
        return PixelSet(self.pixel_coords, self.pixel_triangle, self.pixel_weights)

    @cached_property
    def mesh(self) -> TriMesh:
        return TriMesh(self.vertices, self.triangles, self.boundary)

    @cached_property
    def template(self) -> np.ndarray:
        """Template colours at the template pixels, (n, 3) float32."""
        local = (self.pixel_coords - self.texture_origin).astype(np.int64)
        return self.texture[local[:, 1], local[:, 0]]

    def mode_shape(self, j: int) -> np.ndarray:
        """Nodal displacement (m, 2) of elastic mode j at unit amplitude (1 px RMS)."""
        return self.modes[:, j].reshape(-1, 2)

    def deformed(self, amplitudes: np.ndarray) -> np.ndarray:
        """Node positions (m, 2) for elastic amplitudes (k,) -- Eq. 3, no similarity."""
        return self.vertices + (self.modes[:, : len(amplitudes)] @ amplitudes).reshape(-1, 2)


# ---------------------------------------------------------------------------- persistence

#: Every array of a blob file: kind and shape (names are sizes that must agree).
_SPEC = {
    "contour": ("float", ("q", 2)),
    "vertices": ("float", ("m", 2)),
    "triangles": ("int", ("t", 3)),
    "boundary": ("bool", ("m",)),
    "centre": ("float", (2,)),
    "length": ("float", ()),
    "width": ("float", ()),
    "poisson": ("float", ()),
    "mass": ("float", ("2m", "2m")),
    "stiffness": ("float", ("2m", "2m")),
    "constrained": ("float", ("2m", "c")),
    "modes": ("float", ("2m", "k")),
    "mode_stiffness": ("float", ("k",)),
    "labels": ("str", ("k",)),
    "label_match": ("float", ("k",)),
    "texture": ("float", ("h", "w", 3)),
    "texture_origin": ("int", (2,)),
    "frame_size": ("int", (2,)),
    "blur_sigma": ("float", ()),
    "pixel_coords": ("float", ("n", 2)),
    "pixel_triangle": ("int", ("n",)),
    "pixel_weights": ("float", ("n", 3)),
}

#: Fields of older files under their old names (same format version: only the name changed).
_RENAMED = {"stiffness_penalty": "mode_stiffness"}


def blob_to_bytes(blob: ActiveBlob) -> bytes:
    """Serialise a blob to ``.npz`` bytes (no pickles), e.g. to store inside a .blend."""
    buf = io.BytesIO()
    arrays = {name: np.asarray(getattr(blob, name)) for name in _SPEC}
    np.savez_compressed(
        buf,
        format_kind=np.array(FORMAT_KIND),
        format_version=np.array(FORMAT_VERSION),
        **arrays,
    )
    return buf.getvalue()


def blob_from_bytes(data: bytes, source: str = "the blob data") -> ActiveBlob:
    """Inverse of :func:`blob_to_bytes`.

    Raises
    ------
    VoodooError
        If the bytes are not a blob file of a version this code reads, or its arrays are
        damaged (missing, of the wrong kind or shape, not finite, not fitting together).
    """
    arrays = load_npz(data, source, "Voodoo blob")
    for old, new in _RENAMED.items():  # files written before a field was renamed
        if old in arrays and new not in arrays:
            arrays[new] = arrays.pop(old)
    is_blob, version = header(arrays, FORMAT_KIND)
    if not is_blob:
        raise VoodooError(f"{source} is not a Voodoo blob file (no blob header).")
    if version != FORMAT_VERSION:
        raise VoodooError(
            f"{source} has blob format version {version}; this add-on reads version "
            f"{FORMAT_VERSION}. Rebuild the blob."
        )
    size = check_arrays(arrays, _SPEC, source)
    kw = {name: a.item() if a.ndim == 0 else a for name, a in arrays.items() if name in _SPEC}
    blob = ActiveBlob(**kw)
    _check_consistent(blob, size, source)
    return blob


def _check_consistent(blob: ActiveBlob, size: dict, source: str) -> None:
    m, t = size["m"], size["t"]
    require(size["2m"] == 2 * m, source, "the FE matrices do not match the nodes")
    require(m >= 3 and t >= 1 and size["n"] >= 1, source, "the mesh is empty")
    tri, pix = blob.triangles, blob.pixel_triangle
    require(tri.min() >= 0 and tri.max() < m, source, "triangle corners out of range")
    require(pix.min() >= 0 and pix.max() < t, source, "pixel triangles out of range")
    require(blob.length > 0 and blob.width > 0 and blob.blur_sigma >= 0, source, "bad sizes")
    require((blob.frame_size > 0).all(), source, "bad frame size")
    local = np.floor(blob.pixel_coords - blob.texture_origin)
    inside = (local >= 0).all() and (local < [size["w"], size["h"]]).all()
    require(inside, source, "template pixels outside the texture")


def save_blob(path, blob: ActiveBlob) -> None:
    """Write a blob to an ``.npz`` file."""
    write_file(path, blob_to_bytes(blob), "blob")


def load_blob(path) -> ActiveBlob:
    """Read a blob written by :func:`save_blob`."""
    return blob_from_bytes(read_file(path, "blob"), source=str(path))
