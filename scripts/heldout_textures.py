"""Paint for the held-out hard clips: styles that no clip the tracker was tuned on uses.

``woven`` (``handheld_zoom``), ``street_map`` (``occluded_exit``), ``marbled``
(``glossy_fast_twist``), and for the held-out fold clips ``pouch_print`` (``pouch_crush``) and
``tee_print`` (``cloth_corner_fold``) follow ``hard_textures``: each takes a seeded
``numpy.random.Generator`` and a size in texels and returns an sRGB image, (height, width, 3)
float32 in [0, 1] with rows top-down. The clips use about 1024 texels across, about 3.5 texels
to a pixel at rest.
"""

import cv2
import numpy as np
from foam_paint import smooth_noise
from hard_textures import _colour, _random_text, _smooth_path, fractal_noise

THREAD = 8  # texels per thread of the weave (about 2 px at rest)
SETT = np.array(  # a tartan's stripe colours, mirrored to make the repeat
    [
        (0.55, 0.10, 0.12),
        (0.08, 0.12, 0.30),
        (0.55, 0.10, 0.12),
        (0.10, 0.30, 0.16),
        (0.90, 0.82, 0.55),
        (0.05, 0.05, 0.06),
    ]
)
MOTIF_PALETTE = np.array([(0.95, 0.93, 0.85), (0.95, 0.75, 0.15), (0.20, 0.55, 0.75)])


def _stripes(rng, length):
    """A colour index per texel along one axis: a mirrored sett of random widths, repeated."""
    widths = rng.integers(1, 7, len(SETT)) * THREAD
    sett = np.repeat(np.arange(len(SETT)), widths)
    sett = np.concatenate([sett, sett[::-1]])
    return np.resize(sett, length)


def woven(rng, width, height):
    """Tartan twill: stripes of warp and weft threads, 2/2 twill, uneven yarn, printed motifs."""
    ys, xs = np.mgrid[0:height, 0:width]
    warp = SETT[_stripes(rng, width)][None, :, :]  # (1, W, 3)
    weft = SETT[_stripes(rng, height)][:, None, :]  # (H, 1, 3)
    i, j = xs // THREAD, ys // THREAD
    warp_up = ((i + j) % 4) < 2  # 2/2 twill: diagonal ribs
    image = np.where(warp_up[..., None], warp, weft)
    # Each thread is a round yarn (darker at its edges) with its own shade (slubs).
    phase = np.where(warp_up, xs % THREAD, ys % THREAD) + 0.5
    image = image * (0.75 + 0.25 * np.sin(np.pi * phase / THREAD))[..., None]
    slub_x = 1 + 0.08 * rng.standard_normal(width // THREAD + 1)
    slub_y = 1 + 0.08 * rng.standard_normal(height // THREAD + 1)
    image = image * np.where(warp_up, slub_x[i], slub_y[j])[..., None]
    image = image * (1 + 0.06 * fractal_noise(rng, (height, width), cells=(4, 8, 16)))[..., None]
    image = np.ascontiguousarray(image.astype(np.float32))
    for _ in range(9):  # a few printed motifs: petals round a dot, a ring
        cx, cy = rng.uniform(0.05, 0.95) * width, rng.uniform(0.05, 0.95) * height
        size = rng.uniform(28, 60)
        colour = _colour(MOTIF_PALETTE, rng)
        turn = rng.uniform(0, 360)
        for k in range(6):
            angle = np.radians(turn + 60 * k)
            centre = (cx + 0.6 * size * np.cos(angle), cy + 0.6 * size * np.sin(angle))
            axes = (int(0.45 * size), int(0.2 * size))
            centre = (int(centre[0]), int(centre[1]))
            cv2.ellipse(image, centre, axes, turn + 60 * k, 0, 360, colour, -1, cv2.LINE_AA)
        cv2.circle(image, (int(cx), int(cy)), int(0.3 * size), (0.9, 0.2, 0.15), -1, cv2.LINE_AA)
        cv2.circle(image, (int(cx), int(cy)), int(1.25 * size), colour, 3, cv2.LINE_AA)
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.7), 0, 1)


ROAD_COLOURS = ((0.98, 0.80, 0.35), (1.0, 1.0, 1.0))  # major, minor
INK = np.array([(0.15, 0.15, 0.18), (0.35, 0.20, 0.45), (0.45, 0.25, 0.10), (0.10, 0.25, 0.50)])


