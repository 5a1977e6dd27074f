"""Held-out clips of folds: the kinds of motion of ``folds``, new paint and new motion.

The tracker was tuned on the fold clips of ``folds`` (``samples/folds``); these check that it
generalises and are never to be tuned on. ``HELDOUT_FOLDS`` lists them. ``render_hard_clips.py``
makes them only when asked by name, into a folder of their own (``samples/heldout_folds``),
apart from every other clip::

    .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds --only NAME ...

Each writes the files of a single-sheet hard clip (``NAME.mp4``, ``NAME.json``,
``NAME_truth.npz``) with the conventions of ``folds``: frame 0 flat and square to the camera,
at rest for three frames; every crease runs through the outlined region; the folds are
SimpleDeform bends over a narrow band at the crease (``fold_limits``), so a folded part never
passes through the rest.

``pouch_crush``
    A soft printed snack pouch (``heldout_textures.pouch_print``) is squeezed by two hands that
    come in from the top and the bottom of the image in front of it: it bows a little (its left
    and right edges towards the camera) and its top part folds back behind the rest along a
    horizontal crease a little above the middle (in 0.5 s, from 0.35 s; past about 90 deg it is
    out of sight behind the front part) while the hands push it down and turn it 4 deg, holds folded
    for 0.6 s with the top hand's fingers over the crease and the bottom hand's over the bottom
    edge, then unfolds (from 1.45 s, flat by 1.95 s) and the hands leave (by 2.6 and 3.1 s).
``plush_flip``
    A furry, low-contrast plush patch, grey with soft cream patches (``plush`` here, its hair
    combed another way than ``folds.fur``'s; a sheen material, grey felt behind), held by its
    left end: it turns away from the camera about a vertical axis near its right end
    (``PLUSH_PIVOT``) while drifting a little, and being soft it gives where it is held: the
    right part turns to 35 deg and the part left of ``PLUSH_CREASE`` (59 %) bends a further 65
    deg over a band, to 100 deg (past edge-on: its painted side turns away, ``visible`` false).
    It turns in 1.1 s, holds 0.3 s and turns back.
``cloth_corner_fold``
    A printed t-shirt cloth (``heldout_textures.tee_print``, heather jersey under a bold screen
    print; its back is the plain jersey): its bottom right corner (29 % of it, cut off by a
    diagonal crease across the direction ``CORNER_ANGLE``) folds 180 deg over the rest, towards
    the camera, and lies on it about 0.1 in front, its plain back covering about 20 % more of
    the print; it holds 0.5 s and unfolds flat while the cloth drifts a little.
"""

import math

import bpy  # noqa: F401 - first: mathutils comes with it

# isort: split
import cv2
import heldout_textures as paint  # scripts/ is on sys.path when a script runs
import numpy as np
from hard_textures import fractal_noise
from mathutils import Matrix

from hardclips.folds import (
    FOLD_FILES,
    HAND_REACH,
    add_pushing_hand,
    fold_and_unfold,
    fold_limits,
    hair_streaks,
    paced_fold,
    plush_on_pivot,
    set_back_colour,
)
from hardclips.materials import studio_lights
from hardclips.scene import Clip
from hardclips.sheet import (
    BEND_X_TOWARDS_CAMERA,
    BEND_Y_AWAY,
    add_sheet,
    bend,
    deform_origin,
    deg,
    finish_sheet,
    set_sheen,
)
from hardclips.video import srgb_to_linear

# bend() origin rotation: local X along world -X (towards the sheet's left end) and local +Y
# away from the camera (-Z), bending around world Y.
BEND_LEFT_AWAY = Matrix(((-1, 0, 0), (0, 0, -1), (0, -1, 0))).to_euler()
HAND_DEPTH = 0.32  # the hands' height above the sheet: in front of it, clear of its bow
GREY_FELT = (0.16, 0.155, 0.15, 1.0)  # plush_flip's back and rim (linear RGB)


def diagonal_towards_camera(angle):
    """A bend() origin rotation that folds across the in-plane direction ``angle`` (radians).

    Local X runs along (cos, sin) of ``angle`` in the sheet's plane and local +Y towards the
    camera (+Z): the bend is around the in-plane line at right angles to local X.
    """
    return _diagonal(angle, 1.0)


