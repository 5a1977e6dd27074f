r"""A fifth batch of held-out clips of folds: new paint, axes, speeds and places, never tuned on.

The tracker was tuned on the fold clips of ``folds`` (``samples/folds``); the held-out batches
(``heldout_folds`` to ``heldout_folds4`` and this one, in ``samples/heldout_folds`` to
``samples/heldout_folds5``) check that it generalises and are never to be tuned on. This batch
was made after the fourth, for issue 22's generalisation check. ``HELDOUT_FOLDS5`` lists it.
``render_hard_clips.py`` makes these clips only when asked by name, into a folder of their own
(``samples/heldout_folds5``), apart from every other clip::

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \
        --out samples/heldout_folds5 --only NAME ...

Each writes the files of a single-sheet hard clip (``NAME.mp4``, ``NAME.json``,
``NAME_truth.npz``) with the conventions of ``folds``: frame 0 flat and square to the camera,
at rest for three frames; every crease runs through the outlined region; the folds are
SimpleDeform bends over a band at the crease (``fold_limits``), so a folded part never passes
through the rest. The paint is here (``folk_felt_coaster``, ``patched_denim``,
``paisley_bandana``); the scenes reuse the helpers of ``heldout_folds3`` (hands posed on every
frame, eased keys, ``crease_bend``). Unlike the earlier batches, one patch turns in depth as a
whole, with no crease (strongly foreshortened, never past edge-on), held by a hand behind its
left edge; a corner folds back along a diagonal crease while a hand from the upper right
covers the patch; and a square cloth folds over along (near) its diagonal.

``felt_yaw_turn``
    A folk-art felt coaster (``folk_felt_coaster``: a dusty teal felt base with appliqued felt
    flowers in red, cream, mustard and pink with dark green leaves and vines, each piece raised
    on a soft shadow and edged with running stitches, French knots in the flowers' hearts, a
    blanket stitch round the edge and seed stitches over the base; a sheen material, dark teal
    felt behind), right of and above the middle (``FELT_AT``), is held by a hand at the middle
    of its left edge (its fingers behind the felt, its palm and forearm reaching down along the
    axis out of the image) and turned as a whole, with no crease, in depth about an axis through
    the hand leaning 8 deg right of the vertical (``FELT_TILT``): its right edge goes away from
    the camera, to 75 deg (``FELT_TURN``; strongly foreshortened, never past edge-on) in 0.7 s
    from 0.5 s, holds 0.3 s and turns back to flat in 1 s while it drifts about 15 px right and
    down. The hand comes in along the axis from below (0.1 to 0.45 s), is posed with the felt on
    every frame (it rolls about its forearm, which stays along the axis) and leaves the same way
    (2.8 to 3.3 s). Nothing hides the felt (the hand is behind it).
``denim_corner_tuck``
    A denim patch (``patched_denim``: indigo 3/1 twill, warp-faced with white weft in the
    diagonal ribs, slubby yarn, fades and whiskers, a felled seam and the top of a back pocket
    with gold double topstitching, an arc stitched on the pocket and two copper rivets, and
    iron-on and embroidered patches: a round yellow patch with a red star and a satin-stitched
    rim, a pink heart, a cream name label and a lightning bolt; its back the paler weft side),
    left of and below the middle (``DENIM_AT``): its lower right corner (30 %, beyond a diagonal
    crease rising to the right at 43 deg from the bottom edge left of the middle to the right
    edge near the top, ``DENIM_ANGLE`` and ``DENIM_CREASE``) folds back 180 deg, away from the
    camera, behind the rest (over a band of 0.2; folded it lies about 0.13 behind), at a medium
    speed (0.62 s, from 0.5 s; past about 100 deg it is out of sight), while a hand coming in
    from the upper right (``DENIM_HAND``) lies over the upper right part, beside the crease's
    upper end (hiding about 10 % of the patch), and pushes it about 10 px left and down, turning
    it 3 deg clockwise. It holds folded 0.4 s, unfolds (from 1.52 s, flat by 2.14 s) and the
    hand leaves the way it came (2.2 to 3 s).
``bandana_diagonal_fold``
    A square bandana (``paisley_bandana``: red cotton, a fine plain weave, printed with white
    paisleys outlined and detailed in black, a central medallion of paisleys in a ring of dots,
    small flowers and black fillers, and a border of black and white bands with a row of small
    teardrops; its back the print's faded red showing through), right of the middle
    (``BANDANA_AT``): its top left triangle (30 %) folds over towards the camera by 180 deg onto
    the rest, about a crease 2 deg off parallel to the diagonal from its lower left corner to
    its upper right one and 0.3 off it towards the top left corner (``BANDANA_ANGLE``,
    ``BANDANA_CREASE``: off the corner to corner line, so that the crease runs through the
    outlined region, from the top edge to the left edge, and far enough off it that the flap's
    plain back hides only about another 21 % of the print), over a band of 0.15 (the flap lies
    about 0.1 in front), fast (in 0.5 s, from 0.2 s), holds 0.3 s and unfolds slowly (1.2 s)
    while the cloth turns 8 deg anticlockwise and drifts about 25 px left and up.
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
from hardclips.sheet import add_sheet, deg, finish_sheet, set_sheen
from hardclips.video import srgb_to_linear

# --- paint ----------------------------------------------------------------------------------


def _along(points, closed, length, gap):
    """Dashes along the polyline ``points`` (N, 2), walked by arc length.

    Returns [(start, end), ...]: dashes ``length`` long with ``gap`` between them (texels).
    """
    points = np.asarray(points, np.float64)
    if closed:
        points = np.vstack([points, points[:1]])
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    dashes = []
    for s in np.arange(0.5 * gap, arc[-1] - length, length + gap):
        a = (np.interp(s, arc, points[:, 0]), np.interp(s, arc, points[:, 1]))
        b = (np.interp(s + length, arc, points[:, 0]), np.interp(s + length, arc, points[:, 1]))
        dashes.append((a, b))
    return dashes


def _stitches(image, points, colour, closed=True, length=9.0, gap=6.0, thickness=3):
    """A running stitch of thread ``colour`` along ``points``, each stitch with a faint shadow."""
    shadow = (np.asarray(colour) * 0.35).tolist()
    for (ax, ay), (bx, by) in _along(points, closed, length, gap):
        for offset, tone in ((1.2, shadow), (0.0, list(colour))):
            a = (round((ax + offset) * 16), round((ay + offset) * 16))
            b = (round((bx + offset) * 16), round((by + offset) * 16))
            cv2.line(image, a, b, tone, thickness, cv2.LINE_AA, shift=4)


def _ellipse_points(centre, axes, turn):
    """An ellipse's outline as float points (N, 2), ``turn`` in degrees."""
    t = np.linspace(0, 2 * np.pi, max(24, int(0.5 * (axes[0] + axes[1]))), endpoint=False)
    c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
    x, y = axes[0] * np.cos(t), axes[1] * np.sin(t)
    return np.column_stack([centre[0] + c * x - s * y, centre[1] + s * x + c * y])


