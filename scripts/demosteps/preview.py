"""The preview: Workbench renders of the characters beside the clip with the tracked mesh."""

from pathlib import Path

import bpy

# isort: split
import cv2
import numpy as np

from demosteps import SAMPLE_CLIP
from demosteps.report import DemoError, quiet_stdout, run_operator
from demosteps.stage import RENDER_SIZE

# Preview video drawing (BGR).
LIVE_MESH = (60, 230, 255)
LOST_MESH = (40, 40, 255)
LABEL_SCALE = 0.5


def render_frames(scene, folder: Path, progress_bar) -> dict[int, Path]:
    """Render every scene frame to a PNG with Workbench; returns {scene frame: file}."""
    folder.mkdir(parents=True, exist_ok=True)
    frames = range(scene.frame_start, scene.frame_end + 1)
    bar = progress_bar(len(frames), label="rendering")
    files = {}
    for done, frame in enumerate(frames, start=1):
        scene.frame_set(frame)
        files[frame] = folder / f"frame_{frame:04d}.png"
        scene.render.filepath = str(files[frame])
        with quiet_stdout():
            run_operator(bpy.ops.render.render, write_still=True)
        bar(done)
    return files


def label(canvas: np.ndarray, text: str, org: tuple[int, int]) -> None:
    """White text with a dark outline, readable on any background."""
    for colour, thickness in (((0, 0, 0), 3), ((255, 255, 255), 1)):
        cv2.putText(
            canvas, text, org, cv2.FONT_HERSHEY_SIMPLEX, LABEL_SCALE, colour, thickness, cv2.LINE_AA
        )


def write_preview(path: Path, take, frames: np.ndarray, renders: dict, draw_mesh) -> int:
    """Clip frame + tracked mesh beside the render, per take row; returns frames written.

    Parameters
    ----------
    take : Take
        ``vertices`` (T, m, 2) tracked nodes in clip pixels, ``triangles`` (t, 3).
    frames : (T,) int
        Scene frame of each take row.
    renders : dict
        Scene frame -> rendered PNG.
    draw_mesh : callable
        The engine's ``preview.draw_mesh(canvas, vertices, triangles, colour, scale=...)``.
    """
    render_width, height = RENDER_SIZE
    capture = cv2.VideoCapture(str(SAMPLE_CLIP))
    capture.set(cv2.CAP_PROP_POS_FRAMES, int(take.frame_indices[0]))
    scale = height / capture.get(cv2.CAP_PROP_FRAME_HEIGHT)  # the clip at the render's height
    width = round(capture.get(cv2.CAP_PROP_FRAME_WIDTH) * scale)
    writer = cv2.VideoWriter(
        str(path), cv2.VideoWriter_fourcc(*"mp4v"), float(take.fps), (width + render_width, height)
    )
    if not capture.isOpened() or not writer.isOpened():
        raise DemoError(f"OpenCV could not read {SAMPLE_CLIP} or write {path}.")
    written = 0
    try:
        for row, frame in enumerate(frames):
            ok, image = capture.read()
            if not ok or int(frame) not in renders:
                break
            left = cv2.resize(image, (width, height), interpolation=cv2.INTER_AREA)
            colour = LOST_MESH if take.lost[row] else LIVE_MESH
            draw_mesh(left, take.vertices[row], take.triangles, colour, scale=scale)
            status = "LOST" if take.lost[row] else f"confidence {take.confidence[row]:.2f}"
            label(left, f"clip frame {take.frame_indices[row]}  {status}", (10, 22))
            right = cv2.imread(str(renders[int(frame)]))
            label(right, f"scene frame {frame}  (Workbench)", (10, 22))
            writer.write(np.hstack([left, right]))
            written += 1
    finally:
        capture.release()
        writer.release()
    return written
