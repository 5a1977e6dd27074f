"""The benchmark, ``python -m voodoo_addon bench``: every measurement, and BENCHMARKS.md.

Parts (``--only`` picks some):

``speed``
    Synthetic takes and the sample take, frames per second and node error against the
    truth, with KLT beside it (:mod:`.bench`).
``clips``
    Real footage and Blender renders tracked side by side with KLT and DIS on the mesh
    nodes: texture consistency (mean, 10th percentile), folded and lost frames, node error
    where the renderer gave the truth, and ours over the better of the two (:mod:`.clips`).
``live``
    Per-frame time (median, p95) of the tracker with every robust stage on, on the real
    footage and the hard clips, beside KLT's on the same frames (:mod:`.livespeed`).
``dolls``
    Several dolls in one take (``samples/multi``): each doll's accuracy beside KLT and DIS,
    and the time per frame of the dolls together against each alone (:mod:`.dolls`).
``folds``
    Renders of folds and turns (``samples/folds``, and the held-out ``samples/heldout_folds``):
    a doll partly hidden by itself, judged on the part in view beside KLT and DIS -- node
    error of the seen nodes, folded frames, frames lost while a third is in view, frames to
    sub-pixel after the hidden part is back (:mod:`.folds`).
``osc``
    Latency of the OSC stream on loopback, from a frame being there to its bundle received
    (:mod:`.osclatency`).
``calibration``
    Confidence against true node error on the renders (:mod:`.calibration`).
``hd``
    A 1920x1080 H.264 clip through ``python -m voodoo_addon track``, end to end (:mod:`.hd`).

Everything but ``hd`` runs in a child process with one BLAS/OpenMP thread and one OpenCV
thread, so the figures do not depend on how busy the other cores are; ``hd`` runs the
command as a user would. ``--write BENCHMARKS.md`` puts each part's table between its
``<!-- bench:NAME -->`` and ``<!-- /bench:NAME -->`` lines, with the machine and the date.
"""

from __future__ import annotations

import datetime
import json
import os
import re
import subprocess
import sys
from pathlib import Path

PARTS = ("speed", "live", "dolls", "folds", "osc", "clips", "calibration", "hd")
THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")


def measure(parts, quick: bool = False) -> dict:
    """Run the parts in this process (the caller sets the threads); the report dict."""
    from .bench import machine, run_speed

    report: dict = {"machine": machine(), "date": datetime.date.today().isoformat()}
    if "speed" in parts:
        report["speed"] = run_speed(quick)
    if "live" in parts:
        from .livespeed import run_live

        report["live"] = [{k: v for k, v in r.items() if k != "times_ms"} for r in run_live()]
    if "dolls" in parts:
        from .dolls import run_dolls

        report["dolls"] = run_dolls()
    if "folds" in parts:
        from .folds import run_folds

        report["folds"] = run_folds()
    if "osc" in parts:
        from .osclatency import run_osc_latency

        report["osc"] = run_osc_latency()
    if "clips" in parts:
        from .clips import clip_suite, ratios, run_clip

        rows = []
        for clip in clip_suite():
            rows += [
                {k: v for k, v in r.items() if not isinstance(v, list)} for r in run_clip(clip)
            ]
        report["clips"] = {"rows": rows, "ratios": ratios(rows)}
    if "calibration" in parts:
        from .calibration import calibration_table

        report["calibration"] = calibration_table()
    return report


def run(parts=PARTS, quick: bool = False) -> dict:
    """Every part: the single-threaded ones in a child process, then ``hd``."""
    parts = tuple(parts)
    inner = [p for p in parts if p != "hd"]
    report: dict = {}
    if inner:
        env = dict(os.environ, **{v: "1" for v in THREAD_VARS})
        cmd = [sys.executable, "-c", _CHILD, ",".join(inner), "1" if quick else "0"]
        root = Path(__file__).resolve().parents[2]
        out = subprocess.run(cmd, env=env, cwd=root, capture_output=True, text=True, check=False)
        if out.returncode != 0:
            tail = out.stderr.strip().splitlines()[-1:] or ["the benchmark failed"]
            raise RuntimeError(tail[0])
        report = json.loads(out.stdout.strip().splitlines()[-1])
    if "hd" in parts and not quick:
        from .bench import machine
        from .hd import run_hd

        report.setdefault("machine", machine())
        report.setdefault("date", datetime.date.today().isoformat())
        report["hd"] = run_hd()
    return report


