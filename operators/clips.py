"""Movie clips and masks: which clip is meant, its file, its frames, an outline from a Mask.

Pixel conventions are in :mod:`.pixels`.
"""

from pathlib import Path

import bpy
import numpy as np

from ..voodoo_addon.blob.outline import signed_area
from ..voodoo_addon.errors import VoodooError
from ..voodoo_addon.media.sources import open_source
from .pixels import mask_to_pixels

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


def outline_from_mask(mask, size) -> np.ndarray:
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
            area = abs(signed_area(poly))
            if area > best_area:
                best, best_area = poly, area
    if best is None:
        raise VoodooError(
            f"Mask {mask.name!r} has no closed spline with 3 or more points; close the outline."
        )
    return mask_to_pixels(best, size)
