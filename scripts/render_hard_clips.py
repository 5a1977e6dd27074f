"""Render the hard test clips: a painted sheet bent, tilted, curled, crumpled, lit badly and shaken.

Run headless with the project's virtual environment (Blender as a Python module), one clip after
the other on one CPU core (the process pins itself to one core and renders with one thread)::

    .venv/bin/python scripts/render_hard_clips.py [--out samples/hard] [--only NAME ...]

``--draft`` renders the same scenes with Workbench in seconds (no motion blur, no Cycles
shading) to check the geometry and the ground truth; its clips are not the committed ones.

Every clip NAME writes into ``--out``:

``NAME.mp4``
    H.264 from Blender's FFmpeg, 640x360, with mild gaussian sensor noise added before encoding.
``NAME.json``
    ``{"points": [[x, y], ...]}``: a closed outline (a rounded rectangle, clockwise on screen) of
    a region of the sheet on frame 0, about ``OUTLINE_MARGIN`` px inside the sheet's edge, in
    OpenCV pixel coordinates (origin at the centre of the top-left pixel, y down).
``NAME_truth.npz``
    ``lattice`` (T, R, C, 2) float32: where a regular R x C grid of sheet points is in every
    frame, same pixel convention, projected from Blender's evaluated (deformed) mesh;
    ``visible`` (T, R, C) bool: the point is inside the image, on the side of the sheet turned
    towards the camera and not hidden by anything (a ray cast from the camera); ``fps``.
    On frame 0 the sheet lies flat and square to the camera, so there the lattice is an
    axis-aligned grid (see ``lattice_truth`` in ``voodoo_addon/bench.py``).

and ``README.md`` lists the clips. The clips (all but ``fast_8fps`` at 30 fps; perspective
camera; every sheet holds its rest pose for the first three frames):

``bend_out``
    One half of a matte foam patch bends towards the camera up to 80 degrees and back while the
    whole patch drifts: strong foreshortening and a fold line.
``tilt_twist``
    The patch tilts 55 degrees about a horizontal axis and back, then 55 degrees about a vertical
    axis and back, then twists 45 degrees end to end and back: perspective foreshortening.
``curl_away``
    The top edge curls away from the camera through 210 degrees, holds, and unrolls flat: the
    painted side turns its back to the camera and part of it is hidden (``visible`` false).
``glossy``
    A varnished (roughness 0.2) sheet bends and turns under a small strong lamp beside the
    camera: specular highlights and shading sweep across the paint.
``lighting_drift``
    Ten seconds of slow, gentle motion of a photo-like, low-contrast print while the exposure
    hunts (slow drift and steps of x1.5 and x0.7), the white balance drifts (+-15 % per
    channel) and the shadow of an unseen hand passes over the sheet twice.
``fast_8fps``
    8 fps: mostly 20-45 px of motion per frame, turns of up to 11 degrees per frame and bending,
    with Cycles motion blur (the truth is at the shutter's centre).
``crumple``
    A thin printed bag crumples: creases grow, the sheet is squeezed and folds over itself so
    that some of it is hidden for a while, then it relaxes almost flat.

Everything is seeded: the same command makes the same scenes, truth and outlines (Cycles runs
seeded on one thread, so the renders should repeat too). All seven take about 50 minutes.
"""

import os

# Cycles' thread pool sizes itself from the CPUs this process may use: pin to one core before
# bpy starts it, or a second worker spins on the other core while the first renders.
os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402

import bpy  # noqa: E402  (first of the Blender modules: it makes the others importable)

# isort: split
import bmesh  # noqa: E402
import cv2  # noqa: E402
import hard_textures as paint  # noqa: E402  (scripts/ is on sys.path when run as a script)
import numpy as np  # noqa: E402
from blender_scene import (  # noqa: E402
    packed_image,
    rounded_rectangle,
    textured_grid,
    textured_material,
)
from bpy_extras import anim_utils  # noqa: E402
from bpy_extras.object_utils import world_to_camera_view  # noqa: E402
from foam_paint import backdrop_texture, painted_foam_texture  # noqa: E402
from mathutils import Matrix, Vector  # noqa: E402

WIDTH, HEIGHT = 640, 360
SEED = 2025
NOISE_SIGMA = 0.015  # sensor noise, as a fraction of full scale
MAX_VIDEO_BYTES = 1_400_000
CRF_STEPS = ("MEDIUM", "LOW", "VERYLOW", "LOWEST")  # tried in turn until the video is small

