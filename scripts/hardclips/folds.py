"""Clips of folds: a sheet folds in half or over itself, or turns edge-on, and back.

``FOLDS`` lists them. ``render_hard_clips.py`` makes them only when asked by name, into a
folder of their own (``samples/folds``), apart from the other clips::

    .venv/bin/python scripts/render_hard_clips.py --out samples/folds --only NAME ...

Each writes the files of a single-sheet hard clip (``NAME.mp4``, ``NAME.json``,
``NAME_truth.npz``); the folds are SimpleDeform bends over a narrow band at the crease, so the
folded part lies a little in front of or behind the rest and never passes through it.

``fold_squeeze``
    A soft printed package label (``hard_textures.label``) is squeezed from both sides by two
    hands that come in from the left and right in front of it: the sheet bows a little and its
    right half folds back behind its left half along a vertical crease through the middle (in
    0.57 s, from 0.3 s; the last 90 deg of it hidden behind the front half), holds folded for
    0.73 s with the hands over the front half's left edge and the crease, then unfolds (by
    2.17 s) and the hands leave.
``tail_turn``
    A furry, low-contrast stuffed-toy patch (``fur`` here: soft brown noise, faint darker patches,
    fine hair streaks; a sheen material), lifted and turned by its right end (the tail): it
    turns about a vertical axis through its left end (the body's end, which stays put) so that
    the right end rises towards the camera, and being soft it gives where it is held: the body
    (the left 40 %) turns to 40 deg, the tail (the right 60 %) bends a further 55 deg over a
    band, to 95 deg (just past edge-on: its painted side turns away, ``visible`` false). It
    turns in 1.1 s, holds 0.3 s and turns back.
``sheet_foldover``
    A printed bag sheet (``hard_textures.bag_print``): its top 35 % folds 180 deg towards the
    camera about a horizontal crease (``FOLDOVER_CREASE`` above the middle) and lies over the
    rest about 0.13 in front of it, showing its unpainted back and covering the print below the
    crease about as far down again; it holds 0.5 s and unfolds flat while the sheet drifts a
    little.
"""

import math

import bpy

# isort: split
import cv2
import hard_textures as paint  # scripts/ is on sys.path when a script runs
import numpy as np
from hard_textures import fractal_noise
from mathutils import Matrix

from hardclips.heldout import add_arm
from hardclips.materials import plain_material, studio_lights
from hardclips.scenarios import ellipsoids
from hardclips.scene import Clip
from hardclips.sheet import (
    BEND_X_TOWARDS_CAMERA,
    add_sheet,
    bend,
    deform_origin,
    deg,
    finish_sheet,
    set_sheen,
)

# Origin rotations for bend(), besides those of ``sheet``: local X along world +X and local +Y
# away from the camera (-Z), bending around world Y...
BEND_X_AWAY = (-math.pi / 2, 0.0, 0.0)
# ...and local X along world +Y (up in the image), local +Y towards the camera, around world X.
BEND_Y_TOWARDS_CAMERA = Matrix(((0, 0, 1), (1, 0, 0), (0, 1, 0))).to_euler()

SKIN_COLOUR = (0.62, 0.42, 0.32, 1.0)
FELT_COLOUR = (0.30, 0.21, 0.14, 1.0)  # tail_turn's back and rim
HAND_SCALE = 0.8
HAND_REACH = 1.14 * HAND_SCALE  # from the palm's centre to the fingertips
TURNED_AWAY = math.radians(100)  # paced_fold: past this the folding part is out of sight
HAND_DEPTH = 0.3  # the hands' height above the sheet: in front of it, clear of its bow


def fold_limits(size, crease, band):
    """``bend`` limits (fractions of the sheet's extent) for a fold band from ``crease`` on.

    ``size`` is the sheet's extent along the bend's local X, ``crease`` where the band starts
    and ``band`` its length, both along that axis from the sheet's centre. The band's radius is
    ``band / angle``: a 180-deg fold lies ``2 * band / pi`` from the rest of the sheet.
    """
    start = (crease + size / 2) / size
    return (start, start + band / size)


