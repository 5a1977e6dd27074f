r"""An eighth batch of held-out clips of folds: new paint, axes, speeds and places, never tuned on.

The tracker was tuned on the fold clips of ``folds`` (``samples/folds``); the held-out batches
(``heldout_folds`` to ``heldout_folds7`` and this one, in ``samples/heldout_folds`` to
``samples/heldout_folds8``) check that it generalises and are never to be tuned on. This batch
was made after the seventh, for issue 22's generalisation check. ``HELDOUT_FOLDS8`` lists it.
``render_hard_clips.py`` makes these clips only when asked by name, into a folder of their own
(``samples/heldout_folds8``), apart from every other clip::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \
        --out samples/heldout_folds8 --only NAME ...

Each writes the files of a single-sheet hard clip (``NAME.mp4``, ``NAME.json``,
``NAME_truth.npz``) with the conventions of ``folds``: frame 0 flat and square to the camera,
at rest for three frames; every crease runs through the outlined region; the folds are
SimpleDeform bends over a band at the crease (``fold_limits``), so a folded part never passes
through the rest. The paint is here (``calico_plush``, ``spotted_plush``,
``watercolour_print``); the scenes reuse the helpers of ``heldout_folds3`` (hands posed on
every frame, eased keys, ``crease_bend``). Unlike the earlier batches, two of the sheets are
soft and furry but not faint overall: the calico plush is dyed in large patches of cream,
ginger and near black, and the spotted plush is white with large black spots, so that their
colours vary more than most prints' while their fine texture (the pile) is as faint as any
plush's; the printed card is a watercolour of soft washes, a print whose fine detail is weak.
The calico plush is held by its lower left corner and turned away from the camera about an
axis falling 65 deg to the right, at a moderate pace; the spotted plush's lower left part
folds back about a crease rising 62 deg to the left, under hands in from the lower left and
from above; the card's left side folds over about a crease leaning 16 deg from the vertical
while the card slides up and left.

``calico_tail_turn``
    A stuffed-toy patch of calico faux fur (``calico_plush``: a short soft pile, its fine
    texture only a few per cent of contrast, dyed in large soft-edged patches of cream, ginger
    orange and brown-black, so that its colours vary a lot overall; a sheen material, dark
    brown felt behind), lying left of and above the middle (``CALICO_AT``), is held by a hand
    at its lower left corner (its tail) and turned away from the camera about an axis falling
    65 deg to the right (``CALICO_FALL``) through its upper right part (``CALICO_PIVOT``): the
    patch turns 30 deg about it and its part beyond a crease parallel to the axis through the
    middle (``CALICO_CREASE``; half the patch) bends a further 80 deg over a band of 0.35, so
    that the tail turns to 110 deg (past edge-on: its painted side turns away, behind the
    rest). It turns at a moderate pace (0.8 s, from 0.3 s), holds 0.45 s and turns back (0.85
    s) while it drifts about 16 px right and 10 px up and part of the way back. The hand comes
    in along the axis from below, holds the corner (moved with it frame by frame; its forearm
    stays along the axis, below the patch's bottom edge) and leaves the same way.
``spotted_plush_squeeze``
    A plush patch of white short fur with large irregular black spots (``spotted_plush``:
    dalmatian- and cow-like spots with soft edges, a few satellite specks, a faint short pile;
    a sheen material, near-black felt behind), lying right of and below the middle
    (``SPOT_AT``), is squeezed by two hands in front of it, one from the lower left and one
    from above (``SPOT_UPPER``). It bows a little along the crease and its lower left part
    (about 49 %) folds back behind the rest about a crease through the middle rising 62 deg to
    the left (``SPOT_ANGLE``, ``SPOT_CREASE``: from the bottom edge right of the centre to the
    top edge left of it), over a band of 0.24, in about 0.5 s from 0.4 s (``SPOT_FOLD``; out
    of sight past about 100 deg), while the lower left hand pushes the patch about 13 px right
    and 9 px up and turns it 4 deg clockwise. The lower left hand's fingers follow the folding
    part's edge onto the crease; the upper hand's lie over the upper part. It holds folded
    0.55 s, opens again at a gentle pace (about 0.67 s, from 1.45 s) and the hands leave the
    way they came.
``watercolour_card_fold``
    A printed card with a watercolour landscape (``watercolour_print``: a graded sky wash of
    ultramarine over a rose and peach glow, soft lifted clouds, violet far hills and green
    near hills wet into wet, an ochre field, a lake with soft reflections, blotted trees,
    pigment granulation and a faint cold-press paper grain; hardly any hard edge; its back
    plain white card), lying below the middle (``CARD_AT``): its left side (about 30 %, beyond
    ``CARD_CREASE`` along ``CARD_ANGLE``: a crease leaning 16 deg from the vertical, its top to
    the left) folds over onto the rest by 180 deg, towards the camera, over a band of 0.26
    (its plain back covering about 17 % more of the painting), in 0.75 s from 0.3 s; it holds
    0.45 s and unfolds in 0.9 s while the card slides about 23 px left and 10 px up and turns
    3 deg clockwise.
"""