# Perspective camera above the origin looking down -Z (image x = world X, image y = -world Y):
# at the sheet's rest depth 1 world unit is about 104 px.
CAMERA_HEIGHT = 6.0
LENS_MM, SENSOR_MM = 35.0, 36.0
BACKDROP_SIZE = (16.0, 10.0)
BACKDROP_DEPTH = -2.0
TEXELS = 1024  # texture width; the height follows the sheet's aspect
FOAM_THICKNESS = 0.03
BACK_COLOUR = (0.80, 0.76, 0.66, 1.0)  # unpainted foam: the sheet's back and rim

OUTLINE_MARGIN = 10.0  # px between the region outline and the sheet's edge on frame 0
OUTLINE_POINTS = 60
OUTLINE_CORNER = 0.25  # corner radius as a fraction of the region's shorter half side
RAY_EPSILON = 1e-3  # world units short of the point, so the ray does not hit the point itself


@dataclass
class Sheet:
    """The painted sheet: a grid mesh of ``segments`` cells and its ground-truth lattice."""

    obj: bpy.types.Object
    size: tuple[float, float]
    segments: tuple[int, int]
    stride: int  # keep every stride-th vertex along each axis for the lattice

    def grid_index(self):
        """Vertex index of each grid node, rows top-down in the image: (rows + 1, cols + 1)."""
        co = np.empty(len(self.obj.data.vertices) * 3)
        self.obj.data.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)
        col = np.round((co[:, 0] / self.size[0] + 0.5) * self.segments[0]).astype(int)
        row = np.round((0.5 - co[:, 1] / self.size[1]) * self.segments[1]).astype(int)
        index = np.full((self.segments[1] + 1, self.segments[0] + 1), -1)
        index[row, col] = np.arange(len(co))
        assert (index >= 0).all(), "the sheet is not a regular grid"
        return index


@dataclass(frozen=True)
class Clip:
    name: str
    frames: int
    fps: int
    what: str  # for the README
    build: Callable  # build(rng, clip) -> Sheet, in a scene set up by new_scene
    samples: int = 8  # Cycles samples per pixel (denoised)
    motion_blur: bool = False
    post: Callable | None = None  # post(frame index, seconds, linear RGB (H, W, 3)) -> same

    def keyframe(self, target, channels):
        """Keyframe ``{(data path, index): [(seconds, value), ...]}`` on ``target``."""
        action = bpy.data.actions.new(f"{target.name}Motion")
        slot = action.slots.new(id_type=target.id_type, name=target.name)
        target.animation_data_create()
        target.animation_data.action = action
        target.animation_data.action_slot = slot
        channelbag = anim_utils.action_ensure_channelbag_for_slot(action, slot)
        for (data_path, index), keys in channels.items():
            fcurve = channelbag.fcurves.new(data_path, index=index)
            for seconds, value in keys:
                fcurve.keyframe_points.insert(1 + seconds * self.fps, value)
            fcurve.update()


# --- scene ----------------------------------------------------------------------------------


