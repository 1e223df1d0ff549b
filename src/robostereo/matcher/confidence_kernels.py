"""Numba kernel of the confidence model: the evidence score of every match in one pass.

:meth:`robostereo.matcher.confidence.ConfidenceModel.score` in numpy was some twenty
passes over strided columns of the features, each with a temporary of every match; as
much time as the evidence itself took to make.  Here it is one pass, the same float64
operations in the same order (no fast-math: no reordering, no fused multiply-add), so
the scores are bit for bit numpy's.  Only numba functions.
"""

from __future__ import annotations

import numpy as np

from robostereo.matcher.jit import kernel

__all__ = ["evidence_score"]


@kernel(nogil=True, inline="always")
def _minimum(a, b):  # type: ignore[no-untyped-def]
    """``np.minimum(a, b)`` of two floats: NaN if either is."""
    if a != a:
        return a
    if b != b:
        return b
    return a if a <= b else b


@kernel(nogil=True)
def evidence_score(features, columns, weights):  # type: ignore[no-untyped-def]
    """The score of :class:`~robostereo.matcher.confidence.ConfidenceModel` per row of
    ``features`` (N, F) float64: ``(N,)`` float64.

    ``columns`` (9,) holds the feature columns uniqueness, uniqueness_row, row_agree,
    left_right, right_edge, similarity, path_uniqueness, path_agree, path_swapped;
    ``weights`` (5,) the model's right_edge, similarity, row_agree, path and swap
    weights."""
    c_u, c_ur, c_ra, c_lr, c_re, c_sim, c_up, c_pa, c_ps = (
        columns[0], columns[1], columns[2], columns[3], columns[4], columns[5],
        columns[6], columns[7], columns[8])
    w_re, w_sim, w_ra, w_path, w_swap = weights[0], weights[1], weights[2], weights[3], \
        weights[4]
    n = features.shape[0]
    out = np.empty(n)
    for i in range(n):
        f = features[i]
        edge = w_re * f[c_re] + w_sim * f[c_sim]
        windows = _minimum(f[c_u], f[c_ur]) - (1.0 - f[c_lr]) + edge + w_ra * f[c_ra]
        u_path = f[c_up]
        if f[c_pa] > 0:
            out[i] = windows + w_path * u_path
        elif f[c_ps] > 0:  # swapped: the paths' disparity was taken
            out[i] = u_path - 1.0 + w_swap + edge
        else:
            out[i] = windows - 1.0
    return out
