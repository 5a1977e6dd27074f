"""A 1920x1080 clip through the command line, end to end, as a user would run it.

The clip is the bundled sample take (a Blender render) scaled to 1440x1080 and centred on a
1920x1080 frame, written as H.264 (so decoding costs what it costs on real footage); its
outline is scaled the same way. ``python -m voodoo_addon track`` then runs on it as a separate
process, and the wall time of the whole command -- start-up, reading, building the blob,
tracking every frame, writing the take -- gives the end-to-end frame rate.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

from ..blob.outline import load_contour_json, save_contour_json
from .bench import SAMPLES

SIZE = (1920, 1080)


def make_hd_clip(folder: Path, repeat: int = 2):
    """Write ``hd.mp4`` and ``hd.json`` into ``folder``.

    Returns (video, outline, number of frames, codec).

    The sample take is played forward then backward ``repeat`` times (so the clip is long
    enough for the start-up to count as it does on a real take).
    """
    cap = cv2.VideoCapture(str(SAMPLES / "sample_take.mp4"))
    frames = []
    while True:
        ok, img = cap.read()
        if not ok:
            break
        frames.append(img)
    cap.release()
    if not frames:
        raise RuntimeError("cannot read samples/sample_take.mp4")
    h0, w0 = frames[0].shape[:2]
    scale = SIZE[1] / h0
    w1 = int(round(w0 * scale))
    pad = (SIZE[0] - w1) // 2
    seq = (frames + frames[::-1]) * repeat
    video = folder / "hd.mp4"

    def frames_hd():
        for img in seq:
            big = cv2.resize(img, (w1, SIZE[1]), interpolation=cv2.INTER_LINEAR)
            canvas = np.full((SIZE[1], SIZE[0], 3), 40, np.uint8)
            canvas[:, pad : pad + w1] = big
            yield canvas

    codec = _write_h264(video, frames_hd())
    outline = load_contour_json(SAMPLES / "sample_take.json")
    # Pixel centres scale about the corner half a pixel out.
    outline = (outline + 0.5) * scale - 0.5 + np.array([pad, 0.0])
    path = folder / "hd.json"
    save_contour_json(path, outline)
    return video, path, len(seq), codec


def _write_h264(path: Path, frames) -> str:
    """Encode 8-bit BGR frames; returns the codec.

    H.264 with imageio-ffmpeg's FFmpeg (a development dependency), or MPEG-4 Part 2 with
    OpenCV when it is missing.
    """
    try:
        import imageio_ffmpeg
    except ImportError:
        writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), 30.0, SIZE)
        for f in frames:
            writer.write(f)
        writer.release()
        return "MPEG-4 Part 2 (imageio-ffmpeg missing)"
    cmd = [imageio_ffmpeg.get_ffmpeg_exe(), "-loglevel", "error", "-y", "-f", "rawvideo"]
    cmd += ["-pix_fmt", "bgr24", "-s", f"{SIZE[0]}x{SIZE[1]}", "-r", "30", "-i", "-"]
    cmd += ["-c:v", "libx264", "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p"]
    proc = subprocess.Popen([*cmd, str(path)], stdin=subprocess.PIPE)
    for f in frames:
        proc.stdin.write(np.ascontiguousarray(f).tobytes())
    proc.stdin.close()
    if proc.wait() != 0:
        raise RuntimeError("FFmpeg could not encode the 1080p clip")
    return "H.264"


def run_hd() -> dict:
    """Time ``python -m voodoo_addon track`` on the 1080p clip (a separate process)."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        video, outline, n, codec = make_hd_clip(folder)
        root = Path(__file__).resolve().parents[2]
        cmd = [sys.executable, "-m", "voodoo_addon", "track", str(video)]
        cmd += ["--contour", str(outline), "--out", str(folder / "take.npz"), "--quiet"]
        t0 = time.perf_counter()
        done = subprocess.run(cmd, cwd=root, capture_output=True, text=True, check=False)
        wall = time.perf_counter() - t0
        if done.returncode != 0:
            raise RuntimeError(done.stderr.strip() or "track failed")
    return {
        "clip": f"sample take scaled to {SIZE[0]}x{SIZE[1]}, {codec}",
        "frames": n,
        "wall_s": round(wall, 2),
        "fps_end_to_end": round(n / wall, 1),
        "command": "python -m voodoo_addon track hd.mp4 --contour hd.json --out take.npz",
    }


if __name__ == "__main__":
    print(run_hd())
