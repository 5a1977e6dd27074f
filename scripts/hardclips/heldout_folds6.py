r"""A sixth batch of held-out clips of folds: new paint, axes, speeds and places, never tuned on.

The tracker was tuned on the fold clips of ``folds`` (``samples/folds``); the held-out batches
(``heldout_folds`` to ``heldout_folds5`` and this one, in ``samples/heldout_folds`` to
``samples/heldout_folds6``) check that it generalises and are never to be tuned on. This batch
was made after the fifth, for issue 22's generalisation check. ``HELDOUT_FOLDS6`` lists it.
``render_hard_clips.py`` makes these clips only when asked by name, into a folder of their own
(``samples/heldout_folds6``), apart from every other clip::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \
        --out samples/heldout_folds6 --only NAME ...

Each writes the files of a single-sheet hard clip (``NAME.mp4``, ``NAME.json``,
``NAME_truth.npz``) with the conventions of ``folds``: frame 0 flat and square to the camera,
at rest for three frames; every crease runs through the outlined region; the folds are
SimpleDeform bends over a band at the crease (``fold_limits``), so a folded part never passes
through the rest. The paint is here (``peas_bag_print``, ``minky_dot_plush``,
``street_map``); the scenes reuse the helpers of ``heldout_folds3`` (hands posed on every
frame, eased keys, ``crease_bend``). Unlike the earlier batches, the two hands come in from
above and from the left and the bag's upper part folds back about a crease falling to the
right, fast, and unfolds slowly; the plush is held by its upper right corner and lifted about
an axis falling 40 deg to the right, slowly, and let back fast; the printed sheet's bottom
part folds up over the rest in two steps, and the sheet comes nearer the camera as it unfolds.

``peas_bag_squeeze``
    A soft bag of frozen peas (``peas_bag_print``: glossy film printed in freezer blue fading
    to icy pale blue, frost and white ice crystals, a big italic white wordmark outlined in
    navy and a yellow second word, a heap of several hundred shaded peas and three open pods,
    a red starburst badge, a white panel of cooking instructions, a barcode, a ridged heat
    seal along the bottom; its back the film's milky inside), lying above the middle
    (``PEAS_AT``), is squeezed by two hands in front of it, one from above (a little right)
    and one from the left (``PEAS_LEFT``). It bows a little along the crease and its upper
    part (46 %) folds back behind the rest in half, about a crease through the middle that
    falls 25 deg to the right (``PEAS_ANGLE``, ``PEAS_CREASE``: from the left edge near the
    top to the right edge below the middle), over a band of 0.2 (folded it lies about 0.13
    behind), fast (in about 0.34 s from 0.5 s, ``PEAS_FOLD``; out of sight past about 100
    deg), while the upper hand pushes the bag about 16 px down and a little left and turns it
    4 deg anticlockwise. Folded back, it sticks out below the rest, showing its milky back.
    The upper hand's fingers follow the folding part's edge onto the crease; the left hand's
    lie over the left part below the crease (folded, the hands hide about 7 % of the bag
    besides the part folded away). It holds folded for 0.6 s, unfolds slowly (from
    1.45 s, flat by about 2.25 s) and the hands leave the way they came.
``minky_tail_swing``
    A furry, low-contrast stuffed-toy patch of dusty pink minky (``minky_dot_plush``: a short
    velvety pile, lighter or darker where it is crushed, with raised dots of pile in a staggered
    grid, each lit on one side and shadowed on the other, only a few per cent lighter than the
    ground, unlike the long hair, brush strokes and curls of the other plush paints; a sheen
    material, dark rose felt behind), lying below the middle (``MINKY_AT``), is held by a hand
    at its upper right corner (its tail) and lifted towards the camera about an axis falling 40
    deg to the right (``MINKY_TILT``, through its lower left part, ``MINKY_PIVOT``): the patch
    turns 25 deg about it and, being soft, its part beyond a crease parallel to the axis, a
    little above and right of the middle (``MINKY_CREASE``; 41 % of the patch), bends a further
    85 deg over a band of 0.35, so that the tail turns to 110 deg (past edge-on: its painted
    side turns away, ``visible`` false, and its felt back leans over the rest, hiding with the
    hand about 19 % more of the patch). It turns slowly (1.5 s, from 0.3 s), holds 0.15 s and
    turns back fast (in 0.6 s) while it drifts about 18 px up and 8 px right and most of the way
    back. The hand comes in along its forearm from the upper left (0.05 to 0.3 s), holds the
    corner (moved with the corner frame by frame, it rolls about its forearm, which stays along
    the axis, as the tail rises) and leaves the same way (2.75 to 3.25 s).
``city_map_foldup``
    A printed city street map (``street_map``: cream blocks between white streets cased in
    grey on a tilted, gently bent grid, yellow avenues and a ring road cased in orange, a
    winding blue river with bridges, green parks with trees and ponds, pinkish downtown
    blocks, a railway, street and district names with white halos, red and blue markers, a
    compass rose, a scale bar and a legend, inside a white margin with grid references; its
    back is plain paper), right of and below the middle (``MAP_AT``): its bottom part (29 %,
    below ``MAP_CREASE``) folds up over the rest by 180 deg, towards the camera, about a
    crease falling 5 deg to the right (``MAP_ANGLE``), over a band of 0.16 (the flap lies
    about 0.1 in front), its plain back covering about 19 % more of the print. It folds in
    two steps: up to standing (92 deg) in 0.35 s from 0.3 s, slowly on to 100 deg over 0.3
    s, then over to flat in 0.35 s; it holds 0.45 s and unfolds in one go (0.85 s) while the
    map comes ``MAP_LIFT`` nearer the camera (about 9 % larger on the picture), drifts about
    15 px left and 8 px up and turns 6 deg clockwise.
"""

import math

import bpy  # noqa: F401 - first, before the modules that load with it

# isort: split
import cv2
import numpy as np
from hard_textures import _random_text, fractal_noise  # scripts/ is on sys.path

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
from hardclips.heldout_folds2 import _barcode
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
from hardclips.sheet import add_sheet, bend, deform_origin, deg, finish_sheet
from hardclips.video import srgb_to_linear

