"""Held-out hard clips: made to check that the tracker generalises, never to tune it on.

``HELDOUT`` lists them. ``render_hard_clips.py`` makes them only when asked by name
(``--only handheld_zoom ...``), never by default, into ``samples/heldout``, apart from the
tuned clips of ``samples/hard``::

    .venv/bin/python scripts/render_hard_clips.py --out samples/heldout --only NAME ...

Each differs from the tuned clips in its paint (``heldout_textures``) and its motion:

``handheld_zoom``
    The camera is handheld (smooth jitter of a few px per frame, roll of +-6 deg) and dollies
    in and out, so the sheet's image scale runs from about 1.4x to 0.7x, while a tartan sheet
    bends moderately.
``occluded_exit``
    A street map drifts so that about a third of it leaves the frame on the right and comes
    back; then a hand and forearm pass in front of it, covering 30-50 % of it for about 20
    frames.
``glossy_fast_twist``
    12 fps with motion blur: semi-glossy marbled paper twists up to 50 deg and bends while it
    moves 10-25 px per frame under a small lamp; the exposure steps up x1.4 halfway.
"""

import bpy

# isort: split
import heldout_textures as paint  # scripts/ is on sys.path when a script runs
import numpy as np
from scipy.ndimage import gaussian_filter1d

from hardclips.materials import add_light, studio_lights
from hardclips.scenarios import add_hand, ellipsoids
from hardclips.scene import LENS_MM, SENSOR_MM, WIDTH, Clip
from hardclips.sheet import BEND_X_TOWARDS_CAMERA, add_sheet, bend, deform_origin, deg, finish_sheet

FOCAL_PX = LENS_MM / SENSOR_MM * WIDTH  # image px per radian near the centre


def ramp(t, start, end):
    """0 before ``start``, 1 after ``end``, smoothstep between."""
    s = np.clip((t - start) / (end - start), 0.0, 1.0)
    return s * s * (3 - 2 * s)


def shake(rng, n, step_px, sigma=2.0):
    """Smooth random jitter: low-passed noise whose steps are ``step_px`` RMS per frame.

    In px for the image shifts; the roll's shake uses it in radians.
    """
    path = gaussian_filter1d(rng.standard_normal(n), sigma)
    return path * step_px / np.sqrt(np.mean(np.diff(path) ** 2))


def build_handheld_zoom(rng, clip):
    studio_lights()
    sheet = add_sheet(paint.woven, (2.8, 1.9), (84, 57), 3, rng=rng)
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(sheet, "Bend", origin)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bend"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (0.9, 35), (2.0, -30), (3.1, 25), (4.0, 0)]
            ),
            ("rotation_euler", 0): deg([(0.0, 0), (0.1, 0), (1.3, 15), (2.6, -12), (4.0, 0)]),
            ("rotation_euler", 1): deg([(0.0, 0), (0.1, 0), (0.8, -12), (2.3, 15), (3.6, -5)]),
            ("location", 0): [(0.0, 0), (0.1, 0), (2.0, 0.15), (4.0, -0.1)],
        },
    )
    # The camera: at rest on frames 0-2 (square above the sheet), then handheld. The dolly sets
    # the sheet's scale (6 / height): 1.4x at 1.3 s, 0.7x at 2.8 s, back to 1x.
    camera = bpy.context.scene.camera
    height = camera.location.z
    t = np.arange(clip.frames) / clip.fps
    held = ramp(t, 0.1, 0.6)
    jitter_x = shake(rng, clip.frames, 2.5) + 12 * np.sin(2 * np.pi * t / 3.1 + 0.7)
    jitter_y = shake(rng, clip.frames, 2.5) + 10 * np.sin(2 * np.pi * t / 2.3 + 2.0)
    # Roll: a slow +-6 deg sway and a shake of about 0.23 deg (0.004 rad) a frame.
    roll = 6.0 * np.sin(2 * np.pi * (t - 0.1) / 3.2) + np.degrees(shake(rng, clip.frames, 0.004))
    curves = {
        ("rotation_euler", 0): held * (jitter_y - jitter_y[0]) / FOCAL_PX,
        ("rotation_euler", 1): held * (jitter_x - jitter_x[0]) / FOCAL_PX,
        ("rotation_euler", 2): np.radians(held * np.clip(roll, -6.0, 6.0)),
        ("location", 0): held * 0.12 * np.sin(2 * np.pi * t / 2.7),
        ("location", 1): held * 0.1 * np.sin(2 * np.pi * t / 3.7 + 1.0),
    }
    keys = {key: list(zip(t, values, strict=True)) for key, values in curves.items()}
    scales = [(0.0, 1.0), (0.1, 1.0), (1.3, 1.4), (2.8, 0.7), (4.0, 1.0)]
    keys[("location", 2)] = [(s, height / scale) for s, scale in scales]
    clip.keyframe(camera, keys)
    return finish_sheet(sheet)


def add_arm(hand, length=3.0, radius=0.32):
    """A forearm for ``add_hand``'s hand, reaching down (-Y) from the wrist, as its child."""
    centre, radii = (0.0, -0.4 - length / 2, -0.05), (radius, length / 2, 0.6 * radius)
    mesh = ellipsoids("Arm", [(centre, radii)])
    mesh.materials.append(hand.data.materials[0])
    arm = bpy.data.objects.new("Arm", mesh)
    arm.parent = hand
    bpy.context.scene.collection.objects.link(arm)
    return arm


