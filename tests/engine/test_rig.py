"""A take laid on a target mesh: the mapping, the mode shapes (Eq. 17) and every frame's pose."""

import numpy as np
import pytest

from voodoo_addon.blob import build_blob
from voodoo_addon.devtools.scenarios import scenario_take
from voodoo_addon.errors import VoodooError
from voodoo_addon.takes.rig import UNIT_FRACTION, Rig, fit_mapping, mapping_from_list
from voodoo_addon.tracking.params import ParamLayout, node_positions


@pytest.fixture(scope="module")
def blob():
    frames, contour, _ = scenario_take("bend", frames=1, size=(320, 240))
    return build_blob(frames[0], contour)


def doll_on_xz(blob, scale=0.01):
    """A target whose vertices sit exactly on the doll's nodes, in its XZ plane."""
    v = np.zeros((blob.n_nodes, 3))
    v[:, 0] = blob.vertices[:, 0] * scale
    v[:, 2] = -blob.vertices[:, 1] * scale  # image down is -Z
    return v


def test_a_target_on_the_doll_nodes_moves_exactly_like_them(blob):
    layout = ParamLayout(tuple(blob.labels))
    rest = doll_on_xz(blob)
    rig = Rig(blob, layout, rest, "XZ")
    assert rig.mapping.scale == pytest.approx(0.01)
    rng = np.random.default_rng(0)
    a = layout.identity()
    a[:4] = (7.0, -3.0, 0.4, 0.2)
    a[layout.modes] = rng.normal(0, 2.0, blob.n_modes)
    moved = rig.vertices(a)
    nodes = node_positions(a, layout, blob.vertices, blob.modes, blob.centre)
    np.testing.assert_allclose(moved[:, 0], nodes[:, 0] * 0.01, atol=1e-9)
    np.testing.assert_allclose(moved[:, 2], -nodes[:, 1] * 0.01, atol=1e-9)
    np.testing.assert_allclose(moved[:, 1], 0.0, atol=1e-12)


def test_values_are_mode_amplitudes_in_doll_units(blob):
    layout = ParamLayout(tuple(blob.labels))
    rig = Rig(blob, layout, doll_on_xz(blob), "XZ", modes=[2, 0])
    a = layout.identity()
    a[layout.modes.start + 0] = 3.0
    a[layout.modes.start + 2] = -1.5
    unit = UNIT_FRACTION * blob.length
    np.testing.assert_allclose(rig.values(a), [-1.5 / unit, 3.0 / unit])
    frames = np.stack([a, 2 * a])
    assert rig.values(frames).shape == (2, 2)
    assert rig.offsets.shape == (2, blob.n_nodes, 3)


def test_switched_off_rigid_motion_leaves_the_target_in_place(blob):
    layout = ParamLayout(tuple(blob.labels))
    rig = Rig(blob, layout, doll_on_xz(blob), "XZ", modes=[], use=(False, False, False))
    a = layout.identity()
    a[:4] = (30.0, 12.0, 1.0, 0.5)
    np.testing.assert_allclose(rig.pose(a)[1], np.eye(4))
    full = rig.transforms(a, use=(True, True, True))[0]
    assert not np.allclose(full, np.eye(4))


def test_a_stored_mapping_is_reused(blob):
    layout = ParamLayout(tuple(blob.labels))
    rest = doll_on_xz(blob)
    first = fit_mapping(blob, rest, "XZ")
    again = mapping_from_list(first.axes, first.as_list())
    rig = Rig(blob, layout, rest * 3.0, mapping=again)  # the target was scaled since
    assert rig.mapping == again or rig.mapping.scale == pytest.approx(first.scale)


def test_a_flat_target_is_refused(blob):
    layout = ParamLayout(tuple(blob.labels))
    with pytest.raises(VoodooError, match="flat"):
        Rig(blob, layout, doll_on_xz(blob), "XY")  # the doll lies in XZ: flat in XY


@pytest.mark.parametrize("photometric", ["channel", "global", "none"])
def test_layout_from_a_takes_names(blob, photometric):
    layout = ParamLayout(tuple(blob.labels), photometric)
    assert ParamLayout.from_names(blob.labels, layout.names) == layout
    with pytest.raises(ValueError):
        ParamLayout.from_names(blob.labels, layout.names[:-1] + ("brightness-x",))
    with pytest.raises(ValueError):
        ParamLayout.from_names(blob.labels[:-1], layout.names)
