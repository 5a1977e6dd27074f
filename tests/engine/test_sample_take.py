"""The bundled sample take: footage the tracker was not designed on (rendered by Blender,
H.264-compressed), against the true positions of the slab exported with it."""

import numpy as np
import pytest

from voodoo_addon.devtools.bench import SAMPLES, lattice_truth, run_sample_take


def test_lattice_truth_is_exact_on_its_own_points():
    lattice = np.load(SAMPLES / "sample_truth.npz")["lattice"]
    truth = lattice_truth(SAMPLES / "sample_truth.npz")
    points = lattice[0].reshape(-1, 2).astype(np.float64)
    for i in (0, 45, 149):
        np.testing.assert_allclose(truth(i, points), lattice[i].reshape(-1, 2), atol=1e-4)


@pytest.mark.slow
def test_sample_take_is_tracked_far_better_than_klt():
    row = run_sample_take()
    assert row is not None, "the sample take or its truth is missing"
    assert row["frames"] == 150
    assert row["error_px"] < 0.3  # measured 0.12 px
    assert row["max_error_px"] < 0.6
    assert row["error_px"] * 5 < row["klt_error_px"]
