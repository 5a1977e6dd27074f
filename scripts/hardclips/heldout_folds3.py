"""A third batch of held-out clips of folds: new paint, axes, speeds and places, never tuned on.

The tracker was tuned on the fold clips of ``folds`` (``samples/folds``); the held-out batches
(``heldout_folds``, ``heldout_folds2`` and this one, in ``samples/heldout_folds``,
``samples/heldout_folds2`` and ``samples/heldout_folds3``) check that it generalises and are
never to be tuned on. This batch was made for issue 22's generalisation check. ``HELDOUT_FOLDS3``
lists it. ``render_hard_clips.py`` makes these clips only when asked by name, into a folder of
their own (``samples/heldout_folds3``), apart from every other clip::

    .venv/bin/python scripts/render_hard_clips.py --out samples/heldout_folds3 --only NAME ...

Each writes the files of a single-sheet hard clip (``NAME.mp4``, ``NAME.json``,
``NAME_truth.npz``) with the conventions of ``folds``: frame 0 flat and square to the camera,
at rest for three frames; every crease runs through the outlined region; the folds are
SimpleDeform bends over a band at the crease (``fold_limits``), so a folded part never passes
through the rest. The paint is here (``foil_bag_print``, ``slate_plush``, ``shirt_graphic``).
Unlike the earlier batches, the sheets do not all start in the middle of the image, the creases
and the turning axis are diagonal, and the hands are moved with the sheet frame by frame.

``bag_fold_hands``
    A soft foil snack bag (``foil_bag_print``: brushed, crinkled silver foil under teal ink, a
    big italic wordmark, a round logo, a photo of crisps in a window, small print and a plain
    unprinted band along the bottom; glossy, part metallic), lying right of and above the
    middle (``BAG_AT``), is squeezed by two hands that come in diagonally, from the upper left
    and the lower right, in front of it. It bows a little along the crease and its upper left
    part (46 %) folds back behind the rest along a diagonal crease through the middle
    (``BAG_ANGLE``: the crease runs steeply from the bottom edge left of the centre up to the
    top edge right of it), in 0.45 s from 0.4 s (90 deg after 0.25 s; past about 100 deg it is
    out of sight), while the upper hand pushes the bag about 17 px down and right and turns it
    4 deg. Folded back, the part sticks out below the rest, showing its bare foil back. The
    logo, on the lower right part, stays in view. The upper hand's fingers follow the folding
    part onto the crease, the lower hand's lie over the lower right corner; it holds folded
    for 0.45 s, unfolds (from 1.3 s, flat by 1.75 s) and the hands leave along the diagonal.
``toy_tail_lift``
    A furry, low-contrast stuffed-toy patch, grey-blue with faint slate stripes and pale spots
    (``slate_plush``: fur drawn as thousands of short brush strokes along a combed flow,
    unlike the smeared-noise hair of the other plush paints; a sheen material, dark slate felt
    behind), lying left of the middle, is held by a hand at its lower right corner and turned
    away from the camera about an axis tilted 30 deg from the vertical (``LIFT_AXIS``, through
    its left part, ``LIFT_PIVOT``): the patch turns 50 deg about it and, being soft, its part
    beyond a crease left of the middle parallel to the axis (``LIFT_CREASE``, 62 %) bends a
    further 55 deg over a band of 0.4, so that the far part (38 %) turns to 105 deg (past
    edge-on: its painted side turns away, ``visible`` false). It turns slowly (1.3 s, from
    0.4 s), holds 0.25 s and turns back (in 0.95 s) while it drifts about 25 px left and 12 px
    up and most of the way back. The hand comes in along its forearm from the upper right
    (0.1 to 0.4 s), holds the corner (moved with the corner frame by frame, it rolls about its
    forearm, which stays along the axis, as the corner turns) and leaves the same way (2.95 to
    3.4 s).
``shirt_fold_print``
    A cotton cloth with a big t-shirt print (``shirt_graphic``: a forest green basket-weave
    cloth under a cracked screen print of a mountain badge with arched lettering, a sun, a
    band of diagonal stripes and a bold wordmark), lying right of the middle: its top part
    (37 %, above ``SHIRT_CREASE``: as much as keeps 0.4 of the print in sight) folds down 180
    deg over its print, towards the camera, about a crease tilted 9 deg (``SHIRT_TILT``), in a
    soft loop (over a band of 0.3; the flap lies about 0.19 in front), its plain back covering
    about 20 % more of the print below the crease. It folds slowly (in 1.05 s, from 0.15 s),
    holds 0.45 s and unfolds faster (in 0.95 s) while the cloth slides about 47 px to the left
    and a third of the way back and turns 2 deg.
"""

import math

import bpy

# isort: split
import cv2
import numpy as np
from foam_paint import smooth_noise  # scripts/ is on sys.path when a script runs
from hard_textures import _random_text, fractal_noise
from mathutils import Matrix

from hardclips.folds import (
    FOLD_FILES,
    HAND_REACH,
    add_pushing_hand,
    fold_and_unfold,
    fold_limits,
    paced_fold,
    plush_on_pivot,
    set_back_colour,
)
from hardclips.heldout_folds import diagonal_away, diagonal_towards_camera
from hardclips.materials import studio_lights
from hardclips.scene import Clip
from hardclips.sheet import add_sheet, bend, deform_origin, deg, finish_sheet, set_sheen
from hardclips.truth import evaluated_grid
from hardclips.video import srgb_to_linear


