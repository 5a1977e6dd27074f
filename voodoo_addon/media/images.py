"""Reading and converting pictures: the engine's images are float32 RGB in [0, 1], (H, W, 3)."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from ..errors import VoodooError


def to_float_rgb(image: np.ndarray, bgr: bool = False) -> np.ndarray:
    """Any 8/16-bit or float picture as float32 RGB in [0, 1].

    Parameters
    ----------
    image : (H, W) or (H, W, 3|4) array
    bgr : bool
        True when the channels are OpenCV's BGR(A) order.

    Returns
    -------
    (H, W, 3) float32
    """
    img = np.asarray(image)
    if img.ndim == 2:
        img = np.repeat(img[:, :, None], 3, axis=2)
    if img.ndim != 3 or img.shape[2] not in (3, 4):
        raise VoodooError(f"Expected an RGB picture, got an array of shape {img.shape}.")
    img = img[:, :, :3]
    if bgr:
        img = img[:, :, ::-1]
    if img.dtype == np.uint8:
        out = img.astype(np.float32) / 255.0
    elif img.dtype == np.uint16:
        out = img.astype(np.float32) / 65535.0
    else:
        out = img.astype(np.float32)
    out = np.nan_to_num(out, nan=0.0, posinf=1.0, neginf=0.0)
    return np.ascontiguousarray(np.clip(out, 0.0, 1.0))


def to_uint8_bgr(image: np.ndarray) -> np.ndarray:
    """Float RGB in [0, 1] (or 8-bit RGB) to OpenCV's uint8 BGR, for writing and drawing."""
    if image.dtype == np.uint8:
        return cv2.cvtColor(image, cv2.COLOR_RGB2BGR)
    return np.ascontiguousarray((np.clip(image, 0, 1)[:, :, ::-1] * 255.0 + 0.5).astype(np.uint8))


def blur(image: np.ndarray, sigma: float) -> np.ndarray:
    """Gaussian blur with a kernel cut at 2.5 sigma (the template and the frames share it)."""
    if sigma <= 0:
        return image
    k = 2 * int(np.ceil(2.5 * sigma)) + 1
    return cv2.GaussianBlur(image, (k, k), sigma, borderType=cv2.BORDER_REFLECT)


def check_picture_path(path) -> None:
    """Raise a VoodooError unless OpenCV writes pictures with this name's extension.

    For checking a preview's name before any work is done or any file is written.
    """
    suffix = Path(path).suffix
    try:
        ok = bool(suffix) and cv2.haveImageWriter(str(path))
    except cv2.error:  # e.g. .exr while OpenEXR is disabled
        ok = False
    if not ok:
        kind = f"'{suffix}' pictures" if suffix else "a picture without an extension"
        raise VoodooError(f"Cannot write {kind} ({path}); name it .png or .jpg.")


def write_image(path, image: np.ndarray) -> None:
    """Write float RGB in [0, 1] (or uint8 BGR) to a picture file."""
    check_picture_path(path)
    img = image if image.dtype == np.uint8 else to_uint8_bgr(image)
    try:
        ok = cv2.imwrite(str(path), img)
    except cv2.error as exc:
        raise VoodooError(f"Could not write the picture {path} ({exc.err}).") from None
    if not ok:
        raise VoodooError(f"Could not write the picture {path}.")