def _polygon_mask(shape, points):
    mask = np.zeros(shape, np.float32)
    cv2.fillPoly(mask, [np.round(np.asarray(points) * 16).astype(np.int32)], 1.0, cv2.LINE_AA, 4)
    return mask


FELT = (0.30, 0.50, 0.52)  # the coaster's dusty teal felt base (sRGB)
FELT_COLOURS = np.array(
    [
        (0.78, 0.12, 0.14),  # red
        (0.95, 0.91, 0.80),  # cream
        (0.93, 0.68, 0.13),  # mustard
        (0.91, 0.48, 0.58),  # pink
        (0.12, 0.33, 0.17),  # dark green
        (0.10, 0.09, 0.10),  # black thread
    ]
)


def _felt(rng, shape, fibres):
    """Felt's light (H, W) about 1: mottling, fine grain and ``fibres`` short fuzzy fibres."""
    height, width = shape
    light = 1 + 0.05 * fractal_noise(rng, shape, cells=(4, 8, 16, 32), falloff=0.8)
    grain = cv2.GaussianBlur(rng.standard_normal(shape).astype(np.float32), (0, 0), 1.2)
    light = (light + 0.05 * grain / grain.std()).astype(np.float32)
    for _ in range(fibres):
        x, y = rng.uniform(0, width), rng.uniform(0, height)
        angle, length = rng.uniform(0, np.pi), rng.uniform(4, 12)
        dx, dy = 0.5 * length * math.cos(angle), 0.5 * length * math.sin(angle)
        a = (round((x - dx) * 16), round((y - dy) * 16))
        b = (round((x + dx) * 16), round((y + dy) * 16))
        tone = float(light[int(y), int(x)] * (1 + rng.choice((-1, 1)) * rng.uniform(0.06, 0.12)))
        cv2.line(light, a, b, tone, 1, cv2.LINE_AA, shift=4)
    return light


def _applique(image, mask, colour, light):
    """Lay a felt piece (``mask`` (H, W) in [0, 1]) of ``colour`` on ``image``, in place.

    Raised on a soft shadow, its edge a little fuzzy; ``light`` is the felt's grain.
    """
    shadow = cv2.GaussianBlur(np.roll(mask, (5, 4), axis=(0, 1)), (0, 0), 3.0)
    image *= (1 - 0.4 * shadow)[..., None]
    soft = cv2.GaussianBlur(mask, (0, 0), 0.9)[..., None]
    image[:] = (1 - soft) * image + soft * (light[..., None] * np.asarray(colour))


