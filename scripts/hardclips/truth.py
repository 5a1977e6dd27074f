"""A hard clip's ground truth: the sheet's lattice in every frame, its visibility, the outline.

Pixel coordinates are OpenCV's (origin at the centre of the top-left pixel, y down).
"""

import math

import bpy

# isort: split
import numpy as np
from blender_scene import pixel_position, rounded_rectangle  # scripts/ is on sys.path
from mathutils import Vector

from hardclips.scene import HEIGHT, WIDTH

OUTLINE_MARGIN = 10.0  # px between the region outline and the sheet's edge on frame 0
OUTLINE_POINTS = 60
OUTLINE_CORNER = 0.25  # corner radius as a fraction of the region's shorter half side
RAY_EPSILON = 1e-3  # world units short of the point, so the ray does not hit the point itself


def lattice_truth(scene, sheet):
    """Project the lattice of sheet points in every frame and decide which are visible.

    Returns
    -------
    lattice : (T, R, C, 2) float32
        OpenCV pixel coordinates.
    visible : (T, R, C) bool
    """
    depsgraph = bpy.context.evaluated_depsgraph_get()
    camera = scene.camera
    index = sheet.grid_index()  # (rows + 1, cols + 1)
    keep = (slice(None, None, sheet.stride), slice(None, None, sheet.stride))
    assert all((s % sheet.stride) == 0 for s in sheet.segments), "stride must divide the grid"
    lattices, visibles = [], []
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        local, world = evaluated_grid(sheet, depsgraph, index)
        # The painted side's normal from the grid itself (rows run down the image, i.e. -Y).
        normal = np.cross(np.gradient(world, axis=0), np.gradient(world, axis=1))
        eye = np.array(camera.matrix_world.translation)
        pixels, visible = [], []
        for point, n in zip(world[keep].reshape(-1, 3), normal[keep].reshape(-1, 3), strict=True):
            x, y, depth = pixel_position(scene, camera, Vector(point))
            pixels.append((x, y))
            inside = -0.5 <= x <= WIDTH - 0.5 and -0.5 <= y <= HEIGHT - 0.5 and depth > 0
            facing = float(np.dot(n, eye - point)) > 0.0
            visible.append(inside and facing and not occluded(scene, depsgraph, eye, point))
        shape = world[keep].shape[:2]
        lattices.append(np.reshape(pixels, (*shape, 2)))
        visibles.append(np.reshape(visible, shape))
        if frame == scene.frame_start:
            rest = np.array([v.co[:] for v in sheet.obj.data.vertices])[index]
            assert np.allclose(local, rest, atol=1e-5), "evaluated vertices do not match"
    return np.array(lattices, dtype=np.float32), np.array(visibles)


def evaluated_grid(sheet, depsgraph, index):
    """The sheet's grid as evaluated on the scene's current frame.

    Returns (local, world) coordinates, each (rows + 1, cols + 1, 3); ``index`` is
    ``sheet.grid_index()``.
    """
    evaluated = sheet.obj.evaluated_get(depsgraph)
    vertices = evaluated.data.vertices
    co = np.empty(len(vertices) * 3)
    vertices.foreach_get("co", co)
    local = co.reshape(-1, 3)[: index.size][index]
    matrix = np.array(evaluated.matrix_world)
    return local, local @ matrix[:3, :3].T + matrix[:3, 3]


def occluded(scene, depsgraph, eye, point):
    """Whether anything the camera sees lies on the segment from the eye to ``point``."""
    direction = Vector(point - eye)
    distance = direction.length - RAY_EPSILON
    direction.normalize()
    origin = Vector(eye)
    while distance > 0:
        hit, location, _, _, obj, _ = scene.ray_cast(
            depsgraph, origin, direction, distance=distance
        )
        if not hit:
            return False
        if obj.visible_camera:
            return True
        step = (location - origin).length + 1e-4  # a lamp-only object (the hand): go past it
        origin = origin + step * direction
        distance -= step
    return False


def region_outline(lattice0):
    """A rounded rectangle OUTLINE_MARGIN px inside the sheet's frame-0 image.

    Returns
    -------
    (n_points, 2) float64
    """
    low, high = lattice0.reshape(-1, 2).min(axis=0), lattice0.reshape(-1, 2).max(axis=0)
    half_size = (high - low) / 2 - OUTLINE_MARGIN
    radius = OUTLINE_CORNER * half_size.min()
    perimeter = 4 * half_size.sum() - (8 - 2 * math.pi) * radius
    return rounded_rectangle((low + high) / 2, half_size, radius, perimeter / OUTLINE_POINTS)
