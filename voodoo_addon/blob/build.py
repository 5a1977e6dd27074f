"""Building an active blob from a frame and an outline on it (paper §4, §7).

``build_blob(frame, contour)`` is the one call: outline checked and simplified, quality mesh,
Gaussian-interpolant FE model, modes (with their names), blurred colour template.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..checks import finite, whole
from ..errors import VoodooError
from ..media.images import blur
from ..threads import single_blas_thread
from .crossing import first_crossing
from .fem import assemble, quadrature_points, rms_radius, select_modes, similarity_fields
from .interpolants import GaussianInterpolant
from .labels import label_modes
from .mesh import max_area_setting, min_angle_setting, rasterize, triangulate
from .model import ActiveBlob
from .outline import simplify_contour, validate_contour

#: Template crops start on multiples of this, so pyramid levels stay pixel-aligned.
ALIGN = 16
#: Outlines are simplified to at most this many corners: every corner is a mesh node, and a
#: traced outline of thousands of points would make a mesh too fine to track.
MAX_OUTLINE_CORNERS = 200
#: When it takes more, the tolerance grows by this factor until the outline fits ...
TOLERANCE_STEP = 2**0.5
#: ... up to this fraction of the outline's size (beyond it the shape would be lost).
MAX_TOLERANCE_FRACTION = 0.05
#: Meshes with more nodes than this build and track slowly (a warning) ...
SLOW_NODES = 400
#: ... and with more than this are refused: the FE matrices are dense, (2 m)^2 numbers
#: each, and their eigen-decomposition takes seconds at 800 nodes, minutes at a few thousand.
MAX_NODES = 800
#: A mesh needs at least this many pixels per node (the mass matrix sums over pixels).
PIXELS_PER_NODE = 4
#: Largest template blur, pixels (the kernel grows with it).
MAX_BLUR = 20.0
#: Highest polynomial tier of the mode basis (degree d brings 2 (d + 1) fields).
MAX_POLY_DEGREE = 8


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

    def __post_init__(self):
        """Refuse NaN, infinity and out-of-range settings by name (a VoodooError)."""
        numbers = {
            "n_modes": whole(self.n_modes, "the number of modes", 0),
            "min_angle": min_angle_setting(self.min_angle),
            "max_area": max_area_setting(self.max_area),
            "simplify_tolerance": finite(self.simplify_tolerance, "the outline tolerance", 0.0),
            "blur_sigma": finite(self.blur_sigma, "the template blur", 0.0, MAX_BLUR),
            "poisson": finite(self.poisson, "the Poisson ratio", -1.0, 0.5, True, True),
            "width_factor": finite(self.width_factor, "the interpolant width factor", 0.1, 10.0),
            "poly_degree": whole(self.poly_degree, "the polynomial degree", 0, MAX_POLY_DEGREE),
        }
        for name, value in numbers.items():
            object.__setattr__(self, name, value)
        object.__setattr__(self, "separate_scale", bool(self.separate_scale))


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


def _simplified(pts: np.ndarray, opt: BlobOptions) -> tuple[np.ndarray, list[str]]:
    """The outline within the tolerance band, with at most :data:`MAX_OUTLINE_CORNERS` corners.

    A dense outline (a traced mask, a video's contour) can keep thousands of corners within
    the band; the band then widens step by step until the outline fits, and a warning says
    so. A band that makes the outline cross itself is skipped as well.

    Returns
    -------
    pts : (k, 2) float64
        A validated outline.
    warnings : list of str
    """
    tol = opt.simplify_tolerance
    size = float(np.ptp(pts, axis=0).max())
    first = None
    while True:
        out = simplify_contour(pts, tol)
        first = len(out) if first is None else first
        crossed = len(out) <= MAX_OUTLINE_CORNERS and first_crossing(out) is not None
        if len(out) <= MAX_OUTLINE_CORNERS and not crossed:
            break
        if tol * TOLERANCE_STEP > MAX_TOLERANCE_FRACTION * size:
            problem = "crosses itself" if crossed else f"still needs {len(out)} corners"
            raise VoodooError(
                f"The outline has too much fine detail: simplified within {tol:.1f} px it "
                f"{problem}; draw a smoother outline (at most {MAX_OUTLINE_CORNERS} corners)."
            )
        tol = max(tol, 0.25) * TOLERANCE_STEP
    out = validate_contour(out, frame_size=None)
    if tol == opt.simplify_tolerance:
        return out, []
    return out, [
        f"The outline was simplified to {len(out)} corners within {tol:.1f} px (it needed "
        f"{first} within {opt.simplify_tolerance:g} px); finer detail is not followed."
    ]


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
    # One BLAS thread: the same blob, to the last bit, however many threads a machine
    # has (a multithreaded BLAS sums in another order), so that a take tracked again on
    # the same machine is the same take.
    with single_blas_thread():
        return _build(frame, contour, options or BlobOptions())


def _build(frame, contour, opt: BlobOptions) -> ActiveBlob:
    frame = np.asarray(frame)
    if frame.ndim != 3 or frame.shape[2] != 3 or frame.dtype != np.float32:
        raise VoodooError("The frame must be a float32 RGB picture (H, W, 3).")
    h, w = frame.shape[:2]
    pts, warnings = _simplified(validate_contour(contour, frame_size=(w, h)), opt)
    mesh = triangulate(pts, min_angle=opt.min_angle, max_area=opt.max_area)
    if len(mesh.vertices) > MAX_NODES:
        raise VoodooError(
            f"The mesh would have {len(mesh.vertices)} nodes; at most {MAX_NODES} can be "
            "built and tracked (its matrices are dense). Raise the maximum triangle area."
        )
    pixels = rasterize(mesh)
    if len(pixels.coords) < PIXELS_PER_NODE * len(mesh.vertices):
        raise VoodooError(
            f"The region covers {len(pixels.coords)} pixels for {len(mesh.vertices)} mesh "
            "nodes: it is too thin or too small for its mesh. Outline a wider region or "
            "raise the maximum triangle area."
        )
    if len(mesh.vertices) > SLOW_NODES:
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
    k = opt.n_modes
    if k > available:
        warnings.append(f"Only {available} modes exist for this mesh; using all of them.")
        k = available
    try:
        modal = select_modes(
            mass, stiff, constraints, k, mesh.vertices, centre, length, opt.poly_degree
        )
    except np.linalg.LinAlgError:  # a mass matrix without full rank: too few pixels
        raise VoodooError(
            "The region's elastic model is singular (too few pixels for its mesh); outline "
            "a wider region or raise the maximum triangle area."
        ) from None
    shapes, penalty = modal.shapes, modal.mode_stiffness
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
        mode_stiffness=penalty,
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
