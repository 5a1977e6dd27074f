"""Tracking live without Blender: the doll as a game controller (``voodoo live``).

:func:`run_live` reads a source on a second thread (:mod:`.media.prefetch`), tracks every
frame in order, streams each result over OSC (:mod:`.stream`) as soon as it is tracked, and
measures the rate and the latency -- from the moment a frame is there (read from a camera,
or due at a file's own pace) to the moment its result is sent.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .media.prefetch import Prefetcher
from .media.sources import Frame, FrameSource
from .stream import OscSender, view_share
from .takes.rig import unit
from .takes.take import Take
from .tracking import Tracker, TrackResult
from .tracking.troupe import Troupe


@dataclass
class LiveStats:
    """What a live run did.

    Attributes
    ----------
    results : list of (frame index, time, dict of str to TrackResult)
        Every tracked frame, in order: each doll's result by name.
    latencies : list of float
        Seconds from each frame being there to its result being sent.
    ready : list of float
        ``time.monotonic()`` when each frame was there.
    seconds : float
        Wall time from the first frame to the last result.
    """

    results: list = field(default_factory=list)
    latencies: list = field(default_factory=list)
    ready: list = field(default_factory=list)
    seconds: float = 0.0

    @property
    def frames(self) -> int:
        return len(self.results)

    @property
    def rate(self) -> float:
        """Frames tracked per second."""
        return self.frames / self.seconds if self.seconds > 0 else 0.0

    def latency(self, q: float = 50) -> float:
        """A percentile of the latency, seconds (0 before any frame)."""
        return float(np.percentile(self.latencies, q)) if self.latencies else 0.0

    def line(self) -> str:
        """One line for a person: frames, rate, latency."""
        return (
            f"{self.frames} frames, {self.rate:.1f} fps, latency {1000 * self.latency():.0f} ms "
            f"(p95 {1000 * self.latency(95):.0f} ms)"
        )

    def takes(self, troupe: Troupe, fps: float) -> dict:
        """Each doll's take (a :class:`~.takes.take.Take` by name) of the tracked frames."""
        idx, times, results = zip(*self.results, strict=True)
        return {
            n: Take.from_results(
                [r[n] for r in results],
                troupe.blobs[n].triangles,
                troupe.trackers[n].parameter_names,
                idx,
                times,
                fps,
            )
            for n in troupe.names
        }


def mode_values(tracker: Tracker, params: np.ndarray) -> dict:
    """Each mode's value by its name, from a parameter vector.

    The shape-key value a character would get: the amplitude in units of
    :func:`~.takes.rig.unit`.
    """
    lay = tracker.layout
    values = params[lay.modes] / unit(tracker.blob)
    return dict(zip(lay.names[lay.modes], values.tolist(), strict=True))


def run_live(
    source: FrameSource,
    troupe: Troupe,
    sender: OscSender | None = None,
    paced: bool = True,
    limit: int | None = None,
    stats: LiveStats | None = None,
    every_second: Callable[[LiveStats], None] | None = None,
    on_frame: Callable[[Frame], None] | None = None,
) -> LiveStats:
    """Track ``source`` frame by frame, streaming each doll's result.

    Parameters
    ----------
    source : FrameSource
        A camera (taken at its own pace) or a file (at its frame rate when ``paced``, else
        as fast as it can be tracked).
    troupe : Troupe
        The dolls (one or several); their names are the ones in the OSC addresses.
    sender : OscSender, optional
        Where each frame goes, one bundle per doll (nowhere by default: tracking and
        measuring only).
    limit : int, optional
        Frames at most.
    stats : LiveStats, optional
        Filled in as frames are tracked (so that a caller interrupted by Ctrl-C keeps what
        was tracked); a new one by default.
    every_second : callable, optional
        Called with the stats about once a second.
    on_frame : callable, optional
        Called with every frame as it is read, on the reading thread (a camera's footage
        written as it comes, :class:`~.media.footage.Footage`).
    """
    stats = stats if stats is not None else LiveStats()
    pace = paced and not source.live
    with Prefetcher(source, limit=limit, on_frame=on_frame) as feed:
        start = last_report = None
        while (frame := feed.read()) is not None:
            now = time.monotonic()
            if start is None:
                start = last_report = now - (frame.time if pace else 0.0)
            ready = feed.arrived
            if pace:  # a file at its own pace: the frame is there at its time
                due = start + frame.time
                if due > now:
                    time.sleep(due - now)
                ready = max(ready, due)
            results: dict[str, TrackResult] = troupe.track(frame.pixels)
            if sender is not None:
                for doll, res in results.items():
                    sender.send(
                        doll,
                        frame.index,
                        frame.time,
                        res.params[:4],
                        mode_values(troupe.trackers[doll], res.params),
                        res.confidence,
                        res.lost,
                        view_share(res),
                    )
            done = time.monotonic()
            stats.results.append((frame.index, frame.time, results))
            stats.latencies.append(done - ready)
            stats.ready.append(ready)
            stats.seconds = done - start
            if every_second is not None and done - last_report >= 1.0:
                last_report = done
                every_second(stats)
    return stats
