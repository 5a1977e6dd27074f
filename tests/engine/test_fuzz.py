"""Fuzzing: random and hostile outlines, settings and files at the engine and the command line.

Whatever comes in, the engine either answers (with no NaN or infinity in what it returns) or
raises a VoodooError; the command line exits 0 or 2 with no traceback. No call may take more
than CALL_SECONDS, and nothing may need more than MEMORY bytes (the address-space limit of
the processes doing the work).

The inputs follow a fixed seed, so a failure reproduces; VOODOO_FUZZ_SEED picks other inputs
and VOODOO_FUZZ_SECONDS sets the time of the quick run (per part). A failure names the seed
and the case: ``VOODOO_FUZZ_SEED=s python tests/engine/test_fuzz.py engine s 60`` replays it.
``make fuzz`` runs both parts for four minutes each.

This file is also the engine worker: the test runs it in a subprocess, under the memory limit.
"""

from __future__ import annotations

import io
import json
import os
import resource
import signal
import subprocess
import sys
import time
import traceback
from pathlib import Path

import numpy as np
import pytest

SEED = int(os.environ.get("VOODOO_FUZZ_SEED", "20250110"))
QUICK_SECONDS = float(os.environ.get("VOODOO_FUZZ_SECONDS", "15"))
CALL_SECONDS = 10
MEMORY = 2 << 30
REPO = Path(__file__).resolve().parents[2]
#: Single-threaded maths in the workers: thread pools reserve address space, not memory.
ENV = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
W, H = 160, 120

# ------------------------------------------------------------------------- hostile inputs

NUMBERS = [np.nan, np.inf, -np.inf, 0.0, -1.0, 1e-300, 1e300, 2.5, 1e9, -1e9]


def hostile_number(rng, typical: float, bad: float = 0.5):
    """Usually a sensible value near ``typical``; with probability ``bad``, maybe not."""
    if rng.random() >= bad:
        return float(typical * rng.uniform(0.3, 3.0))
    pick = rng.integers(len(NUMBERS) + 2)
    if pick == len(NUMBERS):
        return int(rng.integers(-5, 50))
    return "text" if pick > len(NUMBERS) else NUMBERS[pick]


def wobbly(rng, n: int) -> np.ndarray:
    t = np.sort(rng.uniform(0, 2 * np.pi, n)) if rng.random() < 0.3 else np.linspace(0, 6.28, n)
    r = 40 * (1 + 0.2 * np.sin(rng.integers(1, 9) * t)) + rng.normal(0, 0.5, n)
    return np.column_stack([W / 2 + r * np.cos(t), H / 2 + 0.8 * r * np.sin(t)])


def hostile_outline(rng):
    """An outline: usually plausible, often broken in one of many ways."""
    kind = int(rng.integers(14))
    n = int(rng.integers(3, 40))
    if kind == 0:
        return rng.uniform(0, [W, H], size=(int(rng.integers(0, 4)), 2))  # 0-3 points
    if kind == 1:
        return rng.uniform(0, [W, H], size=(n, 2))  # random: crosses itself
    if kind == 2:
        pts = wobbly(rng, n)
        return np.repeat(pts, rng.integers(1, 4, n), axis=0)  # duplicate points
    if kind == 3:
        t = rng.uniform(0, 1, n)
        return np.column_stack([20 + 100 * t, 30 + 50 * t])  # collinear
    if kind == 4:
        return wobbly(rng, n) * 10.0 ** rng.integers(-12, 13)  # huge or tiny
    if kind == 5:
        pts = wobbly(rng, n)
        pts[rng.integers(n), rng.integers(2)] = [np.nan, np.inf, -np.inf][rng.integers(3)]
        return pts
    if kind == 6:
        return wobbly(rng, 10_000)  # dense, valid
    if kind == 7:
        return rng.uniform(0, [W, H], size=(10_000, 2))  # dense, crossing everywhere
    if kind == 8:
        pts = wobbly(rng, 4000)
        i = int(rng.integers(4000))
        pts[i] = pts[(i + 2000) % 4000]  # touches itself
        return pts
    if kind == 9:
        return rng.integers(0, 6, size=(n, 2)).astype(float) * 20  # grid: degenerate
    if kind == 10:
        return [[1, 2, 3], [4, 5], "x"][: int(rng.integers(1, 4))]  # not an array
    if kind == 11:
        return rng.uniform(0, 100, size=(n, int(rng.integers(1, 4)) * 2 - 1))  # wrong width
    if kind == 12:
        return np.column_stack([np.full(n, 80.0), rng.uniform(0, H, n)])  # a vertical line
    return wobbly(rng, n)


