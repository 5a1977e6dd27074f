"""Keeping a camera's frames: every frame read, written to a video file as it comes.

A camera's past frames are gone once read. A take tracked both ways reads its frames again,
backwards (:mod:`..takes.both_ways`), so a camera's take keeps them as *footage*: Motion
JPEG in an AVI file, every frame on its own (a seek lands on any frame exactly), written
on the reading thread (:class:`~.prefetch.Prefetcher`'s ``on_frame``) however far behind
the tracker falls. Blender's recorder and ``voodoo live --footage`` both use it.
"""

from __future__ import annotations

from pathlib import Path

import cv2

from ..errors import VoodooError
from .images import to_uint8_bgr
from .sources import Frame


class Footage:
    """A video file being written, frame by frame (a context manager).

    Parameters
    ----------
    path : str or Path
        The file to write (``.avi``); its folder is made if need be.
    fps : float
        The frame rate written into the file.
    size : (int, int)
        Width and height of every frame.

    Raises
    ------
    VoodooError
        When the file cannot be written.
    """

    def __init__(self, path, fps: float, size: tuple[int, int]):
        self.path = Path(path)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise VoodooError(f"Cannot make the folder for the footage {self.path}: {exc}") from exc
        fourcc = cv2.VideoWriter_fourcc(*"MJPG")
        self._writer = cv2.VideoWriter(str(self.path), fourcc, float(fps), tuple(size))
        if not self._writer.isOpened():
            self._writer.release()
            raise VoodooError(f"Cannot write the footage {self.path} (check the folder).")
        #: Frames written so far.
        self.frames = 0

    def write(self, frame: Frame) -> None:
        """Append one frame (a source's :class:`~.sources.Frame`); nothing once closed."""
        if self._writer is None:
            return
        self._writer.write(to_uint8_bgr(frame.pixels))
        self.frames += 1

    def close(self) -> None:
        """Finish the file (it can be read from then on); closing again does nothing."""
        if self._writer is not None:
            self._writer.release()
            self._writer = None

    def __enter__(self) -> Footage:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