def new_scene(clip, draft):
    """Reset Blender; render settings, camera, world and backdrop for ``clip``."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    render = scene.render
    render.resolution_x, render.resolution_y = WIDTH, HEIGHT
    render.resolution_percentage = 100
    render.fps, render.fps_base = clip.fps, 1.0
    render.threads_mode, render.threads = "FIXED", 1
    scene.frame_start, scene.frame_end = 1, clip.frames
    scene.view_settings.view_transform = "Standard"
    if draft:
        render.engine = "BLENDER_WORKBENCH"
        scene.display.shading.light = "STUDIO"
        scene.display.shading.color_type = "TEXTURE"
    else:
        render.engine = "CYCLES"
        cycles = scene.cycles
        cycles.device = "CPU"
        cycles.samples = clip.samples
        cycles.use_adaptive_sampling = False
        cycles.seed, cycles.use_animated_seed = SEED, True
        cycles.use_denoising = True
        cycles.denoiser = "OPENIMAGEDENOISE"
        cycles.denoising_input_passes = "RGB_ALBEDO"
        cycles.denoising_prefilter = "NONE"
        cycles.denoising_quality = "FAST"
        cycles.max_bounces, cycles.diffuse_bounces, cycles.glossy_bounces = 3, 2, 2
        cycles.transmission_bounces = cycles.volume_bounces = 0
        cycles.caustics_reflective = cycles.caustics_refractive = False
        render.use_persistent_data = True
        render.use_motion_blur = clip.motion_blur
        render.motion_blur_position = "CENTER"  # frame f is the shutter's centre
        render.motion_blur_shutter = 0.5

    world = bpy.data.worlds.new("World")
    scene.world = world
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.03, 0.03, 0.035, 1)

    camera = bpy.data.cameras.new("Camera")
    camera.lens, camera.sensor_width, camera.sensor_fit = LENS_MM, SENSOR_MM, "HORIZONTAL"
    camera.clip_start, camera.clip_end = 0.1, 50.0
    camera_obj = bpy.data.objects.new("Camera", camera)
    camera_obj.location = (0.0, 0.0, CAMERA_HEIGHT)
    scene.collection.objects.link(camera_obj)
    scene.camera = camera_obj

    rng = np.random.default_rng([SEED, 0])  # the same backdrop in every clip
    backdrop = packed_image("Backdrop", backdrop_texture(rng, 480, 300))
    textured_grid(
        "Backdrop", BACKDROP_SIZE, (1, 1), textured_material("Backdrop", backdrop), BACKDROP_DEPTH
    )
    return scene


def add_light(name, kind, location, energy, size, target=(0.0, 0.0, 0.0), **settings):
    """A lamp at ``location`` aimed at ``target`` (``size``: area side or lamp radius)."""
    light = bpy.data.lights.new(name, kind)
    light.energy = energy
    if kind == "AREA":
        light.size = size
    else:
        light.shadow_soft_size = size
    for key, value in settings.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(name, light)
    obj.location = location
    obj.rotation_euler = (Vector(target) - Vector(location)).to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(obj)
    return obj


def studio_lights(key=700.0, fill=120.0):
    """A soft key from the upper left and a weaker fill from the lower right."""
    add_light("Key", "AREA", (-3.5, 3.0, 6.0), key, 2.5)
    add_light("Fill", "AREA", (4.0, -3.0, 4.0), fill, 3.0)


def paint_material(name, pixels, roughness, specular=0.3, coat=0.0):
    """A Principled material: ``pixels`` on the front, unpainted foam behind."""
    material = textured_material(name, packed_image(name, pixels))
    nodes, links = material.node_tree.nodes, material.node_tree.links
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular IOR Level"].default_value = specular
    bsdf.inputs["Coat Weight"].default_value = coat
    texture = nodes.active
    backfacing = nodes.new("ShaderNodeNewGeometry")
    mix = nodes.new("ShaderNodeMix")
    mix.data_type = "RGBA"
    socket = {s.identifier: s for s in (*mix.inputs, *mix.outputs)}  # names repeat, ids do not
    links.new(backfacing.outputs["Backfacing"], socket["Factor_Float"])
    links.new(texture.outputs["Color"], socket["A_Color"])
    socket["B_Color"].default_value = BACK_COLOUR
    links.new(socket["Result_Color"], bsdf.inputs["Base Color"])
    return material


def plain_material(name, colour, roughness=0.9):
    material = bpy.data.materials.new(name)
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = colour
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular IOR Level"].default_value = 0.2
    return material


def add_sheet(texture, size, segments, stride, roughness=0.85, thickness=FOAM_THICKNESS, **kw):
    """The painted sheet, flat in the XY plane at the origin, smooth shaded.

    ``texture(rng, width, height)`` paints it; ``thickness`` > 0 gives it an unpainted back and
    rim (a Solidify modifier, added by ``finish_sheet`` after the deformers).
    """
    rng = kw.pop("rng")
    pixels = texture(rng, TEXELS, round(TEXELS * size[1] / size[0]))
    obj = textured_grid("Sheet", size, segments, paint_material("Paint", pixels, roughness, **kw))
    obj.data.shade_smooth()
    obj["thickness"] = thickness
    return Sheet(obj, size, segments, stride)


def finish_sheet(sheet):
    """Solidify the sheet (after its deformers) so that it has a back and a rim."""
    thickness = sheet.obj["thickness"]
    if thickness > 0:
        sheet.obj.data.materials.append(plain_material("Foam", BACK_COLOUR))
        solid = sheet.obj.modifiers.new("Thickness", "SOLIDIFY")
        solid.thickness = thickness
        solid.offset = -1.0  # the painted surface stays where it is; the back is behind it
        solid.material_offset = solid.material_offset_rim = 1
    return sheet


def deform_origin(sheet, location, rotation):
    """An empty parented to the sheet: the space a SimpleDeform modifier works in."""
    empty = bpy.data.objects.new("DeformOrigin", None)
    empty.parent = sheet.obj
    empty.location = location
    empty.rotation_euler = rotation
    bpy.context.scene.collection.objects.link(empty)
    return empty


def bend(sheet, name, origin, limits=(0.0, 1.0)):
    """A SimpleDeform BEND: the origin's local X bends around its local Z (towards local +Y)."""
    modifier = sheet.obj.modifiers.new(name, "SIMPLE_DEFORM")
    modifier.deform_method = "BEND"
    modifier.deform_axis = "Z"
    modifier.origin = origin
    modifier.limits = limits
    modifier.angle = 0.0
    return modifier


