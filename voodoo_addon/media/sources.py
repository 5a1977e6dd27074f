"""Frame sources: a video file, a folder of pictures, or a live camera -- one interface.

Video files and cameras both go through OpenCV's ``VideoCapture``, so tests that read a file
exercise the same code path as a webcam. Frames come out as float32 RGB in [0, 1].
"""

from __future__ import annotations

import abc
import os
import time
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import cv2
import numpy as np

from ..errors import VoodooError
from .images import to_float_rgb

VIDEO_SUFFIXES = {".mp4", ".avi", ".mov", ".mkv", ".webm", ".m4v", ".mpg", ".mpeg", ".ogv"}
IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".exr", ".webp"}


def quiet_opencv() -> None:
    """Silence OpenCV's and FFmpeg's own messages (for the command line).

    They print for unreadable files and absent cameras; the command line reports those as one
    line of its own.
    """
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    cv2.setLogLevel(0)


@dataclass(frozen=True)
class Frame:
    """One frame.

    Attributes
    ----------
    pixels : (H, W, 3) uint8 or float32
        RGB as decoded: 8-bit for videos and cameras (what the tracker takes directly),
        float in [0, 1] for high-bit-depth pictures.
    index : int
        0-based position in the source.
    time : float
        Seconds since the source started (file: index / fps; camera: wall clock).
    """

    pixels: np.ndarray
    index: int
    time: float

    @cached_property
    def image(self) -> np.ndarray:
        """(H, W, 3) float32 RGB in [0, 1] (converted on first use)."""
        return to_float_rgb(self.pixels)


class FrameSource(abc.ABC):
    """Where frames come from. Iterating yields :class:`Frame` until the source ends."""

    #: Frames per second (the file's rate, or the camera's nominal rate).
    fps: float = 30.0
    #: (width, height) in pixels.
    size: tuple = (0, 0)
    #: Number of frames, or None for a live source.
    count: int | None = None
    #: True for cameras.
    live: bool = False

    @abc.abstractmethod
    def read(self) -> Frame | None:
        """The next frame, or None at the end."""

    def seek(self, index: int) -> None:
        """Make :meth:`read` return frame ``index`` next (files only)."""
        raise VoodooError("A live camera cannot seek.")

    def read_at(self, index: int) -> Frame:
        """Frame ``index``; raises VoodooError when it does not exist."""
        self.seek(index)
        frame = self.read()
        if frame is None:
            raise VoodooError(f"Frame {index} is past the end of the source.")
        return frame

    def close(self) -> None:  # noqa: B027 - optional hook
        """Release the file or device."""

    def __iter__(self):
        while (frame := self.read()) is not None:
            yield frame

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class CaptureSource(FrameSource):
    """A video file or a camera through ``cv2.VideoCapture``.

    Parameters
    ----------
    target : str or int
        A file path, or a camera index.
    """

    def __init__(self, target):
        self.live = isinstance(target, int)
        self._target = target
        cap = cv2.VideoCapture(target)
        if not cap.isOpened():
            cap.release()
            if self.live:
                raise VoodooError(
                    f"No camera at index {target}: plug one in, close other programs that use "
                    "it, or pick another index."
                )
            raise VoodooError(f"Cannot open {target} as a video (unknown format or codec).")
        self._cap = cap
        ok, first = cap.read()
        if not ok or first is None:
            cap.release()
            what = f"camera {target}" if self.live else str(target)
            raise VoodooError(f"{what} gave no picture; check the device or the file.")
        self._pending = first
        self.size = (first.shape[1], first.shape[0])
        fps = cap.get(cv2.CAP_PROP_FPS)
        self.fps = float(fps) if fps and np.isfinite(fps) and fps > 0 else 30.0
        n = int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) if not self.live else 0
        self.count = n if n > 0 else (None if self.live else self._count_frames())
        self._index = 0
        self._t0 = time.monotonic()

    def _count_frames(self) -> int:
        probe = cv2.VideoCapture(self._target)
        n = 0
        while probe.grab():
            n += 1
        probe.release()
        return n

    def read(self) -> Frame | None:
        if self._pending is not None:
            img, self._pending = self._pending, None
        else:
            ok, img = self._cap.read()
            if not ok or img is None:
                return None
        i = self._index
        self._index += 1
        t = time.monotonic() - self._t0 if self.live else i / self.fps
        return Frame(_rgb8(img), i, t)

    def seek(self, index: int) -> None:
        if self.live:
            super().seek(index)
        if index < 0 or (self.count is not None and index >= self.count):
            raise VoodooError(f"Frame {index} is outside the clip (0..{(self.count or 1) - 1}).")
        if index == self._index:
            return  # already next (possibly the frame read ahead at opening)
        self._pending = None
        self._cap.set(cv2.CAP_PROP_POS_FRAMES, index)
        self._index = index

    def close(self) -> None:
        self._cap.release()


