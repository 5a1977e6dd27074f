"""Tracking a whole source into a Take, and the take file (the command-line contract)."""

from __future__ import annotations

import io

import numpy as np
import pytest

from voodoo_addon.blob.build import build_blob
from voodoo_addon.devtools.scenarios import scenario_take
from voodoo_addon.errors import VoodooError
from voodoo_addon.media.sources import ArraySource
from voodoo_addon.takes.take import (
    ProgressBar,
    Take,
    load_take,
    missing_frames,
    save_take,
    take_from_bytes,
    take_to_bytes,
    track_source,
)
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


def test_in_view_is_the_share_of_triangles_seen_and_nothing_when_lost(take_setup):
    *_, take = take_setup
    np.testing.assert_array_equal(take.in_view(), np.ones(N))  # a card in view throughout
    visible = take.visible.copy()
    visible[2, : len(visible[2]) // 4] = False  # a quarter folded away
    lost = take.lost.copy()
    lost[5] = True
    partial = Take(**{**vars(take), "visible": visible, "lost": lost})
    share = partial.in_view()
    assert share[2] == pytest.approx(1.0 - (len(visible[2]) // 4) / len(visible[2]))
    assert share[5] == 0.0
    assert share[[0, 1, 3, 4]].tolist() == [1.0] * 4


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


# ------------------------------------------------------------------- damaged take files


def _take_arrays(take) -> dict:
    with np.load(io.BytesIO(take_to_bytes(take)), allow_pickle=False) as npz:
        return {k: npz[k] for k in npz.files}


def _take_with(take, **changes) -> bytes:
    arrays = _take_arrays(take)
    for k, v in changes.items():
        if v is None:
            del arrays[k]
        else:
            arrays[k] = v(arrays[k]) if callable(v) else v
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def _nan_at(a, value=np.nan):
    a = a.astype(np.float64)
    a.flat[len(a.flat) // 2] = value
    return a


TAKE_CORRUPTIONS = {
    "random-bytes": lambda t: np.random.default_rng(1).bytes(3000),
    "truncated": lambda t: take_to_bytes(t)[: len(take_to_bytes(t)) // 2],
    "truncated-end": lambda t: take_to_bytes(t)[:-20],
    "blob-file": lambda t: _take_with(t, format_kind=np.array("voodoo-active-blob")),
    "version-text": lambda t: _take_with(t, format_version=np.array("two")),
    "version-fraction": lambda t: _take_with(t, format_version=np.array(1.5)),
    "missing-params": lambda t: _take_with(t, params=None),
    "missing-visible": lambda t: _take_with(t, visible=None),
    "nan-params": lambda t: _take_with(t, params=_nan_at),
    "inf-vertices": lambda t: _take_with(t, vertices=lambda a: _nan_at(a, np.inf)),
    "nan-confidence": lambda t: _take_with(t, confidence=_nan_at),
    "nan-fps": lambda t: _take_with(t, fps=np.array(np.nan)),
    "zero-fps": lambda t: _take_with(t, fps=np.array(0.0)),
    "confidence-above-one": lambda t: _take_with(t, confidence=lambda a: a + 2),
    "params-wrong-width": lambda t: _take_with(t, params=lambda a: a[:, :3]),
    "frames-disagree": lambda t: _take_with(t, confidence=lambda a: a[:-1]),
    "float-triangles": lambda t: _take_with(t, triangles=lambda a: a * 1.0),
    "triangle-out-of-range": lambda t: _take_with(t, triangles=lambda a: a + 10_000),
    "labels-as-numbers": lambda t: _take_with(t, mode_labels=lambda a: np.arange(len(a))),
    "no-frames": lambda t: _take_with(t, **{k: (lambda a: a[:0]) for k in _PER_FRAME}),
}
_PER_FRAME = (
    "vertices",
    "params",
    "confidence",
    "lost",
    "frame_indices",
    "times",
    "iterations",
    "visible",
)


@pytest.mark.parametrize("make", TAKE_CORRUPTIONS.values(), ids=TAKE_CORRUPTIONS.keys())
def test_damaged_take_raises_a_clear_error(take_setup, make):
    take = take_setup[3]
    with pytest.raises(VoodooError, match="not a (readable|Voodoo) take|corrupt|incomplete"):
        take_from_bytes(make(take), source="t.npz")


def test_take_round_trip_still_works(take_setup):
    take = take_setup[3]
    back = take_from_bytes(take_to_bytes(take))
    np.testing.assert_array_equal(back.params, take.params)
    np.testing.assert_array_equal(back.visible, take.visible)


@pytest.mark.parametrize("limit", [0, -3, 2.5, float("nan")])
def test_track_source_refuses_a_limit_below_one_frame(take_setup, limit):
    frames, _, blob, _ = take_setup
    with pytest.raises(VoodooError, match="number of frames"):
        track_source(blob, ArraySource(frames), limit=limit)


class _ShortSource(ArraySource):
    """Announces more frames than it gives, like a truncated file."""

    def __init__(self, frames, announced):
        super().__init__(frames)
        self.count = announced


def test_missing_frames_are_reported(take_setup):
    frames, _, blob, _ = take_setup
    src = _ShortSource(frames[:4], announced=N)
    take = track_source(blob, src)
    assert len(take) == 4
    msg = missing_frames(src, take, name="clip.avi")
    assert msg is not None and "clip.avi" in msg and f"{N} frames expected, 4 read" in msg
    # Asked for 3: all there.
    assert missing_frames(_ShortSource(frames[:4], N), take, limit=3) is None
    full = ArraySource(frames[:4])
    assert missing_frames(full, track_source(blob, full)) is None
