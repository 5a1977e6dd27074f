"""Pixel conventions at the Blender boundary; every conversion lives here.

- Engine pixels: origin at the centre of the top-left pixel, x right, y down (OpenCV).
- Blender images: rows bottom-up, float RGBA in [0, 1].
- Clip-editor view: frame pixels measured from the bottom-left *edge*, y up; a region's
  View2D maps it to region pixels (so drawing follows pan and zoom).
- Mask coordinates: normalised to the clip, the shorter axis scaled about 0.5 (one unit is
  the longer side), y up.
- The blob mesh shown in the file: pixels / ``DISPLAY_SCALE``, image-down as -Y.
"""

import bpy
import numpy as np

from ..voodoo_addon.errors import VoodooError

#: Pixels per Blender unit of the blob mesh shown in the file.
DISPLAY_SCALE = 100.0


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


def view_to_pixel(x: float, y: float, height: int) -> tuple[float, float]:
    """A clip-editor view point -> engine pixel."""
    return (float(x) - 0.5, float(height) - float(y) - 0.5)


def region_to_pixel(region, mouse_x: int, mouse_y: int, height: int) -> tuple[float, float]:
    """A mouse position in a clip editor's region -> engine pixel of its clip."""
    x, y = region.view2d.region_to_view(mouse_x, mouse_y)
    return view_to_pixel(x, y, height)


def pixels_to_region(points: np.ndarray, height: int, view_to_region) -> np.ndarray:
    """Engine pixels (n, 2) -> region pixels (n, 2).

    ``view_to_region(x, y, clip=False)`` is the region's View2D mapping; it is affine, so two
    calls give it for every point.
    """
    view = np.column_stack([points[:, 0] + 0.5, height - (points[:, 1] + 0.5)])
    o = np.array(view_to_region(0.0, 0.0, clip=False), dtype=np.float64)
    e = np.array(view_to_region(1000.0, 1000.0, clip=False), dtype=np.float64)
    return o + view * (e - o) / 1000.0


def pixels_to_display(points: np.ndarray) -> np.ndarray:
    """Engine pixels (n, 2) -> vertices (n, 3) of the blob mesh shown in the file."""
    v = np.zeros((len(points), 3))
    v[:, 0] = points[:, 0] / DISPLAY_SCALE
    v[:, 1] = -points[:, 1] / DISPLAY_SCALE
    return v
