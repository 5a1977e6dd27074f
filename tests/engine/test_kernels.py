"""The compiled per-pixel loops against plain NumPy written from their definitions."""

import numpy as np
import pytest

from voodoo_addon.tracking import kernels

RNG = np.random.default_rng(7)


def test_positions_are_barycentric_combinations_of_the_nodes():
    nodes = RNG.uniform(0, 100, (12, 2))
    corners = RNG.integers(0, 12, (50, 3)).astype(np.int32)
    w = RNG.uniform(0, 1, (50, 3)).astype(np.float32)
    w /= w.sum(axis=1, keepdims=True)
    out = np.empty((2, 64), np.float32)
    kernels.positions(corners, w, nodes, 3.0, -2.0, out)
    want = np.einsum("nj,njd->nd", w.astype(np.float64), nodes[corners]) - [3.0, -2.0]
    np.testing.assert_allclose(out[:, :50].T, want, atol=1e-4)
    np.testing.assert_array_equal(out[:, 50:], np.repeat(out[:, 49:50], 14, axis=1))


def test_difference_undoes_the_global_lighting():
    s = RNG.uniform(0, 1, (40, 3)).astype(np.float32)
    t = RNG.uniform(0, 1, (40, 3)).astype(np.float32)
    c, b = np.array([1.2, 0.9, 1.0]), np.array([0.05, -0.02, 0.0])
    out = np.empty_like(s)
    kernels.difference(s, t, (1 / c).astype(np.float32), (b / c).astype(np.float32), out)
    np.testing.assert_allclose(out, t - (s - b) / c, atol=1e-6)


@pytest.mark.parametrize("masked", [False, True])
def test_projection_removes_each_patch_gain_and_bias(masked):
    starts = np.array([0, 30, 45, 80], np.int64)
    t = RNG.uniform(0, 1, (80, 3)).astype(np.float32)
    target = RNG.uniform(0, 1, (80, 3)).astype(np.float32)  # an adapted appearance
    s = RNG.uniform(0, 1, (80, 3)).astype(np.float32)
    gain, bias = np.array([0.8, 1.0, 1.1], np.float32), np.array([0.02, 0.0, -0.01], np.float32)
    d = target - (s * gain - bias)
    mask = RNG.uniform(size=80) > 0.3 if masked else np.ones(80, bool)
    out, corr = np.empty_like(d), np.empty(3)
    kernels.project(s, target, gain, bias, t, starts, mask, np.ones(3, bool), out, corr)
    for p in range(3):
        sl = slice(starts[p], starts[p + 1])
        m = mask[sl]
        dd, tt = d[sl][m].astype(np.float64), t[sl][m].astype(np.float64)
        # least squares d ~ mean + gain * (t - mean_t) over the masked values
        a = np.stack([np.ones(dd.size), (tt - tt.mean()).ravel()], axis=1)
        coef = np.linalg.lstsq(a, dd.ravel(), rcond=None)[0]
        want = dd.ravel() - a @ coef
        np.testing.assert_allclose(out[sl][m].ravel(), want, atol=1e-5)
        assert not out[sl][~m].any()
        frame = tt - dd  # the frame as the correlation sees it, in the template's terms
        want_corr = np.corrcoef((frame - frame.mean()).ravel(), (tt - tt.mean()).ravel())[0, 1]
        assert corr[p] == pytest.approx(want_corr, abs=1e-5)


def test_masked_loss_sums_per_triangle_and_caps():
    loss = np.array([0.5, 4.0, 1.0, 2.0], np.float32)
    mask = np.array([True, True, False, True])
    tri = np.array([0, 1, 1, 0], np.int64)
    per = np.empty(2)
    total = kernels.masked_loss(loss, mask, tri, 3.0, per)
    np.testing.assert_allclose(per, [2.5, 4.0])
    assert total == pytest.approx(0.5 + 3.0 + 2.0)