def street_map(rng, width, height):
    """A printed street map: land tint, a lake, parks, contours, roads, labels, a grid, grain."""
    shape = (height, width)
    land = np.array((0.95, 0.93, 0.86)) * (1 + 0.03 * fractal_noise(rng, shape))[..., None]
    image = land.astype(np.float32)
    relief = fractal_noise(rng, shape, cells=(2, 4, 8))
    parks = fractal_noise(rng, shape, cells=(3, 6, 12)) > 0.35
    image[parks] = (0.72, 0.85, 0.62)
    water = relief < -0.45
    image[water] = (0.62, 0.78, 0.92)
    for level in np.arange(-0.3, 0.9, 0.1):  # contour lines round the hills
        mask = ((relief > level) * 255).astype(np.uint8)
        contours, _ = cv2.findContours(mask, cv2.RETR_LIST, cv2.CHAIN_APPROX_NONE)
        cv2.drawContours(image, contours, -1, (0.70, 0.55, 0.40), 1, cv2.LINE_AA)
    shore, _ = cv2.findContours(water.astype(np.uint8), cv2.RETR_LIST, cv2.CHAIN_APPROX_NONE)
    cv2.drawContours(image, shore, -1, (0.25, 0.45, 0.70), 2, cv2.LINE_AA)
    for major, count, casing, lane in ((False, 40, 9, 5), (True, 9, 17, 11)):
        paths = []
        for _ in range(count):
            start = rng.uniform((0, 0), (width, height))
            paths.append(_smooth_path(rng, start, 24, 30, 0.12 if major else 0.05))
        cv2.polylines(image, paths, False, (0.45, 0.42, 0.40), casing, cv2.LINE_AA, shift=4)
        cv2.polylines(image, paths, False, ROAD_COLOURS[not major], lane, cv2.LINE_AA, shift=4)
    for k in range(1, 8):  # the map grid
        x, y = k * width // 8, k * height // 8
        cv2.line(image, (x, 0), (x, height), (0.30, 0.40, 0.70), 1, cv2.LINE_AA)
        cv2.line(image, (0, y), (width, y), (0.30, 0.40, 0.70), 1, cv2.LINE_AA)
    for _ in range(70):  # names of streets and places, small and large
        org = (int(rng.uniform(-0.05, 0.9) * width), int(rng.uniform(0.02, 1) * height))
        scale = rng.choice([0.3, 0.4, 0.5, 0.8])
        font = cv2.FONT_HERSHEY_SIMPLEX if rng.random() < 0.6 else cv2.FONT_HERSHEY_TRIPLEX
        text = _random_text(rng, int(rng.integers(3, 12)))
        cv2.putText(image, text, org, font, scale, _colour(INK, rng), 1, cv2.LINE_AA)
    for _ in range(25):  # symbols: dots in rings
        centre = (int(rng.uniform(0, width)), int(rng.uniform(0, height)))
        cv2.circle(image, centre, 6, (0.80, 0.15, 0.15), 2, cv2.LINE_AA)
        cv2.circle(image, centre, 2, (0.10, 0.10, 0.10), -1, cv2.LINE_AA)
    image *= (1 + 0.04 * rng.standard_normal(shape)).astype(np.float32)[..., None]  # paper
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


MARBLE_PALETTE = np.array(
    [
        (0.10, 0.18, 0.35),
        (0.85, 0.80, 0.70),
        (0.65, 0.20, 0.18),
        (0.92, 0.90, 0.85),
        (0.20, 0.45, 0.42),
        (0.80, 0.62, 0.30),
        (0.30, 0.15, 0.30),
    ]
)


