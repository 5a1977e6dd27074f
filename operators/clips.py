"""Frames and outlines crossing the Blender boundary.

Conventions are converted here and nowhere else: the engine's pixels have their origin at the
centre of the top-left pixel with y down; Blender images are bottom-up rows; mask coordinates
are normalised to the clip with the shorter axis scaled about 0.5 (one unit is the longer
side), y up.
"""

from pathlib import Path

import bpy
import numpy as np

from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.media.sources import open_source

#: Points sampled on each Bezier segment of a mask spline.
BEZIER_SAMPLES = 16


def active_clip(context):
    """The clip of the Clip Editor in context, else the scene's active clip."""
    space = getattr(context, "space_data", None)
    if space is not None and space.type == "CLIP_EDITOR" and space.clip is not None:
        return space.clip
    return context.scene.active_clip


def clip_file(clip) -> Path:
    """The clip's file on disk (VoodooError when it is not there)."""
    if clip is None:
        raise VoodooError("No movie clip: open one in the Movie Clip Editor first.")
    path = Path(bpy.path.abspath(clip.filepath, library=clip.library))
    if not path.exists():
        raise VoodooError(f"The clip's file {path} is missing; relocate the clip.")
    return path


def open_clip(clip):
    """An engine frame source reading the clip's file (OpenCV reads it directly)."""
    return open_source(clip_file(clip))


def source_index(clip, scene_frame: int) -> int:
    """0-based frame of the clip's file shown at a scene frame."""
    return int(scene_frame) - clip.frame_start + clip.frame_offset


def scene_frame(clip, index: int) -> int:
    """Scene frame that shows the clip's 0-based frame ``index``."""
    return int(index) + clip.frame_start - clip.frame_offset


def image_from_rgb(name: str, rgb: np.ndarray, pack: bool = True):
    """A new 8-bit Blender image holding a float RGB frame (H, W, 3), packed into the file."""
    h, w = rgb.shape[:2]
    img = bpy.data.images.new(name, w, h, alpha=False, float_buffer=False)
    rgba = np.ones((h, w, 4), dtype=np.float32)
    rgba[:, :, :3] = rgb[::-1]
    img.pixels.foreach_set(rgba.ravel())
    img.update()
    if pack:
        img.pack()
    return img


def rgb_from_image(img) -> np.ndarray:
    """Float RGB (H, W, 3) of a Blender image, top row first."""
    w, h = img.size
    if w == 0 or h == 0:
        raise VoodooError(f"Image {img.name!r} has no pixels (is its file missing?).")
    buf = np.empty(w * h * img.channels, dtype=np.float32)
    img.pixels.foreach_get(buf)
    rgba = buf.reshape(h, w, img.channels)[::-1]
    rgb = rgba[:, :, :3] if img.channels >= 3 else np.repeat(rgba[:, :, :1], 3, axis=2)
    return np.ascontiguousarray(rgb, dtype=np.float32)


def mask_to_pixels(co: np.ndarray, size) -> np.ndarray:
    """Mask coordinates (n, 2) -> engine pixels (n, 2) for a clip of ``size`` (w, h)."""
    w, h = float(size[0]), float(size[1])
    side = max(w, h)
    x_edge = w / 2 + (co[:, 0] - 0.5) * side
    y_up = h / 2 + (co[:, 1] - 0.5) * side
    return np.column_stack([x_edge - 0.5, h - y_up - 0.5])


def pixels_to_mask(px: np.ndarray, size) -> np.ndarray:
    """Inverse of :func:`mask_to_pixels`."""
    w, h = float(size[0]), float(size[1])
    side = max(w, h)
    x = (px[:, 0] + 0.5 - w / 2) / side + 0.5
    y = (h - px[:, 1] - 0.5 - h / 2) / side + 0.5
    return np.column_stack([x, y])


def _sample_spline(spline) -> np.ndarray:
    """Closed polyline (n, 2) through a cyclic mask spline's Bezier segments."""
    pts = spline.points
    n = len(pts)
    t = np.linspace(0.0, 1.0, BEZIER_SAMPLES, endpoint=False)[:, None]
    out = []
    for i in range(n):
        p0, p1 = pts[i], pts[(i + 1) % n]
        a, b = np.array(p0.co), np.array(p0.handle_right)
        c, d = np.array(p1.handle_left), np.array(p1.co)
        out.append((1 - t) ** 3 * a + 3 * (1 - t) ** 2 * t * b + 3 * (1 - t) * t**2 * c + t**3 * d)
    return np.vstack(out)


def mask_contour(mask, size) -> np.ndarray:
    """Outline (k, 2) in engine pixels from a mask's largest closed spline.

    Parameters
    ----------
    mask : bpy.types.Mask
    size : (int, int)
        The clip's (width, height) the mask was drawn on.
    """
    if mask is None:
        raise VoodooError("No mask: draw one over the clip in the Movie Clip Editor (Mask mode).")
    best, best_area = None, 0.0
    layers = [mask.layers.active] if mask.layers.active else list(mask.layers)
    for layer in layers:
        for spline in layer.splines:
            if len(spline.points) < 3 or not spline.use_cyclic:
                continue
            poly = _sample_spline(spline)
            x, y = poly[:, 0], poly[:, 1]
            area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
            if area > best_area:
                best, best_area = poly, area
    if best is None:
        raise VoodooError(
            f"Mask {mask.name!r} has no closed spline with 3 or more points; close the outline."
        )
    return mask_to_pixels(best, size)
