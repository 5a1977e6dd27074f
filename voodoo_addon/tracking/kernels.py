"""Compiled per-pixel loops of the tracker: one pass over the pixels where NumPy takes ten.

An evaluation of the warp touches every template pixel several times: place it on the warped
mesh, sample the frame there, subtract the template with the global lighting undone, fit and
remove each lighting patch's gain and bias, take the robust value, sum the loss per triangle.
As NumPy expressions each of those is a sweep over the whole array with its own temporary;
here each is a loop that reads a pixel once and keeps the sums in registers (Numba, compiled
ahead of the first frame and cached on disk).

Every kernel has an explicit signature, so it is compiled when this module is imported (or
loaded from Numba's cache), never in the middle of a take; the two helpers of the fold
guard's step (``_area_terms``, ``_crossing``) are compiled into it then. Shapes and meanings
follow the NumPy code they replace: :meth:`.level.Level.positions`, :class:`.warp.CpuWarp`,
:meth:`.photometry.Patches.project`, :class:`.evaluation._Comparison`,
:meth:`.refine.LocalRefiner.normal_equations` and the fold guard's step
(:class:`.folding.FoldGuard`); one more is no pixel loop, the regions of triangles a result
reports out of view (:meth:`.hidden.HiddenPart.seen`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numba as nb
import numpy as np
from numba.core import config as _numba_config

_OPTS = {"cache": True, "nogil": True, "boundscheck": False, "error_model": "numpy"}

# Numba names a function's cache after its file, not after the module it was imported as, and
# a cache written under one module name does not load under another. This file is imported
# as ``voodoo_addon.tracking.kernels`` from a checkout and under the extension's package in
# Blender (``bl_ext.<repo>.voodoo_dolls.voodoo_addon...``), so while its kernels are compiled
# (at import: every signature is explicit) the cache goes to a folder named after the module.
# Where that cannot be written, Numba falls back to the user's cache folder.
_CACHE_DIR = _numba_config.CACHE_DIR
_numba_config.CACHE_DIR = str(Path(__file__).resolve().parent / "__pycache__" / f"numba-{__name__}")


@nb.njit(
    "void(int32[:, ::1], float32[:, ::1], float64[:, ::1], float64, float64, float32[:, ::1])",
    **_OPTS,
)
def positions(corners, weights, nodes, ox, oy, out):
    """Template pixels on the warped mesh: ``out[:, i] = sum_j w_ij nodes[c_ij] - origin``.

    corners, weights : (n, 3)
        Each pixel's triangle corners and barycentric weights.
    nodes : (m, 2)
        Warped nodes.
    out : (2, n_pad)
        x in row 0, y in row 1; the padding columns (past n) repeat the last pixel.
    """
    n = corners.shape[0]
    for i in range(n):
        x = 0.0
        y = 0.0
        for j in range(3):
            c = corners[i, j]
            w = weights[i, j]
            x += w * nodes[c, 0]
            y += w * nodes[c, 1]
        out[0, i] = x - ox
        out[1, i] = y - oy
    for i in range(n, out.shape[1]):
        out[0, i] = out[0, n - 1] if n else 0.0
        out[1, i] = out[1, n - 1] if n else 0.0


@nb.njit(
    "void(float32[:, ::1], float32[:, ::1], float32[::1], float32[::1], float32[:, ::1])", **_OPTS
)
def difference(samples, template, gain, bias, out):
    """``out = template - (samples * gain - bias)``: the global lighting undone (Eq. 4).

    ``gain = 1 / c`` and ``bias = b / c`` per channel.
    """
    n, nc = samples.shape
    for i in range(n):
        for ch in range(nc):
            out[i, ch] = template[i, ch] - (samples[i, ch] * gain[ch] - bias[ch])


@nb.njit(
    "void(float32[:, ::1], float32[:, ::1], float32[::1], float32[::1], float32[:, ::1],"
    " int64[::1], boolean[::1], boolean[::1], float32[:, ::1], float64[::1])",
    **_OPTS,
)
def project(samples, target, gain, bias, template, starts, mask, textured, diff, correlation):
    """The difference image with every lighting patch's grey gain and bias removed.

    ``diff = target - (samples * gain - bias)`` (:func:`difference`), then for each patch
    ``p`` -- the pixels ``starts[p]:starts[p + 1]`` -- the gain and bias of ``template``
    that best explain it on the masked pixels are taken out (see :mod:`.photometry`); the
    pixels outside the mask come out zero. ``correlation`` (G,) receives each patch's
    correlation of frame and template (NaN where the patch is untextured or has no masked
    pixel). ``target`` is what the frame is compared with (the template, or an appearance
    adapted to recent frames); ``template`` gives the patches' lighting directions.
    """
    nc = diff.shape[1]
    for p in range(starts.shape[0] - 1):
        s1 = sd = st = std = stt = sdd = 0.0
        for i in range(starts[p], starts[p + 1]):
            if mask[i]:
                for ch in range(nc):
                    d = target[i, ch] - (samples[i, ch] * gain[ch] - bias[ch])
                    diff[i, ch] = d
                    t = template[i, ch]
                    s1 += 1.0
                    sd += d
                    st += t
                    std += t * d
                    stt += t * t
                    sdd += d * d
        s1 = max(s1, 1.0)
        mean_d = sd / s1
        mean_t = st / s1
        energy = max(stt - st * mean_t, 0.0)
        s_xt = std - st * mean_d
        s_xx = max(sdd - sd * mean_d, 0.0)
        along = s_xt / (energy + 1e-12)
        # The correlation of frame and template from the centred difference (s = t - d):
        # sum(s~ t~) = E - S_xt and sum(s~^2) = E - 2 S_xt + S_xx.
        den = math.sqrt(energy * max(energy - 2.0 * s_xt + s_xx, 0.0))
        if textured[p] and den > 1e-12:
            correlation[p] = (energy - s_xt) / den
        else:
            correlation[p] = np.nan
        md = np.float32(mean_d)
        mt = np.float32(mean_t)
        al = np.float32(along)
        for i in range(starts[p], starts[p + 1]):
            if mask[i]:
                for ch in range(nc):
                    diff[i, ch] = diff[i, ch] - md - al * (template[i, ch] - mt)
            else:
                for ch in range(nc):
                    diff[i, ch] = 0.0


@nb.njit("void(int64[::1], float64[::1], float64[::1], float64[::1], float64[:, ::1])", **_OPTS)
def channel_sums(key, t, s, use, out):
    """The sums the quality's correlations need, per triangle-channel ``key``, into ``out``.

    Rows of ``out`` (6, size): the used pixels (``use``, 0 or 1), ``use t``, ``use t t``,
    ``s'``, ``s' s'`` and ``t s'``, where ``s' = use s``: what ``np.bincount`` would give for
    each, summed in the same order.
    """
    for r in range(out.shape[0]):
        for k in range(out.shape[1]):
            out[r, k] = 0.0
    for i in range(key.shape[0]):
        k = key[i]
        u = use[i]
        ut = u * t[i]
        su = s[i] * u
        out[0, k] += u
        out[1, k] += ut
        out[2, k] += ut * t[i]
        out[3, k] += su
        out[4, k] += su * su
        out[5, k] += t[i] * su


@nb.njit("int64(float32[:, ::1], float32, float32, boolean[::1])", **_OPTS)
def on_picture(positions, bx, by, valid):
    """Which positions (2, n_pad) lie on the picture ``[0, bx] x [0, by]``; how many do.

    The first n go into ``valid`` (n,). A position that is not a number lies off it.
    """
    count = 0
    for i in range(valid.shape[0]):
        x = positions[0, i]
        y = positions[1, i]
        inside = x >= 0 and y >= 0 and x <= bx and y <= by
        valid[i] = inside
        count += inside
    return count


@nb.njit("void(boolean[::1], boolean[::1], int64[::1], boolean[::1])", **_OPTS)
def of_triangles(mask, keep, triangle, out):
    """``out = mask & keep[triangle]``: the pixels of ``mask`` whose triangle is kept."""
    for i in range(mask.shape[0]):
        out[i] = mask[i] and keep[triangle[i]]


@nb.njit("void(boolean[::1], int64[::1], float64[::1])", **_OPTS)
def count_per_triangle(mask, triangle, out):
    """How many pixels of each triangle are in ``mask``, into ``out`` (t,)."""
    for t in range(out.shape[0]):
        out[t] = 0.0
    for i in range(mask.shape[0]):
        if mask[i]:
            out[triangle[i]] += 1.0


@nb.njit("float64(float32[::1], boolean[::1], int64[::1], float64, float64[::1])", **_OPTS)
def masked_loss(loss, mask, triangle, cap, triangle_loss):
    """Each triangle's loss over the masked pixels, into ``triangle_loss`` (t,).

    Returns the sum over the masked pixels of the loss capped at ``cap``.
    """
    for t in range(triangle_loss.shape[0]):
        triangle_loss[t] = 0.0
    total = 0.0
    for i in range(loss.shape[0]):
        if mask[i]:
            s = loss[i]
            triangle_loss[triangle[i]] += s
            total += min(s, cap)
    return total


@nb.njit(
    "void(int64[::1], float32[:, ::1], boolean[::1], float32[:, ::1], int32[:, ::1],"
    " float64[:, ::1], float64, float64[:, :, :, ::1], float64[:, ::1])",
    **_OPTS,
)
def normal_equations(pick, diff, use, gradients, corners, weights, k, hess, rhs):
    """Gauss-Newton normal equations of the node positions (the local stage, :mod:`.refine`).

    For every picked pixel ``i`` (``pick`` into the level's pixels; the other arrays are
    indexed by position in ``pick`` except ``diff`` and ``use``): Lorentzian IRLS weights
    ``w_c = 1 / (1 + k d_c^2)``, the pixel's gradient ``g_c = (gx_c, gy_c)`` and residual
    ``d_c = template - frame`` give ``J^T W J`` and ``J^T W r`` of its three corners,
    spread by the barycentric weights.

    gradients : (n', 6) float32
        The frame's x derivatives of the three channels, then its y derivatives.
    corners, weights : (n', 3)
    hess : (m, 2, m, 2), rhs : (m, 2)
        Zeroed here, then accumulated.
    """
    hess[:] = 0.0
    rhs[:] = 0.0
    for q in range(pick.shape[0]):
        i = pick[q]
        if not use[i]:
            continue
        hxx = hxy = hyy = rx = ry = 0.0
        for ch in range(3):
            d = diff[i, ch]
            w = 1.0 / (1.0 + k * d * d)
            gx = gradients[q, ch]
            gy = gradients[q, 3 + ch]
            hxx += w * gx * gx
            hxy += w * gx * gy
            hyy += w * gy * gy
            rx += w * gx * d
            ry += w * gy * d
        for a in range(3):
            ca = corners[q, a]
            wa = weights[q, a]
            rhs[ca, 0] += wa * rx
            rhs[ca, 1] += wa * ry
            for b in range(3):
                cb = corners[q, b]
                wab = wa * weights[q, b]
                hess[ca, 0, cb, 0] += wab * hxx
                hess[ca, 0, cb, 1] += wab * hxy
                hess[ca, 1, cb, 0] += wab * hxy
                hess[ca, 1, cb, 1] += wab * hyy


@nb.njit(
    "void(float32[:, ::1], float32[:, ::1], boolean[::1], float64[::1], float64[::1], float64,"
    " float32[:, ::1])",
    **_OPTS,
)
def mix_look(template, samples, use, contrast, brightness, anchor, out):
    """The appearance a frame leaves (:meth:`.local.LocalStage.adapt`), into ``out`` (n, c).

    ``out = anchor t + (1 - anchor) (s - b) / c`` on the used pixels, the template ``t``
    elsewhere: the frame's samples ``s`` with its global lighting (``contrast`` ``c``,
    ``brightness`` ``b`` (c,)) undone, mixed with the template. ``anchor t`` is rounded to
    float32 and the rest is float64, as NumPy's expression of it gives.
    """
    a32 = np.float32(anchor)
    rest = 1.0 - anchor
    n, nc = template.shape
    for i in range(n):
        if use[i]:
            for ch in range(nc):
                seen = (np.float64(samples[i, ch]) - brightness[ch]) / contrast[ch]
                out[i, ch] = np.float32(np.float64(a32 * template[i, ch]) + rest * seen)
        else:
            for ch in range(nc):
                out[i, ch] = template[i, ch]


@nb.njit("int64(float64[::1], int64[::1], boolean[::1], int64[::1])", **_OPTS)
def dropped_rows(triangle_weight, triangle, use, out):
    """Rows (3 per pixel) of the pixels of kept triangles left out of the solve; how many.

    A pixel ``i`` whose triangle has weight but that ``use`` leaves out gives the rows
    ``3 i, 3 i + 1, 3 i + 2`` of ``out`` (3n,), in pixel order.
    """
    k = 0
    for i in range(use.shape[0]):
        if triangle_weight[triangle[i]] > 0 and not use[i]:
            out[k] = 3 * i
            out[k + 1] = 3 * i + 1
            out[k + 2] = 3 * i + 2
            k += 3
    return k


@nb.njit("void(int64[:, ::1], boolean[::1], int64[::1])", **_OPTS)
def region_sizes(neighbours, member, out):
    """For each triangle in ``member`` (t,), the size of its region; 0 for the others.

    A region: the members joined to one another through shared edges (``neighbours`` (t, 3):
    the triangles across each edge, -1 where none).
    """
    t = member.shape[0]
    label = np.full(t, -1, np.int64)
    stack = np.empty(t, np.int64)
    sizes = np.zeros(t, np.int64)
    regions = 0
    for start in range(t):
        if not member[start] or label[start] >= 0:
            continue
        label[start] = regions
        stack[0] = start
        top = 1
        while top:
            top -= 1
            k = stack[top]
            sizes[regions] += 1
            for j in range(neighbours.shape[1]):
                other = neighbours[k, j]
                if other >= 0 and member[other] and label[other] < 0:
                    label[other] = regions
                    stack[top] = other
                    top += 1
        regions += 1
    for k in range(t):
        out[k] = sizes[label[k]] if label[k] >= 0 else 0


@nb.njit("void(float32[:, ::1], int64[::1], float64[:, ::1])", **_OPTS)
def gather_columns(matrix, columns, out):
    """``out = matrix[:, columns]`` (p, k) as float64."""
    for r in range(matrix.shape[0]):
        for j in range(columns.shape[0]):
            out[r, j] = matrix[r, columns[j]]


@nb.njit("void(float32[:, :, ::1], float32[:, ::1], float32[:, ::1])", **_OPTS)
def gradients(image, positions, out):
    """The picture's derivatives at ``positions`` (2, n).

    Central differences of bilinear samples one pixel to either side, the border repeated
    beyond the edge. ``out`` (n, 2c): the x derivative of each channel, then the y
    derivative. The four samples of a point share its fractional weights, so they read
    twelve pixels.
    """
    h, w, nc = image.shape
    for i in range(out.shape[0]):
        x = positions[0, i]
        y = positions[1, i]
        if not (abs(x) < 1e7 and abs(y) < 1e7):
            x = np.float32(0.0)
            y = np.float32(0.0)
        fx0 = math.floor(x)
        fy0 = math.floor(y)
        fx = x - fx0
        fy = y - fy0
        x0 = int(fx0)
        y0 = int(fy0)
        if 1 <= x0 and x0 + 2 < w and 1 <= y0 and y0 + 2 < h:  # inside: no clamping
            cm, c0, c1, c2 = x0 - 1, x0, x0 + 1, x0 + 2
            rm, r0, r1, r2 = y0 - 1, y0, y0 + 1, y0 + 2
        else:
            cm = min(max(x0 - 1, 0), w - 1)
            c0 = min(max(x0, 0), w - 1)
            c1 = min(max(x0 + 1, 0), w - 1)
            c2 = min(max(x0 + 2, 0), w - 1)
            rm = min(max(y0 - 1, 0), h - 1)
            r0 = min(max(y0, 0), h - 1)
            r1 = min(max(y0 + 1, 0), h - 1)
            r2 = min(max(y0 + 2, 0), h - 1)
        gx = 1.0 - fx
        gy = 1.0 - fy
        for ch in range(nc):
            p0m, p00, p01, p02 = (
                image[r0, cm, ch],
                image[r0, c0, ch],
                image[r0, c1, ch],
                image[r0, c2, ch],
            )
            p1m, p10, p11, p12 = (
                image[r1, cm, ch],
                image[r1, c0, ch],
                image[r1, c1, ch],
                image[r1, c2, ch],
            )
            # x: B(x + 1, y) - B(x - 1, y) on rows r0, r1
            top = gx * (p01 - p0m) + fx * (p02 - p00)
            bot = gx * (p11 - p1m) + fx * (p12 - p10)
            out[i, ch] = 0.5 * (gy * top + fy * bot)
            # y: B(x, y + 1) - B(x, y - 1) on columns c0, c1
            left = gy * (p10 - image[rm, c0, ch]) + fy * (image[r2, c0, ch] - p00)
            right = gy * (p11 - image[rm, c1, ch]) + fy * (image[r2, c1, ch] - p01)
            out[i, nc + ch] = 0.5 * (gx * left + fx * right)


@nb.njit(**_OPTS)
def _area_terms(e, g, k, t, s):
    """Triangle ``k``'s signed area along a step, ``a0 + b tau + c tau^2``, times its sign.

    ``e`` and ``g`` (4t): its edges and their change, as :func:`edges` lays them out.
    """
    e1x, e1y, e2x, e2y = e[2 * k], e[2 * k + 1], e[2 * t + 2 * k], e[2 * t + 2 * k + 1]
    g1x, g1y, g2x, g2y = g[2 * k], g[2 * k + 1], g[2 * t + 2 * k], g[2 * t + 2 * k + 1]
    h = s * 0.5
    a0 = h * (e1x * e2y - e1y * e2x)
    b = h * ((e1x * g2y - e1y * g2x) + (g1x * e2y - g1y * e2x))
    c = h * (g1x * g2y - g1y * g2x)
    return a0, b, c


@nb.njit(**_OPTS)
def _crossing(f0, f1, f2):
    """First ``tau > 0`` where ``f0 + f1 tau + f2 tau^2`` reaches 0 (inf: none).

    ``f0 >= 0`` up to rounding. -1 when it sits on 0 (to rounding) and is heading below:
    no step at all. The roots are taken in the form that does not cancel
    (``q = -(f1 + sign(f1) sqrt(disc)) / 2``, roots ``q / f2`` and ``f0 / q``), so a
    triangle sitting on its bound is seen leaving it at once.
    """
    f0 = max(f0, 0.0)
    if f0 <= 1e-12 * (1.0 + abs(f1)) and (f1 < 0 or (f1 == 0 and f2 < 0)):
        return -1.0
    disc = f1 * f1 - 4.0 * f2 * f0
    if not disc >= 0:
        return np.inf
    sq = math.sqrt(disc)
    q = -0.5 * (f1 + (sq if f1 >= 0 else -sq))
    r1 = q / f2 if abs(f2) > 1e-300 else np.inf
    r2 = f0 / q if abs(q) > 1e-300 else np.inf
    return min(r1 if r1 > 0 else np.inf, r2 if r2 > 0 else np.inf)


@nb.njit("void(float64[:, ::1], int64[:, ::1], float64[::1])", **_OPTS)
def edges(points, triangles, out):
    """The triangles' two edges from their first corner, from ``points`` (m, 2).

    ``out`` (4t): every triangle's first edge (x, y), then every triangle's second.
    """
    t = triangles.shape[0]
    for k in range(t):
        i0, i1, i2 = triangles[k, 0], triangles[k, 1], triangles[k, 2]
        out[2 * k] = points[i1, 0] - points[i0, 0]
        out[2 * k + 1] = points[i1, 1] - points[i0, 1]
        out[2 * t + 2 * k] = points[i2, 0] - points[i0, 0]
        out[2 * t + 2 * k + 1] = points[i2, 1] - points[i0, 1]


@nb.njit(
    "float64(float64[::1], float64[::1], float64[::1], float64[::1], float64[::1], float64)",
    **_OPTS,
)
def bounded_step(e, g, sign, low, high, backoff):
    """The largest ``tau`` in [0, 1] that keeps every triangle's area within its bounds.

    ``e`` and ``g`` (4t): the triangles' edges and their change along the step (laid out
    as by :func:`edges`). ``sign``, ``low`` and ``high`` (t,): the rest area's sign and the
    bounds (see :class:`.folding.FoldGuard`). Returns 1 when the whole step is safe, else
    ``backoff`` times the first crossing.
    """
    t = sign.shape[0]
    far = True
    for k in range(t):
        s = sign[k]
        a0, b, c = _area_terms(e, g, k, t, s)
        # Over tau in [0, 1] the area moves by at most |b| + |c|.
        reach = abs(b) + abs(c)
        if not (a0 - s * low[k] > reach and s * high[k] - a0 > reach):
            far = False
            break
    if far:
        return 1.0
    tau = 1.0
    for k in range(t):
        s = sign[k]
        a0, b, c = _area_terms(e, g, k, t, s)
        r = min(_crossing(a0 - s * low[k], b, c), _crossing(s * high[k] - a0, -b, -c))
        if r < 0:
            return 0.0
        tau = min(tau, r)
    return 1.0 if tau >= 1.0 else backoff * tau


_numba_config.CACHE_DIR = _CACHE_DIR  # the kernels are compiled: leave Numba as it was