def paced_fold(visible_speed, hidden_speed, accel, turned_away=TURNED_AWAY):
    """A 180-deg fold paced so that the folding edge moves at a steady speed on screen.

    While the folding part still faces the camera (up to ``turned_away``) the angular speed is
    ``visible_speed / sin(angle)`` rad/s: its free edge crosses the image at a steady pace
    instead of rushing through the middle of the turn; after that (the part folded away, out
    of sight) it is ``hidden_speed``. It speeds up from rest and slows to rest at ``accel``
    rad/s^2.

    Returns
    -------
    seconds, angles : (n,) float64
        The time from the fold's start at which it reaches each angle (radians, 0 to pi).
    """
    angles = np.linspace(0.0, math.pi, 2001)
    middle = (angles[1:] + angles[:-1]) / 2
    cap = np.where(
        middle < turned_away, visible_speed / np.maximum(np.sin(middle), 0.2), hidden_speed
    )
    speed = np.minimum.reduce(
        [cap, np.sqrt(2 * accel * middle), np.sqrt(2 * accel * (math.pi - middle))]
    )
    seconds = np.concatenate([[0.0], np.cumsum(np.diff(angles) / speed)])
    return seconds, angles


def fold_and_unfold(t, fold_at, unfold_at, pace):
    """The angle (radians) at times ``t`` of a fold and its unfolding.

    ``pace`` (from ``paced_fold``) runs from ``fold_at`` and backwards from ``unfold_at``: flat
    before, folded (pi) between, flat again once unfolded.
    """
    seconds, angles = pace
    folding = np.interp(t - fold_at, seconds, angles)
    unfolding = np.interp(seconds[-1] - (t - unfold_at), seconds, angles)
    return np.where(t < unfold_at, folding, unfolding)