def extent_along(size, angle):
    """The sheet's extent along the in-plane direction ``angle`` (radians), for fold_limits."""
    return size[0] * abs(math.cos(angle)) + size[1] * abs(math.sin(angle))


def crease_bend(sheet, name, size, angle, crease, band, turn):
    """Bend ``sheet`` (its modifier ``name``) about a crease across the direction ``angle``.

    The crease lies ``crease`` from the centre along ``(cos angle, sin angle)``; the part beyond
    it bends over a band of ``band``, towards the camera or away as ``turn`` says
    (``diagonal_towards_camera`` or ``diagonal_away``).
    """
    d = np.array((math.cos(angle), math.sin(angle)))
    origin = deform_origin(sheet, (*(crease * d), 0.0), turn(angle))
    bend(sheet, name, origin, limits=fold_limits(extent_along(size, angle), crease, band))


def eased(t, keys):
    """Values at times ``t`` (s) eased (cosine) between ``keys`` [(seconds, value), ...].

    Every key is reached at rest, like Blender's auto-clamped Bezier keys; before the first
    key and after the last the value holds.
    """
    seconds = np.array([k[0] for k in keys], np.float64)
    values = np.array([k[1] for k in keys], np.float64)
    t = np.clip(np.asarray(t, np.float64), seconds[0], seconds[-1])
    i = np.clip(np.searchsorted(seconds, t, side="right") - 1, 0, len(keys) - 2)
    u = (t - seconds[i]) / (seconds[i + 1] - seconds[i])
    w = 0.5 - 0.5 * np.cos(np.pi * u)
    return values[i] + w * (values[i + 1] - values[i])


def key_every_frame(clip, target, poses):
    """Key ``target``'s location and quaternion on every frame from ``poses`` [(loc, quat)]."""
    target.rotation_mode = "QUATERNION"
    channels = {("location", k): [] for k in range(3)}
    channels.update({("rotation_quaternion", k): [] for k in range(4)})
    previous = None
    for frame, (location, quaternion) in enumerate(poses):
        q = np.array(quaternion, np.float64)
        if previous is not None and np.dot(q, previous) < 0:
            q = -q  # the same rotation, without a flip between frames
        previous = q
        seconds = frame / clip.fps
        for k in range(3):
            channels[("location", k)].append((seconds, float(location[k])))
        for k in range(4):
            channels[("rotation_quaternion", k)].append((seconds, float(q[k])))
    clip.keyframe(target, channels)


def sheet_frames(clip, sheet):
    """The sheet's evaluated grid (world coordinates) on every frame: (T, rows+1, cols+1, 3).

    Evaluated from its keyframes and deformers as they are when called; leaves the scene on
    its first frame.
    """
    scene = bpy.context.scene
    index = sheet.grid_index()
    grids = []
    for frame in range(clip.frames):
        scene.frame_set(scene.frame_start + frame)
        grids.append(evaluated_grid(sheet, bpy.context.evaluated_depsgraph_get(), index)[1])
    scene.frame_set(scene.frame_start)
    return np.array(grids)


def hand_pose(tips, fingers, back):
    """(location, quaternion) of an ``add_pushing_hand`` hand whose fingertips are at ``tips``.

    ``fingers`` is the direction its fingers point in and ``back`` the direction the back of
    the hand faces (both world, roughly at right angles); the palm's centre is HAND_REACH
    behind the tips.
    """
    y = np.asarray(fingers, np.float64)
    y = y / np.linalg.norm(y)
    z = np.asarray(back, np.float64) - np.dot(back, y) * y
    z = z / np.linalg.norm(z)
    x = np.cross(y, z)
    rotation = Matrix(np.column_stack([x, y, z]).tolist())
    return np.asarray(tips) - HAND_REACH * y, tuple(rotation.to_quaternion())


# --- paint ----------------------------------------------------------------------------------

FOIL = (0.80, 0.81, 0.84)  # bare silver foil: the plain band, the bag's back and rim (sRGB)
BAG_INK = np.array(
    [
        (0.02, 0.42, 0.44),  # teal
        (0.98, 0.86, 0.18),  # lemon
        (0.90, 0.16, 0.36),  # raspberry
        (0.97, 0.97, 0.95),  # white
        (0.05, 0.06, 0.10),  # near black
    ]
)


