"""Sample characters for the voodoo doll to animate, built headless from bpy.data and numpy.

Both characters stand upright in the XZ plane (X right, Z up, feet on Z = 0), facing -Y: Blender's
front view (numpad 1) looks straight at them. A doll frame's image axes (x right, y down) map
onto (X, -Z).

``make_cutout``
    A flat 2D cut-out bunny (body, head, two long ears) about 2 units tall: a hand-designed
    outline, smoothed, filled with a quality Delaunay triangulation (Shewchuk's Triangle) so the
    interior holds enough vertices to deform smoothly.
``make_extruded``
    An animal-cracker box: a box front with an arched circus-wagon top, its cap triangulated
    with interior vertices and extruded along Y into a closed solid with outward normals:
    120 vertices (the paper's box had 116), triangle caps and quad sides.

Run as a script to build both into a fresh scene and save ``/tmp/characters_check.blend``::

    .venv/bin/python scripts/characters.py
"""

import bpy
import numpy as np
import triangle

# Right half of the bunny outline (x, z), counterclockwise from the notch between the feet to
# the top of the head; mirrored for the left half, then corner-cut smooth.
BUNNY_HALF = [
    (0.00, 0.06),
    (0.10, 0.00),
    (0.40, 0.00),
    (0.55, 0.07),
    (0.57, 0.17),  # foot
    (0.63, 0.35),
    (0.63, 0.58),
    (0.55, 0.78),
    (0.40, 0.92),
    (0.24, 0.98),  # body to neck
    (0.33, 1.06),
    (0.38, 1.20),
    (0.34, 1.36),
    (0.24, 1.46),  # cheek and head
    (0.30, 1.62),
    (0.36, 1.82),
    (0.36, 1.97),
    (0.29, 2.06),  # ear, outer side to tip
    (0.21, 2.01),
    (0.17, 1.84),
    (0.13, 1.62),
    (0.10, 1.50),
    (0.00, 1.47),  # ear, inner side
]
BUNNY_SPACING = 0.09  # target edge length of the cut-out's mesh: about 400 vertices
BUNNY_COLOUR = (0.85, 0.72, 0.55, 1.0)

BOX_WIDTH, BOX_HEIGHT, BOX_DEPTH = 2.0, 1.2, 0.6
BOX_ARCH = 0.25  # how far the arched top rises above the box's sides
BOX_OUTLINE_SPACING = 0.2  # between outline points
BOX_INTERIOR_SPACING = 0.4  # target edge length inside a cap: about 60 vertices per cap
BOX_COLOUR = (0.75, 0.12, 0.10, 1.0)

SMOOTHING_PASSES = 2  # Chaikin corner cutting applied to the designed outlines
MIN_ANGLE = 30  # degrees: Triangle's quality bound


def chaikin(points, passes):
    """Smooth a closed polyline by corner cutting (Chaikin).

    Each pass replaces every edge by its 1/4 and 3/4 points. Returns (n * 2**passes, 2) float64.
    """
    for _ in range(passes):
        following = np.roll(points, -1, axis=0)
        points = np.stack(
            [0.75 * points + 0.25 * following, 0.25 * points + 0.75 * following], axis=1
        ).reshape(-1, 2)
    return points


def resample_closed(points, spacing):
    """Points evenly about ``spacing`` apart along the closed polyline through ``points``.

    Returns
    -------
    (n_points, 2) float64
    """
    closed = np.vstack([points, points[:1]])
    steps = np.linalg.norm(np.diff(closed, axis=0), axis=1)
    arc_length = np.concatenate([[0.0], np.cumsum(steps)])
    at = np.linspace(0.0, arc_length[-1], round(arc_length[-1] / spacing), endpoint=False)
    return np.column_stack([np.interp(at, arc_length, closed[:, i]) for i in (0, 1)])


def fill_outline(outline, spacing):
    """Quality-triangulate the inside of a counterclockwise outline, keeping it unsplit.

    Parameters
    ----------
    outline : (n, 2) float64
        Boundary points, counterclockwise in (x, z).
    spacing : float
        Target edge length inside (Triangle may refine further near a denser outline).

    Returns
    -------
    vertices : (m, 2) float64
        The first n are ``outline``, in order; the rest are interior points.
    triangles : (t, 3) int
        Counterclockwise in (x, z), as Triangle always lists them.
    """
    n = len(outline)
    segments = np.column_stack([np.arange(n), (np.arange(n) + 1) % n])
    max_area = np.sqrt(3) / 4 * spacing**2  # an equilateral triangle with sides ``spacing``
    mesh = triangle.triangulate(
        {"vertices": outline, "segments": segments}, f"pq{MIN_ANGLE}Ya{max_area:.6f}"
    )
    return mesh["vertices"], mesh["triangles"]


