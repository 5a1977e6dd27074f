"""The active blob (paper §4, §7) and its file: mesh, Gaussian-interpolant FE modes, template.

:class:`ActiveBlob` holds everything the tracker and the character mapping need;
``blob_to_bytes``/``blob_from_bytes`` (and ``save_blob``/``load_blob`` for files) persist it
as a pickle-free ``.npz`` with a format version. :mod:`.build` makes one from an outline.
"""

from __future__ import annotations

import io
import zipfile
from dataclasses import dataclass, field, fields
from functools import cached_property

import numpy as np

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
        FE matrices (see :mod:`voodoo_addon.fem` for their normalisation).
    constrained : (2m, c) float64
        M-orthonormal exact fields: translate-x, translate-y, rotate and (when separated)
        scale.
    modes : (2m, k) float64
        Elastic modes, M-orthonormal, increasing stiffness, sign fixed by the label.
    stiffness_penalty : (k,) float64
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
    stiffness_penalty: np.ndarray
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

_ARRAY_FIELDS = [f.name for f in fields(ActiveBlob) if f.name != "warnings"]


def blob_to_bytes(blob: ActiveBlob) -> bytes:
    """Serialise a blob to ``.npz`` bytes (no pickles), e.g. to store inside a .blend."""
    buf = io.BytesIO()
    arrays = {name: np.asarray(getattr(blob, name)) for name in _ARRAY_FIELDS}
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
        If the bytes are not a blob file of a version this code reads.
    """
    try:
        loaded = np.load(io.BytesIO(data), allow_pickle=False)
        if not isinstance(loaded, np.lib.npyio.NpzFile):
            raise ValueError("a single array, not an archive")
        with loaded as npz:
            arrays = {k: npz[k] for k in npz.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as exc:
        raise VoodooError(f"{source} is not a Voodoo blob file ({exc}).") from None
    if str(arrays.get("format_kind", "")) != FORMAT_KIND:
        raise VoodooError(f"{source} is not a Voodoo blob file (no blob header).")
    try:
        version = int(arrays["format_version"]) if "format_version" in arrays else -1
    except (TypeError, ValueError):
        version = -1
    if version != FORMAT_VERSION:
        raise VoodooError(
            f"{source} has blob format version {version}; this add-on reads version "
            f"{FORMAT_VERSION}. Rebuild the blob."
        )
    missing = [k for k in _ARRAY_FIELDS if k not in arrays]
    if missing:
        raise VoodooError(f"{source} is incomplete (missing {', '.join(missing)}).")
    kw = {}
    for name in _ARRAY_FIELDS:
        a = arrays[name]
        if a.dtype.kind == "f" and not np.isfinite(a).all():
            raise VoodooError(f"{source} is corrupt ({name} has NaN or infinite values).")
        kw[name] = a.item() if a.ndim == 0 else a
    blob = ActiveBlob(**kw)
    _check_consistent(blob, source)
    return blob


def _check_consistent(blob: ActiveBlob, source: str) -> None:
    m = len(blob.vertices)
    k = blob.modes.shape[1] if blob.modes.ndim == 2 else -1
    ok = (
        blob.vertices.ndim == 2
        and blob.vertices.shape[1] == 2
        and blob.triangles.ndim == 2
        and blob.triangles.shape[1] == 3
        and blob.triangles.min(initial=0) >= 0
        and blob.triangles.max(initial=0) < m
        and blob.mass.shape == (2 * m, 2 * m)
        and blob.stiffness.shape == (2 * m, 2 * m)
        and blob.modes.shape[0] == 2 * m
        and len(blob.labels) == k
        and len(blob.stiffness_penalty) == k
        and blob.texture.ndim == 3
        and blob.pixel_coords.shape == (len(blob.pixel_triangle), 2)
        and blob.pixel_weights.shape == (len(blob.pixel_triangle), 3)
    )
    if not ok:
        raise VoodooError(f"{source} is corrupt (its arrays do not fit together).")


def save_blob(path, blob: ActiveBlob) -> None:
    """Write a blob to an ``.npz`` file."""
    write_file(path, blob_to_bytes(blob), "blob")


def load_blob(path) -> ActiveBlob:
    """Read a blob written by :func:`save_blob`."""
    return blob_from_bytes(read_file(path, "blob"), source=str(path))