def _crisps_photo(rng, height, width):
    """A photo of a heap of crisps on a warm, out-of-focus table. (H, W, 3) float32 sRGB."""
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    fade = (ys / height)[..., None]
    image = (1 - fade) * np.array((0.45, 0.30, 0.22)) + fade * np.array((0.72, 0.52, 0.34))
    for _ in range(10):  # bokeh: soft bright discs behind
        cx, cy = rng.uniform(0, width), rng.uniform(0, 0.5 * height)
        r = rng.uniform(0.05, 0.15) * width
        weight = np.clip(1.5 - np.hypot(xs - cx, ys - cy) / r, 0, 1)[..., None] * 0.5
        image = (1 - weight) * image + weight * np.array((0.95, 0.82, 0.6))
    image = np.ascontiguousarray(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 6.0))
    for _ in range(34):  # crisps: wavy discs, shaded, with seasoning specks, piled low to high
        cx = rng.uniform(0.05, 0.95) * width
        cy = rng.uniform(0.35, 1.05) * height
        rx, ry = rng.uniform(0.07, 0.13) * width, rng.uniform(0.05, 0.1) * height
        turn = rng.uniform(0, np.pi)
        angles = np.linspace(0, 2 * np.pi, 40, endpoint=False)
        wobble = 1 + 0.12 * np.sin(3 * angles + rng.uniform(0, 6)) + rng.normal(0, 0.03, 40)
        px = rx * wobble * np.cos(angles)
        py = ry * wobble * np.sin(angles)
        corners = np.column_stack(
            [cx + px * np.cos(turn) - py * np.sin(turn), cy + px * np.sin(turn) + py * np.cos(turn)]
        )
        poly = np.round(corners * 16).astype(np.int32).reshape(-1, 1, 2)
        shadow = poly + np.array([[[5 * 16, 7 * 16]]], np.int32)
        cv2.fillPoly(image, [shadow], (0.25, 0.15, 0.08), cv2.LINE_AA, shift=4)
        tone = rng.uniform(0.85, 1.05)
        cv2.fillPoly(image, [poly], (0.93 * tone, 0.70 * tone, 0.28 * tone), cv2.LINE_AA, shift=4)
        cv2.polylines(image, [poly], True, (0.7, 0.45, 0.15), 2, cv2.LINE_AA, shift=4)
        for _ in range(int(rng.integers(4, 10))):  # specks of seasoning
            u, v = rng.uniform(-0.7, 0.7, 2)
            c = (int(cx + u * rx), int(cy + v * ry))
            cv2.circle(image, c, int(rng.integers(1, 4)), (0.45, 0.25, 0.1), -1, cv2.LINE_AA)
    shine = 0.06 * smooth_noise(rng, (height, width), 3)[..., None]  # light falling unevenly
    return cv2.GaussianBlur((image * (1 + shine)).astype(np.float32), (0, 0), 1.2)