def hair_streaks(rng, shape, length, angles=(60.0, 35.0)):
    """White noise smeared ``length`` texels along two directions that alternate smoothly.

    Returns
    -------
    (shape[0], shape[1]) float32, zero mean and unit variance.
    """
    grain = rng.standard_normal(shape).astype(np.float32)
    kernel = np.zeros((length, length), np.float32)
    kernel[length // 2, :] = 1.0 / length
    centre = ((length - 1) / 2, (length - 1) / 2)
    smeared = [
        cv2.filter2D(
            grain,
            -1,
            cv2.warpAffine(kernel, cv2.getRotationMatrix2D(centre, a, 1.0), (length, length)),
        )
        for a in angles
    ]
    mix = (0.5 + 0.5 * fractal_noise(rng, shape, cells=(3, 6))).astype(np.float32)
    hair = mix * smeared[0] + (1 - mix) * smeared[1]
    return (hair - hair.mean()) / hair.std()


def fur(rng, width, height):
    """Stuffed-toy fur, low contrast on purpose: soft brown noise, faint patches, hair streaks.

    The hair comes in two sizes: tufts a few pixels wide and about 15 long where the clips show
    it (drawn at a quarter of the resolution and enlarged), and fine hair over them.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    tone = fractal_noise(rng, shape, cells=(3, 6, 12, 24), falloff=0.7)  # (H, W) in [-1, 1]
    patches = np.clip(1.6 * fractal_noise(rng, shape, cells=(4, 8)) - 0.35, 0.0, 1.0)
    small = (height // 4, width // 4)
    tufts = cv2.resize(hair_streaks(rng, small, 21), (width, height), interpolation=cv2.INTER_CUBIC)
    fine = hair_streaks(rng, shape, 15)
    light = 1.0 + 0.05 * tone - 0.1 * patches + 0.05 * tufts + 0.025 * fine  # (H, W) about 1
    brown = np.array((0.50, 0.36, 0.23), np.float32)
    image = light[..., None] * brown + 0.01 * rng.standard_normal((*shape, 3))
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.8), 0, 1)


def add_pushing_hand(name, pointing_right):
    """A skin-coloured hand and forearm seen by the camera, fingers pointing inwards.

    Rounded pieces (ellipsoids): a flat palm, four fingers side by side and a thumb, in the
    layout of ``add_hand`` (fingers along local +Y, so ``add_arm`` fits), then turned so that
    the fingers point right (the left hand) or left (the right hand).
    """
    parts = [((0.0, 0.0, 0.0), (0.42, 0.5, 0.14))]
    parts += [((-0.24 + 0.16 * i, 0.78, 0.0), (0.085, 0.36, 0.075)) for i in range(4)]
    side = 1.0 if pointing_right else -1.0  # the thumb towards the top of the image
    parts.append(((side * 0.44, 0.22, 0.02), (0.09, 0.3, 0.08)))
    mesh = ellipsoids(name, parts)
    mesh.materials.append(plain_material("Skin", SKIN_COLOUR))
    hand = bpy.data.objects.new(name, mesh)
    hand.scale = (HAND_SCALE,) * 3
    hand.rotation_euler = (0.0, 0.0, -math.pi / 2 if pointing_right else math.pi / 2)
    bpy.context.scene.collection.objects.link(hand)
    mesh.shade_smooth()
    add_arm(hand, radius=0.3)
    return hand


def build_fold_squeeze(rng, clip):
    studio_lights()
    size = (2.4, 1.6)
    sheet = add_sheet(paint.label, size, (96, 64), 4, rng=rng, roughness=0.6)
    # The squeeze bows the sheet a little (top and bottom edges towards the camera)...
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_Y_TOWARDS_CAMERA)
    bend(sheet, "Bow", origin)
    # ...and folds its right half back about the vertical centre line, over a band of 0.25
    # (folded, it lies about 0.16 behind the front half). The bow does not change x, so the
    # fold's limits stay put.
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_X_AWAY)
    bend(sheet, "Fold", origin, limits=fold_limits(size[0], 0.0, 0.25))
    # The fold (keyed on every frame): 90 deg 0.33 s after it starts at 0.3 s, folded flat
    # 0.57 s after it starts, its edge at a steady pace while in view; unfolds from 1.6 s, back
    # flat by 2.17 s. The sheet is pushed right meanwhile, which slows the folding edge down on
    # screen.
    t = np.arange(clip.frames) / clip.fps
    fold = fold_and_unfold(t, 0.3, 1.6, paced_fold(4.2, 12.0, 70.0))
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bow"].angle', 0): deg(
                [(0.0, 0), (0.3, 0), (0.9, 30), (1.7, 30), (2.5, 0)]
            ),
            ('modifiers["Fold"].angle', 0): list(zip(t, fold, strict=True)),
            ("location", 0): [(0.0, 0), (0.3, 0), (1.1, 0.3), (1.6, 0.3), (2.5, 0.05)],
            ("location", 1): [(0.0, 0), (0.3, 0), (1.1, 0.04), (2.4, -0.04), (3.3, 0.0)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.3, 0), (1.1, 3), (2.4, -2), (3.3, -1)]),
        },
    )
    # The hands, in from outside the frame: the left one's fingers over the left edge, the
    # right one's over the right edge and then, following it as it folds, over the crease; they
    # press in while it folds (the sheet moves right by 0.3), hold, and leave as it unfolds.
    # Keyed where their fingertips are (the palm's centre is HAND_REACH behind them).
    left = add_pushing_hand("LeftHand", True)
    right = add_pushing_hand("RightHand", False)
    left.location = right.location = (0.0, 0.0, HAND_DEPTH)
    edge = size[0] / 2
    left_tips = [
        (0.0, -4.1),
        (0.1, -4.1),
        (0.5, -edge + 0.35),
        (1.0, -edge + 0.3 + 0.45),
        (1.6, -edge + 0.3 + 0.45),
        (2.3, -edge + 0.05 + 0.3),
        (3.2, -4.1),
    ]
    right_tips = [
        (0.0, 4.1),
        (0.1, 4.1),
        (0.45, edge - 0.3),
        (0.75, 0.1),
        (1.0, 0.3 - 0.35),
        (1.6, 0.3 - 0.35),
        (1.9, 0.7),
        (2.7, 4.1),
    ]
    clip.keyframe(
        left,
        {
            ("location", 0): [(t, x - HAND_REACH) for t, x in left_tips],
            ("location", 1): [(0.0, 0.12), (0.5, 0.12), (1.0, 0.2), (2.3, 0.05)],
        },
    )
    clip.keyframe(
        right,
        {
            ("location", 0): [(t, x + HAND_REACH) for t, x in right_tips],
            ("location", 1): [(0.0, -0.18), (0.45, -0.18), (1.0, -0.25), (1.9, -0.1)],
        },
    )
    return finish_sheet(sheet)


def plush_on_pivot(rng, paint, size, grid, pivot_x, sheen):
    """A furry sheet hung on an empty (``Pivot``) at x = ``pivot_x``, to be turned about it.

    ``sheen`` is (weight, roughness, RGBA tint): velvety at grazing angles. Returns (the
    sheet, the pivot).
    """
    sheet = add_sheet(paint, size, grid, 4, rng=rng, roughness=0.95, specular=0.15, thickness=0.06)
    set_sheen(sheet, *sheen)
    pivot = bpy.data.objects.new("Pivot", None)
    pivot.location = (pivot_x, 0.0, 0.0)
    bpy.context.scene.collection.objects.link(pivot)
    sheet.obj.parent = pivot
    sheet.obj.location = (-pivot_x, 0.0, 0.0)
    return sheet, pivot


def set_back_colour(sheet, colour):
    """Give the finished ``sheet``'s unpainted back and rim ``colour`` (linear RGBA)."""
    material = sheet.obj.data.materials[0]
    mix = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeMix")
    {i.identifier: i for i in mix.inputs}["B_Color"].default_value = colour
    rim = sheet.obj.data.materials[1].node_tree.nodes["Principled BSDF"]
    rim.inputs["Base Color"].default_value = colour


TAIL_CREASE = -0.2  # tail_turn: where the tail's bend starts, from the sheet's centre


def build_tail_turn(rng, clip):
    studio_lights()
    size = (2.1, 1.4)
    # The pivot: the body's end (the sheet's left edge), which stays on the table; the whole
    # toy turns about a vertical axis through it, its right end (the tail) rising towards the
    # camera.
    sheet, pivot = plush_on_pivot(
        rng, fur, size, (84, 56), -size[0] / 2, (0.4, 0.5, (0.85, 0.7, 0.55, 1.0))
    )
    # The soft toy gives where it is held: the tail (the right part, from TAIL_CREASE on) bends
    # further towards the camera over a band of 0.4, so that the body turns 40 deg and the tail
    # 95 deg, past edge-on (its painted side turned away).
    origin = deform_origin(sheet, (TAIL_CREASE, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(sheet, "Tail", origin, limits=fold_limits(size[0], TAIL_CREASE, 0.4))
    clip.keyframe(
        pivot,
        {
            ("rotation_euler", 1): deg([(0.0, 0), (0.1, 0), (1.2, -40), (1.5, -40), (2.6, 0)]),
            ("rotation_euler", 0): deg([(0.0, 0), (0.1, 0), (1.3, 6), (2.6, 0)]),
            ("location", 1): [(0.0, 0), (0.1, 0), (1.4, 0.08), (2.8, 0.0)],
        },
    )
    clip.keyframe(
        sheet.obj,
        {('modifiers["Tail"].angle', 0): deg([(0.0, 0), (0.1, 0), (1.2, 55), (1.5, 55), (2.6, 0)])},
    )
    # Its back and rim: plain felt, a darker brown than the fur (not the foam's cream).
    finish_sheet(sheet)
    set_back_colour(sheet, FELT_COLOUR)
    return sheet


FOLDOVER_CREASE = 0.3  # sheet_foldover: the crease's height above the centre


def build_sheet_foldover(rng, clip):
    studio_lights()
    size = (3.0, 2.0)
    sheet = add_sheet(paint.bag_print, size, (96, 64), 4, rng=rng, roughness=0.6)
    # The top part folds towards the camera about a horizontal crease FOLDOVER_CREASE above
    # the centre line, over a band of 0.2: folded, it lies about 0.13 in front of the rest,
    # its back to the camera.
    origin = deform_origin(sheet, (0.0, FOLDOVER_CREASE, 0.0), BEND_Y_TOWARDS_CAMERA)
    bend(sheet, "Fold", origin, limits=fold_limits(size[1], FOLDOVER_CREASE, 0.2))
    # Slower while the top half still faces the camera (to 95 deg), faster after.
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (0.9, 95), (1.35, 180), (1.85, 180), (2.3, 95), (3.1, 0)]
            ),
            ("location", 0): [(0.0, 0), (0.1, 0), (1.6, 0.15), (3.3, 0.05)],
            ("location", 1): [(0.0, 0), (0.1, 0), (1.6, -0.12), (3.3, -0.03)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.1, 0), (1.6, 4), (3.3, 1)]),
        },
    )
    return finish_sheet(sheet)


