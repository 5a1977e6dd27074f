r"""A fourth batch of held-out clips of folds: new paint, axes, speeds and places, never tuned on.

The tracker was tuned on the fold clips of ``folds`` (``samples/folds``); the held-out batches
(``heldout_folds``, ``heldout_folds2``, ``heldout_folds3`` and this one, in
``samples/heldout_folds`` to ``samples/heldout_folds4``) check that it generalises and are
never to be tuned on. This batch was made after the tracker's last change, for issue 22's
generalisation check. ``HELDOUT_FOLDS4`` lists it. ``render_hard_clips.py`` makes these clips
only when asked by name, into a folder of their own (``samples/heldout_folds4``), apart from
every other clip::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \
        --out samples/heldout_folds4 --only NAME ...

Each writes the files of a single-sheet hard clip (``NAME.mp4``, ``NAME.json``,
``NAME_truth.npz``) with the conventions of ``folds``: frame 0 flat and square to the camera,
at rest for three frames; every crease runs through the outlined region; the folds are
SimpleDeform bends over a band at the crease (``fold_limits``), so a folded part never passes
through the rest. The paint is here (``kraft_coffee_print``, ``sage_boucle_plush``,
``comic_page``); the scenes reuse the helpers of ``heldout_folds3`` (hands posed on every
frame, eased keys). Unlike the earlier batches, the two hands come in from below and from the
right, the bag folds in half from the bottom and slowly, the plush is lifted towards the camera
about an almost horizontal axis, and the printed sheet is an upright page whose right part
folds over sideways.

``kraft_bag_squeeze``
    A soft kraft paper coffee bag (``kraft_coffee_print``: matte brown kraft with fibres, a
    crimped seal along the top, a valve, faint printed beans, a cream label stuck on askew with
    a red stamp logo, the roaster's name, small print, tasting notes and a roast scale, a
    strip of striped teal tape, a faded red date stamp), lying left of and below the middle
    (``KRAFT_AT``), is squeezed by two hands in front of it, one from below and one from the
    right. It bows a little along the crease and its bottom part (52 %) folds back behind the
    rest in half, about a crease through the middle that falls 14 deg to the right
    (``KRAFT_ANGLE``), slowly (in 0.8 s from 0.45 s; 90 deg after 0.45 s, out of sight past
    about 100 deg), while the lower hand pushes the bag about 12 px left and 16 px up and
    turns it 5 deg anticlockwise. Folded back, a corner of it sticks out above the rest on the
    left, showing its bare kraft back. The lower hand's fingers follow the folding part's edge
    onto the crease; the right hand's lie over the right part above the crease. It holds
    folded for 0.5 s, unfolds (from 1.75 s, flat by 2.55 s) and the hands leave the way they
    came.
``fleece_tail_raise``
    A furry, low-contrast stuffed-toy patch, sage green with soft oatmeal patches
    (``sage_boucle_plush``: fur drawn as thousands of small curls, a boucle, unlike the combed
    hair of the other plush paints; a sheen material, dark olive felt behind), lying right of
    the middle, is held by a hand at its lower left corner (its tail) and lifted towards the
    camera about an axis 12 deg off the horizontal (``FLEECE_TILT``, through its upper part,
    ``FLEECE_PIVOT``): the patch turns 35 deg about it and, being soft, its lower half (below
    ``FLEECE_CREASE``) bends a further 80 deg over a band of 0.3, so that the tail turns to
    115 deg (past edge-on: its painted side turns away, ``visible`` false, and its felt back
    leans over the rest). It turns fast (0.8 s, from 0.5 s), holds 0.2 s and turns back (in
    1.1 s) while it drifts about 20 px right and 10 px down and most of the way back. The hand
    comes in along its forearm from the left (0.1 to 0.45 s), holds the corner (moved with the
    corner frame by frame, it rolls about its forearm, which stays along the axis, as the
    tail rises) and leaves the same way (2.8 to 3.3 s).
``comic_page_fold``
    An upright printed comic page (``comic_page``: a red title banner and seven panels of flat
    colour and halftone dots with thick black borders, a city skyline, starbursts with sound
    words, cartoon faces, speed lines, speech balloons and caption boxes, on yellowed
    newsprint; its back is plain newsprint), a little left of and above the middle: its right
    part (34 %, right of ``COMIC_CREASE``) folds over to the left by 180 deg, towards the
    camera, about a crease leaning 7 deg from the vertical (``COMIC_ANGLE``), over a band of
    0.18 (the flap lies about 0.11 in front), its plain back covering about 22 % more of the
    print. It folds fast (in 0.65 s, from 0.2 s), holds 0.35 s and unfolds slowly (in 1.4
    s) while the page drifts about 29 px right and 21 px down, turning 4 deg clockwise, and
    part of the way back.
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
from hardclips.sheet import add_sheet, bend, deform_origin, deg, finish_sheet
from hardclips.video import srgb_to_linear

# --- paint ----------------------------------------------------------------------------------

KRAFT = (0.64, 0.48, 0.32)  # unprinted kraft paper: the bag's back and rim (sRGB)
KRAFT_INK = np.array(
    [
        (0.10, 0.07, 0.06),  # near black
        (0.62, 0.13, 0.10),  # brick red
        (0.95, 0.92, 0.84),  # cream label paper
        (0.20, 0.52, 0.52),  # teal tape
        (0.30, 0.18, 0.10),  # dark brown ink
        (0.85, 0.62, 0.15),  # ochre
    ]
)


def _bean(image, centre, size, turn, colour, thickness):
    """A coffee bean: an outlined ellipse with an S-shaped cleft, drawn on ``image``."""
    c = (round(centre[0] * 16), round(centre[1] * 16))
    axes = (round(size * 16), round(0.68 * size * 16))
    cv2.ellipse(image, c, axes, turn, 0, 360, colour, thickness, cv2.LINE_AA, shift=4)
    t = np.linspace(-0.85, 0.85, 12)
    cleft = np.column_stack([t * size, 0.18 * size * np.sin(np.pi * t)])
    rotation = np.radians(turn)
    rotate = np.array(
        [[math.cos(rotation), -math.sin(rotation)], [math.sin(rotation), math.cos(rotation)]]
    )
    path = np.round((cleft @ rotate.T + centre) * 16).astype(np.int32).reshape(-1, 1, 2)
    cv2.polylines(image, [path], False, colour, thickness, cv2.LINE_AA, shift=4)


def kraft_coffee_print(rng, width, height):
    """A kraft paper coffee bag: fibres, a crimped seal, printed beans, a label, tape, a stamp.

    Matte brown kraft paper with mottling and thousands of short lighter and darker fibres; a
    crimped heat seal along the top; a degassing valve; small coffee beans printed faintly in
    dark brown ink all over; a cream paper label stuck on askew (a red round stamp logo, the
    roaster's name in a big serif, a rule, lines of small print, tasting notes with coloured
    dots and a roast scale of five dots) with a strip of striped teal tape over its corner; a
    red date stamp, faded, printed at an angle; a net weight along the bottom.
    """
    shape = (height, width)
    mottle = fractal_noise(rng, shape, cells=(3, 6, 12, 24), falloff=0.7)
    image = (1 + 0.06 * mottle)[..., None] * np.array(KRAFT)
    image = np.ascontiguousarray(image.astype(np.float32))
    base = image.copy()
    for _ in range(9000):  # fibres
        x, y = rng.uniform(0, width), rng.uniform(0, height)
        angle, length = rng.uniform(0, np.pi), rng.uniform(5, 22)
        dx, dy = 0.5 * length * math.cos(angle), 0.5 * length * math.sin(angle)
        colour = base[int(y), int(x)] * (1 + rng.choice((-1, 1)) * rng.uniform(0.05, 0.12))
        a = (round((x - dx) * 16), round((y - dy) * 16))
        b = (round((x + dx) * 16), round((y + dy) * 16))
        cv2.line(image, a, b, colour.tolist(), 1, cv2.LINE_AA, shift=4)
    # Printed beans in faint dark brown ink (a layer, laid over at part opacity).
    beans = np.zeros(shape, np.float32)
    for _ in range(70):
        centre = rng.uniform((0, 0), (width, height))
        _bean(beans, centre, rng.uniform(12, 20), rng.uniform(0, 180), 1.0, 3)
    beans = cv2.GaussianBlur(beans, (0, 0), 0.8)[..., None] * 0.45
    image = (1 - beans) * image + beans * KRAFT_INK[4]
    image = np.ascontiguousarray(image.astype(np.float32))
    # The crimped heat seal along the top: fine horizontal ribs, and a line under it.
    seal = int(0.08 * height)
    ys = np.arange(seal, dtype=np.float32)[:, None, None]
    image[:seal] *= 0.92 + 0.1 * np.sin(2 * np.pi * ys / 7.0)
    cv2.line(image, (0, seal), (width, seal), (KRAFT_INK[4] * 1.2).tolist(), 3, cv2.LINE_AA)
    # The degassing valve, upper right: a pale plastic disc with a ring and vent holes.
    valve = (int(rng.uniform(0.8, 0.86) * width), int(0.17 * height))
    cv2.circle(image, valve, 40, (0.80, 0.78, 0.72), -1, cv2.LINE_AA)
    cv2.circle(image, valve, 40, (0.45, 0.40, 0.34), 3, cv2.LINE_AA)
    cv2.circle(image, valve, 22, (0.62, 0.58, 0.52), 4, cv2.LINE_AA)
    for k in range(6):
        angle = 2 * np.pi * k / 6
        hole = (valve[0] + int(12 * math.cos(angle)), valve[1] + int(12 * math.sin(angle)))
        cv2.circle(image, hole, 3, (0.25, 0.22, 0.2), -1, cv2.LINE_AA)
    # The label, drawn upright on its own canvas and stuck on askew with a soft shadow.
    w, h = int(0.64 * width), int(0.5 * height)
    label = np.empty((h, w, 3), np.float32)
    label[:] = KRAFT_INK[2]
    label *= (1 + 0.03 * fractal_noise(rng, (h, w), cells=(4, 8)))[..., None].astype(np.float32)
    cv2.rectangle(label, (10, 10), (w - 11, h - 11), KRAFT_INK[0].tolist(), 3)
    cv2.rectangle(label, (18, 18), (w - 19, h - 19), KRAFT_INK[0].tolist(), 1)
    stamp, radius = (int(0.2 * w), int(0.36 * h)), int(0.22 * h)
    red = KRAFT_INK[1].tolist()
    cv2.circle(label, stamp, radius, red, 6, cv2.LINE_AA)
    cv2.circle(label, stamp, radius - 14, red, 2, cv2.LINE_AA)
    _bean(label, np.array(stamp, float), 0.45 * radius, -35.0, red, 6)
    for k in range(12):  # ticks round the stamp's ring
        angle = 2 * np.pi * k / 12
        inner, outer = radius + 8, radius + 20
        a = (stamp[0] + int(inner * math.cos(angle)), stamp[1] + int(inner * math.sin(angle)))
        b = (stamp[0] + int(outer * math.cos(angle)), stamp[1] + int(outer * math.sin(angle)))
        cv2.line(label, a, b, red, 3, cv2.LINE_AA)
    name = _random_text(rng, 7).replace(" ", "") or "ROAST"
    ink = KRAFT_INK[0].tolist()
    cv2.putText(
        label,
        name,
        (int(0.4 * w), int(0.3 * h)),
        cv2.FONT_HERSHEY_COMPLEX,
        2.2,
        ink,
        5,
        cv2.LINE_AA,
    )
    origin = f"ORIGIN {_random_text(rng, 9)}"
    cv2.putText(
        label,
        origin,
        (int(0.41 * w), int(0.42 * h)),
        cv2.FONT_HERSHEY_DUPLEX,
        0.9,
        red,
        2,
        cv2.LINE_AA,
    )
    cv2.line(label, (int(0.4 * w), int(0.47 * h)), (int(0.94 * w), int(0.47 * h)), ink, 2)
    for k in range(4):
        text = _random_text(rng, int(rng.integers(16, 26)))
        org = (int(0.41 * w), int((0.55 + 0.07 * k) * h))
        cv2.putText(label, text, org, cv2.FONT_HERSHEY_SIMPLEX, 0.55, ink, 1, cv2.LINE_AA)
    for k in range(3):  # tasting notes, each with a coloured dot
        x = int((0.07 + 0.3 * k) * w)
        colour = (KRAFT_INK[1], KRAFT_INK[5], KRAFT_INK[3])[k].tolist()
        cv2.circle(label, (x + 10, int(0.8 * h)), 10, colour, -1, cv2.LINE_AA)
        note = _random_text(rng, 6).replace(" ", "") or "CACAO"
        org = (x + 28, int(0.8 * h) + 8)
        cv2.putText(label, note, org, cv2.FONT_HERSHEY_DUPLEX, 0.75, ink, 1, cv2.LINE_AA)
    cv2.putText(
        label, "ROAST", (int(0.07 * w), int(0.92 * h)), cv2.FONT_HERSHEY_SIMPLEX, 0.6, ink, 2
    )
    for k in range(5):  # the roast scale: five dots, three filled
        centre = (int(0.22 * w) + 26 * k, int(0.92 * h) - 6)
        cv2.circle(label, centre, 8, ink, -1 if k < 3 else 2, cv2.LINE_AA)
    turn = rng.uniform(-5.0, -3.0)
    centre = (0.5 * width, 0.5 * height)
    place = cv2.getRotationMatrix2D((w / 2, h / 2), turn, 1.0)
    place[:, 2] += (centre[0] - w / 2, centre[1] - h / 2)
    pasted = cv2.warpAffine(label, place, (width, height), flags=cv2.INTER_LINEAR)
    cover = cv2.warpAffine(np.ones((h, w), np.float32), place, (width, height))[..., None]
    shadow = cv2.GaussianBlur(np.roll(cover[..., 0], (6, 5), axis=(0, 1)), (0, 0), 5.0)
    image = image * (1 - 0.35 * shadow[..., None])
    image = (1 - cover) * image + cover * pasted
    # Striped teal tape over the label's upper left corner, translucent.
    tape = np.zeros(shape, np.float32)
    corner = place @ np.array((0.0, 0.0, 1.0))
    along = np.array((math.cos(math.radians(-38)), math.sin(math.radians(-38))))
    across = np.array((-along[1], along[0]))
    quad = [
        corner + s * 110 * along + t * 32 * across for s, t in ((-1, -1), (1, -1), (1, 1), (-1, 1))
    ]
    cv2.fillPoly(tape, [np.round(np.array(quad) * 16).astype(np.int32)], 1.0, cv2.LINE_AA, shift=4)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    stripes = 0.5 + 0.5 * np.sign(np.sin((xs + ys) * 2 * np.pi / 24))
    tape = (0.7 * tape)[..., None]
    tint = stripes[..., None] * KRAFT_INK[3] + (1 - stripes[..., None]) * np.array(
        (0.9, 0.95, 0.92)
    )
    image = (1 - tape) * image + tape * tint
    image = np.ascontiguousarray(image.astype(np.float32))
    # A red date stamp, faded, at an angle low on the right; the net weight along the bottom.
    stamp_layer = np.zeros(shape, np.float32)
    date = f"BEST BY {int(rng.integers(1, 28)):02d} {int(rng.integers(1, 12)):02d} 27"
    cv2.putText(stamp_layer, date, (int(0.56 * width), int(0.86 * height)), 2, 1.0, 1.0, 3)
    tilt = cv2.getRotationMatrix2D((0.75 * width, 0.85 * height), 7.0, 1.0)
    stamp_layer = cv2.warpAffine(stamp_layer, tilt, (width, height))
    stamp_layer *= (rng.random(shape) > 0.25) * (
        0.55 + 0.3 * fractal_noise(rng, shape, cells=(6, 12))
    )
    stamp_layer = cv2.GaussianBlur(stamp_layer.astype(np.float32), (0, 0), 0.8)[..., None]
    image = (1 - stamp_layer) * image + stamp_layer * KRAFT_INK[1]
    image = np.ascontiguousarray(image.astype(np.float32))
    weight = f"NET WT {int(rng.integers(200, 500))} G   WHOLE BEAN"
    cv2.putText(
        image,
        weight,
        (int(0.06 * width), int(0.95 * height)),
        cv2.FONT_HERSHEY_SIMPLEX,
        0.9,
        KRAFT_INK[0].tolist(),
        2,
        cv2.LINE_AA,
    )
    image *= (1 + 0.02 * rng.standard_normal(shape)).astype(np.float32)[..., None]
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


def sage_boucle_plush(rng, width, height):
    """A sage green boucle plush with soft oatmeal patches, its fur drawn as small curls.

    The fur is thousands of small open loops (arcs of ellipses, each with a faint shadow), a
    little lighter or darker than the colour under them, in clumps, over fine grain: curly,
    unlike the combed hair of the other plush paints, and low contrast on purpose.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    sage, olive, oat = (
        np.array((0.55, 0.60, 0.49)),
        np.array((0.47, 0.51, 0.41)),
        np.array((0.66, 0.65, 0.56)),
    )
    share = np.clip(0.5 + 2.0 * fractal_noise(rng, shape, cells=(2, 4, 8)), 0, 1)
    share = cv2.GaussianBlur(share.astype(np.float32), (0, 0), 10.0)[..., None]
    shade = np.clip(0.5 + 1.5 * fractal_noise(rng, shape, cells=(4, 8, 16)), 0, 1)[..., None]
    image = (1 - 0.8 * shade) * sage + 0.8 * shade * olive
    image = (1 - 0.7 * share) * image + 0.7 * share * oat
    image = np.ascontiguousarray(image.astype(np.float32))
    base = image.copy()
    clumps = rng.uniform((0, 0), (width, height), (900, 2))
    for _ in range(14000):  # curls, most of them in clumps
        if rng.random() < 0.7:
            x, y = clumps[rng.integers(len(clumps))] + rng.normal(0, 14, 2)
        else:
            x, y = rng.uniform(0, width), rng.uniform(0, height)
        x, y = min(max(x, 0), width - 1), min(max(y, 0), height - 1)
        r = rng.uniform(7, 16)
        axes = (round(r * 16), round(r * rng.uniform(0.6, 0.95) * 16))
        turn, start = rng.uniform(0, 360), rng.uniform(0, 360)
        end = start + rng.uniform(200, 320)
        colour = base[int(y), int(x)] * (1 + rng.normal(0, 0.08))
        thick = int(rng.integers(2, 5))
        at = (round((x + 1.5) * 16), round((y + 1.5) * 16))
        dark = (colour * 0.85).tolist()
        cv2.ellipse(image, at, axes, turn, start, end, dark, thick, cv2.LINE_AA, shift=4)
        at = (round(x * 16), round(y * 16))
        cv2.ellipse(image, at, axes, turn, start, end, colour.tolist(), thick, cv2.LINE_AA, shift=4)
    image = image + 0.012 * rng.standard_normal((*shape, 3)).astype(np.float32)
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.7), 0, 1)


