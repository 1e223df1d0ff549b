"""The window matcher's numba kernels against plain references."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.matcher.window_kernels import (
    PATH_COLUMN_STEP,
    PATH_LANES,
    PATH_NONE,
    _scanline,
    right_partners,
)


def _paths_reference(bm, m, w, p1, p2, step):
    """Both scanline paths by the textbook recursion, on every ``step``-th column."""
    cost = bm[:, m:m + w:step].T.astype(float)  # (columns, nd)

    def one(c):
        out = np.empty_like(c)
        out[0] = c[0]
        for x in range(1, len(c)):
            prev = out[x - 1]
            near = np.minimum(np.r_[np.inf, prev[:-1]], np.r_[prev[1:], np.inf]) + p1
            out[x] = c[x] + np.minimum(np.minimum(prev, near), prev.min() + p2) - prev.min()
        return out

    return one(cost), one(cost[::-1])[::-1]


def _paths(bm, m, w, p1, p2):
    nd = bm.shape[0]
    n = -(-w // PATH_COLUMN_STEP)
    lanes = -(-nd // PATH_LANES) * PATH_LANES
    costs = np.full((n + 3, lanes), PATH_NONE, np.uint16)  # more rows than the paths'
    fwd, bwd = (np.full((n + 3, lanes + 2 * PATH_LANES), PATH_NONE, np.uint16)
                for _ in range(2))
    _scanline(bm, m, w, 1, p1, p2, costs, fwd, bwd)
    # the lanes before and past the disparities and the rows past the paths' are left
    # as they were
    for a in (fwd, bwd):
        assert np.all(a[:, :PATH_LANES] == PATH_NONE)
        assert np.all(a[:, PATH_LANES + nd:] == PATH_NONE) and np.all(a[n:] == PATH_NONE)
    return fwd[:n, PATH_LANES:PATH_LANES + nd], bwd[:n, PATH_LANES:PATH_LANES + nd]


@pytest.mark.parametrize("nd", [1, 2, 7, 16, 17, 40])
def test_paths_are_the_semi_global_recursion(nd):
    """Ranges shorter than a block of lanes, a whole block and one past it: every
    disparity, the first and the last (one neighbour) included."""
    rng = np.random.default_rng(4)
    w, m = 41, 8
    bm = rng.integers(0, 3000, (nd, w + 2 * m)).astype(np.int16)
    fwd, bwd = _paths(bm, m, w, 405, 2000)
    ref_f, ref_b = _paths_reference(bm, m, w, 405.0, 2000.0, PATH_COLUMN_STEP)
    assert np.array_equal(fwd, ref_f) and np.array_equal(bwd, ref_b)


def test_paths_hold_the_largest_costs_and_penalties():
    # window sums up to the int16 limit and the largest penalties the matcher takes
    # (200 per window pixel): the uint16 path costs must not wrap
    rng = np.random.default_rng(5)
    nd, w, m = 9, 61, 8
    bm = rng.integers(0, 2, (nd, w + 2 * m)).astype(np.int16) * 32767
    bm[:, ::3] = rng.integers(0, 32768, (nd, bm[:, ::3].shape[1]))
    for p1, p2 in ((0, 16200), (16200, 16200), (81, 16200)):
        fwd, bwd = _paths(bm, m, w, p1, p2)
        ref_f, ref_b = _paths_reference(bm, m, w, float(p1), float(p2), PATH_COLUMN_STEP)
        assert ref_f.max() > 40000  # beyond int16: the test reaches the range it guards
        assert np.array_equal(fwd, ref_f) and np.array_equal(bwd, ref_b)


def test_paths_wrap_in_uint16_as_they_did():
    """Window sums below zero (two masked pixels' pairs) become large uint16 costs; the
    path sums then wrap in uint16, lane by lane, as the recursion in uint16 does."""
    rng = np.random.default_rng(6)
    nd, w, m = 21, 51, 8
    bm = rng.integers(-2000, 3000, (nd, w + 2 * m)).astype(np.int16)
    p1, p2 = 405, 2000
    fwd, bwd = _paths(bm, m, w, p1, p2)
    cost = bm[:, m:m + w:PATH_COLUMN_STEP].T.astype(np.uint16)  # (columns, nd)
    none = np.array([PATH_NONE], np.uint16)

    def one(c):
        out = c.copy()
        wrapped = False
        for x in range(1, len(c)):
            prev = out[x - 1]
            least = prev.min()
            near = np.minimum(np.r_[none, prev[:-1]], np.r_[prev[1:], none]) - least
            near = np.minimum(near, np.uint16(p2 - p1)) + np.uint16(p1)
            step = np.minimum(prev - least, near)
            wrapped |= bool(np.any(c[x].astype(int) + step > PATH_NONE))
            out[x] = c[x] + step
        assert wrapped  # the test reaches the sums that wrap
        return out

    assert np.array_equal(fwd, one(cost)) and np.array_equal(bwd, one(cost[::-1])[::-1])


def _partners_reference(x_left, left_line, left_sign, d_par, seen, lo, hi, right_line,
                        right_x, right_sign):
    """The window matcher's right edge points and sub-pixel disparities, point by point
    as its Notes 4 say: of the two right points around ``x - d`` on the line, the nearer
    of the same sign; within half a pixel, the disparity from it."""
    n = x_left.size
    disparity, right_edge, partner = np.full(n, np.nan), np.full(n, -1), np.full(n, -1)
    use = np.zeros(n)
    for i in range(n):
        x = x_left[i] - d_par[i]
        on_line = np.flatnonzero(right_line == left_line[i])
        best, dist = -1, np.inf
        if np.isfinite(x) and on_line.size:
            at = np.searchsorted(right_x[on_line], x)
            for k in (at - 1, at):
                if 0 <= k < on_line.size and right_sign[on_line[k]] == left_sign[i]:
                    if abs(right_x[on_line[k]] - x) < dist:
                        best, dist = on_line[k], abs(right_x[on_line[k]] - x)
        d = d_par[i]
        if dist <= 0.5:
            partner[i], use[i], d = best, 1.0, x_left[i] - right_x[best]
        if lo - 0.5 <= d <= hi + 0.5 and seen[i]:
            disparity[i], right_edge[i] = d, partner[i]
    return disparity, right_edge, partner, use


def test_right_partners_are_the_plain_nearest_points():
    """On a grid of quarter pixels (distances of exactly half a pixel, ties between the
    two neighbours), lines without right points, NaN disparities and points not seen:
    the kernel's partners, disparities and flags equal the plain reference's."""
    rng = np.random.default_rng(11)
    n_lines, n_right, n = 12, 300, 2000
    right_line = np.sort(rng.integers(0, n_lines - 2, n_right)).astype(np.int32)  # 2 empty
    right_x = np.empty(n_right)
    for line in range(n_lines):
        on = right_line == line
        right_x[on] = np.sort(rng.choice(np.arange(0, 100, 0.25), on.sum(), replace=False))
    right_sign = rng.choice(np.array([-1, 1], np.int8), n_right)
    x_left = rng.integers(0, 480, n) * 0.25
    left_line = rng.integers(0, n_lines, n).astype(np.int32)
    left_sign = rng.choice(np.array([-1, 1], np.int8), n)
    d_par = rng.integers(-40, 80, n) * 0.25
    d_par[::37] = np.nan
    seen = rng.uniform(0, 1, n) > 0.1
    lo, hi = 0.0, 15.0
    line_start = np.searchsorted(right_line, np.arange(n_lines + 1)).astype(np.int64)
    disparity, right_edge, partner = np.empty(n), np.empty(n, np.intp), np.empty(n, np.int64)
    feats = np.full((n, 4), 7.0)
    right_partners(x_left, left_line, left_sign, d_par, seen, lo, hi, line_start, right_x,
                   right_sign, disparity, right_edge, partner, feats, 2)
    want = _partners_reference(x_left, left_line, left_sign, d_par, seen, lo, hi,
                               right_line, right_x, right_sign)
    assert np.array_equal(disparity, want[0], equal_nan=True)
    assert np.array_equal(right_edge, want[1]) and np.array_equal(partner, want[2])
    assert np.array_equal(feats[:, 2], want[3]) and np.all(feats[:, [0, 1, 3]] == 7.0)
    # the cases the data was made to hold
    dist = np.abs(x_left - d_par - right_x[np.maximum(partner, 0)])
    assert np.any((partner >= 0) & (dist == 0.5)) and 0 < np.sum(partner >= 0) < n
    assert np.any((partner >= 0) & np.isnan(disparity))
