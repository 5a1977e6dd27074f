"""Picture conversion and reading: everything becomes float32 RGB in [0, 1]."""

from __future__ import annotations

import numpy as np
import pytest

from voodoo_addon.devtools.synthetic import painted_foam, write_frames
from voodoo_addon.errors import VoodooError
from voodoo_addon.media.images import to_float_rgb, to_uint8_bgr, write_image
from voodoo_addon.media.sources import read_image


def test_uint8_and_uint16_scale_to_unit_range():
    img8 = np.array([[[0, 128, 255]]], np.uint8)
    np.testing.assert_allclose(to_float_rgb(img8), [[[0, 128 / 255, 1]]])
    img16 = np.array([[[0, 32768, 65535]]], np.uint16)
    np.testing.assert_allclose(to_float_rgb(img16), [[[0, 32768 / 65535, 1]]], rtol=1e-6)


def test_bgr_alpha_and_gray():
    bgra = np.array([[[10, 20, 30, 40]]], np.uint8)
    np.testing.assert_allclose(to_float_rgb(bgra, bgr=True) * 255, [[[30, 20, 10]]], rtol=1e-6)
    gray = np.array([[0.25, 0.5]], np.float32)
    out = to_float_rgb(gray)
    assert out.shape == (1, 2, 3)
    np.testing.assert_array_equal(out[..., 0], out[..., 2])


def test_non_finite_and_out_of_range_values_are_clamped():
    img = np.array([[[np.nan, np.inf, -np.inf], [2.0, -1.0, 0.5]]], np.float64)
    out = to_float_rgb(img)
    assert out.dtype == np.float32
    assert np.isfinite(out).all()
    assert out.min() >= 0.0 and out.max() <= 1.0


@pytest.mark.parametrize("shape", [(4, 4, 2), (4, 4, 5), (4,), (2, 2, 2, 3)])
def test_bad_shapes_raise(shape):
    with pytest.raises(VoodooError):
        to_float_rgb(np.zeros(shape))


def test_uint8_bgr_round_trip():
    img = painted_foam(30, 40)
    back = to_float_rgb(to_uint8_bgr(img), bgr=True)
    np.testing.assert_allclose(back, img, atol=0.5 / 255 + 1e-6)


def test_png_round_trip(tmp_path):
    img = painted_foam(30, 40)
    write_image(tmp_path / "a.png", img)
    np.testing.assert_allclose(read_image(tmp_path / "a.png"), img, atol=0.5 / 255 + 1e-6)


def test_read_image_of_a_video_is_its_first_frame(tmp_path):
    frames = [painted_foam(24, 32, seed=s) for s in range(3)]
    write_frames(tmp_path / "v.avi", frames)
    np.testing.assert_allclose(read_image(tmp_path / "v.avi"), frames[0], atol=0.5 / 255 + 1e-6)


def test_missing_and_unreadable_pictures_raise(tmp_path):
    with pytest.raises(VoodooError):
        read_image(tmp_path / "nope.png")
    (tmp_path / "bad.png").write_text("not a picture")
    with pytest.raises(VoodooError):
        read_image(tmp_path / "bad.png")


def test_unwritable_picture_raises(tmp_path):
    with pytest.raises(VoodooError):
        write_image(tmp_path / "no" / "dir" / "a.png", painted_foam(8, 8))
