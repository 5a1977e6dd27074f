"""Render the sample take: a painted foam slab moved, turned, bent and squeezed before a camera.

Run headless with the project's virtual environment (Blender as a Python module)::

    .venv/bin/python scripts/make_sample.py [--out samples] [--frames 150]

Writes into ``--out``:

``sample_take.mp4``
    640x480, 30 fps, H.264, rendered with Workbench. Frame 0 of the video (scene frame 1) shows
    the slab at rest and unbent.
``sample_take.json``
    ``{"points": [[x, y], ...]}``: a closed rounded-rectangle outline of a region of the slab on
    frame 0, in OpenCV pixel coordinates (origin at the centre of the top-left pixel, y down),
    computed by projecting the slab through the camera.

The motion schedule is written in seconds, so speeds do not depend on ``--frames``: a shorter
clip shows the start of the schedule, a longer one holds the last pose. Everything is seeded;
the same command makes the same clip.
"""

import argparse
import json
import math
import time
from pathlib import Path

import bpy  # first: importing bpy makes bmesh and bpy_extras importable

# isort: split
import bmesh
import numpy as np
from bpy_extras import anim_utils
from bpy_extras.object_utils import world_to_camera_view
from characters import resample_closed  # scripts/ is on sys.path when run as a script
from scipy.ndimage import zoom

WIDTH, HEIGHT = 640, 480
FPS = 30
DEFAULT_FRAMES = 150
SEED = 1998
VIDEO_NAME = "sample_take.mp4"
CONTOUR_NAME = "sample_take.json"
TRUTH_NAME = "sample_truth.npz"
TRUTH_STRIDE = 2  # keep every 2nd slab vertex along each axis for the ground truth

# Orthographic camera looking down -Z: ORTHO_SCALE world units span the frame width.
ORTHO_SCALE = 8.0
CAMERA_HEIGHT = 10.0

# The slab lies in the XY plane at the origin; SLAB_SIZE[0] is 40% of the frame width.
SLAB_SIZE = (3.2, 2.2)
SLAB_SEGMENTS = (64, 44)
SLAB_TEXTURE_SIZE = (512, 352)
GRID_CELLS = (7, 5)
LINE_WIDTH = 7.0  # texels
WOBBLE = 5.0  # texels: hand-painted lines are not straight
N_BLOBS = 14
N_DOTS = 60
PAINT_COLOURS = np.array(
    [
        (0.86, 0.20, 0.16),  # red
        (0.95, 0.55, 0.12),  # orange
        (0.96, 0.84, 0.25),  # yellow
        (0.35, 0.70, 0.28),  # green
        (0.16, 0.62, 0.66),  # teal
        (0.22, 0.38, 0.80),  # blue
        (0.56, 0.32, 0.70),  # purple
        (0.93, 0.56, 0.68),  # pink
        (0.93, 0.89, 0.78),  # cream
    ]
)
LINE_COLOUR = (0.07, 0.06, 0.08)

# The backdrop: a darker, faintly mottled plane behind the slab.
BACKDROP_SIZE = (10.0, 8.0)
BACKDROP_DEPTH = -0.5
BACKDROP_TEXTURE_SIZE = (320, 256)
BACKDROP_COLOUR = (0.17, 0.17, 0.19)
BACKDROP_MOTTLE = 0.04
BACKDROP_GRAIN = 0.012

# Motion schedule: channel -> [(time in seconds, value)]. Bezier-eased between keys (Blender's
# default auto-clamped handles): smooth, and flat at every hold and turning point. Locations in
# world units (1 unit = 80 px), turns and bends in degrees, taper as the modifier's factor.
MOTION = {
    "x": [(0.0, 0.0), (0.3, 0.0), (1.3, 0.6), (2.5, -0.5), (3.7, 0.3), (4.7, -0.1)],
    "y": [(0.0, 0.0), (0.3, 0.0), (1.1, 0.3), (2.2, -0.3), (3.4, 0.2), (4.6, 0.0)],
    "turn": [
        (0.0, 0.0),
        (0.5, 0.0),
        (1.5, 25.0),
        (2.2, 25.0),
        (3.6, -30.0),
        (4.2, -15.0),
        (5.0, 15.0),
    ],
    "scale_x": [
        (0.0, 1.0),
        (1.0, 1.0),
        (1.8, 1.2),
        (2.6, 1.0),
        (3.4, 0.82),
        (4.2, 0.9),
        (5.0, 1.0),
    ],
    "scale_y": [
        (0.0, 1.0),
        (1.0, 1.0),
        (1.8, 1.2),
        (2.6, 1.0),
        (3.4, 1.12),
        (4.2, 0.9),
        (5.0, 1.0),
    ],
    "bend": [
        (0.0, 0.0),
        (0.6, 0.0),
        (1.5, 55.0),
        (2.9, -55.0),
        (3.6, 0.0),
        (4.3, 40.0),
        (5.0, 0.0),
    ],
    "taper": [(0.0, 0.0), (2.5, 0.0), (3.2, 0.16), (3.9, -0.14), (4.6, 0.0)],
}

