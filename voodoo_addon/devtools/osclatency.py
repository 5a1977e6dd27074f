"""Latency of the OSC stream on loopback: from a frame being there to its bundle received.

Part ``osc`` of the benchmark. ``voodoo live``'s loop (:func:`voodoo_addon.live.run_live`)
tracks the sample take at the clip's own pace, as a camera would deliver it, and streams every
frame to a UDP receiver on 127.0.0.1 in the same process; the receiver notes when each frame's
bundle arrives. The latency of a frame is that moment less the one the frame was there (due at
the clip's pace, or read, whichever is later): reading is done, tracking and sending are in.
"""

from __future__ import annotations

import socket
import threading
import time
from pathlib import Path

import numpy as np
from pythonosc.osc_bundle import OscBundle

from ..blob.build import build_blob
from ..blob.outline import load_contour_json
from ..live import LiveStats, run_live
from ..media.sources import open_source
from ..stream import OscSender
from ..tracking.troupe import Troupe

SAMPLES = Path(__file__).resolve().parents[2] / "samples"


def _receive(sock: socket.socket, arrivals: dict, stop: threading.Event) -> None:
    while not stop.is_set():
        try:
            dgram = sock.recv(65536)
        except TimeoutError:
            continue
        now = time.monotonic()
        first = next(iter(OscBundle(dgram)))  # /voodoo/<doll>/frame: index, time
        arrivals[int(first.params[0])] = now


def run_osc_latency(video: Path = SAMPLES / "sample_take.mp4") -> dict:
    """Median and p95 latency (ms) of every frame of the sample take, and what arrived."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    sock.settimeout(0.1)
    arrivals: dict = {}
    stop = threading.Event()
    thread = threading.Thread(target=_receive, args=(sock, arrivals, stop), daemon=True)
    thread.start()
    stats = LiveStats()
    try:
        with open_source(video) as src:
            blob = build_blob(src.read().image, load_contour_json(video.with_suffix(".json")))
            src.seek(0)
            troupe = Troupe({"doll": blob})
            with OscSender(f"127.0.0.1:{sock.getsockname()[1]}") as sender:
                run_live(src, troupe, sender, paced=True, stats=stats)
                fps = src.fps
        time.sleep(0.2)
    finally:
        stop.set()
        thread.join()
        sock.close()
    index = [i for i, _, _ in stats.results]
    got = [
        arrivals[i] - ready for i, ready in zip(index, stats.ready, strict=True) if i in arrivals
    ]
    ms = 1000.0 * np.array(got)
    return {
        "clip": video.name,
        "frames": len(index),
        "received": len(got),
        "in_order": sorted(arrivals, key=arrivals.get) == sorted(arrivals),
        "fps": round(float(fps), 2),
        "median_ms": round(float(np.median(ms)), 2) if len(ms) else None,
        "p95_ms": round(float(np.percentile(ms, 95)), 2) if len(ms) else None,
    }


def format_osc(row: dict) -> str:
    return (
        "| clip | frames sent | received | in order | clip fps | latency median | p95 |\n"
        "|---|---|---|---|---|---|---|\n"
        f"| {row['clip']} | {row['frames']} | {row['received']} | "
        f"{'yes' if row['in_order'] else 'no'} | {row['fps']:.0f} | {row['median_ms']:.1f} ms | "
        f"{row['p95_ms']:.1f} ms |"
    )
