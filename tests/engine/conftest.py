"""Shared fixtures for the engine tests (plain pytest, no Blender).

Expensive objects (rendered frames, blobs) are session-scoped and must be treated as read-only.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from voodoo_addon.blob.build import BlobOptions, build_blob
from voodoo_addon.devtools.synthetic import Pose, foam_scene

#: The repository root (holds the extension's __init__.py and voodoo_addon/).
REPO_ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO_ROOT


@pytest.fixture(scope="session")
def foam():
    """A painted-foam scene at 320x240 with an ~8000-pixel elliptical blob outline.

    Returns (scene, rest frame, contour).
    """
    scene, contour = foam_scene(320, 240, 8000, seed=0)
    return scene, scene.render(Pose()), contour


@pytest.fixture(scope="session")
def blob(foam):
    """Blob with the default options (poly_degree=3, scale separated)."""
    _, frame, contour = foam
    return build_blob(frame, contour)


@pytest.fixture(scope="session")
def fe_blob(foam):
    """Blob of plain FE vibration modes, rigid motions only separated."""
    _, frame, contour = foam
    return build_blob(frame, contour, BlobOptions(poly_degree=0, separate_scale=False))


@pytest.fixture(scope="session")
def fe_blob_scale(foam):
    """Blob of plain FE vibration modes with the scale field separated too."""
    _, frame, contour = foam
    return build_blob(frame, contour, BlobOptions(poly_degree=0, separate_scale=True))


def polygon_distance(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Distance (n,) of each point to the closed polygon's boundary."""
    a = polygon
    b = np.roll(polygon, -1, axis=0)
    ab = b - a
    t = ((points[:, None, :] - a[None]) * ab[None]).sum(-1) / (ab * ab).sum(-1)[None]
    t = np.clip(t, 0.0, 1.0)
    proj = a[None] + t[..., None] * ab[None]
    return np.linalg.norm(points[:, None, :] - proj, axis=-1).min(axis=1)


@pytest.fixture(scope="session")
def poly_distance():
    """The :func:`polygon_distance` helper (test modules cannot import conftest by name)."""
    return polygon_distance