def test_normal_equations_match_the_dense_jacobian():
    m, n = 5, 60
    corners = RNG.integers(0, m, (n, 3)).astype(np.int32)
    w = RNG.uniform(0, 1, (n, 3))
    w /= w.sum(axis=1, keepdims=True)
    diff = RNG.normal(0, 0.2, (n, 3)).astype(np.float32)
    grads = RNG.normal(0, 1, (n, 6)).astype(np.float32)
    use = RNG.uniform(size=n) > 0.2
    k = 0.5 / 0.15**2
    hess, rhs = np.empty((m, 2, m, 2)), np.empty((m, 2))
    pick = np.arange(n, dtype=np.int64)
    kernels.normal_equations(pick, diff, use, grads, corners, w, k, hess, rhs)
    # Dense: residual r_ic depends on node j's (x, y) through w_ij * g_ic.
    jac = np.zeros((n, 3, m, 2))
    for i in range(n):
        for j in range(3):
            jac[i, :, corners[i, j], 0] += w[i, j] * grads[i, :3]
            jac[i, :, corners[i, j], 1] += w[i, j] * grads[i, 3:]
    wt = use[:, None] / (1.0 + k * diff.astype(np.float64) ** 2)
    jf = jac.reshape(n * 3, 2 * m)
    want = jf.T @ (wt.ravel()[:, None] * jf)
    np.testing.assert_allclose(hess.reshape(2 * m, 2 * m), want, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(rhs.ravel(), jf.T @ (wt * diff).ravel(), rtol=1e-5, atol=1e-6)


def _bilinear(image, x, y):
    """Bilinear sample with the border repeated (NumPy, one point)."""
    h, w = image.shape[:2]
    x0, y0 = int(np.floor(x)), int(np.floor(y))
    fx, fy = x - x0, y - y0

    def px(r, c):
        return image[min(max(r, 0), h - 1), min(max(c, 0), w - 1)].astype(np.float64)

    top = (1 - fx) * px(y0, x0) + fx * px(y0, x0 + 1)
    bot = (1 - fx) * px(y0 + 1, x0) + fx * px(y0 + 1, x0 + 1)
    return (1 - fy) * top + fy * bot


def test_gradients_are_central_differences_of_bilinear_samples():
    image = RNG.uniform(0, 1, (20, 30, 3)).astype(np.float32)
    pos = np.stack([RNG.uniform(-2, 32, 40), RNG.uniform(-2, 22, 40)]).astype(np.float32)
    out = np.empty((40, 6), np.float32)
    kernels.gradients(image, pos, out)
    for i, (x, y) in enumerate(pos.T.astype(np.float64)):
        gx = 0.5 * (_bilinear(image, x + 1, y) - _bilinear(image, x - 1, y))
        gy = 0.5 * (_bilinear(image, x, y + 1) - _bilinear(image, x, y - 1))
        np.testing.assert_allclose(out[i], np.r_[gx, gy], atol=1e-5)


def test_a_linear_ramp_has_its_slope_as_gradient():
    yy, xx = np.mgrid[0:16, 0:16].astype(np.float32)
    image = np.ascontiguousarray(np.stack([0.01 * xx, 0.02 * yy, 0.01 * xx - 0.03 * yy], -1))
    pos = np.array([[5.3, 7.9], [4.2, 10.5]], np.float32)
    out = np.empty((2, 6), np.float32)
    kernels.gradients(image, pos, out)
    np.testing.assert_allclose(out, [[0.01, 0, 0.01, 0, 0.02, -0.03]] * 2, atol=1e-6)


def test_on_picture_is_the_box_test_and_counts():
    pos = np.stack([RNG.uniform(-3, 23, 70), RNG.uniform(-3, 13, 70)]).astype(np.float32)
    pos[0, 5] = np.nan  # not a number: off the picture
    valid = np.empty(64, bool)  # the last six columns are padding
    count = kernels.on_picture(pos, np.float32(20), np.float32(10), valid)
    x, y = pos[:, :64]
    want = (x >= 0) & (y >= 0) & (x <= 20) & (y <= 10)
    np.testing.assert_array_equal(valid, want)
    assert count == np.count_nonzero(want) and 0 < count < 64 and not valid[5]


def test_pixels_of_kept_triangles_and_counts_per_triangle():
    triangle = RNG.integers(0, 9, 200).astype(np.int64)
    mask = RNG.uniform(size=200) > 0.3
    keep = RNG.uniform(size=9) > 0.4
    out = np.empty(200, bool)
    kernels.of_triangles(mask, keep, triangle, out)
    np.testing.assert_array_equal(out, mask & keep[triangle])
    count = np.empty(9)
    kernels.count_per_triangle(mask, triangle, count)
    np.testing.assert_array_equal(count, np.bincount(triangle, weights=mask, minlength=9))


def test_channel_sums_are_the_bincounts_they_replace_to_the_last_bit():
    key = RNG.integers(0, 30, 400).astype(np.int64)
    t, s = RNG.uniform(0, 1, 400), RNG.uniform(0, 1, 400)
    use = (RNG.uniform(size=400) > 0.3).astype(np.float64)
    out = np.empty((6, 32))
    kernels.channel_sums(key, t, s, use, out)
    su = s * use
    for row, weights in enumerate((use, use * t, use * t * t, su, su * su, t * su)):
        np.testing.assert_array_equal(out[row], np.bincount(key, weights, minlength=32))


@pytest.mark.parametrize("lit", [False, True])
def test_mix_look_is_the_numpy_mix_to_the_last_bit(lit):
    t = RNG.uniform(0, 1, (300, 3)).astype(np.float32)
    s = RNG.uniform(0, 1, (300, 3)).astype(np.float32)
    use = RNG.uniform(size=300) > 0.2
    c = np.array([1.1, 0.95, 1.02]) if lit else np.ones(3)
    b = np.array([0.03, -0.01, 0.0]) if lit else np.zeros(3)
    anchor = 0.37
    out = np.empty_like(t)
    kernels.mix_look(t, s, use, c, b, anchor, out)
    seen = (s.astype(np.float64) - b) / c
    want = np.where(use[:, None], anchor * t + (1.0 - anchor) * seen, t).astype(np.float32)
    np.testing.assert_array_equal(out, want)


def test_dropped_rows_and_gathered_columns_are_the_numpy_selection():
    triangle = RNG.integers(0, 9, 200).astype(np.int64)
    weight = (RNG.uniform(size=9) > 0.3).astype(np.float64)
    use = RNG.uniform(size=200) > 0.4
    rows = np.empty(600, np.int64)
    k = kernels.dropped_rows(weight, triangle, use, rows)
    gone = np.nonzero((weight > 0)[triangle] & ~use)[0]
    np.testing.assert_array_equal(rows[:k], (3 * gone[:, None] + np.arange(3)).ravel())
    jac = RNG.standard_normal((5, 600)).astype(np.float32)
    out = np.empty((5, k))
    kernels.gather_columns(jac, rows[:k], out)
    np.testing.assert_array_equal(out, jac[:, rows[:k]].astype(np.float64))


def test_the_occlusion_tests_median_and_quantile_are_numpys_to_the_last_bit():
    from voodoo_addon.tracking.evaluation import _median, _quantile

    for n in range(1, 60):
        for _ in range(20):
            x = RNG.uniform(-1, 1, n)
            if n % 3 == 0:
                x = np.round(x, 1)  # ties
            ordered = np.sort(x)
            assert _median(ordered) == np.median(x)
            assert _quantile(ordered, 1.0 - 1.0 / 3.0) == np.quantile(x, 1.0 - 1.0 / 3.0)


def test_region_sizes_are_the_connected_components_of_the_members():
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components

    t = 60
    neighbours = np.full((t, 3), -1, np.int64)
    for a, b in RNG.integers(0, t, (70, 2)):
        free_a, free_b = np.flatnonzero(neighbours[a] < 0), np.flatnonzero(neighbours[b] < 0)
        if a != b and b not in neighbours[a] and len(free_a) and len(free_b):
            neighbours[a, free_a[0]], neighbours[b, free_b[0]] = b, a
    for _ in range(10):
        member = RNG.uniform(size=t) > 0.4
        out = np.empty(t, np.int64)
        kernels.region_sizes(neighbours, member, out)
        at = np.flatnonzero(member)
        rows, cols = np.nonzero(neighbours >= 0)
        graph = csr_matrix((np.ones(len(rows)), (rows, neighbours[rows, cols])), shape=(t, t))
        _, label = connected_components(graph[at][:, at], directed=False)
        want = np.zeros(t, np.int64)
        want[at] = np.bincount(label)[label]
        np.testing.assert_array_equal(out, want)