# --- paint ----------------------------------------------------------------------------------

FREEZER_BLUE = (0.06, 0.20, 0.50)  # the peas bag's print: deep blue at the top (sRGB)
ICE_BLUE = (0.55, 0.78, 0.93)  # and icy pale blue lower down
BAG_FILM = (0.84, 0.88, 0.92)  # the film's milky inside: the bag's back and rim (sRGB)
PEAS_INK = np.array(
    [
        (0.98, 0.98, 0.97),  # white
        (0.99, 0.80, 0.10),  # yellow
        (0.85, 0.10, 0.12),  # red
        (0.04, 0.10, 0.30),  # navy
        (0.20, 0.55, 0.12),  # leaf green
    ]
)


def _pea(image, centre, radius, tone):
    """A shaded green pea (a lit sphere with a highlight and a dark rim), in place."""
    x, y = centre
    green = np.array((0.30, 0.62, 0.16)) * tone
    cv2.circle(
        image,
        (round((x + 2) * 16), round((y + 3) * 16)),
        round((radius + 1.5) * 16),
        (green * 0.35).tolist(),
        -1,
        cv2.LINE_AA,
        shift=4,
    )
    for k in range(6):  # lighter towards the upper left, where the key light is
        r = radius * (1 - k / 7)
        shift = 0.07 * radius * k
        colour = np.clip(green * (0.7 + 0.12 * k), 0, 1).tolist()
        at = (round((x - shift) * 16), round((y - shift) * 16))
        cv2.circle(image, at, round(r * 16), colour, -1, cv2.LINE_AA, shift=4)
    at = (round((x - 0.4 * radius) * 16), round((y - 0.45 * radius) * 16))
    cv2.circle(image, at, round(0.18 * radius * 16), (0.9, 0.97, 0.8), -1, cv2.LINE_AA, shift=4)


def _snowflake(image, centre, size, colour, thickness):
    """A six-armed ice crystal with a pair of short branches on each arm, in place."""
    x, y = centre
    branch = 0.3 * size  # the branches' length
    for k in range(6):
        angle = math.pi / 3 * k
        c, s = math.cos(angle), math.sin(angle)
        tip = (x + size * c, y + size * s)
        lines = [((x, y), tip)]
        for along in (0.45, 0.7):
            root = (x + along * size * c, y + along * size * s)
            for side in (-1, 1):
                b = angle + side * math.pi / 4
                lines.append(
                    (root, (root[0] + branch * math.cos(b), root[1] + branch * math.sin(b)))
                )
        for a, b in lines:
            a = (round(a[0] * 16), round(a[1] * 16))
            b = (round(b[0] * 16), round(b[1] * 16))
            cv2.line(image, a, b, colour, thickness, cv2.LINE_AA, shift=4)


def _outlined_text(image, text, org, scale, colours, thicknesses, font=cv2.FONT_HERSHEY_TRIPLEX):
    """``text`` drawn once per colour, thickest first (an outline under the letters), in place."""
    for colour, thickness in zip(colours, thicknesses, strict=True):
        cv2.putText(image, text, org, font, scale, list(colour), thickness, cv2.LINE_AA)


