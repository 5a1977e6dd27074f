"""Pictures for people: the mesh over the frame and what each mode does (``blob --preview``)."""

from __future__ import annotations

import cv2
import numpy as np

from ..media.images import to_uint8_bgr
from .model import ActiveBlob

MESH = (60, 230, 255)  # BGR
GHOST = (150, 150, 150)
OUTLINE = (40, 90, 255)
TEXT = (255, 255, 255)


def draw_mesh(
    canvas: np.ndarray,
    vertices: np.ndarray,
    triangles: np.ndarray,
    colour=MESH,
    scale: float = 1.0,
    offset=(0.0, 0.0),
    thickness: int = 1,
) -> None:
    """Draw triangle edges (anti-aliased, sub-pixel) onto a uint8 BGR canvas in place."""
    shift = 4
    pts = np.round((vertices * scale + np.asarray(offset)) * (1 << shift)).astype(np.int32)
    polys = [pts[t].reshape(-1, 1, 2) for t in triangles]
    cv2.polylines(canvas, polys, True, colour, thickness, cv2.LINE_AA, shift)


def _label(canvas, text, org, size=0.45):
    cv2.putText(canvas, text, org, cv2.FONT_HERSHEY_SIMPLEX, size, (0, 0, 0), 3, cv2.LINE_AA)
    cv2.putText(canvas, text, org, cv2.FONT_HERSHEY_SIMPLEX, size, TEXT, 1, cv2.LINE_AA)


def draw_outline(canvas: np.ndarray, contour: np.ndarray, colour=OUTLINE) -> None:
    """Draw a closed polygon (k, 2) onto a uint8 BGR canvas in place."""
    pts = np.round(np.asarray(contour) * 16).astype(np.int32).reshape(-1, 1, 2)
    cv2.polylines(canvas, [pts], True, colour, 2, cv2.LINE_AA, 4)


def mesh_overlay(
    frame: np.ndarray, blob: ActiveBlob, vertices: np.ndarray | None = None
) -> np.ndarray:
    """The frame (float RGB) with the blob's mesh (at ``vertices``) drawn on it, uint8 BGR.

    Without ``vertices`` the rest mesh and the outline are drawn.
    """
    canvas = to_uint8_bgr(frame)
    draw_mesh(canvas, blob.vertices if vertices is None else vertices, blob.triangles)
    if vertices is None:
        draw_outline(canvas, blob.contour)
    return canvas


def modes_picture(
    frame: np.ndarray,
    blob: ActiveBlob,
    n_modes: int | None = None,
    panel: int = 220,
    columns: int = 4,
) -> np.ndarray:
    """The mesh over the frame, then one panel per mode: the mesh displaced by that mode.

    Each mode is drawn at an RMS displacement of 20% of the blob's RMS radius (positive
    amplitude, so the picture shows what the label's name means), over the rest mesh in grey.

    Returns
    -------
    (H, W, 3) uint8 BGR
    """
    k = blob.n_modes if n_modes is None else min(n_modes, blob.n_modes)
    lo = blob.vertices.min(axis=0)
    hi = blob.vertices.max(axis=0)
    extent = float((hi - lo).max())
    amp = 0.2 * blob.length
    scale = 0.62 * panel / extent
    centre = 0.5 * (lo + hi)
    tiles = []
    # First tile: the frame around the blob with the mesh.
    overlay = mesh_overlay(frame, blob)
    x0 = int(max(0, centre[0] - 0.8 * extent))
    y0 = int(max(0, centre[1] - 0.8 * extent))
    crop = overlay[y0 : int(centre[1] + 0.8 * extent) + 1, x0 : int(centre[0] + 0.8 * extent) + 1]
    tile = cv2.resize(crop, (panel, panel), interpolation=cv2.INTER_AREA)
    _label(tile, f"{blob.n_nodes} nodes, {len(blob.triangles)} tris", (6, 16))
    _label(tile, f"{blob.n_pixels} px", (6, panel - 8))
    tiles.append(tile)
    offset = np.array([panel / 2, panel / 2]) - centre * scale
    for j in range(k):
        tile = np.full((panel, panel, 3), 32, np.uint8)
        draw_mesh(tile, blob.vertices, blob.triangles, GHOST, scale, offset)
        moved = blob.vertices + amp * blob.mode_shape(j)
        draw_mesh(tile, moved, blob.triangles, MESH, scale, offset)
        _label(tile, f"{j + 1}: {blob.labels[j]}", (6, 16))
        _label(tile, f"stiffness {blob.mode_stiffness[j]:.2f}", (6, panel - 8), 0.4)
        tiles.append(tile)
    rows = []
    for r in range(0, len(tiles), columns):
        row = tiles[r : r + columns]
        row += [np.zeros_like(tiles[0])] * (columns - len(row))
        rows.append(np.hstack(row))
    return np.vstack(rows)