def foil_bag_print(rng, width, height):
    """The printed front of a foil snack bag: teal ink over foil, wordmark, logo, a photo.

    Brushed and crinkled silver foil shows through the translucent teal ink (which darkens
    towards the top); a big italic wordmark with a lemon swoosh across the upper part, a
    raspberry round logo lower right, a window with a photo of crisps on the left, lines of
    small print and a net weight, and along the bottom a plain band of bare foil (no print,
    no grain).
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    # The foil: horizontal brushing (noise smeared along x) and crinkles (ridges of noise).
    grain = rng.standard_normal(shape).astype(np.float32)
    brushed = cv2.GaussianBlur(grain, (0, 0), sigmaX=18.0, sigmaY=0.7)
    brushed /= brushed.std()
    crinkle = 1 - np.abs(fractal_noise(rng, shape, cells=(6, 12, 24), falloff=0.7))
    foil = 0.9 + 0.05 * brushed + 0.12 * (crinkle**6 - 0.2)  # (H, W) about 0.9
    ink = (0.75 + 0.35 * ys / height)[..., None] * BAG_INK[0]  # darker at the top
    image = foil[..., None] * (0.15 + 0.85 * ink)  # ink lets some foil through
    image = np.ascontiguousarray(image.astype(np.float32))
    # The photo window, on the left, with a white frame.
    x0, y0, x1, y1 = (int(v) for v in (0.05 * width, 0.44 * height, 0.42 * width, 0.82 * height))
    image[y0:y1, x0:x1] = _crisps_photo(rng, y1 - y0, x1 - x0)
    cv2.rectangle(image, (x0, y0), (x1, y1), BAG_INK[3].tolist(), 6, cv2.LINE_AA)
    # A lemon swoosh and the wordmark, italic and outlined, across the upper part.
    t = np.linspace(0, 1, 60)
    swoosh = np.column_stack(
        [(0.04 + 0.9 * t) * width, (0.36 - 0.12 * np.sin(np.pi * t) - 0.06 * t) * height]
    )
    path = np.round(swoosh * 16).astype(np.int32).reshape(-1, 1, 2)
    cv2.polylines(image, [path], False, BAG_INK[1].tolist(), 22, cv2.LINE_AA, shift=4)
    word = _random_text(rng, 6).replace(" ", "") + "!"
    org = (int(0.06 * width), int(0.27 * height))
    font = cv2.FONT_HERSHEY_TRIPLEX | cv2.FONT_ITALIC
    for colour, thickness in ((BAG_INK[4], 24), (BAG_INK[3], 12)):
        cv2.putText(image, word, org, font, 4.6, colour.tolist(), thickness, cv2.LINE_AA)
    flavour = _random_text(rng, 16)
    cv2.putText(
        image,
        flavour,
        (int(0.08 * width), int(0.1 * height)),
        cv2.FONT_HERSHEY_DUPLEX,
        1.2,
        BAG_INK[1].tolist(),
        2,
        cv2.LINE_AA,
    )
    # The logo, lower right: a raspberry disc with a white ring, a lemon star and initials.
    centre = (int(rng.uniform(0.68, 0.74) * width), int(0.6 * height))
    radius = int(0.16 * height)
    cv2.circle(image, centre, radius + 10, BAG_INK[3].tolist(), -1, cv2.LINE_AA)
    cv2.circle(image, centre, radius, BAG_INK[2].tolist(), -1, cv2.LINE_AA)
    angles = np.pi / 2 + np.pi * np.arange(10) / 5
    radii = np.where(np.arange(10) % 2 == 0, 0.85 * radius, 0.4 * radius)
    star = np.column_stack([np.cos(angles), -np.sin(angles)]) * radii[:, None]
    star = np.round((star + centre) * 16).astype(np.int32).reshape(-1, 1, 2)
    cv2.fillPoly(image, [star], BAG_INK[1].tolist(), cv2.LINE_AA, shift=4)
    initials = _random_text(rng, 2).replace(" ", "Q")
    org = (centre[0] - int(0.55 * radius), centre[1] + int(0.28 * radius))
    cv2.putText(image, initials, org, cv2.FONT_HERSHEY_DUPLEX, 2.4, BAG_INK[4].tolist(), 6)
    # Small print on the right, under the wordmark, and a net weight.
    for k in range(7):
        text = _random_text(rng, int(rng.integers(12, 22)))
        org = (int(0.47 * width), int((0.45 + 0.045 * k) * height))
        cv2.putText(image, text, org, cv2.FONT_HERSHEY_SIMPLEX, 0.5, BAG_INK[3].tolist(), 1)
    weight = f"NET WT {int(rng.integers(40, 250))} G"
    cv2.putText(
        image,
        weight,
        (int(0.5 * width), int(0.84 * height)),
        cv2.FONT_HERSHEY_SIMPLEX,
        0.9,
        BAG_INK[1].tolist(),
        2,
        cv2.LINE_AA,
    )
    image *= (1 + 0.02 * rng.standard_normal(shape)).astype(np.float32)[..., None]
    # The plain band along the bottom: bare foil, one colour.
    image[int(0.89 * height) :] = FOIL
    cv2.line(image, (0, int(0.89 * height)), (width, int(0.89 * height)), BAG_INK[4].tolist(), 2)
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


def slate_plush(rng, width, height):
    """A grey-blue plush with faint slate stripes and pale spots, its fur drawn as brush strokes.

    The fur is thousands of short strokes, a little lighter or darker than the colour under
    them, combed along a smooth flow that turns slowly across the patch (about 35 deg off the
    vertical), over fine grain: low contrast on purpose.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    blue, slate, pale = (
        np.array((0.50, 0.56, 0.64)),
        np.array((0.40, 0.45, 0.53)),
        np.array((0.62, 0.66, 0.71)),
    )
    # Faint wavy stripes across the body, and a few soft pale spots.
    warp = 40.0 * fractal_noise(rng, shape, cells=(2, 4))
    phase = (xs * math.cos(0.5) + ys * math.sin(0.5) + warp) / 95.0
    stripes = np.clip(2.5 * np.sin(2 * np.pi * phase) - 1.0, 0, 1)
    stripes = 0.8 * cv2.GaussianBlur(stripes.astype(np.float32), (0, 0), 6.0)[..., None]
    image = (1 - 0.6 * stripes) * blue + 0.6 * stripes * slate
    for _ in range(9):
        cx, cy = rng.uniform(0, width), rng.uniform(0, height)
        r = rng.uniform(25, 60)
        d = np.hypot(xs - cx, (ys - cy) * rng.uniform(0.7, 1.3)) / r
        weight = np.clip(1.4 - d, 0, 1)[..., None] * 0.45
        image = (1 - weight) * image + weight * pale
    image = image * (1 + 0.04 * fractal_noise(rng, shape, cells=(3, 6, 12)))[..., None]
    image = np.ascontiguousarray(image.astype(np.float32))
    # The fur: short brush strokes along the flow, lighter or darker than the colour under them.
    flow = np.radians(55.0) + 0.5 * smooth_noise(rng, shape, 3)  # radians from the +x axis
    base = image.copy()
    for _ in range(26000):
        x, y = rng.uniform(0, width), rng.uniform(0, height)
        angle = flow[int(y), int(x)] + rng.normal(0, 0.12)
        length = rng.uniform(8, 22)
        dx, dy = 0.5 * length * math.cos(angle), -0.5 * length * math.sin(angle)
        colour = base[int(y), int(x)] * (1 + rng.normal(0, 0.07))
        a = (round((x - dx) * 16), round((y - dy) * 16))
        b = (round((x + dx) * 16), round((y + dy) * 16))
        cv2.line(image, a, b, colour.tolist(), int(rng.integers(1, 3)), cv2.LINE_AA, shift=4)
    image = image + 0.012 * rng.standard_normal((*shape, 3)).astype(np.float32)
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.7), 0, 1)


OXFORD = (0.13, 0.34, 0.24)  # forest green cloth: the shirt, and its unprinted back (sRGB)
SHIRT_INK = np.array(
    [
        (0.96, 0.92, 0.80),  # cream
        (0.96, 0.42, 0.30),  # coral
        (0.95, 0.72, 0.18),  # mustard
        (0.06, 0.08, 0.07),  # black
    ]
)


