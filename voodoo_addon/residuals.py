"""One registration step's numbers: the robust difference image, the update, the confidence.

These are the per-iteration pieces of the tracker (paper §5): warp the frame back onto the
template, turn the difference into the Eq. 16 robust values, find the blocks and pixels an
occluder spoils, solve for the parameter update, and judge the final fit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .levels import Level, Solver
from .norms import RobustNorm
from .params import ParamLayout
from .warp import WarpBackend

_ONES3 = np.ones(3, dtype=np.float32)
#: Pixels the confidence's correlation is computed on (an even subsample).
CONFIDENCE_SAMPLES = 2000


@dataclass
class Evaluation:
    """One evaluation of the warp at one level."""

    samples: np.ndarray  # (n, 3) float32
    dbar: np.ndarray  # (n, 3) float32 robust differences
    valid: np.ndarray  # (n,) bool: inside the picture
    use: np.ndarray  # (n,) bool: taken into the solve (valid, not occluded)
    block_weight: np.ndarray  # (n_blocks,) 0/1
    residual: float
    weighted: bool


def evaluate(
    level: Level,
    a: np.ndarray,
    origin: np.ndarray,
    box: np.ndarray,
    backend: WarpBackend,
    norm: RobustNorm,
    layout: ParamLayout,
    outlier_factor: float,
    floor: float,
    nodes: np.ndarray | None = None,
) -> Evaluation | None:
    """Warp, sample and compare at ``a``: the robust difference image (Eq. 12, 16).

    Parameters
    ----------
    level : Level
    a : (P,) float64
        Parameters.
    origin : (2,) float32
        Level pixel of the bound picture's top-left corner.
    box : (2,) float32
        Largest valid (x, y) in the bound picture.
    backend, norm, layout
        The tracker's warp backend, norm and parameter layout.
    outlier_factor, floor : float
        A block whose mean robust error exceeds ``outlier_factor * max(median, floor)`` is
        occluded (full resolution only).
    nodes : (m, 2) float64, optional
        ``level.nodes(a)`` when the caller has them.

    Returns
    -------
    Evaluation or None
        None when too little of the blob is on the picture to compare.
    """
    n = len(level)
    if nodes is None:
        nodes = level.nodes(a)
    pos = level.positions(a, nodes)
    pos -= origin[:, None]
    x, y = pos[0, :n], pos[1, :n]
    if x.min() >= 0 and y.min() >= 0 and x.max() <= box[0] and y.max() <= box[1]:
        valid, n_valid = None, n
    else:
        valid = (x >= 0) & (y >= 0) & (x <= box[0]) & (y <= box[1])
        n_valid = int(np.count_nonzero(valid))
        if n_valid < 0.15 * n:
            return None
    samples = backend.sample(level.geometry, nodes - origin, pos)
    c, b = layout.channel_gain_offset(a)
    inv_c = (1.0 / c).astype(np.float32)
    # d = I0 - (S - b) / c, then Eq. 16: dbar = sign(d) sqrt(rho(d)).
    d = np.multiply(samples, inv_c)
    np.subtract(level.template, d, out=d)
    d += (b / c).astype(np.float32)
    rho = norm.rho(d)
    dbar = np.sqrt(rho)
    np.copysign(dbar, d, out=dbar)
    loss = rho @ _ONES3  # per pixel, summed over channels (faster than .sum(axis=1))
    valid_all = valid is None
    if valid_all:
        valid = level.all_valid
    nb = level.n_blocks
    if valid_all:
        r_block = np.bincount(level.block, weights=loss, minlength=nb) / level.block_size
        seen = np.ones(nb, dtype=bool)
    else:
        vcount = np.bincount(level.block, weights=valid, minlength=nb)
        vsum = np.bincount(level.block, weights=loss * valid, minlength=nb)
        seen = vcount >= 0.5 * level.block_size
        r_block = np.where(seen, vsum / np.maximum(vcount, 1.0), 0.0)
    weight = seen.astype(np.float64)
    use = valid
    # Occlusion rejection only at full resolution: on coarse levels a block that is merely
    # misaligned looks occluded, and dropping it loses the texture that would align it.
    if seen.any() and level.index == 0:
        med = float(np.median(r_block[seen]))
        limit = outlier_factor * max(med, floor)
        out = seen & (r_block > limit)
        if out.any() and out.sum() <= 0.5 * seen.sum():
            weight[out] = 0.0
            # Something covers part of the blob: also drop its stray pixels from the
            # blocks that stay (their rows come out of the Gram matrix exactly).
            use = valid & (weight[level.block] > 0) & (loss <= limit)
    if use is valid and not weight.all():
        use = valid & (weight[level.block] > 0)
    weighted = use is not level.all_valid
    if weighted:
        n_use = int(np.count_nonzero(use))
        if n_use == 0:
            return None
        residual = float(loss[use].mean())
    else:
        residual = float(loss.mean())
    return Evaluation(samples, dbar, valid, use, weight, residual, weighted)


def solve(solver: Solver, level: Level, ev: Evaluation, a_act: np.ndarray) -> np.ndarray:
    """Parameter update (active parameters) from one evaluation.

    Unweighted: the precomputed ``N B+`` of Eq. 14-15 with the Eq. 10 prior. Weighted
    (occlusion, blob partly off the picture): the same least squares on the collapsed
    basis restricted to the used pixels, with the Gram matrix assembled from per-block
    Gram matrices minus the rows of the dropped pixels of kept blocks.
    """
    if not ev.weighted:
        return solver.update @ ev.dbar.ravel() - solver.prior @ a_act
    gram = np.tensordot(ev.block_weight, solver.block_gram, axes=1)
    gone = np.nonzero((ev.block_weight[level.block] > 0) & ~ev.use)[0]
    if len(gone):
        rows = (3 * gone[:, None] + np.arange(3)).ravel()
        jg = solver.jacobian[rows].astype(np.float64)
        gram = gram - jg.T @ jg
    rhs = solver.jacobian.T @ (ev.dbar * ev.use[:, None]).ravel()
    rhs = rhs - solver.reg * a_act
    try:
        return np.linalg.solve(gram + solver.penalty, rhs)
    except np.linalg.LinAlgError:
        return np.zeros_like(a_act)


def confidence(level: Level, ev: Evaluation) -> float:
    """Correlation of template and frame over the visible pixels, times visibility.

    Per-channel normalised cross-correlation (so insensitive to the lighting model),
    averaged with the template's channel variances as weights, on an even subsample.
    """
    step = max(1, len(ev.valid) // CONFIDENCE_SAMPLES)
    t = level.template[::step]
    s = ev.samples[::step]
    if ev.valid is level.all_valid:
        visible = 1.0
    else:
        visible = float(np.count_nonzero(ev.valid)) / len(ev.valid)
        v = ev.valid[::step]
        if np.count_nonzero(v) < 10:
            return 0.0
        t, s = t[v], s[v]
    k = len(t)
    st, ss = t.sum(axis=0), s.sum(axis=0)
    var_t = np.einsum("ij,ij->j", t, t) - st * st / k
    var_s = np.einsum("ij,ij->j", s, s) - ss * ss / k
    cov = np.einsum("ij,ij->j", t, s) - st * ss / k
    den = np.sqrt(np.maximum(var_t * var_s, 0.0))
    ok = den > 1e-9
    if not ok.any():
        return 0.0
    ncc = float((cov[ok] / den[ok] * var_t[ok]).sum() / var_t[ok].sum())
    return float(np.clip(ncc, 0.0, 1.0) * min(1.0, visible / 0.75))