# Origin rotations for bend(): local X along world X and local +Y towards the camera (+Z)...
BEND_X_TOWARDS_CAMERA = (math.pi / 2, 0.0, 0.0)
# ...local X along world +Y (up in the image) and local +Y away from the camera (-Z).
BEND_Y_AWAY = Matrix(((0, 0, -1), (1, 0, 0), (0, -1, 0))).to_euler()


def deg(keys):
    return [(t, math.radians(v)) for t, v in keys]


# --- clips ----------------------------------------------------------------------------------


def build_bend_out(rng, clip):
    studio_lights()
    sheet = add_sheet(painted_foam_texture, (3.6, 2.4), (96, 64), 4, rng=rng)
    # The right half (origin at the middle, limits from there to the right end) bends up.
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(sheet, "Bend", origin, limits=(0.5, 1.0))
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bend"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (1.4, 80), (1.8, 80), (2.9, 0)]
            ),
            # The hinge starts left of the camera's axis, so the bending half faces it squarely
            # (off axis, perspective would undo much of the foreshortening).
            ("location", 0): [(0.0, -0.9), (0.1, -0.9), (1.6, -1.1), (3.2, -0.75)],
            ("location", 1): [(0.0, 0), (0.1, 0), (1.2, -0.12), (2.6, 0.15), (3.2, 0.1)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.1, 0), (1.5, 8), (3.2, -4)]),
        },
    )
    return finish_sheet(sheet)


def build_tilt_twist(rng, clip):
    studio_lights()
    sheet = add_sheet(paint.spots, (3.2, 2.0), (96, 60), 4, rng=rng)
    twist = sheet.obj.modifiers.new("Twist", "SIMPLE_DEFORM")
    twist.deform_method, twist.deform_axis, twist.angle = "TWIST", "X", 0.0
    clip.keyframe(
        sheet.obj,
        {
            ("rotation_euler", 0): deg([(0.0, 0), (0.1, 0), (0.7, 55), (0.85, 55), (1.35, 0)]),
            ("rotation_euler", 1): deg([(0.0, 0), (1.35, 0), (1.95, -55), (2.1, -55), (2.6, 0)]),
            ('modifiers["Twist"].angle', 0): deg(
                [(0.0, 0), (2.6, 0), (3.2, 45), (3.35, 45), (3.85, 0)]
            ),
            ("location", 0): [(0.0, 0), (0.1, 0), (1.0, 0.2), (2.5, -0.2), (3.85, 0.0)],
        },
    )
    return finish_sheet(sheet)


def build_curl_away(rng, clip):
    studio_lights()
    size = (3.4, 2.4)
    sheet = add_sheet(paint.strokes, size, (96, 68), 4, rng=rng)
    # The top 40 % curls: the bend starts at y0 and runs to the top edge, curling back (-Z).
    y0 = size[1] / 2 - 0.4 * size[1]
    origin = deform_origin(sheet, (0.0, y0, 0.0), BEND_Y_AWAY)
    bend(sheet, "Curl", origin, limits=(0.6, 1.0))
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Curl"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (1.2, 210), (1.9, 210), (2.9, 0)]
            ),
            ("location", 0): [(0.0, 0), (0.1, 0), (1.5, 0.25), (3.2, 0.1)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.1, 0), (1.6, -6), (3.2, -2)]),
        },
    )
    return finish_sheet(sheet)


def build_glossy(rng, clip):
    # A small strong lamp on the camera's side, a dim fill: the highlight is the key. At rest
    # its mirror image falls on the sheet's top right corner; bending and turning sweep it on.
    add_light("Lamp", "POINT", (3.0, 1.9, 5.0), 1100.0, 0.06)
    add_light("Fill", "AREA", (-4.0, -2.0, 5.0), 60.0, 3.0)
    sheet = add_sheet(
        paint.label, (3.4, 2.3), (96, 64), 4, rng=rng, roughness=0.2, specular=0.6, coat=0.3
    )
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(sheet, "Bend", origin)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bend"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (0.8, 60), (1.7, -50), (2.5, 30), (3.0, 0)]
            ),
            ("rotation_euler", 0): deg([(0.0, 0), (0.1, 0), (1.0, -22), (2.0, 18), (3.0, 0)]),
            ("rotation_euler", 1): deg([(0.0, 0), (0.1, 0), (0.7, 20), (1.6, -25), (2.6, 10)]),
            ("location", 0): [(0.0, 0), (0.1, 0), (1.5, -0.3), (3.0, 0.1)],
        },
    )
    return finish_sheet(sheet)


