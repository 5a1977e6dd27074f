"""Tracking speed and accuracy on synthetic takes and the sample take (part of ``bench``).

Single-threaded (see :mod:`.report`). For each configuration a synthetic nonrigid take with
known motion is rendered first, then tracked; the time per frame excludes rendering and
decoding. The same frames are tracked by OpenCV's pyramidal Lucas-Kanade (KLT) on the mesh
nodes, the tool a user would reach for instead.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from ..blob.build import BlobOptions, build_blob
from ..tracking import Tracker
from .synthetic import Pose, foam_scene


@dataclass(frozen=True)
class Config:
    name: str
    size: tuple  # (width, height)
    modes: int
    pixels: int
    paper_fps: float | None
    target_fps: float


CONFIGS = (
    Config("paper-1: 256x256, 14 modes, 8.5k px", (256, 256), 14, 8500, 6.6, 500.0),
    Config("paper-2: 256x256, 20 modes, 17k px", (256, 256), 20, 17000, 3.3, 250.0),
    Config("large: 640x480, 30 modes, 50k px", (640, 480), 30, 50000, None, 100.0),
)


def motion(kind: str, frames: int, size) -> list[Pose]:
    """Nonrigid takes scaled to the frame: what a hand does with a foam doll."""
    w, h = size
    out = []
    for i in range(frames):
        s = 2 * np.pi * i / frames
        if kind == "squeeze":
            out.append(
                Pose(
                    tx=0.06 * w * np.sin(s),
                    ty=0.04 * h * np.sin(2 * s),
                    theta=0.5 * np.sin(s),
                    log_scale=0.12 * np.sin(s),
                    deform={
                        "bend-x": 0.12 * np.sin(2 * s),
                        "shear": 0.05 * np.sin(s),
                        "taper-x": 0.08 * np.sin(3 * s),
                    },
                )
            )
        elif kind == "bend":
            out.append(
                Pose(
                    tx=0.02 * w * np.sin(s),
                    deform={
                        "bend-x": 0.15 * np.sin(s),
                        "bend-y": 0.08 * np.sin(2 * s),
                        "stretch-x": 0.06 * np.sin(3 * s),
                    },
                )
            )
        else:
            raise ValueError(kind)
    return out


def _klt(frames, start_nodes):
    """Pyramidal Lucas-Kanade on the nodes, frame to frame; returns (nodes per frame, seconds)."""
    grays = [cv2.cvtColor((f * 255).astype(np.uint8), cv2.COLOR_RGB2GRAY) for f in frames]
    pts = start_nodes.astype(np.float32).reshape(-1, 1, 2)
    out = [start_nodes.copy()]
    t0 = time.perf_counter()
    for a, b in zip(grays[:-1], grays[1:], strict=True):
        pts, _, _ = cv2.calcOpticalFlowPyrLK(a, b, pts, None, winSize=(21, 21), maxLevel=3)
        out.append(pts.reshape(-1, 2).astype(np.float64))
    return out, time.perf_counter() - t0


#: The bundled sample take: rendered by Blender (scripts/make_sample.py), H.264-compressed, with
#: the true positions of a lattice of slab points in every frame.
SAMPLES = Path(__file__).resolve().parents[2] / "samples"


def lattice_truth(path):
    """Ground truth of the sample take: ``truth(i, points)`` maps frame-0 points to frame i.

    The truth file holds a lattice of slab points per frame (T, rows, cols, 2); on frame 0
    (the slab at rest) the lattice is an axis-aligned grid, so a point's bilinear weights
    there carry it to any frame.
    """
    lattice = np.load(path)["lattice"].astype(np.float64)
    xs, ys = lattice[0, 0, :, 0], lattice[0, :, 0, 1]

    def truth(i, points):
        u = np.interp(points[:, 0], xs, np.arange(len(xs)))
        v = np.interp(points[:, 1], ys, np.arange(len(ys)))
        c = np.clip(np.floor(u).astype(int), 0, len(xs) - 2)
        r = np.clip(np.floor(v).astype(int), 0, len(ys) - 2)
        fu, fv = (u - c)[:, None], (v - r)[:, None]
        g = lattice[i]
        return (
            (1 - fu) * (1 - fv) * g[r, c]
            + fu * (1 - fv) * g[r, c + 1]
            + (1 - fu) * fv * g[r + 1, c]
            + fu * fv * g[r + 1, c + 1]
        )

    return truth


def run_sample_take() -> dict | None:
    """Track the bundled sample take against its ground truth (None when it is absent)."""
    from ..blob.outline import load_contour_json
    from ..media.sources import open_source

    clip, outline, truth_file = (
        SAMPLES / "sample_take.mp4",
        SAMPLES / "sample_take.json",
        SAMPLES / "sample_truth.npz",
    )
    if not (clip.exists() and outline.exists() and truth_file.exists()):
        return None
    with open_source(clip) as src:
        images = [f.image for f in src]
    truth = lattice_truth(truth_file)
    return _track_and_compare(
        images,
        load_contour_json(outline),
        BlobOptions(),
        truth,
        name="sample take: 640x480 Blender render, H.264, 20 modes",
        kind="sample_take.mp4",
        target=100.0,
        paper=None,
    )


def run_config(cfg: Config, kind: str, frames: int) -> dict:
    """One synthetic configuration and sequence."""
    w, h = cfg.size
    scene, contour = foam_scene(w, h, cfg.pixels, seed=3)
    poses = motion(kind, frames, cfg.size)
    rng = np.random.default_rng(7)
    images = [scene.render(p, noise=0.01, rng=rng) for p in poses]
    return _track_and_compare(
        images,
        contour,
        BlobOptions(n_modes=cfg.modes),
        lambda i, pts: scene.forward(poses[i], pts),
        name=cfg.name,
        kind=kind,
        target=cfg.target_fps,
        paper=cfg.paper_fps,
    )


def _track_and_compare(images, contour, options, truth, name, kind, target, paper) -> dict:
    """Build, track every frame (timed), run KLT on the same frames, compare with the truth."""
    t0 = time.perf_counter()
    blob = build_blob(images[0], contour, options)
    t_build = time.perf_counter() - t0
    t0 = time.perf_counter()
    tracker = Tracker(blob)
    t_pre = time.perf_counter() - t0
    times, errs, its = [], [], []
    for i, img in enumerate(images):
        t0 = time.perf_counter()
        res = tracker.track(img)
        times.append(time.perf_counter() - t0)
        errs.append(float(np.linalg.norm(res.nodes - truth(i, blob.vertices), axis=1).mean()))
        its.append(res.iterations)
    klt_nodes, klt_time = _klt(images, blob.vertices)
    klt_err = [
        float(np.linalg.norm(n - truth(i, blob.vertices), axis=1).mean())
        for i, n in enumerate(klt_nodes)
    ]
    per_frame = float(np.mean(times[1:]))
    frames = len(images)
    return {
        "config": name,
        "sequence": kind,
        "frames": frames,
        "pixels": blob.n_pixels,
        "nodes": blob.n_nodes,
        "modes": blob.n_modes,
        "build_s": round(t_build, 4),
        "precompute_s": round(t_pre, 4),
        "ms_per_frame": round(1e3 * per_frame, 3),
        "fps": round(1.0 / per_frame, 1),
        "target_fps": target,
        "paper_fps": paper,
        "iterations": round(float(np.mean(its[1:])), 2),
        "error_px": round(float(np.mean(errs)), 4),
        "max_error_px": round(float(np.max(errs)), 4),
        "klt_fps": round((frames - 1) / klt_time, 1),
        "klt_error_px": round(float(np.mean(klt_err)), 4),
    }


def run_speed(quick: bool = False) -> list[dict]:
    """The speed configurations (and, unless quick, the sample take), single-threaded."""
    cv2.setNumThreads(1)
    frames = 24 if quick else 120
    rows = [run_config(cfg, kind, frames) for cfg in CONFIGS for kind in ("squeeze", "bend")]
    sample = None if quick else run_sample_take()
    if sample is not None:
        rows.append(sample)
    return rows


def _machine() -> str:
    import platform

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (
        f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numpy {np.__version__}, OpenCV {cv2.__version__}"
    )


def machine() -> str:
    """The machine a report was measured on, in one line."""
    return _machine()


def format_speed(rows: list[dict]) -> str:
    """The speed rows as a Markdown table (and the build times)."""
    lines = [
        "| configuration | sequence | px | nodes | fps (target) | iters/frame | error px "
        "| KLT fps | KLT error px |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        ok = "" if r["fps"] >= r["target_fps"] else " **missed**"
        lines.append(
            f"| {r['config']} | {r['sequence']} | {r['pixels']} | {r['nodes']} | "
            f"{r['fps']:.0f} ({r['target_fps']:.0f}){ok} | {r['iterations']:.2f} | "
            f"{r['error_px']:.3f} | {r['klt_fps']:.0f} | {r['klt_error_px']:.3f} |"
        )
    builds = {r["config"]: (r["build_s"], r["precompute_s"]) for r in rows}
    lines.append("")
    for name, (b, p) in builds.items():
        lines.append(
            f"- {name}: blob built in {b * 1e3:.0f} ms, tracker precompute {p * 1e3:.0f} ms"
        )
    return "\n".join(lines)
