r"""A seventh batch of held-out clips of folds: new paint, axes, speeds and places, never tuned on.

The tracker was tuned on the fold clips of ``folds`` (``samples/folds``); the held-out batches
(``heldout_folds`` to ``heldout_folds6`` and this one, in ``samples/heldout_folds`` to
``samples/heldout_folds7``) check that it generalises and are never to be tuned on. This batch
was made after the sixth, for issue 22's generalisation check. ``HELDOUT_FOLDS7`` lists it.
``render_hard_clips.py`` makes these clips only when asked by name, into a folder of their own
(``samples/heldout_folds7``), apart from every other clip::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \
        --out samples/heldout_folds7 --only NAME ...

Each writes the files of a single-sheet hard clip (``NAME.mp4``, ``NAME.json``,
``NAME_truth.npz``) with the conventions of ``folds``: frame 0 flat and square to the camera,
at rest for three frames; every crease runs through the outlined region; the folds are
SimpleDeform bends over a band at the crease (``fold_limits``), so a folded part never passes
through the rest. The paint is here (``gummy_bag_print``, ``shaggy_locks_plush``,
``game_board``); the scenes reuse the helpers of ``heldout_folds3`` (hands posed on every
frame, eased keys, ``crease_bend``) and of ``heldout_folds6`` (``_outlined_text``). Unlike the
earlier batches, each sheet lies at another distance from the camera at rest (the bag nearer,
the plush and the board farther); the bag's right part folds back about a crease leaning from
the vertical at a medium pace under hands in from the right and from the lower left, and
snaps back open fast; the plush is held by its upper left corner and turned away from the
camera about an axis rising 50 deg to the right, fast, held long and let back slowly; the
board's top right corner folds over, half opens and folds over again before it unfolds.

``gummy_bag_squeeze``
    A glossy bag of gummy bears (``gummy_bag_print``: diagonal hot magenta and tangerine
    stripes with a soft sheen, a big wordmark outlined in purple and a yellow second word, a
    clear window showing a heap of translucent gummy bears in six colours, a blue ribbon with
    small print, a white "NEW" roundel with stars, a barcode, a crimped seal along the top;
    its back the film's silvery inside), lying left of and above the middle (``GUMMY_AT``) and
    nearer the camera than any earlier bag (``GUMMY_DEPTH``, about 9 % larger on the picture),
    is squeezed by two hands in front of it, one from the right and one from the lower left
    (``GUMMY_LOWER``). Its right part (45 %) folds back behind the rest about a crease through
    the middle leaning 20 deg from the vertical (``GUMMY_ANGLE``, ``GUMMY_CREASE``: its top
    right of its bottom), over a band of 0.2, at a medium pace (0.58 s from 0.45 s, out of sight
    past about 100 deg) while the right hand pushes the bag about 11 px left and 14 px up and
    turns it 5 deg clockwise. The right hand's fingers follow the folding part's edge onto the
    crease; the lower left hand's lie over the lower left part. It holds folded 0.5 s and snaps
    back open fast (0.26 s, from 1.55 s); the hands leave the way they came.
``shag_tail_turn``
    A furry, low-contrast stuffed-toy patch of caramel shaggy faux fur (``shaggy_locks_plush``:
    long wavy locks, darker at the root and lighter at the tip, flowing in slow waves over a
    soft mottled ground; a few per cent of contrast; a sheen material, dark brown felt behind),
    lying right of and above the middle (``SHAG_AT``) and farther from the camera than the
    earlier plushes (``SHAG_DEPTH``, about 8 % smaller), is held by a hand at its upper left
    corner (its tail) and turned away from the camera about an axis rising 50 deg to the right
    (``SHAG_RISE``) through its lower right part (``SHAG_PIVOT``): the patch turns 20 deg about
    it and its part beyond a crease parallel to the axis, a little down and right of the middle
    (``SHAG_CREASE``; 64 % of the patch), bends a further 100 deg over a band of 0.35, so that
    the tail turns to 120 deg (past edge-on: its painted side turns away, behind the rest). It
    turns fast (0.55 s, from 0.35 s), holds 0.7 s and turns back slowly (1.2 s) while it drifts
    about 19 px left and 9 px down and part of the way back. The hand comes in along the axis
    from the upper right, holds the corner (moved with it frame by frame) and leaves the same
    way.
``board_corner_flutter``
    A printed snakes-and-ladders game board (``game_board``: a 10 x 10 board of numbered
    squares in six bright colours, numbered back and forth from the bottom left, brown
    ladders with rungs, green and orange snakes with diamond markings, heads and tongues, a
    title band and a cream margin with stars; its back plain card), left of and below the
    middle (``BOARD_AT``) and farther from the camera than the earlier sheets (``BOARD_DEPTH``,
    about 10 % smaller): its top right corner (``BOARD_ANGLE``, ``BOARD_CREASE``: beyond a
    crease falling to the right at 55 deg; 25 % of the board) folds over onto the rest by 180
    deg, towards the camera, over a band of 0.14 (its plain back covering about 16 % more of
    the print), in 0.55 s; it half opens back to 95 deg (0.35 s) and folds over again (0.35 s),
    holds 0.35 s and unfolds (0.7 s) while the board slides about 30 px right and 14 px down
    and turns 7 deg anticlockwise.
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
from hardclips.heldout_folds6 import _outlined_text
from hardclips.materials import studio_lights
from hardclips.scene import Clip
from hardclips.sheet import add_sheet, deg, finish_sheet
from hardclips.video import srgb_to_linear

# --- paint ----------------------------------------------------------------------------------

MAGENTA = (0.86, 0.12, 0.48)  # the gummy bag's stripes (sRGB)
TANGERINE = (0.99, 0.52, 0.12)
GUMMY_FILM = (0.80, 0.80, 0.83)  # the film's silvery inside: the bag's back and rim (sRGB)
GUMMY_COLOURS = np.array(
    [
        (0.86, 0.08, 0.10),  # red
        (0.98, 0.48, 0.05),  # orange
        (0.98, 0.85, 0.12),  # yellow
        (0.30, 0.75, 0.15),  # green
        (0.95, 0.92, 0.86),  # clear (pineapple)
        (0.55, 0.05, 0.25),  # raspberry
    ]
)


def _gummy_bear(image, centre, size, turn, colour):
    """A translucent gummy bear (head, ears, belly, arms and legs), lit from the upper left."""
    c, s = math.cos(turn), math.sin(turn)
    parts = [  # (x, y) in bear units (y down), radii (a, b)
        ((0.0, -0.62), (0.34, 0.3)),  # head
        ((-0.26, -0.86), (0.12, 0.12)),  # ears
        ((0.26, -0.86), (0.12, 0.12)),
        ((0.0, 0.05), (0.38, 0.48)),  # belly
        ((-0.4, -0.12), (0.14, 0.22)),  # arms
        ((0.4, -0.12), (0.14, 0.22)),
        ((-0.24, 0.52), (0.17, 0.2)),  # legs
        ((0.24, 0.52), (0.17, 0.2)),
    ]
    colour = np.asarray(colour)
    for grow, tone in ((1.12, 0.55), (1.0, 0.85), (0.7, 1.0)):
        for (x, y), (a, b) in parts:
            at = centre + size * np.array((c * x - s * y, s * x + c * y))
            if tone == 1.0:  # the inside glows: a lighter core, off towards the light
                at = at - 0.08 * size
            cv2.ellipse(
                image,
                (round(at[0] * 16), round(at[1] * 16)),
                (round(a * grow * size * 16), round(b * grow * size * 16)),
                math.degrees(turn),
                0,
                360,
                np.clip(colour * tone + (0.08 if tone == 1.0 else 0), 0, 1).tolist(),
                -1,
                cv2.LINE_AA,
                shift=4,
            )
    at = centre + size * np.array((c * -0.12 - s * -0.72, s * -0.12 + c * -0.72))
    cv2.circle(image, tuple(np.round(at).astype(int)), max(2, round(0.07 * size)), (1, 1, 1), -1)


def _star(image, centre, radius, colour):
    """A filled five-pointed star, in place."""
    angles = -math.pi / 2 + np.arange(10) * math.pi / 5
    radii = np.where(np.arange(10) % 2 == 0, radius, 0.42 * radius)
    points = np.asarray(centre) + np.column_stack([np.cos(angles), np.sin(angles)]) * radii[:, None]
    cv2.fillPoly(image, [np.round(points * 16).astype(np.int32)], list(colour), cv2.LINE_AA, 4)


def gummy_bag_print(rng, width, height):
    """The printed film of a bag of gummy bears: stripes, a clear window full of bears, a logo.

    Diagonal stripes of hot magenta and tangerine, softly shaded with a broad sheen; a big
    white wordmark outlined in purple across the top left and a yellow second word under it; a
    clear window (an oval, rimmed in white and purple) low and right of the middle showing a
    heap of about a hundred translucent gummy bears in six colours over the pale film; a blue
    ribbon with small print, lower left; a white roundel with "NEW" and stars, upper right; a
    barcode on a white panel, bottom left; sparkles; a crimped seal along the top.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    turn = math.radians(rng.uniform(25, 35))
    along = xs * math.cos(turn) + ys * math.sin(turn)
    stripe = 0.5 + 0.5 * np.tanh(6 * np.sin(2 * np.pi * along / rng.uniform(120, 140)))
    image = stripe[..., None] * np.array(MAGENTA) + (1 - stripe[..., None]) * np.array(TANGERINE)
    sheen = np.exp(
        -(((xs - 0.3 * width) / (0.35 * width)) ** 2 + ((ys - 0.4 * height) / height) ** 2)
    )
    image = image * (0.85 + 0.1 * fractal_noise(rng, shape, cells=(3, 6)))[..., None]
    image = image + 0.25 * sheen[..., None] * (1 - image)
    image = np.ascontiguousarray(image.astype(np.float32))
    purple = (0.30, 0.06, 0.40)
    white, yellow, blue = (1.0, 1.0, 1.0), (1.0, 0.88, 0.10), (0.10, 0.30, 0.75)
    # The window: a clear oval with a heap of bears, rimmed in white and purple.
    centre = np.array((0.62 * width, 0.64 * height))
    axes = (0.3 * width, 0.28 * height)
    window = np.zeros(shape, np.uint8)
    cv2.ellipse(
        window, tuple(np.round(centre).astype(int)), tuple(round(a) for a in axes), 0, 0, 360, 1, -1
    )
    bears = np.full((height, width, 3), 0.93, np.float32)
    for _ in range(110):
        r = math.sqrt(rng.uniform(0, 1))
        phi = rng.uniform(0, 2 * math.pi)
        at = centre + 1.05 * r * np.array((axes[0] * math.cos(phi), axes[1] * math.sin(phi)))
        colour = GUMMY_COLOURS[int(rng.integers(0, len(GUMMY_COLOURS)))] * rng.uniform(0.9, 1.05)
        _gummy_bear(bears, at, rng.uniform(32, 42), rng.uniform(-math.pi, math.pi), colour)
    inside = window.astype(bool)
    image[inside] = bears[inside]
    at, size = tuple(np.round(centre).astype(int)), tuple(round(a) for a in axes)
    cv2.ellipse(image, at, size, 0, 0, 360, white, 16, cv2.LINE_AA)
    cv2.ellipse(image, at, size, 0, 0, 360, purple, 5, cv2.LINE_AA)
    cv2.ellipse(image, at, (size[0] - 40, size[1] - 30), 0, 200, 250, white, 9, cv2.LINE_AA)
    # The wordmark, outlined, and the second word.
    name = "".join(rng.choice(list("BOUNCYGUMZ"), 6))
    _outlined_text(
        image, name, (int(0.04 * width), int(0.2 * height)), 3.2, (purple, white), (26, 10)
    )
    _outlined_text(
        image, "BEARS", (int(0.1 * width), int(0.36 * height)), 2.4, (purple, yellow), (22, 8)
    )
    # The roundel, upper right: white with a purple ring, NEW and three stars.
    badge = np.array((0.86 * width, 0.2 * height))
    cv2.circle(image, tuple(np.round(badge).astype(int)), 78, white, -1, cv2.LINE_AA)
    cv2.circle(image, tuple(np.round(badge).astype(int)), 70, purple, 5, cv2.LINE_AA)
    cv2.putText(
        image,
        "NEW",
        (int(badge[0] - 52), int(badge[1] + 14)),
        cv2.FONT_HERSHEY_DUPLEX,
        1.5,
        MAGENTA,
        4,
        cv2.LINE_AA,
    )
    for k in range(3):
        _star(image, badge + ((k - 1) * 34, -42 + 8 * abs(k - 1)), 12, TANGERINE)
    # The ribbon with small print, lower left, and the barcode under it.
    x0, y0 = int(0.03 * width), int(0.55 * height)
    ribbon = np.array([(x0, y0), (x0 + 300, y0 - 12), (x0 + 290, y0 + 60), (x0 - 6, y0 + 70)])
    cv2.fillPoly(image, [ribbon.astype(np.int32)], blue, cv2.LINE_AA)
    for k in range(2):
        cv2.putText(
            image,
            _random_text(rng, int(rng.integers(14, 20))),
            (x0 + 14, y0 + 24 + 28 * k),
            cv2.FONT_HERSHEY_SIMPLEX,
            0.7,
            white,
            2,
            cv2.LINE_AA,
        )
    _barcode(image, rng, (int(0.05 * width), int(0.76 * height)), (int(0.22 * width), 100))
    # Sparkles over the stripes, then the crimped seal along the top.
    for _ in range(40):
        at = rng.uniform((0, 0), (width, height))
        if inside[int(at[1]), int(at[0])]:
            continue
        r = rng.uniform(5, 12)
        for a in (0.0, math.pi / 2):
            d = r * np.array((math.cos(a), math.sin(a)))
            cv2.line(
                image,
                tuple(np.round(at - d).astype(int)),
                tuple(np.round(at + d).astype(int)),
                white,
                2,
                cv2.LINE_AA,
            )
    seal = int(0.07 * height)
    ridge = 0.88 + 0.14 * np.sin(2 * np.pi * np.arange(height, dtype=np.float32) / 7.0)
    image[:seal] = (image[:seal] * 0.7 + 0.3 * np.array(GUMMY_FILM)) * ridge[:seal, None, None]
    image = np.ascontiguousarray(image.astype(np.float32))
    cv2.line(image, (0, seal), (width, seal), purple, 3, cv2.LINE_AA)
    image *= (1 + 0.015 * rng.standard_normal((*shape, 1))).astype(np.float32)
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