def build_occluded_exit(rng, clip):
    studio_lights()
    sheet = add_sheet(paint.street_map, (3.0, 2.0), (96, 64), 4, rng=rng, roughness=0.7)
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(sheet, "Bend", origin)
    # About a third leaves on the right by 1.2 s, comes back by 2.4 s; the hand covers it
    # from about 2.45 s to 3.15 s.
    clip.keyframe(
        sheet.obj,
        {
            ("location", 0): [(0.0, 0), (0.1, 0), (1.2, 2.6), (1.6, 2.6), (2.4, 0.2), (4.0, -0.1)],
            ("location", 1): [(0.0, 0), (0.1, 0), (1.0, 0.12), (2.2, -0.1), (4.0, 0.05)],
            ('modifiers["Bend"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (0.9, 30), (1.8, -25), (2.8, 20), (3.6, -15), (4.0, -10)]
            ),
            ("rotation_euler", 1): deg([(0.0, 0), (0.1, 0), (1.2, 15), (2.5, -10), (4.0, 5)]),
            ("rotation_euler", 2): deg([(0.0, 0), (0.1, 0), (1.4, -8), (3.0, 6), (4.0, 2)]),
        },
    )
    # The hand, 1.5 above the sheet (so a third larger in the image), comes up from below the
    # frame, lies over the sheet's lower left and centre, and leaves downwards to the right.
    hand = add_hand()
    hand.visible_camera = True  # here it is in front of the sheet, not just casting a shadow
    hand.scale = (1.15, 1.15, 1.15)
    add_arm(hand)
    z = 1.5
    passes = [
        (0.0, (-0.9, -3.6, -20)),
        (2.1, (-0.9, -3.6, -20)),
        (2.45, (-0.55, -0.55, -12)),
        (2.8, (-0.3, -0.45, -8)),
        (3.15, (0.0, -0.6, -4)),
        (3.6, (0.4, -3.6, 5)),
        (4.0, (0.4, -3.6, 5)),
    ]
    clip.keyframe(
        hand,
        {
            ("location", 0): [(s, x) for s, (x, _, _) in passes],
            ("location", 1): [(s, y) for s, (_, y, _) in passes],
            ("location", 2): [(0.0, z)],
            ("rotation_euler", 2): deg([(s, a) for s, (_, _, a) in passes]),
        },
    )
    return finish_sheet(sheet)


def build_glossy_fast_twist(rng, clip):
    # A small strong lamp beside the camera and a weaker one on the other side: their
    # highlights run over the sheet as it turns; a dim fill.
    add_light("Lamp", "POINT", (2.6, 2.0, 5.0), 1000.0, 0.06)
    add_light("Lamp2", "POINT", (-3.0, -1.5, 4.5), 350.0, 0.1)
    add_light("Fill", "AREA", (-4.0, 3.0, 5.0), 60.0, 3.0)
    sheet = add_sheet(
        paint.marbled, (2.2, 1.5), (66, 45), 3, rng=rng, roughness=0.3, specular=0.6, coat=0.2
    )
    twist = sheet.obj.modifiers.new("Twist", "SIMPLE_DEFORM")
    twist.deform_method, twist.deform_axis, twist.angle = "TWIST", "X", 0.0
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(sheet, "Bend", origin)
    t = np.arange(clip.frames) / clip.fps  # a key on every frame
    speed = ramp(t, 0.2, 0.9)  # at rest on frames 0-2, then up to full speed
    tau = np.concatenate([[0.0], np.cumsum((speed[1:] + speed[:-1]) / 2 * np.diff(t))])
    w = 2.0  # rad/s along an ellipse: 1.0-2.5 units/s, about 9-22 px per frame at 12 fps
    curves = {
        ("location", 0): 1.25 * np.sin(w * tau),
        ("location", 1): 0.4 * (1 - np.cos(w * tau)) - 0.2 * np.sin(0.5 * w * tau),
        ('modifiers["Twist"].angle', 0): np.radians(50.0) * np.sin(1.7 * tau),
        ('modifiers["Bend"].angle', 0): np.radians(35.0) * np.sin(2.5 * tau + 0.3) * speed,
        ("rotation_euler", 2): np.radians(20.0) * np.sin(1.3 * tau),
        ("rotation_euler", 0): np.radians(12.0) * np.sin(2.2 * tau),
    }
    clip.keyframe(
        sheet.obj,
        {key: list(zip(t, values, strict=True)) for key, values in curves.items()},
    )
    return finish_sheet(sheet)


EXPOSURE_STEP = (2.0, 1.4)  # glossy_fast_twist: (seconds, factor) from then on


def exposure_step(index, seconds, linear):
    """Auto-exposure jumping up halfway through the clip, in linear light."""
    start, factor = EXPOSURE_STEP
    return linear * (factor if seconds >= start else 1.0)


HELDOUT = [
    Clip(
        "handheld_zoom",
        96,
        24,
        "handheld camera (jitter of a few px per frame, roll +-6 deg) dollies in and out: the "
        "tartan sheet's scale runs 1.4x to 0.7x while it bends and tilts (up to about 40 deg)",
        build_handheld_zoom,
    ),
    Clip(
        "occluded_exit",
        120,
        30,
        "a street map bends while a third of it leaves the frame on the right and comes back; "
        "then a hand passes in front, covering 30-50 % of it for about 20 frames",
        build_occluded_exit,
    ),
    Clip(
        "glossy_fast_twist",
        48,
        12,
        "12 fps: semi-glossy (roughness 0.3) marbled paper twists up to 50 deg and bends while "
        "it moves 10-25 px per frame; highlights move; exposure steps x1.4 at 2 s",
        build_glossy_fast_twist,
        samples=12,
        motion_blur=True,
        post=exposure_step,
        post_note="an exposure step",
    ),
]
