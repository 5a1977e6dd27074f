"""Procedural paint for the hard test clips: numpy and OpenCV drawings, one style per clip.

Every function takes a seeded ``numpy.random.Generator`` and a size in texels and returns an
sRGB image, (height, width, 3) float32 in [0, 1] with rows top-down (what
``blender_scene.packed_image`` takes). Sizes are in texels, so the styles keep their look at any
resolution only roughly; the clips use about 1024 texels across.
"""

import cv2
import numpy as np
from foam_paint import smooth_noise


def fractal_noise(rng, shape, cells=(3, 6, 12, 24, 48), falloff=0.6):
    """Sum of smooth noise octaves, the k-th weighted ``falloff**k``, scaled to [-1, 1].

    Returns
    -------
    (shape[0], shape[1]) float64
    """
    total = sum(falloff**k * smooth_noise(rng, shape, n) for k, n in enumerate(cells))  # (H, W)
    return total / np.abs(total).max()


def _colour(palette, rng):
    return tuple(float(c) for c in palette[rng.integers(len(palette))])


def _smooth_path(rng, start, steps, step_len, turn):
    """A wandering polyline: ``steps`` segments of ``step_len`` with a smoothly turning heading.

    Returns
    -------
    (steps + 1, 1, 2) int32, for cv2.polylines at 4 bits of subpixel shift.
    """
    heading = rng.uniform(0, 2 * np.pi) + np.cumsum(rng.normal(0, turn, steps))
    moves = step_len * np.column_stack([np.cos(heading), np.sin(heading)])
    path = np.vstack([start, start + np.cumsum(moves, axis=0)])
    return np.round(path * 16).astype(np.int32).reshape(-1, 1, 2)


def _stroke(image, rng, colour, width, steps, step_len, turn):
    height, width_px = image.shape[:2]
    start = rng.uniform((0, 0), (width_px, height))
    path = _smooth_path(rng, start, steps, step_len, turn)
    cv2.polylines(image, [path], False, colour, int(width), cv2.LINE_AA, shift=4)


def _random_text(rng, n_chars):
    letters = np.array(list("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789   "))
    return "".join(rng.choice(letters, n_chars)).strip() or "A"


SPOT_PALETTE = np.array(
    [
        (0.93, 0.80, 0.45),
        (0.80, 0.45, 0.20),
        (0.35, 0.22, 0.12),
        (0.12, 0.10, 0.10),
        (0.55, 0.70, 0.35),
        (0.25, 0.45, 0.60),
        (0.90, 0.88, 0.80),
    ]
)


def spots(rng, width, height):
    """Colour-noise ground under ring spots (leopard-like) of many sizes and fine dots."""
    shape = (height, width)
    base = np.stack(
        [
            0.62 + 0.22 * fractal_noise(rng, shape),
            0.52 + 0.2 * fractal_noise(rng, shape),
            0.35 + 0.18 * fractal_noise(rng, shape),
        ],
        axis=-1,
    )  # (H, W, 3) warm, mottled
    image = np.ascontiguousarray(np.clip(base, 0, 1).astype(np.float32))
    warp = 6.0 * fractal_noise(rng, shape, cells=(8, 16))  # wobbly spot edges
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    for _ in range(110):
        cx, cy = rng.uniform(0, width), rng.uniform(0, height)
        radius = rng.uniform(8, 42)
        aspect = rng.uniform(0.6, 1.5)
        dist = np.hypot(xs - cx, (ys - cy) * aspect) + warp  # (H, W)
        ring = np.abs(dist - radius) < rng.uniform(2.5, 6.0)
        if rng.random() < 0.5:
            image[dist < radius] = _colour(SPOT_PALETTE, rng)
        image[ring] = SPOT_PALETTE[3]
    for _ in range(500):
        centre = (int(rng.uniform(0, width)), int(rng.uniform(0, height)))
        cv2.circle(
            image, centre, int(rng.integers(1, 4)), _colour(SPOT_PALETTE, rng), -1, cv2.LINE_AA
        )
    return np.clip(image, 0, 1)


STROKE_PALETTE = np.array(
    [
        (0.10, 0.12, 0.30),
        (0.75, 0.10, 0.12),
        (0.95, 0.70, 0.10),
        (0.10, 0.50, 0.35),
        (0.05, 0.05, 0.05),
        (0.40, 0.70, 0.90),
        (0.85, 0.40, 0.65),
    ]
)


