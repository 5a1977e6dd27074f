"""The per-frame cost of recording live in Blender: read a frame, track it, pose the stand-in.

Run as ``.venv/bin/python scripts/bench_live.py [--json] [--vertices N]`` (headless, Blender
as a Python module). The sample take (640x480) is the footage; the target is a flat grid of
about 20,000 vertices (``--vertices``). Each step is :meth:`Recorder.step` as the modal
operator calls it on a timer tick: decode the next frame, track it, move the scene to the
frame and pose the stand-in (its shape-key values and its transform). The report gives the
median and 90th percentile of the whole step and the median of its parts ("the rest" is the
step minus the timed parts: moving the scene to the frame, and the overlay's state).
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
from blender_addon import enable_from_checkout, sample_blob_scene  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def grid_target(n_vertices: int):
    """A flat grid of about ``n_vertices`` vertices in the XZ plane."""
    side = max(2, int(round(np.sqrt(n_vertices))) - 1)
    bpy.ops.mesh.primitive_grid_add(
        x_subdivisions=side, y_subdivisions=side, size=2.0, rotation=(1.5708, 0, 0)
    )
    return bpy.context.active_object


def parts(rec, timings):
    """Wrap the recorder's parts so each one's time is recorded per step."""

    def timed(name, fn):
        def run(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                timings.setdefault(name, []).append(time.perf_counter() - t0)

        return run

    rec.source.read = timed("read frame", rec.source.read)
    rec.tracker.track = timed("track", rec.tracker.track)
    rec._pose = timed("pose stand-in", rec._pose)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--vertices", type=int, default=20000)
    parser.add_argument("--frames", type=int, default=120)
    args = parser.parse_args()
    module = enable_from_checkout()
    import importlib

    recorder = importlib.import_module(f"{module}.operators.recorder")
    sample_blob_scene()
    scene = bpy.context.scene
    target = grid_target(args.vertices)
    scene.voodoo.target = target
    scene.voodoo.axes = "XY"
    rec = recorder.Recorder(bpy.context, max_frames=args.frames, live=True)
    timings: dict = {}
    parts(rec, timings)
    steps = []
    try:
        while True:
            t0 = time.perf_counter()
            more = rec.step()
            steps.append(time.perf_counter() - t0)
            if not more:
                break
    finally:
        rec.close()
    steps = steps[1:]  # the first frame builds caches
    rest = [s - sum(v[i + 1] for v in timings.values()) for i, s in enumerate(steps)]
    timings["the rest (frame_set, overlay)"] = [0.0] + rest
    report = {
        "vertices": len(target.data.vertices),
        "frames": len(steps),
        "step_ms_median": round(1e3 * statistics.median(steps), 2),
        "step_ms_p90": round(1e3 * float(np.percentile(steps, 90)), 2),
        "parts_ms_median": {
            k: round(1e3 * statistics.median(v[1:]), 2) for k, v in timings.items()
        },
    }
    if args.json:
        print(json.dumps(report))
    else:
        print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
