"""The active blob: mesh + Gaussian-interpolant FE modes + blurred colour template (§4, §7).

``build_blob(frame, contour)`` is the one call that turns an outline on a frame into
everything the tracker and the character mapping need; ``save_blob``/``load_blob`` persist it
as a pickle-free ``.npz`` with a format version.
"""

from __future__ import annotations

import io
import zipfile
from dataclasses import dataclass, field, fields
from functools import cached_property

import numpy as np

from .contour import simplify_contour, validate_contour
from .errors import VoodooError, read_file, write_file
from .fem import assemble, quadrature_points, rms_radius, select_modes, similarity_fields
from .images import blur
from .interpolants import GaussianInterpolant
from .labels import label_modes
from .mesh import PixelSet, TriMesh, rasterize, triangulate

FORMAT_KIND = "voodoo-active-blob"
FORMAT_VERSION = 1
#: Template crops start on multiples of this, so pyramid levels stay pixel-aligned.
ALIGN = 16
#: Names of the exact similarity fields, in the order of ``ActiveBlob.constrained``.
SIMILARITY_LABELS = ("translate-x", "translate-y", "rotate", "scale")


@dataclass(frozen=True)
class BlobOptions:
    """How a blob is built. The defaults suit blobs of 5k-60k pixels without tuning.

    Attributes
    ----------
    n_modes : int
        Elastic modes kept (the paper used 14 and 20).
    min_angle : float
        Smallest triangle angle, degrees (Ruppert refinement).
    max_area : float or None
        Largest triangle area in square pixels; None aims at about 80 triangles.
    simplify_tolerance : float
        Tolerance band for the outline, pixels.
    blur_sigma : float
        Gaussian blur of the template texture, pixels (§7).
    poisson : float
        Poisson ratio of the plane-stress material.
    width_factor : float
        Gaussian interpolant width over the mean nearest-node distance.
    separate_scale : bool
        Keep isotropic scale out of the elastic modes (it is tracked exactly by the
        similarity transform). When False only the rigid motions are separated.
    poly_degree : int
        0: the modes are the lowest FE vibration modes, plain eigenvectors of
        ``K phi = w^2 M phi`` (the paper). d > 0: polynomial fields up to degree d come first,
        by Rayleigh-Ritz on the same M and K (see :func:`voodoo_addon.fem.select_modes`).
    """

    n_modes: int = 20
    min_angle: float = 25.0
    max_area: float | None = None
    simplify_tolerance: float = 0.75
    blur_sigma: float = 1.2
    poisson: float = 0.3
    width_factor: float = 1.0
    separate_scale: bool = True
    poly_degree: int = 3


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


def _texture_crop(frame: np.ndarray, contour: np.ndarray, sigma: float):
    """Blurred crop around the contour, origin aligned to :data:`ALIGN`."""
    h, w = frame.shape[:2]
    lo, hi = contour.min(axis=0), contour.max(axis=0)
    margin = 32 + 0.25 * float((hi - lo).max())
    x0 = int(max(0, np.floor((lo[0] - margin) / ALIGN) * ALIGN))
    y0 = int(max(0, np.floor((lo[1] - margin) / ALIGN) * ALIGN))
    x1 = int(min(w, np.ceil(hi[0] + margin) + 1))
    y1 = int(min(h, np.ceil(hi[1] + margin) + 1))
    crop = blur(np.ascontiguousarray(frame[y0:y1, x0:x1], dtype=np.float32), sigma)
    return crop, np.array([x0, y0], dtype=np.int64)


def build_blob(frame: np.ndarray, contour, options: BlobOptions | None = None) -> ActiveBlob:
    """Build an active blob from a frame and an outline on it.

    Parameters
    ----------
    frame : (H, W, 3) float32
        RGB in [0, 1] (see :func:`voodoo_addon.images.to_float_rgb`).
    contour : array_like (k, 2)
        Closed polygon in the frame's pixel coordinates.
    options : BlobOptions, optional

    Returns
    -------
    ActiveBlob

    Raises
    ------
    VoodooError
        For a bad outline (too few points, tiny, self-intersecting, off the frame, NaN) or
        a frame that is not an RGB picture.
    """
    opt = options or BlobOptions()
    frame = np.asarray(frame)
    if frame.ndim != 3 or frame.shape[2] != 3 or frame.dtype != np.float32:
        raise VoodooError("The frame must be a float32 RGB picture (H, W, 3).")
    h, w = frame.shape[:2]
    pts = validate_contour(contour, frame_size=(w, h))
    pts = validate_contour(simplify_contour(pts, opt.simplify_tolerance), frame_size=(w, h))
    mesh = triangulate(pts, min_angle=opt.min_angle, max_area=opt.max_area)
    pixels = rasterize(mesh)
    warnings = []
    if len(mesh.vertices) > 400:
        warnings.append(
            f"The mesh has {len(mesh.vertices)} nodes; building and tracking will be slow. "
            "Raise the maximum triangle area."
        )
    interp = GaussianInterpolant(mesh.vertices, width_factor=opt.width_factor)
    quad = quadrature_points(pixels.coords)
    mass, stiff = assemble(interp, quad, opt.poisson)
    centre = pixels.coords.mean(axis=0)
    length = rms_radius(pixels.coords)
    sim = similarity_fields(mesh.vertices, centre, length)
    constraints = sim if opt.separate_scale else sim[:, :3]
    available = 2 * len(mesh.vertices) - constraints.shape[1]
    k = int(opt.n_modes)
    if k < 0:
        raise VoodooError("The number of modes cannot be negative.")
    if k > available:
        warnings.append(f"Only {available} modes exist for this mesh; using all of them.")
        k = available
    modal = select_modes(
        mass, stiff, constraints, k, mesh.vertices, centre, length, opt.poly_degree
    )
    shapes, penalty = modal.shapes, modal.stiffness
    labels, signs, match = label_modes(
        shapes, mass, modal.constrained, mesh.vertices, centre, length
    )
    shapes = shapes * signs
    texture, origin = _texture_crop(frame, pts, opt.blur_sigma)
    return ActiveBlob(
        contour=pts,
        vertices=mesh.vertices,
        triangles=mesh.triangles,
        boundary=mesh.boundary,
        centre=centre,
        length=length,
        width=interp.width,
        poisson=float(opt.poisson),
        mass=mass,
        stiffness=stiff,
        constrained=modal.constrained,
        modes=shapes,
        stiffness_penalty=penalty,
        labels=np.array(labels, dtype=str),
        label_match=match,
        texture=texture,
        texture_origin=origin,
        frame_size=np.array([w, h], dtype=np.int64),
        blur_sigma=float(opt.blur_sigma),
        pixel_coords=pixels.coords,
        pixel_triangle=pixels.triangle,
        pixel_weights=pixels.weights,
        warnings=tuple(warnings),
    )


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
