"""Readable names for modes: project each mode onto analytic displacement fields.

Fields are written in coordinates normalised about the blob's centroid by its RMS radius,
``x`` to the right and ``y`` down (image axes). The animator picks modes by these names, so
each mode's sign is also fixed by its best field: a positive amplitude deforms the blob the
way the named field does (e.g. "stretch-x" lengthens along x).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

Field = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]

#: name -> displacement field (u, v) of normalised coordinates (x, y), in order of preference:
#: where two fields coincide once the similarity is taken out (stretch-x and stretch-y, shear and
#: the skews), the earlier name is used.
FIELDS: dict[str, Field] = {
    # Constant strain.
    "stretch-x": lambda x, y: (x, 0 * y),
    "stretch-y": lambda x, y: (0 * x, y),
    "shear": lambda x, y: (y, x),
    "skew-x": lambda x, y: (y, 0 * x),
    "skew-y": lambda x, y: (0 * y, x),
    "scale": lambda x, y: (x, y),
    # Euler-Bernoulli bending about the centroid: deflection x^2, sections stay normal.
    "bend-x": lambda x, y: (-2 * x * y, x * x),
    "bend-y": lambda x, y: (y * y, -2 * x * y),
    # Width across the axis growing linearly along it.
    "taper-x": lambda x, y: (0 * x, x * y),
    "taper-y": lambda x, y: (x * y, 0 * y),
    # Stretch growing along the axis.
    "ramp-x": lambda x, y: (x * x, 0 * y),
    "ramp-y": lambda x, y: (0 * x, y * y),
    # Rotation growing with the distance from the centre.
    "twist": lambda x, y: (-y * (x * x + y * y), x * (x * x + y * y)),
    # Radial stretch growing with the distance from the centre.
    "bulge": lambda x, y: (x * (x * x + y * y), y * (x * x + y * y)),
    # S-shaped (cubic) bending.
    "s-bend-x": lambda x, y: (-3 * x * x * y, x**3),
    "s-bend-y": lambda x, y: (y**3, -3 * x * y * y),
    # Width across the axis shrinking towards the middle (a waist).
    "pinch-x": lambda x, y: (0 * x, x * x * y),
    "pinch-y": lambda x, y: (x * y * y, 0 * y),
}

#: A mode is named after one field when that field's share of it is at least this ...
SINGLE_SHARE = 0.4
#: ... or "a+b" after two fields whose shares add up to at least this.
PAIR_SHARE = 0.6


def field_matrix(nodes: np.ndarray, centre: np.ndarray, length: float) -> tuple[list, np.ndarray]:
    """Every catalogue field at the nodes.

    Returns
    -------
    names : list of str
    fields : (2m, n_fields) float64
        Interleaved nodal vectors.
    """
    d = (nodes - centre) / length
    names, cols = [], []
    for name, fn in FIELDS.items():
        u, v = fn(d[:, 0], d[:, 1])
        cols.append(np.column_stack([u, v]).ravel())
        names.append(name)
    return names, np.column_stack(cols)


def label_modes(
    shapes: np.ndarray,
    mass: np.ndarray,
    constrained: np.ndarray,
    nodes: np.ndarray,
    centre: np.ndarray,
    length: float,
) -> tuple[list[str], np.ndarray, np.ndarray]:
    """Name modes and fix their signs.

    The catalogue fields, with the constrained (similarity) part removed, are
    Gram-Schmidt-orthonormalised in the M inner product in order of preference; a mode's share
    of field i is its squared M-projection on the i-th orthonormal field (shares add up to at
    most 1). The field with the largest share names the mode.

    Parameters
    ----------
    shapes : (2m, k) float64
        M-orthonormal elastic modes.
    mass : (2m, 2m) float64
    constrained : (2m, c) float64
        M-orthonormal fields the modes are orthogonal to.
    nodes : (m, 2) float64
    centre : (2,) float64
    length : float
        Normalising length (RMS radius).

    Returns
    -------
    labels : list of str
        Unique names ("bend-x", "bend-x 2", "bend-x+taper-y"), "mode j" (1-based) when no
        field or pair of fields explains enough of the mode.
    signs : (k,) float64
        +1 or -1; multiply the modes by these so a positive amplitude follows the named field.
    share : (k,) float64
        The share (single or pair) that justified the name; 0 for "mode j".
    """
    names, fields = field_matrix(nodes, centre, length)
    fields = fields - constrained @ (constrained.T @ mass @ fields)
    basis, kept = [], []
    scale = np.sqrt(np.einsum("ij,ij->j", fields, mass @ fields)).max()
    for i in range(fields.shape[1]):
        v = fields[:, i].copy()
        for _ in range(2):
            for e in basis:
                v -= (e @ mass @ v) * e
        norm = np.sqrt(v @ mass @ v)
        if norm > 1e-6 * scale:
            basis.append(v / norm)
            kept.append(names[i])
    coef = shapes.T @ mass @ np.column_stack(basis)  # (k, n_kept)
    share = coef**2
    labels, signs, score = [], np.ones(shapes.shape[1]), np.zeros(shapes.shape[1])
    used: dict[str, int] = {}
    for j in range(shapes.shape[1]):
        order = np.argsort(-share[j])
        a, b = order[0], order[1]
        if share[j, a] >= SINGLE_SHARE:
            name, score[j] = kept[a], share[j, a]
        elif share[j, a] + share[j, b] >= PAIR_SHARE:
            name, score[j] = f"{kept[a]}+{kept[b]}", share[j, a] + share[j, b]
        else:
            labels.append(f"mode {j + 1}")
            continue
        signs[j] = 1.0 if coef[j, a] >= 0 else -1.0
        used[name] = used.get(name, 0) + 1
        labels.append(name if used[name] == 1 else f"{name} {used[name]}")
    return labels, signs, score