def marbled(rng, width, height):
    """Marbled paper: bands of ink combed into swirls, dark veins, gold speckles."""
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float64)
    angle = rng.uniform(0, np.pi)
    for strength, cells in ((110.0, (2, 4, 8)), (35.0, (6, 12, 24))):  # stirred twice
        dx = strength * fractal_noise(rng, shape, cells=cells)
        dy = strength * fractal_noise(rng, shape, cells=cells)
        xs, ys = xs + dx, ys + dy
    combs = 6.0 * np.sin(2 * np.pi * (xs * np.sin(angle) - ys * np.cos(angle)) / 45.0)
    band = (xs * np.cos(angle) + ys * np.sin(angle) + combs) / 26.0  # a band per 26 texels
    index = np.floor(band).astype(int)
    order = rng.integers(len(MARBLE_PALETTE), size=index.max() - index.min() + 1)
    image = MARBLE_PALETTE[order[index - index.min()]]  # (H, W, 3)
    edge = np.abs(band - np.round(band))  # 0 on the boundary between two bands
    image = image * (0.55 + 0.45 * np.clip(edge / 0.12, 0, 1))[..., None]  # dark veins
    image = image * (1 + 0.08 * smooth_noise(rng, shape, 40))[..., None]
    image = np.ascontiguousarray(image.astype(np.float32))
    for _ in range(400):  # gold and white speckles
        centre = (int(rng.uniform(0, width)), int(rng.uniform(0, height)))
        colour = (0.95, 0.80, 0.35) if rng.random() < 0.7 else (0.98, 0.97, 0.95)
        cv2.circle(image, centre, int(rng.integers(1, 4)), colour, -1, cv2.LINE_AA)
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


POUCH_INK = np.array(
    [
        (0.98, 0.95, 0.85),
        (0.96, 0.78, 0.20),
        (0.20, 0.55, 0.30),
        (0.85, 0.30, 0.15),
        (0.10, 0.08, 0.12),
    ]
)


def _star(centre, points, outer, inner, turn):
    """A star polygon (``points`` tips) for cv2.fillPoly: (2 * points, 1, 2) int32."""
    angles = turn + np.pi * np.arange(2 * points) / points
    radii = np.where(np.arange(2 * points) % 2 == 0, outer, inner)
    corners = np.column_stack([np.cos(angles), np.sin(angles)]) * radii[:, None] + centre
    return np.round(corners).astype(np.int32).reshape(-1, 1, 2)