def diagonal_away(angle):
    """As :func:`diagonal_towards_camera`, but local +Y away from the camera (-Z).

    The part beyond the crease folds back, behind the rest.
    """
    return _diagonal(angle, -1.0)


def _diagonal(angle, side):
    c, s = math.cos(angle), math.sin(angle)
    return Matrix(((c, 0, side * s), (s, 0, -side * c), (0, side, 0))).to_euler()


POUCH_CREASE = 0.05  # pouch_crush: the crease's height above the sheet's centre


def build_pouch_crush(rng, clip):
    studio_lights()
    size = (2.2, 1.6)
    sheet = add_sheet(
        paint.pouch_print,
        size,
        (88, 64),
        4,
        rng=rng,
        roughness=0.45,
        specular=0.45,
        thickness=0.04,
    )
    # The squeeze bows the pouch a little (left and right edges towards the camera): the bow
    # does not change y, so the fold's limits stay put...
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_X_TOWARDS_CAMERA)
    bend(sheet, "Bow", origin)
    # ...and folds its top part back about a horizontal crease POUCH_CREASE above the centre,
    # over a band of 0.22 (folded, it lies about 0.14 behind the front part).
    origin = deform_origin(sheet, (0.0, POUCH_CREASE, 0.0), BEND_Y_AWAY)
    bend(sheet, "Fold", origin, limits=fold_limits(size[1], POUCH_CREASE, 0.22))
    # The fold (keyed on every frame): 90 deg 0.29 s after it starts at 0.35 s, folded flat
    # 0.5 s after it starts, its edge at a steady pace while in view; unfolds from 1.45 s, back
    # flat by 1.95 s. The hands push the pouch down a little and turn it a few degrees, so the
    # crease is only roughly horizontal.
    t = np.arange(clip.frames) / clip.fps
    fold = fold_and_unfold(t, 0.35, 1.45, paced_fold(4.8, 14.0, 90.0))
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bow"].angle', 0): deg(
                [(0.0, 0), (0.3, 0), (0.85, 25), (1.6, 25), (2.4, 0)]
            ),
            ('modifiers["Fold"].angle', 0): list(zip(t, fold, strict=True)),
            ("location", 1): [(0.0, 0), (0.3, 0), (0.95, -0.14), (1.55, -0.14), (2.6, -0.03)],
            ("location", 0): [(0.0, 0), (0.3, 0), (1.0, 0.1), (2.2, -0.08), (3.3, -0.04)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.3, 0), (1.0, -4), (2.3, 2), (3.3, 1)]),
        },
    )
    # The hands, in from outside the frame: the top one's fingers over the top edge and then,
    # following it as it folds back, over the crease; the bottom one's over the bottom edge.
    # They press while it folds, hold, and leave as it unfolds. Keyed where their fingertips are
    # (the palm's centre is HAND_REACH behind them, up for the top hand, down for the bottom).
    top = add_pushing_hand("TopHand", True)
    bottom = add_pushing_hand("BottomHand", True)
    top.rotation_euler = (0.0, 0.0, math.pi)  # fingers pointing down the image
    bottom.rotation_euler = (0.0, 0.0, 0.0)  # fingers pointing up
    top.location = bottom.location = (0.0, 0.0, HAND_DEPTH)
    edge = size[1] / 2
    crease = POUCH_CREASE - 0.14  # where the crease is once the pouch is pushed down
    top_tips = [
        (0.0, 3.7),
        (0.1, 3.7),
        (0.4, edge - 0.28),
        (0.62, 0.3),
        (0.85, crease - 0.25),
        (1.45, crease - 0.25),
        (1.75, 0.55),
        (2.6, 3.7),
    ]
    bottom_tips = [
        (0.0, -3.7),
        (0.15, -3.7),
        (0.5, -edge + 0.28),
        (0.95, -edge - 0.14 + 0.33),
        (1.5, -edge - 0.14 + 0.33),
        (2.15, -edge - 0.03 + 0.15),
        (3.1, -3.7),
    ]
    clip.keyframe(
        top,
        {
            ("location", 1): [(s, y + HAND_REACH) for s, y in top_tips],
            ("location", 0): [(0.0, 0.35), (0.4, 0.35), (0.9, 0.42), (1.8, 0.3)],
        },
    )
    clip.keyframe(
        bottom,
        {
            ("location", 1): [(s, y - HAND_REACH) for s, y in bottom_tips],
            ("location", 0): [(0.0, -0.5), (0.5, -0.5), (1.0, -0.4), (2.2, -0.55)],
        },
    )
    return finish_sheet(sheet)


