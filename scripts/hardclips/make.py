"""One hard clip's files (truth, outline, video) and the clip folder's README.

A clip of several dolls (``multi``) writes an outline and a truth file per doll.
"""

import json
import tempfile
import time
from pathlib import Path
from typing import NamedTuple

import bpy

# isort: split
import numpy as np

from hardclips.folds import FOLDS, README_FOLDS, visibility_rows
from hardclips.heldout import HELDOUT
from hardclips.heldout_folds import HELDOUT_FOLDS, README_HELDOUT_FOLDS
from hardclips.heldout_folds2 import HELDOUT_FOLDS2, README_HELDOUT_FOLDS2
from hardclips.heldout_folds3 import HELDOUT_FOLDS3, README_HELDOUT_FOLDS3
from hardclips.heldout_folds4 import HELDOUT_FOLDS4, README_HELDOUT_FOLDS4
from hardclips.heldout_folds5 import HELDOUT_FOLDS5, README_HELDOUT_FOLDS5
from hardclips.heldout_folds6 import HELDOUT_FOLDS6, README_HELDOUT_FOLDS6
from hardclips.heldout_folds7 import HELDOUT_FOLDS7, README_HELDOUT_FOLDS7
from hardclips.heldout_folds8 import HELDOUT_FOLDS8, README_HELDOUT_FOLDS8
from hardclips.multi import MULTI
from hardclips.scenarios import CLIPS
from hardclips.scene import HEIGHT, SEED, WIDTH, new_scene
from hardclips.truth import lattice_truth, region_outline
from hardclips.video import NOISE_SIGMA, develop, encode, render_frames


class Group(NamedTuple):
    """The clips made apart from the tuned ones, into a folder of their own."""

    clips: list
    #: The number the first clip's scene is seeded with (the next clip's is one more).
    first: int
    #: What they are called, in the message when they are asked for with other clips.
    name: str
    #: Their folder's README, with a table of how much of each sheet is visible (None: the
    #: README of the hard clips, or of several dolls).
    readme: str | None = None


#: Every group but the tuned clips (``CLIPS``, numbered from 0), in the order they were made.
GROUPS = (
    Group(HELDOUT, 100, "the held-out clips"),
    Group(MULTI, 200, "the clips of several dolls"),
    Group(FOLDS, 300, "the clips of folds", README_FOLDS),
    Group(HELDOUT_FOLDS, 400, "the held-out clips of folds", README_HELDOUT_FOLDS),
    Group(HELDOUT_FOLDS2, 500, "the second held-out fold clips", README_HELDOUT_FOLDS2),
    Group(HELDOUT_FOLDS3, 600, "the third held-out fold clips", README_HELDOUT_FOLDS3),
    Group(HELDOUT_FOLDS4, 700, "the fourth held-out fold clips", README_HELDOUT_FOLDS4),
    Group(HELDOUT_FOLDS5, 800, "the fifth held-out fold clips", README_HELDOUT_FOLDS5),
    Group(HELDOUT_FOLDS6, 900, "the sixth held-out fold clips", README_HELDOUT_FOLDS6),
    Group(HELDOUT_FOLDS7, 1000, "the seventh held-out fold clips", README_HELDOUT_FOLDS7),
    Group(HELDOUT_FOLDS8, 1100, "the eighth held-out fold clips", README_HELDOUT_FOLDS8),
)


def clip_number(clip):
    """The clip's number, which seeds its scene.

    Its place in ``CLIPS``, or in its group counted from the group's ``first`` (see
    :data:`GROUPS`).
    """
    for group in GROUPS:
        if clip in group.clips:
            return group.first + group.clips.index(clip)
    return CLIPS.index(clip)


def doll_files(clip, doll):
    """The outline's and the truth's file names of ``clip``'s ``doll`` (None: its only sheet)."""
    if doll is None:
        return f"{clip.name}.json", f"{clip.name}_truth.npz"
    return f"{clip.name}.{doll}.json", f"{clip.name}_{doll}_truth.npz"


def make_clip(clip, out, draft, truth_only=False):
    """Write ``clip``'s truth and outline into ``out``, then (unless ``truth_only``) its video.

    ``draft`` renders with Workbench. Returns the seconds spent rendering.
    """
    rng = np.random.default_rng([SEED, 2, clip_number(clip)])
    scene = new_scene(clip, draft)
    built = clip.build(rng, clip)  # a Sheet, or {doll name: Sheet} for several dolls
    sheets = built if isinstance(built, dict) else {None: built}
    started = time.perf_counter()
    least = []  # each doll's least visible fraction in a frame
    for doll, sheet in sheets.items():
        lattice, visible = lattice_truth(scene, sheet)  # the other dolls occlude it too
        outline_file, truth_file = doll_files(clip, doll)
        np.savez_compressed(out / truth_file, lattice=lattice, visible=visible, fps=float(clip.fps))
        outline = region_outline(lattice[0])
        (out / outline_file).write_text(
            json.dumps({"points": np.round(outline, 2).tolist()}) + "\n"
        )
        fraction = visible.mean(axis=(1, 2)).min()
        least.append(f"{fraction:.2f}" if doll is None else f"{doll} {fraction:.2f}")
    truth_s = time.perf_counter() - started
    least = ", ".join(least)
    if truth_only:
        print(f"{clip.name}: truth in {truth_s:.0f} s, min visible {least}")
        return 0.0
    with tempfile.TemporaryDirectory(prefix=f"hard_{clip.name}_") as tmp:
        tmp = Path(tmp)
        started = time.perf_counter()
        paths = render_frames(scene, tmp)
        render_s = time.perf_counter() - started
        video = out.resolve() / f"{clip.name}.mp4"
        crf = encode(develop(clip, clip_number(clip), paths, tmp), clip.fps, video)
    print(
        f"{clip.name}: {clip.frames} frames at {clip.fps} fps, lattice {lattice.shape[1:3]}, "
        f"truth {truth_s:.0f} s, render {render_s:.0f} s ({render_s / clip.frames:.2f} s/frame),"
        f" video {video.stat().st_size} bytes (CRF {crf}), min visible {least}",
        flush=True,
    )
    return render_s