def _arched_text(layer, text, centre, radius, span, scale, thickness):
    """Draw ``text`` (1 on ``layer``) letter by letter along the top of a circle."""
    letters = len(text)
    for k, letter in enumerate(text):
        angle = math.pi / 2 + span / 2 - span * (k + 0.5) / letters  # left to right, over the top
        x = centre[0] + radius * math.cos(angle)
        y = centre[1] - radius * math.sin(angle)
        size = int(60 * scale)
        tile = np.zeros((2 * size, 2 * size), np.uint8)
        (w, h), _ = cv2.getTextSize(letter, cv2.FONT_HERSHEY_DUPLEX, scale, thickness)
        org = (size - w // 2, size + h // 2)
        cv2.putText(tile, letter, org, cv2.FONT_HERSHEY_DUPLEX, scale, 1, thickness, cv2.LINE_AA)
        turn = cv2.getRotationMatrix2D((size, size), math.degrees(angle - math.pi / 2), 1.0)
        tile = cv2.warpAffine(tile, turn, (2 * size, 2 * size))
        x0, y0 = int(x) - size, int(y) - size
        region = layer[max(y0, 0) : y0 + 2 * size, max(x0, 0) : x0 + 2 * size]
        part = tile[max(-y0, 0) : max(-y0, 0) + region.shape[0], max(-x0, 0) :][
            :, : region.shape[1]
        ]
        np.maximum(region, part, out=region)


def shirt_graphic(rng, width, height):
    """A t-shirt print on a forest green basket weave: a mountain badge, lettering, stripes.

    The weave has warp and weft threads of two greens in a basket pattern with slubs (uneven
    yarn); the cracked, worn screen print is a big cream ring with arched letters round its top
    holding a coral sun and mustard and cream mountains, a band of diagonal stripes across the
    lower part, a bold wordmark under it and a line of small letters.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width]
    thread = 5  # texels per thread
    warp, weft = (xs // thread) % 2, (ys // thread) % 2
    over = ((xs // (2 * thread)) + (ys // (2 * thread))) % 2  # basket: pairs over and under
    slub = cv2.GaussianBlur(
        rng.standard_normal(shape).astype(np.float32), (0, 0), sigmaX=9, sigmaY=1
    )
    slub_y = cv2.GaussianBlur(rng.standard_normal(shape).astype(np.float32), (0, 0), 1, 9)
    light = np.where(over == 1, 1.0 + 0.05 * warp + 0.25 * slub_y, 0.95 + 0.05 * weft + 0.25 * slub)
    light = light + 0.04 * fractal_noise(rng, shape, cells=(4, 8))
    tint = np.where(over[..., None] == 1, np.array(OXFORD) * 1.1, np.array(OXFORD) * 0.92)
    cloth = (light[..., None] * tint).astype(np.float32)
    ink = np.zeros((height, width, 3), np.float32)
    cover = np.zeros(shape, np.float32)

    def layer():
        return np.zeros(shape, np.uint8)

    def fill(mask, colour):
        ink[mask > 0] = colour
        cover[mask > 0] = 1.0

    centre = (int(rng.uniform(0.45, 0.55) * width), int(0.45 * height))
    radius = int(0.3 * height)
    ring = layer()
    cv2.circle(ring, centre, radius + 46, 1, -1, cv2.LINE_AA)
    fill(ring, SHIRT_INK[0])
    inner = layer()
    cv2.circle(inner, centre, radius, 1, -1, cv2.LINE_AA)
    fill(inner, SHIRT_INK[3])
    letters = layer()
    text = "".join(c for c in _random_text(rng, 14) if c != " ")[:11]
    _arched_text(letters, text, centre, radius + 23, math.radians(150), 1.25, 3)
    fill(letters, SHIRT_INK[3])
    sun = layer()  # a coral sun high in the disc
    sun_at = (centre[0] + int(0.3 * radius), centre[1] - int(0.35 * radius))
    cv2.circle(sun, sun_at, int(0.28 * radius), 1, -1, cv2.LINE_AA)
    fill(sun, SHIRT_INK[1])
    disc = layer()
    cv2.circle(disc, centre, radius - 1, 1, -1, cv2.LINE_AA)
    for k, colour in enumerate((SHIRT_INK[2], SHIRT_INK[0])):  # two ranges of mountains
        peaks = layer()
        base = centre[1] + int((0.45 + 0.25 * k) * radius)
        x = np.linspace(centre[0] - radius, centre[0] + radius, 7 + 2 * k)
        tops = base - rng.uniform(0.35, 0.8, len(x)) * radius * (1 - 0.3 * k)
        y = np.where(np.arange(len(x)) % 2 == 0, tops, base - 0.1 * radius)
        outline = np.column_stack([x, y])
        polygon = np.vstack([outline, [(x[-1], centre[1] + radius), (x[0], centre[1] + radius)]])
        cv2.fillPoly(peaks, [np.round(polygon).astype(np.int32)], 1, cv2.LINE_AA)
        fill(peaks & disc, colour)
    stripes = layer()  # a band of diagonal stripes across the lower part
    y0, y1 = int(0.8 * height), int(0.87 * height)
    for x in range(-60, width + 60, 38):
        quad = np.array([(x, y1), (x + 18, y1), (x + 48, y0), (x + 30, y0)], np.int32)
        cv2.fillPoly(stripes, [quad], 1, cv2.LINE_AA)
    fill(stripes, SHIRT_INK[1])
    word = layer()
    name = _random_text(rng, 7).replace(" ", "")
    (w, _), _ = cv2.getTextSize(name, cv2.FONT_HERSHEY_TRIPLEX, 3.4, 14)
    org = ((width - w) // 2, int(0.975 * height))
    cv2.putText(word, name, org, cv2.FONT_HERSHEY_TRIPLEX, 3.4, 1, 14, cv2.LINE_AA)
    fill(word, SHIRT_INK[2])
    small = layer()
    line = " ".join(_random_text(rng, 4).replace(" ", "X") for _ in range(3))
    cv2.putText(small, line, (int(0.06 * width), int(0.08 * height)), 2, 1.0, 1, 2, cv2.LINE_AA)
    fill(small, SHIRT_INK[0])
    # Cracked, worn ink, with the weave showing through.
    crack = np.abs(fractal_noise(rng, shape, cells=(10, 20, 40))) < 0.02
    cover = cover * ~crack * (rng.random(shape) > 0.06)
    cover = cv2.GaussianBlur(cover.astype(np.float32), (0, 0), 0.7)[..., None]
    image = (1 - cover) * cloth + cover * ink * (0.88 + 0.12 * light[..., None])
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.5), 0, 1)


# --- scenes ---------------------------------------------------------------------------------

BAG_SIZE = (2.3, 1.5)
BAG_AT = (0.35, 0.12)  # bag_fold_hands: the bag's centre at rest, right of and above the middle
BAG_ANGLE = 148.0  # the fold's direction (deg from +X: up and left); the crease runs across it
BAG_CREASE = 0.08  # the crease's distance from the bag's centre along that direction
BAG_BAND = 0.22  # folded, the upper left part lies 2 * band / pi behind the rest
HAND_DEPTH = 0.32  # the hands' height above the sheet: in front of it, clear of its bow


def object_matrices(clip, obj):
    """``obj``'s world matrix on every frame: (T, 4, 4). Leaves the scene on its first frame."""
    scene = bpy.context.scene
    matrices = []
    for frame in range(clip.frames):
        scene.frame_set(scene.frame_start + frame)
        matrices.append(np.array(obj.matrix_world))
    scene.frame_set(scene.frame_start)
    return np.array(matrices)


def build_bag_fold_hands(rng, clip):
    studio_lights()
    size = BAG_SIZE
    sheet = add_sheet(
        foil_bag_print,
        size,
        (92, 60),
        4,
        rng=rng,
        roughness=0.3,
        specular=0.6,
        coat=0.3,
        thickness=0.035,
    )
    bsdf = sheet.obj.data.materials[0].node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Metallic"].default_value = 0.35  # foil under the ink
    angle = math.radians(BAG_ANGLE)
    d = np.array((math.cos(angle), math.sin(angle)))  # the fold's direction, up and left
    along = np.array((d[1], -d[0]))  # the crease's direction, up and right
    # The squeeze bows the bag a little along the crease (the crease's ends towards the
    # camera): that does not change where a point is along d, so the fold's limits stay put...
    origin = deform_origin(sheet, (0.0, 0.0, 0.0), diagonal_towards_camera(angle - math.pi / 2))
    bend(sheet, "Bow", origin)
    # ...and folds the upper left part back about the diagonal crease, over a band of BAG_BAND.
    crease_bend(sheet, "Fold", size, angle, BAG_CREASE, BAG_BAND, diagonal_away)
    # The fold (keyed on every frame), from 0.4 s: 90 deg after about 0.25 s, folded flat
    # after about 0.45 s, its edge at a steady pace while in view; unfolds from 1.3 s. The
    # upper hand pushes the bag down and right (about 20 px) and turns it 4 deg.
    t = np.arange(clip.frames) / clip.fps
    fold = fold_and_unfold(t, 0.4, 1.3, paced_fold(5.5, 15.0, 110.0))
    x0, y0 = BAG_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Bow"].angle', 0): deg(
                [(0.0, 0), (0.35, 0), (0.85, 20), (1.45, 20), (2.1, 0)]
            ),
            ('modifiers["Fold"].angle', 0): list(zip(t, fold, strict=True)),
            ("location", 0): [
                (0.0, x0),
                (0.4, x0),
                (1.0, x0 + 0.13),
                (1.5, x0 + 0.13),
                (2.4, x0 + 0.05),
                (3.3, x0 + 0.04),
            ],
            ("location", 1): [
                (0.0, y0),
                (0.4, y0),
                (1.0, y0 - 0.1),
                (1.55, y0 - 0.1),
                (2.5, y0 - 0.03),
                (3.3, y0 - 0.02),
            ],
            ("rotation_euler", 2): deg([(0.0, 0), (0.4, 0), (1.0, -4), (2.3, 1), (3.3, 0)]),
        },
    )
    # The hands come in along the diagonal, in front of the bag, and move with it: the upper
    # one's fingers (pointing down and right) over the upper left part and then, following it
    # as it folds back, over the crease; the lower one's (pointing up and left) over the lower
    # right corner. Where their fingertips are: how far along d from the bag's centre, and
    # how far along the crease (in the bag's frame).
    upper_tips = [
        (0.0, 4.6),
        (0.1, 4.6),
        (0.38, 1.0),
        (0.55, 0.6),
        (0.66, 0.3),
        (0.85, BAG_CREASE - 0.22),
        (1.3, BAG_CREASE - 0.22),
        (1.55, 0.7),
        (2.4, 4.6),
    ]
    lower_tips = [
        (0.0, -4.6),
        (0.15, -4.6),
        (0.45, -1.05),
        (0.95, -0.85),
        (1.5, -0.85),
        (2.1, -1.05),
        (3.0, -4.6),
    ]
    matrices = object_matrices(clip, sheet.obj)
    for name, tips, across, sign in (
        ("UpperHand", upper_tips, 0.05, -1.0),
        ("LowerHand", lower_tips, -0.1, 1.0),
    ):
        hand = add_pushing_hand(name, True)
        s = eased(t, tips)
        poses = []
        for m, reach in zip(matrices, s, strict=True):
            local = reach * d + across * along
            tip = m[:3, :3] @ (*local, 0.0) + m[:3, 3]
            tip[2] = HAND_DEPTH
            fingers = m[:3, :3] @ (*(sign * d), 0.0)
            poses.append(hand_pose(tip, fingers, (0.0, 0.0, 1.0)))
        key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(FOIL)), 1.0))
    return sheet


