"""The take plot of the demo: mode amplitudes and the similarity over time, drawn with OpenCV.

``plot_take(path, take, frames, mode_values, mode_names, title)`` writes a PNG with four
stacked panels (shape-key values of the modes; translation; rotation; scale), each with a
legend; frames where the blob was lost are shaded.
"""

from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

PLOT_WIDTH = 1500
PLOT_LEFT = 90  # room for the y tick labels
PLOT_LEGEND = 300  # legend column on the right of each panel
PLOT_TOP = 70  # room for the figure title
PLOT_GAP = 75  # between panels: x tick labels and the next panel's title
PANEL_HEIGHTS = (460, 200, 170, 170)  # modes, translation, rotation, scale
BACKGROUND = (255, 255, 255)
INK = (40, 40, 40)
GRID = (228, 228, 228)
LOST_SHADE = (215, 215, 255)
FONT = cv2.FONT_HERSHEY_SIMPLEX
# Distinct line colours (BGR), Tableau-20 order: enough for 20 modes.
PALETTE = [
    (180, 119, 31),
    (14, 127, 255),
    (44, 160, 44),
    (40, 39, 214),
    (189, 103, 148),
    (75, 86, 140),
    (194, 119, 227),
    (127, 127, 127),
    (34, 189, 188),
    (207, 190, 23),
    (232, 199, 174),
    (120, 187, 255),
    (138, 223, 152),
    (150, 152, 255),
    (213, 176, 197),
    (148, 156, 196),
    (210, 182, 247),
    (199, 199, 199),
    (141, 219, 219),
    (229, 218, 158),
]


@dataclass
class Series:
    """One plotted line."""

    label: str
    values: np.ndarray
    colour: tuple[int, int, int]


def nice_ticks(lo: float, hi: float, count: int = 6) -> np.ndarray:
    """Round tick values (steps of 1, 2 or 5 times a power of ten) covering [lo, hi]."""
    raw = max(hi - lo, 1e-12) / count
    magnitude = 10.0 ** np.floor(np.log10(raw))
    step = magnitude * next(s for s in (1, 2, 5, 10) if s * magnitude >= raw)
    return np.arange(np.ceil(lo / step) * step, hi + 1e-9 * step, step)


def tick_text(value: float) -> str:
    """A tick label without trailing zeros."""
    return f"{value:.3g}" if abs(value) >= 1e-9 else "0"


def value_range(series: list[Series]) -> tuple[float, float]:
    """The plotted y range: all values with a little headroom, never empty."""
    values = np.concatenate([s.values for s in series])
    lo, hi = float(values.min()), float(values.max())
    pad = 0.06 * (hi - lo) if hi > lo else max(abs(hi), 1.0) * 0.1
    return lo - pad, hi + pad


def draw_panel(canvas, box, x, series: list[Series], title: str, lost: np.ndarray) -> None:
    """A line chart of ``series`` over ``x`` in ``box`` (x0, y0, x1, y1), legend on its right.

    Frames where the take lost the blob are shaded.
    """
    x0, y0, x1, y1 = box
    x_lo, x_hi = float(x[0]), float(max(x[-1], x[0] + 1))
    y_lo, y_hi = value_range(series)

    def to_px(xs, ys):
        px = x0 + (np.asarray(xs) - x_lo) / (x_hi - x_lo) * (x1 - x0)
        py = y1 - (np.asarray(ys) - y_lo) / (y_hi - y_lo) * (y1 - y0)
        return np.column_stack([px, py])

    for frame in x[lost]:
        (a, _), (b, _) = to_px([frame - 0.5, frame + 0.5], [0, 0])
        cv2.rectangle(canvas, (int(a), y0), (int(b), y1), LOST_SHADE, -1)
    for value in nice_ticks(y_lo, y_hi):
        py = int(round(to_px([x_lo], [value])[0, 1]))
        cv2.line(canvas, (x0, py), (x1, py), INK if value == 0 else GRID, 1)
        text = tick_text(value)
        (tw, th), _ = cv2.getTextSize(text, FONT, 0.45, 1)
        cv2.putText(canvas, text, (x0 - 8 - tw, py + th // 2), FONT, 0.45, INK, 1, cv2.LINE_AA)
    for value in nice_ticks(x_lo, x_hi, 10):
        px = int(round(to_px([value], [y_lo])[0, 0]))
        cv2.line(canvas, (px, y0), (px, y1), GRID, 1)
        text = tick_text(value)
        (tw, th), _ = cv2.getTextSize(text, FONT, 0.45, 1)
        cv2.putText(canvas, text, (px - tw // 2, y1 + th + 8), FONT, 0.45, INK, 1, cv2.LINE_AA)
    for s in series:
        points = np.round(to_px(x, s.values) * 16).astype(np.int32).reshape(-1, 1, 2)
        cv2.polylines(canvas, [points], False, s.colour, 2, cv2.LINE_AA, 4)
    cv2.rectangle(canvas, (x0, y0), (x1, y1), INK, 1)
    cv2.putText(canvas, title, (x0, y0 - 12), FONT, 0.6, INK, 1, cv2.LINE_AA)
    for i, s in enumerate(series):
        ly = y0 + 14 + 22 * i
        cv2.line(canvas, (x1 + 20, ly), (x1 + 50, ly), s.colour, 3, cv2.LINE_AA)
        cv2.putText(canvas, s.label, (x1 + 58, ly + 5), FONT, 0.5, INK, 1, cv2.LINE_AA)


def plot_take(path: Path, take, frames: np.ndarray, mode_values, mode_names, title) -> None:
    """Write the mode amplitudes and the similarity over the take as a PNG chart.

    Parameters
    ----------
    mode_values : (T, k) float
        Shape-key values of the k modes per take row.
    mode_names : list of str
    """
    params = take.params
    panels = [
        (
            "Mode amplitudes (shape-key values)",
            [
                Series(name, mode_values[:, j], PALETTE[j % len(PALETTE)])
                for j, name in enumerate(mode_names)
            ],
        ),
        (
            "Translation (pixels, image y down)",
            [
                Series("translate x", params[:, 0], PALETTE[0]),
                Series("translate y", params[:, 1], PALETTE[3]),
            ],
        ),
        ("Rotation (degrees)", [Series("rotate", np.degrees(params[:, 2]), PALETTE[2])]),
        ("Scale (factor)", [Series("scale", np.exp(params[:, 3]), PALETTE[4])]),
    ]
    height = PLOT_TOP + sum(PANEL_HEIGHTS) + PLOT_GAP * len(PANEL_HEIGHTS)
    canvas = np.full((height, PLOT_WIDTH, 3), BACKGROUND, dtype=np.uint8)
    cv2.putText(canvas, title, (PLOT_LEFT, 36), FONT, 0.75, INK, 2, cv2.LINE_AA)
    y0 = PLOT_TOP + 20
    for (panel_title, series), panel_height in zip(panels, PANEL_HEIGHTS, strict=True):
        box = (PLOT_LEFT, y0, PLOT_WIDTH - PLOT_LEGEND, y0 + panel_height)
        draw_panel(canvas, box, frames, series, panel_title, take.lost)
        y0 += panel_height + PLOT_GAP
    note = "x: scene frame" + ("   shaded: blob lost" if take.lost.any() else "")
    cv2.putText(canvas, note, (PLOT_LEFT, height - 18), FONT, 0.5, INK, 1, cv2.LINE_AA)
    if not cv2.imwrite(str(path), canvas):
        raise OSError(f"OpenCV could not write {path}.")


# ---------------------------------------------------------------------------------- main