import math

import bpy  # noqa: F401 - first, before the modules that load with it

# isort: split
import cv2
import numpy as np
from hard_textures import fractal_noise  # scripts/ is on sys.path

from hardclips.folds import (
    FOLD_FILES,
    add_pushing_hand,
    fold_and_unfold,
    hair_streaks,
    paced_fold,
    plush_on_pivot,
    set_back_colour,
)
from hardclips.heldout_folds import diagonal_away, diagonal_towards_camera
from hardclips.heldout_folds3 import (
    HAND_DEPTH,
    crease_bend,
    eased,
    hand_pose,
    key_every_frame,
    object_matrices,
    sheet_frames,
)
from hardclips.materials import studio_lights
from hardclips.scene import Clip
from hardclips.sheet import add_sheet, bend, deform_origin, deg, finish_sheet, set_sheen
from hardclips.video import srgb_to_linear

# --- paint ----------------------------------------------------------------------------------

CALICO_CREAM = (0.94, 0.88, 0.77)  # the calico plush's dyes (sRGB)
CALICO_GINGER = (0.86, 0.48, 0.17)
CALICO_DARK = (0.14, 0.10, 0.08)
CALICO_FELT = (0.05, 0.03, 0.02, 1.0)  # calico_tail_turn's back and rim (linear RGB)


def _patches(rng, shape, share, cells=(2, 4, 8), blur=40.0):
    """A soft-edged mask of large patches covering about ``share`` of the texture, in [0, 1].

    Fractal noise cut at its ``1 - share`` quantile, then blurred by ``blur`` texels.
    """
    field = fractal_noise(rng, shape, cells=cells, falloff=0.5)
    cut = (field > np.quantile(field, 1 - share)).astype(np.float32)
    return cv2.GaussianBlur(cut, (0, 0), blur)