NEWSPRINT = (0.93, 0.91, 0.82)  # the comic page's paper: its gutters and its plain back (sRGB)
COMIC_INK = np.array(
    [
        (0.07, 0.07, 0.09),  # black
        (0.12, 0.55, 0.85),  # cyan
        (0.88, 0.22, 0.52),  # magenta
        (0.98, 0.84, 0.18),  # yellow
        (0.86, 0.16, 0.12),  # red
        (0.98, 0.78, 0.62),  # skin
        (0.30, 0.66, 0.30),  # green
    ]
)


def _halftone(shape, tone, period, turn):
    """Ben-Day dots: 1 inside a dot of a grid turned ``turn`` rad, dots sized by ``tone`` (0-1).

    Returns
    -------
    shape float32, antialiased at the dots' edges.
    """
    ys, xs = np.mgrid[0 : shape[0], 0 : shape[1]].astype(np.float32)
    u = xs * math.cos(turn) + ys * math.sin(turn)
    v = -xs * math.sin(turn) + ys * math.cos(turn)
    du = (u / period) % 1 - 0.5
    dv = (v / period) % 1 - 0.5
    distance = np.hypot(du, dv) * period
    radius = 0.72 * period * np.sqrt(np.clip(tone, 0, 1))
    return np.clip(radius - distance + 0.5, 0, 1).astype(np.float32)


