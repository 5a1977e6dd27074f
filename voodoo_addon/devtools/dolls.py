"""Several dolls in one take: accuracy per doll, and what two dolls cost against one.

Part ``dolls`` of the benchmark. Every clip under ``samples/multi`` (``NAME.mp4``, an outline
``NAME.DOLL.json`` per doll, and for renders ``NAME_DOLL_truth.npz``, see
``samples/multi/README.md``) is decoded first and every doll's blob built on frame 0. Then:

- **together**: :class:`~voodoo_addon.tracking.troupe.Troupe` over all dolls, as ``track``
  runs it, timed per frame; each doll judged as the clips part judges a track (texture
  consistency, folded frames, node error where the renderer says the point is seen, lost
  frames while the doll is in view), beside KLT and DIS run on each doll's nodes;
- **alone**: each doll's own tracker over the same frames, timed per frame, to show what
  tracking them together costs over the sum of each alone.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..blob.build import build_blob
from ..blob.outline import load_contour_json
from ..media.images import to_float_rgb
from ..media.sources import open_source
from ..tracking.quality import score_track
from ..tracking.troupe import Troupe
from .baselines import track_dis, track_klt
from .clips import IN_VIEW, SAMPLES, LatticeTruth, track_ours, truth_errors

MULTI = SAMPLES / "multi"


@dataclass(frozen=True)
class MultiClip:
    """A clip of several dolls: its video, each doll's outline and (renders) truth."""

    name: str
    video: Path
    outlines: dict
    truths: dict


def multi_clips(root: Path = MULTI) -> list[MultiClip]:
    """The clips of several dolls under ``root``."""
    clips = []
    for video in sorted(root.glob("*.mp4")):
        stem = video.stem
        outlines = {p.name[len(stem) + 1 : -5]: p for p in sorted(root.glob(f"{stem}.*.json"))}
        truths = {n: root / f"{stem}_{n}_truth.npz" for n in outlines}
        truths = {n: p for n, p in truths.items() if p.exists()}
        if len(outlines) >= 2:
            clips.append(MultiClip(stem, video, outlines, truths))
    return clips


def _ms(seconds) -> tuple[float, float]:
    ms = 1000.0 * np.asarray(seconds, np.float64)
    return round(float(np.median(ms)), 2), round(float(np.percentile(ms, 95)), 2)


def track_together(frames, blobs: dict):
    """The troupe over the frames: per doll (vertices, lost), and the seconds per frame."""
    troupe = Troupe(blobs)
    verts = {n: [] for n in blobs}
    lost = {n: [] for n in blobs}
    secs = []
    for i, frame in enumerate(frames):
        t0 = time.perf_counter()
        got = troupe.track(frame)
        if i:
            secs.append(time.perf_counter() - t0)
        for n, r in got.items():
            verts[n].append(r.nodes)
            lost[n].append(r.lost)
    out = {n: (np.array(verts[n]), np.array(lost[n])) for n in blobs}
    return out, np.array(secs)


def run_multi(clip: MultiClip) -> dict:
    """One clip: a row per doll and tracker, and the speed together and alone."""
    with open_source(clip.video) as src:
        frames = [f.pixels for f in src]
    first = to_float_rgb(frames[0])
    blobs = {n: build_blob(first, load_contour_json(p)) for n, p in clip.outlines.items()}
    together, secs = track_together(frames, blobs)
    alone = {n: track_ours(frames, b)[2] for n, b in blobs.items()}
    rows = []
    for n, blob in blobs.items():
        runs = {"ours": together[n]}
        runs["klt"] = track_klt(frames, blob.vertices)[:2]
        runs["dis"] = track_dis(frames, blob.vertices)[:2]
        truth = LatticeTruth(clip.truths[n]) if n in clip.truths else None
        for tracker, (verts, lost) in runs.items():
            score = score_track(frames, verts, blob.triangles, lost)
            row = {"clip": clip.name, "doll": n, "tracker": tracker, **score.summary()}
            if truth is not None:
                err, seen = truth_errors(truth, blob.vertices, verts)
                row["error_px"] = round(float(np.nanmean(err)), 3)
                row["error_p90_px"] = round(float(np.nanpercentile(err, 90)), 3)
                in_view = seen >= IN_VIEW
                row["lost_in_view"] = int(np.count_nonzero(lost[: len(seen)] & in_view))
                row["least_seen"] = round(float(seen.min()), 2)
            rows.append(row)
    speed = {"frames": len(frames), "dolls": len(blobs), "together": _ms(secs)}
    speed["alone"] = {n: _ms(s) for n, s in alone.items()}
    speed["sum_alone_median"] = round(sum(v[0] for v in speed["alone"].values()), 2)
    return {"clip": clip.name, "rows": rows, "speed": speed}


def run_dolls(root: Path = MULTI) -> list[dict]:
    return [run_multi(c) for c in multi_clips(root)]


def format_dolls(results: list[dict]) -> str:
    """The Markdown tables: accuracy per doll and tracker, then speed."""
    lines = [
        "| clip | doll | tracker | consistency mean | p10 | folded frames | error px (p90) "
        "| lost in view | least seen |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for res in results:
        for r in res["rows"]:
            err = f"{r['error_px']:.2f} ({r['error_p90_px']:.2f})" if "error_px" in r else "—"
            lines.append(
                f"| {r['clip']} | {r['doll']} | {r['tracker']} | {r['consistency_mean']:.3f} | "
                f"{r['consistency_p10']:.3f} | {100 * r['folded_fraction']:.0f}% | {err} | "
                f"{r.get('lost_in_view', '—')} | {r.get('least_seen', '—')} |"
            )
    lines += [
        "",
        "| clip | frames | dolls | together: median ms | p95 ms | each alone: median ms (p95) "
        "| sum of the medians alone |",
        "|---|---|---|---|---|---|---|",
    ]
    for res in results:
        s = res["speed"]
        each = ", ".join(f"{n} {m:.1f} ({p:.1f})" for n, (m, p) in s["alone"].items())
        lines.append(
            f"| {res['clip']} | {s['frames']} | {s['dolls']} | {s['together'][0]:.1f} | "
            f"{s['together'][1]:.1f} | {each} | {s['sum_alone_median']:.1f} |"
        )
    return "\n".join(lines)