FOLDS = [
    Clip(
        "fold_squeeze",
        100,
        30,
        "two hands squeeze a printed package label from the left and right: it bows and its "
        "right half folds back behind the left half along a vertical crease (in 0.57 s), "
        "holds 0.73 s with the hands over both sides of the front half, unfolds; the hands "
        "leave",
        build_fold_squeeze,
    ),
    Clip(
        "tail_turn",
        90,
        30,
        "a furry, low-contrast stuffed-toy patch is turned in depth by its tail end about a "
        "vertical axis through its other end in 1.1 s: the body turns 40 deg, the tail (the "
        "right 60 %) bends on to 95 deg, past edge-on (painted side turned away); holds 0.3 s, "
        "turns back",
        build_tail_turn,
    ),
    Clip(
        "sheet_foldover",
        100,
        30,
        "the top 35 % of a printed sheet folds 180 deg towards the camera over the rest (its "
        "unpainted back covers about as much again of the print), holds 0.5 s and unfolds flat",
        build_sheet_foldover,
    ),
]


#: What a fold clip folder holds (the end of its README; shared with the held-out folds).
FOLD_FILES = """\
Each clip NAME has `NAME.mp4` (H.264, {width}x{height}, gaussian sensor noise of {noise:.1f} %
added before encoding), `NAME.json` (the region outline on frame 0) and `NAME_truth.npz`
(`lattice`, `visible`, `fps`), in the formats of the hard clips (see
[`../hard/README.md`](../hard/README.md)): OpenCV pixel coordinates, `lattice` (T, R, C, 2)
float32 projected from the renderer's deformed mesh, `visible` (T, R, C) bool, false where the
point is outside the image, turned away from the camera (folded back, turned past edge-on, or
folded over so that its painted side faces the sheet) or hidden by anything (the front half,
the folded-over flap, a hand). Frame 0 shows the sheet flat, square to the perspective camera
and at rest for three frames, so the frame-0 lattice is an axis-aligned grid; every fold's
crease runs through the outlined region.

| clip | frames | fps | what happens | renderer |
| --- | ---: | ---: | --- | --- |
{rows}

How much of each sheet's lattice is visible (from `NAME_truth.npz`):

| clip | least visible | frames under 1/3 | frames under 2/3 |
| --- | ---: | --- | --- |
{visibility}
"""