CARAMEL = (0.70, 0.50, 0.30)  # the shaggy plush's caramel (sRGB)
UMBER_FELT = (0.09, 0.05, 0.025, 1.0)  # shag_tail_turn's back and rim (linear RGB)


def shaggy_locks_plush(rng, width, height):
    """Caramel shaggy faux fur: long wavy locks over a mottled ground, low contrast on purpose.

    A few hundred locks, each a tapering clump 14-28 texels wide and 130-260 long that follows
    a slowly waving flow (its direction drifts across the patch), with a shadow along its
    lower side, darker at the root and lighter at the tip, some 5-15 % from the ground (the
    later locks lie over the earlier ones); a soft mottled ground; fine hair along the flow.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    tone = fractal_noise(rng, shape, cells=(3, 6, 12, 24), falloff=0.7)
    flow = 1.1 + 0.9 * fractal_noise(rng, shape, cells=(2, 4))  # the locks' direction (rad)
    locks = np.zeros(shape, np.float32)
    steps = 12
    for _ in range(int(width * height / 2500)):
        x, y = rng.uniform(-80, width + 40), rng.uniform(-80, height + 40)
        length, thick = rng.uniform(130, 260), rng.uniform(14, 28)
        level = rng.uniform(-0.6, 0.6)
        wave = rng.uniform(0, 2 * math.pi)
        for k in range(steps):
            i = int(np.clip(y, 0, height - 1))
            j = int(np.clip(x, 0, width - 1))
            a = flow[i, j] + 0.4 * math.sin(k / 2.0 + wave)
            nx, ny = x + length / steps * math.cos(a), y + length / steps * math.sin(a)
            width_k = max(2, round(thick * (1 - 0.7 * k / steps)))
            value = level + 1.2 * (k / steps - 0.5)  # darker at the root, lighter at the tip
            for shift, colour in ((0.35 * width_k, -1.2), (0.0, value)):  # shadow, then lock
                a0 = (round((x - shift * math.sin(a)) * 16), round((y + shift * math.cos(a)) * 16))
                a1 = (
                    round((nx - shift * math.sin(a)) * 16),
                    round((ny + shift * math.cos(a)) * 16),
                )
                cv2.line(locks, a0, a1, float(colour), width_k, cv2.LINE_AA, shift=4)
            x, y = nx, ny
    locks = cv2.GaussianBlur(locks, (0, 0), 2.5)
    fine = hair_streaks(rng, shape, 11, angles=(55.0, 75.0))
    light = 1.0 + 0.07 * tone + 0.12 * locks + 0.025 * fine
    image = light[..., None] * np.array(CARAMEL) + 0.01 * rng.standard_normal((*shape, 3))
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.7), 0, 1)


BOARD_CARD = (0.90, 0.88, 0.83)  # the board's plain card back, and its rim (sRGB)
BOARD_INK = np.array(
    [
        (0.95, 0.30, 0.28),  # squares: red
        (0.99, 0.80, 0.20),  # yellow
        (0.35, 0.70, 0.95),  # sky blue
        (0.55, 0.82, 0.40),  # green
        (0.98, 0.60, 0.25),  # orange
        (0.78, 0.55, 0.90),  # lilac
    ]
)


def _snake(image, rng, head, tail, colour):
    """A wavy snake from ``head`` to ``tail``: outlined body, diamond markings, head, tongue."""
    head, tail = np.asarray(head, np.float64), np.asarray(tail, np.float64)
    d = tail - head
    n = np.array((-d[1], d[0])) / np.linalg.norm(d)
    t = np.linspace(0, 1, 80)
    wave = rng.uniform(35, 55) * np.sin(2 * np.pi * rng.uniform(1.2, 1.8) * t) * np.sin(np.pi * t)
    body = head + t[:, None] * d + wave[:, None] * n
    path = [np.round(body * 16).astype(np.int32)]
    dark = (np.asarray(colour) * 0.45).tolist()
    cv2.polylines(image, path, False, dark, 30, cv2.LINE_AA, 4)
    cv2.polylines(image, path, False, list(colour), 22, cv2.LINE_AA, 4)
    for k in range(4, 76, 6):  # diamonds along the back
        at, step = body[k], body[k + 1] - body[k - 1]
        step = step / np.linalg.norm(step)
        side = np.array((-step[1], step[0]))
        diamond = np.array([at + 9 * step, at + 6 * side, at - 9 * step, at - 6 * side])
        cv2.fillPoly(image, [np.round(diamond * 16).astype(np.int32)], dark, cv2.LINE_AA, 4)
    out = (body[0] - body[3]) / np.linalg.norm(body[0] - body[3])
    tip = body[0] + 28 * out
    cv2.line(
        image,
        tuple(np.round(tip).astype(int)),
        tuple(np.round(tip + 14 * out).astype(int)),
        (0.85, 0.1, 0.1),
        3,
        cv2.LINE_AA,
    )
    angle = math.degrees(math.atan2(out[1], out[0]))
    at = tuple(np.round(body[0] + 10 * out).astype(int))
    cv2.ellipse(image, at, (24, 17), angle, 0, 360, dark, -1, cv2.LINE_AA)
    cv2.ellipse(image, at, (20, 13), angle, 0, 360, list(colour), -1, cv2.LINE_AA)
    side = np.array((-out[1], out[0]))
    for s in (-1, 1):
        eye = tuple(np.round(body[0] + 14 * out + s * 7 * side).astype(int))
        cv2.circle(image, eye, 4, (1, 1, 1), -1, cv2.LINE_AA)
        cv2.circle(image, eye, 2, (0, 0, 0), -1, cv2.LINE_AA)


def _ladder(image, bottom, top):
    """A brown ladder from ``bottom`` to ``top``: two rails and rungs, in place."""
    bottom, top = np.asarray(bottom, np.float64), np.asarray(top, np.float64)
    d = top - bottom
    length = np.linalg.norm(d)
    n = np.array((-d[1], d[0])) / length * 15
    wood, edge = (0.62, 0.38, 0.16), (0.30, 0.17, 0.06)
    for k in range(1, int(length // 26)):
        at = bottom + d * k * 26 / length
        a, b = tuple(np.round(at - n).astype(int)), tuple(np.round(at + n).astype(int))
        cv2.line(image, a, b, edge, 7, cv2.LINE_AA)
        cv2.line(image, a, b, wood, 4, cv2.LINE_AA)
    for s in (-1, 1):
        a, b = tuple(np.round(bottom + s * n).astype(int)), tuple(np.round(top + s * n).astype(int))
        cv2.line(image, a, b, edge, 9, cv2.LINE_AA)
        cv2.line(image, a, b, wood, 5, cv2.LINE_AA)


def game_board(rng, width, height):
    """A printed snakes-and-ladders board: numbered squares, ladders, snakes, a title band.

    A cream margin with small stars round a 10 x 10 board whose squares take six bright
    colours in a shuffled pattern, each with its number (1 at the bottom left, back and forth
    up to 100 at the top left) in black; five brown ladders and five green, orange or purple
    snakes with darker diamond markings, heads with eyes and red tongues, drawn over the
    squares; a dark title band along the top with the game's name; paper grain.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    image = np.empty((height, width, 3), np.float32)
    image[:] = (0.97, 0.93, 0.82)
    margin, band = int(0.035 * width), int(0.09 * height)
    x0, y0 = margin, margin + band
    cw, ch = (width - 2 * margin) / 10, (height - y0 - margin) / 10
    cells = {}
    for row in range(10):  # from the bottom
        for col in range(10):
            number = 10 * row + (col if row % 2 == 0 else 9 - col) + 1
            left, top = x0 + col * cw, y0 + (9 - row) * ch
            colour = BOARD_INK[(col + 2 * row + int(rng.integers(0, 2))) % len(BOARD_INK)]
            a = (round(left), round(top))
            b = (round(left + cw), round(top + ch))
            cv2.rectangle(image, a, b, colour.tolist(), -1)
            cv2.rectangle(image, a, b, (0.15, 0.12, 0.1), 2)
            cv2.putText(
                image,
                str(number),
                (round(left + 6), round(top + 26)),
                cv2.FONT_HERSHEY_DUPLEX,
                0.75,
                (0.08, 0.06, 0.05),
                2,
                cv2.LINE_AA,
            )
            cells[number] = np.array((left + cw / 2, top + ch / 2))
    # Ladders (up) and snakes (down) between squares some rows apart.
    for _ in range(5):
        low = int(rng.integers(2, 60))
        high = min(99, low + int(rng.integers(18, 40)))
        _ladder(image, cells[low] + rng.uniform(-10, 10, 2), cells[high] + rng.uniform(-10, 10, 2))
    snake_colours = [(0.25, 0.65, 0.20), (0.95, 0.55, 0.10), (0.50, 0.25, 0.65)]
    for k in range(5):
        high = int(rng.integers(40, 99))
        low = max(2, high - int(rng.integers(22, 45)))
        _snake(image, rng, cells[high], cells[low], snake_colours[k % 3])
    # The title band and the stars in the margin.
    cv2.rectangle(image, (margin, margin), (width - margin, y0), (0.12, 0.18, 0.42), -1)
    _outlined_text(
        image,
        "SNAKES & LADDERS",
        (margin + 40, y0 - int(0.022 * height)),
        1.6,
        ((0.99, 0.80, 0.20), (0.99, 0.99, 0.97)),
        (9, 3),
    )
    for _ in range(30):
        edge = int(rng.integers(0, 4))
        u = rng.uniform(0.03, 0.97)
        at = [
            (u * width, margin / 2),
            (u * width, height - margin / 2),
            (margin / 2, u * height),
            (width - margin / 2, u * height),
        ][edge]
        _star(image, at, rng.uniform(6, 11), BOARD_INK[int(rng.integers(0, 6))] * 0.8)
    cv2.rectangle(image, (x0, y0), (width - margin, height - margin), (0.1, 0.08, 0.06), 4)
    image *= (1 + 0.02 * fractal_noise(rng, shape, cells=(4, 8, 16)))[..., None].astype(np.float32)
    image *= (1 + 0.012 * rng.standard_normal(shape)).astype(np.float32)[..., None]
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