LIFT_SIZE = (2.0, 1.5)
LIFT_AT = (-0.4, -0.05)  # toy_tail_lift: the patch's centre at rest, left of the middle
LIFT_AXIS = 30.0  # the turning axis: deg from the vertical, leaning right
LIFT_PIVOT = -0.75  # the axis's distance from the centre, across it (to the lower right)
LIFT_CREASE = -0.2  # where the soft part's bend starts, likewise
SLATE_FELT = (0.05, 0.06, 0.08, 1.0)  # toy_tail_lift's back and rim (linear RGB)


def build_toy_tail_lift(rng, clip):
    studio_lights()
    size = LIFT_SIZE
    tilt = math.radians(LIFT_AXIS)
    axis = np.array((math.sin(tilt), math.cos(tilt)))  # up and a little right
    across = np.array((math.cos(tilt), -math.sin(tilt)))  # down and right, towards the corner
    sheet, pivot = plush_on_pivot(
        rng, slate_plush, size, (80, 60), 0.0, (0.45, 0.45, (0.75, 0.82, 0.95, 1.0))
    )
    # The pivot: the tilted axis through the left part; turning about it by a positive angle
    # takes the part right of it away from the camera.
    at = np.array(LIFT_AT) + LIFT_PIVOT * across
    pivot.location = (*at, 0.0)
    pivot.rotation_mode = "AXIS_ANGLE"
    pivot.rotation_axis_angle = (0.0, *axis, 0.0)
    sheet.obj.location = (*(-LIFT_PIVOT * across), 0.0)
    # The soft toy gives where it is held: the part beyond LIFT_CREASE bends further away from
    # the camera over a band of 0.4, so that the patch turns 50 deg and that part 105 deg.
    angle = -tilt  # the direction across the axis
    crease_bend(sheet, "Lift", size, angle, LIFT_CREASE, 0.4, diagonal_away)
    clip.keyframe(
        pivot,
        {
            ("rotation_axis_angle", 0): deg([(0.0, 0), (0.4, 0), (1.7, 50), (1.95, 50), (2.9, 0)]),
            ("location", 0): [(0.0, at[0]), (0.4, at[0]), (1.6, at[0] - 0.24), (3.4, at[0] - 0.04)],
            ("location", 1): [(0.0, at[1]), (0.4, at[1]), (1.6, at[1] + 0.12), (3.4, at[1] + 0.02)],
        },
    )
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Lift"].angle', 0): deg(
                [(0.0, 0), (0.45, 0), (1.7, 55), (1.95, 55), (2.85, 0)]
            )
        },
    )
    # The hand holds the lower right corner: its fingers (pointing down the axis) lie over the
    # corner a little inside it, the back of the hand away from the painted side; moved with
    # the corner on every frame, it rolls about its forearm (which stays along the axis, out to
    # the upper right) as the corner turns. It comes in along the axis and leaves the same way.
    grids = sheet_frames(clip, sheet)
    t = np.arange(clip.frames) / clip.fps
    away = eased(t, [(0.0, 3.5), (0.1, 3.5), (0.4, 0.0), (2.95, 0.0), (3.4, 3.5)])
    hand = add_pushing_hand("Hand", True)
    poses = []
    for grid, out in zip(grids, away, strict=True):
        corner = grid[-1, -1]
        along_x = corner - grid[-1, -3]
        along_y = grid[-3, -1] - corner
        along_x, along_y = along_x / np.linalg.norm(along_x), along_y / np.linalg.norm(along_y)
        normal = np.cross(along_x, along_y)
        a = axis[0] * along_x + axis[1] * along_y
        n = across[0] * along_x + across[1] * along_y
        tips = corner + (out - 0.2) * a - 0.08 * n + 0.13 * normal
        poses.append(hand_pose(tips, -a, normal))
    key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, SLATE_FELT)
    return sheet


