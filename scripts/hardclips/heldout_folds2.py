"""A second batch of held-out clips of folds: new paint, new folds and turns, never tuned on.

The tracker was tuned on the fold clips of ``folds`` (``samples/folds``); the first held-out
batch (``heldout_folds``, ``samples/heldout_folds``) and this one check that it generalises and
are never to be tuned on. These were made after the tracker's last change. ``HELDOUT_FOLDS2``
lists them. ``render_hard_clips.py`` makes them only when asked by name, into a folder of
their own (``samples/heldout_folds2``), apart from every other clip::

    .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds2 --only NAME ...

Each writes the files of a single-sheet hard clip (``NAME.mp4``, ``NAME.json``,
``NAME_truth.npz``) with the conventions of ``folds``: frame 0 flat and square to the camera,
at rest for three frames; every crease runs through the outlined region; the folds are
SimpleDeform bends over a band at the crease (``fold_limits``), so a folded part never passes
through the rest. The paint is here (``carton_print``, ``teddy_plush``, ``poster_print``),
in the style of ``heldout_textures``.

``box_side_squeeze``
    The printed face of a soft cereal carton (``carton_print``: a sunburst, a big wordmark, a
    bowl of flakes, a badge, a barcode) is squeezed by two hands that come in from the left and
    the right in front of it: it bows a little (its top and bottom edges towards the camera)
    and its LEFT part (``BOX_LEFT``, 42 %) folds back behind the rest along a vertical crease
    left of the centre, fast (in 0.4 s, from 0.45 s; past about 100 deg it is out of sight),
    while the hands push the whole carton about 40 px down and right and turn it 3 deg; it
    holds folded for 0.5 s with the left hand's fingers over the crease and the right hand's
    over the right edge, unfolds (from 1.35 s, flat by 1.75 s) and the hands leave.
``plush_nod``
    A furry, low-contrast plush patch, honey tan with soft cocoa patches (``teddy_plush``, its
    hair combed up and down, unlike ``folds.fur`` and ``heldout_folds.plush``; a sheen
    material, dark brown felt behind), held at its bottom edge by a hand that comes in from
    below: it nods away from the camera about a horizontal axis (``Pivot``, through its bottom
    edge; the patch tilts 15 deg) and being soft its top part (above ``NOD_CREASE``, 55 %)
    bends a further 85 deg over a band, to 100 deg (past edge-on: its painted side turns away,
    ``visible`` false). It turns in 1.0 s, holds 0.3 s, turns back while it drifts a little,
    and the hand lets go.
``paper_half_fold``
    A printed poster sheet of paper (``poster_print``: photos of soft blobs, a headline,
    columns of text lines; its back is plain paper): its left part (``PAPER_LEFT``, 38 %: as
    near the half as keeps 0.4 of the print in sight) folds 180 deg over the rest, towards
    the camera, about a vertical crease left of the middle, in a soft loop as paper does when
    its crease is not pressed (over a band of 0.5; the flap lies about 0.32 in front), its
    plain back covering about 22 % more of the print, right of the crease; it
    holds 0.4 s and unfolds while the sheet turns 5 deg in its plane and back, and drifts.
"""

import math

import bpy  # noqa: F401 - first: mathutils comes with it

# isort: split
import cv2
import numpy as np
from foam_paint import smooth_noise  # scripts/ is on sys.path when a script runs
from hard_textures import _colour, _random_text, fractal_noise

from hardclips.folds import (
    BEND_Y_TOWARDS_CAMERA,
    FOLD_FILES,
    HAND_REACH,
    add_pushing_hand,
    fold_and_unfold,
    fold_limits,
    paced_fold,
    plush_on_pivot,
    set_back_colour,
)
from hardclips.heldout_folds import (
    BEND_LEFT_AWAY,
    HAND_DEPTH,
    diagonal_towards_camera,
    two_tone_plush,
)
from hardclips.materials import studio_lights
from hardclips.scene import Clip
from hardclips.sheet import (
    BEND_Y_AWAY,
    add_sheet,
    bend,
    deform_origin,
    deg,
    finish_sheet,
)
from hardclips.video import srgb_to_linear

# --- paint ----------------------------------------------------------------------------------

