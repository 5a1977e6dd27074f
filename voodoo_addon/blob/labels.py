"""Readable names for modes: fit each mode with analytic displacement fields of rising order.

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

#: A mode is named after one family of fields when that family's share of it is at least
#: this ...
SINGLE_SHARE = 0.4
#: ... or "a+b" after two families whose shares add up to at least this.
PAIR_SHARE = 0.6

#: Orders of the library: every catalogue field f also comes as f times these envelopes
#: (in normalised coordinates), order by order. Modes are mixtures of a field and its own
#: higher-order variants (a bend whose curvature grows towards the ends, a shear stronger at
#: the rim); fitting the family ``{f e}`` names them after ``f``.
ENVELOPES: tuple[tuple[Callable[[np.ndarray, np.ndarray], np.ndarray], ...], ...] = (
    (lambda x, y: 1.0 + 0 * x,),
    (lambda x, y: x * x, lambda x, y: y * y),
    (lambda x, y: x**4, lambda x, y: x * x * y * y, lambda x, y: y**4),
)


def field_matrix(nodes: np.ndarray, centre: np.ndarray, length: float) -> tuple[list, np.ndarray]:
    """Every catalogue field at the nodes.

    Returns
    -------
    names : list of str
    fields : (2m, n_fields) float64
        Interleaved nodal vectors.
    """
    return _fields(nodes, centre, length, ENVELOPES[:1])


def _fields(nodes, centre, length, orders) -> tuple[list, np.ndarray]:
    """The catalogue times every envelope of ``orders``, order by order: names and columns."""
    d = (nodes - centre) / length
    x, y = d[:, 0], d[:, 1]
    names, cols = [], []
    for envelopes in orders:
        for name, fn in FIELDS.items():
            u, v = fn(x, y)
            for env in envelopes:
                e = env(x, y)
                cols.append(np.column_stack([u * e, v * e]).ravel())
                names.append(name)
    return names, np.column_stack(cols)


def _family_basis(fields, names, mass, constrained):
    """M-orthonormal basis of the library in order, each vector owned by a family.

    Gram-Schmidt (twice, for stability) in the M inner product, the constrained part taken
    out first. A column adding nothing new is dropped; so is every column of a family whose
    own field (the first column) is already spanned -- skew-x once shear is there, scale when
    it is separated -- so that no mode is named after a field the blob cannot show.
    """
    fields = fields - constrained @ (constrained.T @ mass @ fields)
    norms = np.sqrt(np.einsum("ij,ij->j", fields, mass @ fields))
    tiny = 1e-6 * norms.max()
    basis = np.zeros((len(fields), 0))
    m_basis = np.zeros((len(fields), 0))
    owners, dead = [], set()
    for i, name in enumerate(names):
        if name in dead:
            continue
        v = fields[:, i]
        for _ in range(2):
            v = v - basis @ (m_basis.T @ v)
        mv = mass @ v
        norm = np.sqrt(max(float(v @ mv), 0.0))
        if norm <= max(tiny, 1e-4 * norms[i]):
            if name not in owners:
                dead.add(name)
            continue
        basis = np.column_stack([basis, v / norm])
        m_basis = np.column_stack([m_basis, mv / norm])
        owners.append(name)
    return basis, m_basis, owners


def label_modes(
    shapes: np.ndarray,
    mass: np.ndarray,
    constrained: np.ndarray,
    nodes: np.ndarray,
    centre: np.ndarray,
    length: float,
) -> tuple[list[str], np.ndarray, np.ndarray]:
    """Name modes and fix their signs.

    Each mode is fitted against a library of analytic fields of increasing order: the
    catalogue (:data:`FIELDS`), then each field times the :data:`ENVELOPES` of order 2 and
    4. The library, with the constrained (similarity) part removed, is Gram-Schmidt-
    orthonormalised in the M inner product in that order; a mode's share of a basis vector
    is its squared M-projection on it, and a family's share (a field and its higher-order
    variants) is the sum over the family's vectors. Shares add up to at most 1: the fraction
    of the mode's energy the family explains beyond the fields before it. The family with
    the largest share names the mode.

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
        Unique names ("bend-x", "bend-x 2" for the next mode best named bend-x,
        "bend-x+taper-y"), "mode j" (1-based) when no family or pair of families explains
        enough of the mode.
    signs : (k,) float64
        +1 or -1; multiply the modes by these so a positive amplitude follows the named
        field (the mode correlates positively with it).
    share : (k,) float64
        The share (single or pair) that justified the name; 0 for "mode j".
    """
    names, fields = _fields(nodes, centre, length, ENVELOPES)
    basis, m_basis, owners = _family_basis(fields, names, mass, constrained)
    families = list(dict.fromkeys(owners))
    coef = shapes.T @ m_basis  # (k, n_basis)
    owner = np.array([families.index(o) for o in owners])
    share = np.zeros((shapes.shape[1], len(families)))
    np.add.at(share.T, owner, (coef**2).T)
    # Sign: the mode's correlation with the family's own field (its first column).
    own = fields[:, [names.index(f) for f in families]]
    own = own - constrained @ (constrained.T @ mass @ own)
    corr = shapes.T @ mass @ own  # (k, n_families)
    labels, signs, score = [], np.ones(shapes.shape[1]), np.zeros(shapes.shape[1])
    used: set[str] = set()
    for j in range(shapes.shape[1]):
        order = np.argsort(-share[j], kind="stable")
        a, b = order[0], order[1]
        if share[j, a] >= SINGLE_SHARE:
            name, score[j] = families[a], share[j, a]
        elif share[j, a] + share[j, b] >= PAIR_SHARE:
            name, score[j] = f"{families[a]}+{families[b]}", share[j, a] + share[j, b]
        else:
            name = f"mode {j + 1}"
        if score[j] > 0:
            signs[j] = 1.0 if corr[j, a] >= 0 else -1.0
        labels.append(_unique(name, used))
    return labels, signs, score


def _unique(name: str, used: set) -> str:
    """``name``, or ``name 2``, ``name 3``, ... whichever is free; marked as used."""
    out, k = name, 1
    while out in used:
        k += 1
        out = f"{name} {k}"
    used.add(out)
    return out
