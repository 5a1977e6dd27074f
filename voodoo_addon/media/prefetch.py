"""Reading frames on the second core while the first one tracks.

Decoding a video frame and converting it from OpenCV's BGR costs a few milliseconds at
640x480 and tens at 1080p: as much as tracking it. :class:`Prefetcher` reads another source
on a thread of its own -- OpenCV's decoder and colour conversion release the GIL, so it runs
beside the tracker -- and hands the frames over in order through a queue.

- A file is read ahead by a few frames (``depth``), so memory stays bounded.
- A camera is read as fast as it delivers, into a queue without a bound: a frame the
  tracker has not reached yet waits for it, and none is ever dropped (a webcam's driver
  drops what is not read in time). The caller sees how far behind it is (:attr:`backlog`)
  and when each frame arrived (:attr:`arrived`), for the latency.
"""

from __future__ import annotations

import queue
import threading
import time
from collections.abc import Callable

from ..errors import VoodooError
from .sources import Frame, FrameSource

#: Frames a file is read ahead by default.
DEPTH = 8
#: Returned by :meth:`Prefetcher.read` with ``wait=False`` when no frame has arrived yet.
PENDING = object()
_END = object()


class Prefetcher(FrameSource):
    """Another source, read ahead on a thread; a :class:`FrameSource` itself.

    Parameters
    ----------
    source : FrameSource
        Read from its current position; the prefetcher does not close it.
    depth : int or None
        Frames read ahead at most; None reads without a bound (a camera: no frame dropped).
        Default: :data:`DEPTH` for a file, no bound for a live source.
    limit : int, optional
        Stop reading after this many frames.
    on_frame : callable, optional
        Called on the reading thread with each :class:`Frame` as it arrives, before it is
        queued (e.g. to write the footage of a camera take).
    """

    def __init__(
        self,
        source: FrameSource,
        depth: int | None | str = "auto",
        limit: int | None = None,
        on_frame: Callable[[Frame], None] | None = None,
    ):
        self.source = source
        self.fps, self.size, self.count, self.live = (
            source.fps,
            source.size,
            source.count,
            source.live,
        )
        if depth == "auto":
            depth = None if source.live else DEPTH
        self._queue: queue.Queue = queue.Queue(maxsize=depth or 0)
        self._limit = limit
        self._on_frame = on_frame
        self._stop = threading.Event()  # read no further
        self._closed = threading.Event()  # nobody takes frames any more
        self._error: BaseException | None = None
        self._done = False
        self.delivered = 0  # frames read from the source
        self.taken = 0  # frames handed to the consumer
        #: ``time.monotonic()`` when the frame last returned by :meth:`read` arrived.
        self.arrived: float | None = None
        self._thread = threading.Thread(target=self._run, name="voodoo-frames", daemon=True)
        self._thread.start()

    # ------------------------------------------------------------------ reading thread

    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                if self._limit is not None and self.delivered >= self._limit:
                    break
                frame = self.source.read()
                if frame is None:
                    break
                arrived = time.monotonic()
                if self._on_frame is not None:
                    self._on_frame(frame)
                self.delivered += 1
                if not self._put((frame, arrived)):
                    return
        except BaseException as exc:  # handed to the consumer by read()
            self._error = exc
        self._put(_END)

    def _put(self, item) -> bool:
        """Queue ``item``, waiting while the queue is full; False once closed."""
        while True:
            try:
                self._queue.put(item, timeout=0.05)
                return True
            except queue.Full:
                if self._closed.is_set():
                    return False

    # ------------------------------------------------------------------ consumer

    def read(self, wait: bool = True):
        """The next frame in order; None when the source has ended (or was stopped).

        With ``wait=False``, :data:`PENDING` when the next frame has not arrived yet.

        Raises
        ------
        VoodooError
            When reading the source failed (the frames before it were delivered).
        """
        if self._done:
            return None
        try:
            item = self._queue.get(block=wait)
        except queue.Empty:
            return PENDING
        if item is _END:
            self._done = True
            self._thread.join()  # its last act was queuing the end: once read, it is over
            if self._error is not None:
                err = self._error
                if isinstance(err, VoodooError):
                    raise err
                raise VoodooError(f"Reading the frames failed: {err}") from err
            return None
        frame, self.arrived = item
        self.taken += 1
        return frame

    @property
    def backlog(self) -> int:
        """Frames read but not yet taken."""
        return self.delivered - self.taken

    @property
    def reading(self) -> bool:
        """The reading thread is still going (the source has not ended nor been stopped)."""
        return self._thread.is_alive()

    def stop_reading(self) -> None:
        """Read no further frame; the ones already read can still be taken."""
        self._stop.set()

    def seek(self, index: int) -> None:
        raise VoodooError("A source being read ahead cannot seek; seek before reading it.")

    def close(self) -> None:
        """Stop the reading thread and drop what it had read ahead."""
        self._stop.set()
        self._closed.set()
        while self._thread.is_alive():
            try:
                while True:
                    self._queue.get_nowait()
            except queue.Empty:
                pass
            self._thread.join(timeout=0.05)
        self._done = True
