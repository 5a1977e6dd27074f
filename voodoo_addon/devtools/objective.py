"""Which pose a fold render's picture favours, the true one or the tracked one.

The fits find the pose that explains the pixels best; on a furry doll turning under a lamp
that pose can lie pixels away from the truth (BENCHMARKS.md, *Where minky_tail_swing's
error comes from*). This tells a search that misses the optimum from an optimum that is
off. On each frame the picture, blurred as the template is, is sampled at the finest
level's pixels for two poses: the *modes at best* fit of the renderer's seen nodes
(:func:`.folds.nearest_modal_params`, the lighting the tracker's) and the tracker's own
modal pose on that frame (its result without the local stage's offsets). Each is compared
with frame 0 sampled at the capture pose, patch by patch (the tracker's lighting patches),
by the mean normalised correlation of the colours, and separately of the grey picture's
Sobel derivatives::

    python -m voodoo_addon.devtools.objective minky_tail_swing --first 10 --last 30
        --camera dim --seed 0

(one command line).
"""

from __future__ import annotations

import cv2
import numpy as np

from ..media.images import to_float_rgb
from ..tracking import kernels
from ..tracking.tracker import Tracker
from .camera import CameraFaults, add_camera_arguments, chosen_camera
from .folds import fold_suite, nearest_modal_params, open_fold_clip


def compare_poses(clip, first: int, last: int, camera: CameraFaults | None = None) -> list[dict]:
    """One row per frame ``first``..``last`` of ``clip`` (see the module's text).

    Keys: ``frame``, ``track_error_px`` (the tracker's modal pose on the renderer's seen
    nodes), ``colour_true``, ``colour_track``, ``gradient_true``, ``gradient_track``.
    """
    frames, blob, truth = open_fold_clip(clip, camera)
    tracker = Tracker(blob)
    layout = tracker.layout
    best = nearest_modal_params(blob, truth, layout)
    level = tracker.fitter.levels[0].level
    rest = np.zeros_like(blob.vertices)
    patch = level.patches.of_pixel if level.patches is not None else np.zeros(len(level), int)

    def picture(frame):
        image = to_float_rgb(frame)
        if level.scale != 1.0:
            size = level.scale
            image = cv2.resize(image, None, fx=size, fy=size, interpolation=cv2.INTER_AREA)
        image = cv2.GaussianBlur(image, (0, 0), blob.blur_sigma)
        grey = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY)
        gx = cv2.Sobel(grey, cv2.CV_32F, 1, 0, ksize=3)
        gy = cv2.Sobel(grey, cv2.CV_32F, 0, 1, ksize=3)
        return np.dstack([image, gx, gy]).astype(np.float32)

    def sample(image, a):
        nodes = tracker.fitter.nodes(a, rest) * level.scale
        pos = np.empty((2, len(level)), np.float32)
        kernels.positions(level.corners, level.weights, nodes, 0.0, 0.0, pos)
        out = cv2.remap(image, pos[0][None], pos[1][None], cv2.INTER_LINEAR)
        return out.reshape(len(level), -1)

    reference = sample(picture(frames[0]), layout.identity())
    rows = []
    for i, frame in enumerate(frames[: last + 1]):
        tracker.track(frame)
        if i < first:
            continue
        image = picture(frame)
        true_pose = best[i].copy()
        true_pose[layout.modes.stop :] = tracker.state[layout.modes.stop :]
        nodes, seen = truth(i, blob.vertices)
        tracked = tracker.fitter.nodes(tracker.state, rest)
        row = {
            "frame": i,
            "track_error_px": float(np.linalg.norm(nodes - tracked, axis=1)[seen].mean()),
        }
        for name, a in (("true", true_pose), ("track", tracker.state)):
            got = sample(image, a)
            row[f"colour_{name}"] = _patch_correlation(reference[:, :3], got[:, :3], patch)
            row[f"gradient_{name}"] = _patch_correlation(reference[:, 3:], got[:, 3:], patch)
        rows.append(row)
    return rows


def _patch_correlation(a: np.ndarray, b: np.ndarray, patch: np.ndarray) -> float:
    """The mean over patches of the normalised correlation of ``a`` and ``b`` (n, c)."""
    out = []
    for p in np.unique(patch):
        x = a[patch == p].ravel()
        y = b[patch == p].ravel()
        x = x - x.mean()
        y = y - y.mean()
        den = np.sqrt((x * x).sum() * (y * y).sum())
        if den > 1e-9:
            out.append(float((x * y).sum() / den))
    return float(np.mean(out)) if out else float("nan")


def main(argv=None) -> int:
    import argparse

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("clip", help="a fold render's name (tuned or held out)")
    p.add_argument("--first", type=int, default=0)
    p.add_argument("--last", type=int, default=30)
    add_camera_arguments(p)
    args = p.parse_args(argv)
    camera = chosen_camera(p, args)
    clips = [c for c in fold_suite() if c.name == args.clip]
    if not clips:
        p.error(f"no fold render named {args.clip!r}")
    print("| frame | track px | colours: true / track | gradients: true / track |")
    print("|---|---|---|---|")
    for r in compare_poses(clips[0], args.first, args.last, camera):
        print(
            f"| {r['frame']} | {r['track_error_px']:.2f} | {r['colour_true']:.4f} / "
            f"{r['colour_track']:.4f} | {r['gradient_true']:.3f} / {r['gradient_track']:.3f} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
