"""The window matcher's numba kernels against plain references."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.matcher.window_kernels import PATH_COLUMN_STEP, PATH_LANES, PATH_NONE, _scanline


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
