"""How well a registration fits: the per-frame confidence."""

from __future__ import annotations

import numpy as np

from .decomposition import Evaluation
from .level import Level

#: Pixels the confidence's correlation is computed on (an even subsample).
CONFIDENCE_SAMPLES = 2000

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