SHIRT_SIZE = (2.6, 2.0)
SHIRT_AT = (0.3, 0.05)  # shirt_fold_print: the cloth's centre at rest
SHIRT_TILT = 9.0  # the crease's tilt (deg; it rises to the right)
SHIRT_CREASE = 0.26  # the crease's distance from the centre, up across it
SHIRT_BAND = 0.3  # the loop at the crease: folded, the flap lies 2 * band / pi in front


def build_shirt_fold_print(rng, clip):
    studio_lights()
    size = SHIRT_SIZE
    sheet = add_sheet(
        shirt_graphic,
        size,
        (96, 72),
        4,
        rng=rng,
        roughness=0.9,
        specular=0.2,
        thickness=0.012,
    )
    set_sheen(sheet, 0.35, 0.45)  # cotton
    # The top part folds down towards the camera about a crease tilted SHIRT_TILT deg, in a
    # soft loop: folded, it lies about 0.19 in front of the rest, its plain back to the camera.
    angle = math.radians(90.0 + SHIRT_TILT)
    crease_bend(sheet, "Fold", size, angle, SHIRT_CREASE, SHIRT_BAND, diagonal_towards_camera)
    # Slowly while the print on the flap is in view, faster once it is past edge-on; unfolds
    # faster than it folded. The cloth slides left about 0.45 and part of the way back.
    x0, y0 = SHIRT_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): deg(
                [(0.0, 0), (0.15, 0), (0.75, 70), (1.2, 180), (1.65, 180), (2.05, 100), (2.6, 0)]
            ),
            ("location", 0): [
                (0.0, x0),
                (0.15, x0),
                (1.2, x0 - 0.3),
                (1.9, x0 - 0.45),
                (2.8, x0 - 0.3),
                (3.3, x0 - 0.28),
            ],
            ("location", 1): [(0.0, y0), (0.15, y0), (1.5, y0 - 0.04), (3.3, y0)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.15, 0), (1.5, 2), (3.3, 0.5)]),
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(OXFORD)), 1.0))
    return sheet