CARTON_INK = np.array(
    [
        (0.98, 0.96, 0.90),  # cream
        (0.98, 0.80, 0.10),  # yolk yellow
        (0.85, 0.12, 0.10),  # red
        (0.10, 0.35, 0.70),  # blue
        (0.08, 0.07, 0.08),  # black
        (0.25, 0.65, 0.25),  # green
    ]
)
CARTON_BOARD = (0.66, 0.60, 0.50)  # the carton's unprinted grey board: its back and rim (sRGB)


def _barcode(image, rng, corner, size):
    """A white panel with an EAN-like barcode and its digits, its top left at ``corner``."""
    x0, y0 = corner
    w, h = size
    cv2.rectangle(image, (x0, y0), (x0 + w, y0 + h), (1.0, 1.0, 1.0), -1)
    x, bottom = x0 + 12, y0 + h - 30
    while x < x0 + w - 16:
        bar = int(rng.integers(2, 9))
        guard = x < x0 + 20 or abs(x - (x0 + w // 2)) < 5 or x > x0 + w - 26
        cv2.rectangle(image, (x, y0 + 10), (x + bar - 1, bottom + (12 if guard else 0)), 0.0, -1)
        x += bar + int(rng.integers(2, 7))
    digits = "".join(str(d) for d in rng.integers(0, 10, 13))
    cv2.putText(
        image,
        digits,
        (x0 + 8, y0 + h - 6),
        cv2.FONT_HERSHEY_SIMPLEX,
        0.7,
        (0, 0, 0),
        2,
        cv2.LINE_AA,
    )


def carton_print(rng, width, height):
    """The printed face of a cereal carton: sunburst, wordmark, a bowl of flakes, a barcode.

    A red and orange sunburst from a point low on the right, a huge outlined wordmark on a
    blue band across the top, a bowl of flakes and berries, a round badge, panels of small
    print, a barcode on a white panel low on the left; coated board with a faint grain.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    sun = np.array((rng.uniform(0.6, 0.75) * width, rng.uniform(0.7, 0.85) * height))
    angle = np.arctan2(ys - sun[1], xs - sun[0])
    rays = (np.floor((angle + np.pi) / (2 * np.pi) * 28) % 2)[..., None]  # (H, W, 1)
    glow = np.clip(np.hypot(xs - sun[0], ys - sun[1]) / width, 0, 1)[..., None]
    red, orange = np.array((0.88, 0.20, 0.10)), np.array((0.97, 0.55, 0.12))
    image = (rays * red + (1 - rays) * orange) * (1.05 - 0.35 * glow)
    image = np.ascontiguousarray(image.astype(np.float32))
    # A blue band across the top with the wordmark in huge outlined letters.
    band = np.array([(0, 0), (width, 0), (width, 0.30 * height), (0, 0.38 * height)])
    cv2.fillPoly(image, [np.round(band).astype(np.int32)], CARTON_INK[3].tolist(), cv2.LINE_AA)
    word = _random_text(rng, 6).replace(" ", "") or "FLAKES"
    org = (int(0.03 * width), int(0.30 * height))
    for colour, thickness in ((CARTON_INK[4], 26), (CARTON_INK[0], 16), (CARTON_INK[1], 7)):
        cv2.putText(
            image, word, org, cv2.FONT_HERSHEY_TRIPLEX, 6.0, colour.tolist(), thickness, cv2.LINE_AA
        )
    tagline = _random_text(rng, 18)
    cv2.putText(
        image,
        tagline,
        (int(0.05 * width), int(0.36 * height)),
        cv2.FONT_HERSHEY_DUPLEX,
        1.1,
        CARTON_INK[0].tolist(),
        2,
        cv2.LINE_AA,
    )
    # A bowl of flakes and berries, low in the middle.
    bowl = (int(rng.uniform(0.45, 0.55) * width), int(0.72 * height))
    rx, ry = int(0.2 * width), int(0.07 * height)
    cv2.ellipse(image, bowl, (rx, int(2.6 * ry)), 0, 0, 180, (0.95, 0.95, 0.97), -1, cv2.LINE_AA)
    cv2.ellipse(image, bowl, (rx, int(2.6 * ry)), 0, 0, 180, CARTON_INK[3].tolist(), 8)
    cv2.ellipse(image, bowl, (rx, ry), 0, 0, 360, (0.92, 0.90, 0.85), -1, cv2.LINE_AA)
    for _ in range(70):  # flakes: irregular golden polygons heaped on the milk
        t = rng.uniform(0, 2 * np.pi)
        r = np.sqrt(rng.uniform(0, 1))
        c = np.array((bowl[0] + 0.95 * rx * r * np.cos(t), bowl[1] - 0.9 * ry * abs(np.sin(t))))
        c[1] -= rng.uniform(0, 0.12 * height) * (1 - r)
        n = int(rng.integers(5, 8))
        turn = rng.uniform(0, 2 * np.pi)
        radii = rng.uniform(10, 22, n)
        angles = turn + 2 * np.pi * np.arange(n) / n
        corners = c + np.column_stack([np.cos(angles), np.sin(angles)]) * radii[:, None]
        tone = rng.uniform(0.8, 1.05)
        colour = tuple(float(v) for v in np.clip(np.array((0.90, 0.62, 0.22)) * tone, 0, 1))
        cv2.fillPoly(image, [np.round(corners).astype(np.int32)], colour, cv2.LINE_AA)
        cv2.polylines(image, [np.round(corners).astype(np.int32)], True, (0.55, 0.32, 0.1), 1)
    for _ in range(9):  # berries
        c = (int(bowl[0] + rng.uniform(-0.8, 0.8) * rx), int(bowl[1] - rng.uniform(0, 1.6) * ry))
        cv2.circle(image, c, int(rng.integers(10, 16)), (0.35, 0.10, 0.35), -1, cv2.LINE_AA)
        cv2.circle(image, (c[0] - 4, c[1] - 4), 3, (0.9, 0.8, 0.95), -1, cv2.LINE_AA)
    # A round badge with a number, upper right under the band.
    centre = (int(rng.uniform(0.78, 0.88) * width), int(0.5 * height))
    cv2.circle(image, centre, 70, CARTON_INK[1].tolist(), -1, cv2.LINE_AA)
    cv2.circle(image, centre, 70, CARTON_INK[2].tolist(), 6, cv2.LINE_AA)
    cv2.circle(image, centre, 58, CARTON_INK[2].tolist(), 2, cv2.LINE_AA)
    number = f"{int(rng.integers(10, 60))}%"
    cv2.putText(
        image,
        number,
        (centre[0] - 52, centre[1] + 16),
        cv2.FONT_HERSHEY_DUPLEX,
        1.6,
        CARTON_INK[4].tolist(),
        4,
        cv2.LINE_AA,
    )
    # Green panels of small print on the left, and the barcode low on the left.
    x0, y0 = int(0.03 * width), int(0.42 * height)
    cv2.rectangle(
        image, (x0, y0), (x0 + int(0.26 * width), y0 + int(0.26 * height)), (0.2, 0.5, 0.2), -1
    )
    for k in range(9):
        text = _random_text(rng, int(rng.integers(10, 18)))
        org = (x0 + 8, y0 + 24 + 20 * k)
        cv2.putText(image, text, org, cv2.FONT_HERSHEY_SIMPLEX, 0.55, CARTON_INK[0].tolist(), 1)
    _barcode(image, rng, (int(0.05 * width), int(0.74 * height)), (int(0.2 * width), 120))
    for _ in range(14):  # stars of sparkle over the sunburst
        c = (int(rng.uniform(0, width)), int(rng.uniform(0.4, 1.0) * height))
        size = int(rng.integers(6, 16))
        cv2.line(image, (c[0] - size, c[1]), (c[0] + size, c[1]), CARTON_INK[0].tolist(), 3)
        cv2.line(image, (c[0], c[1] - size), (c[0], c[1] + size), CARTON_INK[0].tolist(), 3)
    # Coated board: a faint grain and uneven ink.
    image *= (1 + 0.03 * fractal_noise(rng, shape, cells=(4, 8, 16)))[..., None].astype(np.float32)
    image *= (1 + 0.02 * rng.standard_normal(shape)).astype(np.float32)[..., None]
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


def teddy_plush(rng, width, height):
    """A honey tan plush with soft cocoa patches (see :func:`.heldout_folds.two_tone_plush`).

    Its hair runs close to the vertical (in the texture), unlike ``folds.fur``'s and
    ``heldout_folds.plush``'s.
    """
    return two_tone_plush(
        rng,
        width,
        height,
        fur=(0.72, 0.56, 0.36),
        patch=(0.55, 0.40, 0.27),
        patches=((3, 6, 12), 1.6, 10),
        tufts=(23, (82.0, 101.0), 0.06),
        fine=(13, (86.0, 97.0)),
    )


POSTER_INK = np.array(
    [
        (0.12, 0.12, 0.16),
        (0.75, 0.15, 0.30),
        (0.10, 0.45, 0.55),
        (0.45, 0.45, 0.50),
        (0.90, 0.55, 0.10),
    ]
)
PAPER = (0.93, 0.92, 0.88)  # the poster's paper: its margins and its plain back (sRGB)


def _blob_photo(rng, height, width):
    """A photo of soft blobs: a graded sky, hazy hills and blurred lights. (H, W, 3) float32."""
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    top, bottom = rng.uniform(0.2, 0.7, 3), rng.uniform(0.3, 0.9, 3)
    fade = (ys / height)[..., None]
    image = (1 - fade) * top + fade * bottom
    for k in range(3):  # hills: soft-edged bands under a wavy skyline, darker towards the front
        level = (0.35 + 0.2 * k) * height + 0.12 * height * smooth_noise(rng, (1, width), 4)[0]
        edge = np.clip((ys - level) / 6.0, 0, 1)[..., None]
        image = (1 - edge) * image + edge * (rng.uniform(0.15, 0.6, 3) * (1 - 0.2 * k))
    for _ in range(int(rng.integers(12, 20))):  # blurred lights and blobs
        cx, cy = rng.uniform(0, width), rng.uniform(0, height)
        r = rng.uniform(0.04, 0.16) * min(width, height)
        d = np.hypot((xs - cx) / r, (ys - cy) / (r * rng.uniform(0.6, 1.4)))
        weight = np.clip(1.6 - 1.2 * d, 0, 1)[..., None] * rng.uniform(0.4, 0.9)
        image = (1 - weight) * image + weight * rng.uniform(0.1, 1.0, 3)
    image = image * (1 + 0.05 * fractal_noise(rng, (height, width), cells=(8, 16, 32)))[..., None]
    return cv2.GaussianBlur(image.astype(np.float32), (0, 0), 2.5)


def poster_print(rng, width, height):
    """A printed poster: two photos of soft blobs, a headline, columns of text lines, rules.

    A big photo on the upper left, a smaller one on the right, a headline in two sizes, three
    columns of small text lines, coloured rules and a page number, on off-white paper.
    """
    image = np.empty((height, width, 3), np.float32)
    image[:] = PAPER

    def place(x0, y0, x1, y1):
        x0, y0, x1, y1 = (int(v) for v in (x0 * width, y0 * height, x1 * width, y1 * height))
        image[y0:y1, x0:x1] = _blob_photo(rng, y1 - y0, x1 - x0)
        cv2.rectangle(image, (x0, y0), (x1 - 1, y1 - 1), POSTER_INK[0].tolist(), 2)

    place(0.04, 0.05, 0.56, 0.56)  # the big photo
    place(0.62, 0.05, 0.96, 0.34)  # a smaller one, on the right
    headline = _random_text(rng, 8).replace(" ", "")
    cv2.putText(
        image,
        headline,
        (int(0.04 * width), int(0.68 * height)),
        cv2.FONT_HERSHEY_DUPLEX,
        3.2,
        POSTER_INK[1].tolist(),
        9,
        cv2.LINE_AA,
    )
    cv2.line(
        image,
        (int(0.04 * width), int(0.71 * height)),
        (int(0.96 * width), int(0.71 * height)),
        POSTER_INK[2].tolist(),
        5,
    )
    columns = [(0.04, 0.74, 0.95), (0.36, 0.74, 0.95), (0.68, 0.74, 0.95), (0.62, 0.45, 0.56)]
    for x, top, bottom in columns:  # columns of text lines, ragged right
        for y in np.arange(top, bottom, 0.028):
            text = _random_text(rng, int(rng.integers(14, 24)))
            org = (int(x * width), int(y * height))
            colour = _colour(POSTER_INK[:4], rng)
            cv2.putText(image, text, org, cv2.FONT_HERSHEY_SIMPLEX, 0.55, colour, 1, cv2.LINE_AA)
    subhead = _random_text(rng, 12)
    cv2.putText(
        image,
        subhead,
        (int(0.62 * width), int(0.41 * height)),
        cv2.FONT_HERSHEY_TRIPLEX,
        1.3,
        POSTER_INK[2].tolist(),
        2,
        cv2.LINE_AA,
    )
    for k in range(3):  # coloured squares and rules under the smaller photo's text
        y = int((0.575 + 0.04 * k) * height)
        colour = POSTER_INK[1 + k].tolist()
        x0 = int(0.62 * width)
        cv2.rectangle(image, (x0, y), (x0 + 20, y + 20), colour, -1)
        cv2.line(image, (x0 + 34, y + 10), (int((0.8 + 0.05 * k) * width), y + 10), colour, 4)
    cv2.putText(
        image,
        str(int(rng.integers(2, 99))),
        (int(0.92 * width), int(0.985 * height)),
        cv2.FONT_HERSHEY_SIMPLEX,
        0.9,
        POSTER_INK[0].tolist(),
        2,
        cv2.LINE_AA,
    )
    image *= (1 + 0.025 * rng.standard_normal((height, width))).astype(np.float32)[..., None]
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


# --- scenes ---------------------------------------------------------------------------------

BOX_LEFT = 0.42  # box_side_squeeze: the part of the carton's width that folds back
BOX_SIZE = (2.4, 1.6)
BOX_CREASE = -BOX_SIZE[0] / 2 + BOX_LEFT * BOX_SIZE[0]  # the crease's x, left of the centre


def build_box_side_squeeze(rng, clip):
    studio_lights()
    size = BOX_SIZE
    sheet = add_sheet(
        carton_print,
        size,
        (96, 64),
        4,
        rng=rng,
        roughness=0.5,
        specular=0.4,
        thickness=0.03,
    )
    # The squeeze bows the carton a little (top and bottom edges towards the camera): the bow
    # does not change x, so the fold's limits stay put...
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), BEND_Y_TOWARDS_CAMERA)
    bend(sheet, "Bow", origin)
    # ...and folds its left part back about a vertical crease at BOX_CREASE, over a band of 0.25
    # (folded, it lies about 0.16 behind the front part). The bend's local X runs left (world
    # -X), so the crease lies -BOX_CREASE along it from the centre.
    origin = deform_origin(sheet, (BOX_CREASE, 0.0, 0.0), BEND_LEFT_AWAY)
    bend(sheet, "Fold", origin, limits=fold_limits(size[0], -BOX_CREASE, 0.25))
    # The fold (keyed on every frame), fast: 90 deg 0.23 s after it starts at 0.45 s, folded
    # flat 0.4 s after it starts, its edge at a steady pace while in view; unfolds from 1.35 s,
    # back flat by 1.75 s. The hands push the carton down and right (about 40 px) and turn it
    # a few degrees, so the crease is only roughly vertical.
    t = np.arange(clip.frames) / clip.fps
    fold = fold_and_unfold(t, 0.45, 1.35, paced_fold(6.0, 17.0, 130.0))
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bow"].angle', 0): deg(
                [(0.0, 0), (0.35, 0), (0.8, 22), (1.45, 22), (2.1, 0)]
            ),
            ('modifiers["Fold"].angle', 0): list(zip(t, fold, strict=True)),
            ("location", 0): [
                (0.0, 0),
                (0.35, 0),
                (0.95, 0.3),
                (1.5, 0.3),
                (2.4, 0.12),
                (3.3, 0.08),
            ],
            ("location", 1): [
                (0.0, 0),
                (0.35, 0),
                (1.0, -0.22),
                (1.6, -0.22),
                (2.6, -0.1),
                (3.3, -0.08),
            ],
            ("rotation_euler", 2): deg([(0.0, 0), (0.35, 0), (1.0, 3), (2.2, -1), (3.3, 0)]),
        },
    )
    # The hands, in from outside the frame: the left one's fingers over the left edge and then,
    # following it as it folds back, over the crease; the right one's over the right edge.
    # They press while it folds, hold, and leave as it unfolds. Keyed where their fingertips
    # are (the palm's centre is HAND_REACH behind them, left for the left hand, right for the
    # right one).
    left = add_pushing_hand("LeftHand", True)
    right = add_pushing_hand("RightHand", False)
    left.location = right.location = (0.0, 0.0, HAND_DEPTH)
    edge = size[0] / 2
    crease = BOX_CREASE + 0.3  # where the crease is once the carton is pushed right
    left_tips = [
        (0.0, -4.1),
        (0.1, -4.1),
        (0.45, -edge + 0.3),
        (0.56, -0.55),
        (0.67, BOX_CREASE + 0.15 - 0.05),  # at the folding edge, 90 deg, pushed half way
        (0.85, crease + 0.12),
        (1.35, crease + 0.12),
        (1.6, -0.5),
        (2.5, -4.1),
    ]
    right_tips = [
        (0.0, 4.1),
        (0.1, 4.1),
        (0.45, edge - 0.3),
        (0.95, edge + 0.3 - 0.4),
        (1.5, edge + 0.3 - 0.4),
        (2.2, edge + 0.12 - 0.2),
        (3.0, 4.1),
    ]
    clip.keyframe(
        left,
        {
            ("location", 0): [(s, x - HAND_REACH) for s, x in left_tips],
            ("location", 1): [(0.0, 0.12), (0.45, 0.12), (1.0, -0.05), (2.3, 0.05)],
        },
    )
    clip.keyframe(
        right,
        {
            ("location", 0): [(s, x + HAND_REACH) for s, x in right_tips],
            ("location", 1): [(0.0, -0.2), (0.45, -0.2), (1.0, -0.42), (2.2, -0.25)],
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(CARTON_BOARD)), 1.0))
    return sheet


NOD_SIZE = (1.9, 1.6)
NOD_CREASE = -0.08  # plush_nod: where the top part's bend starts, from the sheet's centre
NOD_PIVOT = -NOD_SIZE[1] / 2  # the turning axis: the bottom edge, where it is held
COCOA_FELT = (0.10, 0.06, 0.035, 1.0)  # plush_nod's back and rim (linear RGB)


def build_plush_nod(rng, clip):
    studio_lights()
    size = NOD_SIZE
    # The pivot: a horizontal axis along the bottom edge, where the hand holds it; the patch
    # turns about it, its top going away from the camera, while the pivot drifts a little.
    sheet, pivot = plush_on_pivot(
        rng, teddy_plush, size, (76, 64), 0.0, (0.45, 0.45, (0.95, 0.8, 0.6, 1.0))
    )
    pivot.location = (0.0, NOD_PIVOT, 0.0)
    sheet.obj.location = (0.0, -NOD_PIVOT, 0.0)
    # The soft plush gives: the part above NOD_CREASE (55 %) bends further away over a band of
    # 0.25, so that the held part turns 15 deg and the top part 100 deg.
    origin = deform_origin(sheet, (0.0, NOD_CREASE, 0.0), BEND_Y_AWAY)
    bend(sheet, "Nod", origin, limits=fold_limits(size[1], NOD_CREASE, 0.25))
    clip.keyframe(
        pivot,
        {
            ("rotation_euler", 0): deg([(0.0, 0), (0.35, 0), (1.35, -15), (1.65, -15), (2.65, 0)]),
            ("rotation_euler", 2): deg([(0.0, 0), (0.35, 0), (1.5, 3), (3.2, 1)]),
            ("location", 0): [(0.0, 0), (0.35, 0), (1.5, 0.15), (3.2, 0.05)],
            ("location", 1): [
                (0.0, NOD_PIVOT),
                (0.35, NOD_PIVOT),
                (1.4, NOD_PIVOT + 0.08),
                (3.2, NOD_PIVOT + 0.02),
            ],
        },
    )
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Nod"].angle', 0): deg(
                [(0.0, 0), (0.35, 0), (1.35, 85), (1.65, 85), (2.65, 0)]
            )
        },
    )
    # The hand, in from below the frame before the nod: its fingers over the bottom edge,
    # holding it; it follows the drift and lets go at the end. Keyed where its fingertips are
    # (the palm's centre is HAND_REACH below them).
    hand = add_pushing_hand("Hand", True)
    hand.rotation_euler = (0.0, 0.0, 0.0)  # fingers pointing up
    hand.location = (0.0, 0.0, HAND_DEPTH)
    tips = [
        (0.0, -3.7),
        (0.1, -3.7),
        (0.35, NOD_PIVOT + 0.22),
        (1.4, NOD_PIVOT + 0.08 + 0.22),
        (2.7, NOD_PIVOT + 0.03 + 0.2),
        (3.2, -2.6),
    ]
    clip.keyframe(
        hand,
        {
            ("location", 1): [(s, y - HAND_REACH) for s, y in tips],
            ("location", 0): [(0.0, -0.15), (0.35, -0.15), (1.5, 0.0), (3.2, -0.1)],
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, COCOA_FELT)
    return sheet


PAPER_SIZE = (3.0, 2.0)
PAPER_LEFT = 0.38  # paper_half_fold: the part of the sheet's width that folds over
PAPER_CREASE = -PAPER_SIZE[0] / 2 + PAPER_LEFT * PAPER_SIZE[0]  # the crease's x
PAPER_BAND = 0.5  # the loop at the crease: folded, the flap lies 2 * band / pi in front


def build_paper_half_fold(rng, clip):
    studio_lights()
    size = PAPER_SIZE
    sheet = add_sheet(
        poster_print,
        size,
        (96, 64),
        4,
        rng=rng,
        roughness=0.7,
        specular=0.3,
        thickness=0.01,
    )
    # The left part folds towards the camera about a vertical crease at PAPER_CREASE, in a
    # loop (over a band of PAPER_BAND): folded, it lies about 0.32 in front of the rest, its
    # plain back to the camera. The bend's local X runs left (world -X).
    origin = deform_origin(sheet, (PAPER_CREASE, 0.0, 0.0), diagonal_towards_camera(math.pi))
    bend(sheet, "Fold", origin, limits=fold_limits(size[0], -PAPER_CREASE, PAPER_BAND))
    # Slower while the flap still shows its print (to 95 deg), faster after; the sheet turns 5
    # deg in its plane and back meanwhile, and drifts.
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): deg(
                [(0.0, 0), (0.1, 0), (0.8, 95), (1.15, 180), (1.55, 180), (1.95, 95), (2.6, 0)]
            ),
            ("rotation_euler", 2): deg([(0.0, 0), (0.1, 0), (1.3, 5), (2.8, -1), (3.3, 0)]),
            ("location", 0): [(0.0, 0), (0.1, 0), (1.4, 0.1), (3.3, 0.03)],
            ("location", 1): [(0.0, 0), (0.1, 0), (1.5, -0.08), (3.3, -0.02)],
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(PAPER)), 1.0))
    return sheet


HELDOUT_FOLDS2 = [
    Clip(
        "box_side_squeeze",
        100,
        30,
        "two hands squeeze the printed face of a soft cereal carton from the left and right: it "
        "bows and its left 42 % folds back behind the rest along a roughly vertical crease left "
        "of the centre (in 0.4 s) while it is pushed about 40 px down and right, holds 0.5 s "
        "with the hands over the crease and the right edge, unfolds; the hands leave",
        build_box_side_squeeze,
    ),
    Clip(
        "plush_nod",
        96,
        30,
        "a furry, low-contrast honey and cocoa plush patch, held at its bottom edge by a hand, "
        "nods away from the camera about a horizontal axis in 1.0 s: the held part tilts 15 "
        "deg, the top 55 % bends on to 100 deg, past edge-on (painted side turned away); holds "
        "0.3 s, turns back while it drifts; the hand lets go",
        build_plush_nod,
    ),
    Clip(
        "paper_half_fold",
        100,
        30,
        "the left 38 % of a printed poster sheet folds 180 deg over the rest about a vertical "
        "crease left of the middle, towards the camera, in a soft loop (its plain back covers "
        "about 22 % more of the print), holds 0.4 s and unfolds while the sheet turns 5 deg in "
        "its plane and back",
        build_paper_half_fold,
    ),
]


README_HELDOUT_FOLDS2 = (
    """# Held-out clips of folds, second batch

Clips for checking that the tracker generalises to folds: never tune it on these. They were
made after the tracker's last change, and are to be measured once, as held-out. The tracker
was tuned on the fold clips of [`../folds`](../folds/README.md); like the first held-out batch
([`../heldout_folds`](../heldout_folds/README.md)) these show the same kinds of motion (a sheet
squeezed until part of it folds back, a soft patch turned past edge-on, a part folded over the
rest) with paint and motion that neither earlier batch has: a fold back left of the centre,
faster, while the sheet is pushed along; a nod about a horizontal axis; a fold over of the
left part in a soft loop while the sheet turns in its plane. Rendered with Blender {blender}
(the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes and paint in
`scripts/hardclips/heldout_folds2.py`) from a fixed seed, so the same command makes the same
scenes, truth and outlines; it makes them only when named, apart from every other clip:

    .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds2 --only {names}

Keep them out of `samples/folds` and `samples/heldout_folds`. Check them with
`.venv/bin/python scripts/check_hard_clips.py --dir samples/heldout_folds2` (statistics, and
contact sheets in `/tmp/hard_check/`).

"""
    + FOLD_FILES
)