def _balloon(image, rng, centre, size, tail):
    """A speech balloon: a white ellipse with a tail towards ``tail``, lines of small text."""
    black = COMIC_INK[0].tolist()
    tip = np.array(tail, np.float64)
    c = np.array(centre, np.float64)
    side = np.array((-(tip - c)[1], (tip - c)[0]))
    side = 0.25 * size[1] * side / np.linalg.norm(side)
    triangle = np.round(np.array([c + side, c - side, tip])).astype(np.int32)
    for colour, grow in ((black, 4), ((1.0, 1.0, 1.0), 0)):
        cv2.ellipse(
            image, centre, (size[0] + grow, size[1] + grow), 0, 0, 360, colour, -1, cv2.LINE_AA
        )
        if grow:
            cv2.polylines(image, [triangle], True, colour, 8, cv2.LINE_AA)
        else:
            cv2.fillPoly(image, [triangle], colour, cv2.LINE_AA)
    lines = 3 if size[1] > 45 else 2
    for k in range(lines):
        text = _random_text(rng, int(size[0] / 11))
        y = centre[1] + int((k - (lines - 1) / 2) * 22) + 6
        org = (centre[0] - int(0.72 * size[0]), y)
        cv2.putText(image, text, org, cv2.FONT_HERSHEY_SIMPLEX, 0.6, black, 2, cv2.LINE_AA)