def peas_bag_print(rng, width, height):
    """The printed film of a bag of frozen peas: frost, a heap of peas, a wordmark, a barcode.

    Deep freezer blue fading to icy pale blue downwards, with frosty mottling and white ice
    crystals; a big italic white wordmark outlined in navy across the upper left and a yellow
    second word under it; a heap of several hundred shaded peas (each lit from the upper left,
    with a highlight and a dark rim) and three open pods, low and right of the middle; a red
    starburst badge with a number, upper right; a white panel of cooking instructions with
    small icons and lines of small print, lower left; a barcode on a white panel, lower right;
    a ridged heat seal along the bottom; frost speckles along the edges.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    down = (ys / height)[..., None] ** 0.8
    image = (1 - down) * np.array(FREEZER_BLUE) + down * np.array(ICE_BLUE)
    frost = np.clip(0.5 + 1.8 * fractal_noise(rng, shape, cells=(4, 8, 16, 32)), 0, 1)
    image = image + (0.12 * frost)[..., None]
    image = np.ascontiguousarray(image.astype(np.float32))
    white, yellow, red, navy, leaf = PEAS_INK
    for _ in range(45):  # ice crystals, faint and bright
        at = rng.uniform((0, 0), (width, 0.75 * height))
        colour = (np.array(white) * rng.uniform(0.75, 1.0)).tolist()
        _snowflake(image, at, rng.uniform(10, 34), colour, int(rng.integers(2, 4)))
    # The wordmark: a made-up brand in big white italic capitals outlined in navy, and a second
    # word in yellow under it.
    brand = (_random_text(rng, 6).replace(" ", "") or "FROSTY")[:6]
    italic = cv2.FONT_HERSHEY_TRIPLEX | cv2.FONT_ITALIC
    org = (int(0.04 * width), int(0.22 * height))
    _outlined_text(image, brand, org, 4.6, (navy, white), (30, 12), italic)
    word = (_random_text(rng, 8).replace(" ", "") or "PEAS")[:7]
    org = (int(0.07 * width), int(0.36 * height))
    _outlined_text(image, word, org, 2.6, (navy, yellow), (20, 8), italic)
    tagline = _random_text(rng, 22)
    cv2.putText(
        image,
        tagline,
        (int(0.07 * width), int(0.43 * height)),
        cv2.FONT_HERSHEY_DUPLEX,
        1.0,
        white.tolist(),
        2,
        cv2.LINE_AA,
    )
    # The heap of peas, drawn back to front (the lower ones in front), and three open pods.
    heap = np.array((rng.uniform(0.56, 0.62) * width, 0.74 * height))
    peas = []
    for _ in range(700):
        t, r = rng.uniform(0, 2 * np.pi), np.sqrt(rng.uniform(0, 1))
        at = heap + np.array((0.36 * width * r * math.cos(t), 0.2 * height * r * math.sin(t)))
        at[1] -= 0.12 * height * (1 - r * r)  # heaped up in the middle
        peas.append(at)
    peas.sort(key=lambda p: p[1])
    for at in peas:
        _pea(image, at, rng.uniform(13, 19), rng.uniform(0.85, 1.15))
    for k in range(3):
        at = heap + np.array(((k - 1) * 0.2 * width, rng.uniform(-0.24, -0.16) * height))
        turn = rng.uniform(-30, 30) + (k - 1) * 25
        c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
        t = np.linspace(-1, 1, 40)
        upper = np.column_stack([95 * t, 26 * (1 - t * t) + 4])
        lower = np.column_stack([95 * t[::-1], -26 * (1 - t[::-1] ** 2) - 4])
        pod = np.vstack([upper, lower]) @ np.array([[c, s], [-s, c]]) + at
        cv2.fillPoly(
            image, [np.round(pod * 16).astype(np.int32)], (0.36, 0.68, 0.22), cv2.LINE_AA, 4
        )
        cv2.polylines(
            image,
            [np.round(pod * 16).astype(np.int32)],
            True,
            (0.12, 0.32, 0.06),
            4,
            cv2.LINE_AA,
            4,
        )
        for j in range(5):  # the peas inside
            p = np.array(((j - 2) * 32.0, 0.0)) @ np.array([[c, s], [-s, c]]) + at
            _pea(image, p, 14, 1.0)
    # The badge: a red starburst with a white ring and a number, upper right.
    centre = np.array((rng.uniform(0.83, 0.88) * width, 0.2 * height))
    angles = np.linspace(0, 2 * np.pi, 33)[:-1] + rng.uniform(0, 0.2)
    radii = np.where(np.arange(32) % 2 == 0, 100.0, 82.0)
    burst = centre + np.column_stack([np.cos(angles), np.sin(angles)]) * radii[:, None]
    cv2.fillPoly(image, [np.round(burst * 16).astype(np.int32)], red.tolist(), cv2.LINE_AA, 4)
    at = tuple(np.round(centre).astype(int))
    cv2.circle(image, at, 66, white.tolist(), 4, cv2.LINE_AA)
    number = f"{int(rng.integers(2, 9))}0%"
    cv2.putText(
        image,
        number,
        (at[0] - 56, at[1] + 18),
        cv2.FONT_HERSHEY_DUPLEX,
        1.7,
        white.tolist(),
        4,
        cv2.LINE_AA,
    )
    # Cooking instructions: a white panel with a pan and a bowl drawn in navy, small print.
    x0, y0, w, h = int(0.03 * width), int(0.5 * height), int(0.27 * width), int(0.36 * height)
    cv2.rectangle(image, (x0, y0), (x0 + w, y0 + h), white.tolist(), -1, cv2.LINE_AA)
    cv2.rectangle(image, (x0 + 6, y0 + 6), (x0 + w - 6, y0 + h - 6), navy.tolist(), 3)
    cv2.circle(image, (x0 + 52, y0 + 48), 24, navy.tolist(), 5, cv2.LINE_AA)
    cv2.line(image, (x0 + 76, y0 + 48), (x0 + 125, y0 + 40), navy.tolist(), 7, cv2.LINE_AA)
    cv2.rectangle(image, (x0 + 150, y0 + 28), (x0 + 210, y0 + 68), navy.tolist(), 4)
    cv2.circle(image, (x0 + 198, y0 + 48), 5, navy.tolist(), -1, cv2.LINE_AA)
    for k in range(int((h - 100) // 22)):
        text = _random_text(rng, int(rng.integers(12, 22)))
        cv2.putText(
            image,
            text,
            (x0 + 16, y0 + 100 + 22 * k),
            cv2.FONT_HERSHEY_SIMPLEX,
            0.55,
            navy.tolist(),
            1,
            cv2.LINE_AA,
        )
    # The barcode, lower right, and the net weight under the badge.
    _barcode(image, rng, (int(0.78 * width), int(0.76 * height)), (int(0.18 * width), 110))
    weight = f"{int(rng.integers(4, 10))}00 g"
    cv2.putText(
        image,
        weight,
        (int(0.8 * width), int(0.42 * height)),
        cv2.FONT_HERSHEY_DUPLEX,
        1.3,
        white.tolist(),
        3,
        cv2.LINE_AA,
    )
    # Frost speckles thick along the edges, and the ridged heat seal along the bottom.
    edge = np.minimum(np.minimum(xs, width - 1 - xs), np.minimum(ys, height - 1 - ys))
    near = np.exp(-edge / 40.0)
    specks = cv2.GaussianBlur((rng.random(shape) < 0.05 * near).astype(np.float32), (0, 0), 1.2)
    specks = np.clip(3.0 * specks, 0, 0.8)[..., None]
    image = (1 - specks) * image + specks * white
    seal = int(0.06 * height)
    ridge = 0.9 + 0.12 * np.sin(2 * np.pi * np.arange(width, dtype=np.float32) / 9.0)
    image[-seal:] = image[-seal:] * 0.6 + 0.4 * np.array(BAG_FILM)
    image[-seal:] *= ridge[None, :, None]
    image = np.ascontiguousarray(image.astype(np.float32))
    cv2.line(image, (0, height - seal), (width, height - seal), navy.tolist(), 3, cv2.LINE_AA)
    image *= (1 + 0.015 * rng.standard_normal((*shape, 1))).astype(np.float32)
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


MINKY_PINK = (0.80, 0.60, 0.62)  # the minky plush's dusty pink (sRGB)
ROSE_FELT = (0.20, 0.09, 0.10, 1.0)  # minky_tail_swing's back and rim (linear RGB)


def minky_dot_plush(rng, width, height):
    """A dusty pink minky plush: a short crushed pile with raised dots, low contrast on purpose.

    A short velvety pile, lighter or darker where it is crushed (soft swirls of pile laid one
    way or another: short hair streaks that alternate direction over the patch) and a little
    mottled; raised dots of pile in a staggered grid (about 5 mm apart on the toy, jittered a
    little), each lit from the upper left and shadowed on the lower right, only a few per cent
    lighter than the ground; fine fuzz.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    tone = fractal_noise(rng, shape, cells=(3, 6, 12, 24), falloff=0.7)
    crushed = np.clip(1.8 * fractal_noise(rng, shape, cells=(2, 4, 8)), -1, 1)
    crushed = cv2.GaussianBlur(crushed.astype(np.float32), (0, 0), 6.0)
    small = (height // 3, width // 3)
    pile = cv2.resize(
        hair_streaks(rng, small, 9, angles=(20.0, 160.0)),
        (width, height),
        interpolation=cv2.INTER_CUBIC,
    )
    fine = hair_streaks(rng, shape, 9, angles=(80.0, 100.0))
    light = 1.0 + 0.04 * tone + 0.07 * crushed + 0.03 * pile + 0.02 * fine
    # The dots: a staggered grid, each a soft bump lit from the upper left.
    bumps = np.zeros(shape, np.float32)
    step = 40.0
    for row, y in enumerate(np.arange(-step, height + step, step * 0.866)):
        for x in np.arange(-step + (row % 2) * step / 2, width + step, step):
            cx, cy = x + rng.normal(0, 2.0), y + rng.normal(0, 2.0)
            r = rng.uniform(8.5, 10.5)
            cv2.circle(
                bumps,
                (round(cx * 16), round(cy * 16)),
                round(r * 16),
                1.0,
                -1,
                cv2.LINE_AA,
                shift=4,
            )
    bumps = cv2.GaussianBlur(bumps, (0, 0), 2.0)
    lit = bumps - np.roll(bumps, (3, 3), axis=(0, 1))  # light on the upper left, shadow below
    light = light + 0.05 * bumps + 0.06 * lit
    image = light[..., None] * np.array(MINKY_PINK) + 0.01 * rng.standard_normal((*shape, 3))
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.7), 0, 1)


