"""Frames read ahead on a second thread: in order, none dropped, errors and stops handled."""

import threading
import time

import numpy as np
import pytest

from voodoo_addon.errors import VoodooError
from voodoo_addon.media.prefetch import DEPTH, PENDING, Prefetcher
from voodoo_addon.media.sources import ArraySource, Frame


def frames(n, size=(8, 6)):
    return [np.full((size[1], size[0], 3), i % 256, np.uint8) for i in range(n)]


class Camera(ArraySource):
    """A live source that delivers a frame every ``period`` seconds."""

    live = True

    def __init__(self, pictures, period=0.0, fail_at=None):
        super().__init__(pictures, fps=30.0)
        self.period, self.fail_at = period, fail_at

    def read(self):
        if self.fail_at is not None and self._index == self.fail_at:
            raise OSError("the device went away")
        time.sleep(self.period)
        return super().read()


def test_every_frame_arrives_in_order():
    src = ArraySource(frames(30))
    with Prefetcher(src) as ahead:
        got = [(f.index, int(f.pixels[0, 0, 0])) for f in ahead]
    assert got == [(i, i) for i in range(30)]


def test_a_file_is_read_ahead_by_a_bounded_number_of_frames():
    src = ArraySource(frames(50))
    with Prefetcher(src) as ahead:
        time.sleep(0.2)
        # the queue, and the frame the reading thread holds until there is room
        assert ahead.backlog == ahead.delivered == DEPTH + 1
        assert [f.index for f in ahead] == list(range(50))


def test_limit_stops_reading():
    src = ArraySource(frames(20))
    with Prefetcher(src, limit=5) as ahead:
        assert [f.index for f in ahead] == [0, 1, 2, 3, 4]
    assert src._index == 5


def test_a_camera_faster_than_its_reader_loses_no_frame():
    cam = Camera(frames(40), period=0.001)
    seen_by_writer = []
    with Prefetcher(cam, on_frame=lambda f: seen_by_writer.append(f.index)) as ahead:
        got, most_behind = [], 0
        while (frame := ahead.read()) is not None:
            time.sleep(0.01)  # a slow tracker
            most_behind = max(most_behind, ahead.backlog)
            got.append(frame.index)
            assert ahead.arrived <= time.monotonic()
    assert got == list(range(40)) == seen_by_writer
    assert most_behind > 10  # it really fell behind, and still got every frame


def test_not_waiting_says_pending_until_a_frame_arrives():
    cam = Camera(frames(2), period=0.3)
    with Prefetcher(cam) as ahead:
        assert ahead.read(wait=False) is PENDING
        assert isinstance(ahead.read(), Frame)


def test_a_failing_source_delivers_what_came_before_then_says_why():
    cam = Camera(frames(10), fail_at=4)
    with Prefetcher(cam) as ahead:
        got = [ahead.read().index for _ in range(4)]
        with pytest.raises(VoodooError, match="device went away"):
            ahead.read()
        assert ahead.read() is None
    assert got == [0, 1, 2, 3]


def test_stop_reading_keeps_what_was_read_and_ends():
    cam = Camera(frames(1000), period=0.001)
    ahead = Prefetcher(cam)
    time.sleep(0.05)
    ahead.stop_reading()
    rest = list(ahead)
    assert 0 < len(rest) < 1000 and [f.index for f in rest] == list(range(len(rest)))
    assert not ahead.reading
    ahead.close()


def test_close_ends_the_thread_even_when_nobody_reads():
    ahead = Prefetcher(ArraySource(frames(100)))
    time.sleep(0.05)
    ahead.close()
    assert not ahead.reading
    assert "voodoo-frames" not in [t.name for t in threading.enumerate()]


def test_a_prefetched_source_cannot_seek():
    with Prefetcher(ArraySource(frames(3))) as ahead, pytest.raises(VoodooError):
        ahead.seek(0)