def pouch_print(rng, width, height):
    """A printed snack pouch: plum-to-orange ground, wordmark, citrus slices, badges, small print.

    Fine wavy guilloche lines cover the ground; the wordmark lies on a tilted cream ribbon.
    """
    shape = (height, width)
    ys = np.arange(height)[:, None]  # (H, 1)
    fade = np.clip(ys / height + 0.15 * fractal_noise(rng, shape, cells=(2, 4)), 0, 1)[..., None]
    top, bottom = np.array((0.36, 0.10, 0.30)), np.array((0.90, 0.48, 0.16))
    image = np.ascontiguousarray(((1 - fade) * top + fade * bottom).astype(np.float32))
    for k in range(0, height + 40, 14):  # guilloche: two families of fine wavy lines
        for period, amplitude, tint in ((170.0, 9.0, 1.25), (95.0, 5.0, 0.8)):
            x = np.arange(0, width + 8, 8, dtype=np.float64)
            y = k + amplitude * np.sin(2 * np.pi * x / period + rng.uniform(0, 2 * np.pi))
            path = np.round(np.column_stack([x, y]) * 16).astype(np.int32).reshape(-1, 1, 2)
            colour = tuple(float(c) for c in np.clip(image[min(k, height - 1), 0] * tint, 0, 1))
            cv2.polylines(image, [path], False, colour, 1, cv2.LINE_AA, shift=4)
    # A cream ribbon with the wordmark, in the upper part, slightly tilted.
    y0 = rng.uniform(0.12, 0.2) * height
    ribbon = np.array(
        [(0, y0), (width, y0 - 0.05 * height), (width, y0 + 0.17 * height), (0, y0 + 0.22 * height)]
    )
    cv2.fillPoly(image, [np.round(ribbon).astype(np.int32)], POUCH_INK[0].tolist(), cv2.LINE_AA)
    word = _random_text(rng, 7).replace(" ", "")
    org = (int(0.06 * width), int(y0 + 0.16 * height))
    for colour, thickness in (((0.55, 0.08, 0.20), 12), ((0.95, 0.70, 0.15), 3)):  # outlined
        cv2.putText(image, word, org, cv2.FONT_HERSHEY_TRIPLEX, 4.2, colour, thickness, cv2.LINE_AA)
    for _ in range(11):  # citrus slices: rind, flesh, white segment lines
        centre = np.array((rng.uniform(0.05, 0.95) * width, rng.uniform(0.4, 1.0) * height))
        radius = rng.uniform(35, 85)
        c = tuple(int(v) for v in centre)
        rind = (0.95, 0.62, 0.08) if rng.random() < 0.6 else (0.55, 0.75, 0.15)
        cv2.circle(image, c, int(radius), rind, -1, cv2.LINE_AA)
        cv2.circle(image, c, int(0.86 * radius), (1.0, 0.88, 0.55), -1, cv2.LINE_AA)
        cv2.circle(image, c, int(0.8 * radius), tuple(0.9 * v for v in rind), -1, cv2.LINE_AA)
        turn = rng.uniform(0, 2 * np.pi)
        for j in range(int(rng.integers(7, 11))):
            angle = turn + 2 * np.pi * j / 9
            tip = centre + 0.8 * radius * np.array((np.cos(angle), np.sin(angle)))
            cv2.line(image, c, tuple(int(v) for v in tip), (1.0, 0.92, 0.7), 3, cv2.LINE_AA)
    for _ in range(2):  # starburst badges with a price-like number
        centre = np.array((rng.uniform(0.15, 0.85) * width, rng.uniform(0.3, 0.8) * height))
        outer = rng.uniform(70, 100)
        star = _star(centre, int(rng.integers(14, 22)), outer, 0.8 * outer, rng.uniform(0, 1))
        cv2.fillPoly(image, [star], POUCH_INK[1].tolist(), cv2.LINE_AA)
        cv2.polylines(image, [star], True, POUCH_INK[4].tolist(), 3, cv2.LINE_AA)
        text = str(int(rng.integers(10, 99)))
        org = (int(centre[0] - 0.55 * outer), int(centre[1] + 0.3 * outer))
        cv2.putText(image, text, org, cv2.FONT_HERSHEY_DUPLEX, 2.2, POUCH_INK[3].tolist(), 6)
    for k in range(9):  # the small print, in a dark box low on the left
        org = (int(0.04 * width), int((0.6 + 0.04 * k) * height))
        text = _random_text(rng, int(rng.integers(12, 26)))
        cv2.putText(image, text, org, cv2.FONT_HERSHEY_SIMPLEX, 0.55, POUCH_INK[0].tolist(), 1)
    for _ in range(3):  # leaves: dark green ellipses with a light midrib
        centre = (int(rng.uniform(0.1, 0.9) * width), int(rng.uniform(0.3, 0.95) * height))
        angle = rng.uniform(0, 180)
        cv2.ellipse(image, centre, (60, 22), angle, 0, 360, POUCH_INK[2].tolist(), -1, cv2.LINE_AA)
        cv2.ellipse(image, centre, (55, 1), angle, 0, 360, (0.7, 0.85, 0.5), 2, cv2.LINE_AA)
    image *= (1 + 0.03 * rng.standard_normal(shape)).astype(np.float32)[..., None]
    return np.clip(cv2.GaussianBlur(image, (0, 0), 0.6), 0, 1)


TEE_INK = np.array(
    [
        (0.97, 0.94, 0.86),
        (0.98, 0.72, 0.12),
        (0.92, 0.30, 0.22),
        (0.15, 0.65, 0.62),
        (0.08, 0.08, 0.10),
    ]
)
JERSEY = (0.20, 0.27, 0.42)  # heather navy: the cloth, and its unprinted back