MAP_PAPER = (0.96, 0.95, 0.91)  # the street map's paper: its margin and its plain back (sRGB)
MAP_INK = np.array(
    [
        (0.93, 0.90, 0.82),  # land (blocks)
        (0.99, 0.99, 0.98),  # streets
        (0.62, 0.60, 0.56),  # street casing
        (0.99, 0.84, 0.36),  # avenues
        (0.86, 0.52, 0.14),  # avenue casing
        (0.58, 0.77, 0.91),  # water
        (0.30, 0.50, 0.72),  # water's edge, and blue ink
        (0.70, 0.85, 0.58),  # parks
        (0.88, 0.80, 0.78),  # downtown blocks
        (0.20, 0.20, 0.22),  # black ink
        (0.84, 0.16, 0.14),  # red ink
    ]
)


def _label(image, text, org, scale, colour, thickness=1):
    """Map lettering: ``text`` with a white halo, so that it reads over streets and blocks."""
    font = cv2.FONT_HERSHEY_SIMPLEX
    cv2.putText(image, text, org, font, scale, list(MAP_INK[1]), thickness + 4, cv2.LINE_AA)
    cv2.putText(image, text, org, font, scale, list(colour), thickness, cv2.LINE_AA)


def street_map(rng, width, height):
    """A printed city street map: a tilted street grid, avenues, a river, parks, lettering.

    Inside a white margin with grid references (letters along the top, numbers down the side)
    and thin blue reference lines: cream blocks between white streets cased in grey, laid on a
    grid turned about 12 deg and bent a little; two yellow avenues cased in orange cutting
    across it and a ring road; a blue river winding across with bridges; green parks with
    tree dots and a pond; pinkish downtown blocks; a railway (black and white dashes);
    street names and district names with white halos; red and blue numbered markers; a
    compass rose, a scale bar and a legend box. Plain paper on the back.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    land, street, casing, avenue, avenue_edge, water, blue, park, downtown, black, red = (
        c.tolist() for c in MAP_INK
    )
    image = np.empty((height, width, 3), np.float32)
    image[:] = land
    # The street grid, turned and bent: block outlines in map coordinates, drawn as polylines.
    turn = math.radians(rng.uniform(9, 15))
    c, s = math.cos(turn), math.sin(turn)
    centre = np.array((width / 2, height / 2))

    def to_map(u, v):
        """Grid coordinates (u along the streets, v across them) to texels, with a bend."""
        u, v = np.asarray(u, np.float64), np.asarray(v, np.float64)
        v = v + 18.0 * np.sin(u / 260.0)
        return np.stack([centre[0] + c * u - s * v, centre[1] + s * u + c * v], axis=-1)

    span = 0.8 * np.hypot(width, height)
    spacing_u, spacing_v = rng.uniform(62, 70), rng.uniform(48, 56)
    us = np.arange(-span, span, spacing_u)
    vs = np.arange(-span, span, spacing_v)
    blocks = []
    for i in range(len(us) - 1):
        for j in range(len(vs) - 1):
            u0, u1, v0, v1 = us[i], us[i + 1], vs[j], vs[j + 1]
            t = np.linspace(0, 1, 6)
            ring = np.concatenate(
                [
                    to_map(u0 + (u1 - u0) * t, np.full(6, v0)),
                    to_map(np.full(6, u1), v0 + (v1 - v0) * t),
                    to_map(u1 - (u1 - u0) * t, np.full(6, v1)),
                    to_map(np.full(6, u0), v1 - (v1 - v0) * t),
                ]
            )
            middle = ring.mean(axis=0)
            if -60 < middle[0] < width + 60 and -60 < middle[1] < height + 60:
                blocks.append(ring)
    poly = [np.round(b * 16).astype(np.int32) for b in blocks]
    cv2.polylines(image, poly, True, casing, 16, cv2.LINE_AA, 4)
    cv2.polylines(image, poly, True, street, 11, cv2.LINE_AA, 4)
    # Blocks: most plain, some downtown, some parks (with tree dots, one with a pond).
    near = np.hypot(*(np.array([b.mean(axis=0) for b in blocks]) - centre * (1.1, 0.8)).T)
    for k, ring in enumerate(blocks):
        inner = (ring - ring.mean(axis=0)) * 0.82 + ring.mean(axis=0)
        pts = [np.round(inner * 16).astype(np.int32)]
        if near[k] < 0.16 * width and rng.random() < 0.8:
            cv2.fillPoly(image, pts, downtown, cv2.LINE_AA, 4)
            for _ in range(int(rng.integers(2, 5))):  # buildings: darker footprints
                a = inner[int(rng.integers(0, len(inner)))]
                b = ring.mean(axis=0)
                p = a + rng.uniform(0.2, 0.5) * (b - a)
                size = rng.uniform(6, 12)
                cv2.rectangle(
                    image,
                    tuple(np.round(p - size).astype(int)),
                    tuple(np.round(p + size).astype(int)),
                    (np.array(downtown) * 0.85).tolist(),
                    -1,
                    cv2.LINE_AA,
                )
        elif rng.random() < 0.12:
            cv2.fillPoly(image, pts, park, cv2.LINE_AA, 4)
            for _ in range(int(rng.integers(6, 12))):
                a = inner[int(rng.integers(0, len(inner)))]
                p = a + rng.uniform(0.15, 0.85) * (ring.mean(axis=0) - a)
                cv2.circle(
                    image,
                    tuple(np.round(p).astype(int)),
                    int(rng.integers(3, 6)),
                    (np.array(park) * 0.7).tolist(),
                    -1,
                    cv2.LINE_AA,
                )
            if rng.random() < 0.3:
                cv2.ellipse(
                    image,
                    tuple(np.round(ring.mean(axis=0)).astype(int)),
                    (10, 6),
                    rng.uniform(0, 180),
                    0,
                    360,
                    water,
                    -1,
                    cv2.LINE_AA,
                )
    # The river: a wide winding band across the map, an edge line, bridges where streets go.
    t = np.linspace(-0.1, 1.1, 200)
    river = np.column_stack(
        [
            t * width,
            height * (0.62 + 0.1 * np.sin(2.4 * np.pi * t + rng.uniform(0, 2 * np.pi)) - 0.18 * t),
        ]
    )
    path = [np.round(river * 16).astype(np.int32)]
    cv2.polylines(image, path, False, blue, 64, cv2.LINE_AA, 4)
    cv2.polylines(image, path, False, water, 58, cv2.LINE_AA, 4)
    for k in range(5):  # bridges: short cased segments across the river
        x = (0.12 + 0.19 * k + rng.uniform(-0.03, 0.03)) * width
        y = np.interp(x, river[:, 0], river[:, 1])
        a, b = (round(x - 6 * s), round(y - 40)), (round(x + 6 * s), round(y + 40))
        cv2.line(image, a, b, casing, 14, cv2.LINE_AA)
        cv2.line(image, a, b, street, 9, cv2.LINE_AA)
    # The avenues (two straight, across the grid) and a ring road, yellow cased in orange.
    lines = []
    for _ in range(2):
        angle = rng.uniform(35, 60) * rng.choice((-1, 1)) + math.degrees(turn)
        d = np.array((math.cos(math.radians(angle)), math.sin(math.radians(angle))))
        at = centre + rng.uniform(-0.2, 0.2, 2) * (width, height)
        lines.append(np.array([at - 2 * width * d, at + 2 * width * d]))
    ring = np.column_stack(
        [
            centre[0] + 0.36 * width * np.cos(np.linspace(0, 2 * np.pi, 120)),
            centre[1] + 0.36 * height * np.sin(np.linspace(0, 2 * np.pi, 120)),
        ]
    )
    lines.append(ring)
    for line in lines:
        cv2.polylines(
            image, [np.round(line * 16).astype(np.int32)], False, avenue_edge, 22, cv2.LINE_AA, 4
        )
    for line in lines:
        cv2.polylines(
            image, [np.round(line * 16).astype(np.int32)], False, avenue, 15, cv2.LINE_AA, 4
        )
    # The railway: black with white dashes, a gentle curve.
    t = np.linspace(0, 1, 60)
    rail = np.column_stack([width * (0.05 + 0.9 * t), height * (0.2 + 0.15 * t * t)])
    cv2.polylines(image, [np.round(rail * 16).astype(np.int32)], False, black, 7, cv2.LINE_AA, 4)
    for k in range(0, len(rail) - 1, 2):
        a, b = rail[k], rail[k + 1]
        cv2.line(
            image,
            tuple(np.round(a).astype(int)),
            tuple(np.round(b).astype(int)),
            street,
            3,
            cv2.LINE_AA,
        )
    # Lettering: street names along some streets (upright), district names spaced out.
    for _ in range(26):
        at = rng.uniform((0.08, 0.08), (0.9, 0.92)) * (width, height)
        name = _random_text(rng, int(rng.integers(5, 10))).replace(" ", "") + " ST"
        _label(image, name, tuple(np.round(at).astype(int)), 0.42, black)
    for _ in range(4):
        at = rng.uniform((0.1, 0.15), (0.75, 0.9)) * (width, height)
        name = " ".join(_random_text(rng, int(rng.integers(5, 8))).replace(" ", ""))
        _label(image, name, tuple(np.round(at).astype(int)), 0.8, (0.45, 0.42, 0.5), 2)
    # Markers: red pins (a disc with a white dot) and blue numbered squares.
    for k in range(14):
        at = tuple(np.round(rng.uniform((0.08, 0.08), (0.92, 0.92)) * (width, height)).astype(int))
        if k % 2:
            cv2.circle(image, at, 10, red, -1, cv2.LINE_AA)
            cv2.circle(image, at, 4, street, -1, cv2.LINE_AA)
        else:
            cv2.rectangle(image, (at[0] - 11, at[1] - 11), (at[0] + 11, at[1] + 11), blue, -1)
            cv2.putText(
                image,
                str(k // 2 + 1),
                (at[0] - 6, at[1] + 6),
                cv2.FONT_HERSHEY_SIMPLEX,
                0.5,
                street,
                2,
                cv2.LINE_AA,
            )
    # The compass rose (upper right), the scale bar and the legend (lower left).
    rose = np.array((0.88 * width, 0.17 * height))
    for k in range(8):
        angle = math.pi / 4 * k - math.pi / 2
        r = 48 if k % 2 == 0 else 26
        tip = rose + r * np.array((math.cos(angle), math.sin(angle)))
        side = rose + 8 * np.array((math.cos(angle + math.pi / 2), math.sin(angle + math.pi / 2)))
        tri = np.array([rose, tip, side])
        cv2.fillPoly(image, [np.round(tri * 16).astype(np.int32)], black, cv2.LINE_AA, 4)
        other = rose - (side - rose)
        tri = np.array([rose, tip, other])
        cv2.fillPoly(image, [np.round(tri * 16).astype(np.int32)], street, cv2.LINE_AA, 4)
        cv2.polylines(image, [np.round(tri * 16).astype(np.int32)], True, black, 1, cv2.LINE_AA, 4)
    cv2.putText(
        image,
        "N",
        (int(rose[0] - 9), int(rose[1] - 54)),
        cv2.FONT_HERSHEY_DUPLEX,
        0.8,
        black,
        2,
        cv2.LINE_AA,
    )
    x0, y0, w, h = int(0.05 * width), int(0.7 * height), int(0.24 * width), int(0.23 * height)
    cv2.rectangle(image, (x0, y0), (x0 + w, y0 + h), street, -1)
    cv2.rectangle(image, (x0, y0), (x0 + w, y0 + h), black, 2)
    for k, colour in enumerate((avenue, park, water, downtown, red)):
        y = y0 + 22 + 30 * k
        if y + 10 > y0 + h:
            break
        cv2.rectangle(image, (x0 + 12, y - 9), (x0 + 44, y + 9), colour, -1)
        cv2.rectangle(image, (x0 + 12, y - 9), (x0 + 44, y + 9), black, 1)
        cv2.putText(
            image,
            _random_text(rng, int(rng.integers(6, 12))),
            (x0 + 54, y + 6),
            cv2.FONT_HERSHEY_SIMPLEX,
            0.5,
            black,
            1,
            cv2.LINE_AA,
        )
    bar = (x0, y0 - 20)
    for k in range(4):
        colour = black if k % 2 == 0 else street
        cv2.rectangle(
            image, (bar[0] + 40 * k, bar[1]), (bar[0] + 40 * (k + 1), bar[1] + 9), colour, -1
        )
    cv2.rectangle(image, bar, (bar[0] + 160, bar[1] + 9), black, 1)
    # The margin with grid references, and thin blue reference lines over the map.
    margin = int(0.045 * width)
    columns, rows = 8, 6
    for k in range(1, columns):
        x = margin + k * (width - 2 * margin) // columns
        cv2.line(image, (x, margin), (x, height - margin), blue, 1, cv2.LINE_AA)
    for k in range(1, rows):
        y = margin + k * (height - 2 * margin) // rows
        cv2.line(image, (margin, y), (width - margin, y), blue, 1, cv2.LINE_AA)
    edge = np.zeros(shape, bool)
    edge[:margin], edge[-margin:], edge[:, :margin], edge[:, -margin:] = True, True, True, True
    image[edge] = MAP_PAPER
    cv2.rectangle(image, (margin, margin), (width - margin, height - margin), black, 3)
    for k in range(columns):
        x = margin + (2 * k + 1) * (width - 2 * margin) // (2 * columns) - 8
        for y in (margin - 12, height - 12):
            cv2.putText(
                image, "ABCDEFGH"[k], (x, y), cv2.FONT_HERSHEY_DUPLEX, 0.7, blue, 2, cv2.LINE_AA
            )
    for k in range(rows):
        y = margin + (2 * k + 1) * (height - 2 * margin) // (2 * rows) + 8
        for x in (12, width - margin + 12):
            cv2.putText(
                image, str(k + 1), (x, y), cv2.FONT_HERSHEY_DUPLEX, 0.7, blue, 2, cv2.LINE_AA
            )
    image *= (1 + 0.02 * fractal_noise(rng, shape, cells=(4, 8, 16)))[..., None].astype(np.float32)
    image *= (1 + 0.012 * rng.standard_normal(shape)).astype(np.float32)[..., None]
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


# --- scenes ---------------------------------------------------------------------------------

PEAS_SIZE = (2.2, 1.6)
PEAS_AT = (0.05, 0.3)  # peas_bag_squeeze: the bag's centre at rest, above the middle
PEAS_ANGLE = 65.0  # the fold's direction (deg from +X: up, a little right)
PEAS_CREASE = 0.06  # the crease's distance from the bag's centre along that direction
PEAS_BAND = 0.2  # folded, the upper part lies 2 * band / pi behind the rest
PEAS_LEFT = 188.0  # the left hand comes in along this direction (deg from +X, bag frame)
PEAS_FOLD = (0.5, 1.45)  # when it starts to fold and to unfold (s)


def build_peas_bag_squeeze(rng, clip):
    studio_lights()
    size = PEAS_SIZE
    sheet = add_sheet(
        peas_bag_print,
        size,
        (88, 64),
        4,
        rng=rng,
        roughness=0.35,
        specular=0.5,
        coat=0.15,
        thickness=0.02,
    )
    angle = math.radians(PEAS_ANGLE)
    d = np.array((math.cos(angle), math.sin(angle)))  # the fold's direction, up
    # The squeeze bows the bag a little along the crease (the crease's ends towards the
    # camera): that does not change where a point is along d, so the fold's limits stay put...
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), diagonal_towards_camera(angle - math.pi / 2))
    bend(sheet, "Bow", origin)
    # ...and folds the upper part back about the crease falling to the right, over a band of
    # PEAS_BAND.
    crease_bend(sheet, "Fold", size, angle, PEAS_CREASE, PEAS_BAND, diagonal_away)
    # The fold (keyed on every frame): fast over (about 0.34 s), slowly back (about 0.8 s).
    # The upper hand pushes the bag down and a little left and turns it 4 deg anticlockwise.
    t = np.arange(clip.frames) / clip.fps
    fold_at, unfold_at = PEAS_FOLD
    fast = fold_and_unfold(t, fold_at, t[-1] + 1.0, paced_fold(7.0, 20.0, 200.0))
    slow = fold_and_unfold(t, -10.0, unfold_at, paced_fold(3.3, 9.0, 30.0))
    fold = np.where(t < unfold_at, fast, slow)
    x0, y0 = PEAS_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bow"].angle', 0): deg(
                [(0.0, 0), (0.4, 0), (0.85, 18), (1.5, 18), (2.3, 0)]
            ),
            ('modifiers["Fold"].angle', 0): list(zip(t, fold, strict=True)),
            ("location", 0): [(0.0, x0), (0.45, x0), (1.0, x0 - 0.05), (2.6, x0 - 0.03)],
            ("location", 1): [
                (0.0, y0),
                (0.45, y0),
                (1.0, y0 - 0.15),
                (1.5, y0 - 0.15),
                (2.6, y0 - 0.06),
            ],
            ("rotation_euler", 2): deg([(0.0, 0), (0.45, 0), (1.0, 4), (2.6, 2)]),
        },
    )
    # The hands come in in front of the bag and move with it: the upper one from above, its
    # fingers (pointing down, a little left) over the upper part and then, following its edge
    # as it folds back (a little inside the edge as seen while in view), onto the crease; the
    # left one from the left, its fingers (pointing right) over the left part below the
    # crease. Where their fingertips are: how far out from the bag's centre along the
    # direction they come in from (for the upper hand, the larger of the keys and the folding
    # edge), and how far across it (bag frame).
    edge = min(size[0] / 2 / abs(d[0]), size[1] / 2 / abs(d[1]))  # the top edge, along d
    folding_edge = PEAS_CREASE + np.maximum((edge - PEAS_CREASE) * np.cos(fold) - 0.25, -0.2)
    upper_tips = [
        (0.0, 4.4),
        (0.1, 4.4),
        (0.45, 0.6),
        (0.85, PEAS_CREASE - 0.2),
        (unfold_at, PEAS_CREASE - 0.2),
        (2.3, 0.6),
        (3.2, 4.4),
    ]
    left_tips = [
        (0.0, 4.4),
        (0.15, 4.4),
        (0.5, 0.8),
        (1.0, 0.72),
        (unfold_at, 0.72),
        (2.2, 0.8),
        (3.1, 4.4),
    ]
    side = math.radians(PEAS_LEFT)
    matrices = object_matrices(clip, sheet.obj)
    for name, reach, out, across in (
        ("UpperHand", np.maximum(eased(t, upper_tips), folding_edge), d, -0.1),
        ("LeftHand", eased(t, left_tips), np.array((math.cos(side), math.sin(side))), 0.1),
    ):
        hand = add_pushing_hand(name, True)
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
    set_back_colour(sheet, (*srgb_to_linear(np.array(BAG_FILM)), 1.0))
    return sheet


MINKY_SIZE = (1.9, 1.5)
MINKY_AT = (-0.05, -0.42)  # minky_tail_swing: the patch's centre at rest, below the middle
MINKY_TILT = 40.0  # the turning axis: deg from the horizontal, falling to the right
MINKY_PIVOT = -0.55  # the axis's distance from the centre, across it (to the upper right)
MINKY_CREASE = 0.12  # where the tail's bend starts, likewise
MINKY_BAND = 0.35  # the length of the tail's bend
MINKY_INSET = 0.22  # the hand's fingertips: how far inside the upper right corner, across


def build_minky_tail_swing(rng, clip):
    studio_lights()
    size = MINKY_SIZE
    tilt = math.radians(MINKY_TILT)
    axis = np.array((math.cos(tilt), -math.sin(tilt)))  # right and down
    across = np.array((math.sin(tilt), math.cos(tilt)))  # up and right, towards the tail
    sheet, pivot = plush_on_pivot(
        rng, minky_dot_plush, size, (76, 60), 0.0, (0.5, 0.35, (0.95, 0.82, 0.84, 1.0))
    )
    # The pivot: the tilted axis through the lower left part; turning about it by a positive
    # angle lifts the part beyond it (to the upper right) towards the camera.
    at = np.array(MINKY_AT) + MINKY_PIVOT * across
    pivot.location = (*at, 0.0)
    pivot.rotation_mode = "AXIS_ANGLE"
    pivot.rotation_axis_angle = (0.0, *axis, 0.0)
    sheet.obj.location = (*(-MINKY_PIVOT * across), 0.0)
    # The soft toy gives where it is held: the tail (the part beyond MINKY_CREASE, towards the
    # upper right corner) bends further towards the camera over a band of MINKY_BAND, so that
    # the patch turns 25 deg and the tail 110 deg, past edge-on, leaning back over the rest.
    angle = math.pi / 2 - tilt  # the direction ``across``
    crease_bend(sheet, "Tail", size, angle, MINKY_CREASE, MINKY_BAND, diagonal_towards_camera)
    # Slowly up (1.5 s), a short hold, fast back (0.6 s), drifting up and a little right.
    up, top, back = 0.3, 1.8, 1.95
    clip.keyframe(
        pivot,
        {
            ("rotation_axis_angle", 0): deg([(0.0, 0), (up, 0), (top, 25), (back, 25), (2.55, 0)]),
            ("location", 0): [(0.0, at[0]), (up, at[0]), (1.9, at[0] + 0.08), (3.2, at[0] + 0.02)],
            ("location", 1): [(0.0, at[1]), (up, at[1]), (1.9, at[1] + 0.17), (3.2, at[1] + 0.04)],
        },
    )
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Tail"].angle', 0): deg(
                [(0.0, 0), (up, 0), (top, 85), (back, 85), (2.55, 0)]
            )
        },
    )
    # The hand holds the upper right corner (the tail's end): its fingers (pointing down and
    # right, along the axis) lie over the corner MINKY_INSET inside it, the back of the hand
    # away from the painted side; moved with the corner on every frame, it rolls about its
    # forearm (which stays along the axis, out to the upper left, above the patch's top edge)
    # as the tail rises. It comes in along the axis from the upper left and leaves the same way.
    grids = sheet_frames(clip, sheet)
    t = np.arange(clip.frames) / clip.fps
    away = eased(t, [(0.0, 3.5), (0.05, 3.5), (0.3, 0.0), (2.75, 0.0), (3.25, 3.5)])
    hand = add_pushing_hand("Hand", True)
    poses = []
    for grid, out in zip(grids, away, strict=True):
        corner = grid[0, -1]
        along_x = corner - grid[0, -3]
        along_y = corner - grid[2, -1]
        along_x, along_y = along_x / np.linalg.norm(along_x), along_y / np.linalg.norm(along_y)
        normal = np.cross(along_x, along_y)
        a = axis[0] * along_x + axis[1] * along_y
        n = across[0] * along_x + across[1] * along_y
        tips = corner - out * a - MINKY_INSET * n + 0.13 * normal
        poses.append(hand_pose(tips, a, normal))
    key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, ROSE_FELT)
    return sheet


MAP_SIZE = (2.4, 2.0)
MAP_AT = (0.45, -0.2)  # city_map_foldup: the map's centre at rest, right of and below
MAP_ANGLE = -95.0  # the fold's direction (deg from +X: down, a little left)
MAP_CREASE = 0.42  # the crease's distance from the centre along that direction
MAP_BAND = 0.16  # folded, the flap lies 2 * band / pi in front
MAP_LIFT = 0.5  # how far the map comes towards the camera while it unfolds


def build_city_map_foldup(rng, clip):
    studio_lights()
    size = MAP_SIZE
    sheet = add_sheet(
        street_map,
        size,
        (72, 60),
        4,
        rng=rng,
        roughness=0.7,
        specular=0.3,
        thickness=0.006,
    )
    # The bottom part folds up over the rest, towards the camera, about a crease falling 5 deg
    # to the right; folded, it lies about 0.1 in front of the rest, its plain back to the
    # camera.
    angle = math.radians(MAP_ANGLE)
    crease_bend(sheet, "Fold", size, angle, MAP_CREASE, MAP_BAND, diagonal_towards_camera)
    # In two steps: up to standing (92 deg) in 0.35 s, slowly on to 100 deg over 0.3 s, over
    # to flat in 0.35 s; held 0.45 s, unfolded in one go (0.85 s). Meanwhile the map comes
    # MAP_LIFT nearer the camera (about 9 % larger), drifts left and up and turns 6 deg
    # clockwise.
    x0, y0 = MAP_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): deg(
                [
                    (0.0, 0),
                    (0.3, 0),
                    (0.65, 92),
                    (0.95, 100),
                    (1.3, 180),
                    (1.75, 180),
                    (2.6, 0),
                ]
            ),
            ("location", 0): [(0.0, x0), (1.0, x0), (2.9, x0 - 0.14)],
            ("location", 1): [(0.0, y0), (1.0, y0), (2.9, y0 + 0.08)],
            ("location", 2): [(0.0, 0.0), (1.3, 0.0), (2.9, MAP_LIFT)],
            ("rotation_euler", 2): deg([(0.0, 0), (1.0, 0), (2.9, -6)]),
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(MAP_PAPER)), 1.0))
    return sheet


HELDOUT_FOLDS6 = [
    Clip(
        "peas_bag_squeeze",
        100,
        30,
        "two hands, in from above and from the left, squeeze a glossy bag of frozen peas lying "
        "above the middle: it bows and its upper part (46 %) folds back behind the rest in "
        "half, about a crease falling 25 deg to the right, fast (0.34 s), while the upper hand "
        "pushes it about 16 px down and turns it 4 deg; holds 0.6 s with the upper hand over "
        "the crease and the left hand over the left part, unfolds slowly (0.8 s); the hands "
        "leave",
        build_peas_bag_squeeze,
    ),
    Clip(
        "minky_tail_swing",
        100,
        30,
        "a furry, low-contrast dusty pink minky plush patch with raised dots, below the "
        "middle, held by a hand at its upper right corner (its tail), is lifted towards the "
        "camera slowly (1.5 s) about an axis falling 40 deg to the right through its lower "
        "left part while it drifts about 18 px up: the patch turns 25 deg, its upper right "
        "part (41 %) on to 110 deg, past edge-on (painted side turned away, its back leaning "
        "over the rest); holds 0.15 s, turns back fast (0.6 s); the hand leaves",
        build_minky_tail_swing,
    ),
    Clip(
        "city_map_foldup",
        100,
        30,
        "the bottom 29 % of a printed city street map folds up over the rest by 180 deg, "
        "towards the camera, about a crease falling 5 deg to the right (its plain back covers "
        "about 19 % more of the print), in two steps (up to standing in 0.35 s, a near pause, "
        "over in 0.35 s); holds 0.45 s and unfolds (0.85 s) while the map comes nearer the "
        "camera (about 9 % larger), drifts about 15 px left and 8 px up and turns 6 deg",
        build_city_map_foldup,
    ),
]


README_HELDOUT_FOLDS6 = (
    """# Held-out clips of folds, sixth batch

