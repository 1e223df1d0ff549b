"""The window matcher's numba kernels against plain references."""

from __future__ import annotations

import numpy as np

from robostereo.matcher.window_kernels import PATH_COLUMN_STEP, _scanline


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
    fwd, bwd = np.zeros((w, nd), np.uint16), np.zeros((w, nd), np.uint16)
    bufs = [np.empty(nd, np.uint16) for _ in range(4)]
    _scanline(bm, m, w, 1, p1, p2, np.empty((w, nd), np.uint16), fwd, bwd, *bufs)
    n = -(-w // PATH_COLUMN_STEP)
    return fwd[:n], bwd[:n]


def test_paths_are_the_semi_global_recursion():
    rng = np.random.default_rng(4)
    nd, w, m = 7, 41, 8
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
