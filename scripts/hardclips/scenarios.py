"""The hard clips, one ``build_*`` function each, and ``CLIPS``, the list that names them.

A builder runs in a scene made by ``new_scene``: it adds the lamps and the sheet, keys the
motion in seconds (the sheet holds its rest pose for the first three frames) and returns the
finished ``Sheet``. ``camera_drift`` is the camera post of ``lighting_drift``.
"""

import math

import bpy

# isort: split
import bmesh
import hard_textures as paint  # scripts/ is on sys.path when a script runs
import numpy as np
from foam_paint import painted_foam_texture
from mathutils import Vector

from hardclips.materials import add_light, plain_material, studio_lights
from hardclips.scene import Clip
from hardclips.sheet import (
    BEND_X_TOWARDS_CAMERA,
    BEND_Y_AWAY,
    add_sheet,
    bend,
    deform_origin,
    deg,
    finish_sheet,
)


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


def ellipsoids(name, parts):
    """A mesh of ellipsoids, one per ``(centre, radii)`` in ``parts``."""
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    for centre, radii in parts:
        made = bmesh.ops.create_uvsphere(bm, u_segments=16, v_segments=8, radius=1.0)
        for vert in made["verts"]:
            vert.co = Vector(c + r * v for c, r, v in zip(centre, radii, vert.co, strict=True))
    bm.to_mesh(mesh)
    bm.free()
    return mesh


def add_hand():
    """A rough hand: a flattened palm and four fingers, seen by the lamps only."""
    parts = [((0.0, 0.0, 0.0), (0.45, 0.55, 0.15))]
    parts += [((-0.27 + 0.18 * i, 0.75, 0.0), (0.08, 0.32, 0.07)) for i in range(4)]
    mesh = ellipsoids("Hand", parts)
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
