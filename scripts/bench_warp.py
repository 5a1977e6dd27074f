"""GPU warp (Blender's gpu module) against the CPU warp: time per warp and per tracked frame.

Run as ``.venv/bin/python scripts/bench_warp.py [--json]`` (single-threaded, headless; on a
machine without a GPU the gpu module runs on Mesa's llvmpipe, a software rasteriser).
"""

import argparse
import json
import os
import sys
import tempfile
import time

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[var] = "1"
os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp()

import bpy  # noqa: E402, F401  (Blender first: it owns the GPU context)
import cv2  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from blender_addon import enable_from_checkout  # noqa: E402

FRAMES = 120
REPEAT = 50


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    cv2.setNumThreads(1)
    module = enable_from_checkout()
    import importlib

    engine = importlib.import_module(f"{module}.voodoo_addon")
    bench = importlib.import_module(f"{module}.voodoo_addon.devtools.bench")
    synthetic = importlib.import_module(f"{module}.voodoo_addon.devtools.synthetic")
    gpu_warp = importlib.import_module(f"{module}.operators.gpu_warp")
    if not gpu_warp.ensure_gpu():
        raise SystemExit("no GPU context")
    import gpu

    rows = []
    for cfg in bench.CONFIGS:
        scene, contour = synthetic.foam_scene(*cfg.size, cfg.pixels, seed=3)
        poses = bench.motion("squeeze", FRAMES, cfg.size)
        rng = np.random.default_rng(7)
        frames = [scene.render(p, noise=0.01, rng=rng) for p in poses]
        blob = engine.build_blob(frames[0], contour, engine.BlobOptions(n_modes=cfg.modes))
        row = {"config": cfg.name, "renderer": gpu.platform.renderer_get()}
        for name, backend in (("cpu", engine.CpuWarp()), ("gpu", gpu_warp.GpuWarp())):
            tracker = engine.Tracker(blob, backend=backend)
            level = tracker.levels[0]
            a = tracker.layout.identity()
            backend.bind(frames[1])
            pos, nodes = level.positions(a), level.nodes(a)
            backend.sample(level.geometry, nodes, pos)
            t0 = time.perf_counter()
            for _ in range(REPEAT):
                backend.sample(level.geometry, nodes, pos)
            row[f"{name}_warp_ms"] = round(1e3 * (time.perf_counter() - t0) / REPEAT, 3)
            times = []
            for f in frames:
                t0 = time.perf_counter()
                tracker.track(f)
                times.append(time.perf_counter() - t0)
            row[f"{name}_fps"] = round(1.0 / float(np.mean(times[1:])), 1)
            backend.close()
        rows.append(row)
        if not args.json:
            print(row, flush=True)
    if args.json:
        print(json.dumps(rows))


if __name__ == "__main__":
    main()