def hostile_options(rng) -> dict:
    fields = {
        "n_modes": 12,
        "min_angle": 25.0,
        "max_area": 100.0,
        "simplify_tolerance": 0.75,
        "blur_sigma": 1.2,
        "poisson": 0.3,
        "width_factor": 1.0,
        "poly_degree": 3,
    }
    bad = 0.0 if rng.random() < 0.5 else 0.5
    return {k: hostile_number(rng, v, bad) for k, v in fields.items() if rng.random() < 0.4}


def hostile_tracker_options(rng) -> dict:
    fields = {"sigma": 0.15, "gamma": 1e-5, "max_levels": 3, "max_iterations": 8,
              "lost_below": 0.15, "refine_below": 0.97, "pixel_budget": 20000}  # fmt: skip
    bad = 0.0 if rng.random() < 0.5 else 0.5
    return {k: hostile_number(rng, v, bad) for k, v in fields.items() if rng.random() < 0.3}


def damaged(rng, data: bytes) -> bytes:
    """A file's bytes truncated, flipped, replaced or with one array changed."""
    kind = int(rng.integers(6))
    if kind == 0:
        return data[: int(rng.integers(0, len(data)))]
    if kind == 1:
        raw = bytearray(data)
        for i in rng.integers(0, len(raw), int(rng.integers(1, 20))):
            raw[i] ^= int(rng.integers(1, 256))
        return bytes(raw)
    if kind == 2:
        return rng.bytes(int(rng.integers(0, 5000)))
    with np.load(io.BytesIO(data), allow_pickle=False) as npz:
        arrays = {k: npz[k] for k in npz.files}
    key = sorted(arrays)[int(rng.integers(len(arrays)))]
    a = arrays[key]
    if kind == 3:
        del arrays[key]
    elif kind == 4 and a.dtype.kind == "f" and a.size:
        a = a.copy()
        a.flat[int(rng.integers(a.size))] = [np.nan, np.inf][int(rng.integers(2))]
        arrays[key] = a
    else:
        arrays[key] = (
            [a.astype(np.float64) * 1.5, a.ravel()[:3], np.array("x")][int(rng.integers(3))]
            if a.dtype.kind != "U"
            else np.arange(3)
        )
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def _finite(*arrays) -> bool:
    return all(
        np.isfinite(np.asarray(a, dtype=np.float64)).all()
        for a in arrays
        if np.asarray(a).dtype.kind in "fiu"
    )


# ------------------------------------------------------------------------- engine worker


class _Hang(BaseException):
    """A call ran past CALL_SECONDS (a BaseException: no `except Exception` swallows it)."""


def _on_alarm(signum, frame):
    raise _Hang(f"no answer after {CALL_SECONDS} s")


def _world():
    """A frame, a blob, a take and their files: what the engine cases start from."""
    from voodoo_addon.blob.build import build_blob
    from voodoo_addon.blob.model import blob_to_bytes
    from voodoo_addon.devtools.scenarios import scenario_take
    from voodoo_addon.media.sources import ArraySource
    from voodoo_addon.takes.take import take_to_bytes, track_source

    frames, contour, _ = scenario_take("bend", 3, (W, H), blob_pixels=3000)
    blob = build_blob(frames[0], contour)
    take = track_source(blob, ArraySource(frames))
    return {
        "frames": frames,
        "blob": blob,
        "take": take,
        "blob_bytes": blob_to_bytes(blob),
        "take_bytes": take_to_bytes(take),
    }


def _case_outline(rng, w):
    from voodoo_addon.blob.crossing import first_crossing
    from voodoo_addon.blob.outline import validate_contour

    out = validate_contour(hostile_outline(rng), frame_size=(W, H) if rng.random() < 0.5 else None)
    assert _finite(out) and len(out) >= 3 and first_crossing(out) is None


def _case_build(rng, w):
    from voodoo_addon.blob.build import BlobOptions, build_blob

    pts = hostile_outline(rng)
    blob = build_blob(w["frames"][0], pts, BlobOptions(**hostile_options(rng)))
    assert _finite(*(getattr(blob, k) for k in ("vertices", "modes", "mass", "texture")))
    assert len(set(blob.labels)) == len(blob.labels)


