"""Frame sources: video files, picture folders, arrays and (missing) cameras."""

from __future__ import annotations

import numpy as np
import pytest

from voodoo_addon.devtools.synthetic import painted_foam, write_frames
from voodoo_addon.errors import VoodooError
from voodoo_addon.media.images import write_image
from voodoo_addon.media.sources import ArraySource, CaptureSource, ImageFolderSource, open_source

N_FRAMES, W, H = 7, 64, 48


@pytest.fixture(scope="module")
def clip():
    """Distinct frames, already on the 8-bit grid (so lossless files give them back exactly)."""
    frames = [painted_foam(H, W, seed=i) for i in range(N_FRAMES)]
    return [(np.round(f * 255) / 255).astype(np.float32) for f in frames]


@pytest.fixture(scope="module", params=["avi", "folder", "array"])
def source_factory(request, clip, tmp_path_factory):
    kind = request.param
    if kind == "array":
        return kind, lambda: ArraySource(clip)
    base = tmp_path_factory.mktemp(kind)
    path = base / ("clip.avi" if kind == "avi" else "frames")
    write_frames(path, clip)  # .avi is lossless FFV1
    return kind, lambda: open_source(path)


def test_count_size_and_type(source_factory):
    kind, make = source_factory
    with make() as src:
        expected = {"avi": CaptureSource, "folder": ImageFolderSource, "array": ArraySource}
        assert isinstance(src, expected[kind])
        assert src.count == N_FRAMES
        assert src.size == (W, H)
        assert src.live is False
        assert src.fps > 0


def test_reads_every_frame_in_order(source_factory, clip):
    _, make = source_factory
    with make() as src:
        frames = list(src)
        fps = src.fps
    assert [f.index for f in frames] == list(range(N_FRAMES))
    for f, want in zip(frames, clip, strict=True):
        assert f.image.dtype == np.float32 and f.image.shape == (H, W, 3)
        np.testing.assert_allclose(f.image, want, atol=1e-6)
    np.testing.assert_allclose([f.time for f in frames], np.arange(N_FRAMES) / fps)


@pytest.mark.parametrize("order", [[3, 1, 6, 0], [5, 5, 2]])
def test_seek_and_read_at(source_factory, clip, order):
    _, make = source_factory
    with make() as src:
        for i in order:
            f = src.read_at(i)
            assert f.index == i
            np.testing.assert_allclose(f.image, clip[i], atol=1e-6)
            # Reading on continues from there.
            if i + 1 < N_FRAMES:
                nxt = src.read()
                assert nxt.index == i + 1
                np.testing.assert_allclose(nxt.image, clip[i + 1], atol=1e-6)
        src.seek(N_FRAMES - 1)
        assert src.read().index == N_FRAMES - 1
        assert src.read() is None


@pytest.mark.parametrize("index", [-1, N_FRAMES, 10_000])
def test_seek_outside_raises(source_factory, index):
    _, make = source_factory
    with make() as src:
        with pytest.raises(VoodooError):
            src.seek(index)
        with pytest.raises(VoodooError):
            src.read_at(index)


def test_missing_file_raises(tmp_path):
    with pytest.raises(VoodooError, match="does not exist"):
        open_source(tmp_path / "nope.mp4")


@pytest.mark.parametrize("suffix", [".mp4", ".avi", ".mov"])
def test_not_a_video_raises(tmp_path, suffix):
    path = tmp_path / f"notes{suffix}"
    path.write_text("this is not a video\n" * 50)
    with pytest.raises(VoodooError):
        open_source(path)


def test_empty_file_raises(tmp_path):
    path = tmp_path / "empty.mp4"
    path.write_bytes(b"")
    with pytest.raises(VoodooError):
        open_source(path)


@pytest.mark.parametrize("spec", ["camera:97", 97, "camera:x", "camera:"])
def test_missing_camera_raises(spec):
    with pytest.raises(VoodooError):
        open_source(spec)


def test_empty_folder_raises(tmp_path):
    with pytest.raises(VoodooError):
        open_source(tmp_path)


def test_folder_with_a_broken_picture_raises(tmp_path, clip):
    write_image(tmp_path / "a_000.png", clip[0])
    (tmp_path / "a_001.png").write_bytes(b"not a png")
    with open_source(tmp_path) as src:
        src.read()
        with pytest.raises(VoodooError):
            src.read()


def test_folder_with_mixed_sizes_raises(tmp_path, clip):
    write_image(tmp_path / "a_000.png", clip[0])
    write_image(tmp_path / "a_001.png", clip[1][:20, :30])
    with open_source(tmp_path) as src:
        src.read()
        with pytest.raises(VoodooError):
            src.read()


def test_array_source_needs_frames():
    with pytest.raises(VoodooError):
        ArraySource([])


def test_array_source_converts_uint8(clip):
    src = ArraySource([(f * 255).round().astype(np.uint8) for f in clip])
    f = src.read()
    assert f.image.dtype == np.float32
    np.testing.assert_allclose(f.image, clip[0], atol=1e-6)