def bunny_outline():
    """The smoothed bunny outline, counterclockwise in (x, z). Returns (n, 2) float64."""
    right = np.array(BUNNY_HALF)
    left = right[-2:0:-1] * (-1.0, 1.0)  # mirror, skipping the two points on the centre line
    outline = chaikin(np.vstack([right, left]), SMOOTHING_PASSES)
    return resample_closed(outline, BUNNY_SPACING)


def box_outline():
    """A box front with an arched top, counterclockwise in (x, z). Returns (n, 2) float64."""
    half = BOX_WIDTH / 2
    top_x = np.linspace(half, -half, 9)
    top = np.column_stack([top_x, BOX_HEIGHT + BOX_ARCH * (1 - (top_x / half) ** 2)])
    corners = np.array([(-half, 0.0), (half, 0.0)])
    sharp = resample_closed(np.vstack([corners, top]), BOX_OUTLINE_SPACING / 2)
    return resample_closed(chaikin(sharp, SMOOTHING_PASSES), BOX_OUTLINE_SPACING)


def flat_material(name, colour):
    """A plain-coloured material (``colour`` RGBA), shown alike by Workbench, EEVEE and Cycles."""
    material = bpy.data.materials.new(name)
    material.diffuse_color = colour
    material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = colour
    return material


def new_object(name, vertices, faces, colour, collection):
    """Link a new mesh object built from ``vertices`` (n, 3) and ``faces`` into ``collection``.

    Adds a planar front-view (X, Z) UV map over the object's bounds and a flat material.
    """
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices.tolist(), [], [list(face) for face in faces])
    mesh.validate()
    xz = vertices[:, [0, 2]]
    uv = (xz - xz.min(axis=0)) / np.ptp(xz, axis=0)  # (n, 2) in [0, 1]
    loop_vertices = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertices)
    mesh.uv_layers.new(name="UVMap").data.foreach_set("uv", uv[loop_vertices].ravel())
    mesh.materials.append(flat_material(name, colour))
    obj = bpy.data.objects.new(name, mesh)
    if collection is None:
        collection = bpy.context.scene.collection
    collection.objects.link(obj)
    return obj


def make_cutout(name="Bunny", collection=None):
    """A flat, triangulated bunny cut-out in the XZ plane facing -Y, about 2 units tall.

    Parameters
    ----------
    name : str
        Name of the new object, its mesh and its material.
    collection : bpy.types.Collection, optional
        Where to link it; the current scene's master collection by default.

    Returns
    -------
    bpy.types.Object
    """
    vertices, triangles = fill_outline(bunny_outline(), BUNNY_SPACING)
    xyz = np.column_stack([vertices[:, 0], np.zeros(len(vertices)), vertices[:, 1]])
    return new_object(name, xyz, triangles, BUNNY_COLOUR, collection)


def make_extruded(name="CrackerBox", collection=None):
    """A closed animal-cracker box: an arched box front in XZ extruded along Y.

    The front (Y < 0) and back caps are triangulated with interior vertices; the sides are
    quads. All faces point outwards.

    Parameters
    ----------
    name : str
        Name of the new object, its mesh and its material.
    collection : bpy.types.Collection, optional
        Where to link it; the current scene's master collection by default.

    Returns
    -------
    bpy.types.Object
    """
    outline = box_outline()
    vertices, triangles = fill_outline(outline, BOX_INTERIOR_SPACING)
    m, n = len(vertices), len(outline)
    front = np.column_stack([vertices[:, 0], np.full(m, -BOX_DEPTH / 2), vertices[:, 1]])
    back = front * (1.0, -1.0, 1.0)
    ring = np.arange(n)
    following = (ring + 1) % n
    sides = np.column_stack([ring, ring + m, following + m, following])  # outward quads
    faces = [*triangles, *(triangles[:, ::-1] + m), *sides]
    return new_object(name, np.vstack([front, back]), faces, BOX_COLOUR, collection)


def main():
    """Build both characters into an empty scene, print their sizes, save a .blend to check."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    for obj in (make_cutout(), make_extruded()):
        corners = np.array(obj.bound_box)
        print(
            f"{obj.name}: {len(obj.data.vertices)} vertices, {len(obj.data.polygons)} faces,"
            f" bounds {corners.min(axis=0).round(3)} .. {corners.max(axis=0).round(3)}"
        )
    bpy.ops.wm.save_as_mainfile(filepath="/tmp/characters_check.blend")


if __name__ == "__main__":
    main()