# Region outline on frame 0: a rounded rectangle centred on the slab's projection.
REGION_FRACTION = 0.8  # of the slab's projected width and height
REGION_CORNER = 0.3  # corner radius as a fraction of the region's shorter half side
REGION_SPACING = 12.0  # pixels between outline points
ARC_SAMPLES = 32  # per rounded corner, before even resampling


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("samples"), help="output folder")
    parser.add_argument("--frames", type=int, default=DEFAULT_FRAMES, help="clip length")
    parser.add_argument(
        "--truth-only", action="store_true", help="write the ground truth, render nothing"
    )
    return parser.parse_args(argv)


def smooth_noise(rng, shape, cells):
    """Smooth random field in [-1, 1]: a coarse random grid, bicubically upsampled.

    Returns
    -------
    (shape[0], shape[1]) float64
    """
    coarse = rng.uniform(-1.0, 1.0, size=(cells + 3, cells + 3))
    fine = zoom(coarse, (shape[0] / cells, shape[1] / cells), order=3)
    return np.clip(fine[: shape[0], : shape[1]], -1.0, 1.0)


def painted_foam_texture(rng, width, height):
    """A painted-foam pattern: wobbly dark grid lines over coloured cells, blobs and dots.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float64)
    u = xs + WOBBLE * smooth_noise(rng, (height, width), 6)  # (H, W) wobbled coordinates
    v = ys + WOBBLE * smooth_noise(rng, (height, width), 6)
    cell_w, cell_h = width / GRID_CELLS[0], height / GRID_CELLS[1]
    col = np.clip((u // cell_w).astype(int), 0, GRID_CELLS[0] - 1)
    row = np.clip((v // cell_h).astype(int), 0, GRID_CELLS[1] - 1)
    cell_colour = rng.integers(len(PAINT_COLOURS), size=(GRID_CELLS[1], GRID_CELLS[0]))
    image = PAINT_COLOURS[cell_colour[row, col]]  # (H, W, 3)

    for _ in range(N_BLOBS):
        cx, cy = rng.uniform(0, width), rng.uniform(0, height)
        radius = rng.uniform(0.25, 0.45) * min(cell_w, cell_h)
        inside = np.hypot(u - cx, (v - cy) * rng.uniform(0.7, 1.4)) < radius
        image[inside] = PAINT_COLOURS[rng.integers(len(PAINT_COLOURS))]
    for _ in range(N_DOTS):
        cx, cy = rng.uniform(0, width), rng.uniform(0, height)
        inside = np.hypot(xs - cx, ys - cy) < rng.uniform(2.5, 5.0)
        image[inside] = LINE_COLOUR if rng.random() < 0.6 else PAINT_COLOURS[-1]

    dist_x = np.abs((u + cell_w / 2) % cell_w - cell_w / 2)  # distance to the nearest line
    dist_y = np.abs((v + cell_h / 2) % cell_h - cell_h / 2)
    on_line = np.minimum(dist_x, dist_y) < LINE_WIDTH / 2
    image[on_line] = LINE_COLOUR
    paint = 1.0 + 0.05 * smooth_noise(rng, (height, width), 24)  # uneven paint and foam pores
    return np.clip(image * paint[..., None], 0.0, 1.0).astype(np.float32)


def backdrop_texture(rng, width, height):
    """A dark, faintly mottled backdrop. Returns (height, width, 3) float32, rows top-down."""
    mottle = BACKDROP_MOTTLE * smooth_noise(rng, (height, width), 5)
    grain = BACKDROP_GRAIN * rng.standard_normal((height, width))
    image = np.asarray(BACKDROP_COLOUR) + (mottle + grain)[..., None]
    return np.clip(image, 0.0, 1.0).astype(np.float32)


def packed_image(name, pixels):
    """A packed Blender image holding ``pixels`` (H, W, 3) float in [0, 1], rows top-down."""
    height, width = pixels.shape[:2]
    image = bpy.data.images.new(name, width, height, alpha=False)
    rgba = np.ones((height, width, 4), dtype=np.float32)
    rgba[..., :3] = pixels[::-1]  # Blender stores rows bottom-up
    image.pixels.foreach_set(rgba.ravel())
    image.pack()
    return image


def textured_material(name, image):
    """A material whose base colour is ``image`` (what Workbench shows in TEXTURE mode)."""
    material = bpy.data.materials.new(name)
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    nodes.active = texture
    bsdf = nodes["Principled BSDF"]
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    return material


def textured_grid(name, size, segments, material, depth=0.0):
    """A subdivided rectangle in the XY plane at height ``depth``, UV-mapped over [0, 1]^2."""
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")  # create_grid fills the UV layer that exists
    bmesh.ops.create_grid(
        bm, x_segments=segments[0], y_segments=segments[1], size=0.5, calc_uvs=True
    )
    for vert in bm.verts:
        vert.co = (vert.co.x * size[0], vert.co.y * size[1], depth)
    bm.to_mesh(mesh)
    bm.free()
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def add_deformers(slab):
    """SimpleDeform modifiers: a taper along X, then an in-plane bend about the Z axis."""
    taper = slab.modifiers.new("Taper", "SIMPLE_DEFORM")
    taper.deform_method = "TAPER"
    taper.deform_axis = "X"
    bend = slab.modifiers.new("Bend", "SIMPLE_DEFORM")
    bend.deform_method = "BEND"
    bend.deform_axis = "Z"


def motion_channels():
    """Map each MOTION channel to (data path, array index, conversion to Blender units)."""
    return {
        "x": ("location", 0, float),
        "y": ("location", 1, float),
        "turn": ("rotation_euler", 2, math.radians),
        "scale_x": ("scale", 0, float),
        "scale_y": ("scale", 1, float),
        "bend": ('modifiers["Bend"].angle', 0, math.radians),
        "taper": ('modifiers["Taper"].factor', 0, float),
    }


def animate(slab):
    """Keyframe the MOTION schedule on the slab (scene frame 1 is time 0)."""
    action = bpy.data.actions.new("SlabMotion")
    slot = action.slots.new(id_type="OBJECT", name=slab.name)
    slab.animation_data_create()
    slab.animation_data.action = action
    slab.animation_data.action_slot = slot
    channelbag = anim_utils.action_ensure_channelbag_for_slot(action, slot)
    for channel, (data_path, index, convert) in motion_channels().items():
        fcurve = channelbag.fcurves.new(data_path, index=index)
        for seconds, value in MOTION[channel]:
            fcurve.keyframe_points.insert(1 + seconds * FPS, convert(value))
        fcurve.update()


def add_camera():
    """An orthographic camera above the origin, looking straight down at the slab."""
    camera = bpy.data.cameras.new("Camera")
    camera.type = "ORTHO"
    camera.ortho_scale = ORTHO_SCALE
    obj = bpy.data.objects.new("Camera", camera)
    obj.location = (0.0, 0.0, CAMERA_HEIGHT)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.scene.camera = obj
    return obj


def build_scene(rng):
    """Reset Blender and build backdrop, animated slab and camera. Returns the slab object."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    foam = packed_image("PaintedFoam", painted_foam_texture(rng, *SLAB_TEXTURE_SIZE))
    backdrop = packed_image("Backdrop", backdrop_texture(rng, *BACKDROP_TEXTURE_SIZE))
    textured_grid(
        "Backdrop",
        BACKDROP_SIZE,
        (1, 1),
        textured_material("Backdrop", backdrop),
        depth=BACKDROP_DEPTH,
    )
    slab = textured_grid(
        "FoamSlab", SLAB_SIZE, SLAB_SEGMENTS, textured_material("PaintedFoam", foam)
    )
    add_deformers(slab)
    animate(slab)
    add_camera()
    return slab