# --- scenes ---------------------------------------------------------------------------------

GUMMY_SIZE = (2.0, 1.5)
GUMMY_AT = (-0.6, 0.28)  # gummy_bag_squeeze: the bag's centre at rest, left of and above
GUMMY_DEPTH = 0.5  # how much nearer the camera than the other sheets' rest plane it lies
GUMMY_ANGLE = -20.0  # the fold's direction (deg from +X: right, a little down)
GUMMY_CREASE = 0.1  # the crease's distance from the bag's centre along that direction
GUMMY_BAND = 0.2  # folded, the right part lies 2 * band / pi behind the rest
GUMMY_LOWER = 230.0  # the lower hand comes in along this direction (deg from +X, bag frame)
GUMMY_FOLD = (0.45, 1.55)  # when it starts to fold and to unfold (s)


def build_gummy_bag_squeeze(rng, clip):
    studio_lights()
    size = GUMMY_SIZE
    sheet = add_sheet(
        gummy_bag_print,
        size,
        (80, 60),
        4,
        rng=rng,
        roughness=0.3,
        specular=0.55,
        coat=0.2,
        thickness=0.02,
    )
    angle = math.radians(GUMMY_ANGLE)
    d = np.array((math.cos(angle), math.sin(angle)))  # the fold's direction, right
    # The right part folds back about the crease leaning 20 deg from the vertical.
    crease_bend(sheet, "Fold", size, angle, GUMMY_CREASE, GUMMY_BAND, diagonal_away)
    # The fold (keyed on every frame): over at a medium pace (0.58 s), snapping back (0.26 s).
    # The right hand pushes the bag left and a little up and turns it 5 deg clockwise.
    t = np.arange(clip.frames) / clip.fps
    fold_at, unfold_at = GUMMY_FOLD
    fold = fold_and_unfold(t, fold_at, t[-1] + 1.0, paced_fold(4.5, 12.0, 60.0))
    snap = fold_and_unfold(t, -10.0, unfold_at, paced_fold(10.0, 25.0, 300.0))
    fold = np.where(t < unfold_at, fold, snap)
    x0, y0 = GUMMY_AT
    z0 = GUMMY_DEPTH
    sheet.obj.location = (x0, y0, z0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): list(zip(t, fold, strict=True)),
            ("location", 0): [(0.0, x0), (0.4, x0), (1.0, x0 - 0.11), (2.8, x0 - 0.05)],
            ("location", 1): [(0.0, y0), (0.4, y0), (1.0, y0 + 0.07), (2.8, y0 + 0.02)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.4, 0), (1.0, -5), (2.8, -2)]),
        },
    )
    # The hands come in in front of the bag and move with it: the right one, its fingers
    # (pointing left) over the right part and then, following its edge as it folds back, onto
    # the crease; the lower left one, its fingers (pointing up and right) over the lower left
    # part. Where their fingertips are: how far out from the bag's centre along the direction
    # they come in from (for the right hand, the larger of the keys and the folding edge), and
    # how far across it (bag frame).
    edge = min(size[0] / 2 / abs(d[0]), size[1] / 2 / abs(d[1]))  # the right edge, along d
    folding_edge = GUMMY_CREASE + np.maximum((edge - GUMMY_CREASE) * np.cos(fold) - 0.25, -0.2)
    right_tips = [
        (0.0, 4.4),
        (0.05, 4.4),
        (0.4, 0.6),
        (0.95, GUMMY_CREASE - 0.2),
        (unfold_at, GUMMY_CREASE - 0.2),
        (2.1, 0.7),
        (3.0, 4.4),
    ]
    lower_tips = [
        (0.0, 4.4),
        (0.1, 4.4),
        (0.45, 0.75),
        (1.0, 0.68),
        (unfold_at, 0.68),
        (2.2, 0.75),
        (3.2, 4.4),
    ]
    side = math.radians(GUMMY_LOWER)
    matrices = object_matrices(clip, sheet.obj)
    for name, reach, out, across in (
        ("RightHand", np.maximum(eased(t, right_tips), folding_edge), d, 0.1),
        ("LowerHand", eased(t, lower_tips), np.array((math.cos(side), math.sin(side))), -0.1),
    ):
        hand = add_pushing_hand(name, False)
        normal = np.array((-out[1], out[0]))
        poses = []
        for m, r in zip(matrices, reach, strict=True):
            local = r * out + across * normal
            tip = m[:3, :3] @ (*local, 0.0) + m[:3, 3]
            tip[2] = z0 + HAND_DEPTH
            fingers = m[:3, :3] @ (*(-out), 0.0)
            poses.append(hand_pose(tip, fingers, (0.0, 0.0, 1.0)))
        key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(GUMMY_FILM)), 1.0))
    return sheet