def build_lighting_drift(rng, clip):
    # A spot from the far left at a low angle casts the hand's shadow; a weak fill lifts it.
    lamp = (-7.0, 0.5, 6.0)
    add_light("Lamp", "SPOT", lamp, 6000.0, 0.25, spot_size=math.radians(50), spot_blend=0.5)
    add_light("Fill", "AREA", (3.0, -3.0, 5.0), 120.0, 3.0)
    sheet = add_sheet(paint.photo, (3.2, 2.2), (80, 56), 4, rng=rng, roughness=0.7)
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(sheet, "Bend", origin)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bend"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (2.5, 25), (5.0, -15), (7.5, 20), (10.0, 0)]
            ),
            ("location", 0): [(0.0, 0), (0.1, 0), (3.0, 0.3), (6.5, -0.25), (10.0, 0.05)],
            ("location", 1): [(0.0, 0), (0.1, 0), (4.0, -0.15), (8.0, 0.15), (10.0, 0.0)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.1, 0), (3.5, 8), (7.0, -6), (10.0, 2)]),
            ("rotation_euler", 0): deg([(0.0, 0), (0.1, 0), (4.5, 10), (9.0, -8), (10.0, -6)]),
        },
    )
    # The hand: halfway between the lamp and the sheet (its shadow is twice its size), outside
    # the camera's view and invisible to the camera anyway.
    hand = add_hand()
    height = 3.0
    half = (height / lamp[2]) * np.array(lamp)  # the hand's position at shadow point 0

    def over(x, y):  # the hand's location that casts its shadow at (x, y) on the sheet
        return tuple(half + (1 - height / lamp[2]) * np.array([x, y, 0.0]))

    # Parked with its shadow off the sheet; down over it from 2 s to 4.5 s, up from 6 s to 8.5 s.
    passes = [
        (0.0, (-0.3, 2.6)),
        (2.0, (-0.3, 2.6)),
        (4.5, (0.0, -2.6)),
        (6.0, (0.5, -2.6)),
        (8.5, (0.4, 2.6)),
        (10.0, (0.4, 2.6)),
    ]
    clip.keyframe(
        hand,
        {("location", i): [(t, over(*xy)[i]) for t, xy in passes] for i in range(3)},
    )
    return finish_sheet(sheet)


def add_hand():
    """A rough hand: a flattened palm and four fingers, seen by the lamps only."""
    parts = [((0.0, 0.0, 0.0), (0.45, 0.55, 0.15))]
    parts += [((-0.27 + 0.18 * i, 0.75, 0.0), (0.08, 0.32, 0.07)) for i in range(4)]
    mesh = bpy.data.meshes.new("Hand")
    bm = bmesh.new()
    for centre, radii in parts:
        made = bmesh.ops.create_uvsphere(bm, u_segments=16, v_segments=8, radius=1.0)
        for vert in made["verts"]:
            vert.co = Vector(c + r * v for c, r, v in zip(centre, radii, vert.co, strict=True))
    bm.to_mesh(mesh)
    bm.free()
    mesh.materials.append(plain_material("Skin", (0.6, 0.4, 0.3, 1)))
    hand = bpy.data.objects.new("Hand", mesh)
    hand.visible_camera = False
    bpy.context.scene.collection.objects.link(hand)
    return hand


def build_fast_8fps(rng, clip):
    studio_lights()
    sheet = add_sheet(paint.bold, (2.2, 1.4), (66, 42), 3, rng=rng)
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(sheet, "Bend", origin)
    t = np.arange(clip.frames) / clip.fps  # a key on every frame
    s = np.clip((t - 0.25) / 0.75, 0.0, 1.0)
    speed = s * s * (3 - 2 * s)  # at rest on frames 0-2, then up to full speed by 1 s
    # The motions below run on tau, a clock that starts slowly: their speed ramps up smoothly.
    tau = np.concatenate([[0.0], np.cumsum((speed[1:] + speed[:-1]) / 2 * np.diff(t))])
    curves = {
        ("location", 0): 1.2 * np.sin(1.4 * tau),
        ("location", 1): 0.35 * np.sin(2.1 * tau),
        ("rotation_euler", 2): np.radians(48.0) * np.sin(1.9 * tau),
        ('modifiers["Bend"].angle', 0): np.radians(35.0) * np.sin(2.7 * tau),
    }
    clip.keyframe(
        sheet.obj,
        {key: list(zip(t, values, strict=True)) for key, values in curves.items()},
    )
    return finish_sheet(sheet)