def folk_felt_coaster(rng, width, height):
    """A folk-art felt coaster: appliqued felt flowers, leaves and vines, stitches, on teal felt.

    Dusty teal felt (mottled, grainy, fuzzy with thousands of short fibres); a big red flower
    of eight petals in the middle (each petal with a pink inner petal and a running stitch in
    cream, a mustard heart ringed with black French knots); vines of dark green chain stitch
    curling out to the corners with felt leaves (each with a stitched vein); five small round
    flowers of five petals in cream, mustard, pink and red with contrasting hearts and cross
    stitches; cream seed stitches over the base; a mustard blanket stitch round the edge and a
    cream running stitch inside it.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    light = _felt(rng, shape, 14000)
    image = np.ascontiguousarray((light[..., None] * np.array(FELT)).astype(np.float32))
    red, cream, mustard, pink, green, black = FELT_COLOURS
    centre = np.array((width * rng.uniform(0.46, 0.54), height * rng.uniform(0.46, 0.54)))
    # Vines: chain stitch (small green loops) from near the middle curling to each corner.
    leaves = []
    for cx, cy in ((0.08, 0.1), (0.92, 0.12), (0.1, 0.9), (0.9, 0.88)):
        corner = np.array((cx * width, cy * height))
        t = np.linspace(0, 1, 40)[:, None]
        bulge = rng.uniform(-0.25, 0.25) * np.array((-(corner - centre)[1], (corner - centre)[0]))
        path = centre + t * (corner - centre) + np.sin(np.pi * t) * bulge
        for (ax, ay), (bx, by) in _along(path[5:], False, 10.0, 1.0):
            mid = (round(8 * (ax + bx)), round(8 * (ay + by)))
            angle = math.degrees(math.atan2(by - ay, bx - ax))
            cv2.ellipse(
                image, mid, (7 * 16, 4 * 16), angle, 0, 360, green.tolist(), 4, cv2.LINE_AA, shift=4
            )
        for k in (14, 22, 30):  # leaves along the vine, alternately on either side
            direction = path[k + 1] - path[k - 1]
            side = np.array((-direction[1], direction[0])) / np.linalg.norm(direction)
            side *= 1 if k % 16 == 14 else -1
            leaves.append((path[k] + 40 * side, math.degrees(math.atan2(side[1], side[0]))))
    for at, turn in leaves:  # a lens of felt with a stitched vein
        size = rng.uniform(48, 62)
        t = np.linspace(-1, 1, 30)
        upper = np.column_stack([size * t, 0.42 * size * (1 - t * t)])
        lower = np.column_stack([size * t[::-1], -0.42 * size * (1 - t[::-1] ** 2)])
        c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
        lens = np.vstack([upper, lower]) @ np.array([[c, s], [-s, c]]) + at
        _applique(image, _polygon_mask(shape, lens), green * rng.uniform(0.9, 1.2), light)
        vein = np.array([[-0.8 * size, 0.0], [0.8 * size, 0.0]]) @ np.array([[c, s], [-s, c]]) + at
        _stitches(image, vein, (0.55, 0.75, 0.35), closed=False, length=7, gap=4, thickness=2)
    # The big flower: eight red petals with pink inner petals, a mustard heart, French knots.
    petal_size = 0.145 * min(width, height)
    turn0 = rng.uniform(0, 45)
    for k in range(8):
        angle = math.radians(turn0 + 45 * k)
        at = centre + 0.95 * petal_size * np.array((math.cos(angle), math.sin(angle)))
        turn = math.degrees(angle)
        outline = _ellipse_points(at, (petal_size, 0.5 * petal_size), turn)
        _applique(image, _polygon_mask(shape, outline), red, light)
        inner = _ellipse_points(at, (0.6 * petal_size, 0.24 * petal_size), turn)
        _applique(image, _polygon_mask(shape, inner), pink, light)
        seam = _ellipse_points(at, (petal_size - 9, 0.5 * petal_size - 9), turn)
        _stitches(image, seam, cream)
    heart = _ellipse_points(centre, (0.55 * petal_size,) * 2, 0.0)
    _applique(image, _polygon_mask(shape, heart), mustard, light)
    _stitches(image, _ellipse_points(centre, (0.55 * petal_size - 8,) * 2, 0.0), red)
    for k in range(12):
        angle = 2 * np.pi * k / 12
        knot = centre + 0.3 * petal_size * np.array((math.cos(angle), math.sin(angle)))
        cv2.circle(image, tuple(np.round(knot).astype(int)), 5, black.tolist(), -1, cv2.LINE_AA)
        cv2.circle(image, tuple(np.round(knot - 1.5).astype(int)), 2, (0.4, 0.4, 0.4), -1)
    cv2.circle(image, tuple(np.round(centre).astype(int)), 9, red.tolist(), -1, cv2.LINE_AA)
    # Small round flowers of five petals between the vines.
    spots = [(0.5, 0.12), (0.5, 0.88), (0.12, 0.5), (0.88, 0.5), (0.73, 0.27)]
    for k, (fx, fy) in enumerate(spots):
        at = np.array((fx * width, fy * height)) + rng.normal(0, 10, 2)
        colour = (cream, mustard, pink, red, cream)[k]
        middle = (red, black, mustard, cream, pink)[k]
        r = rng.uniform(0.045, 0.055) * min(width, height)
        turn = rng.uniform(0, 72)
        for j in range(5):
            angle = math.radians(turn + 72 * j)
            petal = at + 1.05 * r * np.array((math.cos(angle), math.sin(angle)))
            _applique(
                image, _polygon_mask(shape, _ellipse_points(petal, (r, r), 0.0)), colour, light
            )
        _applique(
            image, _polygon_mask(shape, _ellipse_points(at, (0.6 * r,) * 2, 0.0)), middle, light
        )
        for a, b in ((-1, -1), (-1, 1)):  # a cross stitch in the heart
            p = (round((at[0] + a * 0.3 * r) * 16), round((at[1] + b * 0.3 * r) * 16))
            q = (round((at[0] - a * 0.3 * r) * 16), round((at[1] - b * 0.3 * r) * 16))
            cv2.line(
                image, p, q, black.tolist() if k != 1 else cream.tolist(), 3, cv2.LINE_AA, shift=4
            )
    # Seed stitches over the bare base: short cream dashes at random angles, where no piece is.
    base = np.abs(image - light[..., None] * np.array(FELT)).sum(axis=2) < 0.06
    for _ in range(260):
        x, y = int(rng.uniform(30, width - 30)), int(rng.uniform(30, height - 30))
        if not base[y, x]:
            continue
        angle = rng.uniform(0, np.pi)
        d = 5.0 * np.array((math.cos(angle), math.sin(angle)))
        for tone, offset in (((cream * 0.35).tolist(), 1.2), (cream.tolist(), 0.0)):
            p, q = (
                tuple(np.round((v + offset) * 16).astype(int)) for v in ((x, y) - d, (x, y) + d)
            )
            cv2.line(image, p, q, tone, 3, cv2.LINE_AA, shift=4)
    # The edge: a mustard blanket stitch (a thread along the edge, legs into the felt) and a
    # cream running stitch inside it.
    inset, leg = 9.0, 20.0
    corners = np.array(
        [
            (inset, inset),
            (width - inset, inset),
            (width - inset, height - inset),
            (inset, height - inset),
        ]
    )
    thread = mustard.tolist()
    shadow = (mustard * 0.35).tolist()
    for k in range(4):
        a, b = corners[k], corners[(k + 1) % 4]
        along = (b - a) / np.linalg.norm(b - a)
        inward = np.array((-along[1], along[0]))  # the corners run clockwise on the image
        steps = np.arange(0.0, np.linalg.norm(b - a), 16.0)
        for tone, offset in ((shadow, 1.2), (thread, 0.0)):
            ends = [np.round((a + offset) * 16), np.round((b + offset) * 16)]
            cv2.line(image, *(tuple(e.astype(int)) for e in ends), tone, 3, cv2.LINE_AA, shift=4)
            for step in steps:
                p = a + step * along + offset
                q = p + leg * inward
                p, q = (tuple(np.round(v * 16).astype(int)) for v in (p, q))
                cv2.line(image, p, q, tone, 3, cv2.LINE_AA, shift=4)
    inner = np.array(
        [(40.0, 40.0), (width - 40.0, 40.0), (width - 40.0, height - 40.0), (40.0, height - 40.0)]
    )
    _stitches(image, inner, cream, length=12, gap=8)
    image = image * (1 + 0.02 * rng.standard_normal((*shape, 1))).astype(np.float32)
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


INDIGO = (0.11, 0.19, 0.36)  # the denim's warp (sRGB)
WEFT = (0.62, 0.64, 0.66)  # its weft, where it shows on the face
DENIM_BACK = (0.58, 0.63, 0.72)  # the weft-faced back of the denim and its rim (sRGB)
GOLD_THREAD = (0.86, 0.58, 0.20)
DENIM_INK = np.array(
    [
        (0.97, 0.80, 0.15),  # yellow
        (0.80, 0.12, 0.14),  # red
        (0.92, 0.47, 0.62),  # pink
        (0.95, 0.92, 0.82),  # cream
        (0.08, 0.08, 0.09),  # black
        (0.98, 0.52, 0.12),  # orange
    ]
)


def _satin_rim(image, points, colour, width):
    """A satin-stitched rim along the closed polyline ``points``, in place.

    A band of ``colour`` ``width`` texels wide, drawn as close stitches across it over a darker
    ground.
    """
    dark = (np.asarray(colour) * 0.6).tolist()
    path = np.round(np.vstack([points, points[:1]]) * 16).astype(np.int32).reshape(-1, 1, 2)
    cv2.polylines(image, [path], False, dark, int(width), cv2.LINE_AA, shift=4)
    for (ax, ay), (bx, by) in _along(points, True, 0.1, 3.0):
        d = np.array((by - ay, -(bx - ax)))
        d = 0.5 * (width - 1) * d / (np.linalg.norm(d) + 1e-9)
        p, q = (np.array((ax, ay)) + d, np.array((ax, ay)) - d)
        p, q = (tuple(np.round(v * 16).astype(int)) for v in (p, q))
        cv2.line(image, p, q, list(colour), 2, cv2.LINE_AA, shift=4)


def _star_points(centre, outer, inner, turn, points=5):
    angles = np.radians(turn) - np.pi / 2 + np.pi * np.arange(2 * points) / points
    radii = np.where(np.arange(2 * points) % 2 == 0, outer, inner)
    return np.column_stack([np.cos(angles), np.sin(angles)]) * radii[:, None] + centre


def _heart_points(centre, size, turn):
    t = np.linspace(0, 2 * np.pi, 80, endpoint=False)
    x = 16 * np.sin(t) ** 3
    y = -(13 * np.cos(t) - 5 * np.cos(2 * t) - 2 * np.cos(3 * t) - np.cos(4 * t))
    c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
    points = np.column_stack([x, y]) * size / 32
    return points @ np.array([[c, s], [-s, c]]) + centre


def _patch(image, points, colour, rim, rim_width=12):
    """An iron-on patch: ``points`` filled with ``colour``, raised on a shadow, a satin rim."""
    shape = image.shape[:2]
    mask = _polygon_mask(shape, points)
    shadow = cv2.GaussianBlur(np.roll(mask, (5, 4), axis=(0, 1)), (0, 0), 3.5)
    image *= (1 - 0.45 * shadow)[..., None]
    image[:] = (1 - mask[..., None]) * image + mask[..., None] * np.asarray(colour)
    _satin_rim(image, points, rim, rim_width)


def patched_denim(rng, width, height):
    """Indigo denim: 3/1 twill, fades and whiskers, a seam, a pocket's top, patches.

    Warp-faced right-hand twill (indigo warp over three white wefts, so fine white ribs run up
    to the right), each warp thread its own shade and slubby along its length; faded paler in
    broad patches and a few light whiskers; a felled seam down the left part and the top of a
    back pocket (a hem with gold double topstitching, an arc stitched on the pocket, two copper
    rivets, a darker unfaded pocket under a soft shadow); four iron-on patches with
    satin-stitched rims (a round yellow one with a red star, a pink heart, a cream label with
    a word, an orange lightning bolt) and an embroidered daisy in thread.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width]
    thread = 4  # texels per thread (about a pixel at rest)
    i, j = xs // thread, ys // thread
    warp_up = ((i + j) % 4) != 0  # 3/1 twill: the weft shows on one diagonal in four
    shade = 1 + 0.09 * rng.standard_normal(width // thread + 1)  # each warp thread's dye
    slub = cv2.GaussianBlur(rng.standard_normal(shape).astype(np.float32), (0, 0), 1.0, 25.0)
    warp = (shade[i] + 1.2 * slub)[..., None] * np.array(INDIGO)
    weft = (1 + 0.05 * rng.standard_normal(height // thread + 1))[j][..., None] * np.array(WEFT)
    phase = np.where(warp_up, xs % thread, ys % thread) + 0.5
    yarn = (0.84 + 0.16 * np.sin(np.pi * phase / thread))[..., None]
    cloth = np.where(warp_up[..., None], warp, weft) * yarn
    # Fades: broad paler patches and whiskers (thin light streaks, roughly across).
    fade = np.clip(0.5 + 1.4 * fractal_noise(rng, shape, cells=(2, 4, 8)), 0, 1) * 0.45
    whiskers = np.zeros(shape, np.float32)
    for _ in range(7):
        y0, x0 = rng.uniform(0.35, 0.75) * height, rng.uniform(0.35, 0.75) * width
        t = np.linspace(-1, 1, 30)
        path = np.column_stack([x0 + 0.18 * width * t, y0 + rng.uniform(-40, 40) * t + 15 * t * t])
        path = np.round(path * 16).astype(np.int32).reshape(-1, 1, 2)
        cv2.polylines(whiskers, [path], False, 1.0, int(rng.integers(5, 10)), cv2.LINE_AA, 4)
    whiskers = cv2.GaussianBlur(whiskers, (0, 0), 4.0) * 0.5
    pale = np.array((0.55, 0.64, 0.80))
    lift = np.clip(fade + whiskers, 0, 0.8)[..., None]
    image = np.ascontiguousarray(((1 - lift) * cloth + lift * pale * yarn).astype(np.float32))
    gold = np.array(GOLD_THREAD)
    # The top of a back pocket, lower left: darker (unfaded) below its hem, a shadow round it.
    x0, x1 = int(0.05 * width), int(0.34 * width)
    top = int(0.56 * height)
    pocket = np.array([(x0, top), (x1, top + 10), (x1 - 8, height + 40), (x0 + 8, height + 40)])
    mask = _polygon_mask(shape, pocket)
    shadow = cv2.GaussianBlur(np.roll(mask, (6, 3), axis=(0, 1)), (0, 0), 5.0) * (1 - mask)
    image *= (1 - 0.5 * shadow - 0.25 * mask)[..., None]
    hem = np.array([(x0, top + 28), (x1, top + 38)])
    for offset in (0.0, 28.0):  # the hem's folded edge, its stitching, the sides' stitching
        row = np.array([(x0 + 6, top + 6 + offset), (x1 - 6, top + 16 + offset)])
        _stitches(image, row, gold, closed=False, length=8, gap=3, thickness=3)
    cv2.line(
        image,
        tuple(hem[0]),
        tuple(hem[1]),
        (INDIGO[0] * 0.5, INDIGO[1] * 0.5, INDIGO[2] * 0.5),
        2,
        cv2.LINE_AA,
    )
    for side in (1, -1):
        for inset in (8, 16):
            x = x0 + inset if side == 1 else x1 - inset
            row = np.array([(x, top + 40), (x + side * 6, height)])
            _stitches(image, row, gold, closed=False, length=8, gap=3, thickness=3)
    for inset in (0, 10):  # the arc on the pocket
        t = np.linspace(0, 1, 40)
        arc = np.column_stack(
            [x0 + 20 + (x1 - x0 - 40) * t, top + 110 + inset - 55 * np.sin(2 * np.pi * t) ** 2]
        )
        _stitches(image, arc, gold, closed=False, length=8, gap=3, thickness=3)
    for x in (x0 + 4, x1 - 4):  # copper rivets at the pocket's top corners
        c = (x, top + 10)
        cv2.circle(image, c, 11, (0.35, 0.18, 0.08), -1, cv2.LINE_AA)
        cv2.circle(image, c, 8, (0.72, 0.42, 0.20), -1, cv2.LINE_AA)
        cv2.circle(image, (c[0] - 3, c[1] - 3), 3, (0.95, 0.75, 0.55), -1, cv2.LINE_AA)
    # A felled seam down the left part: a ridge with two rows of gold topstitching.
    seam = int(0.42 * width) + int(rng.integers(-10, 10))
    ridge = np.exp(-(((xs - seam) / 14.0) ** 2))[..., None]
    image *= 0.82 + 0.3 * ridge - 0.2 * np.exp(-(((xs - seam - 22) / 5.0) ** 2))[..., None]
    for offset in (-10, 10):
        row = np.array([(seam + offset, -10), (seam + offset, height + 10)])
        _stitches(image, row, gold, closed=False, length=8, gap=3, thickness=3)
    # The patches: round with a star (upper left), a heart (upper right), a label (middle),
    # a lightning bolt (lower right), and an embroidered daisy.
    yellow, red, pink, cream, black, orange = DENIM_INK
    at = np.array((rng.uniform(0.16, 0.22) * width, 0.25 * height))
    _patch(image, _ellipse_points(at, (85, 85), 0.0), yellow, red, 14)
    star = _star_points(at, 58, 24, rng.uniform(-10, 10))
    cv2.fillPoly(image, [np.round(star * 16).astype(np.int32)], red.tolist(), cv2.LINE_AA, 4)
    _stitches(image, _ellipse_points(at, (66, 66), 0.0), red, length=7, gap=3, thickness=2)
    at = np.array((0.80 * width, rng.uniform(0.2, 0.26) * height))
    _patch(image, _heart_points(at, 130, rng.uniform(-15, 15)), pink, cream, 10)
    turn = rng.uniform(-8, 8)
    w, h = 240, 92
    at = np.array((rng.uniform(0.55, 0.6) * width, 0.45 * height))
    c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
    box = np.array([(-w, -h), (w, -h), (w, h), (-w, h)]) / 2 @ np.array([[c, s], [-s, c]]) + at
    _patch(image, box, cream, black, 10)
    label = np.zeros(shape, np.float32)
    word = (_random_text(rng, 6).replace(" ", "") or "DENIM")[:6]
    (tw, th), _ = cv2.getTextSize(word, cv2.FONT_HERSHEY_TRIPLEX, 1.9, 5)
    org = (int(at[0] - tw / 2), int(at[1] + th / 2))
    cv2.putText(label, word, org, cv2.FONT_HERSHEY_TRIPLEX, 1.9, 1.0, 5, cv2.LINE_AA)
    label = cv2.warpAffine(label, cv2.getRotationMatrix2D(tuple(at), -turn, 1.0), (width, height))
    image = (1 - label[..., None]) * image + label[..., None] * red
    image = np.ascontiguousarray(image.astype(np.float32))
    bolt = np.array(
        [
            (0.1, -1.0),
            (0.55, -1.0),
            (0.2, -0.15),
            (0.6, -0.15),
            (-0.35, 1.0),
            (-0.05, 0.1),
            (-0.45, 0.1),
        ]
    )
    at = np.array((0.8 * width, 0.74 * height))
    _patch(image, bolt * 110 + at, orange, black, 10)
    at = np.array((rng.uniform(0.6, 0.66) * width, 0.85 * height))  # the embroidered daisy
    for k in range(10):
        angle = 2 * np.pi * k / 10
        tip = at + 34 * np.array((math.cos(angle), math.sin(angle)))
        petal = _ellipse_points((at + tip) / 2, (17, 6), math.degrees(angle))
        cv2.fillPoly(image, [np.round(petal * 16).astype(np.int32)], cream.tolist(), cv2.LINE_AA, 4)
        cv2.polylines(
            image,
            [np.round(petal * 16).astype(np.int32)],
            True,
            (cream * 0.7).tolist(),
            1,
            cv2.LINE_AA,
            4,
        )
    cv2.circle(image, tuple(np.round(at).astype(int)), 11, yellow.tolist(), -1, cv2.LINE_AA)
    image = image * (1 + 0.015 * rng.standard_normal((*shape, 1))).astype(np.float32)
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


BANDANA_RED = (0.74, 0.08, 0.10)  # the bandana's cotton (sRGB)
BANDANA_BACK = (0.62, 0.16, 0.16)  # its back: the print's red showing through, faded (sRGB)
BANDANA_WHITE = (0.96, 0.95, 0.92)
BANDANA_BLACK = (0.06, 0.05, 0.06)


def _paisley_points(centre, size, turn, curl):
    """A paisley (boteh): a drop with a round foot whose tip curls ``curl`` rad to one side.

    ``size`` is its length (texels), ``turn`` (deg) the direction its tip points in, before the
    curl. Returns float points (N, 2).
    """
    t = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    x = 0.72 * np.sin(t) * np.abs(np.sin(t / 2)) ** 1.3
    y = -np.cos(t)  # the tip at y = -1, the foot at y = 1
    # The curl: turn each point about the foot's middle, the more the nearer the tip.
    along = np.clip((0.35 - y) / 1.35, 0, 1) ** 2
    angle = curl * along
    px, py = x, y - 0.35
    x = px * np.cos(angle) - py * np.sin(angle)
    y = px * np.sin(angle) + py * np.cos(angle) + 0.35
    c, s = math.cos(math.radians(turn + 90)), math.sin(math.radians(turn + 90))
    points = np.column_stack([x, y]) * size / 2
    return points @ np.array([[c, s], [-s, c]]) + centre


def _paisley(image, rng, centre, size, turn, curl):
    """A printed paisley: white, outlined in black, with an inner drop, dots and ticks."""
    white, black = list(BANDANA_WHITE), list(BANDANA_BLACK)
    outer = _paisley_points(centre, size, turn, curl)
    foot = np.asarray(centre) + 0.15 * size * np.array(
        (-math.cos(math.radians(turn)), -math.sin(math.radians(turn)))
    )
    inner = 0.55 * (outer - foot) + foot
    width = max(2, int(size / 30))
    for k in range(18, 73, 3):  # ticks round the foot, like feathers
        d = outer[k] - foot
        tip = outer[k] + 0.12 * size * d / np.linalg.norm(d)
        p, q = (tuple(np.round(v * 16).astype(int)) for v in (outer[k], tip))
        cv2.line(image, p, q, black, width, cv2.LINE_AA, shift=4)
    poly = [np.round(outer * 16).astype(np.int32)]
    cv2.fillPoly(image, poly, white, cv2.LINE_AA, 4)
    cv2.polylines(image, poly, True, black, 2 * width, cv2.LINE_AA, 4)
    middle = 0.78 * (outer - foot) + foot
    for point in middle[::4]:  # a ring of red dots between the outlines
        cv2.circle(
            image,
            tuple(np.round(point).astype(int)),
            max(2, int(size / 28)),
            list(BANDANA_RED),
            -1,
            cv2.LINE_AA,
        )
    poly = [np.round(inner * 16).astype(np.int32)]
    cv2.fillPoly(image, poly, black, cv2.LINE_AA, 4)
    core = 0.55 * (inner - foot) + foot
    cv2.fillPoly(image, [np.round(core * 16).astype(np.int32)], list(BANDANA_RED), cv2.LINE_AA, 4)
    cv2.circle(
        image, tuple(np.round(foot).astype(int)), max(3, int(size / 16)), white, -1, cv2.LINE_AA
    )


def _flower(image, centre, radius, colour, heart):
    for k in range(4):
        angle = math.pi / 4 + k * math.pi / 2
        petal = np.asarray(centre) + radius * np.array((math.cos(angle), math.sin(angle)))
        cv2.circle(
            image, tuple(np.round(petal).astype(int)), int(0.7 * radius), colour, -1, cv2.LINE_AA
        )
    cv2.circle(
        image, tuple(np.round(centre).astype(int)), int(0.5 * radius), heart, -1, cv2.LINE_AA
    )


def paisley_bandana(rng, width, height):
    """A red cotton bandana printed with white and black paisleys and a border.

    A fine plain weave of red cotton (uneven yarn, a little mottled); a border of bands (a
    black band with white dots between thin white lines, then a row of small white teardrops
    turning round the corners) and a plain red hem; in the middle a medallion (a ring of eight
    paisleys, tips out, round a white star in a black disc, inside a ring of dots); in the
    field paisleys of three sizes at random turns with small four-petal flowers and black
    fillers (dots and commas); the print a little worn.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width]
    thread = 3
    weave = ((xs // thread) + (ys // thread)) % 2
    yarn_x = 1 + 0.06 * rng.standard_normal(width // thread + 1)[xs // thread]
    yarn_y = 1 + 0.06 * rng.standard_normal(height // thread + 1)[ys // thread]
    light = np.where(weave == 1, yarn_x, yarn_y) * (0.94 + 0.06 * weave)
    light = light * (1 + 0.05 * fractal_noise(rng, shape, cells=(3, 6, 12)))
    cloth = (light[..., None] * np.array(BANDANA_RED)).astype(np.float32)
    image = np.ascontiguousarray(cloth.copy())
    white, black = list(BANDANA_WHITE), list(BANDANA_BLACK)
    centre = np.array((width / 2, height / 2))
    # The field: paisleys, largest first, kept apart; flowers and fillers between them.
    placed = []
    margin = 0.17 * width
    for size, count in ((150, 10), (100, 14), (64, 26)):
        for _ in range(200 * count):
            if count == 0:
                break
            at = rng.uniform((margin, margin), (width - margin, height - margin))
            if np.linalg.norm(at - centre) < 0.2 * width + 0.5 * size:
                continue
            if any(np.linalg.norm(at - p) < 0.55 * (size + s) for p, s in placed):
                continue
            placed.append((at, size))
            _paisley(image, rng, at, size, rng.uniform(0, 360), rng.choice((-1, 1)) * 0.9)
            count -= 1
    for _ in range(400):
        at = rng.uniform((margin, margin), (width - margin, height - margin))
        if np.linalg.norm(at - centre) < 0.2 * width or any(
            np.linalg.norm(at - p) < 0.5 * s + 18 for p, s in placed
        ):
            continue
        if rng.random() < 0.4:
            _flower(image, at, rng.uniform(7, 10), white, black)
            placed.append((at, 20))
        else:
            cv2.circle(
                image,
                tuple(np.round(at).astype(int)),
                int(rng.integers(3, 6)),
                black,
                -1,
                cv2.LINE_AA,
            )
    # The medallion.
    cv2.circle(image, tuple(np.round(centre).astype(int)), int(0.19 * width), white, 4, cv2.LINE_AA)
    for k in range(36):
        angle = 2 * np.pi * k / 36
        dot = centre + 0.175 * width * np.array((math.cos(angle), math.sin(angle)))
        cv2.circle(image, tuple(np.round(dot).astype(int)), 6, black, -1, cv2.LINE_AA)
    for k in range(8):
        angle = 2 * np.pi * k / 8 + 0.2
        at = centre + 0.1 * width * np.array((math.cos(angle), math.sin(angle)))
        _paisley(image, rng, at, 96, math.degrees(angle), 0.8)
    cv2.circle(image, tuple(np.round(centre).astype(int)), 44, black, -1, cv2.LINE_AA)
    star = _star_points(centre, 38, 16, rng.uniform(0, 72))
    cv2.fillPoly(image, [np.round(star * 16).astype(np.int32)], white, cv2.LINE_AA, 4)
    # The border: bands round the edge, a row of small teardrops inside them, a plain hem.
    hem, band, row = int(0.035 * width), int(0.055 * width), int(0.05 * width)
    edge = np.minimum(np.minimum(xs, ys), np.minimum(width - 1 - xs, height - 1 - ys))
    image[edge < hem + band + row] = cloth[edge < hem + band + row]
    lines = ((edge >= hem) & (edge < hem + 5)) | ((edge >= hem + band - 5) & (edge < hem + band))
    image[(edge >= hem + 5) & (edge < hem + band - 5)] = black
    image[lines] = white
    for inset, step, draw in ((hem + band / 2, 26.0, "dot"), (hem + band + row / 2, 52.0, "drop")):
        corners = np.array(
            [
                (inset, inset),
                (width - inset, inset),
                (width - inset, height - inset),
                (inset, height - inset),
            ]
        )
        for k in range(4):
            a, b = corners[k], corners[(k + 1) % 4]
            length = np.linalg.norm(b - a)
            along = (b - a) / length
            turn = math.degrees(math.atan2(along[1], along[0]))
            count = int(length // step)
            for n in range(count + 1):
                at = a + (n * length / count) * along
                if draw == "dot":
                    cv2.circle(image, tuple(np.round(at).astype(int)), 5, white, -1, cv2.LINE_AA)
                elif 0 < n < count:
                    drop = [
                        np.round(_paisley_points(at, 0.8 * row, turn, 0.9) * 16).astype(np.int32)
                    ]
                    cv2.fillPoly(image, drop, white, cv2.LINE_AA, 4)
                    cv2.polylines(image, drop, True, black, 3, cv2.LINE_AA, 4)
                    cv2.circle(image, tuple(np.round(at).astype(int)), 3, black, -1, cv2.LINE_AA)
    # Worn print: the cloth shows through here and there; the weave's light over everything.
    worn = np.clip(0.5 + 2.0 * fractal_noise(rng, shape, cells=(8, 16, 32)), 0, 1) * 0.25
    worn = (worn * (rng.random(shape) < 0.5))[..., None]
    image = (1 - worn) * image + worn * cloth
    image = image * (0.96 + 0.04 * light)[..., None] / (0.96 + 0.04 * light.mean())
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.6), 0, 1)


# --- scenes ---------------------------------------------------------------------------------

FELT_SIZE = (1.7, 1.5)
FELT_AT = (0.35, 0.2)  # felt_yaw_turn: the coaster's centre at rest, right of and above
FELT_TILT = 8.0  # the turning axis: deg from the vertical, its top leaning right
FELT_TURN = 75.0  # how far it turns (deg): strongly foreshortened, not past edge-on
FELT_GRIP = 0.18  # the fingertips: how far up the axis from the middle of the left edge
FELT_BEHIND = 0.2  # the hand's depth behind the felt's painted side (the fingers behind it)
TEAL_FELT = (0.05, 0.11, 0.12, 1.0)  # felt_yaw_turn's back and rim (linear RGB)


def build_felt_yaw_turn(rng, clip):
    studio_lights()
    size = FELT_SIZE
    tilt = math.radians(FELT_TILT)
    axis = np.array((math.sin(tilt), math.cos(tilt)))  # up and a little right
    sheet, pivot = plush_on_pivot(
        rng, folk_felt_coaster, size, (68, 60), 0.0, (0.3, 0.5, (0.9, 0.9, 0.9, 1.0))
    )
    # The pivot: the tilted axis through the middle of the left edge; turning about it by a
    # positive angle takes the part right of it (all but a sliver of the lower left corner)
    # away from the camera. The coaster turns as a whole: no bend.
    at = np.array(FELT_AT) - (size[0] / 2, 0.0)
    pivot.location = (*at, 0.0)
    pivot.rotation_mode = "AXIS_ANGLE"
    pivot.rotation_axis_angle = (0.0, *axis, 0.0)
    sheet.obj.location = (size[0] / 2, 0.0, 0.0)
    # To FELT_TURN in 0.7 s, held 0.3 s, back to flat in 1 s while it drifts right and down
    # (about 15 px).
    clip.keyframe(
        pivot,
        {
            ("rotation_axis_angle", 0): deg(
                [(0.0, 0), (0.5, 0), (1.2, FELT_TURN), (1.5, FELT_TURN), (2.5, 0)]
            ),
            ("location", 0): [(0.0, at[0]), (1.5, at[0]), (2.6, at[0] + 0.11)],
            ("location", 1): [(0.0, at[1]), (1.5, at[1]), (2.6, at[1] - 0.09)],
        },
    )
    # The hand holds the middle of the left edge from behind: its fingers (pointing up the
    # axis) behind the felt, the palm and forearm reaching down along the axis out of the
    # image, the back of the hand away from the felt; moved with the coaster on every frame, it
    # rolls about its forearm as the coaster turns. It comes in along the axis from below and
    # leaves the same way.
    grids = sheet_frames(clip, sheet)
    t = np.arange(clip.frames) / clip.fps
    away = eased(t, [(0.0, 3.5), (0.1, 3.5), (0.45, 0.0), (2.8, 0.0), (3.3, 3.5)])
    hand = add_pushing_hand("Hand", True)
    middle = grids.shape[1] // 2
    poses = []
    for grid, out in zip(grids, away, strict=True):
        edge = grid[middle, 0]
        along_x = grid[middle, 2] - edge
        along_y = grid[middle - 2, 0] - edge
        along_x, along_y = along_x / np.linalg.norm(along_x), along_y / np.linalg.norm(along_y)
        normal = np.cross(along_x, along_y)
        a = axis[0] * along_x + axis[1] * along_y
        tips = edge + (FELT_GRIP - out) * a - FELT_BEHIND * normal
        poses.append(hand_pose(tips, a, -normal))
    key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, TEAL_FELT)
    return sheet


DENIM_SIZE = (2.2, 1.6)
DENIM_AT = (-0.45, -0.12)  # denim_corner_tuck: the patch's centre at rest, left of and below
DENIM_ANGLE = -47.0  # the fold's direction (deg from +X: down and right, to the corner)
DENIM_CREASE = 0.31  # the crease's distance from the centre along it: 30 % beyond it
DENIM_BAND = 0.2  # folded, the corner lies 2 * band / pi behind the rest
DENIM_HAND = 36.0  # the hand comes in along this direction (deg from +X, patch frame)


def build_denim_corner_tuck(rng, clip):
    studio_lights()
    size = DENIM_SIZE
    sheet = add_sheet(
        patched_denim,
        size,
        (88, 64),
        4,
        rng=rng,
        roughness=0.85,
        specular=0.2,
        thickness=0.02,
    )
    set_sheen(sheet, 0.2, 0.5)  # cotton twill
    # The lower right corner folds back behind the rest about a diagonal crease (from the
    # bottom edge left of the middle up to the right edge near the top), over a band of
    # DENIM_BAND.
    angle = math.radians(DENIM_ANGLE)
    crease_bend(sheet, "Fold", size, angle, DENIM_CREASE, DENIM_BAND, diagonal_away)
    # The fold (keyed on every frame) at a medium speed (0.62 s) from 0.5 s; unfolds from
    # 1.52 s. The hand pushes the patch a little left and down and turns it 3 deg clockwise.
    t = np.arange(clip.frames) / clip.fps
    fold = fold_and_unfold(t, 0.5, 1.52, paced_fold(4.0, 12.0, 55.0))
    x0, y0 = DENIM_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): list(zip(t, fold, strict=True)),
            ("location", 0): [(0.0, x0), (0.45, x0), (1.1, x0 - 0.08), (2.3, x0 - 0.05)],
            ("location", 1): [(0.0, y0), (0.45, y0), (1.1, y0 - 0.06), (2.3, y0 - 0.04)],
            ("rotation_euler", 2): deg([(0.0, 0), (0.45, 0), (1.1, -3), (2.4, -2)]),
        },
    )
    # The hand comes in from the upper right in front of the patch and moves with it, its
    # fingers (pointing down and left) over the upper right part, beside the crease's upper
    # end. Where its fingertips are: how far out from the patch's centre along DENIM_HAND,
    # and how far across it (patch frame).
    tips = [(0.0, 4.4), (0.1, 4.4), (0.5, 0.5), (1.52, 0.44), (2.2, 0.5), (3.0, 4.4)]
    out = np.array((math.cos(math.radians(DENIM_HAND)), math.sin(math.radians(DENIM_HAND))))
    normal = np.array((-out[1], out[0]))
    hand = add_pushing_hand("Hand", False)
    poses = []
    for m, r in zip(object_matrices(clip, sheet.obj), eased(t, tips), strict=True):
        local = r * out + 0.05 * normal
        tip = m[:3, :3] @ (*local, 0.0) + m[:3, 3]
        tip[2] = HAND_DEPTH
        poses.append(hand_pose(tip, m[:3, :3] @ (*(-out), 0.0), (0.0, 0.0, 1.0)))
    key_every_frame(clip, hand, poses)
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(DENIM_BACK)), 1.0))
    return sheet


BANDANA_SIZE = (1.9, 1.9)
BANDANA_AT = (0.45, 0.02)  # bandana_diagonal_fold: the cloth's centre at rest, right of middle
BANDANA_ANGLE = 133.0  # the fold's direction (deg from +X: up and left; 135 is the corner's)
BANDANA_CREASE = 0.3  # the crease's distance from the centre along it (30 % beyond it)
BANDANA_BAND = 0.15  # folded, the flap lies 2 * band / pi in front


def build_bandana_diagonal_fold(rng, clip):
    studio_lights()
    size = BANDANA_SIZE
    sheet = add_sheet(
        paisley_bandana,
        size,
        (76, 76),
        4,
        rng=rng,
        roughness=0.9,
        specular=0.2,
        thickness=0.008,
    )
    set_sheen(sheet, 0.3, 0.45)  # cotton
    # The top left triangle folds over towards the camera about a crease (nearly) parallel to
    # the diagonal, BANDANA_CREASE off it towards the top left corner, and lies over the rest
    # about 0.1 in front of it, its plain back to the camera.
    angle = math.radians(BANDANA_ANGLE)
    crease_bend(sheet, "Fold", size, angle, BANDANA_CREASE, BANDANA_BAND, diagonal_towards_camera)
    # Fast over (0.5 s), slowly back (1.2 s); while it unfolds the cloth turns 8 deg
    # anticlockwise and drifts left and up.
    x0, y0 = BANDANA_AT
    sheet.obj.location = (x0, y0, 0.0)
    clip.keyframe(
        sheet.obj,
        {
            ('modifiers["Fold"].angle', 0): deg(
                [(0.0, 0), (0.2, 0), (0.45, 95), (0.7, 180), (1.0, 180), (1.6, 100), (2.2, 0)]
            ),
            ("location", 0): [(0.0, x0), (1.0, x0), (2.6, x0 - 0.21)],
            ("location", 1): [(0.0, y0), (1.0, y0), (2.6, y0 + 0.12)],
            ("rotation_euler", 2): deg([(0.0, 0), (1.0, 0), (2.6, 8)]),
        },
    )
    finish_sheet(sheet)
    set_back_colour(sheet, (*srgb_to_linear(np.array(BANDANA_BACK)), 1.0))
    return sheet


HELDOUT_FOLDS5 = [
    Clip(
        "felt_yaw_turn",
        102,
        30,
        "a folk-art felt coaster with appliqued felt flowers and stitching, right of and above "
        "the middle, held by a hand behind the middle of its left edge, is turned as a whole "
        "(no crease) in depth about an axis through the hand leaning 8 deg from the vertical: "
        "its right edge goes away from the camera, to 75 deg in 0.7 s (strongly foreshortened, "
        "not past edge-on); holds 0.3 s, turns back to flat in 1 s while it drifts about 15 px "
        "right and down; the hand leaves",
        build_felt_yaw_turn,
    ),
    Clip(
        "denim_corner_tuck",
        100,
        30,
        "the lower right corner (30 %) of a denim patch with iron-on patches, a seam and a "
        "pocket's top folds back 180 deg behind the rest about a diagonal crease, at a medium "
        "speed (0.62 s), while a hand in from the upper right lies over the upper right part "
        "and pushes the patch about 10 px left and down, turning it 3 deg; holds 0.4 s, "
        "unfolds; the hand leaves",
        build_denim_corner_tuck,
    ),
    Clip(
        "bandana_diagonal_fold",
        100,
        30,
        "the top left triangle (30 %) of a square red paisley bandana folds over towards the "
        "camera by 180 deg onto the rest, about a crease along its diagonal, 0.3 off it towards "
        "the corner (its plain back covers about 21 % more of the print), fast "
        "(0.5 s); holds 0.3 s and unfolds slowly (1.2 s) while the cloth turns 8 deg and "
        "drifts about 25 px left and up",
        build_bandana_diagonal_fold,
    ),
]


README_HELDOUT_FOLDS5 = (
    """# Held-out clips of folds, fifth batch

Clips for checking that the tracker generalises to folds (issue 22): never tune it on these;
they are to be measured once, as held-out. The tracker was tuned on the fold clips of
[`../folds`](../folds/README.md); like the first four held-out batches
([`../heldout_folds`](../heldout_folds/README.md),
[`../heldout_folds2`](../heldout_folds2/README.md),
[`../heldout_folds3`](../heldout_folds3/README.md) and
[`../heldout_folds4`](../heldout_folds4/README.md)) these show the same kinds of motion (a
sheet turned in depth, a part folded back behind the rest, a part folded over the rest) with
paint, axes, speeds and places that no earlier batch has: a felt coaster turned as a whole,
with no crease, to 75 deg about an almost vertical axis by a hand at its left edge (strongly
foreshortened, never past edge-on); the corner of a denim patch folded back along a diagonal
crease while a hand from the upper right covers part of the patch; a square bandana folded
over along (near) its diagonal, fast, and unfolded slowly while it turns and drifts. Rendered
with Blender {blender} (the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes and paint in
`scripts/hardclips/heldout_folds5.py`) from a fixed seed, so the same command makes the same
scenes, truth and outlines; it makes them only when named, apart from every other clip:

    OMP_NUM_THREADS=1 .venv/bin/python scripts/render_hard_clips.py \\
        --out samples/heldout_folds5 --only {names}

Keep them out of `samples/folds` and `samples/heldout_folds` to `samples/heldout_folds4`.
Check them with `.venv/bin/python scripts/check_hard_clips.py --dir samples/heldout_folds5`
(statistics, and contact sheets in `/tmp/hard_check/`).

"""
    + FOLD_FILES
)
