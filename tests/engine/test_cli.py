"""The command line, run the way a user runs it: ``python -m voodoo_addon ...`` in a subprocess.

Contract (docs/design.md, *Command line*): exit code 0 on success, 2 with a one-line message on
stderr on bad input.
"""

from __future__ import annotations

import json
import subprocess
import sys

import cv2
import numpy as np
import pytest

from voodoo_addon.blob.model import load_blob
from voodoo_addon.blob.outline import save_contour_json
from voodoo_addon.devtools.scenarios import scenario_take
from voodoo_addon.devtools.synthetic import write_frames
from voodoo_addon.media.images import write_image
from voodoo_addon.tracking.params import SIMILARITY

N_FRAMES = 36  # more than 30: the progress bar is shown unless --quiet


def run_cli(repo_root, *args, timeout=300):
    return subprocess.run(
        [sys.executable, "-m", "voodoo_addon", *map(str, args)],
        cwd=repo_root,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def run_blob(repo_root, d, out, *options):
    """``blob`` on the fixture's first frame and outline (``d``), writing ``out``."""
    return run_cli(
        repo_root, "blob", d / "frame.png", "--contour", d / "contour.json", "--out", out, *options
    )


def assert_clean_failure(proc):
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("error:")
    assert "Traceback" not in proc.stderr


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A synthetic take on disk: the clip (lossless AVI), its first frame, its outline."""
    d = tmp_path_factory.mktemp("cli")
    frames, contour, truth = scenario_take("translate", N_FRAMES, (320, 240), blob_pixels=5000)
    write_frames(d / "clip.avi", frames)
    write_image(d / "frame.png", frames[0])
    save_contour_json(d / "contour.json", contour)
    (d / "notes.mp4").write_text("not a video\n" * 20)
    return d, truth


def test_blob_writes_blob_and_preview(repo_root, files, tmp_path):
    d, _ = files
    out, preview = tmp_path / "b.npz", tmp_path / "p.png"
    proc = run_blob(repo_root, d, out, "--preview", preview)
    assert proc.returncode == 0, proc.stderr
    blob = load_blob(out)
    assert blob.n_modes == 20
    np.testing.assert_array_equal(blob.frame_size, [320, 240])
    pic = cv2.imread(str(preview))
    assert pic is not None and pic.ndim == 3 and pic.size > 0
    assert str(out) in proc.stdout


def test_blob_options_are_passed_on(repo_root, files, tmp_path):
    d, _ = files
    out = tmp_path / "b.npz"
    proc = run_blob(repo_root, d, out, "--modes", 6, "--poly-degree", 0, "--min-angle", 30)
    assert proc.returncode == 0, proc.stderr
    blob = load_blob(out)
    assert blob.n_modes == 6
    assert blob.mesh.min_angle() >= 30 - 1e-6
    # poly_degree=0: plain FE modes (K phi = w^2 M phi with the projector, scale separated).
    r = blob.constrained
    proj = np.eye(len(blob.mass)) - r @ r.T @ blob.mass
    lhs = proj.T @ blob.stiffness @ blob.modes
    np.testing.assert_allclose(
        lhs, blob.mass @ blob.modes * blob.mode_stiffness, atol=1e-9 * np.abs(lhs).max()
    )


def _bad_blob_inputs(d, tmp_path):
    bowtie = tmp_path / "bowtie.json"
    bowtie.write_text(json.dumps({"points": [[50, 50], [150, 150], [150, 50], [50, 150]]}))
    malformed = tmp_path / "malformed.json"
    malformed.write_text('{"points": [[50, 50], [150, 150]')
    wrong = tmp_path / "wrong.json"
    wrong.write_text(json.dumps([[50, 50], [150, 50], [150, 150]]))
    outside = tmp_path / "outside.json"
    outside.write_text(json.dumps({"points": [[50, 50], [500, 50], [500, 150]]}))
    return {
        "missing-frame": (tmp_path / "nope.png", d / "contour.json"),
        "not-a-picture": (d / "contour.json", d / "contour.json"),
        "missing-contour": (d / "frame.png", tmp_path / "nope.json"),
        "self-intersecting": (d / "frame.png", bowtie),
        "malformed-json": (d / "frame.png", malformed),
        "no-points-key": (d / "frame.png", wrong),
        "off-frame": (d / "frame.png", outside),
    }


@pytest.mark.parametrize(
    "case",
    [
        "missing-frame",
        "not-a-picture",
        "missing-contour",
        "self-intersecting",
        "malformed-json",
        "no-points-key",
        "off-frame",
    ],
)
def test_blob_bad_input_exits_2(repo_root, files, tmp_path, case):
    d, _ = files
    frame, contour = _bad_blob_inputs(d, tmp_path)[case]
    out = tmp_path / "b.npz"
    proc = run_cli(repo_root, "blob", frame, "--contour", contour, "--out", out)
    assert_clean_failure(proc)
    assert not out.exists()


def test_track_writes_the_contract_npz(repo_root, files, tmp_path):
    d, truth = files
    out = tmp_path / "t.npz"
    proc = run_cli(
        repo_root,
        "track",
        d / "clip.avi",
        "--contour",
        d / "contour.json",
        "--out",
        out,
        "--quiet",
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""  # --quiet: no progress bar
    with np.load(out, allow_pickle=False) as npz:
        v, tri = npz["vertices"], npz["triangles"]
        params, conf, labels = npz["params"], npz["confidence"], npz["mode_labels"]
    t, n = v.shape[:2]
    assert t == N_FRAMES
    assert v.shape == (t, n, 2) and v.dtype.kind == "f"
    assert tri.ndim == 2 and tri.shape[1] == 3 and tri.dtype.kind == "i"
    assert tri.min() == 0 and tri.max() == n - 1
    assert params.shape == (t, labels.shape[0]) and params.dtype.kind == "f"
    assert conf.shape == (t,) and conf.dtype.kind == "f"
    assert ((conf >= 0) & (conf <= 1)).all()
    assert labels.ndim == 1 and labels.dtype.kind == "U"
    assert tuple(labels[:4]) == SIMILARITY
    assert len(labels) == 4 + 20 + 6
    assert np.isfinite(v).all() and np.isfinite(params).all()
    # And the motion is right (the file is lossless): rest nodes follow the true motion.
    err = [np.linalg.norm(v[i] - truth(i, v[0]), axis=1).mean() for i in range(t)]
    assert np.mean(err) < 0.5


def test_track_both_ways_writes_the_same_contract(repo_root, files, tmp_path):
    """``--both-ways``: the file tracked again backwards and merged; the same take file,
    as near the truth, with the work of both passes; its progress is said too."""
    d, truth = files
    one, both = tmp_path / "one.npz", tmp_path / "both.npz"
    args = ("track", d / "clip.avi", "--contour", d / "contour.json", "--out")
    assert run_cli(repo_root, *args, one, "--quiet").returncode == 0
    proc = run_cli(repo_root, *args, both, "--both-ways")
    assert proc.returncode == 0, proc.stderr
    assert "backwards" in proc.stderr
    with np.load(one) as a, np.load(both) as b:
        assert set(a.files) == set(b.files)
        assert b["vertices"].shape == a["vertices"].shape and not b["lost"].any()
        np.testing.assert_array_equal(b["frame_indices"], a["frame_indices"])
        assert np.all(b["iterations"] > a["iterations"])
        v = b["vertices"]
    err = [np.linalg.norm(v[i] - truth(i, v[0]), axis=1).mean() for i in range(len(v))]
    assert np.mean(err) < 0.5


def test_track_progress_goes_to_stderr(repo_root, files, tmp_path):
    d, _ = files
    out = tmp_path / "t.npz"
    proc = run_cli(
        repo_root,
        "track",
        d / "clip.avi",
        "--contour",
        d / "contour.json",
        "--out",
        out,
        "--modes",
        6,
    )
    assert proc.returncode == 0, proc.stderr
    assert f"{N_FRAMES}/{N_FRAMES}" in proc.stderr
    assert "tracking" not in proc.stdout
    assert len(proc.stdout.strip().splitlines()) == 1
    assert proc.stdout.startswith("track:")
    with np.load(out, allow_pickle=False) as npz:
        assert npz["params"].shape[1] == 4 + 6 + 6


@pytest.mark.parametrize(
    "video", ["notes.mp4", "missing.avi", "camera:97"], ids=["not-a-video", "missing", "camera"]
)
def test_track_unreadable_video_exits_2(repo_root, files, tmp_path, video):
    d, _ = files
    target = video if video.startswith("camera:") else d / video
    out = tmp_path / "t.npz"
    proc = run_cli(repo_root, "track", target, "--contour", d / "contour.json", "--out", out)
    assert_clean_failure(proc)
    assert not out.exists()


def test_track_bad_contour_exits_2(repo_root, files, tmp_path):
    d, _ = files
    bowtie = tmp_path / "bowtie.json"
    bowtie.write_text(json.dumps({"points": [[50, 50], [150, 150], [150, 50], [50, 150]]}))
    proc = run_cli(
        repo_root, "track", d / "clip.avi", "--contour", bowtie, "--out", tmp_path / "t.npz"
    )
    assert_clean_failure(proc)


def test_track_without_contour_exits_2(repo_root, files, tmp_path):
    d, _ = files
    proc = run_cli(repo_root, "track", d / "clip.avi", "--out", tmp_path / "t.npz")
    assert_clean_failure(proc)


def test_track_unknown_frozen_parameter_exits_2(repo_root, files, tmp_path):
    d, _ = files
    proc = run_cli(
        repo_root,
        "track",
        d / "clip.avi",
        "--contour",
        d / "contour.json",
        "--out",
        tmp_path / "t.npz",
        "--freeze",
        "rotation",
        "--frames",
        2,
    )
    assert_clean_failure(proc)


def test_segment_writes_a_contour(repo_root, tmp_path):
    from voodoo_addon.devtools.synthetic import Pose, foam_scene

    scene, _ = foam_scene(320, 240, 8000)
    frame = tmp_path / "f.png"
    write_image(frame, scene.render(Pose()))
    out = tmp_path / "c.json"
    proc = run_cli(repo_root, "segment", frame, "--point", 160, 120, "--out", out)
    assert proc.returncode == 0, proc.stderr
    pts = np.array(json.loads(out.read_text())["points"])
    assert pts.ndim == 2 and pts.shape[1] == 2 and len(pts) >= 8
    proc = run_cli(repo_root, "segment", frame, "--point", 5, 5, "--out", tmp_path / "d.json")
    assert_clean_failure(proc)


@pytest.mark.parametrize(
    "args",
    [
        ["--box", "nan", 10, 200, 200],
        ["--point", 160, "inf"],
        ["--point", 160, 120, "--preview", "p.xyz"],
    ],
    ids=["box-nan", "point-inf", "preview-extension"],
)
def test_segment_bad_request_exits_2(repo_root, files, tmp_path, args):
    d, _ = files
    out = tmp_path / "c.json"
    args = [tmp_path / a if str(a).endswith(".xyz") else a for a in args]
    proc = run_cli(repo_root, "segment", d / "frame.png", *args, "--out", out)
    assert_clean_failure(proc)
    assert not out.exists()


# ----------------------------------------------------- user errors: one line, exit code 2


@pytest.mark.parametrize(
    "args",
    [
        ["nosuch"],
        ["translate", "--size", 0, 0],
        ["translate", "--size", -5, 100],
        ["translate", "--frames", 0],
        ["translate", "--frames", -4],
    ],
    ids=["unknown-scenario", "size-zero", "size-negative", "frames-zero", "frames-negative"],
)
def test_synth_bad_request_exits_2_and_writes_nothing(repo_root, tmp_path, args):
    out = tmp_path / "s.avi"
    proc = run_cli(repo_root, "synth", *args, "--out", out, "--contour", tmp_path / "c.json")
    assert_clean_failure(proc)
    assert not out.exists() and not (tmp_path / "c.json").exists()


def test_unknown_preview_extension_exits_2_before_the_blob_is_written(repo_root, files, tmp_path):
    d, _ = files
    out = tmp_path / "b.npz"
    proc = run_blob(repo_root, d, out, "--preview", tmp_path / "p.xyz")
    assert_clean_failure(proc)
    assert ".xyz" in proc.stderr
    assert not out.exists()


@pytest.mark.parametrize("frames", [0, -2])
def test_track_frames_below_one_exits_2(repo_root, files, tmp_path, frames):
    d, _ = files
    out = tmp_path / "t.npz"
    proc = run_cli(
        repo_root, "track", d / "clip.avi", "--contour", d / "contour.json", "--out", out,
        "--frames", frames,
    )  # fmt: skip
    assert_clean_failure(proc)
    assert "--frames" in proc.stderr
    assert not out.exists()


def test_truncated_video_is_tracked_and_the_shortfall_said(repo_root, files, tmp_path):
    d, _ = files
    clip = tmp_path / "cut.avi"
    data = (d / "clip.avi").read_bytes()
    clip.write_bytes(data[: len(data) // 2])
    out = tmp_path / "t.npz"
    proc = run_cli(
        repo_root, "track", clip, "--contour", d / "contour.json", "--out", out, "--quiet"
    )
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    with np.load(out, allow_pickle=False) as npz:
        n = len(npz["params"])
    assert 0 < n < N_FRAMES
    assert f"{N_FRAMES} frames expected, {n} read" in proc.stderr
    assert f"track: {n} frames" in proc.stdout


@pytest.fixture(scope="module")
def damaged(files, tmp_path_factory):
    """Good and damaged blob and take files."""
    from voodoo_addon.blob.build import build_blob
    from voodoo_addon.blob.model import save_blob
    from voodoo_addon.blob.outline import load_contour_json
    from voodoo_addon.media.sources import ArraySource, read_image
    from voodoo_addon.takes.take import save_take, track_source

    d, _ = files
    out = tmp_path_factory.mktemp("damaged")
    frame = read_image(d / "frame.png")
    blob = build_blob(frame, load_contour_json(d / "contour.json"))
    save_blob(out / "blob.npz", blob)
    save_take(out / "take.npz", track_source(blob, ArraySource([frame] * 3)))
    rng = np.random.default_rng(0)
    for kind in ("blob", "take"):
        good = (out / f"{kind}.npz").read_bytes()
        (out / f"{kind}-truncated.npz").write_bytes(good[: len(good) // 2])
        (out / f"{kind}-random.npz").write_bytes(rng.bytes(4000))
        np.savez(out / f"{kind}-wrong-keys.npz", a=np.arange(3))
        with np.load(out / f"{kind}.npz", allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
        key = "modes" if kind == "blob" else "params"
        arrays[key] = np.full_like(arrays[key], np.nan)
        np.savez(out / f"{kind}-nan.npz", **arrays)
    return out


@pytest.mark.parametrize("damage", ["truncated", "random", "wrong-keys", "nan"])
def test_damaged_blob_exits_2(repo_root, files, damaged, tmp_path, damage):
    d, _ = files
    blob = damaged / f"blob-{damage}.npz"
    out = tmp_path / "t.npz"
    proc = run_cli(repo_root, "track", d / "clip.avi", "--blob", blob, "--out", out)
    assert_clean_failure(proc)
    assert str(blob) in proc.stderr
    assert not out.exists()


@pytest.mark.parametrize("damage", ["truncated", "random", "wrong-keys", "nan"])
def test_damaged_take_exits_2(repo_root, files, damaged, damage):
    d, _ = files
    take = damaged / f"take-{damage}.npz"
    proc = run_cli(repo_root, "check", d / "clip.avi", take)
    assert_clean_failure(proc)
    assert str(take) in proc.stderr


@pytest.mark.slow
def test_bench_prints_one_json_line(repo_root):
    # `python -m voodoo_addon bench --json` prints one JSON line of the benchmark.
    proc = run_cli(repo_root, "bench", "--json", "--quick", timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    lines = proc.stdout.strip().splitlines()
    assert len(lines) == 1
    report = json.loads(lines[0])
    assert isinstance(report, dict) and report
