"""Mode labels: a mode called "bend-x" bends along x, and names come back for pure fields."""

from __future__ import annotations

import numpy as np
import pytest

from voodoo_addon.blob.build import BlobOptions, build_blob
from voodoo_addon.blob.labels import FIELDS, SINGLE_SHARE, field_matrix, label_modes


def _field(blob, name):
    """The named analytic field at the blob's nodes, constrained part removed, M-unit."""
    names, fields = field_matrix(blob.vertices, blob.centre, blob.length)
    f = fields[:, names.index(name)]
    r, m = blob.constrained, blob.mass
    f = f - r @ (r.T @ m @ f)
    return f / np.sqrt(f @ m @ f)


def _cosine(blob, j, name):
    return float(blob.modes[:, j] @ blob.mass @ _field(blob, name))


def _label_one(blob, f):
    """Name one displacement field on the blob's mesh: (labels, signs, share)."""
    return label_modes(
        f[:, None], blob.mass, blob.constrained, blob.vertices, blob.centre, blob.length
    )


@pytest.mark.parametrize("name", ["stretch-x", "shear", "bend-x", "bend-y"])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_pure_fields_get_their_own_names(blob, name, sign):
    f = sign * _field(blob, name)
    labels, signs, share = _label_one(blob, f)
    assert labels == [name]
    assert signs[0] == sign
    assert share[0] > 0.95


def test_random_field_gets_no_name(blob):
    rng = np.random.default_rng(0)
    f = rng.normal(size=len(blob.mass))
    r, m = blob.constrained, blob.mass
    f = f - r @ (r.T @ m @ f)
    f /= np.sqrt(f @ m @ f)
    labels, signs, share = label_modes(f[:, None], m, r, blob.vertices, blob.centre, blob.length)
    assert labels == ["mode 1"]
    assert share[0] == 0.0


def test_field_matrix_layout(blob):
    names, fields = field_matrix(blob.vertices, blob.centre, blob.length)
    assert names == list(FIELDS)
    assert fields.shape == (2 * blob.n_nodes, len(FIELDS))
    d = (blob.vertices - blob.centre) / blob.length
    bend = fields[:, names.index("bend-x")].reshape(-1, 2)
    np.testing.assert_allclose(bend[:, 0], -2 * d[:, 0] * d[:, 1])
    np.testing.assert_allclose(bend[:, 1], d[:, 0] ** 2)


@pytest.mark.parametrize("blob_name", ["blob", "fe_blob", "fe_blob_scale"])
def test_labels_are_unique_and_justified(request, blob_name):
    b = request.getfixturevalue(blob_name)
    labels = list(b.labels)
    assert len(labels) == b.n_modes
    assert len(set(labels)) == len(labels)
    for lab, share in zip(labels, b.label_match, strict=True):
        if lab.startswith("mode "):
            assert share == 0.0
        elif "+" not in lab:
            assert share >= SINGLE_SHARE


@pytest.mark.parametrize("blob_name", ["blob", "fe_blob", "fe_blob_scale"])
@pytest.mark.parametrize("name", ["bend-x", "bend-y"])
def test_bend_mode_really_bends(request, blob_name, name):
    b = request.getfixturevalue(blob_name)
    labels = list(b.labels)
    assert name in labels
    j = labels.index(name)
    # Sign fixed by the label: a positive amplitude bends the named way.
    assert _cosine(b, j, name) > 0.8


@pytest.mark.parametrize("poly_degree", [0, 3])
@pytest.mark.parametrize(
    "box, axis",
    [((60, 100, 260, 140), "x"), ((140, 20, 180, 220), "y")],
    ids=["horizontal-bar", "vertical-bar"],
)
def test_softest_mode_of_a_bar_bends_along_its_long_axis(box, axis, poly_degree):
    x0, y0, x1, y1 = box
    rng = np.random.default_rng(0)
    frame = rng.uniform(0, 1, (240, 320, 3)).astype(np.float32)
    bar = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], float)
    b = build_blob(frame, bar, BlobOptions(poly_degree=poly_degree))
    name = f"bend-{axis}"
    assert b.labels[0] == name
    assert _cosine(b, 0, name) > 0.8
    # ... and clearly softer than the next mode.
    assert b.mode_stiffness[0] < 0.7 * b.mode_stiffness[1]


def test_positive_bend_x_amplitude_deflects_the_ends_down(blob):
    # bend-x is (-2xy, x^2): with y down, the ends of the blob move down relative to the middle.
    j = list(blob.labels).index("bend-x")
    moved = blob.deformed(np.eye(blob.n_modes)[j] * 5.0)
    dy = moved[:, 1] - blob.vertices[:, 1]
    x = blob.vertices[:, 0] - blob.centre[0]
    far = np.abs(x) > 0.7 * np.abs(x).max()
    mid = np.abs(x) < 0.2 * np.abs(x).max()
    assert dy[far].mean() > dy[mid].mean() + 1.0


# ------------------------------------------------------------------ higher-order modes


def _variant(blob, name, envelope):
    """The named field times an envelope of the normalised coordinates, M-unit."""
    d = (blob.vertices - blob.centre) / blob.length
    u, v = FIELDS[name](d[:, 0], d[:, 1])
    e = envelope(d[:, 0], d[:, 1])
    f = np.column_stack([u * e, v * e]).ravel()
    r, m = blob.constrained, blob.mass
    f = f - r @ (r.T @ m @ f)
    return f / np.sqrt(f @ m @ f)


@pytest.mark.parametrize("blob_name", ["blob", "fe_blob"])
def test_a_typical_blob_leaves_at_most_two_modes_unnamed(request, blob_name):
    # Twenty modes of an elliptical foam blob: the higher ones are fields of order 4-6
    # (a bend whose curvature grows outwards, a shear stronger at the rim), named after the
    # family they belong to; before, eight to ten of them were "mode N".
    b = request.getfixturevalue(blob_name)
    assert b.n_modes == 20
    unnamed = [lab for lab in b.labels if lab.startswith("mode ")]
    assert len(unnamed) <= 2, list(b.labels)


@pytest.mark.parametrize("name", ["bend-x", "bend-y", "shear"])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_higher_order_variant_is_named_after_its_field(blob, name, sign):
    f = sign * _variant(blob, name, lambda x, y: x * x + y * y)
    labels, signs, share = _label_one(blob, f)
    assert labels == [name]
    assert signs[0] == sign
    assert share[0] > 0.8


def test_a_second_mode_of_the_same_family_gets_a_number(blob):
    first = _field(blob, "bend-x")
    second = _variant(blob, "bend-x", lambda x, y: x * x + y * y)
    shapes = np.column_stack([first, second])
    labels, _, share = label_modes(
        shapes, blob.mass, blob.constrained, blob.vertices, blob.centre, blob.length
    )
    assert labels == ["bend-x", "bend-x 2"]
    assert (share > 0.8).all()