def _pile(rng, shape, angles, tufts, fine):
    """A short plush pile's shading about 1: mottling, tufts and fine hair along ``angles``.

    ``tufts`` and ``fine`` are their weights; the tufts are drawn at a quarter size and
    enlarged.
    """
    tone = fractal_noise(rng, shape, cells=(3, 6, 12, 24), falloff=0.7)
    small = (shape[0] // 4, shape[1] // 4)
    big = cv2.resize(
        hair_streaks(rng, small, 17, angles=angles),
        (shape[1], shape[0]),
        interpolation=cv2.INTER_CUBIC,
    )
    thin = hair_streaks(rng, shape, 9, angles=angles)
    return 1.0 + 0.04 * tone + tufts * big + fine * thin


def calico_plush(rng, width, height):
    """Calico faux fur: a faint short pile dyed in large soft patches of cream, ginger and black.

    Cream fur with large patches (about a third of it) of ginger orange and, over them, large
    patches of near black (about a quarter), each with edges blurred over some 40 texels and
    the dye a little uneven inside; a short pile (mottling, tufts and fine hair combed a little
    off the horizontal), a few per cent of contrast, so that the colours vary a lot overall but
    the fine texture stays faint.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    ginger = _patches(rng, shape, 0.38, cells=(3, 5, 10))[..., None]
    dark = _patches(rng, shape, 0.28, cells=(2, 4, 8))[..., None]
    colour = (1 - ginger) * np.array(CALICO_CREAM) + ginger * np.array(CALICO_GINGER)
    colour = (1 - dark) * colour + dark * np.array(CALICO_DARK)
    uneven = 1.0 + 0.05 * fractal_noise(rng, shape, cells=(4, 8), falloff=0.6)
    light = _pile(rng, shape, (15.0, 40.0), 0.03, 0.015) * uneven
    image = light[..., None] * colour + 0.006 * rng.standard_normal((*shape, 3))
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.8), 0, 1)


SPOT_WHITE = (0.93, 0.91, 0.86)  # the spotted plush's white fur and black spots (sRGB)
SPOT_BLACK = (0.07, 0.065, 0.06)
SPOT_FELT = (0.012, 0.011, 0.010, 1.0)  # spotted_plush_squeeze's back and rim (linear RGB)


def _blob_points(rng, centre, radius, turn, stretch):
    """An irregular closed outline round ``centre``: a stretched circle with wobbly harmonics."""
    angles = np.linspace(0, 2 * math.pi, 72, endpoint=False)
    wobble = np.ones_like(angles)
    for k, amplitude in ((2, 0.16), (3, 0.12), (4, 0.07), (5, 0.05), (7, 0.03)):
        wobble += amplitude * rng.uniform(0.4, 1.0) * np.sin(k * angles + rng.uniform(0, 6.3))
    x = radius * stretch * wobble * np.cos(angles)
    y = radius / stretch * wobble * np.sin(angles)
    c, s = math.cos(turn), math.sin(turn)
    return np.column_stack([centre[0] + c * x - s * y, centre[1] + s * x + c * y])


def spotted_plush(rng, width, height):
    """White plush with large irregular black spots: dalmatian- and cow-like, soft edges.

    Eight big cow-like spots (a radius of 80-135 texels, irregular and stretched), ten smaller
    dalmatian spots (38-65 texels) and a few specks beside them, their edges blurred over some
    30 texels (as the pile blurs them); the white a little creamy and uneven; a faint short
    pile (tufts and fine hair combed down and to the right), a few per cent of contrast.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    spots = np.zeros(shape, np.float32)
    kinds = [(8, (80.0, 135.0), (1.0, 1.5)), (10, (38.0, 65.0), (1.0, 1.25))]
    for count, radii, stretches in kinds:
        for _ in range(count):
            centre = rng.uniform((-40, -40), (width + 40, height + 40))
            radius = rng.uniform(*radii)
            points = _blob_points(
                rng, centre, radius, rng.uniform(0, math.pi), rng.uniform(*stretches)
            )
            cv2.fillPoly(spots, [np.round(points * 16).astype(np.int32)], 1.0, cv2.LINE_AA, 4)
            for _ in range(int(rng.integers(0, 3))):  # specks beside it
                phi = rng.uniform(0, 2 * math.pi)
                reach = rng.uniform(1.3, 1.8) * radius
                at = centre + reach * np.array((math.cos(phi), math.sin(phi)))
                small = _blob_points(rng, at, rng.uniform(14, 24), 0.0, 1.0)
                cv2.fillPoly(spots, [np.round(small * 16).astype(np.int32)], 1.0, cv2.LINE_AA, 4)
    spots = cv2.GaussianBlur(spots, (0, 0), 32.0)[..., None]
    white = np.array(SPOT_WHITE) * (1.0 + 0.03 * fractal_noise(rng, shape, cells=(3, 6)))[..., None]
    colour = (1 - spots) * white + spots * np.array(SPOT_BLACK)
    light = _pile(rng, shape, (55.0, 75.0), 0.03, 0.015)
    image = light[..., None] * colour + 0.006 * rng.standard_normal((*shape, 3))
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.8), 0, 1)


WATERCOLOUR_PAPER = (0.97, 0.955, 0.92)  # the card's paper (sRGB)
CARD_BACK = (0.94, 0.93, 0.90)  # the card's plain back, and its rim (sRGB)
PIGMENTS = {  # the colour a pigment lets through (sRGB): each wash multiplies by it
    "ultramarine": (0.38, 0.55, 0.88),
    "rose": (0.97, 0.62, 0.62),
    "peach": (0.99, 0.80, 0.58),
    "violet": (0.70, 0.60, 0.82),
    "sap": (0.55, 0.74, 0.38),
    "hooker": (0.30, 0.50, 0.32),
    "ochre": (0.95, 0.78, 0.45),
    "sepia": (0.62, 0.50, 0.40),
    "cerulean": (0.50, 0.75, 0.88),
}


