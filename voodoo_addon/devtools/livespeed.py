"""Can the tracker keep up with a camera? Per-frame time on real footage and the hard clips.

Part ``live`` of the benchmark. For every clip of the suite (:func:`.clips.clip_suite`: the
real footage, the tuned renders and the held-out renders) the frames are decoded first and
the blob built on frame 0; then every later frame is given to ``Tracker.track`` and timed on
its own, with every robust stage on (proposals, local stage, occlusion, adaptation) as a
user gets it. OpenCV's pyramidal Lucas-Kanade on the mesh nodes is timed the same way on the
same frames in the same run, so that a slower or busier machine shows in both. The figures
a live input device needs are the median (the rate it sustains) and the 95th percentile (the
frames that make the stand-in stutter).
"""

from __future__ import annotations

import numpy as np

from ..blob.build import build_blob
from ..media.images import to_float_rgb
from .baselines import track_klt
from .clips import SAMPLES, clip_suite, read_clip, track_ours

#: What a live camera asks of one core: a 30 fps camera's frame time at the median, and the
#: 95th percentile within two of them.
MEDIAN_MS = 16.0
P95_MS = 33.0


def _stats(seconds: np.ndarray) -> tuple[float, float]:
    ms = 1000.0 * np.asarray(seconds, np.float64)
    return float(np.median(ms)), float(np.percentile(ms, 95))


def run_clip(clip) -> dict:
    """One clip's row: this tracker's and KLT's per-frame time, median and p95 (ms)."""
    frames, outline, _ = read_clip(clip)
    blob = build_blob(to_float_rgb(frames[0]), outline)
    _, lost, ours, _ = track_ours(frames, blob)
    _, _, klt = track_klt(frames, blob.vertices)
    med, p95 = _stats(ours)
    k_med, k_p95 = _stats(klt)
    h, w = frames[0].shape[:2]
    return {
        "clip": clip.name,
        "size": f"{w}x{h}",
        "frames": len(frames),
        "nodes": blob.n_nodes,
        "median_ms": round(med, 2),
        "p95_ms": round(p95, 2),
        "max_ms": round(1000.0 * float(np.max(ours)), 2),
        "klt_median_ms": round(k_med, 3),
        "klt_p95_ms": round(k_p95, 3),
        "lost_frames": int(np.count_nonzero(lost)),
        "times_ms": np.round(1000.0 * ours, 3).tolist(),
    }


def run_live(root=SAMPLES) -> list[dict]:
    """Every clip's row, then one row for all frames of all clips together."""
    rows = [run_clip(clip) for clip in clip_suite(root)]
    every = np.concatenate([r["times_ms"] for r in rows]) / 1000.0 if rows else np.zeros(1)
    med, p95 = _stats(every)
    rows.append({"clip": "all frames", "median_ms": round(med, 2), "p95_ms": round(p95, 2)})
    return rows


def meets(row: dict) -> bool:
    """Within :data:`MEDIAN_MS` and :data:`P95_MS`."""
    return row["median_ms"] <= MEDIAN_MS and row["p95_ms"] <= P95_MS


def format_live(rows: list[dict]) -> str:
    """The Markdown table of :func:`run_live`'s rows."""
    lines = [
        f"| clip | size | frames | median ms | p95 ms | max ms | fps (median) | KLT median ms "
        f"| KLT p95 ms | median / KLT | p95 / KLT | within {MEDIAN_MS:.0f} / {P95_MS:.0f} ms |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if "klt_median_ms" not in r:
            lines.append(
                f"| **{r['clip']}** | | | **{r['median_ms']:.1f}** | **{r['p95_ms']:.1f}** "
                f"| | | | | | | {'yes' if meets(r) else 'no'} |"
            )
            continue
        lines.append(
            f"| {r['clip']} | {r['size']} | {r['frames']} | {r['median_ms']:.1f} | "
            f"{r['p95_ms']:.1f} | {r['max_ms']:.0f} | {1000.0 / r['median_ms']:.0f} | "
            f"{r['klt_median_ms']:.2f} | {r['klt_p95_ms']:.2f} | "
            f"{r['median_ms'] / r['klt_median_ms']:.1f}x | {r['p95_ms'] / r['klt_p95_ms']:.1f}x | "
            f"{'yes' if meets(r) else 'no'} |"
        )
    return "\n".join(lines)
