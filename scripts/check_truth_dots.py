"""Check the hard clips' ground truth against Blender's own render, pixel for pixel.

Builds each clip's scene as ``render_hard_clips.py`` does, but paints the sheet black with a
white dot centred on every lattice point's texture coordinate, renders a few frames with the
clip's renderer settings (Cycles, motion blur included) and compares the dots' centroids in the
image with the lattice positions in the truth (visible points off the sheet's edge only)::

    .venv/bin/python scripts/check_truth_dots.py [--only NAME ...]

(the held-out clips of ``hardclips/heldout.py`` only when named with ``--only``).

Prints, per clip and frame, the mean offset (centroid minus truth), the median and 90th
percentile distance in pixels, and how many dots show where the truth says a point is hidden
(should be none): about 0.1 px where the sheet is flat and well lit; dots that are
strongly foreshortened, shaded unevenly or smeared by motion blur give less exact centroids.
Writes nothing but temporary renders. Takes a few seconds per frame (one core).
"""

import argparse
import tempfile
from pathlib import Path

import cv2
import numpy as np
from hardclips import heldout, scenarios  # first: hardclips pins one core before bpy starts
from hardclips.scene import new_scene
from hardclips.truth import lattice_truth

# isort: split
import bpy

DOT_RADIUS = 6  # texels
FRAMES = {  # frames to render per clip: at rest and deformed
    "bend_out": (0, 45),
    "tilt_twist": (20, 55, 100),
    "curl_away": (36,),
    "glossy": (25, 60),
    "lighting_drift": (110,),
    "fast_8fps": (20, 30),
    "crumple": (45,),
}
HELDOUT_FRAMES = {
    "handheld_zoom": (31, 50, 67),  # scale 1.4x, rolled, 0.7x
    "occluded_exit": (40, 80),  # a third out of the frame; the hand over it
    "glossy_fast_twist": (20, 33),  # motion blur, before and after the exposure step
}


def dotted_sheet(add_sheet):
    """``add_sheet`` with the paint replaced by dots on the lattice points."""

    def add(texture, size, segments, stride, **kw):
        def dots(rng, width, height):
            image = np.zeros((height, width, 3), np.float32)
            for row in range(0, segments[1] + 1, stride):
                for col in range(0, segments[0] + 1, stride):
                    # Texture coordinate (u, v) = (col / cols, 1 - row / rows); rows top-down.
                    x = col / segments[0] * width - 0.5
                    y = row / segments[1] * height - 0.5
                    centre = (int(round(x * 16)), int(round(y * 16)))
                    cv2.circle(image, centre, DOT_RADIUS * 16, (1, 1, 1), -1, cv2.LINE_AA, 4)
            return image

        return add_sheet(dots, size, segments, stride, **kw)

    return add


def dot_centroids(image, threshold=0.3):
    """Intensity-weighted centroids of the small bright blobs: (n, 2) pixel coordinates."""
    grey = image.mean(axis=2)
    count, labels = cv2.connectedComponents((grey > threshold).astype(np.uint8))
    weight = np.clip(grey - threshold, 0, None)
    ys, xs = np.mgrid[0 : grey.shape[0], 0 : grey.shape[1]]
    found = []
    for k in range(1, count):
        blob = labels == k
        if 3 <= blob.sum() <= 400:
            w = weight[blob]
            found.append(((w * xs[blob]).sum() / w.sum(), (w * ys[blob]).sum() / w.sum()))
    return np.array(found).reshape(-1, 2)


def check(clip, folder):
    scene = new_scene(clip, draft=False)
    sheet = clip.build(np.random.default_rng(0), clip)
    frames = {**FRAMES, **HELDOUT_FRAMES}[clip.name]
    scene.frame_end = max(frames) + 1
    lattice, visible = lattice_truth(scene, sheet)
    settings = scene.render.image_settings
    settings.media_type, settings.file_format = "IMAGE", "PNG"
    settings.color_mode, settings.color_depth = "RGB", "16"
    for frame in frames:
        scene.frame_set(frame + 1)
        scene.render.filepath = str(folder / f"{clip.name}_{frame}.png")
        bpy.ops.render.render(write_still=True)
        image = cv2.imread(scene.render.filepath, cv2.IMREAD_UNCHANGED)[..., ::-1] / 65535.0
        found = dot_centroids(image)
        interior = visible[frame].copy()
        interior[[0, -1], :] = interior[:, [0, -1]] = False  # edge dots are cut in half
        truth = lattice[frame][interior]
        distance = np.linalg.norm(found[:, None] - truth[None], axis=-1)  # (dots, points)
        matched = distance.min(axis=1) < 2.0
        error = found[matched] - truth[distance.argmin(axis=1)[matched]]
        size = np.linalg.norm(error, axis=1)
        # Dots where the truth says a point is hidden (behind something, or turned away).
        hidden = lattice[frame][~visible[frame]]
        near = np.linalg.norm(found[~matched, None] - hidden[None], axis=-1) < 2.0
        print(
            f"{clip.name:15s} frame {frame:3d}: {matched.sum():3d} of {len(truth)} visible inner"
            f" points found; offset ({error[:, 0].mean():+.3f}, {error[:, 1].mean():+.3f}) px,"
            f" median {np.median(size):.3f} px, 90 % {np.percentile(size, 90):.3f} px;"
            f" {near.any(axis=1).sum()} dots seen at the {len(hidden)} hidden points",
            flush=True,
        )


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--only", nargs="+", choices=[*FRAMES, *HELDOUT_FRAMES], help="check these clips"
    )
    args = parser.parse_args()
    scenarios.add_sheet = dotted_sheet(scenarios.add_sheet)  # what the builders call
    heldout.add_sheet = dotted_sheet(heldout.add_sheet)
    with tempfile.TemporaryDirectory(prefix="truth_dots_") as folder:
        for clip in scenarios.CLIPS + heldout.HELDOUT:
            if (clip.name in FRAMES) if args.only is None else (clip.name in args.only):
                check(clip, Path(folder))


if __name__ == "__main__":
    main()