_CHILD = """
import json, sys
import cv2
cv2.setNumThreads(1)
from voodoo_addon.devtools.report import measure
print(json.dumps(measure(sys.argv[1].split(","), sys.argv[2] == "1")))
"""


def sections(report: dict) -> dict:
    """Markdown of every part in the report, by part name."""
    from .bench import format_speed

    head = f"Measured {report.get('date', '')} on {report.get('machine', '?')}."
    # How the tracker's own timings ran (see ``Tracker._follow_ahead``).
    one = (
        "One thread for the arithmetic (BLAS, OpenCV, Numba); after a poor frame the tracker"
        " follows the next frame's points on a helper thread."
    )
    out = {}
    if "speed" in report:
        out["speed"] = (
            f"{head} {one}\n\n```sh\npython -m voodoo_addon bench --only speed\n```\n\n"
            + format_speed(report["speed"])
        )
    if "live" in report:
        from .livespeed import format_live

        out["live"] = (
            f"{head} {one}\n\n```sh\npython -m voodoo_addon bench --only live\n```\n\n"
            + format_live(report["live"])
        )
    if "dolls" in report:
        from .dolls import format_dolls

        out["dolls"] = (
            f"{head} {one}\n\n```sh\npython -m voodoo_addon bench --only dolls\n```\n\n"
            + format_dolls(report["dolls"])
        )
    if "folds" in report:
        from .folds import format_folds

        out["folds"] = (
            f"{head} {one}\n\n```sh\npython -m voodoo_addon bench --only folds\n```\n\n"
            + format_folds(report["folds"])
        )
    if "osc" in report:
        from .osclatency import format_osc

        out["osc"] = (
            f"{head} One thread for tracking, the receiver on another.\n\n```sh\n"
            "python -m voodoo_addon bench --only osc\n```\n\n" + format_osc(report["osc"])
        )
    if "clips" in report:
        from .clips import format_rows

        out["clips"] = (
            f"{head} {one}\n\n```sh\npython -m voodoo_addon bench --only clips\n```\n\n"
            + format_rows(report["clips"]["rows"])
        )
    if "calibration" in report:
        from .calibration import format_table

        out["calibration"] = (
            f"{head}\n\n```sh\npython -m voodoo_addon bench --only calibration\n```\n\n"
            + format_table(report["calibration"])
        )
    if "hd" in report:
        hd = report["hd"]
        out["hd"] = (
            f"{head} Default threads, as a user runs it.\n\n```sh\n"
            f"python -m voodoo_addon bench --only hd   # runs: {hd['command']}\n```\n\n"
            "| clip | frames | wall time | frames per second, end to end |\n"
            "|---|---|---|---|\n"
            f"| {hd['clip']} | {hd['frames']} | {hd['wall_s']:.2f} s | "
            f"{hd['fps_end_to_end']:.1f} |"
        )
    return out


def write(path, report: dict) -> list[str]:
    """Replace the marked sections of ``path`` with the report's; returns the parts written.

    A part whose markers are missing is appended at the end under its own heading.
    """
    path = Path(path)
    text = path.read_text() if path.exists() else "# Benchmarks\n"
    done = []
    for name, body in sections(report).items():
        block = f"<!-- bench:{name} -->\n{body}\n<!-- /bench:{name} -->"
        pattern = re.compile(rf"<!-- bench:{name} -->.*?<!-- /bench:{name} -->", re.S)
        if pattern.search(text):
            text = pattern.sub(lambda _m, block=block: block, text)
        else:
            text = text.rstrip() + f"\n\n## {name}\n\n{block}\n"
        done.append(name)
    path.write_text(text)
    return done


def print_report(report: dict) -> None:
    for name, body in sections(report).items():
        print(f"## {name}\n\n{body}\n")
