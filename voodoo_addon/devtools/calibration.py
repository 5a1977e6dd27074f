"""Is the confidence calibrated? Confidence against true node error on the rendered clips.

For each rendered clip (ground truth from Blender: the hard, held-out and fold clips), the
tracker's own frames give the confidence of meshes that are (nearly) right; the same frames
with the tracked pose moved off by a known amount (a translation of 1-24 px in a random
direction, plus a turn) give the confidence of meshes that are wrong by that much. The table
of confidence per error bin is what the thresholds are chosen from: a frame is *lost* below
``TrackerOptions.lost_below``, and Blender marks stretches below ``ATTENTION_BELOW`` for an
animator to check.
"""

from __future__ import annotations

import numpy as np

from ..blob.build import build_blob
from ..media.images import to_float_rgb
from ..tracking import Tracker
from .clips import LatticeTruth, clip_suite, read_clip

#: Error bins of the table, pixels.
BINS = (0.0, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, np.inf)
#: Offsets tried around each sampled frame's pose, pixels.
OFFSETS = (1.0, 2.0, 4.0, 8.0, 16.0, 24.0)


def judge(tracker: Tracker, frame: np.ndarray, a: np.ndarray) -> float:
    """The confidence the tracker gives parameters ``a`` on ``frame`` (no fitting)."""
    fitter = tracker.fitter
    pyr = fitter.pyramid(frame, [a], False)
    if pyr is None:
        return 0.0
    images, origin = pyr
    step = fitter.levels[0]
    org, box = step.bind(images[step.index], origin)
    ev = step.evaluate(a, org, box)
    return 0.0 if ev is None else fitter.quality(ev, a, images.judged(step.index)).in_view


def samples(clip, every: int = 6, seed: int = 0):
    """(confidence, true error) pairs of one clip: tracked frames and moved-off poses."""
    frames, outline, _ = read_clip(clip)
    blob = build_blob(to_float_rgb(frames[0]), outline)
    truth = LatticeTruth(clip.truth)
    tracker = Tracker(blob)
    rng = np.random.default_rng(seed)
    out = []
    for i, frame in enumerate(frames):
        res = tracker.track(frame)
        if i % every or i >= len(truth):
            continue
        pos, seen = truth(i, blob.vertices)
        if seen.mean() < 0.5:
            continue

        def error(nodes, pos=pos, seen=seen):
            return float(np.linalg.norm(nodes - pos, axis=1)[seen].mean())

        out.append((res.confidence, error(res.nodes)))
        for d in OFFSETS:
            a = res.params.copy()
            angle = rng.uniform(0, 2 * np.pi)
            a[:2] += d * np.array([np.cos(angle), np.sin(angle)])
            a[2] += rng.normal(0, 0.02)
            out.append((judge(tracker, frame, a), error(tracker.nodes(a))))
    return out


def calibration_table(clips=None) -> list[dict]:
    """Confidence per true-error bin over the rendered clips."""
    pairs = []
    if clips is None:
        from .folds import fold_suite

        clips = clip_suite() + fold_suite()
    for clip in clips:
        if clip.truth is not None:
            pairs += samples(clip)
    conf, err = np.array(pairs).T
    rows = []
    for lo, hi in zip(BINS[:-1], BINS[1:], strict=True):
        sel = (err >= lo) & (err < hi)
        if not sel.any():
            continue
        c = conf[sel]
        rows.append(
            {
                "error_px": f"{lo:g}-{hi:g}" if np.isfinite(hi) else f">{lo:g}",
                "frames": int(sel.sum()),
                "confidence_p10": round(float(np.percentile(c, 10)), 3),
                "confidence_median": round(float(np.median(c)), 3),
                "confidence_p90": round(float(np.percentile(c, 90)), 3),
            }
        )
    return rows


def format_table(rows: list[dict]) -> str:
    lines = [
        "| true node error (px) | samples | confidence p10 | median | p90 |",
        "|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['error_px']} | {r['frames']} | {r['confidence_p10']:.2f} | "
            f"{r['confidence_median']:.2f} | {r['confidence_p90']:.2f} |"
        )
    return "\n".join(lines)


if __name__ == "__main__":
    print(format_table(calibration_table()))