def strokes(rng, width, height):
    """Pale paper with brush strokes of many widths and directions, splatters and scribbles."""
    shape = (height, width)
    paper = 0.86 + 0.05 * fractal_noise(rng, shape)
    image = np.ascontiguousarray(
        np.stack([paper, paper * 0.97, paper * 0.9], axis=-1).astype(np.float32)
    )
    for _ in range(70):  # broad strokes first, then ever finer ones on top
        _stroke(image, rng, _colour(STROKE_PALETTE, rng), rng.uniform(14, 34), 14, 14, 0.25)
    for _ in range(120):
        _stroke(image, rng, _colour(STROKE_PALETTE, rng), rng.uniform(3, 9), 20, 8, 0.4)
    for _ in range(90):
        _stroke(image, rng, _colour(STROKE_PALETTE, rng), 1, 30, 3, 0.8)
    for _ in range(300):
        centre = (int(rng.uniform(0, width)), int(rng.uniform(0, height)))
        cv2.circle(
            image, centre, int(rng.integers(1, 6)), _colour(STROKE_PALETTE, rng), -1, cv2.LINE_AA
        )
    grain = 1.0 + 0.04 * smooth_noise(rng, shape, 96)  # paint thickness
    return np.clip(image * grain[..., None], 0, 1)


LABEL_PALETTE = np.array(
    [
        (0.90, 0.15, 0.20),
        (0.10, 0.30, 0.65),
        (0.98, 0.80, 0.15),
        (0.15, 0.60, 0.40),
        (0.95, 0.95, 0.92),
        (0.10, 0.10, 0.12),
        (0.95, 0.50, 0.10),
    ]
)


def label(rng, width, height):
    """A printed label: colour panels, rings and bars, lines of small text, a barcode."""
    image = np.empty((height, width, 3), np.float32)
    image[:] = (0.95, 0.94, 0.90)
    for _ in range(14):
        x0, y0 = rng.uniform(-0.1, 0.9) * width, rng.uniform(-0.1, 0.9) * height
        x1, y1 = x0 + rng.uniform(0.1, 0.35) * width, y0 + rng.uniform(0.1, 0.35) * height
        cv2.rectangle(
            image, (int(x0), int(y0)), (int(x1), int(y1)), _colour(LABEL_PALETTE, rng), -1
        )
    for _ in range(10):
        centre = (int(rng.uniform(0, width)), int(rng.uniform(0, height)))
        radius = int(rng.uniform(20, 90))
        cv2.circle(
            image, centre, radius, _colour(LABEL_PALETTE, rng), int(rng.uniform(4, 16)), cv2.LINE_AA
        )
    for _ in range(60):  # text lines of several sizes
        org = (int(rng.uniform(-0.1, 0.9) * width), int(rng.uniform(0, 1) * height))
        scale = rng.uniform(0.35, 1.3)
        cv2.putText(
            image,
            _random_text(rng, int(rng.integers(4, 16))),
            org,
            cv2.FONT_HERSHEY_SIMPLEX,
            scale,
            _colour(LABEL_PALETTE, rng),
            max(1, int(2 * scale)),
            cv2.LINE_AA,
        )
    x, y = int(0.6 * width), int(0.75 * height)  # barcode
    for bar in rng.integers(1, 5, 40):
        cv2.rectangle(image, (x, y), (x + int(bar) - 1, y + 60), (0.05, 0.05, 0.05), -1)
        x += int(bar) + int(rng.integers(1, 4))
    return np.clip(image, 0, 1)


