"""Numba kernel of the photometric check: how far matched grey levels are apart.

:mod:`robostereo.matcher.photometric` checks each match on about a thousand pairs of
grey levels: in numpy the places to read and the fit were some forty small calls, as much
as 5-10 % of a small pair's whole match; here they are two.  Only numba functions.
"""

from __future__ import annotations

import numpy as np

from robostereo.matcher.jit import kernel

__all__ = ["difference_kernel", "places_kernel"]


@kernel(nogil=True)
def _line(gl, gr, use):  # type: ignore[no-untyped-def]
    """Least-squares ``gl = a * gr + b`` over the pairs ``use`` (closed form); the
    identity's offset alone where the right grey levels do not vary."""
    n = 0
    sx = 0.0
    sy = 0.0
    sxx = 0.0
    sxy = 0.0
    for i in range(gl.shape[0]):
        if use[i]:
            n += 1
            sx += gr[i]
            sy += gl[i]
            sxx += gr[i] * gr[i]
            sxy += gr[i] * gl[i]
    if n == 0:
        return 1.0, 0.0
    den = n * sxx - sx * sx
    if den <= 1e-9 * max(n * sxx, 1.0):
        return 1.0, (sy - sx) / n
    a = (n * sxy - sx * sy) / den
    return a, (sy - a * sx) / n


@kernel(nogil=True)
def difference_kernel(gl, gr):  # type: ignore[no-untyped-def]
    """``(median |gl - gr|, median |gl - (a gr + b)|)`` for pairs ``gl, gr`` (M,) float64,
    M >= 8: ``a, b`` by least squares, then again without the pairs more than three
    times the median difference off the first line."""
    m = gl.shape[0]
    off = np.empty(m)
    use = np.ones(m, np.bool_)
    for i in range(m):
        off[i] = abs(gl[i] - gr[i])
    as_they_are = np.median(off)
    a, b = _line(gl, gr, use)
    for i in range(m):
        off[i] = abs(gl[i] - (a * gr[i] + b))
    limit = 3.0 * np.median(off)
    kept = 0
    for i in range(m):
        use[i] = off[i] <= limit
        kept += use[i]
    if kept >= 8:
        a, b = _line(gl, gr, use)
    for i in range(m):
        off[i] = abs(gl[i] - (a * gr[i] + b))
    return as_they_are, np.median(off)


@kernel(nogil=True)
def places_kernel(rows, x, disparity, offsets, h, w, max_matches):  # type: ignore[no-untyped-def]
    """Pixels that :func:`~robostereo.matcher.photometric.grey_pairs` reads: of at most
    ``max_matches`` matches (evenly spaced over the finite ones), for each column offset
    whose pixels lie in both images, the row, the left column ``round(x) + o``, the
    right column ``x0 = floor(round(x) + o - disparity)`` and the fraction ``t`` towards
    ``x0 + 1``.  ``rows`` (N,) int64, ``x, disparity`` (N,) float64, ``offsets`` (K,)
    int64.  Returns four arrays of one length M <= max_matches * K."""
    n = rows.shape[0]
    finite = np.empty(n, np.int64)
    m = 0
    for i in range(n):
        if np.isfinite(x[i]) and np.isfinite(disparity[i]):
            finite[m] = i
            m += 1
    take = min(m, max_matches)
    k = offsets.shape[0]
    yy = np.empty(take * k, np.int64)
    xl = np.empty(take * k, np.int64)
    x0 = np.empty(take * k, np.int64)
    t = np.empty(take * k)
    c = 0
    for j in range(take):
        # evenly spaced, as np.linspace(0, m - 1, take).round()
        i = finite[int(np.round(j * (m - 1) / (take - 1))) if take > 1 else 0]
        y = rows[i]
        if y < 0 or y >= h:
            continue
        for o in offsets:
            left_col = np.round(x[i]) + o
            right = left_col - disparity[i]
            f = np.floor(right)
            if left_col < 0 or left_col >= w or f < 0 or f + 1 >= w:
                continue
            yy[c] = y
            xl[c] = np.int64(left_col)
            x0[c] = np.int64(f)
            t[c] = right - f
            c += 1
    return yy[:c], xl[:c], x0[:c], t[:c]
