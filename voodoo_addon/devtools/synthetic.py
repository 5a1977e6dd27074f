"""Synthetic takes with known motion: ground truth for tests and the benchmark.

A textured object (painted foam, or any picture) lies on a static background; each frame is
the object moved by a known forward map ``f(x) = S(x + u(x))`` -- a similarity ``S`` after an
analytic deformation ``u`` built from the named fields of :mod:`voodoo_addon.labels` -- plus
lighting change, sensor noise and an optional occluder. Frames are rendered by inverting ``f``
at every pixel, and the true position of any template point is ``f`` of it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np

from ..blob.labels import FIELDS
from ..tracking.params import rotation


def painted_foam(height: int, width: int, seed: int = 0, cell: int = 18) -> np.ndarray:
    """A foam block painted with a coloured grid and blobs, like the paper's doll (Fig. 1).

    Returns
    -------
    (height, width, 3) float32 in [0, 1]
    """
    rng = np.random.default_rng(seed)
    ny, nx = height // cell + 2, width // cell + 2
    colours = rng.uniform(0.15, 0.95, size=(ny, nx, 3)).astype(np.float32)
    img = cv2.resize(colours, (nx * cell, ny * cell), interpolation=cv2.INTER_NEAREST)
    img = np.ascontiguousarray(img[:height, :width])
    for y in range(0, height, cell):
        cv2.line(img, (0, y), (width - 1, y), (0.08, 0.08, 0.1), 2)
    for x in range(0, width, cell):
        cv2.line(img, (x, 0), (x, height - 1), (0.08, 0.08, 0.1), 2)
    for _ in range((height * width) // (cell * cell * 3)):
        c = (int(rng.integers(0, width)), int(rng.integers(0, height)))
        cv2.circle(
            img,
            c,
            int(rng.integers(2, cell // 2)),
            tuple(float(v) for v in rng.uniform(0, 1, 3)),
            -1,
        )
    # Paint is not perfectly flat: add soft low-frequency shading and fine grain.
    shade = cv2.GaussianBlur(rng.normal(0, 1, (height, width)).astype(np.float32), (0, 0), cell)
    shade = 0.08 * shade / (np.abs(shade).max() + 1e-6)
    grain = rng.normal(0, 0.02, (height, width, 1)).astype(np.float32)
    return np.clip(img + shade[:, :, None] + grain, 0, 1).astype(np.float32)


def background(height: int, width: int, seed: int = 1) -> np.ndarray:
    """A dim, softly textured backdrop (H, W, 3) float32."""
    rng = np.random.default_rng(seed)
    noise = rng.uniform(0, 1, (height // 8 + 1, width // 8 + 1, 3)).astype(np.float32)
    img = cv2.resize(noise, (width, height), interpolation=cv2.INTER_CUBIC)
    return np.clip(0.12 + 0.18 * img, 0, 1).astype(np.float32)


@dataclass(frozen=True)
class Pose:
    """The object's state in one frame.

    Attributes
    ----------
    tx, ty : float
        Translation of the object centre, pixels.
    theta : float
        Rotation, radians (y down).
    log_scale : float
    deform : dict
        Field name (see :data:`voodoo_addon.labels.FIELDS`) -> amplitude as a fraction of
        the object's RMS radius.
    contrast, brightness : float
        ``frame = contrast * frame + brightness``.
    occluder : (x0, y0, x1, y1) or None
        A flat grey rectangle in front of the object, frame pixels.
    channel_gain : (3,) float
        White balance / exposure: each channel multiplied by its gain.
    shade : (cx, cy, radius, gain) or None
        A soft shadow (gain < 1) or lit patch (gain > 1) on the object, frame pixels: the
        object's colours times ``1 + (gain - 1) exp(-d^2 / 2 radius^2)``.
    glint : (cx, cy, radius, level) or None
        A specular highlight on the object: white light ``level exp(-d^2 / 2 radius^2)``
        added.
    blur : (dx, dy) or None
        Motion blur along this displacement (pixels) during the exposure.
    """

    tx: float = 0.0
    ty: float = 0.0
    theta: float = 0.0
    log_scale: float = 0.0
    deform: dict = field(default_factory=dict)
    contrast: float = 1.0
    brightness: float = 0.0
    occluder: tuple | None = None
    channel_gain: tuple = (1.0, 1.0, 1.0)
    shade: tuple | None = None
    glint: tuple | None = None
    blur: tuple | None = None


class Scene:
    """An object texture inside an outline, on a background.

    Parameters
    ----------
    texture : (H, W, 3) float32
        The object's surface in its rest pose, frame-sized.
    mask : (H, W) bool
        Where the object is in its rest pose.
    backdrop : (H, W, 3) float32
    centre : (2,) float
        Pivot of the similarity and origin of the deformation fields.
    length : float
        Normalising length of the deformation fields (RMS radius).
    """

    def __init__(self, texture, mask, backdrop, centre, length):
        self.texture = texture.astype(np.float32)
        self.mask = mask.astype(np.float32)
        self.backdrop = backdrop.astype(np.float32)
        self.centre = np.asarray(centre, dtype=np.float64)
        self.length = float(length)
        h, w = mask.shape
        ys, xs = np.mgrid[0:h, 0:w]
        self._grid = np.stack([xs, ys], axis=-1).reshape(-1, 2).astype(np.float64)

    def displacement(self, pose: Pose, x: np.ndarray) -> np.ndarray:
        """Deformation ``u(x)`` (n, 2) of rest-pose points x (n, 2)."""
        # Far from the object the fields only matter to the renderer's inversion: keep them tame.
        d = np.clip((x - self.centre) / self.length, -3.0, 3.0)
        u = np.zeros_like(x)
        for name, amp in pose.deform.items():
            fu, fv = FIELDS[name](d[:, 0], d[:, 1])
            u[:, 0] += amp * self.length * fu
            u[:, 1] += amp * self.length * fv
        return u

    def forward(self, pose: Pose, x: np.ndarray) -> np.ndarray:
        """Where rest-pose points x (n, 2) are in the frame of ``pose``."""
        y = x + self.displacement(pose, x) - self.centre
        return (
            self.centre
            + np.array([pose.tx, pose.ty])
            + np.exp(pose.log_scale) * y @ rotation(pose.theta).T
        )

    def inverse(self, pose: Pose, y: np.ndarray, iterations: int = 30) -> np.ndarray:
        """Rest-pose points whose image is y (fixed-point inversion of the deformation)."""
        z = (y - self.centre - np.array([pose.tx, pose.ty])) @ rotation(pose.theta)
        z = z * np.exp(-pose.log_scale) + self.centre
        x = z.copy()
        if pose.deform:
            for _ in range(iterations):
                x = z - self.displacement(pose, x)
        return x

    def render(self, pose: Pose, noise: float = 0.0, rng=None) -> np.ndarray:
        """The frame (H, W, 3) float32 of a pose."""
        h, w = self.mask.shape
        src = self.inverse(pose, self._grid).astype(np.float32)
        mx, my = src[:, 0].reshape(h, w), src[:, 1].reshape(h, w)
        obj = cv2.remap(self.texture, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)
        cover = cv2.remap(self.mask, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)
        if pose.shade is not None:
            cx, cy, r, g = pose.shade
            obj = obj * (1.0 + (g - 1.0) * _spot(h, w, cx, cy, r))[:, :, None]
        if pose.glint is not None:
            cx, cy, r, level = pose.glint
            obj = obj + level * _spot(h, w, cx, cy, r)[:, :, None]
        frame = obj * cover[:, :, None] + self.backdrop * (1.0 - cover[:, :, None])
        frame = frame * np.asarray(pose.channel_gain, np.float32)
        if pose.blur is not None:
            frame = _motion_blur(frame, *pose.blur)
        frame = pose.contrast * frame + pose.brightness
        if pose.occluder is not None:
            x0, y0, x1, y1 = (int(round(v)) for v in pose.occluder)
            frame[max(y0, 0) : max(y1, 0), max(x0, 0) : max(x1, 0)] = (0.55, 0.5, 0.45)
        if noise > 0:
            rng = rng or np.random.default_rng(0)
            frame = frame + rng.normal(0, noise, frame.shape).astype(np.float32)
        return np.clip(frame, 0, 1).astype(np.float32)


def _spot(h: int, w: int, cx: float, cy: float, radius: float) -> np.ndarray:
    """A Gaussian spot (h, w) float32 of peak 1."""
    ys, xs = np.mgrid[0:h, 0:w].astype(np.float32)
    return np.exp(-((xs - cx) ** 2 + (ys - cy) ** 2) / (2.0 * radius**2)).astype(np.float32)


def _motion_blur(frame: np.ndarray, dx: float, dy: float) -> np.ndarray:
    """The frame averaged along a straight motion of (dx, dy) pixels."""
    steps = max(2, int(np.ceil(np.hypot(dx, dy))))
    k = 2 * steps + 1
    kernel = np.zeros((k, k), np.float32)
    for t in np.linspace(-0.5, 0.5, 2 * steps + 1):
        kernel[int(round(steps + t * dy)), int(round(steps + t * dx))] += 1.0
    return cv2.filter2D(frame, -1, kernel / kernel.sum(), borderType=cv2.BORDER_REFLECT)


def squash_right(rest: np.ndarray, centre, length: float, amount: float) -> np.ndarray:
    """``rest`` with its right half pressed towards the line x = ``centre[0]``.

    By ``amount`` (0: unchanged, 0.9: to a tenth of its width): the right half folding
    away, as a bend past 80 degrees shows it. What then lies beyond ``3 * length`` of the
    line is the picture's top-left colour.
    """
    h, w = rest.shape[:2]
    xs = np.arange(w, dtype=np.float32)
    src = np.where(xs > centre[0], centre[0] + (xs - centre[0]) / max(1.0 - amount, 1e-3), xs)
    mx = np.tile(src, (h, 1)).astype(np.float32)
    my = np.tile(np.arange(h, dtype=np.float32)[:, None], (1, w))
    out = cv2.remap(rest, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    out[mx > centre[0] + 3 * length] = rest[0, 0]
    return out


def ellipse_contour(centre, rx: float, ry: float, n: int = 64, angle: float = 0.0) -> np.ndarray:
    """Closed ellipse polygon (n, 2)."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    pts = np.column_stack([rx * np.cos(t), ry * np.sin(t)]) @ rotation(angle).T
    return pts + np.asarray(centre, dtype=np.float64)


