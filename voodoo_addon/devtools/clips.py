"""The hard clips: real footage and Blender renders, tracked side by side with KLT and DIS.

Every clip is a video, an outline on its first frame, and -- for renders -- the true
position of a lattice of surface points in every frame (with their visibility). Each tracker
(ours, OpenCV's pyramidal Lucas-Kanade on the mesh nodes, DIS optical flow sampled at the
nodes) runs on the same decoded frames and is judged the same way: texture consistency
(:mod:`voodoo_addon.tracking.quality`), folded frames, lost frames, and, where the renderer
gave it, the node error against the truth.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..blob.build import build_blob
from ..blob.outline import load_contour_json
from ..media.images import to_float_rgb
from ..media.sources import ArraySource, open_source
from ..takes.both_ways import merge, track_backward
from ..takes.take import Take
from ..tracking import Tracker
from ..tracking.quality import score_track
from ..tracking.troupe import Troupe
from .baselines import track_dis, track_klt

SAMPLES = Path(__file__).resolve().parents[2] / "samples"
#: A true node counts as seen when its bilinear visibility is at least this.
VISIBLE = 0.5
#: A frame shows the object when at least this fraction of the true nodes is seen.
IN_VIEW = 0.2


@dataclass(frozen=True)
class Clip:
    """One test clip.

    Attributes
    ----------
    name : str
    video : Path
    outline : Path
        ``{"points": [[x, y], ...]}`` on frame 0.
    truth : Path or None
        ``lattice`` (T, R, C, 2) and ``visible`` (T, R, C) of a surface grid, axis-aligned
        on frame 0.
    """

    name: str
    video: Path
    outline: Path
    truth: Path | None = None


def clip_suite(root: Path = SAMPLES) -> list[Clip]:
    """The clips under ``root`` with their outlines.

    ``real/*.mp4``, ``hard/*.mp4`` and ``heldout/*.mp4`` (rendered after the tracker was
    tuned, to check that it generalises).
    """
    clips = []
    for sub in ("real", "hard", "heldout"):
        for video in sorted((root / sub).glob("*.mp4")):
            stem = video.with_suffix("")
            outline = next(
                (p for p in (Path(f"{stem}.contour.json"), Path(f"{stem}.json")) if p.exists()),
                None,
            )
            if outline is None:
                continue
            truth = Path(f"{stem}_truth.npz")
            clips.append(Clip(video.stem, video, outline, truth if truth.exists() else None))
    return clips


class LatticeTruth:
    """True positions and visibility of frame-0 points, from a rendered lattice.

    On frame 0 the lattice is an axis-aligned grid, so a point's bilinear weights there carry
    it to any frame.
    """

    def __init__(self, path: Path):
        with np.load(path) as npz:
            self.lattice = npz["lattice"].astype(np.float64)  # (T, R, C, 2)
            vis = npz["visible"] if "visible" in npz.files else None
        if vis is None:
            vis = np.ones(self.lattice.shape[:3], bool)
        self.visible = vis.astype(np.float64)
        self.xs = self.lattice[0, 0, :, 0]
        self.ys = self.lattice[0, :, 0, 1]

    def __len__(self) -> int:
        return len(self.lattice)

    def _weights(self, points):
        u = np.interp(points[:, 0], self.xs, np.arange(len(self.xs)))
        v = np.interp(points[:, 1], self.ys, np.arange(len(self.ys)))
        c = np.clip(np.floor(u).astype(int), 0, len(self.xs) - 2)
        r = np.clip(np.floor(v).astype(int), 0, len(self.ys) - 2)
        return r, c, (u - c)[:, None], (v - r)[:, None]

    def _bilinear(self, grid, r, c, fu, fv):
        return (
            (1 - fu) * (1 - fv) * grid[r, c]
            + fu * (1 - fv) * grid[r, c + 1]
            + (1 - fu) * fv * grid[r + 1, c]
            + fu * fv * grid[r + 1, c + 1]
        )

    def __call__(self, i: int, points: np.ndarray):
        """(positions (n, 2), seen (n,) bool) of frame-0 ``points`` in frame ``i``."""
        r, c, fu, fv = self._weights(points)
        pos = self._bilinear(self.lattice[i], r, c, fu, fv)
        vis = self._bilinear(self.visible[i][:, :, None], r, c, fu, fv)[:, 0]
        return pos, vis >= VISIBLE


def truth_errors(truth: LatticeTruth, rest: np.ndarray, vertices: np.ndarray):
    """Mean error of the seen nodes per frame (NaN when none is seen) and the seen fraction."""
    errs, seen = [], []
    for i in range(min(len(truth), len(vertices))):
        pos, vis = truth(i, rest)
        seen.append(vis.mean())
        d = np.linalg.norm(vertices[i] - pos, axis=1)
        errs.append(float(d[vis].mean()) if vis.any() else np.nan)
    return np.array(errs), np.array(seen)


def read_clip(clip: Clip):
    """Decoded frames (8-bit RGB, as the tracker gets them from a video) and the outline."""
    with open_source(clip.video) as src:
        frames = [f.pixels for f in src]
        fps = src.fps
    return frames, load_contour_json(clip.outline), fps


def track_ours(frames, blob, options=None, params=False, visible=False):
    """Our tracker over the frames.

    Returns vertices (T, m, 2), lost (T,), the seconds of each frame after the first
    (T - 1,) and the confidence (T,); with ``params``, also the parameters (T, P); with
    ``visible``, last, the triangles reported in view (T, t).
    """
    tracker = Tracker(blob, options=options)
    verts, lost, conf, times, rows, seen = [], [], [], [], [], []
    for i, frame in enumerate(frames):
        t0 = time.perf_counter()
        res = tracker.track(frame)
        if i:
            times.append(time.perf_counter() - t0)
        verts.append(res.nodes)
        lost.append(res.lost)
        conf.append(res.confidence)
        rows.append(res.params)
        seen.append(res.visible)
    out = np.array(verts), np.array(lost), np.array(times), np.array(conf)
    out += (np.array(rows),) if params else ()
    return (*out, np.array(seen)) if visible else out


def track_ours_both_ways(frames, blob, forward, options=None, passes: dict | None = None):
    """Ours tracked back from the end of a forward track and merged with it.

    ``forward``: what ``track_ours(frames, blob, options, params=True, visible=True)`` gave
    on the same frames (see :mod:`voodoo_addon.takes.both_ways`). Returns the same six
    arrays for the merged take; its seconds are each frame's two passes together (the
    frames but the first and the last, which each pass starts on). ``passes``, when given,
    gets the backward pass's take as ``"backward"``.
    """
    verts, lost, secs, conf, params, visible = forward
    n = len(frames)
    troupe = Troupe({"doll": blob}, options=options)
    take = Take(
        vertices=verts,
        triangles=blob.triangles,
        params=params,
        confidence=conf,
        lost=lost,
        param_names=np.array(troupe.trackers["doll"].parameter_names, dtype=str),
        frame_indices=np.arange(n),
        times=np.arange(n) / 30.0,
        fps=30.0,
        iterations=np.zeros(n, np.int64),
        visible=visible,
    )
    stamps = [time.perf_counter()]
    backward = track_backward(
        troupe, ArraySource(frames), {"doll": take}, lambda _: stamps.append(time.perf_counter())
    )["doll"]
    merged = merge(take, backward)
    if passes is not None:
        passes["backward"] = backward
    back = np.zeros(n)  # frame i's backward pass at [i] (none after the frame it starts on)
    done = np.diff(stamps)[::-1]
    back[: len(done)] = done
    both = np.asarray(secs)[:-1] + back[1:-1] if n > 2 else np.zeros(0)
    return merged.vertices, merged.lost, both, merged.confidence, merged.params, merged.visible


def run_clip(clip: Clip, trackers=("ours", "klt", "dis"), options=None) -> list[dict]:
    """Every tracker on one clip; one row per tracker."""
    frames, outline, fps = read_clip(clip)
    blob = build_blob(to_float_rgb(frames[0]), outline)
    truth = LatticeTruth(clip.truth) if clip.truth else None
    rows = []
    for name in trackers:
        conf = None
        if name == "ours":
            verts, lost, secs, conf = track_ours(frames, blob, options)
        elif name == "klt":
            verts, lost, secs = track_klt(frames, blob.vertices)
        else:
            verts, lost, secs = track_dis(frames, blob.vertices)
        score = score_track(frames, verts, blob.triangles, lost)
        row = {
            "clip": clip.name,
            "tracker": name,
            "frames": len(frames),
            "fps_clip": round(float(fps), 2),
            "nodes": blob.n_nodes,
            "pixels": blob.n_pixels,
            **score.summary(),
            "track_fps": round(len(secs) / max(float(secs.sum()), 1e-9), 1),
        }
        if truth is not None:
            err, seen = truth_errors(truth, blob.vertices, verts)
            in_view = seen >= IN_VIEW
            row["error_px"] = round(float(np.nanmean(err)), 3)
            row["error_p90_px"] = round(float(np.nanpercentile(err, 90)), 3)
            row["lost_in_view"] = int(np.count_nonzero(lost[: len(seen)] & in_view))
        if conf is not None:
            row["confidence"] = conf.round(3).tolist()
            row["per_frame"] = np.round(score.per_frame, 3).tolist()
            if truth is not None:
                row["frame_error"] = np.round(err, 3).tolist()
        rows.append(row)
    if truth is not None:
        # The renderer's own mesh, judged the same way: what a perfect track would score.
        verts = np.array([truth(i, blob.vertices)[0] for i in range(min(len(truth), len(frames)))])
        score = score_track(frames, verts, blob.triangles)
        rows.append(
            {
                "clip": clip.name,
                "tracker": "truth",
                "frames": len(verts),
                **score.summary(),
                "track_fps": None,
            }
        )
    return rows


def ratios(rows: list[dict]) -> list[dict]:
    """Ours against the better of KLT and DIS on each clip (consistency mean and p10)."""
    out = []
    for clip in dict.fromkeys(r["clip"] for r in rows):
        by = {r["tracker"]: r for r in rows if r["clip"] == clip}
        if not {"ours", "klt", "dis"} <= by.keys():
            continue
        ours = by["ours"]
        best_mean = max(by["klt"]["consistency_mean"], by["dis"]["consistency_mean"])
        best_p10 = max(by["klt"]["consistency_p10"], by["dis"]["consistency_p10"])
        out.append(
            {
                "clip": clip,
                "mean_ratio": round(ours["consistency_mean"] / best_mean, 3),
                "p10_ratio": round(ours["consistency_p10"] / best_p10, 3)
                if best_p10 > 0
                else float("inf"),
                "folded": ours["folded_fraction"],
                "lost": ours["lost_fraction"],
            }
        )
    return out


def format_rows(rows: list[dict]) -> str:
    """A Markdown table of the per-tracker rows and the ratios."""
    lines = [
        "| clip | tracker | consistency mean | p10 | folded frames | lost frames | "
        "error px (p90) | lost in view | fps |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        err = f"{r['error_px']:.2f} ({r['error_p90_px']:.2f})" if "error_px" in r else "—"
        liv = str(r["lost_in_view"]) if "lost_in_view" in r else "—"
        fps = "—" if r["track_fps"] is None else f"{r['track_fps']:.0f}"
        name = "*true mesh*" if r["tracker"] == "truth" else r["tracker"]
        lines.append(
            f"| {r['clip']} | {name} | {r['consistency_mean']:.3f} | "
            f"{r['consistency_p10']:.3f} | {100 * r['folded_fraction']:.0f}% | "
            f"{100 * r['lost_fraction']:.0f}% | {err} | {liv} | {fps} |"
        )
    lines += [
        "",
        "| clip | ours / best of KLT, DIS: mean | p10 | ours folded | ours lost |",
        "|---|---|---|---|---|",
    ]
    for q in ratios(rows):
        lines.append(
            f"| {q['clip']} | {q['mean_ratio']:.2f} | {q['p10_ratio']:.2f} | "
            f"{100 * q['folded']:.0f}% | {100 * q['lost']:.0f}% |"
        )
    return "\n".join(lines)


def main(argv=None) -> int:
    import argparse

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--only", nargs="*", help="clip names")
    p.add_argument("--trackers", nargs="*", default=["ours", "klt", "dis"])
    p.add_argument("--json", help="write all rows (with per-frame series) here")
    p.add_argument(
        "--root",
        type=Path,
        default=SAMPLES,
        help="folder holding real/ and hard/ (default: the repository's samples)",
    )
    args = p.parse_args(argv)
    rows = []
    for clip in clip_suite(args.root):
        if args.only and clip.name not in args.only:
            continue
        t0 = time.perf_counter()
        got = run_clip(clip, args.trackers)
        rows += got
        brief = {
            r["tracker"]: (r["consistency_mean"], r["consistency_p10"], r["folded_fraction"])
            for r in got
        }
        print(f"{clip.name}: {brief} ({time.perf_counter() - t0:.0f} s)", flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(rows))
    print(format_rows([{k: v for k, v in r.items()} for r in rows]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
