"""Quality triangle meshes of a contour, and the pixels they cover.

Ruppert refinement via Shewchuk's Triangle (paper §7); the covered pixel set carries
barycentric coordinates for piecewise-affine warping.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import triangle as tr

from ..checks import finite
from ..errors import VoodooError
from .outline import signed_area

#: Default number of triangles the refinement aims for: with the boundary vertices this gives
#: 60-120 nodes for any blob size (the paper used 72 nodes for 8.5k pixels, 61 for 17k).
DEFAULT_TRIANGLES = 80
#: More triangles than this are refused (a mistyped area would take minutes and gigabytes).
MAX_TRIANGLES = 20000


@dataclass(frozen=True)
class TriMesh:
    """A planar triangle mesh.

    Attributes
    ----------
    vertices : (n_nodes, 2) float64
        Node positions, pixel coordinates.
    triangles : (n_tris, 3) int32
        Vertex indices, counter-clockwise on screen.
    boundary : (n_nodes,) bool
        True for nodes on the outline.
    """

    vertices: np.ndarray
    triangles: np.ndarray
    boundary: np.ndarray

    @property
    def area(self) -> float:
        """Total area in square pixels."""
        return float(np.abs(triangle_areas(self.vertices, self.triangles)).sum())

    def min_angle(self) -> float:
        """Smallest interior angle of any triangle, degrees."""
        return float(triangle_angles(self.vertices, self.triangles).min())


def triangle_edges(triangles: np.ndarray) -> np.ndarray:
    """Every triangle's three edges (3 t, 2), smaller node first.

    The first edge of each triangle, then the second, then the third: row ``k t + i`` is
    edge ``k`` of triangle ``i``.
    """
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    return np.sort(e, axis=1)


def mesh_edges(triangles: np.ndarray) -> np.ndarray:
    """The mesh's edges (e, 2), each once, smaller node first, in sorted order."""
    return np.unique(triangle_edges(triangles), axis=0)


def triangle_areas(vertices: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Signed areas (n_tris,), positive for counter-clockwise in a y-up frame."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    ab, ac = b - a, c - a
    return 0.5 * (ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])


