"""A hard clip's video: Cycles frames, the camera post (exposure, noise), H.264 that fits.

Frames are rendered as 16-bit PNGs, developed with the clip's post in linear light plus
gaussian sensor noise into 8-bit PNGs, and encoded by Blender's sequencer and FFmpeg.
"""

import bpy

# isort: split
import cv2
import numpy as np
from blender_scene import frame_size, h264_output  # scripts/ is on sys.path

from hardclips.scene import HEIGHT, SEED, WIDTH

NOISE_SIGMA = 0.015  # sensor noise, as a fraction of full scale
MAX_VIDEO_BYTES = 1_400_000
CRF_STEPS = ("MEDIUM", "LOW", "VERYLOW", "LOWEST")  # tried in turn until the video is small


def srgb_to_linear(image):
    return np.where(image <= 0.04045, image / 12.92, ((image + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(image):
    image = np.clip(image, 0.0, 1.0)
    return np.where(image <= 0.0031308, image * 12.92, 1.055 * image ** (1 / 2.4) - 0.055)


def render_frames(scene, folder):
    """Render the animation as 16-bit PNGs into ``folder``. Returns their paths in order."""
    settings = scene.render.image_settings
    settings.media_type = "IMAGE"
    settings.file_format = "PNG"
    settings.color_mode, settings.color_depth = "RGB", "16"
    scene.render.filepath = str(folder / "frame_")
    bpy.ops.render.render(animation=True)
    paths = sorted(folder.glob("frame_*.png"))
    assert len(paths) == scene.frame_end - scene.frame_start + 1, "frames are missing"
    return paths


def develop(clip, number, paths, folder):
    """Camera post: ``clip.post`` in linear light, sensor noise, 8 bits. Returns PNG paths.

    ``number`` is the clip's place in ``CLIPS``: it seeds the noise.
    """
    rng = np.random.default_rng([SEED, 1, number])
    out = []
    for i, path in enumerate(paths):
        image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)[..., ::-1] / 65535.0  # RGB
        if clip.post is not None:
            image = linear_to_srgb(clip.post(i, i / clip.fps, srgb_to_linear(image)))
        image = image + rng.normal(0.0, NOISE_SIGMA, image.shape)
        rgb = np.clip(np.round(image * 255), 0, 255).astype(np.uint8)
        out.append(folder / f"cam_{i:04d}.png")
        cv2.imwrite(str(out[-1]), rgb[..., ::-1])
    return out


def encode(paths, fps, video_path):
    """H.264 MP4 of the PNGs through Blender's sequencer and FFmpeg, small enough.

    Tries ever lower qualities (CRF_STEPS) until the file is under MAX_VIDEO_BYTES.
    """
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    editor = scene.sequence_editor_create()
    strip = editor.strips.new_image("Frames", str(paths[0]), channel=1, frame_start=1)
    for path in paths[1:]:
        strip.elements.append(path.name)
    strip.colorspace_settings.name = "sRGB"
    frame_size(scene, (WIDTH, HEIGHT), fps)
    scene.render.threads_mode, scene.render.threads = "FIXED", 1
    scene.frame_start, scene.frame_end = 1, len(paths)
    h264_output(scene, video_path, fps)
    for crf in CRF_STEPS:
        scene.render.ffmpeg.constant_rate_factor = crf
        bpy.ops.render.render(animation=True)
        if video_path.stat().st_size <= MAX_VIDEO_BYTES:
            break
    return crf