def foam_scene(width: int, height: int, blob_pixels: float, seed: int = 0, texture=None):
    """A foam object on a backdrop, with a blob outline of about ``blob_pixels`` inside it.

    Returns
    -------
    scene : Scene
    contour : (k, 2) float64
        The blob outline (an ellipse 1.4:1) on the rest frame.
    """
    centre = np.array([(width - 1) / 2.0, (height - 1) / 2.0])
    ry = np.sqrt(blob_pixels / (np.pi * 1.4))
    rx = 1.4 * ry
    tex = painted_foam(height, width, seed) if texture is None else texture
    # The foam block is larger than the blob (the animator outlines a region on it).
    mask = np.zeros((height, width), np.uint8)
    cv2.ellipse(
        mask,
        (int(round(centre[0])), int(round(centre[1]))),
        (int(rx * 1.35 + 6), int(ry * 1.45 + 6)),
        0,
        0,
        360,
        1,
        -1,
    )
    backdrop = background(height, width, seed + 1)
    length = float(np.sqrt((rx * rx + ry * ry) / 4.0))
    scene = Scene(tex, mask.astype(bool), backdrop, centre, length)
    return scene, ellipse_contour(centre, rx, ry)


#: Ground-truth scenarios: name -> what the object does over the take.
def write_frames(path, frames, fps: float = 30.0) -> None:
    """Write frames (float RGB) to a video file, or to numbered PNGs in a folder.

    A ``path`` without a suffix is a folder. ``.avi`` uses the lossless FFV1 codec, other
    suffixes MPEG-4.
    """
    from pathlib import Path

    from ..media.images import to_uint8_bgr, write_image

    path = Path(path)
    if not path.suffix:
        path.mkdir(parents=True, exist_ok=True)
        for i, f in enumerate(frames):
            write_image(path / f"frame_{i:05d}.png", f)
        return
    h, w = frames[0].shape[:2]
    fourcc = cv2.VideoWriter_fourcc(*("FFV1" if path.suffix.lower() == ".avi" else "mp4v"))
    writer = cv2.VideoWriter(str(path), fourcc, fps, (w, h))
    if not writer.isOpened():
        from ..errors import VoodooError

        raise VoodooError(f"Cannot write the video {path}.")
    for f in frames:
        writer.write(to_uint8_bgr(f))
    writer.release()