class ImageFolderSource(FrameSource):
    """A folder of numbered pictures, read in name order."""

    def __init__(self, folder):
        folder = Path(folder)
        self._files = sorted(p for p in folder.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
        if not self._files:
            raise VoodooError(f"{folder} holds no pictures (PNG, JPEG, TIFF, ...).")
        first = self._load(0)
        self.size = (first.shape[1], first.shape[0])
        self.count = len(self._files)
        self.fps = 30.0
        self._index = 0

    def _load(self, i: int) -> np.ndarray:
        img = cv2.imread(str(self._files[i]), cv2.IMREAD_UNCHANGED)
        if img is None:
            raise VoodooError(f"{self._files[i]} is not a readable picture.")
        if img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] == 3:
            return _rgb8(img)
        return to_float_rgb(img, bgr=img.ndim == 3)

    def read(self) -> Frame | None:
        if self._index >= len(self._files):
            return None
        img = self._load(self._index)
        if (img.shape[1], img.shape[0]) != self.size:
            raise VoodooError(
                f"{self._files[self._index]} has a different size from the first picture."
            )
        frame = Frame(img, self._index, self._index / self.fps)
        self._index += 1
        return frame

    def seek(self, index: int) -> None:
        if not 0 <= index < len(self._files):
            raise VoodooError(f"Frame {index} is outside the sequence (0..{len(self._files) - 1}).")
        self._index = index


class ArraySource(FrameSource):
    """Frames already in memory (tests, generated takes)."""

    def __init__(self, frames, fps: float = 30.0):
        self._frames = list(frames)
        if not self._frames:
            raise VoodooError("No frames given.")
        self.size = (self._frames[0].shape[1], self._frames[0].shape[0])
        self.count = len(self._frames)
        self.fps = fps
        self._index = 0

    def read(self) -> Frame | None:
        if self._index >= len(self._frames):
            return None
        i = self._index
        self._index += 1
        img = self._frames[i]
        if not (img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] == 3):
            img = to_float_rgb(img)
        return Frame(img, i, i / self.fps)

    def seek(self, index: int) -> None:
        if not 0 <= index < len(self._frames):
            raise VoodooError(f"Frame {index} is outside the take (0..{len(self._frames) - 1}).")
        self._index = index


def _rgb8(bgr: np.ndarray) -> np.ndarray:
    """OpenCV's 8-bit BGR(A) or grey as 8-bit RGB (H, W, 3)."""
    if bgr.dtype != np.uint8:
        return to_float_rgb(bgr, bgr=bgr.ndim == 3)
    if bgr.ndim == 2:
        return cv2.cvtColor(bgr, cv2.COLOR_GRAY2RGB)
    code = cv2.COLOR_BGRA2RGB if bgr.shape[2] == 4 else cv2.COLOR_BGR2RGB
    return cv2.cvtColor(bgr, code)


def open_source(spec) -> FrameSource:
    """Open a frame source.

    Parameters
    ----------
    spec : str, Path or int
        A camera index (``0``, ``"0"`` or ``"camera:0"``), a folder of pictures, or a video
        file.

    Raises
    ------
    VoodooError
        When the camera is not there or the file is missing or unreadable.
    """
    if isinstance(spec, int):
        return CaptureSource(spec)
    text = str(spec)
    if text.startswith("camera:"):
        text = text[len("camera:") :]
        if not text.isdigit():
            raise VoodooError(f"{spec!r}: a camera is named camera:N with N a device number.")
        return CaptureSource(int(text))
    if text.isdigit() and not Path(text).exists():
        return CaptureSource(int(text))
    path = Path(text)
    if path.is_dir():
        return ImageFolderSource(path)
    if not path.exists():
        raise VoodooError(f"{path} does not exist.")
    return CaptureSource(str(path))


def read_image(path) -> np.ndarray:
    """Read a picture file, or the first frame of a video file.

    Returns
    -------
    (H, W, 3) float32 RGB in [0, 1]

    Raises
    ------
    VoodooError
        If the file is missing or cannot be decoded.
    """
    path = Path(path)
    if not path.exists():
        raise VoodooError(f"{path} does not exist.")
    if path.suffix.lower() in VIDEO_SUFFIXES:
        with open_source(path) as src:
            frame = src.read()
            if frame is None:
                raise VoodooError(f"{path} holds no readable frame.")
            return frame.image
    img = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if img is None:
        raise VoodooError(f"{path} is not a picture OpenCV can read (PNG, JPEG, TIFF, ...).")
    return to_float_rgb(img, bgr=img.ndim == 3)
