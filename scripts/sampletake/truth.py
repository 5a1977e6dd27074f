"""The sample take's ground truth and frame-0 outline, projected from the slab's deformed mesh.

Pixel coordinates are OpenCV's (origin at the centre of the top-left pixel, y down).
"""

import bpy
import numpy as np
from blender_scene import grid_index, pixel_position, rounded_rectangle

from sampletake.scene import SLAB_SEGMENTS, SLAB_SIZE

TRUTH_STRIDE = 2  # keep every 2nd slab vertex along each axis for the ground truth

# Region outline on frame 0: a rounded rectangle centred on the slab's projection.
REGION_FRACTION = 0.8  # of the slab's projected width and height
REGION_CORNER = 0.3  # corner radius as a fraction of the region's shorter half side
REGION_SPACING = 12.0  # pixels between outline points


def projected_vertices(scene, obj):
    """The evaluated mesh's vertices in OpenCV pixel coordinates at the current frame.

    Returns
    -------
    (n_vertices, 2) float64
    """
    camera = scene.camera
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    world = evaluated.matrix_world
    return np.array(
        [pixel_position(scene, camera, world @ vert.co)[:2] for vert in evaluated.data.vertices]
    )


def region_outline(scene, slab):
    """The frame-0 region: a rounded rectangle covering REGION_FRACTION of the slab's image."""
    scene.frame_set(scene.frame_start)
    pixels = projected_vertices(scene, slab)
    low, high = pixels.min(axis=0), pixels.max(axis=0)
    half_size = REGION_FRACTION * (high - low) / 2
    radius = REGION_CORNER * half_size.min()
    return rounded_rectangle((low + high) / 2, half_size, radius, REGION_SPACING)


def lattice_truth(scene, slab):
    """Where a lattice of slab points is in every frame: the take's ground truth.

    The slab is a regular grid of vertices; every ``TRUTH_STRIDE``-th one along each axis is
    projected in every frame. Frame 0 shows the slab at rest, so there the lattice is an
    axis-aligned grid and any point of the slab can be located in it bilinearly.

    Returns
    -------
    (n_frames, rows, cols, 2) float32
        OpenCV pixel coordinates.
    """
    index = grid_index(slab.data, SLAB_SIZE, SLAB_SEGMENTS)[::TRUTH_STRIDE, ::TRUTH_STRIDE]
    frames = []
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        frames.append(projected_vertices(scene, slab)[index])
    return np.array(frames, dtype=np.float32)


def max_speed(scene, slab):
    """Largest per-frame image displacement of any slab vertex over the clip, in pixels."""
    previous, fastest = None, 0.0
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        current = projected_vertices(scene, slab)
        if previous is not None:
            fastest = max(fastest, float(np.linalg.norm(current - previous, axis=1).max()))
        previous = current
    return fastest
