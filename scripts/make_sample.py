"""Render the sample take: a painted foam slab moved, turned, bent and squeezed before a camera.

Run headless with the project's virtual environment (Blender as a Python module)::

    .venv/bin/python scripts/make_sample.py [--out samples] [--frames 150]

Writes into ``--out``:

``sample_take.mp4``
    640x480, 30 fps, H.264, rendered with Workbench. Frame 0 of the video (scene frame 1) shows
    the slab at rest and unbent.
``sample_take.json``
    ``{"points": [[x, y], ...]}``: a closed rounded-rectangle outline of a region of the slab on
    frame 0, in OpenCV pixel coordinates (origin at the centre of the top-left pixel, y down),
    computed by projecting the slab through the camera.

The motion schedule is written in seconds, so speeds do not depend on ``--frames``: a shorter
clip shows the start of the schedule, a longer one holds the last pose. Everything is seeded;
the same command makes the same clip. ``--truth-only`` writes the outline and the ground truth
(``sample_truth.npz``, see ``sampletake/truth.py``) and renders nothing.

The scene is built by ``sampletake/scene.py``, the truth and outline by ``sampletake/truth.py``
(from the helpers in ``blender_scene.py`` and ``foam_paint.py``, shared with
``render_hard_clips.py``).
"""

import argparse
import json
import time
from pathlib import Path

import bpy  # first: importing bpy makes bmesh and bpy_extras importable

# isort: split
import numpy as np
from sampletake.scene import SEED, build_scene, configure_render  # scripts/ is on sys.path
from sampletake.truth import lattice_truth, max_speed, region_outline

DEFAULT_FRAMES = 150
VIDEO_NAME = "sample_take.mp4"
CONTOUR_NAME = "sample_take.json"
TRUTH_NAME = "sample_truth.npz"


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("samples"), help="output folder")
    parser.add_argument("--frames", type=int, default=DEFAULT_FRAMES, help="clip length")
    parser.add_argument(
        "--truth-only", action="store_true", help="write the ground truth, render nothing"
    )
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    started = time.perf_counter()
    args.out.mkdir(parents=True, exist_ok=True)
    video_path = args.out.resolve() / VIDEO_NAME
    slab = build_scene(np.random.default_rng(SEED))
    scene = bpy.context.scene
    configure_render(scene, args.frames, video_path)

    points = region_outline(scene, slab)
    contour_path = args.out / CONTOUR_NAME
    contour_path.write_text(json.dumps({"points": np.round(points, 2).tolist()}) + "\n")
    print(f"max slab speed {max_speed(scene, slab):.1f} px/frame")
    truth_path = args.out / TRUTH_NAME
    np.savez_compressed(truth_path, lattice=lattice_truth(scene, slab))
    print(f"wrote {truth_path} ({truth_path.stat().st_size / 1e6:.2f} MB)")
    if args.truth_only:
        return

    bpy.ops.render.render(animation=True)
    print(
        f"wrote {video_path} ({video_path.stat().st_size / 1e6:.2f} MB, {args.frames} frames)"
        f" and {contour_path} ({len(points)} points) in {time.perf_counter() - started:.1f} s"
    )


if __name__ == "__main__":
    main()