def _case_track(rng, w):
    from voodoo_addon.tracking import Tracker, TrackerOptions

    blob = w["blob"]
    frozen = list(rng.choice(["rotate", "scale", "translate-x", "bogus"], rng.integers(0, 2)))
    tracker = Tracker(blob, options=TrackerOptions(**hostile_tracker_options(rng)), frozen=frozen)
    for _ in range(2):
        kind = int(rng.integers(5))
        frame = w["frames"][int(rng.integers(3))].copy()
        if kind == 1:
            frame = rng.uniform(0, 1, frame.shape).astype(np.float32)
        elif kind == 2:
            frame[rng.integers(H), rng.integers(W)] = np.nan
        elif kind == 3:
            frame = (frame * 255).astype(np.uint8)
        elif kind == 4:
            frame = frame[: H // 2]
        r = tracker.track(frame)
        assert _finite(r.params, r.nodes, r.confidence) and 0 <= r.confidence <= 1


def _case_rig(rng, w):
    from voodoo_addon.takes.rig import Rig
    from voodoo_addon.tracking.params import ParamLayout

    blob, take = w["blob"], w["take"]
    rest = np.column_stack([blob.vertices[:, 0], np.zeros(blob.n_nodes), -blob.vertices[:, 1]])
    layout = ParamLayout.from_names(blob.labels, take.param_names)
    rig = Rig(blob, layout, rest * 0.01, modes=[0, 1, 2])
    gain = hostile_number(rng, 1.0)
    assert _finite(rig.shape(int(rng.integers(3)), gain))
    assert _finite(rig.vertices(take.params[-1], [gain, 1.0, hostile_number(rng, 1.0)]))


def _case_segment(rng, w):
    from voodoo_addon.blob.segment import segment_contour

    if rng.random() < 0.5:
        request = {"point": [hostile_number(rng, 80.0), hostile_number(rng, 60.0)]}
    else:
        request = {"box": [hostile_number(rng, v) for v in (30.0, 20.0, 130.0, 100.0)]}
    assert _finite(segment_contour(w["frames"][0], **request))


def _case_blob_file(rng, w):
    from voodoo_addon.blob.model import blob_from_bytes

    blob = blob_from_bytes(damaged(rng, w["blob_bytes"]))
    assert _finite(blob.vertices, blob.modes, blob.texture)


def _case_take_file(rng, w):
    from voodoo_addon.takes.take import take_from_bytes

    take = take_from_bytes(damaged(rng, w["take_bytes"]))
    assert _finite(take.vertices, take.params, take.confidence, take.times)


def _case_contour_file(rng, w):
    import tempfile

    from voodoo_addon.blob.outline import load_contour_json, validate_contour

    texts = [
        json.dumps({"points": np.asarray(hostile_outline(rng), dtype=object).tolist()}),
        '{"points": [[1, 2], [NaN, 3], [4, Infinity]]}',
        '{"points": [[1e999, 2], [3, 4], [5, 6]]}',
        '{"points": "abc"}',
        "[1, 2, 3]",
        rng.bytes(200).decode("latin-1"),
        '{"points": [[[1]]]}',
    ]
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "c.json"
        path.write_text(texts[int(rng.integers(len(texts)))], encoding="latin-1")
        assert _finite(validate_contour(load_contour_json(path)))


CASES = {
    "outline": (_case_outline, 3),
    "build": (_case_build, 3),
    "track": (_case_track, 2),
    "rig": (_case_rig, 1),
    "segment": (_case_segment, 1),
    "blob-file": (_case_blob_file, 2),
    "take-file": (_case_take_file, 2),
    "contour-file": (_case_contour_file, 1),
}


def engine_fuzz(seed: int, seconds: float) -> dict:
    """Run engine cases for ``seconds``; return the cases run and the failures."""
    from voodoo_addon.errors import VoodooError

    world = _world()
    names = list(CASES)
    weights = np.array([CASES[k][1] for k in names], float)
    signal.signal(signal.SIGALRM, _on_alarm)
    failures, done, outcomes = {}, 0, {}
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        rng = np.random.default_rng([seed, done])
        kind = names[int(rng.choice(len(names), p=weights / weights.sum()))]
        signal.alarm(CALL_SECONDS)
        try:
            CASES[kind][0](rng, world)
            outcome = "ok"
        except VoodooError:
            outcome = "refused"
        except BaseException as exc:  # noqa: BLE001 - anything else is the finding
            outcome = "failed"
            where = traceback.extract_tb(exc.__traceback__)[-1]
            at = f"{type(exc).__name__} at {Path(where.filename).name}:{where.lineno}"
            first, n = failures.get(at, (f"case {done} ({kind}): {str(exc)[:200]}", 0))
            failures[at] = (first, n + 1)
        finally:
            signal.alarm(0)
        outcomes[f"{kind} {outcome}"] = outcomes.get(f"{kind} {outcome}", 0) + 1
        done += 1
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    found = [f"{at}, {n} time(s), first {first}" for at, (first, n) in failures.items()]
    return {"cases": done, "failures": found, "outcomes": outcomes, "peak_bytes": peak}


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def _run_engine_worker(seconds: float) -> dict:
    proc = subprocess.run(
        [sys.executable, __file__, "engine", str(SEED), str(seconds)],
        cwd=REPO,
        env=ENV,
        capture_output=True,
        text=True,
        timeout=seconds + 180,
        preexec_fn=_limit_memory,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _check_engine_report(report: dict) -> None:
    hint = f"VOODOO_FUZZ_SEED={SEED}"
    assert not report["failures"], f"{hint}\n" + "\n".join(report["failures"])
    assert report["cases"] >= 10, report
    assert report["peak_bytes"] < MEMORY, report


def test_engine_survives_hostile_input():
    _check_engine_report(_run_engine_worker(QUICK_SECONDS))


# ------------------------------------------------------------------------- command line

SCENARIO_NAMES = ["translate", "bend", "nosuch", ""]


def _arg(rng, typical):
    """A command-line number: usually sensible, sometimes not a number at all."""
    v = hostile_number(rng, typical)
    if isinstance(v, float) and float(v).is_integer() and abs(v) < 1e15 and rng.random() < 0.5:
        v = int(v)
    return str(v)


def _cli_args(rng, d: Path) -> list[str]:
    """One random command: blob, track, check, segment or synth, with hostile inputs."""
    out = d / "out"
    out.mkdir(exist_ok=True)
    contour = out / "c.json"
    contour.write_text(
        json.dumps({"points": np.asarray(hostile_outline(rng), dtype=object).tolist()})
        if rng.random() < 0.8
        else rng.bytes(100).decode("latin-1"),
        encoding="latin-1",
    )
    blob_opts = []
    for flag, typical in (("--modes", 12), ("--max-area", 100.0), ("--min-angle", 25.0)):
        if rng.random() < 0.3:
            blob_opts += [flag, _arg(rng, typical)]
    pick = lambda *xs: xs[int(rng.integers(len(xs)))]  # noqa: E731
    command = pick("blob", "track", "check", "segment", "synth")
    if command == "blob":
        args = ["blob", str(pick(d / "frame.png", d / "clip.avi", d / "bad.avi", d / "none.png"))]
        args += ["--contour", str(pick(contour, d / "contour.json")), "--out", str(out / "b.npz")]
        if rng.random() < 0.3:
            args += ["--preview", str(out / f"p{pick('.png', '.jpg', '.xyz', '')}")]
        return args + blob_opts
    if command == "track":
        args = ["track", str(pick(d / "clip.avi", d / "cut.avi", d / "bad.avi")), "--quiet"]
        if rng.random() < 0.5:
            args += ["--blob", str(pick(d / "blob.npz", d / "damaged-blob.npz"))]
        else:
            args += ["--contour", str(pick(contour, d / "contour.json"))] + blob_opts
        if rng.random() < 0.5:
            args += ["--frames", _arg(rng, 2)]
        return args + ["--out", str(out / "t.npz")]
    if command == "check":
        args = ["check", str(pick(d / "clip.avi", d / "cut.avi")), str(
            pick(d / "take.npz", d / "damaged-take.npz"))]  # fmt: skip
        return args + (["--json"] if rng.random() < 0.5 else [])
    if command == "segment":
        where = (
            ["--point", _arg(rng, 80), _arg(rng, 60)]
            if rng.random() < 0.5
            else ["--box"] + [_arg(rng, v) for v in (30, 20, 130, 100)]
        )
        return ["segment", str(d / "frame.png"), *where, "--out", str(out / "s.json")]
    size = [_arg(rng, 160), _arg(rng, 128)] if rng.random() < 0.5 else ["160", "128"]
    frames = _arg(rng, 2) if rng.random() < 0.5 else "2"
    name = pick(*SCENARIO_NAMES)
    return ["synth", name, "--size", *size, "--frames", frames, "--out", str(out / "y.avi")]


def _check_cli_outputs(args: list[str], d: Path) -> None:
    """After exit 0: what the command wrote reads back, with no NaN."""
    from voodoo_addon.blob.model import load_blob
    from voodoo_addon.takes.take import load_take

    out = d / "out"
    if args[0] == "blob":
        load_blob(out / "b.npz")  # refuses NaN
    elif args[0] == "track":
        load_take(out / "t.npz")
    elif args[0] == "segment":
        assert _finite(json.loads((out / "s.json").read_text())["points"])


def _no_nan_json(text: str):
    def refuse(name):
        raise AssertionError(f"{name} in the JSON output")

    return json.loads(text, parse_constant=refuse)


def cli_fuzz(d: Path, seed: int, seconds: float) -> tuple[int, list[str]]:
    """Run random commands for ``seconds``; return how many ran and what went wrong."""
    failures, done = [], 0
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        rng = np.random.default_rng([seed, 1_000_000 + done])
        args = _cli_args(rng, d)
        shown = " ".join(a.replace(str(d), "D") for a in args)
        try:
            proc = subprocess.run(
                [sys.executable, "-m", "voodoo_addon", *args],
                cwd=REPO,
                env=ENV,
                capture_output=True,
                text=True,
                timeout=CALL_SECONDS,
                preexec_fn=_limit_memory,
            )
        except subprocess.TimeoutExpired:
            failures.append(f"case {done}: no answer after {CALL_SECONDS} s: {shown}")
            done += 1
            continue
        problem = None
        if proc.returncode not in (0, 2) or "Traceback" in proc.stderr:
            problem = f"exit {proc.returncode}: {proc.stderr.strip()[-600:]}"
        elif "out of memory" in proc.stderr:
            problem = "out of memory"
        elif proc.returncode == 0:
            try:
                _check_cli_outputs(args, d)
                if "--json" in args:
                    _no_nan_json(proc.stdout.strip().splitlines()[-1])
            except Exception as exc:  # noqa: BLE001
                problem = f"output: {type(exc).__name__}: {exc}"
        if problem:
            failures.append(f"case {done}: {shown}\n    {problem}")
        done += 1
        for f in (d / "out").iterdir():
            f.unlink()
    return done, failures


@pytest.fixture(scope="module")
def cli_files(tmp_path_factory):
    """A short clip, its first frame, an outline, a blob and a take; damaged copies."""
    from voodoo_addon.blob.build import build_blob
    from voodoo_addon.blob.model import save_blob
    from voodoo_addon.blob.outline import save_contour_json
    from voodoo_addon.devtools.scenarios import scenario_take
    from voodoo_addon.devtools.synthetic import write_frames
    from voodoo_addon.media.images import write_image
    from voodoo_addon.media.sources import ArraySource
    from voodoo_addon.takes.take import save_take, track_source

    d = tmp_path_factory.mktemp("fuzz")
    frames, contour, _ = scenario_take("bend", 4, (W, H), blob_pixels=3000)
    write_frames(d / "clip.avi", frames)
    write_image(d / "frame.png", frames[0])
    save_contour_json(d / "contour.json", contour)
    blob = build_blob(frames[0], contour)
    save_blob(d / "blob.npz", blob)
    save_take(d / "take.npz", track_source(blob, ArraySource(frames)))
    rng = np.random.default_rng(SEED)
    clip = (d / "clip.avi").read_bytes()
    (d / "cut.avi").write_bytes(clip[: len(clip) // 2])
    (d / "bad.avi").write_bytes(rng.bytes(3000))
    for kind in ("blob", "take"):
        (d / f"damaged-{kind}.npz").write_bytes(damaged(rng, (d / f"{kind}.npz").read_bytes()))
    return d


def _check_cli(d: Path, seconds: float) -> None:
    done, failures = cli_fuzz(d, SEED, seconds)
    assert not failures, f"VOODOO_FUZZ_SEED={SEED}\n" + "\n".join(failures)
    assert done >= 3


def test_command_line_survives_hostile_input(cli_files):
    _check_cli(cli_files, QUICK_SECONDS)


if __name__ == "__main__":
    sys.path.insert(0, str(REPO))
    _, part, seed_text, seconds_text = sys.argv
    print(json.dumps(engine_fuzz(int(seed_text), float(seconds_text))))