def _ridge(rng, width, base, swing, cells):
    """A wavy line across the painting: its row at every column, ``base`` +- ``swing``."""
    line = fractal_noise(rng, (1, width), cells=cells, falloff=0.6)[0]
    return base + swing * line


def watercolour_print(rng, width, height):
    """A printed watercolour landscape: soft washes and gradients, hardly any hard edge.

    Transparent washes glazed over warm white paper (each multiplies the paper by its
    pigment's colour to a varying density): a sky graded from ultramarine at the top to a rose
    and peach glow at the horizon, with soft clouds lifted out; violet far hills and green
    near hills laid wet into wet (their edges blurred over 8-18 texels, a faint darker rim of
    pigment along two of them); an ochre field graded into sap green; a lake of cerulean with
    the sky's glow reflected in soft horizontal streaks; a few blotted trees; pigment
    granulation, and a faint cold-press paper grain.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    density = {name: np.zeros(shape, np.float32) for name in PIGMENTS}

    def soft(mask, sigma):
        return cv2.GaussianBlur(mask.astype(np.float32), (0, 0), sigma)

    def wet(field):  # a wash's uneven density: wet-in-wet blooms and backruns
        return field * (0.8 + 0.35 * fractal_noise(rng, shape, cells=(3, 6, 12), falloff=0.55))

    horizon = 0.48 * height
    # The sky: ultramarine graded down to the horizon, clouds lifted out, a glow below.
    sky = np.clip(1.0 - ys / horizon, 0, 1) ** 1.3
    clouds = np.clip(1.6 * fractal_noise(rng, shape, cells=(2, 4, 8), falloff=0.5) - 0.2, 0, 1)
    clouds *= np.clip(1.3 - ys / horizon, 0, 1)
    density["ultramarine"] += wet(1.35 * sky * (1 - 0.85 * soft(clouds, 10.0)))
    glow = np.exp(-(((ys - 0.9 * horizon) / (0.28 * height)) ** 2))
    # Far hills (violet) and near hills (sap, a deeper green lower down), wet into wet.
    far = _ridge(rng, width, 0.40 * height, 0.07 * height, (2, 4, 8))
    near = _ridge(rng, width, 0.56 * height, 0.08 * height, (2, 3, 6))
    far_mask = soft(ys > far[None, :], 9.0)
    near_mask = soft(ys > near[None, :], 14.0)
    above = 1 - 0.8 * far_mask
    density["rose"] += wet(1.1 * glow * above * (0.6 + 0.4 * np.sin(xs / width * 3.0 + 1.0)))
    density["peach"] += wet(1.4 * above * np.exp(-(((ys - horizon) / (0.12 * height)) ** 2)))
    density["violet"] += wet(1.3 * far_mask * (1 - 0.6 * near_mask))
    density["violet"] += 0.35 * np.exp(-(((ys - far[None, :] - 3) / 5.0) ** 2))  # its rim
    density["sap"] += wet(1.5 * near_mask)
    density["hooker"] += wet(0.9 * near_mask * np.clip((ys - near[None, :]) / 90.0, 0, 1))
    density["hooker"] += 0.3 * np.exp(-(((ys - near[None, :] - 4) / 6.0) ** 2))
    # The lake: cerulean between two soft shores, the glow reflected in streaks along it.
    top = _ridge(rng, width, 0.70 * height, 0.03 * height, (2, 4))
    bottom = _ridge(rng, width, 0.82 * height, 0.03 * height, (2, 4))
    lake = soft((ys > top[None, :]) & (ys < bottom[None, :]), 8.0)
    streaks = cv2.GaussianBlur(
        rng.standard_normal(shape).astype(np.float32), (0, 0), sigmaX=60.0, sigmaY=3.0
    )
    streaks /= np.abs(streaks).max()
    density["sap"] *= 1 - 0.9 * lake
    density["hooker"] *= 1 - 0.9 * lake
    density["cerulean"] += wet(1.4 * lake * (1.0 + 0.5 * streaks))
    density["rose"] += 0.6 * lake * np.clip(streaks, 0, 1)
    # The field below the lake: ochre, graded into green at the bottom.
    field = soft(ys > bottom[None, :] + 6, 12.0)
    density["sap"] *= 1 - 0.7 * field
    density["ochre"] += wet(1.6 * field)
    density["sap"] += wet(1.2 * field * np.clip((ys - bottom[None, :]) / (0.2 * height), 0, 1))
    # Trees: blotted blobs of deep green and sepia on the near hills, soft.
    trees = np.zeros(shape, np.float32)
    for _ in range(16):
        x = rng.uniform(0, width)
        y = near[int(np.clip(x, 0, width - 1))] + rng.uniform(-10, 40)
        for _ in range(5):
            at = (round((x + rng.normal(0, 14)) * 16), round((y + rng.normal(0, 12)) * 16))
            r = round(rng.uniform(10, 24) * 16)
            cv2.circle(trees, at, r, 1.0, -1, cv2.LINE_AA, 4)
    trees = soft(trees, 5.0)
    density["hooker"] += wet(1.2 * trees)
    density["sepia"] += 0.5 * trees * np.clip(fractal_noise(rng, shape, cells=(8, 16)), 0, 1)
    # Pigment granulation, then glaze the washes over the paper.
    grain = 1.0 + 0.06 * fractal_noise(rng, shape, cells=(40, 80), falloff=0.7)
    image = np.ones((height, width, 3), np.float32) * np.array(WATERCOLOUR_PAPER, np.float32)
    for name, colour in PIGMENTS.items():
        d = (np.clip(density[name], 0, None) * grain)[..., None]
        image = image * np.power(np.array(colour, np.float32), d)
    paper = 1.0 + 0.012 * fractal_noise(rng, shape, cells=(60, 120), falloff=0.8)
    image = image * paper[..., None]
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.7), 0, 1)


# --- scenes ---------------------------------------------------------------------------------

CALICO_SIZE = (2.0, 1.5)
CALICO_AT = (-0.55, 0.3)  # calico_tail_turn: the patch's centre at rest, left of and above
CALICO_FALL = 65.0  # the turning axis: deg from the horizontal, falling to the right
CALICO_PIVOT = -0.55  # the axis's distance from the centre, across it (to the upper right)
CALICO_CREASE = 0.0  # where the tail's bend starts, likewise: through the centre
CALICO_BAND = 0.35  # the length of the tail's bend
CALICO_INSET = 0.2  # the hand's fingertips: how far inside the lower left corner, across


def build_calico_tail_turn(rng, clip):
    studio_lights()
    size = CALICO_SIZE
    fall = math.radians(CALICO_FALL)
    axis = np.array((math.cos(fall), -math.sin(fall)))  # down and right
    across = np.array((-math.sin(fall), -math.cos(fall)))  # down and left, towards the tail
    sheet, pivot = plush_on_pivot(
        rng, calico_plush, size, (80, 60), 0.0, (0.45, 0.45, (0.98, 0.9, 0.8, 1.0))
    )
    # The pivot: the axis through the upper right part, pointing down and right, so that
    # turning about it by a positive angle takes the part beyond it (to the lower left) away
    # from the camera.
    at = np.array(CALICO_AT) + CALICO_PIVOT * across
    pivot.location = (*at, 0.0)
    pivot.rotation_mode = "AXIS_ANGLE"
    pivot.rotation_axis_angle = (0.0, *axis, 0.0)
    sheet.obj.location = (*(-CALICO_PIVOT * across), 0.0)
    # The soft toy gives where it is held: the tail (beyond CALICO_CREASE, towards the lower
    # left corner) bends further away over a band of CALICO_BAND, so that the patch turns 30
    # deg and the tail 110 deg, past edge-on, behind the rest.
    angle = math.atan2(across[1], across[0])
    crease_bend(sheet, "Tail", size, angle, CALICO_CREASE, CALICO_BAND, diagonal_away)
    # Away at a moderate pace (0.8 s), held 0.45 s, back in 0.85 s, drifting right and up.
    start, top, back, flat = 0.3, 1.1, 1.55, 2.4
    clip.keyframe(
        pivot,
        {
            ("rotation_axis_angle", 0): deg(
                [(0.0, 0), (start, 0), (top, 30), (back, 30), (flat, 0)]
            ),
            ("location", 0): [
                (0.0, at[0]),
                (start, at[0]),
                (1.5, at[0] + 0.16),
                (3.3, at[0] + 0.07),
            ],
            ("location", 1): [
                (0.0, at[1]),
                (start, at[1]),
                (1.5, at[1] + 0.1),
                (3.3, at[1] + 0.04),
            ],
        },
    )
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Tail"].angle', 0): deg(
                [(0.0, 0), (start, 0), (top, 80), (back, 80), (flat, 0)]
            )
        },
    )
    # The hand holds the lower left corner (the tail's end): its fingers (pointing up and
    # left, along the axis) lie over the corner CALICO_INSET inside it, its back away from
    # the painted side; moved with the corner on every frame, its forearm stays along the
    # axis, out to the lower right below the patch's bottom edge. It comes in along the axis
    # and leaves the same way.
    grids = sheet_frames(clip, sheet)
    t = np.arange(clip.frames) / clip.fps
    away = eased(t, [(0.0, 3.5), (0.05, 3.5), (0.3, 0.0), (2.45, 0.0), (2.95, 3.5)])
    hand = add_pushing_hand("Hand", True)
    poses = []
    for grid, out in zip(grids, away, strict=True):
        corner = grid[-1, 0]
        along_x = grid[-1, 2] - corner
        along_y = grid[-3, 0] - corner
        along_x, along_y = along_x / np.linalg.norm(along_x), along_y / np.linalg.norm(along_y)
        normal = np.cross(along_x, along_y)
        a = axis[0] * along_x + axis[1] * along_y
        n = across[0] * along_x + across[1] * along_y
        tips = corner + out * a - CALICO_INSET * n + 0.13 * normal
        poses.append(hand_pose(tips, -a, normal))
    key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, CALICO_FELT)
    return sheet


SPOT_SIZE = (2.1, 1.55)
SPOT_AT = (0.55, -0.28)  # spotted_plush_squeeze: the patch's centre at rest, right of and below
SPOT_ANGLE = 208.0  # the fold's direction (deg from +X: left and down)
SPOT_CREASE = 0.02  # the crease's distance from the patch's centre along that direction
SPOT_BAND = 0.24  # folded, the lower left part lies 2 * band / pi behind the rest
SPOT_UPPER = 78.0  # the upper hand comes in along this direction (deg from +X, patch frame)
SPOT_FOLD = (0.4, 1.45)  # when it starts to fold and to unfold (s)


def build_spotted_plush_squeeze(rng, clip):
    studio_lights()
    size = SPOT_SIZE
    sheet = add_sheet(
        spotted_plush,
        size,
        (84, 60),
        4,
        rng=rng,
        roughness=0.95,
        specular=0.15,
        thickness=0.04,
    )
    set_sheen(sheet, 0.45, 0.4, (0.95, 0.95, 0.92, 1.0))
    angle = math.radians(SPOT_ANGLE)
    d = np.array((math.cos(angle), math.sin(angle)))  # the fold's direction, left and down
    # The squeeze bows the patch a little along the crease (the crease's ends towards the
    # camera): that does not change where a point is along d, so the fold's limits stay put...
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), diagonal_towards_camera(angle - math.pi / 2))
    bend(sheet, "Bow", origin)
    # ...and folds the lower left part back about the crease rising 62 deg to the left, over a
    # band of SPOT_BAND.
    crease_bend(sheet, "Fold", size, angle, SPOT_CREASE, SPOT_BAND, diagonal_away)
    # The fold (keyed on every frame): over in about 0.5 s, open again in about 0.7 s. The
    # lower left hand pushes the patch right and up and turns it 4 deg clockwise.
    t = np.arange(clip.frames) / clip.fps
    fold_at, unfold_at = SPOT_FOLD
    over = fold_and_unfold(t, fold_at, t[-1] + 1.0, paced_fold(5.0, 14.0, 90.0))
    back = fold_and_unfold(t, -10.0, unfold_at, paced_fold(3.8, 10.0, 45.0))
    fold = np.where(t < unfold_at, over, back)
    x0, y0 = SPOT_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bow"].angle', 0): deg(
                [(0.0, 0), (0.35, 0), (0.85, 15), (1.5, 15), (2.3, 0)]
            ),
            ('modifiers["Fold"].angle', 0): list(zip(t, fold, strict=True)),
            ("location", 0): [(0.0, x0), (0.35, x0), (1.0, x0 + 0.125), (2.8, x0 + 0.05)],
            ("location", 1): [(0.0, y0), (0.35, y0), (1.0, y0 + 0.09), (2.8, y0 + 0.03)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.35, 0), (1.0, -4), (2.8, -1.5)]),
        },
    )
    # The hands come in in front of the patch and move with it: the lower left one, its
    # fingers (pointing up and right) over the lower left part and then, following its edge
    # as it folds back, onto the crease; the upper one, its fingers (pointing down) over the
    # upper part. Where their fingertips are: how far out from the patch's centre along the
    # direction they come in from (for the lower left hand, the larger of the keys and the
    # folding edge), and how far across it (patch frame).
    edge = min(size[0] / 2 / abs(d[0]), size[1] / 2 / abs(d[1]))  # the left edge, along d
    folding_edge = SPOT_CREASE + np.maximum((edge - SPOT_CREASE) * np.cos(fold) - 0.25, -0.2)
    lower_tips = [
        (0.0, 4.4),
        (0.05, 4.4),
        (0.38, 0.7),
        (0.9, SPOT_CREASE - 0.2),
        (unfold_at, SPOT_CREASE - 0.2),
        (2.1, 0.75),
        (3.0, 4.4),
    ]
    upper_tips = [
        (0.0, 4.4),
        (0.1, 4.4),
        (0.45, 0.5),
        (1.0, 0.45),
        (unfold_at, 0.45),
        (2.2, 0.5),
        (3.2, 4.4),
    ]
    side = math.radians(SPOT_UPPER)
    matrices = object_matrices(clip, sheet.obj)
    for name, reach, out, across in (
        ("LowerHand", np.maximum(eased(t, lower_tips), folding_edge), d, 0.1),
        ("UpperHand", eased(t, upper_tips), np.array((math.cos(side), math.sin(side))), -0.15),
    ):
        hand = add_pushing_hand(name, False)
        normal = np.array((-out[1], out[0]))
        poses = []
        for m, r in zip(matrices, reach, strict=True):
            local = r * out + across * normal
            tip = m[:3, :3] @ (*local, 0.0) + m[:3, 3]
            tip[2] = HAND_DEPTH
            fingers = m[:3, :3] @ (*(-out), 0.0)
            poses.append(hand_pose(tip, fingers, (0.0, 0.0, 1.0)))
        key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, SPOT_FELT)
    return sheet


CARD_SIZE = (2.5, 1.75)
CARD_AT = (0.1, -0.35)  # watercolour_card_fold: the card's centre at rest, below the middle
CARD_ANGLE = 196.0  # the fold's direction (deg from +X: left, a little down)
CARD_CREASE = 0.47  # the crease's distance from the centre along that direction
CARD_BAND = 0.26  # folded, the flap lies 2 * band / pi in front


def build_watercolour_card_fold(rng, clip):
    studio_lights()
    size = CARD_SIZE
    sheet = add_sheet(
        watercolour_print,
        size,
        (80, 56),
        4,
        rng=rng,
        roughness=0.55,
        specular=0.35,
        thickness=0.01,
    )
    # The left side folds over onto the rest, towards the camera, about a crease leaning 16
    # deg from the vertical (its top to the left); folded, it lies about 0.17 in front, its
    # plain back to the camera.
    angle = math.radians(CARD_ANGLE)
    crease_bend(sheet, "Fold", size, angle, CARD_CREASE, CARD_BAND, diagonal_towards_camera)
    # Over in 0.75 s (slower while the painting on it is in view), held 0.45 s, unfolded in
    # 0.9 s; meanwhile the card slides left and up and turns 3 deg clockwise.
    x0, y0 = CARD_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): deg(
                [(0.0, 0), (0.3, 0), (0.75, 80), (1.05, 180), (1.5, 180), (2.4, 0)]
            ),
            ("location", 0): [(0.0, x0), (0.3, x0), (2.9, x0 - 0.22)],
            ("location", 1): [(0.0, y0), (0.3, y0), (2.9, y0 + 0.1)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.3, 0), (2.9, -3)]),
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(CARD_BACK)), 1.0))
    return sheet


HELDOUT_FOLDS8 = [
    Clip(
        "calico_tail_turn",
        100,
        30,
        "a furry stuffed-toy patch of calico faux fur (a faint short pile dyed in large soft "
        "patches of cream, ginger and brown-black: colourful overall, faint in its fine "
        "detail), left of and above the middle, held by a hand at its lower left corner (its "
        "tail), is turned away from the camera at a moderate pace (0.8 s) about an axis "
        "falling 65 deg to the right through its upper right part: the patch turns 30 deg, "
        "its lower left half on to 110 deg, past edge-on (painted side turned away, behind "
        "the rest); holds 0.45 s, turns back (0.85 s) while it drifts about 16 px right and "
        "10 px up; the hand leaves",
        build_calico_tail_turn,
    ),
    Clip(
        "spotted_plush_squeeze",
        100,
        30,
        "two hands, in from the lower left and from above, squeeze a plush patch of white "
        "short fur with large soft-edged black spots, lying right of and below the middle: it "
        "bows and its lower left part (49 %) folds back behind the rest about a crease "
        "rising 62 deg to the left (0.5 s), while the lower hand pushes it about 13 px right "
        "and 9 px up and turns it 4 deg; holds 0.55 s with the lower hand over the crease and "
        "the upper hand over the upper part, opens again gently (0.67 s); the hands leave",
        build_spotted_plush_squeeze,
    ),
    Clip(
        "watercolour_card_fold",
        100,
        30,
        "the left side (30 %) of a printed card with a watercolour landscape (soft washes "
        "and gradients, hardly any hard edge, weak fine detail), below the middle, folds "
        "over onto the rest by 180 deg, towards the camera, about a crease leaning 16 deg "
        "from the vertical (0.75 s; its plain back covers about 17 % more of the painting); "
        "holds 0.45 s and unfolds (0.9 s) while the card slides about 23 px left and 10 px up "
        "and turns 3 deg",
        build_watercolour_card_fold,
    ),
]


README_HELDOUT_FOLDS8 = (
    """# Held-out clips of folds, eighth batch