HELDOUT_FOLDS3 = [
    Clip(
        "bag_fold_hands",
        100,
        30,
        "two hands, in from the upper left and the lower right, squeeze a glossy foil snack "
        "bag lying right of and above the middle: it bows and its upper left part (46 %) folds "
        "back behind the rest along a diagonal crease through the middle (in 0.45 s) while it "
        "is pushed about 17 px down and right and turned 4 deg, its logo staying in view; "
        "holds 0.45 s with the hands over the crease and the lower right corner, unfolds; the "
        "hands leave along the diagonal",
        build_bag_fold_hands,
    ),
    Clip(
        "toy_tail_lift",
        104,
        30,
        "a furry, low-contrast grey-blue plush patch with faint stripes and spots, held by a "
        "hand at its lower right corner, turns away from the camera in 1.3 s about an axis "
        "tilted 30 deg from the vertical while it drifts about 25 px left and up: the patch "
        "turns 50 deg, its far part (38 %) on to 105 deg, past edge-on (painted side turned "
        "away); holds 0.25 s, turns back; the hand leaves",
        build_toy_tail_lift,
    ),
    Clip(
        "shirt_fold_print",
        100,
        30,
        "the top 37 % of a cotton cloth with a big t-shirt print folds down 180 deg over its "
        "print, towards the camera, about a crease tilted 9 deg, in a soft loop (its plain "
        "back covers about 20 % more of the print), slowly (1.05 s); holds 0.45 s and unfolds "
        "in 0.95 s while the cloth slides about 47 px left and a third of the way back",
        build_shirt_fold_print,
    ),
]


README_HELDOUT_FOLDS3 = (
    """# Held-out clips of folds, third batch

Clips for checking that the tracker generalises to folds (issue 22): never tune it on these;
they are to be measured once, as held-out. The tracker was tuned on the fold clips of
[`../folds`](../folds/README.md); like the first two held-out batches
([`../heldout_folds`](../heldout_folds/README.md) and
[`../heldout_folds2`](../heldout_folds2/README.md)) these show the same kinds of motion (a
sheet squeezed until part of it folds back, a soft patch turned past edge-on, a part folded
over the rest) with paint, axes, speeds and places that neither earlier batch has: a glossy
foil bag folded back along a diagonal crease by hands that come in diagonally, the bag lying
off the middle; a plush patch held by a corner and turned away about a tilted axis while it
drifts; the top of a printed cloth folded down over its print about a tilted crease, slowly,
while the cloth slides sideways. Rendered with Blender {blender}
(the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes and paint in
`scripts/hardclips/heldout_folds3.py`) from a fixed seed, so the same command makes the same
scenes, truth and outlines; it makes them only when named, apart from every other clip:

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \\
        --out samples/heldout_folds3 --only {names}

Keep them out of `samples/folds`, `samples/heldout_folds` and `samples/heldout_folds2`. Check
them with `.venv/bin/python scripts/check_hard_clips.py --dir samples/heldout_folds3`
(statistics, and contact sheets in `/tmp/hard_check/`).

"""
    + FOLD_FILES
)
