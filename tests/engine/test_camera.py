"""A camera's faults put on clean frames (devtools.camera): each fault does what it says, the
same every run, and the fold benchmark runs on the degraded frames."""

import cv2
import numpy as np

from voodoo_addon.devtools.camera import CAMERAS, CameraFaults, degrade
from voodoo_addon.devtools.folds import fold_clips, main, run_fold_clip

NONE = CameraFaults(blur=0.0, drift=0.0, noise=0.0, jpeg=100)


def _flat(value=120, frames=4, size=(48, 64)):
    return [np.full((*size, 3), value, np.uint8) for _ in range(frames)]


def _checker(size=(64, 64), cell=4):
    y, x = np.mgrid[: size[0], : size[1]]
    grey = np.where(((x // cell) + (y // cell)) % 2, 200, 50).astype(np.uint8)
    return np.repeat(grey[..., None], 3, axis=2)


def test_no_fault_leaves_the_frames_as_they_are():
    frames = [_checker(), _checker()[::-1].copy()]
    for got, want in zip(degrade(frames, NONE), frames, strict=True):
        assert got.dtype == np.uint8 and got.shape == want.shape
        np.testing.assert_array_equal(got, want)


def test_sensor_noise_has_the_asked_spread_and_the_same_seed_gives_the_same_frames():
    faults = CameraFaults(blur=0.0, drift=0.0, noise=5.0, jpeg=100, seed=7)
    got = degrade(_flat(), faults)
    spread = np.std(np.stack(got).astype(np.float64) - 120.0)
    assert 4.7 < spread < 5.3
    again = degrade(_flat(), faults)
    for a, b in zip(got, again, strict=True):
        np.testing.assert_array_equal(a, b)
    other = degrade(_flat(), CameraFaults(blur=0.0, drift=0.0, noise=5.0, jpeg=100, seed=8))
    assert not np.array_equal(got[0], other[0])


def test_exposure_swings_over_the_clip():
    faults = CameraFaults(blur=0.0, drift=0.2, noise=0.0, jpeg=100)
    got = degrade(_flat(100, frames=4), faults)
    # A sine over four frames: 1, 1.2, 1, 0.8 times the light.
    assert [int(f[0, 0, 0]) for f in got] == [100, 120, 100, 80]


def test_defocus_and_jpeg_take_away_fine_detail():
    sharp = _checker()

    def detail(img):
        return float(np.abs(cv2.Laplacian(img[..., 0].astype(np.float32), cv2.CV_32F)).mean())

    blurred = degrade([sharp], CameraFaults(blur=1.5, drift=0.0, noise=0.0, jpeg=100))[0]
    assert detail(blurred) < 0.5 * detail(sharp)
    assert abs(float(blurred.mean()) - float(sharp.mean())) < 2.0
    coded = degrade([sharp], CameraFaults(blur=0.0, drift=0.0, noise=0.0, jpeg=30))[0]
    assert not np.array_equal(coded, sharp)
    assert np.abs(coded.astype(int) - sharp.astype(int)).mean() < 20


def test_the_fold_benchmark_runs_on_a_cameras_frames(capsys):
    """KLT (fast) on one fold clip through a webcam: the table is written, and the clip's
    frames differ from the clean render's."""
    clip = next(c for c in fold_clips() if c.name == "sheet_foldover")
    clean = run_fold_clip(clip, ("klt",))[0]
    webcam = run_fold_clip(clip, ("klt",), camera=CAMERAS["webcam"])[0]
    assert clean["frame_error"] != webcam["frame_error"]
    assert np.isfinite(webcam["error_px"])
    assert main(["--only", "sheet_foldover", "--trackers", "klt", "--camera", "dim"]) == 0
    assert "| sheet_foldover | klt |" in capsys.readouterr().out


def test_a_redraw_moves_a_few_values_by_one_level_and_each_seed_others():
    """The ``redraw`` camera is the clean render again: no blur, no exposure swing, no JPEG,
    and about a third of the values one grey level off, other ones for another seed."""
    frames = [_checker(), _checker()[::-1].copy()]
    redraw = CAMERAS["redraw"]
    first = degrade(frames, redraw)
    second = degrade(frames, CameraFaults(**{**redraw.__dict__, "seed": 1}))
    for got, other, clean in zip(first, second, frames, strict=True):
        step = got.astype(int) - clean.astype(int)
        assert np.abs(step).max() <= 3
        assert 0.2 < np.count_nonzero(step) / step.size < 0.45
        assert not np.array_equal(got, other)