def triangle_angles(vertices: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Interior angles (n_tris, 3) in degrees."""
    p = vertices[triangles]  # (t, 3, 2)
    out = np.empty(triangles.shape, dtype=np.float64)
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        cosang = np.einsum("ij,ij->i", u, v) / (
            np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1)
        )
        out[:, k] = np.degrees(np.arccos(np.clip(cosang, -1.0, 1.0)))
    return out


def _triangle_number(value: float) -> str:
    """A positive number as Triangle's switches read it: digits and one dot, no exponent.

    Triangle stops reading a number at the first other character, so ``1e+06`` would be 1.
    """
    return np.format_float_positional(value, precision=9, unique=True, trim="-")


def min_angle_setting(value) -> float:
    """The smallest triangle angle as Triangle can meet it: 1 to 33 degrees (VoodooError)."""
    return finite(value, "the minimum triangle angle", 1.0, 33.0)


def max_area_setting(value) -> float | None:
    """A largest triangle area: None (automatic) or a positive finite number (VoodooError)."""
    if value is None:
        return None
    return finite(value, "the maximum triangle area", 0.0, low_open=True)


def triangulate(
    contour: np.ndarray, min_angle: float = 25.0, max_area: float | None = None
) -> TriMesh:
    """Constrained quality Delaunay triangulation of a simple polygon.

    Parameters
    ----------
    contour : (k, 2) float64
        A validated contour (see :func:`voodoo_addon.contour.validate_contour`).
    min_angle : float
        Smallest triangle angle in degrees (Ruppert refinement; Triangle's ``q``). Values
        above about 33 degrees may not terminate; below 1 degree is meaningless; both are
        refused.
    max_area : float, optional
        Largest triangle area in square pixels (Triangle's ``a``). By default the polygon's
        area over :data:`DEFAULT_TRIANGLES`. Must be positive and finite; anything larger
        than the polygon gives its coarsest quality mesh.

    Returns
    -------
    TriMesh
    """
    min_angle = min_angle_setting(min_angle)
    area = abs(signed_area(contour))
    max_area = max_area_setting(max_area)
    if max_area is None:
        max_area = area / DEFAULT_TRIANGLES
    if area / max_area > MAX_TRIANGLES:
        raise VoodooError(
            f"A maximum triangle area of {max_area:g} px would need over {MAX_TRIANGLES} "
            f"triangles for this {area:.0f} px region; choose a larger area."
        )
    # No triangle of the polygon can be larger than the polygon: a larger bound changes
    # nothing, and this keeps the number Triangle reads short.
    max_area = min(max_area, area)
    k = len(contour)
    segments = np.stack([np.arange(k), (np.arange(k) + 1) % k], axis=1)
    switches = f"pq{_triangle_number(min_angle)}a{_triangle_number(max_area)}Q"
    result = tr.triangulate({"vertices": contour, "segments": segments}, switches)
    verts = np.asarray(result["vertices"], dtype=np.float64)
    tris = np.asarray(result["triangles"], dtype=np.int32)
    markers = np.asarray(result.get("vertex_markers", np.zeros((len(verts), 1)))).ravel()
    # Triangle returns counter-clockwise in y-up; flip to counter-clockwise on screen (y down).
    if (triangle_areas(verts, tris) > 0).any():
        tris = tris[:, [0, 2, 1]]
    # Drop any vertex not used by a triangle (Triangle keeps none, but be sure).
    used = np.zeros(len(verts), dtype=bool)
    used[tris.ravel()] = True
    if not used.all():
        remap = np.cumsum(used) - 1
        verts, markers, tris = verts[used], markers[used], remap[tris].astype(np.int32)
    return TriMesh(vertices=verts, triangles=tris, boundary=markers > 0)


@dataclass(frozen=True)
class PixelSet:
    """The pixels whose centres lie inside a mesh, with barycentric coordinates.

    Attributes
    ----------
    coords : (n_pix, 2) float64
        Integer pixel centres (x, y) inside the mesh.
    triangle : (n_pix,) int32
        Index of the containing triangle.
    weights : (n_pix, 3) float64
        Barycentric coordinates with respect to that triangle's vertices; rows sum to 1.
    """

    coords: np.ndarray
    triangle: np.ndarray
    weights: np.ndarray

    def __len__(self) -> int:
        return len(self.coords)

    def positions(self, nodes: np.ndarray, triangles: np.ndarray) -> np.ndarray:
        """Where each pixel goes when the mesh nodes move to ``nodes`` (n_nodes, 2).

        Returns
        -------
        (n_pix, 2) float64
        """
        corner = nodes[triangles[self.triangle]]  # (n_pix, 3, 2)
        return np.einsum("pk,pkd->pd", self.weights, corner)


def barycentric(points: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Barycentric coordinates of points (n, 2) in one triangle (3, 2): (n, 3)."""
    a, b, c = corners
    m = np.array([[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]])
    lam = np.linalg.solve(m, (points - a).T).T  # (n, 2)
    return np.column_stack([1.0 - lam.sum(axis=1), lam])


def rasterize(mesh: TriMesh) -> PixelSet:
    """Collect the pixel centres covered by the mesh.

    A pixel on an edge shared by two triangles is assigned to the first of them, so every
    pixel appears once.
    """
    v, t = mesh.vertices, mesh.triangles
    lo = np.floor(v.min(axis=0)).astype(int)
    hi = np.ceil(v.max(axis=0)).astype(int)
    owner = np.full((hi[1] - lo[1] + 1, hi[0] - lo[0] + 1), -1, dtype=np.int32)
    eps = 1e-9
    for k, tri in enumerate(t):
        corners = v[tri]
        x0, y0 = np.ceil(corners.min(axis=0) - eps).astype(int)
        x1, y1 = np.floor(corners.max(axis=0) + eps).astype(int)
        if x1 < x0 or y1 < y0:
            continue
        ys, xs = np.mgrid[y0 : y1 + 1, x0 : x1 + 1]
        pts = np.column_stack([xs.ravel(), ys.ravel()]).astype(np.float64)
        w = barycentric(pts, corners)
        inside = (w >= -eps).all(axis=1)
        px = pts[inside].astype(int)
        sub = owner[px[:, 1] - lo[1], px[:, 0] - lo[0]]
        free = sub < 0
        owner[px[free, 1] - lo[1], px[free, 0] - lo[0]] = k
    ys, xs = np.nonzero(owner >= 0)
    coords = np.column_stack([xs + lo[0], ys + lo[1]]).astype(np.float64)
    tri_idx = owner[ys, xs]
    weights = np.empty((len(coords), 3))
    for k in np.unique(tri_idx):
        sel = tri_idx == k
        weights[sel] = barycentric(coords[sel], v[t[k]])
    weights = np.clip(weights, 0.0, 1.0)
    weights /= weights.sum(axis=1, keepdims=True)
    if len(coords) == 0:
        raise VoodooError("The mesh covers no pixel centre; outline a larger region.")
    return PixelSet(coords=coords, triangle=tri_idx.astype(np.int32), weights=weights)