SHAG_SIZE = (1.8, 1.5)
SHAG_AT = (0.6, 0.3)  # shag_tail_turn: the patch's centre at rest, right of and above
SHAG_DEPTH = -0.5  # how much nearer the camera than the other sheets' rest plane (farther)
SHAG_RISE = 50.0  # the turning axis: deg from the horizontal, rising to the right
SHAG_PIVOT = -0.5  # the axis's distance from the centre, across it (to the lower right)
SHAG_CREASE = -0.2  # where the tail's bend starts, likewise (down and right of the centre)
SHAG_BAND = 0.35  # the length of the tail's bend
SHAG_INSET = 0.2  # the hand's fingertips: how far inside the upper left corner, across


def build_shag_tail_turn(rng, clip):
    studio_lights()
    size = SHAG_SIZE
    rise = math.radians(SHAG_RISE)
    up = np.array((math.cos(rise), math.sin(rise)))  # along the axis, up and right
    across = np.array((-math.sin(rise), math.cos(rise)))  # up and left, towards the tail
    sheet, pivot = plush_on_pivot(
        rng, shaggy_locks_plush, size, (72, 60), 0.0, (0.55, 0.4, (0.98, 0.85, 0.7, 1.0))
    )
    # The pivot: the axis through the lower right part, pointing down and left, so that
    # turning about it by a positive angle takes the part beyond it (to the upper left) away
    # from the camera.
    at = np.array(SHAG_AT) + SHAG_PIVOT * across
    z0 = SHAG_DEPTH
    pivot.location = (*at, z0)
    pivot.rotation_mode = "AXIS_ANGLE"
    pivot.rotation_axis_angle = (0.0, *(-up), 0.0)
    sheet.obj.location = (*(-SHAG_PIVOT * across), 0.0)
    # The soft toy gives where it is held: the tail (beyond SHAG_CREASE, towards the upper
    # left corner) bends further away over a band of SHAG_BAND, so that the patch turns 20 deg
    # and the tail 120 deg, past edge-on, behind the rest.
    angle = math.atan2(across[1], across[0])
    crease_bend(sheet, "Tail", size, angle, SHAG_CREASE, SHAG_BAND, diagonal_away)
    # Fast away (0.55 s), a long hold (0.7 s), slowly back (1.2 s), drifting left and down.
    start, top, back, flat = 0.35, 0.9, 1.6, 2.8
    clip.keyframe(
        pivot,
        {
            ("rotation_axis_angle", 0): deg(
                [(0.0, 0), (start, 0), (top, 20), (back, 20), (flat, 0)]
            ),
            ("location", 0): [
                (0.0, at[0]),
                (start, at[0]),
                (1.6, at[0] - 0.2),
                (3.3, at[0] - 0.08),
            ],
            ("location", 1): [
                (0.0, at[1]),
                (start, at[1]),
                (1.6, at[1] - 0.1),
                (3.3, at[1] - 0.04),
            ],
        },
    )
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Tail"].angle', 0): deg(
                [(0.0, 0), (start, 0), (top, 100), (back, 100), (flat, 0)]
            )
        },
    )
    # The hand holds the upper left corner (the tail's end): its fingers (pointing down and
    # left, along the axis) lie over the corner SHAG_INSET inside it, its back away from the
    # painted side; moved with the corner on every frame, its forearm stays along the axis,
    # out to the upper right above the patch's top edge. It comes in along the axis and
    # leaves the same way.
    grids = sheet_frames(clip, sheet)
    t = np.arange(clip.frames) / clip.fps
    away = eased(t, [(0.0, 3.5), (0.05, 3.5), (0.33, 0.0), (2.85, 0.0), (3.3, 3.5)])
    hand = add_pushing_hand("Hand", True)
    poses = []
    for grid, out in zip(grids, away, strict=True):
        corner = grid[0, 0]
        along_x = grid[0, 2] - corner
        along_y = corner - grid[2, 0]
        along_x, along_y = along_x / np.linalg.norm(along_x), along_y / np.linalg.norm(along_y)
        normal = np.cross(along_x, along_y)
        a = up[0] * along_x + up[1] * along_y
        n = across[0] * along_x + across[1] * along_y
        tips = corner + out * a - SHAG_INSET * n + 0.13 * normal
        poses.append(hand_pose(tips, -a, normal))
    key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, UMBER_FELT)
    return sheet


