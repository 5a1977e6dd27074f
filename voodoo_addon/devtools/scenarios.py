"""Named ground-truth takes: poses of the synthetic doll frame by frame (tests, benchmark)."""

from __future__ import annotations

import numpy as np

from ..checks import whole
from ..errors import VoodooError
from .synthetic import Pose, Scene, foam_scene, write_frames

#: Frames a written scenario may have (they are rendered in memory first).
MAX_FRAMES = 2000
#: Width and height a written scenario may have, pixels (the doll is about 5000 pixels).
SIZE_RANGE = (128, 1920)

SCENARIOS = (
    "translate",
    "rotate",
    "scale",
    "bend",
    "lighting",
    "occluder",
    "noise",
    "exit",
    "mixed",
    "shading",
    "exposure",
    "jumps",
)


def scenario_poses(name: str, scene: Scene, frames: int = 48, size=(320, 240)) -> list[Pose]:
    """Poses of a named ground-truth take (frame 0 is always the rest pose).

    translate  15 px per frame back and forth (sharp reversals)
    rotate     a full turn over the take
    scale      0.5x to 2x and back
    bend       bend-x and taper-x, up to 15% of the RMS radius
    lighting   contrast and brightness changing by +-30%
    occluder   a grey card covering a quarter of the blob crosses it
    noise      sensor noise of 0.05 (13 grey levels) with slow motion
    exit       the object leaves the frame entirely and comes back
    mixed      translation, rotation, scale and bending at once
    shading    bending under a lamp: a soft shadow and a specular glint sweep across it
    exposure   auto exposure and white balance: steps of x1.5 and x0.7, channels drifting
               by +-15%, with slow motion
    jumps      a cheap camera at 8 fps: 6-9% of the frame width and up to 12 degrees
               between frames, reversing, with motion blur
    """
    w, h = size
    t = np.arange(frames) / max(frames - 1, 1)
    poses = []
    for i, s in enumerate(t):
        if name == "translate":
            # Triangle wave of amplitude 60 px at 15 px/frame, plus a slow vertical drift.
            phase = (i * 15.0) % 240.0
            tx = phase if phase <= 60 else (120 - phase if phase <= 180 else phase - 240)
            poses.append(Pose(tx=tx, ty=20 * np.sin(2 * np.pi * s)))
        elif name == "rotate":
            poses.append(Pose(theta=2 * np.pi * s, tx=5 * np.sin(2 * np.pi * s)))
        elif name == "scale":
            poses.append(Pose(log_scale=np.log(2.0) * np.sin(2 * np.pi * s)))
        elif name == "bend":
            poses.append(
                Pose(
                    deform={
                        "bend-x": 0.15 * np.sin(2 * np.pi * s),
                        "taper-x": 0.15 * np.sin(4 * np.pi * s),
                    }
                )
            )
        elif name == "lighting":
            c = 1.0 + 0.3 * np.sin(2 * np.pi * s)
            poses.append(
                Pose(
                    contrast=c,
                    brightness=0.15 * np.sin(4 * np.pi * s),
                    tx=3 * np.sin(2 * np.pi * s),
                )
            )
        elif name == "occluder":
            # A card a quarter of the blob's area, sliding across its middle.
            side = np.sqrt(0.25 * np.pi * scene.length**2 * 2)
            cx = scene.centre[0] - 2.5 * scene.length + 5 * scene.length * s
            cy = scene.centre[1]
            poses.append(
                Pose(
                    occluder=(cx - side / 2, cy - side / 2, cx + side / 2, cy + side / 2),
                    tx=4 * np.sin(2 * np.pi * s),
                )
            )
        elif name == "noise":
            poses.append(
                Pose(
                    tx=10 * np.sin(2 * np.pi * s),
                    theta=0.2 * np.sin(2 * np.pi * s),
                    deform={"bend-x": 0.1 * np.sin(2 * np.pi * s)},
                )
            )
        elif name == "exit":
            # Out to the right past the edge by frame 1/3, back by 2/3, then stay.
            far = w + 2 * scene.length * 1.6
            k = np.clip(np.sin(np.pi * np.clip(s * 1.5, 0, 1)), 0, 1)
            poses.append(Pose(tx=far * k))
        elif name == "mixed":
            poses.append(
                Pose(
                    tx=30 * np.sin(2 * np.pi * s),
                    ty=15 * np.sin(4 * np.pi * s),
                    theta=0.8 * np.sin(2 * np.pi * s),
                    log_scale=0.3 * np.sin(2 * np.pi * s),
                    deform={
                        "bend-x": 0.1 * np.sin(4 * np.pi * s),
                        "shear": 0.05 * np.sin(2 * np.pi * s),
                    },
                )
            )
        elif name == "shading":
            length = scene.length
            c = scene.centre
            sweep = -2.0 + 4.0 * s
            poses.append(
                Pose(
                    tx=5 * np.sin(2 * np.pi * s),
                    deform={"bend-x": 0.12 * np.sin(2 * np.pi * s)},
                    shade=(c[0] + sweep * length, c[1] - 0.3 * length, 0.7 * length, 0.45),
                    glint=(c[0] - sweep * length, c[1] + 0.4 * length, 0.3 * length, 0.6),
                )
            )
        elif name == "exposure":
            step = 1.0 if s < 1 / 3 else (1.5 if s < 2 / 3 else 0.7)
            drift = 0.15 * np.sin(2 * np.pi * s)
            poses.append(
                Pose(
                    tx=8 * np.sin(2 * np.pi * s),
                    theta=0.15 * np.sin(2 * np.pi * s),
                    channel_gain=(step * (1 + drift), step, step * (1 - drift)),
                )
            )
        elif name == "jumps":
            # Position on a zigzag: each frame jumps 6-9% of the width, turning.
            step = w * (0.06 + 0.03 * np.sin(5.0 * i))
            phase = np.floor(i / 3) % 2  # three jumps one way, three back
            prev = poses[-1] if poses else Pose()
            tx = prev.tx + (step if phase == 0 else -step) if i else 0.0
            ty = 0.2 * h * np.sin(0.9 * i) if i else 0.0
            theta = 0.2 * np.sin(0.7 * i) if i else 0.0
            blur = None if not i else (0.3 * (tx - prev.tx), 0.3 * (ty - prev.ty))
            poses.append(
                Pose(
                    tx=tx,
                    ty=ty,
                    theta=theta,
                    deform={"bend-x": 0.08 * np.sin(0.5 * i)},
                    blur=blur,
                )
            )
        else:
            raise ValueError(f"unknown scenario {name!r}; have {', '.join(SCENARIOS)}")
    return poses


