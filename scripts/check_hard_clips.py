"""Check the hard test clips against their ground truth and draw a contact sheet for each.

Run with the project's virtual environment (no Blender needed)::

    .venv/bin/python scripts/check_hard_clips.py [--dir samples/hard] [--out /tmp/hard_check]
        [NAME ...]

For every clip it reads ``NAME.mp4`` with OpenCV and checks that frame count, size and fps match
``NAME_truth.npz``, that frame 0's lattice is an axis-aligned grid and that the outline in
``NAME.json`` is a valid polygon inside the sheet. It prints

* ``motion``: the largest inter-frame displacement of a lattice point visible in both frames (px),
* ``visible``: the smallest fraction of lattice points visible in a frame,
* ``area``: the smallest ratio of a lattice cell's image area to its frame-0 area, over cells
  whose four corners are visible (and, as ``area_all``, over all cells: negative means the cell
  is seen flipped, i.e. from behind or folded over),
* ``ncc``: how well each frame, pulled back to frame 0 through the truth, matches frame 0
  (normalised cross-correlation of the high-passed texture over the visible part of the outlined
  region; the lowest frame),
* for the frames drawn, the shift of the truth that would match frame 0 best (about 0 when the
  truth follows the texture; ``check_truth_dots.py`` checks the absolute position),

and writes ``OUT/NAME.png``: frames 0, T/3, 2T/3 and T-1, the most foreshortened frame and the
frame with the lowest ``ncc``, each with the lattice (visible points green, hidden red) and the
outline carried by the truth drawn on it, and below each the same frame pulled back to frame 0
by the truth (it should look like frame 0 wherever the sheet is visible; the rest is darkened).
"""

import argparse
import json
import sys
from pathlib import Path

import cv2
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from voodoo_addon.blob.outline import validate_contour  # noqa: E402
from voodoo_addon.devtools.bench import lattice_truth  # noqa: E402

WIDTH, HEIGHT = 640, 360


def read_video(path):
    """All frames (BGR uint8) and the fps the container declares."""
    capture = cv2.VideoCapture(str(path))
    fps = capture.get(cv2.CAP_PROP_FPS)
    frames = []
    while True:
        ok, frame = capture.read()
        if not ok:
            break
        frames.append(frame)
    capture.release()
    return frames, fps


def cell_areas(lattice):
    """Signed image area of every lattice cell: (T, R - 1, C - 1)."""
    tl, tr = lattice[:, :-1, :-1], lattice[:, :-1, 1:]
    br, bl = lattice[:, 1:, 1:], lattice[:, 1:, :-1]
    quad = np.stack([tl, tr, br, bl], axis=-2)  # (T, R-1, C-1, 4, 2)
    x, y = quad[..., 0], quad[..., 1]
    return 0.5 * (x * np.roll(y, -1, axis=-1) - np.roll(x, -1, axis=-1) * y).sum(axis=-1)


def pull_back(frame, truth, i, points):
    """Sample ``frame`` (frame i) at where the truth carries each frame-0 pixel ``points``."""
    where = truth(i, points).astype(np.float32)
    map_x = where[:, 0].reshape(HEIGHT, WIDTH)
    map_y = where[:, 1].reshape(HEIGHT, WIDTH)
    return cv2.remap(frame, map_x, map_y, cv2.INTER_LINEAR, borderValue=(0, 0, 0))


def visible_weight(visible, lattice0, points):
    """Bilinear weight of the visible lattice points around each frame-0 pixel, in [0, 1].

    The same bilinear scheme as the truth's: 1 only where all four surrounding points are seen.
    """
    xs, ys = lattice0[0, :, 0], lattice0[:, 0, 1]
    u = np.interp(points[:, 0], xs, np.arange(len(xs)))
    v = np.interp(points[:, 1], ys, np.arange(len(ys)))
    c = np.clip(np.floor(u).astype(int), 0, len(xs) - 2)
    r = np.clip(np.floor(v).astype(int), 0, len(ys) - 2)
    fu, fv = u - c, v - r
    g = visible.astype(np.float64)
    return (
        (1 - fu) * (1 - fv) * g[r, c]
        + fu * (1 - fv) * g[r, c + 1]
        + (1 - fu) * fv * g[r + 1, c]
        + fu * fv * g[r + 1, c + 1]
    )


