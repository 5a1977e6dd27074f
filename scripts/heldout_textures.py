"""Paint for the held-out hard clips: styles that no clip the tracker was tuned on uses.

``woven`` (``handheld_zoom``), ``street_map`` (``occluded_exit``) and ``marbled``
(``glossy_fast_twist``) follow ``hard_textures``: each takes a seeded
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