def photo(rng, width, height):
    """A photo-like, low-contrast texture: mossy gravel under soft light, gently blurred."""
    shape = (height, width)
    ground = fractal_noise(rng, shape, cells=(2, 4, 8, 16, 32, 64, 128), falloff=0.75)
    image = np.stack(
        [0.45 + 0.08 * ground, 0.43 + 0.07 * ground, 0.36 + 0.05 * ground], axis=-1
    ).astype(np.float32)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    for _ in range(260):  # pebbles: soft ellipses, lit from the top left, greyish
        cx, cy = rng.uniform(0, width), rng.uniform(0, height)
        rx, ry = rng.uniform(8, 34), rng.uniform(8, 34)
        dx, dy = (xs - cx) / rx, (ys - cy) / ry  # (H, W)
        inside = np.clip(4.0 * (1.0 - np.hypot(dx, dy)), 0, 1)
        shade = rng.normal(0, 0.05) - 0.05 * (dx + dy)  # brighter towards the top left
        image += (inside * 0.8 * shade)[..., None] + inside[..., None] * rng.normal(0, 0.012, 3)
    moss = np.clip(fractal_noise(rng, shape, cells=(4, 8, 16)) * 2 - 0.4, 0, 1)
    image = image * (1 - 0.4 * moss[..., None]) + 0.4 * moss[..., None] * np.array(
        (0.30, 0.40, 0.18), np.float32
    )
    image *= 1.0 + 0.05 * rng.standard_normal(shape).astype(np.float32)[..., None]
    return np.clip(cv2.GaussianBlur(image, (0, 0), 1.2), 0, 1)


BOLD_PALETTE = np.array(
    [
        (0.95, 0.85, 0.10),
        (0.85, 0.10, 0.10),
        (0.10, 0.25, 0.80),
        (0.05, 0.05, 0.05),
        (0.98, 0.98, 0.95),
        (0.10, 0.65, 0.25),
    ]
)


def bold(rng, width, height):
    """Big bold shapes that survive motion blur: blobs, thick strokes, dots, on white."""
    image = np.empty((height, width, 3), np.float32)
    image[:] = (0.93, 0.92, 0.88)
    shape = (height, width)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    warp = 25.0 * fractal_noise(rng, shape, cells=(3, 6))
    for _ in range(30):
        cx, cy = rng.uniform(0, width), rng.uniform(0, height)
        inside = np.hypot(xs - cx, ys - cy) + warp < rng.uniform(40, 120)
        image[inside] = _colour(BOLD_PALETTE, rng)
    for _ in range(14):
        _stroke(image, rng, _colour(BOLD_PALETTE, rng), rng.uniform(16, 30), 10, 25, 0.35)
    for _ in range(120):
        centre = (int(rng.uniform(0, width)), int(rng.uniform(0, height)))
        cv2.circle(
            image, centre, int(rng.integers(6, 18)), _colour(BOLD_PALETTE, rng), -1, cv2.LINE_AA
        )
    return image


PRINT_PALETTE = np.array(
    [
        (0.20, 0.25, 0.55),
        (0.80, 0.25, 0.30),
        (0.20, 0.55, 0.50),
        (0.10, 0.10, 0.12),
        (0.95, 0.60, 0.20),
    ]
)


def bag_print(rng, width, height):
    """A printed shopping bag: pastel ground, halftone dots, stripes, slogans and small print."""
    image = np.empty((height, width, 3), np.float32)
    image[:] = (0.93, 0.88, 0.80)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float32)
    tone = 0.5 + 0.5 * fractal_noise(rng, (height, width), cells=(2, 4))  # halftone density
    period = 9.0
    cell_x, cell_y = (xs % period) - period / 2, (ys % period) - period / 2
    dots = np.hypot(cell_x, cell_y) < 0.45 * period * tone
    image[dots] = (0.60, 0.75, 0.85)
    for _ in range(6):  # stripes
        y0 = int(rng.uniform(0, height))
        cv2.rectangle(
            image, (0, y0), (width, y0 + int(rng.uniform(6, 30))), _colour(PRINT_PALETTE, rng), -1
        )
    for _ in range(8):  # logo rings
        centre = (int(rng.uniform(0, width)), int(rng.uniform(0, height)))
        cv2.circle(
            image,
            centre,
            int(rng.uniform(25, 70)),
            _colour(PRINT_PALETTE, rng),
            int(rng.uniform(5, 14)),
            cv2.LINE_AA,
        )
    for _ in range(45):
        org = (int(rng.uniform(-0.1, 0.9) * width), int(rng.uniform(0, 1) * height))
        scale = rng.choice([0.4, 0.6, 1.0, 1.8])
        cv2.putText(
            image,
            _random_text(rng, int(rng.integers(3, 14))),
            org,
            cv2.FONT_HERSHEY_DUPLEX,
            scale,
            _colour(PRINT_PALETTE, rng),
            max(1, int(2 * scale)),
            cv2.LINE_AA,
        )
    return np.clip(image, 0, 1)