def high_pass(grey):
    grey = grey.astype(np.float32)
    return grey - cv2.GaussianBlur(grey, (0, 0), 4.0)


def ncc(a, b, mask):
    """Normalised cross-correlation of the texture (shading and lighting drift filtered out)."""
    a, b = high_pass(a)[mask].astype(np.float64), high_pass(b)[mask].astype(np.float64)
    a, b = a - a.mean(), b - b.mean()
    return float((a * b).sum() / np.sqrt((a * a).sum() * (b * b).sum() + 1e-12))


def best_shift(frame, frame0, truth, i, pixels, mask):
    """The shift (dx, dy) of the truth in frame i that best matches frame 0 (px), to 0.05 px."""
    grey0 = cv2.cvtColor(frame0, cv2.COLOR_BGR2GRAY)
    grey = cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY)
    where = truth(i, pixels).astype(np.float32)

    def score(dx, dy):
        back = cv2.remap(
            grey,
            (where[:, 0] + dx).reshape(HEIGHT, WIDTH),
            (where[:, 1] + dy).reshape(HEIGHT, WIDTH),
            cv2.INTER_CUBIC,
        )
        return ncc(back, grey0, mask)

    best = (0.0, 0.0)
    for step in (0.25, 0.05):
        grid = [
            (best[0] + step * a, best[1] + step * b) for a in range(-4, 5) for b in range(-4, 5)
        ]
        best = max(grid, key=lambda d: score(*d))
    return best


