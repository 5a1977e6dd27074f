"""A hard clip's description (``Clip``) and its scene: render settings, camera, world, backdrop."""

from collections.abc import Callable
from dataclasses import dataclass

import bpy

# isort: split
import numpy as np
from blender_scene import (  # scripts/ is on sys.path when a script runs
    camera_above,
    frame_size,
    keyframe,
    packed_image,
    textured_grid,
    textured_material,
    workbench,
)
from foam_paint import backdrop_texture

WIDTH, HEIGHT = 640, 360
SEED = 2025

# Perspective camera above the origin looking down -Z (image x = world X, image y = -world Y):
# at the sheet's rest depth 1 world unit is about 104 px.
CAMERA_HEIGHT = 6.0
LENS_MM, SENSOR_MM = 35.0, 36.0
BACKDROP_SIZE = (16.0, 10.0)
BACKDROP_DEPTH = -2.0


@dataclass(frozen=True)
class Clip:
    name: str
    frames: int
    fps: int
    what: str  # for the README
    build: Callable  # build(rng, clip) -> Sheet, in a scene set up by new_scene
    samples: int = 8  # Cycles samples per pixel (denoised)
    motion_blur: bool = False
    post: Callable | None = None  # post(frame index, seconds, linear RGB (H, W, 3)) -> same
    post_note: str = "exposure and white balance"  # what post does, for the README

    def keyframe(self, target, channels):
        """Keyframe ``{(data path, index): [(seconds, value), ...]}`` on ``target``."""
        keyframe(target, channels, self.fps)


def new_scene(clip, draft):
    """Reset Blender; render settings, camera, world and backdrop for ``clip``."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    frame_size(scene, (WIDTH, HEIGHT), clip.fps)
    scene.render.threads_mode, scene.render.threads = "FIXED", 1
    scene.frame_start, scene.frame_end = 1, clip.frames
    if draft:
        workbench(scene, "STUDIO", "TEXTURE")
    else:
        cycles_settings(scene, clip)

    world = bpy.data.worlds.new("World")
    scene.world = world
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.03, 0.03, 0.035, 1)

    camera_above(
        CAMERA_HEIGHT,
        lens=LENS_MM,
        sensor_width=SENSOR_MM,
        sensor_fit="HORIZONTAL",
        clip_start=0.1,
        clip_end=50.0,
    )

    rng = np.random.default_rng([SEED, 0])  # the same backdrop in every clip
    backdrop = packed_image("Backdrop", backdrop_texture(rng, 480, 300))
    textured_grid(
        "Backdrop", BACKDROP_SIZE, (1, 1), textured_material("Backdrop", backdrop), BACKDROP_DEPTH
    )
    return scene


def cycles_settings(scene, clip):
    """Cycles on the CPU, seeded, few samples denoised by OIDN, few bounces; motion blur."""
    render = scene.render
    render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = clip.samples
    cycles.use_adaptive_sampling = False
    cycles.seed, cycles.use_animated_seed = SEED, True
    cycles.use_denoising = True
    cycles.denoiser = "OPENIMAGEDENOISE"
    cycles.denoising_input_passes = "RGB_ALBEDO"
    cycles.denoising_prefilter = "NONE"
    cycles.denoising_quality = "FAST"
    cycles.max_bounces, cycles.diffuse_bounces, cycles.glossy_bounces = 3, 2, 2
    cycles.transmission_bounces = cycles.volume_bounces = 0
    cycles.caustics_reflective = cycles.caustics_refractive = False
    render.use_persistent_data = True
    render.use_motion_blur = clip.motion_blur
    render.motion_blur_position = "CENTER"  # frame f is the shutter's centre
    render.motion_blur_shutter = 0.5