def build_crumple(rng, clip):
    studio_lights(key=650.0, fill=150.0)
    sheet = add_sheet(
        paint.bag_print, (3.2, 2.2), (120, 84), 4, rng=rng, roughness=0.45, thickness=0.0
    )
    creases = bpy.data.textures.new("Creases", "CLOUDS")
    creases.noise_type, creases.noise_basis = "HARD_NOISE", "BLENDER_ORIGINAL"
    creases.noise_scale, creases.noise_depth = 0.45, 2
    folds = bpy.data.textures.new("Folds", "CLOUDS")
    folds.cloud_type, folds.noise_scale, folds.noise_depth = "COLOR", 0.9, 1
    crease = sheet.obj.modifiers.new("Creases", "DISPLACE")
    crease.texture, crease.texture_coords, crease.direction = creases, "LOCAL", "Z"
    crease.mid_level, crease.strength = 0.5, 0.0
    fold = sheet.obj.modifiers.new("Folds", "DISPLACE")
    fold.texture, fold.texture_coords, fold.direction = folds, "LOCAL", "RGB_TO_XYZ"
    fold.mid_level, fold.strength = 0.5, 0.0
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Creases"].strength', 0): [
                (0.0, 0),
                (0.1, 0),
                (1.2, 0.36),
                (1.9, 0.4),
                (3.0, 0.03),
                (3.2, 0.03),
            ],
            ('modifiers["Folds"].strength', 0): [
                (0.0, 0),
                (0.1, 0),
                (1.2, 0.75),
                (1.9, 0.8),
                (3.0, 0.04),
                (3.2, 0.04),
            ],
            ("scale", 0): [(0.0, 1), (0.1, 1), (1.2, 0.78), (1.9, 0.8), (3.0, 0.98)],
            ("scale", 1): [(0.0, 1), (0.1, 1), (1.2, 0.9), (1.9, 0.88), (3.0, 0.99)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.1, 0), (1.5, 7), (3.2, 2)]),
        },
    )
    return finish_sheet(sheet)