def configure_render(scene, n_frames, video_path):
    """Workbench, flat texture colours, Standard view, H.264 MP4 without B-frames."""
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.light = "FLAT"
    scene.display.shading.color_type = "TEXTURE"
    scene.view_settings.view_transform = "Standard"
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    scene.render.fps = FPS
    scene.frame_start, scene.frame_end = 1, n_frames
    settings = scene.render.image_settings
    settings.media_type = "VIDEO"
    settings.file_format = "FFMPEG"
    settings.color_mode = "RGB"
    ffmpeg = scene.render.ffmpeg
    ffmpeg.format = "MPEG4"
    ffmpeg.codec = "H264"
    ffmpeg.constant_rate_factor = "MEDIUM"
    ffmpeg.ffmpeg_preset = "GOOD"
    ffmpeg.gopsize = FPS
    ffmpeg.use_max_b_frames = True
    ffmpeg.max_b_frames = 0
    scene.render.use_file_extension = False
    scene.render.filepath = str(video_path)


def projected_vertices(scene, obj):
    """The evaluated mesh's vertices in OpenCV pixel coordinates at the current frame.

    Returns
    -------
    (n_vertices, 2) float64
    """
    camera = scene.camera
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    world = evaluated.matrix_world
    points = []
    for vert in evaluated.data.vertices:
        ndc = world_to_camera_view(scene, camera, world @ vert.co)  # x right, y up, in [0, 1]
        points.append((ndc.x * WIDTH - 0.5, (1.0 - ndc.y) * HEIGHT - 0.5))
    return np.array(points)