BOARD_SIZE = (2.7, 2.2)
BOARD_AT = (-0.45, -0.3)  # board_corner_flutter: the board's centre at rest, left and below
BOARD_DEPTH = -0.7  # how much nearer the camera than the other sheets' rest plane (farther)
BOARD_ANGLE = 35.0  # the fold's direction (deg from +X: up and right, to the corner)
BOARD_CREASE = 0.6  # the crease's distance from the centre along that direction
BOARD_BAND = 0.14  # folded, the corner lies 2 * band / pi in front


def build_board_corner_flutter(rng, clip):
    studio_lights()
    size = BOARD_SIZE
    sheet = add_sheet(
        game_board,
        size,
        (72, 60),
        4,
        rng=rng,
        roughness=0.6,
        specular=0.35,
        thickness=0.008,
    )
    # The top right corner folds over onto the rest, towards the camera, about a crease
    # falling to the right at 55 deg; folded, it lies about 0.09 in front, its plain back to
    # the camera.
    angle = math.radians(BOARD_ANGLE)
    crease_bend(sheet, "Fold", size, angle, BOARD_CREASE, BOARD_BAND, diagonal_towards_camera)
    # Over in 0.55 s, half open again to 95 deg (0.35 s) and over again (0.35 s), held 0.35 s,
    # unfolded in 0.7 s; meanwhile the board slides right and a little down and turns 7 deg
    # anticlockwise.
    x0, y0 = BOARD_AT
    sheet.obj.location = (x0, y0, BOARD_DEPTH)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): deg(
                [
                    (0.0, 0),
                    (0.25, 0),
                    (0.8, 180),
                    (0.9, 180),
                    (1.25, 95),
                    (1.6, 180),
                    (1.95, 180),
                    (2.65, 0),
                ]
            ),
            ("location", 0): [(0.0, x0), (0.7, x0), (2.3, x0 + 0.32), (3.3, x0 + 0.3)],
            ("location", 1): [(0.0, y0), (0.7, y0), (2.3, y0 - 0.11), (3.3, y0 - 0.1)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.7, 0), (2.3, 7), (3.3, 6)]),
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(BOARD_CARD)), 1.0))
    return sheet


