"""The whole Active Voodoo Dolls job, headless, on the bundled sample take.

Run with the project's virtual environment (Blender as a Python module)::

    .venv/bin/python scripts/demo.py [--out out] [--frames N]

Everything goes through the add-on's public operators, loaded the way a user's extension is:
the sample clip becomes the scene's movie clip, frame 0 is captured, the bundled outline
becomes a Mask and then the blob's outline, the blob "Doll" is built, the clip is tracked onto
a flat cut-out bunny and the take applied to a 3D cracker box too. Writes into ``--out``:

``demo.blend``
    The scene: clip (path relative to the file), capture, outline, blob, take, both characters
    animated (shape keys + transform keys), a camera framing their whole motion, a light.
``preview.mp4``
    Per frame: the clip with the tracked mesh drawn on it, beside a Workbench render of the
    characters at that frame.
``modes.png``
    The keyed mode amplitudes (shape-key values) and the similarity (translation, rotation,
    scale) over the take.

``--frames N`` tracks and renders only the first N frames (quick runs); the default is the
whole clip. The steps are in ``demosteps/`` (doll, stage, preview, report).
"""

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

# Blender's user folders must point at a scratch folder before bpy is first imported, so the
# user's own settings and extensions are never touched.
SCRATCH = Path(tempfile.mkdtemp(prefix="voodoo-demo-"))
os.environ["BLENDER_USER_RESOURCES"] = str(SCRATCH / "user")

import bpy  # noqa: E402

# isort: split
from demosteps import ROOT, SAMPLE_CLIP  # noqa: E402  (scripts/ is on sys.path when this runs)
from demosteps.doll import DOLL_NAME, build_doll, load_clip, start_blender  # noqa: E402
from demosteps.preview import render_frames, write_preview  # noqa: E402
from demosteps.report import DemoError, Steps, file_size  # noqa: E402
from demosteps.stage import (  # noqa: E402
    add_camera_and_light,
    make_characters,
    motion_corners,
    save_blend,
    setup_render,
    track_and_apply,
)
from plot_take import plot_take  # noqa: E402

DEFAULT_OUT = ROOT / "out"
BLEND_NAME = "demo.blend"
PREVIEW_NAME = "preview.mp4"
MODES_NAME = "modes.png"


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="output folder")
    parser.add_argument(
        "--frames", type=int, default=None, help="track and render only the first N frames"
    )
    args = parser.parse_args(argv)
    if args.frames is not None and args.frames < 1:
        parser.error("--frames must be 1 or more")
    return args


def run(args: argparse.Namespace) -> None:
    """The demo's steps; raises DemoError when one fails."""
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    steps = Steps(total=7)
    with steps("Start Blender and enable the add-on"):
        addon, sub = start_blender(SCRATCH)
        scene = bpy.context.scene
        print(f"      {addon} (Blender {bpy.app.version_string})")
    with steps(f"Load {SAMPLE_CLIP.name}, capture frame 0, outline it, build the blob"):
        clip = load_clip(scene, SAMPLE_CLIP, args.frames)
        build_doll(sub, clip)
    with steps("Track the clip onto the bunny, apply the take to the cracker box"):
        bunny, box = make_characters(scene)
        take_name = track_and_apply(scene, bunny, box, args.frames)
    with steps("Frame the characters' motion, save demo.blend"):
        corners = motion_corners(scene, (bunny, box))
        add_camera_and_light(scene, corners)
        setup_render(scene)
        save_blend(out / BLEND_NAME, clip)

    store, apply = sub("operators.storage"), sub("operators.apply")
    blob = store.stored_blob(scene.voodoo.blob)
    take = store.stored_take(scene.voodoo.blob, take_name).take
    frames = store.stored_take(scene.voodoo.blob, take_name).frames
    with steps(f"Render {scene.frame_end - scene.frame_start + 1} frames with Workbench"):
        renders = render_frames(
            scene, SCRATCH / "frames", sub("voodoo_addon.takes.take").ProgressBar
        )
    with steps("Compose preview.mp4"):
        draw_mesh = sub("voodoo_addon.blob.preview").draw_mesh
        written = write_preview(out / PREVIEW_NAME, take, frames, renders, draw_mesh)
        print(f"      {written} frames")
    with steps("Plot the modes"):
        modes = apply.layout_for(blob, take).modes
        values = take.params[:, modes] / sub("voodoo_addon.takes.rig").unit(blob)
        names = [str(n) for n in take.param_names[modes]]
        title = f"{DOLL_NAME}: take '{take_name}' on {SAMPLE_CLIP.name}, {len(take)} frames"
        plot_take(out / MODES_NAME, take, frames, values, names, title)

    print(f"\nTracked {len(take)} frames, blob lost in {int(take.lost.sum())}. Run times:")
    print(steps.summary())
    print("\nWritten:")
    for name in (BLEND_NAME, PREVIEW_NAME, MODES_NAME):
        print(f"  {out / name}  ({file_size(out / name)})")


def main(argv=None) -> int:
    args = parse_args(argv)
    try:
        run(args)
    except (DemoError, OSError) as exc:
        print(f"demo: {exc}", file=sys.stderr)
        return 1
    finally:
        shutil.rmtree(SCRATCH, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
