"""The doll: Blender with the add-on enabled, the clip loaded and the blob built on frame 0."""

import importlib
import json
from pathlib import Path

import bpy

# isort: split
import blender_addon  # scripts/ is on sys.path when a script runs
import numpy as np

from demosteps import SAMPLE_OUTLINE
from demosteps.report import run_operator

DOLL_NAME = "Doll"
MASK_NAME = "Outline"


def start_blender(scratch: Path):
    """An empty scene with the checkout enabled as an extension; returns ``(addon, sub)``.

    ``addon`` is the add-on's module name, ``sub("operators.storage")`` imports its submodules.
    """
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.preferences.filepaths.save_version = 0  # no demo.blend1 backups
    addon = blender_addon.enable_from_checkout(repo_module="voodoo_demo", scratch=scratch)
    return addon, lambda name: importlib.import_module(f"{addon}.{name}")


def load_clip(scene, path: Path, frames: int | None):
    """Load the clip as the scene's active clip; the scene's frames and rate follow it."""
    clip = bpy.data.movieclips.load(str(path))
    scene.active_clip = clip
    count = clip.frame_duration if frames is None else min(frames, clip.frame_duration)
    scene.frame_start = clip.frame_start
    scene.frame_end = clip.frame_start + count - 1
    scene.render.fps = round(clip.fps)
    scene.render.fps_base = round(clip.fps) / clip.fps
    scene.frame_set(scene.frame_start)
    return clip


def add_outline_mask(frames_module, points, size):
    """A Mask with one closed, straight-edged spline through the outline's pixel points."""
    co = frames_module.pixels_to_mask(np.asarray(points, dtype=float), size)
    mask = bpy.data.masks.new(MASK_NAME)
    spline = mask.layers.new(name="Layer").splines.new()
    spline.points.add(len(co) - 1)
    for point, (x, y) in zip(spline.points, co, strict=True):
        point.co = (x, y)
        point.handle_type = "VECTOR"
        point.handle_left = point.handle_right = (x, y)
    spline.use_cyclic = True
    return mask


def build_doll(sub, clip) -> None:
    """Capture the clip's first frame, outline it from the bundled contour, build the blob."""
    run_operator(bpy.ops.voodoo.capture_frame)
    points = json.loads(SAMPLE_OUTLINE.read_text())["points"]
    add_outline_mask(sub("operators.pixels"), points, tuple(clip.size))
    run_operator(bpy.ops.voodoo.contour_from_mask, mask=MASK_NAME)
    run_operator(bpy.ops.voodoo.build_blob, name=DOLL_NAME)
