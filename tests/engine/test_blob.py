"""The active blob: building it, and saving/loading it without pickles."""

from __future__ import annotations

import dataclasses
import io
import zipfile

import cv2
import numpy as np
import pytest

from voodoo_addon.blob.build import BlobOptions, build_blob
from voodoo_addon.blob.model import (
    FORMAT_KIND,
    FORMAT_VERSION,
    ActiveBlob,
    blob_from_bytes,
    blob_to_bytes,
    load_blob,
    save_blob,
)
from voodoo_addon.errors import VoodooError

FIELD_NAMES = [f.name for f in dataclasses.fields(ActiveBlob) if f.name != "warnings"]


def _npz_bytes(**arrays) -> bytes:
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def _arrays(blob) -> dict:
    """The blob's file contents as a dict of arrays (to tamper with)."""
    with np.load(io.BytesIO(blob_to_bytes(blob)), allow_pickle=False) as npz:
        return {k: npz[k] for k in npz.files}


def assert_same_blob(a: ActiveBlob, b: ActiveBlob):
    for name in FIELD_NAMES:
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        assert x.dtype == y.dtype, name
        assert x.shape == y.shape, name
        np.testing.assert_array_equal(x, y, err_msg=name)
        assert type(getattr(a, name)) is type(getattr(b, name)), name


# ------------------------------------------------------------------------- building


def test_blob_contents(blob, foam):
    _, frame, contour = foam
    m, k = blob.n_nodes, blob.n_modes
    assert blob.vertices.shape == (m, 2) and blob.vertices.dtype == np.float64
    assert blob.triangles.dtype == np.int32 and blob.triangles.max() == m - 1
    assert blob.mass.shape == blob.stiffness.shape == (2 * m, 2 * m)
    assert blob.modes.shape == (2 * m, k) and k == 20
    assert blob.labels.shape == (k,) and blob.labels.dtype.kind == "U"
    assert blob.texture.dtype == np.float32 and blob.texture.ndim == 3
    np.testing.assert_array_equal(blob.frame_size, [320, 240])
    np.testing.assert_allclose(blob.centre, blob.pixel_coords.mean(axis=0))
    assert blob.length > 0 and blob.width > 0
    # The template crop is pixel-aligned and covers every template pixel.
    assert blob.texture_origin.dtype == np.int64
    assert (blob.texture_origin % 16 == 0).all()
    local = blob.pixel_coords - blob.texture_origin
    assert local.min() >= 0
    assert (local.max(axis=0) < [blob.texture.shape[1], blob.texture.shape[0]]).all()
    # Template = the blurred frame at the template pixels.
    blurred = cv2.GaussianBlur(frame, (0, 0), blob.blur_sigma, borderType=cv2.BORDER_REFLECT)
    xy = blob.pixel_coords.astype(int)
    np.testing.assert_allclose(blob.template, blurred[xy[:, 1], xy[:, 0]], atol=0.02)
    assert blob.template.shape == (blob.n_pixels, 3)
    assert blob.warnings == ()


def test_blob_outline_stays_close_to_the_user_contour(blob, foam, poly_distance):
    _, _, contour = foam
    assert poly_distance(contour, blob.contour).max() <= BlobOptions().simplify_tolerance + 1e-9


def test_deformed_and_mode_shape(blob):
    np.testing.assert_array_equal(blob.deformed(np.zeros(blob.n_modes)), blob.vertices)
    amp = np.zeros(blob.n_modes)
    amp[2] = 3.0
    np.testing.assert_allclose(blob.deformed(amp), blob.vertices + 3.0 * blob.mode_shape(2))
    assert blob.mode_shape(0).shape == (blob.n_nodes, 2)


def test_interpolant_is_delta_at_the_nodes(blob):
    np.testing.assert_allclose(blob.interpolant(blob.vertices), np.eye(blob.n_nodes), atol=1e-6)


@pytest.mark.parametrize("n_modes", [0, 4, 20])
def test_mode_count_option(foam, n_modes):
    _, frame, contour = foam
    b = build_blob(frame, contour, BlobOptions(n_modes=n_modes))
    assert b.n_modes == n_modes == len(b.labels) == len(b.mode_stiffness)


