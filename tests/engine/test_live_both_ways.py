"""``voodoo live --footage --both-ways``: a live take kept with every frame read, then
tracked again backwards and merged (media.footage, cli, takes.both_ways)."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from voodoo_addon import cli
from voodoo_addon.media import sources
from voodoo_addon.media.footage import Footage
from voodoo_addon.media.sources import ArraySource, CaptureSource, Frame, read_image
from voodoo_addon.takes.take import load_take

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "sample_take.mp4"
OUTLINE = ROOT / "samples" / "sample_take.json"


def live(*args):
    cmd = [sys.executable, "-m", "voodoo_addon", "live", str(SAMPLE), "--contour", str(OUTLINE)]
    cmd += ["--fast", "--quiet", "--frames", "20", *map(str, args)]
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_live_keeps_its_footage_and_tracks_the_take_both_ways(tmp_path):
    """Every frame read goes to the footage; with --both-ways the take written is the live
    one merged with a backward pass: the same frames, the work of both passes in it."""
    plain, both, footage = tmp_path / "plain.npz", tmp_path / "both.npz", tmp_path / "f.avi"
    done = live("--out", plain)
    assert done.returncode == 0, done.stderr
    done = live("--out", both, "--footage", footage, "--both-ways")
    assert done.returncode == 0, done.stderr
    assert "warning" not in done.stderr, done.stderr
    with CaptureSource(str(footage)) as src:
        assert src.count == 20 and src.size == read_image(SAMPLE).shape[1::-1]
        first = src.read().image
    assert np.abs(first - read_image(SAMPLE)).mean() < 0.02  # JPEG-compressed frame 0
    forward, merged = load_take(plain), load_take(both)
    np.testing.assert_array_equal(merged.frame_indices, forward.frame_indices)
    assert np.all(merged.iterations > forward.iterations)
    assert not merged.lost.any() and np.isfinite(merged.params).all()
    assert np.linalg.norm(merged.vertices - forward.vertices, axis=2).mean() < 1.0


def test_live_both_ways_needs_somewhere_to_write_the_take(tmp_path):
    done = live("--both-ways")
    assert done.returncode == 2 and "--both-ways needs --out" in done.stderr


class _Camera(ArraySource):
    """The sample take's frames, as a camera gives them (live: no seeking)."""

    live = True

    def read(self):
        frame = super().read()
        return None if frame is None else Frame(frame.pixels, frame.index, frame.index / 30.0)


@pytest.fixture
def camera(monkeypatch):
    """``camera:0`` is a stand-in camera; files open as they do."""
    with CaptureSource(str(SAMPLE)) as src:
        frames = [src.read().pixels for _ in range(30)]
    real = sources.open_source

    def open_source(spec):
        return _Camera(frames, fps=30.0) if str(spec) == "camera:0" else real(spec)

    monkeypatch.setattr(sources, "open_source", open_source)
    return frames


def test_a_camera_take_is_tracked_both_ways_on_its_footage(camera, tmp_path, capsys):
    """A camera cannot be read again: --both-ways asks for --footage, and with it the
    backward pass reads the footage."""
    out, footage = tmp_path / "take.npz", tmp_path / "cam.avi"
    args = ["live", "camera:0", "--contour", str(OUTLINE), "--quiet", "--out", str(out)]
    assert cli.main([*args, "--both-ways"]) == 2
    assert "--both-ways with a camera needs --footage" in capsys.readouterr().err
    assert not out.exists()
    assert cli.main([*args, "--both-ways", "--footage", str(footage)]) == 0
    err = capsys.readouterr().err
    assert "warning" not in err, err
    # The camera's first frame builds the blob; the take tracks the ones after it, and the
    # footage keeps them all, so that its frame N is the take's frame index N.
    take = load_take(out)
    assert take.frame_indices.tolist() == list(range(1, len(camera)))
    assert not take.lost.any() and np.isfinite(take.params).all()
    with CaptureSource(str(footage)) as src:
        assert src.count == len(camera)
        kept = [src.read().pixels.astype(float) for _ in range(len(camera))]
    # Frame for frame (JPEG aside), not one off: the doll moves from frame 12 on.
    same = sum(np.abs(kept[k] - camera[k]).mean() for k in range(12, len(camera)))
    off = sum(np.abs(kept[k] - camera[k - 1]).mean() for k in range(12, len(camera)))
    assert same < 0.8 * off


def test_footage_that_cannot_be_written_is_a_clear_error(tmp_path):
    blocked = tmp_path / "a file"
    blocked.write_text("not a folder")
    with pytest.raises(sources.VoodooError, match="footage"):
        Footage(blocked / "take.avi", 30.0, (64, 48))
    footage = Footage(tmp_path / "ok.avi", 30.0, (64, 48))
    footage.close()
    footage.write(Frame(np.zeros((48, 64, 3), np.uint8), 0, 0.0))  # after close: nothing
    assert footage.frames == 0