def two_tone_plush(rng, width, height, fur, patch, patches, tufts, fine):
    """A low-contrast plush: ``fur`` colour with soft ``patch`` patches, and hair.

    The hair, in tufts and fine hair as in ``folds.fur``, is combed by the angle ranges given.

    Parameters
    ----------
    fur, patch : (3,) sRGB
    patches : (cells, gain, blur)
        The patches' fractal noise cells, its gain, and the blur of their edges (pixels).
    tufts : (length, angles, weight)
        Hair streaks drawn at a quarter size and scaled up, and their share of the shading.
    fine : (length, angles)
        Hair streaks at full size.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    tone = fractal_noise(rng, shape, cells=(3, 6, 12, 24), falloff=0.7)  # (H, W) in [-1, 1]
    cells, gain, blur = patches
    share = np.clip(0.5 + gain * fractal_noise(rng, shape, cells=cells), 0.0, 1.0)
    share = cv2.GaussianBlur(share.astype(np.float32), (0, 0), blur)  # soft-edged patches
    small = (height // 4, width // 4)
    length, angles, weight = tufts
    big = cv2.resize(
        hair_streaks(rng, small, length, angles=angles),
        (width, height),
        interpolation=cv2.INTER_CUBIC,
    )
    thin = hair_streaks(rng, shape, fine[0], angles=fine[1])
    light = 1.0 + 0.05 * tone + weight * big + 0.03 * thin  # (H, W) about 1
    colour = (1 - share[..., None]) * np.array(fur) + share[..., None] * np.array(patch)
    image = light[..., None] * colour + 0.01 * rng.standard_normal((*shape, 3))
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.8), 0, 1)


def plush(rng, width, height):
    """A grey and cream plush: grey fur, soft cream patches (see :func:`two_tone_plush`).

    Its hair is combed another way than ``folds.fur``'s.
    """
    return two_tone_plush(
        rng,
        width,
        height,
        fur=(0.60, 0.60, 0.61),
        patch=(0.77, 0.72, 0.62),
        patches=((2, 4, 8), 1.5, 12),
        tufts=(25, (115.0, 150.0), 0.05),
        fine=(11, (120.0, 145.0)),
    )


PLUSH_PIVOT = 0.85  # plush_flip: the turning axis, right of the sheet's centre
PLUSH_CREASE = 0.2  # where the bend of the held part starts, from the sheet's centre


def build_plush_flip(rng, clip):
    studio_lights()
    size = (2.2, 1.3)
    # The pivot: a vertical axis near the right end; the patch turns about it, its left end
    # (where it is held) going away from the camera, while the pivot drifts left and down.
    sheet, pivot = plush_on_pivot(
        rng, plush, size, (88, 52), PLUSH_PIVOT, (0.45, 0.4, (0.8, 0.8, 0.82, 1.0))
    )
    # The soft plush gives where it is held: the part left of PLUSH_CREASE bends further away
    # over a band of 0.35, so that the right part turns 35 deg and the left part 100 deg.
    origin = deform_origin(sheet, (PLUSH_CREASE, 0.0, 0.0), BEND_LEFT_AWAY)
    bend(sheet, "Held", origin, limits=fold_limits(size[0], -PLUSH_CREASE, 0.35))
    clip.keyframe(
        pivot,
        {
            ("rotation_euler", 1): deg([(0.0, 0), (0.1, 0), (1.2, -35), (1.5, -35), (2.6, 0)]),
            ("rotation_euler", 0): deg([(0.0, 0), (0.1, 0), (1.2, -5), (2.7, 0)]),
            ("location", 0): [
                (0.0, PLUSH_PIVOT),
                (0.1, PLUSH_PIVOT),
                (1.3, PLUSH_PIVOT - 0.2),
                (2.9, PLUSH_PIVOT - 0.05),
            ],
            ("location", 1): [(0.0, 0), (0.1, 0), (1.1, -0.1), (2.9, 0.04)],
        },
    )
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Held"].angle', 0): deg(
                [(0.0, 0), (0.15, 0), (1.2, 65), (1.5, 65), (2.6, 0)]
            )
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, GREY_FELT)
    return sheet


CORNER_ANGLE = -47.0  # cloth_corner_fold: the fold's direction (deg from +X; down and right)
CORNER_CREASE = 0.45  # the crease's distance from the sheet's centre along that direction


def build_cloth_corner_fold(rng, clip):
    studio_lights()
    size = (3.0, 2.0)
    sheet = add_sheet(
        paint.tee_print,
        size,
        (96, 64),
        4,
        rng=rng,
        roughness=0.9,
        specular=0.2,
        thickness=0.012,
    )
    set_sheen(sheet, 0.3, 0.5)  # cotton
    # The bottom right corner folds towards the camera about a diagonal crease over a band of
    # 0.16: folded, it lies about 0.1 in front of the rest, its plain back to the camera. Along
    # the fold's direction the sheet spans ``extent``, centred on the sheet's centre.
    angle = math.radians(CORNER_ANGLE)
    direction = np.array((math.cos(angle), math.sin(angle)))
    extent = size[0] * abs(direction[0]) + size[1] * abs(direction[1])
    origin = deform_origin(
        sheet, (*(CORNER_CREASE * direction), 0.0), diagonal_towards_camera(angle)
    )
    bend(sheet, "Corner", origin, limits=fold_limits(extent, CORNER_CREASE, 0.16))
    # Slower while the corner still shows its print (to 95 deg), faster after.
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Corner"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (0.85, 95), (1.25, 180), (1.75, 180), (2.2, 95), (2.95, 0)]
            ),
            ("location", 0): [(0.0, 0), (0.1, 0), (1.4, -0.12), (3.3, -0.04)],
            ("location", 1): [(0.0, 0), (0.1, 0), (1.5, 0.1), (3.3, 0.02)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.1, 0), (1.5, -3), (3.3, -1)]),
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(paint.JERSEY)), 1.0))
    return sheet


HELDOUT_FOLDS = [
    Clip(
        "pouch_crush",
        100,
        30,
        "two hands squeeze a printed snack pouch from the top and bottom: it bows and its top "
        "part folds back behind the rest along a roughly horizontal crease (in 0.5 s), holds "
        "0.6 s with the hands over the crease and the bottom edge, unfolds; the hands leave",
        build_pouch_crush,
    ),
    Clip(
        "plush_flip",
        90,
        30,
        "a furry, low-contrast grey and cream plush patch, held by its left end, turns away "
        "from the camera about a vertical axis near its right end in 1.1 s while it drifts: "
        "the right part turns 35 deg, the left 59 % bends on to 100 deg, past edge-on (painted "
        "side turned away); holds 0.3 s, turns back",
        build_plush_flip,
    ),
    Clip(
        "cloth_corner_fold",
        100,
        30,
        "the bottom right corner (29 %) of a printed t-shirt cloth folds 180 deg over the "
        "rest about a diagonal crease, towards the camera (its plain back covers about 20 % "
        "more of the print), holds 0.5 s and unfolds flat",
        build_cloth_corner_fold,
    ),
]


README_HELDOUT_FOLDS = (
    """# Held-out clips of folds

Clips for checking that the tracker generalises to folds: never tune it on these. The tracker
was tuned on the fold clips of [`../folds`](../folds/README.md); these show the same kinds of
motion (a sheet squeezed until it folds in half, a soft patch turned past edge-on, a part
folded over the rest) with other paint and other motion, and are to be measured once, as
held-out. Rendered with Blender {blender} (the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes and the plush paint
in `scripts/hardclips/heldout_folds.py`, other paint from `scripts/heldout_textures.py`) from a
fixed seed, so the same command makes the same scenes, truth and outlines; it makes them only
when named, apart from every other clip:

    .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds --only {names}

Keep them out of `samples/folds`. Check them with
`.venv/bin/python scripts/check_hard_clips.py --dir samples/heldout_folds` (statistics, and
contact sheets in `/tmp/hard_check/`).

"""
    + FOLD_FILES
)