def check(name, folder, out):
    frames, fps = read_video(folder / f"{name}.mp4")
    data = np.load(folder / f"{name}_truth.npz")
    lattice, visible, truth_fps = data["lattice"], data["visible"], float(data["fps"])
    outline = np.array(json.loads((folder / f"{name}.json").read_text())["points"])
    n = len(lattice)
    problems = []
    if len(frames) != n:
        problems.append(f"{len(frames)} video frames, {n} truth frames")
    if frames and frames[0].shape[:2] != (HEIGHT, WIDTH):
        problems.append(f"frame size {frames[0].shape[1]}x{frames[0].shape[0]}")
    if abs(fps - truth_fps) > 1e-3:
        problems.append(f"video fps {fps}, truth fps {truth_fps}")
    if lattice.dtype != np.float32 or visible.shape != lattice.shape[:3]:
        problems.append("truth arrays have the wrong type or shape")
    rest = lattice[0].astype(np.float64)
    skew = max(
        np.abs(rest[..., 0] - rest[..., 0].mean(axis=0)).max(),
        np.abs(rest[..., 1] - rest[..., 1].mean(axis=1, keepdims=True)).max(),
    )
    if skew > 0.01:
        problems.append(f"frame-0 lattice is not axis-aligned ({skew:.3f} px)")
    if not (visible[:3].all() and np.allclose(lattice[:3], lattice[0], atol=1e-3)):
        problems.append("the sheet is not at rest and fully visible on frames 0-2")
    validate_contour(outline, (WIDTH, HEIGHT))  # raises on a bad polygon
    low, high = rest.reshape(-1, 2).min(axis=0), rest.reshape(-1, 2).max(axis=0)
    margin = min((outline - low).min(), (high - outline).min())
    if not 30 <= len(outline) <= 80 or margin < 7.5:
        problems.append(f"outline: {len(outline)} points, {margin:.1f} px inside the sheet")

    both = visible[1:] & visible[:-1]
    steps = np.linalg.norm(lattice[1:] - lattice[:-1], axis=-1)  # (T-1, R, C)
    motion = steps[both].max() if both.any() else 0.0
    areas = cell_areas(lattice.astype(np.float64))
    ratio = areas / areas[0]
    corners = visible[:, :-1, :-1] & visible[:, :-1, 1:] & visible[:, 1:, 1:] & visible[:, 1:, :-1]
    area_visible = ratio[corners].min()
    coverage = visible.mean(axis=(1, 2))

    truth = lattice_truth(folder / f"{name}_truth.npz")
    ys, xs = np.mgrid[0:HEIGHT, 0:WIDTH]
    pixels = np.column_stack([xs.ravel(), ys.ravel()]).astype(np.float64)
    region = np.zeros((HEIGHT, WIDTH), np.uint8)
    cv2.fillPoly(region, [np.round(outline * 16).astype(np.int32)], 1, cv2.LINE_8, shift=4)
    inside = (
        (pixels[:, 0] >= low[0])
        & (pixels[:, 0] <= high[0])
        & (pixels[:, 1] >= low[1])
        & (pixels[:, 1] <= high[1])
    ).reshape(HEIGHT, WIDTH) & (region > 0)
    grey0 = cv2.cvtColor(frames[0], cv2.COLOR_BGR2GRAY)

    def pulled_and_mask(i):
        back = pull_back(frames[i], truth, i, pixels)
        weight = visible_weight(visible[i], rest, pixels).reshape(HEIGHT, WIDTH)
        return back, inside & (weight > 0.999)

    scores = []
    for i in range(min(n, len(frames))):
        back, mask = pulled_and_mask(i)
        if mask.sum() > 500:
            scores.append((ncc(cv2.cvtColor(back, cv2.COLOR_BGR2GRAY), grey0, mask), i))
    # The four frames asked for, the most foreshortened one and the one matching worst.
    squeezed = int(np.argmin(np.where(corners, ratio, np.inf).min(axis=(1, 2))))
    shown = [0, n // 3, 2 * n // 3, n - 1, squeezed, min(scores)[1] if scores else 0]
    tiles, pulled = [], []
    shifts = []
    for i in shown[: len(frames)]:
        back, mask = pulled_and_mask(i)
        if i > 0 and mask.sum() > 500:
            shifts.append(best_shift(frames[i], frames[0], truth, i, pixels, mask))
        tiles.append(draw(frames[i], lattice[i], visible[i], truth(i, outline), i))
        back[~mask] //= 3
        pulled.append(label(back, f"frame {i} pulled back to frame 0"))
    rows = [np.hstack(group[k : k + 3]) for k in (0, 3) for group in (tiles, pulled)]
    sheet = np.vstack(rows)
    out.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(str(out / f"{name}.png"), sheet)
    worst = min(scores) if scores else (float("nan"), -1)
    print(
        f"{name:15s} {n:4d} frames {truth_fps:4.0f} fps  lattice {lattice.shape[1]}x"
        f"{lattice.shape[2]}  motion {motion:5.1f} px  visible {coverage.min():.2f}  "
        f"area {area_visible:.2f} (all {ratio.min():+.2f})  ncc {worst[0]:.3f} "
        f"(frame {worst[1]})\n    best truth shift on the frames drawn (px): "
        + " ".join(f"({dx:+.2f},{dy:+.2f})" for dx, dy in shifts)
        + ("".join(f"\n    PROBLEM: {p}" for p in problems))
    )
    return not problems


def label(image, text):
    cv2.putText(image, text, (8, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.55, (0, 0, 0), 3, cv2.LINE_AA)
    cv2.putText(
        image, text, (8, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.55, (255, 255, 255), 1, cv2.LINE_AA
    )
    return image


def draw(frame, lattice, visible, outline, i):
    image = frame.copy()
    cv2.polylines(
        image,
        [np.round(outline * 16).astype(np.int32)],
        True,
        (0, 255, 255),
        1,
        cv2.LINE_AA,
        shift=4,
    )
    for (x, y), seen in zip(lattice.reshape(-1, 2), visible.ravel(), strict=True):
        colour = (0, 255, 0) if seen else (0, 0, 255)
        cv2.circle(
            image,
            (int(round(x * 16)), int(round(y * 16))),
            2 * 16,
            colour,
            -1,
            cv2.LINE_AA,
            shift=4,
        )
    return label(image, f"frame {i}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("names", nargs="*", help="clips to check (default: all)")
    parser.add_argument("--dir", type=Path, default=ROOT / "samples" / "hard")
    parser.add_argument("--out", type=Path, default=Path("/tmp/hard_check"))
    args = parser.parse_args(argv)
    names = args.names or sorted(p.name[: -len("_truth.npz")] for p in args.dir.glob("*_truth.npz"))
    ok = all([check(name, args.dir, args.out) for name in names])
    sizes = sum(p.stat().st_size for p in args.dir.iterdir() if p.is_file())
    print(f"{len(names)} clips, {sizes} bytes in {args.dir}")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