def test_too_many_modes_are_clamped_with_a_warning(foam):
    _, frame, contour = foam
    b = build_blob(frame, contour, BlobOptions(n_modes=10_000))
    assert b.n_modes == 2 * b.n_nodes - 4
    assert any("modes" in w for w in b.warnings)


@pytest.mark.parametrize(
    "frame",
    [
        np.zeros((240, 320, 3), np.uint8),
        np.zeros((240, 320), np.float32),
        np.zeros((240, 320, 4), np.float32),
        np.zeros((240, 320, 3), np.float64),
    ],
    ids=["uint8", "gray", "rgba", "float64"],
)
def test_bad_frame_raises(foam, frame):
    _, _, contour = foam
    with pytest.raises(VoodooError):
        build_blob(frame, contour)


@pytest.mark.parametrize(
    "contour",
    [
        [(10, 10), (20, 20)],
        [(0, 0), (50, 50), (50, 0), (0, 50)],
        [(300, 100), (400, 100), (400, 200), (300, 200)],
        [(10, 10), (100, np.nan), (100, 100)],
    ],
    ids=["two-points", "bow-tie", "off-frame", "nan"],
)
def test_bad_contour_raises(foam, contour):
    _, frame, _ = foam
    with pytest.raises(VoodooError):
        build_blob(frame, contour)


def test_negative_mode_count_raises(foam):
    _, frame, contour = foam
    with pytest.raises(VoodooError):
        build_blob(frame, contour, BlobOptions(n_modes=-1))


# ------------------------------------------------------------------------- persistence


def test_bytes_round_trip_is_exact(blob):
    data = blob_to_bytes(blob)
    assert isinstance(data, bytes)
    assert_same_blob(blob, blob_from_bytes(data))


def test_file_round_trip_is_exact(blob, tmp_path):
    path = tmp_path / "doll.npz"
    save_blob(path, blob)
    back = load_blob(path)
    assert_same_blob(blob, back)
    # And it still behaves like a blob.
    assert back.labels.tolist() == blob.labels.tolist()
    np.testing.assert_array_equal(back.template, blob.template)


def test_files_written_before_the_mode_stiffness_rename_still_load(blob):
    arrays = _arrays(blob)
    arrays["stiffness_penalty"] = arrays.pop("mode_stiffness")  # the name until 2026-11
    assert_same_blob(blob, blob_from_bytes(_npz_bytes(**arrays)))


def test_file_is_a_pickle_free_npz(blob, tmp_path):
    path = tmp_path / "doll.npz"
    save_blob(path, blob)
    with np.load(path, allow_pickle=False) as npz:
        assert str(npz["format_kind"]) == FORMAT_KIND
        assert int(npz["format_version"]) == FORMAT_VERSION
        for name in FIELD_NAMES:
            assert npz[name].dtype != object


def _tampered(blob, **changes) -> bytes:
    arrays = _arrays(blob)
    for k, v in changes.items():
        if v is None:
            del arrays[k]
        else:
            arrays[k] = v
    return _npz_bytes(**arrays)


