"""Procedural paint of the sample take, numpy only: the painted-foam pattern and the backdrop.

``make_sample.py`` paints its slab and backdrop with these; ``render_hard_clips.py`` reuses them
(the ``bend_out`` sheet and every clip's backdrop) and ``hard_textures.py`` builds its styles on
``smooth_noise``. Every function takes a seeded ``numpy.random.Generator`` and returns an sRGB
image, (height, width, 3) float32 in [0, 1] with rows top-down (what
``blender_scene.packed_image`` takes).
"""

import numpy as np
from scipy.ndimage import zoom

GRID_CELLS = (7, 5)
LINE_WIDTH = 7.0  # texels
WOBBLE = 5.0  # texels: hand-painted lines are not straight
N_BLOBS = 14
N_DOTS = 60
PAINT_COLOURS = np.array(
    [
        (0.86, 0.20, 0.16),  # red
        (0.95, 0.55, 0.12),  # orange
        (0.96, 0.84, 0.25),  # yellow
        (0.35, 0.70, 0.28),  # green
        (0.16, 0.62, 0.66),  # teal
        (0.22, 0.38, 0.80),  # blue
        (0.56, 0.32, 0.70),  # purple
        (0.93, 0.56, 0.68),  # pink
        (0.93, 0.89, 0.78),  # cream
    ]
)
LINE_COLOUR = (0.07, 0.06, 0.08)

# The backdrop: darker than the paint, faintly mottled.
BACKDROP_COLOUR = (0.17, 0.17, 0.19)
BACKDROP_MOTTLE = 0.04
BACKDROP_GRAIN = 0.012


def smooth_noise(rng, shape, cells):
    """Smooth random field in [-1, 1]: a coarse random grid, bicubically upsampled.

    Returns
    -------
    (shape[0], shape[1]) float64
    """
    coarse = rng.uniform(-1.0, 1.0, size=(cells + 3, cells + 3))
    fine = zoom(coarse, (shape[0] / cells, shape[1] / cells), order=3)
    return np.clip(fine[: shape[0], : shape[1]], -1.0, 1.0)


def painted_foam_texture(rng, width, height):
    """A painted-foam pattern: wobbly dark grid lines over coloured cells, blobs and dots.

    Returns
    -------
    (height, width, 3) float32 sRGB in [0, 1], rows top-down.
    """
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float64)
    u = xs + WOBBLE * smooth_noise(rng, (height, width), 6)  # (H, W) wobbled coordinates
    v = ys + WOBBLE * smooth_noise(rng, (height, width), 6)
    cell_w, cell_h = width / GRID_CELLS[0], height / GRID_CELLS[1]
    col = np.clip((u // cell_w).astype(int), 0, GRID_CELLS[0] - 1)
    row = np.clip((v // cell_h).astype(int), 0, GRID_CELLS[1] - 1)
    cell_colour = rng.integers(len(PAINT_COLOURS), size=(GRID_CELLS[1], GRID_CELLS[0]))
    image = PAINT_COLOURS[cell_colour[row, col]]  # (H, W, 3)

    for _ in range(N_BLOBS):
        cx, cy = rng.uniform(0, width), rng.uniform(0, height)
        radius = rng.uniform(0.25, 0.45) * min(cell_w, cell_h)
        inside = np.hypot(u - cx, (v - cy) * rng.uniform(0.7, 1.4)) < radius
        image[inside] = PAINT_COLOURS[rng.integers(len(PAINT_COLOURS))]
    for _ in range(N_DOTS):
        cx, cy = rng.uniform(0, width), rng.uniform(0, height)
        inside = np.hypot(xs - cx, ys - cy) < rng.uniform(2.5, 5.0)
        image[inside] = LINE_COLOUR if rng.random() < 0.6 else PAINT_COLOURS[-1]

    dist_x = np.abs((u + cell_w / 2) % cell_w - cell_w / 2)  # distance to the nearest line
    dist_y = np.abs((v + cell_h / 2) % cell_h - cell_h / 2)
    on_line = np.minimum(dist_x, dist_y) < LINE_WIDTH / 2
    image[on_line] = LINE_COLOUR
    paint = 1.0 + 0.05 * smooth_noise(rng, (height, width), 24)  # uneven paint and foam pores
    return np.clip(image * paint[..., None], 0.0, 1.0).astype(np.float32)


def backdrop_texture(rng, width, height):
    """A dark, faintly mottled backdrop. Returns (height, width, 3) float32, rows top-down."""
    mottle = BACKDROP_MOTTLE * smooth_noise(rng, (height, width), 5)
    grain = BACKDROP_GRAIN * rng.standard_normal((height, width))
    image = np.asarray(BACKDROP_COLOUR) + (mottle + grain)[..., None]
    return np.clip(image, 0.0, 1.0).astype(np.float32)