def srgb_to_linear(image):
    return np.where(image <= 0.04045, image / 12.92, ((image + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(image):
    image = np.clip(image, 0.0, 1.0)
    return np.where(image <= 0.0031308, image * 12.92, 1.055 * image ** (1 / 2.4) - 0.055)


# Exposure steps of lighting_drift: (seconds, factor), each holding from then on.
EXPOSURE_STEPS = ((3.4, 1.5), (6.9, 0.7))


def camera_drift(index, seconds, linear):
    """Auto-exposure hunting and a drifting white balance, in linear light."""
    exposure = (
        1.0
        + 0.12 * math.sin(2 * math.pi * seconds / 6.5)
        + 0.06 * math.sin(2 * math.pi * seconds / 2.1 + 1.0)
    )
    for start, factor in EXPOSURE_STEPS:
        if seconds >= start:
            exposure *= factor
    phases = np.array([0.3, 2.4, 4.4])
    periods = np.array([9.0, 7.0, 11.0])
    balance = 1.0 + 0.15 * np.sin(2 * np.pi * seconds / periods + phases) * min(1, seconds)
    return linear * (exposure * balance)


CLIPS = [
    Clip(
        "bend_out",
        96,
        30,
        "the right half of a matte foam patch bends towards the camera to 80 deg and back "
        "while the patch drifts",
        build_bend_out,
    ),
    Clip(
        "tilt_twist",
        120,
        30,
        "tilts 55 deg about a horizontal axis and back, 55 deg about a vertical axis and back, "
        "then twists 45 deg end to end and back",
        build_tilt_twist,
    ),
    Clip(
        "curl_away",
        96,
        30,
        "the top edge curls away from the camera through 210 deg (back turned, part hidden), "
        "holds, unrolls flat",
        build_curl_away,
    ),
    Clip(
        "glossy",
        90,
        30,
        "varnished sheet (roughness 0.2) bends and turns under a small strong lamp beside the "
        "camera: highlights sweep across",
        build_glossy,
        samples=12,
    ),
    Clip(
        "lighting_drift",
        300,
        30,
        "slow gentle motion of a low-contrast photo-like print; exposure drifts and steps "
        "(x1.5, x0.7), white balance drifts +-15 %, a hand's shadow passes twice",
        build_lighting_drift,
        post=camera_drift,
    ),
    Clip(
        "fast_8fps",
        56,
        8,
        "8 fps, mostly 20-45 px per frame, turns up to 11 deg per frame and bending, with motion "
        "blur",
        build_fast_8fps,
        samples=12,
        motion_blur=True,
    ),
    Clip(
        "crumple",
        96,
        30,
        "a thin printed bag crumples (creases, squeeze, folds over itself) and relaxes almost flat",
        build_crumple,
    ),
]


# --- ground truth ---------------------------------------------------------------------------


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
    n_vertices = index.size
    keep = (slice(None, None, sheet.stride), slice(None, None, sheet.stride))
    assert all((s % sheet.stride) == 0 for s in sheet.segments), "stride must divide the grid"
    lattices, visibles = [], []
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        evaluated = sheet.obj.evaluated_get(depsgraph)
        vertices = evaluated.data.vertices
        co = np.empty(len(vertices) * 3)
        vertices.foreach_get("co", co)
        local = co.reshape(-1, 3)[:n_vertices][index]  # (rows + 1, cols + 1, 3)
        world_matrix = np.array(evaluated.matrix_world)
        world = local @ world_matrix[:3, :3].T + world_matrix[:3, 3]
        # The painted side's normal from the grid itself (rows run down the image, i.e. -Y).
        normal = np.cross(np.gradient(world, axis=0), np.gradient(world, axis=1))
        eye = np.array(camera.matrix_world.translation)
        pixels, visible = [], []
        for point, n in zip(world[keep].reshape(-1, 3), normal[keep].reshape(-1, 3), strict=True):
            ndc = world_to_camera_view(scene, camera, Vector(point))  # x right, y up, [0, 1]
            x, y = ndc.x * WIDTH - 0.5, (1.0 - ndc.y) * HEIGHT - 0.5
            pixels.append((x, y))
            inside = -0.5 <= x <= WIDTH - 0.5 and -0.5 <= y <= HEIGHT - 0.5 and ndc.z > 0
            facing = float(np.dot(n, eye - point)) > 0.0
            visible.append(inside and facing and not occluded(scene, depsgraph, eye, point))
        shape = world[keep].shape[:2]
        lattices.append(np.reshape(pixels, (*shape, 2)))
        visibles.append(np.reshape(visible, shape))
        if frame == scene.frame_start:
            rest = np.array([v.co[:] for v in sheet.obj.data.vertices])[index]
            assert np.allclose(local, rest, atol=1e-5), "evaluated vertices do not match"
    return np.array(lattices, dtype=np.float32), np.array(visibles)


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


# --- video ----------------------------------------------------------------------------------


def render_frames(scene, folder):
    """Render the animation as 16-bit PNGs into ``folder``. Returns their paths in order."""
    settings = scene.render.image_settings
    settings.media_type = "IMAGE"
    settings.file_format = "PNG"
    settings.color_mode, settings.color_depth = "RGB", "16"
    scene.render.filepath = str(folder / "frame_")
    bpy.ops.render.render(animation=True)
    paths = sorted(folder.glob("frame_*.png"))
    assert len(paths) == scene.frame_end - scene.frame_start + 1, "frames are missing"
    return paths


def develop(clip, paths, folder):
    """Camera post: ``clip.post`` in linear light, sensor noise, 8 bits. Returns PNG paths."""
    rng = np.random.default_rng([SEED, 1, CLIPS.index(clip)])
    out = []
    for i, path in enumerate(paths):
        image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)[..., ::-1] / 65535.0  # RGB
        if clip.post is not None:
            image = linear_to_srgb(clip.post(i, i / clip.fps, srgb_to_linear(image)))
        image = image + rng.normal(0.0, NOISE_SIGMA, image.shape)
        rgb = np.clip(np.round(image * 255), 0, 255).astype(np.uint8)
        out.append(folder / f"cam_{i:04d}.png")
        cv2.imwrite(str(out[-1]), rgb[..., ::-1])
    return out


def encode(paths, fps, video_path):
    """H.264 MP4 of the PNGs through Blender's sequencer and FFmpeg, small enough.

    Tries ever lower qualities (CRF_STEPS) until the file is under MAX_VIDEO_BYTES.
    """
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    editor = scene.sequence_editor_create()
    strip = editor.strips.new_image("Frames", str(paths[0]), channel=1, frame_start=1)
    for path in paths[1:]:
        strip.elements.append(path.name)
    strip.colorspace_settings.name = "sRGB"
    scene.view_settings.view_transform = "Standard"
    render = scene.render
    render.resolution_x, render.resolution_y = WIDTH, HEIGHT
    render.resolution_percentage = 100
    render.fps, render.fps_base = fps, 1.0
    render.threads_mode, render.threads = "FIXED", 1
    scene.frame_start, scene.frame_end = 1, len(paths)
    settings = render.image_settings
    settings.media_type = "VIDEO"
    settings.file_format = "FFMPEG"
    settings.color_mode = "RGB"
    ffmpeg = render.ffmpeg
    ffmpeg.format, ffmpeg.codec = "MPEG4", "H264"
    ffmpeg.ffmpeg_preset = "GOOD"
    ffmpeg.gopsize = fps
    ffmpeg.use_max_b_frames, ffmpeg.max_b_frames = True, 0
    render.use_file_extension = False
    render.filepath = str(video_path)
    for crf in CRF_STEPS:
        ffmpeg.constant_rate_factor = crf
        bpy.ops.render.render(animation=True)
        if video_path.stat().st_size <= MAX_VIDEO_BYTES:
            break
    return crf


# --- main -----------------------------------------------------------------------------------


def make_clip(clip, out, draft, truth_only=False):
    rng = np.random.default_rng([SEED, 2, CLIPS.index(clip)])
    scene = new_scene(clip, draft)
    sheet = clip.build(rng, clip)
    started = time.perf_counter()
    lattice, visible = lattice_truth(scene, sheet)
    truth_s = time.perf_counter() - started
    np.savez_compressed(
        out / f"{clip.name}_truth.npz", lattice=lattice, visible=visible, fps=float(clip.fps)
    )
    outline = region_outline(lattice[0])
    (out / f"{clip.name}.json").write_text(
        json.dumps({"points": np.round(outline, 2).tolist()}) + "\n"
    )
    if truth_only:
        print(
            f"{clip.name}: truth in {truth_s:.0f} s, min visible "
            f"{visible.mean(axis=(1, 2)).min():.2f}"
        )
        return 0.0
    with tempfile.TemporaryDirectory(prefix=f"hard_{clip.name}_") as tmp:
        tmp = Path(tmp)
        started = time.perf_counter()
        paths = render_frames(scene, tmp)
        render_s = time.perf_counter() - started
        video = out.resolve() / f"{clip.name}.mp4"
        crf = encode(develop(clip, paths, tmp), clip.fps, video)
    print(
        f"{clip.name}: {clip.frames} frames at {clip.fps} fps, lattice {lattice.shape[1:3]}, "
        f"truth {truth_s:.0f} s, render {render_s:.0f} s ({render_s / clip.frames:.2f} s/frame),"
        f" video {video.stat().st_size} bytes (CRF {crf}), min visible "
        f"{visible.mean(axis=(1, 2)).min():.2f}",
        flush=True,
    )
    return render_s


README = """# Hard test clips

Rendered with Blender {blender} (the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py): every scene, texture,
motion and the camera post-processing is generated by the script from a fixed seed, so the same
command makes the same scenes, truth and outlines (about 50 minutes on one CPU core):

    .venv/bin/python scripts/render_hard_clips.py --out samples/hard

(`--only NAME ...` remakes some clips only). Check them with
`.venv/bin/python scripts/check_hard_clips.py` (statistics, and contact sheets in
`/tmp/hard_check/`); `.venv/bin/python scripts/check_truth_dots.py` re-renders a few frames
with dots painted on the lattice points and measures them against the truth.

Each clip NAME has `NAME.mp4` (H.264, {width}x{height}, mild gaussian sensor noise of
{noise:.1f} % added before encoding), `NAME.json` (the region outline on frame 0, OpenCV pixel
coordinates) and `NAME_truth.npz` (`lattice` (T, R, C, 2) float32: pixel positions of a grid of
surface points in every frame, projected from the renderer's deformed mesh; `visible` (T, R, C):
inside the image, painted side towards the camera and not hidden, by ray casts; `fps`). Frame 0
shows the sheet flat, square to the perspective camera and at rest for three frames, so the
frame-0 lattice is an axis-aligned grid.

| clip | frames | fps | what happens | renderer |
| --- | ---: | ---: | --- | --- |
{rows}
"""


def write_readme(out):
    rows = []
    for clip in CLIPS:
        renderer = f"Cycles (CPU), {clip.samples} spp + OIDN denoiser"
        if clip.motion_blur:
            renderer += ", motion blur (shutter 0.5 frame, centred)"
        if clip.post is not None:
            renderer += "; exposure and white balance in post"
        rows.append(f"| `{clip.name}` | {clip.frames} | {clip.fps} | {clip.what} | {renderer} |")
    (out / "README.md").write_text(
        README.format(
            blender=bpy.app.version_string,
            width=WIDTH,
            height=HEIGHT,
            noise=100 * NOISE_SIGMA,
            rows="\n".join(rows),
        )
    )


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("samples/hard"), help="output folder")
    parser.add_argument(
        "--only", nargs="+", choices=[c.name for c in CLIPS], help="make only these clips"
    )
    parser.add_argument(
        "--draft", action="store_true", help="render with Workbench, to check the geometry"
    )
    parser.add_argument(
        "--truth-only", action="store_true", help="write the ground truth, render nothing"
    )
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    total = 0.0
    for clip in CLIPS:
        if args.only is None or clip.name in args.only:
            total += make_clip(clip, args.out, args.draft, args.truth_only)
    if not (args.draft or args.truth_only):
        write_readme(args.out)
    print(f"rendering took {total:.0f} s in all")


if __name__ == "__main__":
    main()