HELDOUT_FOLDS7 = [
    Clip(
        "gummy_bag_squeeze",
        100,
        30,
        "two hands, in from the right and from the lower left, squeeze a glossy bag of gummy "
        "bears lying left of and above the middle, nearer the camera (about 9 % larger): its "
        "right part (45 %) folds back behind the rest about a crease leaning 20 deg from the "
        "vertical, at a medium pace (0.58 s), while the right hand pushes it about 11 px left "
        "and 14 px up and turns it 5 deg; holds 0.5 s with the right hand over the crease and "
        "the lower hand over the lower left part, snaps back open fast (0.26 s); the hands "
        "leave",
        build_gummy_bag_squeeze,
    ),
    Clip(
        "shag_tail_turn",
        100,
        30,
        "a furry, low-contrast caramel shaggy plush patch with long wavy locks, right of and "
        "above the middle and farther from the camera (about 8 % smaller), held by a hand at "
        "its upper left corner (its tail), is turned away from the camera fast (0.55 s) about "
        "an axis rising 50 deg to the right through its lower right part: the patch turns 20 "
        "deg, its upper left part (64 %) on to 120 deg, past edge-on (painted side turned away, "
        "behind the rest); holds 0.7 s, turns back slowly (1.2 s) while it drifts about 19 px "
        "left and 9 px down; the hand leaves",
        build_shag_tail_turn,
    ),
    Clip(
        "board_corner_flutter",
        100,
        30,
        "the top right corner (25 %) of a printed snakes-and-ladders board, left of and below "
        "the middle and farther from the camera (about 10 % smaller), folds over onto the rest "
        "by 180 deg, towards the camera, about a crease falling 55 deg to the right (0.55 s; "
        "its plain back covers about 16 % more of the print), half opens to 95 deg and folds "
        "over again (0.35 s each), holds 0.35 s and unfolds (0.7 s) while the board slides "
        "about 30 px right and 14 px down and turns 7 deg",
        build_board_corner_flutter,
    ),
]