README_FOLDS = (
    """# Clips of folds

Test clips of a sheet that folds in half or over itself, or turns edge-on, and back, so that
much of it is hidden for a while. Rendered with Blender {blender} (the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes and the fur paint
in `scripts/hardclips/folds.py`, other paint from `scripts/hard_textures.py`) from a fixed seed,
so the same command makes the same scenes, truth and outlines; it makes them only when named:

    .venv/bin/python scripts/render_hard_clips.py --out samples/folds --only {names}

Check them with `.venv/bin/python scripts/check_hard_clips.py --dir samples/folds` (statistics,
and contact sheets in `/tmp/hard_check/`).

"""
    + FOLD_FILES
)


def frame_spans(frames):
    """``[3, 4, 5, 9]`` -> ``"3-5, 9"`` (frame indices from 0); ``"none"`` when empty."""
    spans = []
    for frame in frames:
        if spans and frame == spans[-1][1] + 1:
            spans[-1][1] = frame
        else:
            spans.append([frame, frame])
    return ", ".join(f"{a}" if a == b else f"{a}-{b}" for a, b in spans) or "none"


def visibility_rows(out, clips):
    """A README row per clip whose truth is in ``out``: its visible fractions."""
    rows = []
    for clip in clips:
        path = out / f"{clip.name}_truth.npz"
        if not path.exists():
            continue
        fraction = np.load(path)["visible"].mean(axis=(1, 2))  # (T,)
        rows.append(
            f"| `{clip.name}` | {fraction.min():.2f} (frame {fraction.argmin()}) "
            f"| {frame_spans(np.flatnonzero(fraction < 1 / 3))} "
            f"| {frame_spans(np.flatnonzero(fraction < 2 / 3))} |"
        )
    return "\n".join(rows)