def _with_nan(blob, name, value=np.nan):
    a = _arrays(blob)[name].copy()
    a.flat[len(a.flat) // 2] = value
    return _tampered(blob, **{name: a})


CORRUPTIONS = {
    "random-bytes": lambda b: np.random.default_rng(0).bytes(5000),
    "empty": lambda b: b"",
    "truncated": lambda b: blob_to_bytes(b)[: len(blob_to_bytes(b)) // 2],
    "truncated-end": lambda b: blob_to_bytes(b)[:-30],
    "other-npz": lambda b: _npz_bytes(a=np.arange(4), b=np.ones((2, 2))),
    "plain-npy": lambda b: (lambda buf: (np.save(buf, np.arange(5)), buf.getvalue())[1])(
        io.BytesIO()
    ),
    "wrong-kind": lambda b: _tampered(b, format_kind=np.array("voodoo-take")),
    "no-header": lambda b: _tampered(b, format_kind=None, format_version=None),
    "version-2": lambda b: _tampered(b, format_version=np.array(FORMAT_VERSION + 1)),
    "version-0": lambda b: _tampered(b, format_version=np.array(0)),
    "version-text": lambda b: _tampered(b, format_version=np.array("one")),
    "missing-modes": lambda b: _tampered(b, modes=None),
    "nan-modes": lambda b: _with_nan(b, "modes"),
    "nan-vertices": lambda b: _with_nan(b, "vertices"),
    "nan-texture": lambda b: _with_nan(b, "texture"),
    "inf-mass": lambda b: _with_nan(b, "mass", np.inf),
    "triangle-index-out-of-range": lambda b: _tampered(
        b, triangles=_arrays(b)["triangles"] + 10_000
    ),
    "modes-wrong-shape": lambda b: _tampered(b, modes=_arrays(b)["modes"][:-2]),
    "labels-wrong-length": lambda b: _tampered(b, labels=_arrays(b)["labels"][:-1]),
    "float-triangles": lambda b: _tampered(b, triangles=_arrays(b)["triangles"] + 0.5),
    "labels-as-numbers": lambda b: _tampered(b, labels=np.arange(b.n_modes)),
    "length-as-a-list": lambda b: _tampered(b, length=np.array([1.0, 2.0])),
    "length-zero": lambda b: _tampered(b, length=np.array(0.0)),
    "pixel-triangle-out-of-range": lambda b: _tampered(
        b, pixel_triangle=_arrays(b)["pixel_triangle"] + len(b.triangles)
    ),
    "texture-moved-off-the-pixels": lambda b: _tampered(
        b, texture_origin=_arrays(b)["texture_origin"] + 5_000
    ),
    "mass-of-other-nodes": lambda b: _tampered(b, mass=np.eye(2 * b.n_nodes + 2)),
    "nan-scalar": lambda b: _tampered(b, width=np.array(np.nan)),
    "huge-declared-size": lambda b: _declared_huge(blob_to_bytes(b)),
}


def _declared_huge(data: bytes) -> bytes:
    """The archive with one member claiming to unpack to 100 GB (a damaged size field)."""
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(data)) as src, zipfile.ZipFile(out, "w") as dst:
        for info in src.infolist():
            dst.writestr(info, src.read(info))
    raw = bytearray(out.getvalue())
    # Patch the uncompressed size of the first central-directory entry.
    at = raw.find(b"PK\x01\x02")
    raw[at + 24 : at + 28] = (0xFFFFFFF0).to_bytes(4, "little")
    return bytes(raw)


@pytest.mark.parametrize("make", CORRUPTIONS.values(), ids=CORRUPTIONS.keys())
def test_corrupt_data_raises(blob, make):
    with pytest.raises(VoodooError, match="not a Voodoo blob|corrupt|incomplete|version"):
        blob_from_bytes(make(blob))


def test_corrupt_file_raises_with_the_file_name(blob, tmp_path):
    path = tmp_path / "broken.npz"
    path.write_bytes(blob_to_bytes(blob)[:1000])
    with pytest.raises(VoodooError, match="broken.npz"):
        load_blob(path)


def test_a_zip_that_is_not_an_npz_raises(tmp_path):
    path = tmp_path / "x.npz"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("hello.txt", "not an array")
    with pytest.raises(VoodooError):
        load_blob(path)


class _Trap:
    """Pickles to a call that creates a marker file when unpickled."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        import pathlib

        return (pathlib.Path.touch, (pathlib.Path(self.marker),))


@pytest.mark.parametrize("field", ["modes", "labels", "format_kind"])
def test_object_arrays_are_rejected_not_unpickled(blob, tmp_path, field):
    marker = tmp_path / "pwned"
    trap = np.empty(1, dtype=object)
    trap[0] = _Trap(marker)
    path = tmp_path / "evil.npz"
    path.write_bytes(_tampered(blob, **{field: trap}))
    # The payload is real: loading with pickles allowed would run it.
    with np.load(path, allow_pickle=True) as npz:
        npz[field]
    assert marker.exists()
    marker.unlink()
    with pytest.raises(VoodooError):
        load_blob(path)
    assert not marker.exists()


def test_missing_file_raises(tmp_path):
    with pytest.raises(VoodooError):
        load_blob(tmp_path / "nope.npz")


def test_unwritable_path_raises(blob, tmp_path):
    with pytest.raises(VoodooError):
        save_blob(tmp_path / "no" / "such" / "dir" / "b.npz", blob)
