"""Tracking a whole source into a Take, and the take file (the command-line contract)."""

from __future__ import annotations

import io

import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.scenarios import scenario_take
from voodoo_addon.errors import VoodooError
from voodoo_addon.media.sources import ArraySource
from voodoo_addon.takes.take import ProgressBar, Take, load_take, save_take, track_source
from voodoo_addon.tracking import Tracker

N = 12


@pytest.fixture(scope="module")
def take_setup():
    frames, contour, truth = scenario_take("translate", N, (320, 240), blob_pixels=5000)
    blob = build_blob(frames[0], contour)
    take = track_source(blob, ArraySource(frames, fps=25.0))
    return frames, truth, blob, take


def test_take_shapes_and_accuracy(take_setup):
    frames, truth, blob, take = take_setup
    m, p = blob.n_nodes, Tracker(blob).layout.size
    assert len(take) == N
    assert take.vertices.shape == (N, m, 2)
    assert take.params.shape == (N, p)
    assert take.confidence.shape == take.lost.shape == (N,)
    assert take.param_names.shape == (p,)
    np.testing.assert_array_equal(take.triangles, blob.triangles)
    np.testing.assert_array_equal(take.frame_indices, np.arange(N))
    np.testing.assert_allclose(take.times, np.arange(N) / 25.0)
    assert take.fps == 25.0
    assert (take.iterations >= 1).all()
    err = [
        np.linalg.norm(take.vertices[i] - truth(i, blob.vertices), axis=1).mean() for i in range(N)
    ]
    assert np.mean(err) < 0.5


def test_limit_and_progress(take_setup):
    frames, _, blob, _ = take_setup
    calls = []
    take = track_source(blob, ArraySource(frames), progress=calls.append, limit=5)
    assert len(take) == 5
    assert calls == [1, 2, 3, 4, 5]


def test_starts_at_the_source_position(take_setup):
    frames, _, blob, _ = take_setup
    src = ArraySource(frames)
    src.seek(N - 3)
    take = track_source(blob, src)
    np.testing.assert_array_equal(take.frame_indices, [N - 3, N - 2, N - 1])


def test_empty_source_raises(take_setup):
    frames, _, blob, _ = take_setup
    src = ArraySource(frames)
    src.seek(N - 1)
    src.read()
    with pytest.raises(VoodooError):
        track_source(blob, src)


def test_take_file_round_trip(take_setup, tmp_path):
    take = take_setup[3]
    path = tmp_path / "t.npz"
    save_take(path, take)
    back = load_take(path)
    for name in Take.__dataclass_fields__:
        x, y = np.asarray(getattr(take, name)), np.asarray(getattr(back, name))
        np.testing.assert_array_equal(x, y, err_msg=name)
        assert x.dtype == y.dtype, name


def test_take_file_holds_the_contract(take_setup, tmp_path):
    take = take_setup[3]
    path = tmp_path / "t.npz"
    save_take(path, take)
    with np.load(path, allow_pickle=False) as npz:
        t, m = take.vertices.shape[:2]
        assert npz["vertices"].shape == (t, m, 2) and npz["vertices"].dtype.kind == "f"
        assert npz["triangles"].shape[1] == 3 and npz["triangles"].dtype.kind == "i"
        assert npz["params"].shape == (t, len(npz["mode_labels"]))
        assert npz["confidence"].shape == (t,)
        assert npz["mode_labels"].dtype.kind == "U"


@pytest.mark.parametrize(
    "content",
    [b"garbage", b"", "other-npz"],
)
def test_bad_take_files_raise(tmp_path, content):
    path = tmp_path / "t.npz"
    if content == "other-npz":
        np.savez(path, a=np.arange(3))
    else:
        path.write_bytes(content)
    with pytest.raises(VoodooError):
        load_take(path)


def test_missing_take_file_raises(tmp_path):
    with pytest.raises(VoodooError):
        load_take(tmp_path / "nope.npz")


def test_progress_bar_writes_to_its_stream():
    stream = io.StringIO()
    bar = ProgressBar(4, stream=stream)
    for i in range(1, 5):
        bar(i)
    text = stream.getvalue()
    assert "4/4" in text
    assert text.endswith("\n")
