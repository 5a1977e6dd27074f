"""Quality meshes (Ruppert refinement through Triangle) and their pixel rasters."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.blob.mesh import (
    barycentric,
    rasterize,
    triangle_angles,
    triangle_areas,
    triangulate,
)
from voodoo_addon.blob.outline import signed_area, validate_contour
from voodoo_addon.devtools.synthetic import Pose, ellipse_contour, foam_scene
from voodoo_addon.errors import VoodooError


def _star(points: int, outer: float, inner: float, centre=(160.0, 120.0)) -> np.ndarray:
    t = np.arange(2 * points) * np.pi / points
    r = np.where(np.arange(2 * points) % 2 == 0, outer, inner)
    return np.column_stack([centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)])


POLYGONS = {
    "ellipse": ellipse_contour((160.0, 120.0), 70.0, 45.0, n=48, angle=0.3),
    "L": np.array([(50, 50), (150, 50), (150, 100), (100, 100), (100, 200), (50, 200)], float),
    "star": _star(5, 100.0, 50.0),
    "bar": np.array([(60, 100), (260, 100), (260, 140), (60, 140)], float),
}


def _interior_angles(poly: np.ndarray) -> np.ndarray:
    prev, nxt = np.roll(poly, 1, axis=0), np.roll(poly, -1, axis=0)
    u, v = prev - poly, nxt - poly
    cos = (u * v).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
    return np.degrees(np.arccos(np.clip(cos, -1, 1)))


@pytest.mark.parametrize("name", POLYGONS)
@pytest.mark.parametrize("min_angle", [20.0, 25.0, 30.0])
def test_minimum_angle_is_met(name, min_angle):
    poly = validate_contour(POLYGONS[name])
    # Ruppert's guarantee needs input corners no sharper than the requested angle.
    assert _interior_angles(poly).min() >= min_angle
    mesh = triangulate(poly, min_angle=min_angle)
    assert mesh.min_angle() >= min_angle - 1e-6
    assert triangle_angles(mesh.vertices, mesh.triangles).min() == pytest.approx(mesh.min_angle())


@pytest.mark.parametrize("name", POLYGONS)
def test_mesh_area_equals_polygon_area(name):
    poly = validate_contour(POLYGONS[name])
    mesh = triangulate(poly)
    assert mesh.area == pytest.approx(abs(signed_area(poly)), rel=1e-3)


@pytest.mark.parametrize("name", POLYGONS)
def test_mesh_structure(name):
    poly = validate_contour(POLYGONS[name])
    mesh = triangulate(poly)
    v, t = mesh.vertices, mesh.triangles
    assert v.dtype == np.float64 and v.shape[1] == 2
    assert t.dtype == np.int32 and t.shape[1] == 3
    assert mesh.boundary.dtype == bool and mesh.boundary.shape == (len(v),)
    # Every node is used; no degenerate triangles; all counter-clockwise on screen (y down),
    # i.e. negative in the y-up shoelace convention.
    assert np.array_equal(np.unique(t), np.arange(len(v)))
    areas = triangle_areas(v, t)
    assert (areas < 0).all()
    # Every contour corner is a node, flagged as boundary.
    for p in poly:
        d = np.linalg.norm(v - p, axis=1)
        assert d.min() < 1e-9
        assert mesh.boundary[np.argmin(d)]
    # Boundary nodes lie on the outline; the others strictly inside it.
    contour = poly.astype(np.float32).reshape(-1, 1, 2)
    inside = np.array([cv2.pointPolygonTest(contour, tuple(map(float, p)), True) for p in v])
    assert np.all(np.abs(inside[mesh.boundary]) < 1e-3)
    assert np.all(inside[~mesh.boundary] > 1e-3)


def test_max_area_is_respected():
    poly = validate_contour(POLYGONS["ellipse"])
    mesh = triangulate(poly, max_area=40.0)
    assert np.abs(triangle_areas(mesh.vertices, mesh.triangles)).max() <= 40.0 + 1e-9
    coarse = triangulate(poly, max_area=400.0)
    assert len(mesh.triangles) > len(coarse.triangles)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"min_angle": 40.0},
        {"min_angle": 0.0},
        {"min_angle": -5.0},
        {"max_area": 0.0},
        {"max_area": -10.0},
        {"max_area": 1e-4},  # millions of triangles
    ],
)
def test_bad_mesh_parameters_raise(kwargs):
    with pytest.raises(VoodooError):
        triangulate(validate_contour(POLYGONS["ellipse"]), **kwargs)


@pytest.mark.parametrize("blob_pixels", [8000, 12000, 17000])
def test_default_blob_has_60_to_120_nodes(blob_pixels):
    scene, contour = foam_scene(320, 240, blob_pixels)
    blob = build_blob(scene.render(Pose()), contour)
    assert 60 <= blob.n_nodes <= 120
    assert blob.n_pixels == pytest.approx(blob_pixels, rel=0.03)


def test_bar_blob_node_count():
    frame = np.full((240, 320, 3), 0.5, np.float32)
    blob = build_blob(frame, POLYGONS["bar"])
    assert 60 <= blob.n_nodes <= 120


# ------------------------------------------------------------------------- raster


@pytest.mark.parametrize("name", POLYGONS)
def test_rasterize_covers_the_polygon(name):
    poly = validate_contour(POLYGONS[name])
    mesh = triangulate(poly)
    px = rasterize(mesh)
    n = len(px)
    area = abs(signed_area(poly))
    perimeter = np.linalg.norm(np.roll(poly, -1, axis=0) - poly, axis=1).sum()
    # Pixel count ~ area, off by at most about half the pixels along the outline.
    assert abs(n - area) <= 0.5 * perimeter + 4
    assert n == pytest.approx(area, rel=0.05)
    # Every pixel once; integer centres.
    assert len({tuple(c) for c in px.coords}) == n
    np.testing.assert_array_equal(px.coords, np.round(px.coords))
    # Exactly the pixel centres inside the outline (those on it may go either way).
    x0, y0 = np.floor(poly.min(axis=0)).astype(int) - 1
    x1, y1 = np.ceil(poly.max(axis=0)).astype(int) + 1
    contour = poly.astype(np.float32).reshape(-1, 1, 2)
    have = {tuple(c) for c in px.coords.astype(int)}
    for y in range(y0, y1 + 1):
        for x in range(x0, x1 + 1):
            d = cv2.pointPolygonTest(contour, (float(x), float(y)), True)
            if d > 1e-3:
                assert (x, y) in have
            elif d < -1e-3:
                assert (x, y) not in have


@pytest.mark.parametrize("name", POLYGONS)
def test_barycentric_weights_reconstruct_pixels(name):
    mesh = triangulate(validate_contour(POLYGONS[name]))
    px = rasterize(mesh)
    assert px.weights.shape == (len(px), 3)
    assert px.triangle.dtype == np.int32
    np.testing.assert_allclose(px.weights.sum(axis=1), 1.0, atol=1e-12)
    assert px.weights.min() >= 0.0 and px.weights.max() <= 1.0
    np.testing.assert_allclose(px.positions(mesh.vertices, mesh.triangles), px.coords, atol=1e-6)


def test_pixels_follow_an_affine_motion_of_the_nodes():
    mesh = triangulate(validate_contour(POLYGONS["star"]))
    px = rasterize(mesh)
    a = np.array([[1.1, -0.2], [0.3, 0.9]])
    b = np.array([5.0, -7.0])
    moved = px.positions(mesh.vertices @ a.T + b, mesh.triangles)
    np.testing.assert_allclose(moved, px.coords @ a.T + b, atol=1e-6)


def test_barycentric_of_corners_is_identity():
    corners = np.array([(0.0, 0.0), (4.0, 1.0), (1.0, 5.0)])
    np.testing.assert_allclose(barycentric(corners, corners), np.eye(3), atol=1e-12)
    centroid = corners.mean(axis=0, keepdims=True)
    np.testing.assert_allclose(barycentric(centroid, corners), [[1 / 3] * 3], atol=1e-12)