Clips for checking that the tracker generalises to folds (issue 22): never tune it on these;
they are to be measured once, as held-out. The tracker was tuned on the fold clips of
[`../folds`](../folds/README.md); like the first seven held-out batches
([`../heldout_folds`](../heldout_folds/README.md),
[`../heldout_folds2`](../heldout_folds2/README.md),
[`../heldout_folds3`](../heldout_folds3/README.md),
[`../heldout_folds4`](../heldout_folds4/README.md),
[`../heldout_folds5`](../heldout_folds5/README.md),
[`../heldout_folds6`](../heldout_folds6/README.md) and
[`../heldout_folds7`](../heldout_folds7/README.md)) these show the same kinds of motion (a
soft patch turned past edge-on by its tail, a soft patch squeezed until part of it folds back,
a part folded over the rest) with paint, axes, speeds and places that no earlier batch has: a
calico plush dyed in large patches of cream, ginger and near black (its colours vary a lot
overall, its fine texture is faint), held by its lower left corner and turned away from the
camera about an axis falling 65 deg to the right, at a moderate pace; a white plush with large
soft black spots, whose lower left part folds back about a crease rising 62 deg to the left
under hands in from the lower left and from above; a printed watercolour card (soft washes,
weak fine detail) whose left side folds over about a crease leaning 16 deg from the vertical
while the card slides. Rendered with Blender {blender} (the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes and paint in
`scripts/hardclips/heldout_folds8.py`) from a fixed seed, so the same command makes the same
scenes, truth and outlines; it makes them only when named, apart from every other clip:

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \\
        --out samples/heldout_folds8 --only {names}

Keep them out of `samples/folds` and `samples/heldout_folds` to `samples/heldout_folds7`.
Check them with `.venv/bin/python scripts/check_hard_clips.py --dir samples/heldout_folds8`
(statistics, and contact sheets in `/tmp/hard_check/`).

"""
    + FOLD_FILES
)