Clips for checking that the tracker generalises to folds (issue 22): never tune it on these;
they are to be measured once, as held-out. The tracker was tuned on the fold clips of
[`../folds`](../folds/README.md); like the first five held-out batches
([`../heldout_folds`](../heldout_folds/README.md),
[`../heldout_folds2`](../heldout_folds2/README.md),
[`../heldout_folds3`](../heldout_folds3/README.md),
[`../heldout_folds4`](../heldout_folds4/README.md) and
[`../heldout_folds5`](../heldout_folds5/README.md)) these show the same kinds of motion (a
soft bag squeezed until part of it folds back, a soft patch turned past edge-on by its tail, a
part folded over the rest) with paint, axes, speeds and places that no earlier batch has: a
glossy bag of frozen peas above the middle folded back in half, fast, by hands that come in
from above and from the left, and unfolded slowly; a dusty pink minky plush lifted by its upper
right corner towards the camera about an axis falling 40 deg to the right, slowly, and let back
fast; the bottom part of a city street map folded up over the rest in two steps and unfolded
while the map comes nearer the camera. Rendered with Blender {blender} (the `bpy` module,
headless) by [`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes and
paint in `scripts/hardclips/heldout_folds6.py`) from a fixed seed, so the same command makes
the same scenes, truth and outlines; it makes them only when named, apart from every other
clip:

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \\
        --out samples/heldout_folds6 --only {names}

Keep them out of `samples/folds` and `samples/heldout_folds` to `samples/heldout_folds5`.
Check them with `.venv/bin/python scripts/check_hard_clips.py --dir samples/heldout_folds6`
(statistics, and contact sheets in `/tmp/hard_check/`).

"""
    + FOLD_FILES
)
