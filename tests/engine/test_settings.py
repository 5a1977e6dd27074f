"""Settings a person types: NaN, infinity and out-of-range values are refused by name.

A NaN gain once wrote NaN into a shape key; an infinite one was kept by Blender as 3.4e38.
Every number of the blob's and the tracker's options, and every gain, goes through
voodoo_addon.checks before it reaches arithmetic.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from voodoo_addon.blob.build import BlobOptions
from voodoo_addon.errors import VoodooError
from voodoo_addon.takes.rig import MAX_GAIN, Rig, check_gain
from voodoo_addon.tracking.options import TrackerOptions
from voodoo_addon.tracking.params import ParamLayout

NON_FINITE = [float("nan"), float("inf"), float("-inf")]


def _numeric_fields(cls):
    defaults = cls()
    return [
        f.name
        for f in dataclasses.fields(cls)
        if isinstance(getattr(defaults, f.name), int | float)
        and not isinstance(getattr(defaults, f.name), bool)
    ]


@pytest.mark.parametrize("value", NON_FINITE, ids=["nan", "inf", "-inf"])
@pytest.mark.parametrize("field", _numeric_fields(BlobOptions))
def test_blob_options_refuse_non_finite_numbers(field, value):
    with pytest.raises(VoodooError, match=r"(?i)finite|whole"):
        BlobOptions(**{field: value})


@pytest.mark.parametrize("value", NON_FINITE, ids=["nan", "inf", "-inf"])
@pytest.mark.parametrize("field", _numeric_fields(TrackerOptions))
def test_tracker_options_refuse_non_finite_numbers(field, value):
    with pytest.raises(VoodooError, match=r"(?i)finite|whole"):
        TrackerOptions(**{field: value})


@pytest.mark.parametrize(
    "kwargs",
    [
        {"n_modes": -1},
        {"n_modes": 2.5},
        {"min_angle": 40.0},
        {"max_area": 0.0},
        {"max_area": -5.0},
        {"simplify_tolerance": -1.0},
        {"blur_sigma": -1.0},
        {"poisson": 0.5},
        {"width_factor": 0.0},
        {"poly_degree": -1},
        {"poly_degree": 99},
        {"n_modes": "twenty"},
    ],
    ids=str,
)
def test_blob_options_refuse_out_of_range_values(kwargs):
    with pytest.raises(VoodooError):
        BlobOptions(**kwargs)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"sigma": 0.0},
        {"gamma": -1.0},
        {"max_levels": 0},
        {"max_iterations": 0},
        {"lost_below": 1.5},
        {"refine_below": -0.1},
        {"pixel_budget": -10},
        {"pixel_outlier": -1.0},
        {"lighting": "sunny"},
    ],
    ids=str,
)
def test_tracker_options_refuse_out_of_range_values(kwargs):
    with pytest.raises(VoodooError):
        TrackerOptions(**kwargs)


def test_valid_options_are_kept_as_plain_numbers():
    opt = BlobOptions(n_modes=np.int64(12), min_angle=np.float32(20.0), max_area=None)
    assert opt.n_modes == 12 and type(opt.n_modes) is int
    assert type(opt.min_angle) is float
    assert TrackerOptions(pixel_budget=None).pixel_budget is None
    assert TrackerOptions(max_levels=2.0).max_levels == 2


# ------------------------------------------------------------------------------------ gains


@pytest.fixture(scope="module")
def rig(blob):
    rest = np.zeros((blob.n_nodes, 3))
    rest[:, 0] = blob.vertices[:, 0] * 0.01
    rest[:, 2] = -blob.vertices[:, 1] * 0.01
    return Rig(blob, ParamLayout(tuple(blob.labels)), rest, "XZ", modes=[0, 1, 2])


@pytest.mark.parametrize("gain", [*NON_FINITE, 3.4e38, -1e6, MAX_GAIN * 1.01, "2"])
def test_bad_gain_is_refused_by_name_and_never_reaches_the_mesh(rig, gain):
    name = str(rig.blob.labels[1])
    with pytest.raises(VoodooError, match="gain") as err:
        rig.shape(1, gain)
    assert name in str(err.value)
    gains = [1.0, gain, 1.0]
    with pytest.raises(VoodooError, match="gain"):
        rig.vertices(ParamLayout(tuple(rig.blob.labels)).identity(), gains)


def test_good_gains_scale_the_shapes(rig):
    np.testing.assert_allclose(rig.shape(2, -2.5), rig.rest - 2.5 * rig.offsets[2])
    np.testing.assert_allclose(rig.shape(0), rig.rest + rig.offsets[0])
    layout = ParamLayout(tuple(rig.blob.labels))
    a = layout.identity()
    a[layout.modes.start : layout.modes.start + 3] = 3.0
    v = rig.vertices(a, [0.0, 0.0, 0.0])
    np.testing.assert_allclose(v, rig.vertices(layout.identity()))
    assert np.isfinite(rig.vertices(a, np.array([MAX_GAIN, -MAX_GAIN, 1.0]))).all()


def test_wrong_number_of_gains_is_refused(rig):
    with pytest.raises(VoodooError, match="gains for 3 modes"):
        rig.vertices(ParamLayout(tuple(rig.blob.labels)).identity(), [1.0, 1.0])


def test_check_gain_passes_plain_floats():
    assert check_gain(np.float32(1.5), "bend-x") == 1.5
    assert type(check_gain(np.int64(2))) is float
