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


def test_paths_are_the_semi_global_recursion():
    rng = np.random.default_rng(4)
    nd, w, m = 7, 41, 8
    bm = rng.integers(0, 3000, (nd, w + 2 * m)).astype(np.int16)
    n = -(-w // PATH_COLUMN_STEP)
    fwd, bwd = np.zeros((w, nd), np.float32), np.zeros((w, nd), np.float32)
    bufs = [np.empty(nd, np.float32) for _ in range(4)]
    _scanline(bm, m, w, 1, np.float32(405), np.float32(2000), np.empty((w, nd), np.float32),
              fwd, bwd, *bufs)
    ref_f, ref_b = _paths_reference(bm, m, w, 405.0, 2000.0, PATH_COLUMN_STEP)
    assert np.allclose(fwd[:n], ref_f) and np.allclose(bwd[:n], ref_b)