MAKING = """# Hard test clips

Rendered with Blender {blender} (the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py): every scene, texture,
motion and the camera post-processing is generated by the script from a fixed seed, so the same
command makes the same scenes, truth and outlines (about 50 minutes on one CPU core):

    .venv/bin/python scripts/render_hard_clips.py --out samples/hard

(`--only NAME ...` remakes some clips only)."""

MAKING_HELDOUT = """# Held-out hard clips

Clips for checking that the tracker generalises: never tune it on these. They were rendered
after the tracker's last change (2026-11-23) and its first run on them is what BENCHMARKS.md
shows; `python -m voodoo_addon bench --only clips` and the slow clip test in
`tests/engine/test_robustness.py` run them with the other clips. Rendered with Blender
{blender} (the `bpy` module, headless) by `scripts/render_hard_clips.py` (scenes in
`scripts/hardclips/heldout.py`, paint in `scripts/heldout_textures.py`) from a fixed seed, so
the same command makes the same scenes, truth and outlines; it makes them only when named:

    .venv/bin/python scripts/render_hard_clips.py --out samples/heldout --only {names}

Keep them out of `samples/hard`."""

README = """{making} Check them with
`.venv/bin/python scripts/check_hard_clips.py{check_dir}` (statistics, and contact sheets in
`/tmp/hard_check/`); `.venv/bin/python scripts/check_truth_dots.py` re-renders a few frames
with dots painted on the lattice points and measures them against the truth.

Each clip NAME has `NAME.mp4` (H.264, {width}x{height}, mild gaussian sensor noise of
{noise:.1f} % added before encoding), `NAME.json` (the region outline on frame 0, OpenCV pixel
coordinates) and `NAME_truth.npz` (`lattice` (T, R, C, 2) float32: pixel positions of a grid of
surface points in every frame, projected from the renderer's deformed mesh; `visible` (T, R, C):
inside the image, painted side towards the camera and not hidden, by ray casts; `fps`). Frame 0
shows the sheet flat, square to the perspective camera and at rest for three frames, so the
frame-0 lattice is an axis-aligned grid.

| clip | frames | fps | what happens | renderer |
| --- | ---: | ---: | --- | --- |
{rows}
"""


README_MULTI = """# Clips of several dolls

Test clips for tracking several dolls (painted sheets) in one take, which pass in front of each
other. Rendered with Blender {blender} (the `bpy` module, headless) by
[`scripts/render_hard_clips.py`](../../scripts/render_hard_clips.py) (scenes in
`scripts/hardclips/multi.py`, paint from `scripts/hard_textures.py`) from a fixed seed, so the
same command makes the same scenes, truth and outlines; it makes them only when named:

    .venv/bin/python scripts/render_hard_clips.py --out samples/multi --only {names}

Each clip NAME has `NAME.mp4` (H.264, {width}x{height}, gaussian sensor noise of {noise:.1f} %
added before encoding) and, for each doll DOLL (`left`, `right`), `NAME.DOLL.json` (the region
outline of that doll on frame 0) and `NAME_DOLL_truth.npz` (its lattice, `visible` and `fps`).
These are the formats of the single-doll clips (see [`../hard/README.md`](../hard/README.md)):
OpenCV pixel coordinates, `lattice` (T, R, C, 2) float32, `visible` (T, R, C) bool. A doll's
`visible` is false where the other doll hides it (the ray casts see every doll), where it turns
its back to the camera or where it leaves the image. On frame 0 every doll lies flat, square to
the perspective camera, apart from the others and at rest for three frames.

| clip | frames | fps | what happens | renderer |
| --- | ---: | ---: | --- | --- |
{rows}
"""


def write_readme(out, clips=CLIPS):
    """``out``/README.md: how the clips were made, what they hold, one row per clip.

    ``clips`` is ``CLIPS`` or the clips of one of :data:`GROUPS`.
    """
    making = MAKING if clips is CLIPS else MAKING_HELDOUT
    rows = []
    for clip in clips:
        renderer = f"Cycles (CPU), {clip.samples} spp + OIDN denoiser"
        if clip.motion_blur:
            renderer += ", motion blur (shutter 0.5 frame, centred)"
        if clip.post is not None:
            renderer += f"; {clip.post_note} in post"
        rows.append(f"| `{clip.name}` | {clip.frames} | {clip.fps} | {clip.what} | {renderer} |")
    shared = {
        "blender": bpy.app.version_string,
        "names": " ".join(c.name for c in clips),
        "width": WIDTH,
        "height": HEIGHT,
        "noise": 100 * NOISE_SIGMA,
        "rows": "\n".join(rows),
    }
    folds = next((g.readme for g in GROUPS if g.clips is clips and g.readme), None)
    if folds is not None:
        text = folds.format(**shared, visibility=visibility_rows(out, clips))
    elif clips is MULTI:
        text = README_MULTI.format(**shared)
    else:
        check_dir = "" if clips is CLIPS else " --dir samples/heldout"
        text = README.format(**shared, making=making.format(**shared), check_dir=check_dir)
    (out / "README.md").write_text(text)