def tee_print(rng, width, height):
    """A printed t-shirt: heather navy jersey under a cracked screen print of bold shapes.

    The jersey has knit ribs and yarn flecks; the print is a striped sunset disc, stars, a big
    outlined number, block letters, a zigzag band, a lightning bolt and dots.
    """
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    # The jersey: knit columns 6 texels wide, staggered loops, heather flecks of yarn.
    ribs = 0.06 * np.sin(2 * np.pi * xs / 6) + 0.04 * np.sin(
        2 * np.pi * ys / 5 + np.pi * ((xs // 6) % 2)
    )
    flecks = cv2.GaussianBlur(rng.standard_normal(shape).astype(np.float32), (0, 0), 1.0)
    light = 1 + ribs + 0.25 * flecks + 0.04 * fractal_noise(rng, shape, cells=(4, 8))
    cloth = (light[..., None] * np.array(JERSEY, np.float32)).astype(np.float32)
    # The print, drawn as colour and coverage.
    ink = np.zeros((height, width, 3), np.float32)
    cover = np.zeros(shape, np.float32)

    def fill(mask, colour):
        ink[mask > 0] = colour
        cover[mask > 0] = 1.0

    def layer():
        return np.zeros(shape, np.uint8)

    disc = layer()  # a sunset disc, its lower half cut by stripes
    centre = (int(rng.uniform(0.35, 0.65) * width), int(rng.uniform(0.35, 0.55) * height))
    radius = int(0.3 * height)
    cv2.circle(disc, centre, radius, 1, -1, cv2.LINE_AA)
    fill(disc, TEE_INK[1])
    lower = layer()
    cv2.circle(lower, centre, radius, 1, -1, cv2.LINE_AA)
    lower[: centre[1]] = 0
    fill(lower, TEE_INK[2])
    for k in range(6):
        y = centre[1] + int((0.15 + 0.14 * k) * radius)
        cv2.rectangle(cover, (0, y), (width, y + 6 + 2 * k), 0.0, -1)
    for _ in range(9):  # stars
        star = layer()
        where = np.array((rng.uniform(0, width), rng.uniform(0, height)))
        outer = rng.uniform(30, 75)
        cv2.fillPoly(star, [_star(where, 5, outer, 0.42 * outer, rng.uniform(0, 1))], 1)
        fill(star, _colour(TEE_INK[[0, 1, 3]], rng))
    number = layer()  # a big varsity number, outlined
    org = (int(rng.uniform(0.02, 0.1) * width), int(0.92 * height))
    digits = str(int(rng.integers(10, 99)))
    cv2.putText(number, digits, org, cv2.FONT_HERSHEY_DUPLEX, 9.0, 1, 55, cv2.LINE_AA)
    fill(number, TEE_INK[0])
    inner = layer()
    cv2.putText(inner, digits, org, cv2.FONT_HERSHEY_DUPLEX, 9.0, 1, 30, cv2.LINE_AA)
    fill(inner, TEE_INK[2])
    word = layer()  # block letters across the top and the bottom right
    for (x, y), scale in (((0.05, 0.17), 3.6), ((0.5, 0.97), 2.6)):
        text = _random_text(rng, 6).replace(" ", "")
        org = (int(x * width), int(y * height))
        cv2.putText(word, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, 1, 16)
    fill(word, TEE_INK[0])
    zigzag = layer()  # a zigzag band and a lightning bolt
    x = np.linspace(-20, width + 20, 18)
    y = 0.28 * height + np.where(np.arange(18) % 2 == 0, -22, 22)
    path = np.round(np.column_stack([x, y])).astype(np.int32).reshape(-1, 1, 2)
    cv2.polylines(zigzag, [path], False, 1, 14, cv2.LINE_AA)
    fill(zigzag, TEE_INK[3])
    bolt = layer()
    bx, by = rng.uniform(0.7, 0.9) * width, rng.uniform(0.3, 0.5) * height
    shape_bolt = np.array([(0, 0), (60, 0), (30, 90), (75, 90), (-10, 250), (15, 130), (-30, 130)])
    cv2.fillPoly(bolt, [np.round(shape_bolt + (bx, by)).astype(np.int32)], 1, cv2.LINE_AA)
    fill(bolt, TEE_INK[1])
    for _ in range(60):  # dots of ink
        dot = layer()
        c = (int(rng.uniform(0, width)), int(rng.uniform(0, height)))
        cv2.circle(dot, c, int(rng.integers(5, 14)), 1, -1, cv2.LINE_AA)
        fill(dot, _colour(TEE_INK, rng))
    # Cracked, worn ink: thin gaps along noise contours and a fine speckle.
    crack = np.abs(fractal_noise(rng, shape, cells=(12, 24, 48))) < 0.025
    cover = cover * ~crack * (rng.random(shape) > 0.05)
    cover = cv2.GaussianBlur(cover.astype(np.float32), (0, 0), 0.7)[..., None]
    image = (1 - cover) * cloth + cover * ink * (0.9 + 0.1 * light[..., None])
    return np.clip(cv2.GaussianBlur(image.astype(np.float32), (0, 0), 0.5), 0, 1)