README_HELDOUT_FOLDS7 = (
    """# Held-out clips of folds, seventh batch

Clips for checking that the tracker generalises to folds (issue 22): never tune it on these;
they are to be measured once, as held-out. The tracker was tuned on the fold clips of
[`../folds`](../folds/README.md); like the first six held-out batches
([`../heldout_folds`](../heldout_folds/README.md),
[`../heldout_folds2`](../heldout_folds2/README.md),
[`../heldout_folds3`](../heldout_folds3/README.md),
[`../heldout_folds4`](../heldout_folds4/README.md),
[`../heldout_folds5`](../heldout_folds5/README.md) and
[`../heldout_folds6`](../heldout_folds6/README.md)) these show the same kinds of motion (a
soft bag squeezed until part of it folds back, a soft patch turned past edge-on by its tail, a
part folded over the rest) with paint, axes, speeds, places and distances from the camera that
no earlier batch has: a glossy bag of gummy bears, nearer the camera, whose right part folds
back about a crease leaning from the vertical under hands in from the right and the lower left
and snaps back open; a caramel shaggy plush, farther away, turned away from the camera by its
upper left corner about an axis rising 50 deg to the right, fast, held long and let back
slowly; a snakes-and-ladders board, farther away, whose top right corner folds over, half
opens and folds over again before it unfolds while the board slides. Rendered with Blender
{blender} (the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes and paint in
`scripts/hardclips/heldout_folds7.py`) from a fixed seed, so the same command makes the same
scenes, truth and outlines; it makes them only when named, apart from every other clip:

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \\
        --out samples/heldout_folds7 --only {names}

Keep them out of `samples/folds` and `samples/heldout_folds` to `samples/heldout_folds6`.
Check them with `.venv/bin/python scripts/check_hard_clips.py --dir samples/heldout_folds7`
(statistics, and contact sheets in `/tmp/hard_check/`).

"""
    + FOLD_FILES
)
