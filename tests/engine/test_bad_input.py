"""Hostile numbers from the user reach the engine: they give a VoodooError or a sound result.

Areas, angles, mode counts, gains, boxes and points can be huge, negative, NaN or infinite;
none of them may crash, hang, eat the machine's memory or produce NaN.
"""

from __future__ import annotations

import numpy as np
import pytest

from voodoo_addon.blob.mesh import triangle_areas, triangulate
from voodoo_addon.blob.outline import signed_area, validate_contour
from voodoo_addon.devtools.synthetic import ellipse_contour
from voodoo_addon.errors import VoodooError

ELLIPSE = validate_contour(ellipse_contour((160.0, 120.0), 70.0, 45.0, n=48, angle=0.3))


@pytest.mark.parametrize("max_area", [1e6, 1e7, 3.5e9, 1e12, 1e300])
def test_huge_max_area_gives_the_coarsest_mesh(max_area):
    # Triangle reads its area switch as digits and dots only: "a1e+06" would be 1 px^2.
    area = abs(signed_area(ELLIPSE))
    coarsest = triangulate(ELLIPSE, max_area=area)
    mesh = triangulate(ELLIPSE, max_area=max_area)
    assert len(mesh.triangles) == len(coarsest.triangles)
    assert len(mesh.vertices) < 2 * len(ELLIPSE)
    assert mesh.area == pytest.approx(area, rel=1e-9)
    assert mesh.min_angle() >= 25.0 - 1e-6
    assert (triangle_areas(mesh.vertices, mesh.triangles) < 0).all()


@pytest.mark.parametrize("max_area", [1e-3 * 4000, 12.5, 333.333])
def test_max_area_is_read_exactly(max_area):
    mesh = triangulate(ELLIPSE, max_area=max_area)
    largest = np.abs(triangle_areas(mesh.vertices, mesh.triangles)).max()
    assert largest <= max_area + 1e-9
    # Not a much smaller area than asked for (a misread switch gives tiny triangles).
    assert largest > 0.5 * max_area


@pytest.mark.parametrize("max_area", [np.inf, -np.inf, np.nan, -1.0, 0.0])
def test_non_finite_or_non_positive_max_area_is_refused(max_area):
    with pytest.raises(VoodooError, match="area"):
        triangulate(ELLIPSE, max_area=max_area)


@pytest.mark.parametrize("min_angle", [np.nan, np.inf, -np.inf, 1e-5, 34.0])
def test_bad_min_angle_is_refused(min_angle):
    with pytest.raises(VoodooError, match="angle"):
        triangulate(ELLIPSE, min_angle=min_angle)
