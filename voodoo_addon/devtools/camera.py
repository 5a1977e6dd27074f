"""A real camera's faults, put on clean renders: defocus, exposure drift, sensor noise, JPEG.

A render is sharper, steadier and cleaner than what a webcam sends. To see whether a result
on renders holds on a camera's frames, :func:`degrade` gives a clip, frame by frame, what a
cheap camera adds, in the order the camera adds it: the lens blurs (defocus), the
auto-exposure swings the brightness, the sensor adds noise, and the frame is compressed as
JPEG, which is what USB webcams send (MJPEG). The faults are seeded, so a degraded clip is
the same every run.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import cv2
import numpy as np


@dataclass(frozen=True)
class CameraFaults:
    """What a camera adds to a clean frame.

    Attributes
    ----------
    blur : float
        Defocus: Gaussian sigma in pixels (0: none).
    drift : float
        Exposure swing: the gain goes ``1 + drift * sin(2 pi t / T)`` over the clip's T
        frames (0: none).
    noise : float
        Sensor noise: standard deviation in 8-bit grey levels (0: none).
    jpeg : int
        JPEG quality of every frame, 1-100 (100: not compressed).
    seed : int
        Seed of the noise.
    """

    blur: float = 0.8
    drift: float = 0.15
    noise: float = 4.0
    jpeg: int = 70
    seed: int = 0


#: The cameras the fold benchmark can put on its clips: ``webcam`` a fair USB webcam in
#: room light, ``dim`` a cheap one in a dim room (more noise and blur, harder compression),
#: and ``redraw``, no camera at all: the clean render with half a grey level of sensor noise,
#: which moves about a third of its values by one level. The tracker is chaotic on the fold
#: renders -- a difference in the last bits of its arithmetic (another processor, the
#: Lorentzian's sigma changed by one part in 10^10) moves a clip's error by up to 2 px and
#: its lost frames by three -- so a change to it is judged over several seeds of this.
CAMERAS = {
    "webcam": CameraFaults(),
    "dim": CameraFaults(blur=1.0, drift=0.2, noise=7.0, jpeg=60),
    "redraw": CameraFaults(blur=0.0, drift=0.0, noise=0.5, jpeg=100),
}


def degrade(frames, faults: CameraFaults) -> list[np.ndarray]:
    """The frames (8-bit RGB, (H, W, 3)) as the camera ``faults`` would send them."""
    rng = np.random.default_rng(faults.seed)
    count = len(frames)
    out = []
    for i, frame in enumerate(frames):
        x = np.asarray(frame, np.float32)
        if faults.blur > 0:
            x = cv2.GaussianBlur(x, (0, 0), faults.blur)
        x = x * np.float32(1.0 + faults.drift * np.sin(2.0 * np.pi * i / count))
        if faults.noise > 0:
            x = x + rng.normal(0.0, faults.noise, x.shape).astype(np.float32)
        x = np.clip(np.rint(x), 0, 255).astype(np.uint8)
        if faults.jpeg < 100:
            ok, data = cv2.imencode(".jpg", x[..., ::-1], [cv2.IMWRITE_JPEG_QUALITY, faults.jpeg])
            if not ok:
                raise RuntimeError("OpenCV could not encode a frame as JPEG")
            x = np.ascontiguousarray(cv2.imdecode(data, cv2.IMREAD_COLOR)[..., ::-1])
        out.append(x)
    return out


def add_camera_arguments(parser) -> None:
    """``--camera`` and ``--seed`` on a command line that tracks the fold renders."""
    parser.add_argument(
        "--camera", choices=sorted(CAMERAS), help="put a camera's faults on the frames first"
    )
    parser.add_argument(
        "--seed",
        type=int,
        help="with --camera, another draw of its sensor noise: a change is real only if it "
        "holds over several",
    )


def chosen_camera(parser, args) -> CameraFaults | None:
    """The camera the arguments of :func:`add_camera_arguments` name (None: the clean render)."""
    if args.seed is not None and not args.camera:
        parser.error("--seed needs --camera")
    camera = CAMERAS[args.camera] if args.camera else None
    if args.seed is not None:
        camera = replace(camera, seed=args.seed)
    return camera