def rounded_rectangle(centre, half_size, radius, spacing):
    """Points evenly about ``spacing`` apart around a rounded rectangle.

    The outline runs clockwise on screen (angle increasing with y down); its straight sides are
    the gaps between the four corner arcs.

    Returns
    -------
    (n_points, 2) float64
    """
    angles = (np.arange(4 * ARC_SAMPLES) + 0.5) * (math.pi / 2 / ARC_SAMPLES)
    directions = np.column_stack([np.cos(angles), np.sin(angles)])  # (4 * ARC_SAMPLES, 2)
    arc_centres = (np.asarray(half_size) - radius) * np.sign(directions)
    return np.asarray(centre) + resample_closed(arc_centres + radius * directions, spacing)


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
    co = np.array([v.co[:2] for v in slab.data.vertices])
    col = np.round((co[:, 0] / SLAB_SIZE[0] + 0.5) * SLAB_SEGMENTS[0]).astype(int)
    row = np.round((0.5 - co[:, 1] / SLAB_SIZE[1]) * SLAB_SEGMENTS[1]).astype(int)  # image down
    keep = (col % TRUTH_STRIDE == 0) & (row % TRUTH_STRIDE == 0)
    order = np.lexsort((col[keep], row[keep]))
    shape = (SLAB_SEGMENTS[1] // TRUTH_STRIDE + 1, SLAB_SEGMENTS[0] // TRUTH_STRIDE + 1)
    frames = []
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        frames.append(projected_vertices(scene, slab)[keep][order].reshape(*shape, 2))
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


def main(argv=None):
    args = parse_args(argv)
    started = time.perf_counter()
    args.out.mkdir(parents=True, exist_ok=True)
    video_path = args.out.resolve() / VIDEO_NAME
    slab = build_scene(np.random.default_rng(SEED))
    scene = bpy.context.scene
    configure_render(scene, args.frames, video_path)

    points = region_outline(scene, slab)
    contour_path = args.out / CONTOUR_NAME
    contour_path.write_text(json.dumps({"points": np.round(points, 2).tolist()}) + "\n")
    print(f"max slab speed {max_speed(scene, slab):.1f} px/frame")
    truth_path = args.out / TRUTH_NAME
    np.savez_compressed(truth_path, lattice=lattice_truth(scene, slab))
    print(f"wrote {truth_path} ({truth_path.stat().st_size / 1e6:.2f} MB)")
    if args.truth_only:
        return

    bpy.ops.render.render(animation=True)
    print(
        f"wrote {video_path} ({video_path.stat().st_size / 1e6:.2f} MB, {args.frames} frames)"
        f" and {contour_path} ({len(points)} points) in {time.perf_counter() - started:.1f} s"
    )


if __name__ == "__main__":
    main()