def _starburst(image, centre, radius, points, colour, rng):
    angles = 2 * np.pi * np.arange(2 * points) / (2 * points) + rng.uniform(0, 1)
    radii = np.where(np.arange(2 * points) % 2 == 0, radius, 0.62 * radius)
    radii = radii * rng.uniform(0.85, 1.15, 2 * points)
    corners = np.column_stack([np.cos(angles), np.sin(angles)]) * radii[:, None] + centre
    corners = np.round(corners).astype(np.int32)
    cv2.fillPoly(image, [corners], colour, cv2.LINE_AA)
    cv2.polylines(image, [corners], True, COMIC_INK[0].tolist(), 5, cv2.LINE_AA)


def _panel_art(rng, kind, box, shape):
    """The drawing of one comic panel, on a full-page canvas (the panel clips it).

    ``kind`` is one of "city", "bang", "face", "speed"; ``box`` (x0, y0, x1, y1) the panel's
    bounds.
    """
    height, width = shape
    x0, y0, x1, y1 = box
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    black = COMIC_INK[0].tolist()
    fade = np.clip((ys - y0) / max(y1 - y0, 1), 0, 1)
    sky = COMIC_INK[rng.choice([1, 2, 3])]
    dots = _halftone(shape, 0.15 + 0.6 * fade, 9.0, math.radians(rng.uniform(10, 75)))[..., None]
    art = (1 - dots) * np.array(NEWSPRINT) + dots * sky
    art = np.ascontiguousarray(art.astype(np.float32))
    w, h = x1 - x0, y1 - y0
    if kind == "city":  # a skyline of buildings with lit windows
        x = x0 - 10
        while x < x1:
            bw = int(rng.uniform(0.12, 0.25) * w)
            top = int(y1 - rng.uniform(0.3, 0.8) * h)
            colour = (COMIC_INK[rng.choice([1, 2, 6])] * rng.uniform(0.45, 0.7)).tolist()
            cv2.rectangle(art, (x, top), (x + bw, y1), colour, -1)
            cv2.rectangle(art, (x, top), (x + bw, y1), black, 4)
            for wy in range(top + 12, y1 - 10, 22):
                for wx in range(x + 10, x + bw - 12, 18):
                    if rng.random() < 0.6:
                        cv2.rectangle(art, (wx, wy), (wx + 8, wy + 10), COMIC_INK[3].tolist(), -1)
            x += bw + int(rng.integers(-6, 10))
    elif kind == "bang":  # a starburst with a sound word
        centre = (x0 + 0.5 * w, y0 + 0.52 * h)
        _starburst(art, centre, 0.42 * min(w, h), 11, COMIC_INK[3].tolist(), rng)
        _starburst(art, centre, 0.26 * min(w, h), 9, COMIC_INK[4].tolist(), rng)
        word = (_random_text(rng, 4).replace(" ", "") or "KRAK") + "!"
        scale = 0.28 * min(w, h) / 30
        (tw, th), _ = cv2.getTextSize(word, cv2.FONT_HERSHEY_TRIPLEX, scale, 8)
        org = (int(centre[0] - tw / 2), int(centre[1] + th / 2))
        for colour, thickness in ((black, 14), ((1.0, 1.0, 1.0), 6)):
            cv2.putText(
                art, word, org, cv2.FONT_HERSHEY_TRIPLEX, scale, colour, thickness, cv2.LINE_AA
            )
    elif kind == "face":  # a round cartoon head with hair, eyes and an open mouth
        centre = (int(x0 + rng.uniform(0.4, 0.6) * w), int(y0 + 0.58 * h))
        r = int(0.3 * min(w, h))
        hair = COMIC_INK[rng.choice([0, 4, 3])].tolist()
        cv2.ellipse(
            art, (centre[0], centre[1] - r // 3), (r + 8, r), 0, 180, 360, hair, -1, cv2.LINE_AA
        )
        cv2.circle(art, centre, r, COMIC_INK[5].tolist(), -1, cv2.LINE_AA)
        cv2.circle(art, centre, r, black, 5, cv2.LINE_AA)
        cheeks = _halftone(shape, 0.35, 6.0, 0.3) * (np.hypot(xs - centre[0], ys - centre[1]) < r)
        art = np.ascontiguousarray(
            (art * (1 - 0.5 * cheeks[..., None]) + 0.5 * cheeks[..., None] * COMIC_INK[2]).astype(
                np.float32
            )
        )
        for side in (-1, 1):
            eye = (centre[0] + side * r // 3, centre[1] - r // 6)
            cv2.ellipse(art, eye, (r // 7, r // 5), 0, 0, 360, (1.0, 1.0, 1.0), -1, cv2.LINE_AA)
            cv2.ellipse(art, eye, (r // 7, r // 5), 0, 0, 360, black, 3, cv2.LINE_AA)
            cv2.circle(art, (eye[0] + side * 3, eye[1] + 4), r // 12, black, -1, cv2.LINE_AA)
        mouth = (centre[0], centre[1] + r // 2)
        cv2.ellipse(art, mouth, (r // 4, r // 6), 0, 0, 360, COMIC_INK[4].tolist(), -1, cv2.LINE_AA)
        cv2.ellipse(art, mouth, (r // 4, r // 6), 0, 0, 360, black, 3, cv2.LINE_AA)
    else:  # speed lines from a point, with a rocket-like oval flying out of it
        focus = np.array((x0 + rng.uniform(0.2, 0.8) * w, y0 + rng.uniform(0.3, 0.7) * h))
        for _ in range(60):
            angle = rng.uniform(0, 2 * np.pi)
            r0, r1 = rng.uniform(0.15, 0.3) * max(w, h), max(w, h)
            a = focus + r0 * np.array((math.cos(angle), math.sin(angle)))
            b = focus + r1 * np.array((math.cos(angle), math.sin(angle)))
            cv2.line(
                art,
                tuple(np.round(a).astype(int)),
                tuple(np.round(b).astype(int)),
                black,
                int(rng.integers(2, 6)),
                cv2.LINE_AA,
            )
        body = (int(focus[0]), int(focus[1]))
        turn = rng.uniform(0, 180)
        axes = (int(0.22 * min(w, h)), int(0.09 * min(w, h)))
        cv2.ellipse(art, body, axes, turn, 0, 360, COMIC_INK[4].tolist(), -1, cv2.LINE_AA)
        cv2.ellipse(art, body, axes, turn, 0, 360, black, 5, cv2.LINE_AA)
        cv2.circle(art, body, axes[1] // 2, (1.0, 1.0, 1.0), -1, cv2.LINE_AA)
    if rng.random() < 0.5:  # a yellow caption box in the upper left corner
        bw, bh = int(0.55 * w), 58
        cv2.rectangle(art, (x0 + 6, y0 + 6), (x0 + 6 + bw, y0 + 6 + bh), COMIC_INK[3].tolist(), -1)
        cv2.rectangle(art, (x0 + 6, y0 + 6), (x0 + 6 + bw, y0 + 6 + bh), black, 3)
        for k in range(2):
            text = _random_text(rng, int(bw / 13))
            org = (x0 + 14, y0 + 28 + 22 * k)
            cv2.putText(art, text, org, cv2.FONT_HERSHEY_SIMPLEX, 0.55, black, 2, cv2.LINE_AA)
    else:  # a speech balloon
        centre = (int(x0 + rng.uniform(0.35, 0.65) * w), int(y0 + 0.22 * h))
        size = (int(0.36 * w), int(min(0.16 * h, 60)))
        tail = (centre[0] + rng.uniform(-0.2, 0.2) * w, centre[1] + 0.3 * h)
        _balloon(art, rng, centre, size, tail)
    return art


def comic_page(rng, width, height):
    """A printed comic page: a title banner and seven panels of flat colour and halftone dots.

    On yellowed newsprint: a red banner with an outlined yellow title and an issue number; a
    grid of seven panels (three rows, the gutters a little slanted) with thick black borders,
    each a halftone sky and a drawing (a city skyline with lit windows, a starburst with a
    sound word, a cartoon face, speed lines and a flying oval) with a speech balloon or a
    caption box; a page number; ink a little uneven.
    """
    shape = (height, width)
    image = np.empty((height, width, 3), np.float32)
    image[:] = NEWSPRINT
    image *= (1 + 0.04 * fractal_noise(rng, shape, cells=(3, 6, 12)))[..., None].astype(np.float32)
    black = COMIC_INK[0].tolist()
    # The title banner.
    top = int(0.11 * height)
    cv2.rectangle(image, (14, 14), (width - 15, top), COMIC_INK[4].tolist(), -1)
    cv2.rectangle(image, (14, 14), (width - 15, top), black, 5)
    title = _random_text(rng, 8).replace(" ", "") or "COMICS"
    org = (40, top - 30)
    for colour, thickness in ((black, 18), (COMIC_INK[3].tolist(), 8)):
        cv2.putText(
            image, title, org, cv2.FONT_HERSHEY_TRIPLEX, 3.0, colour, thickness, cv2.LINE_AA
        )
    issue = (width - 80, (14 + top) // 2)
    cv2.circle(image, issue, 46, (1.0, 1.0, 1.0), -1, cv2.LINE_AA)
    cv2.circle(image, issue, 46, black, 4, cv2.LINE_AA)
    number = f"{int(rng.integers(1, 99))}"
    cv2.putText(image, number, (issue[0] - 30, issue[1] + 16), 2, 1.4, black, 4, cv2.LINE_AA)
    # Seven panels in three rows; the vertical gutters lean a little.
    gutter, margin = 14, 16
    bounds = [top + gutter, int(0.42 * height), int(0.70 * height), int(0.975 * height)]
    splits = [[0.57], [0.34, 0.68], [0.42]]  # where each row's gutters are (of the width)
    kinds = list(rng.permutation(["city", "bang", "face", "speed", "city", "bang", "face"]))
    for row, cuts in enumerate(splits):
        y0 = bounds[row] + (gutter // 2 if row > 0 else 0)
        y1 = bounds[row + 1] - gutter // 2
        edges = [margin] + [int(c * width) for c in cuts] + [width - margin]
        lean = [0] + [int(rng.integers(-30, 30)) for _ in cuts] + [0]
        for k in range(len(edges) - 1):
            left = edges[k] + (gutter // 2 if k > 0 else 0)
            right = edges[k + 1] - (gutter // 2 if k < len(cuts) else 0)
            quad = np.array(
                [
                    (left + lean[k], y0),
                    (right + lean[k + 1], y0),
                    (right - lean[k + 1], y1),
                    (left - lean[k], y1),
                ],
                np.int32,
            )
            box = (int(quad[:, 0].min()), y0, int(quad[:, 0].max()), y1)
            art = _panel_art(rng, kinds.pop(), box, shape)
            mask = np.zeros(shape, np.float32)
            cv2.fillPoly(mask, [quad], 1.0, cv2.LINE_AA)
            image = (1 - mask[..., None]) * image + mask[..., None] * art
            image = np.ascontiguousarray(image.astype(np.float32))
            cv2.polylines(image, [quad], True, black, 6, cv2.LINE_AA)
    cv2.putText(
        image,
        str(int(rng.integers(2, 40))),
        (width // 2 - 12, height - 8),
        cv2.FONT_HERSHEY_SIMPLEX,
        0.8,
        black,
        2,
        cv2.LINE_AA,
    )
    image *= (1 + 0.03 * fractal_noise(rng, shape, cells=(8, 16, 32)))[..., None].astype(np.float32)
    image *= (1 + 0.02 * rng.standard_normal(shape)).astype(np.float32)[..., None]
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


# --- scenes ---------------------------------------------------------------------------------

KRAFT_SIZE = (2.0, 1.7)
KRAFT_AT = (-0.6, -0.25)  # kraft_bag_squeeze: the bag's centre at rest, left of and below
KRAFT_ANGLE = -104.0  # the fold's direction (deg from +X: down, a little left)
KRAFT_CREASE = -0.03  # the crease's distance from the bag's centre along that direction
KRAFT_BAND = 0.2  # folded, the bottom part lies 2 * band / pi behind the rest
KRAFT_RIGHT = -10.0  # the right hand comes in along this direction (deg from +X, bag frame)


def build_kraft_bag_squeeze(rng, clip):
    studio_lights()
    size = KRAFT_SIZE
    sheet = add_sheet(
        kraft_coffee_print,
        size,
        (80, 68),
        4,
        rng=rng,
        roughness=0.8,
        specular=0.25,
        thickness=0.03,
    )
    angle = math.radians(KRAFT_ANGLE)
    d = np.array((math.cos(angle), math.sin(angle)))  # the fold's direction, down
    # The squeeze bows the bag a little along the crease (the crease's ends towards the
    # camera): that does not change where a point is along d, so the fold's limits stay put...
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), diagonal_towards_camera(angle - math.pi / 2))
    bend(sheet, "Bow", origin)
    # ...and folds the bottom part back about the tilted crease, over a band of KRAFT_BAND.
    crease_bend(sheet, "Fold", size, angle, KRAFT_CREASE, KRAFT_BAND, diagonal_away)
    # The fold (keyed on every frame), slow, from 0.45 s; unfolds from 1.75 s. The lower hand
    # pushes the bag up and left and turns it 5 deg (counter-clockwise).
    t = np.arange(clip.frames) / clip.fps
    pace = paced_fold(3.3, 9.0, 30.0)
    fold = fold_and_unfold(t, 0.45, 1.75, pace)
    x0, y0 = KRAFT_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bow"].angle', 0): deg(
                [(0.0, 0), (0.4, 0), (1.0, 16), (1.8, 16), (2.5, 0)]
            ),
            ('modifiers["Fold"].angle', 0): list(zip(t, fold, strict=True)),
            ("location", 0): [
                (0.0, x0),
                (0.45, x0),
                (1.2, x0 - 0.12),
                (1.8, x0 - 0.12),
                (2.7, x0 - 0.04),
                (3.5, x0 - 0.03),
            ],
            ("location", 1): [
                (0.0, y0),
                (0.45, y0),
                (1.2, y0 + 0.15),
                (1.8, y0 + 0.15),
                (2.8, y0 + 0.05),
                (3.5, y0 + 0.04),
            ],
            ("rotation_euler", 2): deg([(0.0, 0), (0.45, 0), (1.2, 5), (2.6, -1), (3.5, 1)]),
        },
    )
    # The hands come in in front of the bag and move with it: the lower one from below, its
    # fingers (pointing up) over the bottom part and then, following its edge as it folds
    # back (a little inside the edge as seen while in view), onto the crease; the right one
    # from the right, its fingers (pointing left) over the right part above the crease. Where
    # their fingertips are: how far out from the bag's centre along the direction they come in
    # from (the larger of the keys and, for the lower hand, the folding edge), and how far
    # across it (bag frame).
    length = size[1] / 2 / abs(d[1]) - KRAFT_CREASE  # from the crease to the bottom edge
    folding_edge = KRAFT_CREASE + np.maximum(length * np.cos(fold) - 0.3, -0.2)
    lower_tips = [
        (0.0, 4.4),
        (0.1, 4.4),
        (0.45, 0.6),
        (0.6, KRAFT_CREASE - 0.2),
        (1.75, KRAFT_CREASE - 0.2),
        (2.1, 0.6),
        (2.9, 4.4),
    ]
    right_tips = [
        (0.0, 4.4),
        (0.2, 4.4),
        (0.6, 0.8),
        (1.2, 0.66),
        (1.8, 0.66),
        (2.45, 0.8),
        (3.3, 4.4),
    ]
    side = math.radians(KRAFT_RIGHT)
    matrices = object_matrices(clip, sheet.obj)
    for name, reach, out, across in (
        ("LowerHand", np.maximum(eased(t, lower_tips), folding_edge), d, 0.12),
        ("RightHand", eased(t, right_tips), np.array((math.cos(side), math.sin(side))), 0.3),
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
    set_back_colour(sheet, (*srgb_to_linear(np.array(KRAFT)), 1.0))
    return sheet


FLEECE_SIZE = (1.8, 1.6)
FLEECE_AT = (0.55, -0.1)  # fleece_tail_raise: the patch's centre at rest, right of the middle
FLEECE_TILT = 12.0  # the turning axis: deg from the horizontal, rising to the right
FLEECE_PIVOT = -0.62  # the axis's distance from the centre, across it (downwards): above
FLEECE_CREASE = 0.0  # where the tail's bend starts, likewise: through the centre
FLEECE_BAND = 0.3  # the length of the tail's bend
OLIVE_FELT = (0.06, 0.07, 0.04, 1.0)  # fleece_tail_raise's back and rim (linear RGB)


def build_fleece_tail_raise(rng, clip):
    studio_lights()
    size = FLEECE_SIZE
    tilt = math.radians(FLEECE_TILT)
    axis = np.array((math.cos(tilt), math.sin(tilt)))  # right and a little up
    down = np.array((math.sin(tilt), -math.cos(tilt)))  # across it, down towards the tail
    sheet, pivot = plush_on_pivot(
        rng, sage_boucle_plush, size, (72, 64), 0.0, (0.5, 0.4, (0.8, 0.88, 0.7, 1.0))
    )
    # The pivot: the tilted axis through the upper part; turning about -axis by a positive
    # angle lifts the part below it towards the camera.
    at = np.array(FLEECE_AT) + FLEECE_PIVOT * down
    pivot.location = (*at, 0.0)
    pivot.rotation_mode = "AXIS_ANGLE"
    pivot.rotation_axis_angle = (0.0, *(-axis), 0.0)
    sheet.obj.location = (*(-FLEECE_PIVOT * down), 0.0)
    # The soft toy gives where it is held: the tail (the half below FLEECE_CREASE) bends further
    # towards the camera over a band of FLEECE_BAND, so that the patch turns 35 deg and the
    # tail 115 deg, past edge-on, leaning back over the rest.
    angle = tilt - math.pi / 2  # the direction ``down``
    crease_bend(sheet, "Tail", size, angle, FLEECE_CREASE, FLEECE_BAND, diagonal_towards_camera)
    clip.keyframe(
        pivot,
        {
            ("rotation_axis_angle", 0): deg([(0.0, 0), (0.5, 0), (1.3, 35), (1.5, 35), (2.6, 0)]),
            ("location", 0): [(0.0, at[0]), (0.5, at[0]), (1.5, at[0] + 0.2), (3.4, at[0] + 0.05)],
            ("location", 1): [(0.0, at[1]), (0.5, at[1]), (1.5, at[1] - 0.1), (3.4, at[1] - 0.03)],
        },
    )
    clip.keyframe(
        sheet.obj,
        {('modifiers["Tail"].angle', 0): deg([(0.0, 0), (0.5, 0), (1.3, 80), (1.5, 80), (2.6, 0)])},
    )
    # The hand holds the lower left corner (the tail's end): its fingers (pointing right, along
    # the axis) lie over the corner a little inside it, the back of the hand away from the
    # painted side; moved with the corner on every frame, it rolls about its forearm (which
    # stays along the axis, out to the left) as the tail rises. It comes in along the axis from
    # the left and leaves the same way.
    grids = sheet_frames(clip, sheet)
    t = np.arange(clip.frames) / clip.fps
    away = eased(t, [(0.0, 3.5), (0.1, 3.5), (0.45, 0.0), (2.8, 0.0), (3.3, 3.5)])
    hand = add_pushing_hand("Hand", True)
    poses = []
    for grid, out in zip(grids, away, strict=True):
        corner = grid[-1, 0]
        along_x = grid[-1, 2] - corner
        along_y = grid[-3, 0] - corner
        along_x, along_y = along_x / np.linalg.norm(along_x), along_y / np.linalg.norm(along_y)
        normal = np.cross(along_x, along_y)
        a = axis[0] * along_x + axis[1] * along_y
        n = down[0] * along_x + down[1] * along_y
        tips = corner + (0.2 - out) * a - 0.08 * n + 0.13 * normal
        poses.append(hand_pose(tips, a, normal))
    key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, OLIVE_FELT)
    return sheet


COMIC_SIZE = (1.8, 2.4)  # a page, upright
COMIC_AT = (-0.25, 0.12)  # comic_page_fold: the page's centre at rest
COMIC_ANGLE = -7.0  # the fold's direction (deg from +X: right, a little down)
COMIC_CREASE = 0.28  # the crease's distance from the centre along that direction
COMIC_BAND = 0.18  # folded, the flap lies 2 * band / pi in front


def build_comic_page_fold(rng, clip):
    studio_lights()
    size = COMIC_SIZE
    sheet = add_sheet(
        comic_page,
        size,
        (72, 96),
        4,
        rng=rng,
        roughness=0.75,
        specular=0.3,
        thickness=0.008,
    )
    # The right part folds over to the left, towards the camera, about a crease leaning 7 deg
    # from the vertical; folded, it lies about 0.11 in front of the rest, its plain back to
    # the camera.
    angle = math.radians(COMIC_ANGLE)
    crease_bend(sheet, "Fold", size, angle, COMIC_CREASE, COMIC_BAND, diagonal_towards_camera)
    # Fast over (0.65 s), slowly back (1.4 s); the page drifts down and right and turns 4 deg
    # clockwise meanwhile, and part of the way back.
    x0, y0 = COMIC_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): deg(
                [(0.0, 0), (0.2, 0), (0.6, 95), (0.85, 180), (1.2, 180), (1.9, 95), (2.6, 0)]
            ),
            ("location", 0): [(0.0, x0), (0.2, x0), (1.4, x0 + 0.28), (3.3, x0 + 0.12)],
            ("location", 1): [(0.0, y0), (0.2, y0), (1.4, y0 - 0.2), (3.3, y0 - 0.08)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.2, 0), (1.4, -4), (3.3, -1.5)]),
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(NEWSPRINT)), 1.0))
    return sheet


HELDOUT_FOLDS4 = [
    Clip(
        "kraft_bag_squeeze",
        105,
        30,
        "two hands, in from below and from the right, squeeze a matte kraft paper coffee bag "
        "with a label, lying left of and below the middle: it bows and its bottom part (52 %) "
        "folds back behind the rest in half, about a crease through the middle falling 14 deg "
        "to the right, slowly (0.8 s), while it is pushed about 12 px left and 16 px up and "
        "turned 5 deg; holds 0.5 s with the lower hand over the crease and the right hand over "
        "the right part, unfolds; the hands leave",
        build_kraft_bag_squeeze,
    ),
    Clip(
        "fleece_tail_raise",
        102,
        30,
        "a furry, low-contrast sage green plush patch with curly fur and soft oatmeal patches, "
        "held by a hand at its lower left corner, is lifted towards the camera in 0.8 s about "
        "an axis 12 deg off the horizontal through its upper part while it drifts about 20 px "
        "right and 10 px down: the patch turns 35 deg, its lower half on to 115 deg, past edge-on "
        "(painted side turned away, its back leaning over the rest); holds 0.2 s, turns back; "
        "the hand leaves",
        build_fleece_tail_raise,
    ),
    Clip(
        "comic_page_fold",
        100,
        30,
        "the right 34 % of an upright printed comic page folds over to the left by 180 deg, "
        "towards the camera, about a crease leaning 7 deg from the vertical (its plain back "
        "covers about 22 % more of the print), fast (0.65 s); holds 0.35 s and unfolds "
        "slowly (1.4 s) while the page drifts about 29 px right and 21 px down, turning 4 deg, "
        "and part of the way back",
        build_comic_page_fold,
    ),
]


README_HELDOUT_FOLDS4 = (
    """# Held-out clips of folds, fourth batch

Clips for checking that the tracker generalises to folds (issue 22): never tune it on these;
they were made after the tracker's last change and are to be measured once, as held-out. The
tracker was tuned on the fold clips of [`../folds`](../folds/README.md); like the first three
held-out batches ([`../heldout_folds`](../heldout_folds/README.md),
[`../heldout_folds2`](../heldout_folds2/README.md) and
[`../heldout_folds3`](../heldout_folds3/README.md)) these show the same kinds of motion (a
sheet squeezed until part of it folds back, a soft patch turned past edge-on, a part folded
over the rest) with paint, axes, speeds and places that no earlier batch has: a matte kraft
paper bag folded back in half from the bottom, slowly, by hands that come in from below and
from the right; a curly plush patch lifted by a corner towards the camera about an almost
horizontal axis, fast; the right part of an upright comic page folded over sideways, fast, and
unfolded slowly while the page drifts. Rendered with Blender {blender}
(the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes and paint in
`scripts/hardclips/heldout_folds4.py`) from a fixed seed, so the same command makes the same
scenes, truth and outlines; it makes them only when named, apart from every other clip:

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \\
        --out samples/heldout_folds4 --only {names}

Keep them out of `samples/folds`, `samples/heldout_folds`, `samples/heldout_folds2` and
`samples/heldout_folds3`. Check them with
`.venv/bin/python scripts/check_hard_clips.py --dir samples/heldout_folds4` (statistics, and
contact sheets in `/tmp/hard_check/`).

"""
    + FOLD_FILES
)