def scenario_take(
    name: str,
    frames: int = 48,
    size=(320, 240),
    blob_pixels: float = 5000,
    noise: float | None = None,
    seed: int = 0,
):
    """Render a named scenario.

    Returns
    -------
    frames : list of (H, W, 3) float32
    contour : (k, 2) float64
        Blob outline on frame 0.
    truth : callable
        ``truth(i, points)`` -> where rest-pose points (n, 2) are in frame i.
    """
    w, h = size
    scene, contour = foam_scene(w, h, blob_pixels, seed=seed)
    poses = scenario_poses(name, scene, frames, size)
    if noise is None:
        noise = 0.05 if name == "noise" else 0.01
    rng = np.random.default_rng(seed + 100)
    images = [scene.render(p, noise=noise, rng=rng) for p in poses]
    return images, contour, lambda i, pts: scene.forward(poses[i], pts)


def write_scenario(name: str, path, frames: int = 48, size=(320, 240)) -> np.ndarray:
    """Render a scenario to a video or folder; returns the blob outline on frame 0.

    Raises
    ------
    VoodooError
        For an unknown scenario, a number of frames or a size out of range (checked before
        anything is rendered).
    """
    if name not in SCENARIOS:
        raise VoodooError(f"Unknown scenario {name!r}; pick from {', '.join(SCENARIOS)}.")
    frames = whole(frames, "the number of frames", 1, MAX_FRAMES)
    try:
        w, h = size
    except (TypeError, ValueError):
        raise VoodooError(f"The size must be a width and a height; got {size!r}.") from None
    size = (whole(w, "the width", *SIZE_RANGE), whole(h, "the height", *SIZE_RANGE))
    images, contour, _ = scenario_take(name, frames, size)
    write_frames(path, images)
    return contour
