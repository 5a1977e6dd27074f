"""How long re-mixing the modes of a long take costs in Blender: Apply again with other modes.

Run as ``.venv/bin/python scripts/bench_remix.py [--json] [--frames 1000]`` (headless,
Blender as a Python module). The blob is built on the sample take and 150 of its frames are
tracked; that take, repeated, becomes a take of at least ``--frames`` frames, applied once to a flat
grid of about 20,000 vertices with shape keys for every mode. Then each round picks other
modes and gains (and switches rotation on or off) and runs Apply, which rewrites the take's
action in place: the report gives the median and the slowest round, and the cost of a mode
toggle alone (curves are muted, nothing is rewritten).
"""

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp()

import bpy  # noqa: E402  (Blender first)
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from bench_live import grid_target  # noqa: E402
from blender_addon import enable_from_checkout, sample_blob_scene  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def long_take(storage, blob_mesh, name, frames):
    """Repeat the stored take ``name`` to at least ``frames`` frames; returns its length.

    The longer take replaces it, on consecutive scene frames.
    """
    stored = storage.stored_take(blob_mesh, name)
    take, scene_frames = stored.take, list(stored.frames)
    while len(take) < frames:
        take = take.extended(stored.take)
        scene_frames += [scene_frames[-1] + 1 + i for i in range(len(stored.take))]
    storage.store_take(blob_mesh, name, take, scene_frames, stored.rest_frame)
    return len(take)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--frames", type=int, default=1000)
    parser.add_argument("--vertices", type=int, default=20000)
    parser.add_argument("--rounds", type=int, default=10)
    args = parser.parse_args()
    module = enable_from_checkout()
    import importlib

    storage = importlib.import_module(f"{module}.operators.storage")
    sample_blob_scene()
    scene = bpy.context.scene
    s = scene.voodoo
    bpy.ops.voodoo.track_clip(max_frames=150)  # no target yet: the take is only stored
    frames = long_take(storage, s.blob, s.last_take, args.frames)
    scene.frame_end = frames + 1
    target = grid_target(args.vertices)
    s.target = target
    s.axes = "XY"
    t0 = time.perf_counter()
    bpy.ops.voodoo.apply_take()
    first = time.perf_counter() - t0
    rng = np.random.default_rng(0)
    rounds, toggles = [], []
    for i in range(args.rounds):
        t0 = time.perf_counter()
        for m in s.modes:
            m.enabled = bool(rng.uniform() < 0.6)
        toggles.append(time.perf_counter() - t0)
        for m in s.modes:
            m.gain = float(rng.choice([0.5, 1.0, 2.0]))
        s.apply_rotation = bool(i % 2)
        t0 = time.perf_counter()
        bpy.ops.voodoo.apply_take()
        rounds.append(time.perf_counter() - t0)
    report = {
        "frames": frames,  # whole repeats of the 150 tracked frames
        "modes": len(s.modes),
        "vertices": len(target.data.vertices),
        "first_apply_s": round(first, 3),
        "reapply_s_median": round(statistics.median(rounds), 3),
        "reapply_s_max": round(max(rounds), 3),
        "toggle_all_modes_ms_median": round(1e3 * statistics.median(toggles), 2),
        "actions": len(bpy.data.actions),
        "nla_tracks": len(target.animation_data.nla_tracks),
    }
    print(json.dumps(report) if args.json else json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
