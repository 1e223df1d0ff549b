"""Window costs at edge points: every disparity of the range, side-aware windows.

The seed compares a left edge point only with right *edge points* (3.2, 3.5).  On
real scenes the true partner is often not a right edge point at all (occlusion, a
depth edge whose two sides move differently, blur), and then the best wrong
candidate wins.  This stage scores, for each left edge point, *every* whole-pixel
disparity of the search range with a window cost, so that a partner that is no edge
still gets found, and so that a point whose partner is nowhere (occluded, out of
view) can be told apart: its best cost is not unique, or the right pixel prefers
another partner (the left-right check).

Per pixel pair the cost is the census Hamming distance [1]_ of a ``7 x 5``
neighbourhood plus the truncated absolute difference of the horizontal Sobel
gradients; it is summed over a ``9 x 9`` window placed five ways (centred on the
edge, and shifted half a window left, right, up and down) and the lowest is kept: at
a depth boundary only the window on the occluding surface sees one disparity
(side-aware windows, as in multiple-window matching [2]_).

Where a window alone is ambiguous (a repeated pattern, weak texture: two near-equal
minima), the costs of the centred windows are also aggregated along the row, from the
left and from the right, as two scanline paths of semi-global matching [3]_; a path
carries the disparity of the row's textured parts into the ambiguous ones, and where
the paths disagree with the windows and are unique enough their disparity is taken.

The work is done in one pass down the image (a numba kernel): pixel costs of a row
for all disparities, vertical column sums kept running over a ring of the last nine
rows, window sums of nine columns, the paths on every fifth row, and at each row the
windows of that row's edge points read from the window sums of it and of the rows half
a window above and below.
Cost is therefore linear in the disparity range and the image size, per-image work
(census, gradients) is done once, and memory is a few rows of costs.

References
----------
.. [1] R. Zabih and J. Woodfill, "Non-parametric local transforms for computing
   visual correspondence", ECCV 1994.
.. [2] A. Fusiello, V. Roberto and E. Trucco, "Efficient stereo with multiple
   windowing", CVPR 1997.
.. [3] H. Hirschmüller, "Stereo processing by semiglobal matching and mutual
   information", IEEE TPAMI 30(2), 2008.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba as nb
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic
from numpy.typing import NDArray

from robostereo.confidence import DEFAULT_MODEL, FEATURES, ConfidenceModel
from robostereo.edges import EdgeSet
from robostereo.errors import InputError
from robostereo.matching import SimilarityWeights, pair_similarity
from robostereo.parallel import n_threads, run_all

__all__ = [
    "WindowCosts",
    "WindowMatch",
    "census_transform",
    "coarse_range",
    "sobel_x",
    "warm_up",
    "window_costs",
    "window_match",
]

#: census neighbourhood (width, height): 7 x 5 minus the centre = 34 bits
CENSUS_SIZE = (7, 5)
#: half size of the aggregation window (9 x 9) and the shift of the side windows
HALF_WINDOW = 4

@intrinsic
def _popcount(typingctx, x):  # type: ignore[no-untyped-def]
    sig = types.uint64(types.uint64)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        fn = builder.module.declare_intrinsic("llvm.ctpop", [ir.IntType(64)])
        return builder.call(fn, args)

    return sig, codegen


@nb.njit(cache=True, fastmath=True, nogil=True)
def _census_bits(acc, nbr, centre):  # type: ignore[no-untyped-def]
    for x in range(acc.shape[0]):
        acc[x] = (acc[x] << np.uint64(1)) | np.uint64(nbr[x] < centre[x])


@nb.njit(cache=True, nogil=True)
def _census(padded, h, w, hw, hh):  # type: ignore[no-untyped-def]
    out = np.zeros((h, w), np.uint64)
    for y in range(h):
        centre = padded[y + hh, hw:hw + w]
        for dy in range(-hh, hh + 1):
            for dx in range(-hw, hw + 1):
                if dy != 0 or dx != 0:
                    _census_bits(out[y], padded[y + hh + dy, hw + dx:hw + dx + w], centre)
    return out


@nb.njit(cache=True, fastmath=True, nogil=True)
def _shift_in(acc, nbr, centre):  # type: ignore[no-untyped-def]
    """``acc = acc << 1 | (nbr < centre)`` along a row (32-bit lanes, as the floats)."""
    for x in range(acc.shape[0]):
        acc[x] = (acc[x] << np.uint32(1)) | np.uint32(nbr[x] < centre[x])


@nb.njit(cache=True, fastmath=True, nogil=True)
def _census_row(g, y, out, buf, acc):  # type: ignore[no-untyped-def]
    """Row ``y`` of the default 7 x 5 census of ``g`` into ``out`` (W,), the borders
    replicated.  ``buf`` (5, W + 6) float32 receives the five rows padded; ``acc``
    (2, W) uint32 collects the first two bits and the last 32, each comparison done
    along the row for all pixels at once (vector lanes as wide as the floats)."""
    h, w = g.shape
    for dy in range(5):
        src = g[min(max(y + dy - 2, 0), h - 1)]
        b = buf[dy]
        b[3:w + 3] = src
        for k in range(3):
            b[k] = src[0]
            b[w + 3 + k] = src[w - 1]
    centre = buf[2, 3:w + 3]
    hi = acc[0]
    lo = acc[1]
    hi[:] = 0
    lo[:] = 0
    bit = 0
    for dy in range(5):
        for dx in range(7):
            if dy != 2 or dx != 3:
                _shift_in(hi if bit < 2 else lo, buf[dy, dx:dx + w], centre)
                bit += 1
    for x in range(w):
        out[x] = (np.uint64(hi[x]) << np.uint64(32)) | np.uint64(lo[x])


@nb.njit(cache=True, nogil=True)
def _census_7x5(g):  # type: ignore[no-untyped-def]
    h, w = g.shape
    out = np.empty((h, w), np.uint64)
    buf = np.empty((5, w + 6), np.float32)
    acc = np.empty((2, w), np.uint32)
    for y in range(h):
        _census_row(g, y, out[y], buf, acc)
    return out


@nb.njit(cache=True, fastmath=True, nogil=True)
def _sobel_row(g, y, out):  # type: ignore[no-untyped-def]
    """Row ``y`` of the horizontal 3 x 3 Sobel derivative of ``g``, rounded to int16,
    the border reflected without repeating the edge pixel (``BORDER_REFLECT_101``)."""
    h, w = g.shape
    ya = (1 if h > 1 else 0) if y == 0 else y - 1
    yb = (h - 2 if h > 1 else 0) if y == h - 1 else y + 1
    a, b, c = g[ya], g[y], g[yb]
    two = np.float32(2.0)
    for x in range(w):
        xl = (1 if w > 1 else 0) if x == 0 else x - 1
        xr = (w - 2 if w > 1 else 0) if x == w - 1 else x + 1
        v = (a[xr] - a[xl]) + two * (b[xr] - b[xl]) + (c[xr] - c[xl])
        out[x] = np.int16(min(max(np.rint(v), -32767.0), 32767.0))


@nb.njit(cache=True, nogil=True)
def _sobel(g):  # type: ignore[no-untyped-def]
    h, w = g.shape
    out = np.empty((h, w), np.int16)
    for y in range(h):
        _sobel_row(g, y, out[y])
    return out


@nb.njit(cache=True, nogil=True)
def _pixel_row(g, y, valid, check, census_bad, sobel_bad, cen, sob, buf,
               acc):  # type: ignore[no-untyped-def]
    """Census and Sobel of row ``y``; pixels outside ``valid`` (where ``check``) get
    the values that make every pair with them cost nearly the most."""
    _census_row(g, y, cen, buf, acc)
    _sobel_row(g, y, sob)
    if check:
        v = valid[y]
        for x in range(cen.shape[0]):
            if not v[x]:
                cen[x] = census_bad
                sob[x] = sobel_bad


def census_transform(grey: NDArray[np.floating], *, size: tuple[int, int] = CENSUS_SIZE
                     ) -> NDArray[np.uint64]:
    """Census transform: one bit per neighbour, set where it is darker than the centre.

    Parameters
    ----------
    grey : ndarray, shape (H, W)
    size : tuple of int
        ``(width, height)`` of the neighbourhood, odd, at most 64 bits in all.

    Returns
    -------
    ndarray of uint64, shape (H, W)
        Borders replicate the edge pixels.

    Examples
    --------
    >>> g = np.zeros((5, 7), np.float32); g[2, 3] = 9.0
    >>> bin(int(census_transform(g)[2, 3])).count("1"), int(census_transform(g)[0, 0])
    (34, 0)
    """
    wd, ht = size
    if wd % 2 == 0 or ht % 2 == 0 or wd * ht - 1 > 64 or wd < 1 or ht < 1:
        raise InputError(f"census size must be odd (width, height) with at most 65 cells, "
                         f"got {size}")
    hw, hh = wd // 2, ht // 2
    g = np.ascontiguousarray(grey, dtype=np.float32)
    if (wd, ht) == (7, 5):
        return _census_7x5(g)
    padded = np.pad(g, ((hh, hh), (hw, hw)), mode="edge")
    return _census(padded, g.shape[0], g.shape[1], hw, hh)


def sobel_x(grey: NDArray[np.floating]) -> NDArray[np.int16]:
    """Horizontal 3 x 3 Sobel derivative, rounded to whole grey levels (int16).

    The border is reflected without repeating the edge pixel (OpenCV's
    ``BORDER_REFLECT_101``).

    >>> g = np.tile(np.arange(6, dtype=np.float32), (3, 1))
    >>> sobel_x(g)[1, 2:4].tolist()
    [8, 8]
    """
    return _sobel(np.ascontiguousarray(grey, dtype=np.float32))


@nb.njit(cache=True, fastmath=True, nogil=True)
def _pixel_update(colsum, ring, cl, cr, gl, gr, trunc, tmp):  # type: ignore[no-untyped-def]
    """Replace one ring row of pixel costs and update the column sums, for 1-D rows:
    ``p[x] = H(cl[x], cr[x]) + min(|gl[x] - gr[x]|, trunc)``.  The Hamming distances
    go through ``tmp`` so that the rest runs in 16-bit vector lanes."""
    n = colsum.shape[0]
    for x in range(n):
        tmp[x] = np.int16(_popcount(cl[x] ^ cr[x]))
    for x in range(n):
        a = np.int16(gl[x])
        b = np.int16(gr[x])
        g = np.int16(max(a, b) - min(a, b))
        p = np.int16(tmp[x] + np.int16(min(g, trunc)))
        colsum[x] = np.int16(colsum[x] + np.int16(p - ring[x]))
        ring[x] = p


@nb.njit(cache=True, fastmath=True, nogil=True)
def _constant_update(colsum, ring, value):  # type: ignore[no-untyped-def]
    for x in range(colsum.shape[0]):
        colsum[x] += value - ring[x]
        ring[x] = value


@nb.njit(cache=True, fastmath=True, nogil=True)
def _row_update(cl, cr, gl, gr, d0, nd, trunc, pmax, m, colsum, ring,
                compute, tmp):  # type: ignore[no-untyped-def]
    """Pixel costs of one row for every disparity into a ring slot, with the column
    sums: ``[k, x + m]`` pairs left pixel ``x`` with right pixel ``x - d0 - k``; pairs
    that leave the image (and every pair when not ``compute``) cost ``pmax``."""
    w = cl.shape[0]
    for k in range(nd):
        d = d0 + k
        x0 = min(max(d, 0), w)
        x1 = max(min(w + d, w), x0)
        if not compute:
            x0 = x1 = w
        c = colsum[k]
        r = ring[k]
        _constant_update(c[m:m + x0], r[m:m + x0], pmax)
        _constant_update(c[m + x1:m + w], r[m + x1:m + w], pmax)
        if x1 > x0:
            _pixel_update(c[m + x0:m + x1], r[m + x0:m + x1], cl[x0:x1], cr[x0 - d:x1 - d],
                          gl[x0:x1], gr[x0 - d:x1 - d], trunc, tmp)


@nb.njit(cache=True, fastmath=True, nogil=True)
def _box(col, out, t2, t4):  # type: ignore[no-untyped-def]
    """``out[x] = col[x - 4] + ... + col[x + 4]`` (nine columns) by pair sums."""
    n = col.shape[0]
    for x in range(n - 1):
        t2[x] = col[x] + col[x + 1]
    for x in range(n - 3):
        t4[x] = t2[x] + t2[x + 2]
    for x in range(n - 7):
        t2[x] = t4[x] + t4[x + 4]
    for x in range(n - 8):
        out[x + 4] = t2[x] + col[x + 8]


@nb.njit(cache=True, fastmath=True, nogil=True)
def _least(bu, bm, bd, k, x, hw, vertical):  # type: ignore[no-untyped-def]
    """Least window sum at column ``x``, disparity ``k``: centred and half a window left
    and right on the row's box sums ``bm`` (returned second), and with ``vertical``
    also centred on the rows half a window above (``bu``) and below (``bd``)."""
    row = np.int32(min(bm[k, x - hw], min(bm[k, x], bm[k, x + hw])))
    if vertical:
        return min(row, np.int32(min(bu[k, x], bd[k, x]))), row
    return row, row


@nb.njit(cache=True, fastmath=True, nogil=True, inline="always")
def _path_step(cost, prev, cur, p1, p2):  # type: ignore[no-untyped-def]
    """One step of a scanline path (semi-global matching, [3]_ eq. 13):
    ``cur[k] = cost[k] + min(prev[k], prev[k -/+ 1] + p1, min(prev) + p2) - min(prev)``
    (``prev`` and ``cur`` distinct, ``nd >= 2``)."""
    nd = prev.shape[0]
    mn = prev[0]
    for k in range(1, nd):
        mn = min(mn, prev[k])
    jump = mn + p2
    for k in range(1, nd - 1):
        lo = prev[k - 1]
        hi = prev[k + 1]
        c = (lo if lo < hi else hi) + p1
        v = prev[k]
        c = v if v < c else c
        cur[k] = cost[k] + (jump if jump < c else c) - mn
    c = prev[1] + p1
    c = prev[0] if prev[0] < c else c
    cur[0] = cost[0] + (jump if jump < c else c) - mn
    c = prev[nd - 2] + p1
    c = prev[nd - 1] if prev[nd - 1] < c else c
    cur[nd - 1] = cost[nd - 1] + (jump if jump < c else c) - mn


@nb.njit(cache=True, fastmath=True, nogil=True)
def _scanline(bm, m, w, q, p1, p2, bt, fwd, bwd, a, b, c, d):  # type: ignore[no-untyped-def]
    """Window costs of one row aggregated along it, both ways (two paths of
    semi-global matching): ``L_left`` into ``fwd`` and ``L_right`` into ``bwd``, both
    (W, nd).  The two paths are stepped in one loop (independent chains), in float32
    (exact for these sums).  With ``q > 1`` a path disparity is a bin of ``q`` whole
    ones, its cost the least of theirs (wide ranges)."""
    nd_fine = bm.shape[0]
    nd = a.shape[0]
    w = (w + PATH_COLUMN_STEP - 1) // PATH_COLUMN_STEP
    if q == 1:
        for k in range(nd_fine):  # the row's window sums, disparity fastest
            src = bm[k]
            for x in range(w):
                bt[x, k] = np.float32(src[m + PATH_COLUMN_STEP * x])
    else:
        for x in range(w):
            for j in range(nd):
                bt[x, j] = np.float32(np.inf)
        for k in range(nd_fine):
            src = bm[k]
            j = k // q
            for x in range(w):
                bt[x, j] = min(bt[x, j], np.float32(src[m + PATH_COLUMN_STEP * x]))
    for k in range(nd):
        a[k] = bt[0, k]
        fwd[0, k] = a[k]
        c[k] = bt[w - 1, k]
        bwd[w - 1, k] = c[k]
    if nd >= 2:
        for x in range(1, w):  # a, c hold the previous column, b, d the new (swapped)
            xb = w - 1 - x
            if x % 2:
                _path_step(bt[x], a, b, p1, p2)
                _path_step(bt[xb], c, d, p1, p2)
                fwd[x] = b
                bwd[xb] = d
            else:
                _path_step(bt[x], b, a, p1, p2)
                _path_step(bt[xb], d, c, p1, p2)
                fwd[x] = a
                bwd[xb] = c
    else:
        for x in range(w):
            fwd[x, 0] = bt[x, 0]
            bwd[x, 0] = bt[x, 0]


@nb.njit(cache=True, nogil=True)
def _load_row(ga, gb, va, vb, check_a, check_b, yc, cen_a, cen_b, sob_a, sob_b,
              loaded, buf, acc):  # type: ignore[no-untyped-def]
    """Census and Sobel rows ``yc`` of both images into the buffers (once per row)."""
    if loaded[0] != yc:
        _pixel_row(ga, yc, va, check_a, np.uint64(0xAAAAAAAAAAAAAAAA), np.int16(-32000),
                   cen_a, sob_a, buf, acc)
        _pixel_row(gb, yc, vb, check_b, np.uint64(0x5555555555555555), np.int16(32000),
                   cen_b, sob_b, buf, acc)
        loaded[0] = yc


@nb.njit(cache=True, fastmath=True, nogil=True)
def _stream_rows(ga, gb, va, vb, check_a, check_b, row_start, cols, dlo, nd, trunc, pmax,
                 hw, vertical, p1, p2, path_step, y_first, y_last,
                 out):  # type: ignore[no-untyped-def]
    """One pass down rows ``y_first .. y_last - 1`` of the grey images ``ga``, ``gb``;
    ``out[i]`` receives the summary of each edge point ``i`` on them (see
    :class:`WindowCosts`).  Census and Sobel rows are made as the pass needs them."""
    h, w = ga.shape
    n_ring = 2 * hw + 1
    m = 2 * hw
    wp = w + 2 * m
    big = np.int32(OUT_OF_VIEW)
    base = 4 * n_ring  # keeps ring indices of negative rows positive
    ring = np.zeros((n_ring, nd, wp), np.int16)   # pixel costs of the last 2 hw + 1 rows
    colsum = np.zeros((nd, wp), np.int16)         # their column sums
    boxes = np.zeros((n_ring, nd, wp), np.int16)  # window sums of the last 2 hw + 1 rows
    t2 = np.zeros(wp, np.int16)
    t4 = np.zeros(wp, np.int16)
    s5 = np.empty(nd, np.int32)
    s3 = np.empty(nd, np.int32)
    cl = np.empty(w, np.uint64)  # census and Sobel of the row being added
    cr = np.empty(w, np.uint64)
    gl = np.empty(w, np.int16)
    gr = np.empty(w, np.int16)
    loaded = np.full(1, -1, np.int64)
    buf = np.empty((5, w + 6), np.float32)  # padded grey rows for the census
    acc = np.empty((2, w), np.uint32)
    ptmp = np.empty(w, np.int16)  # Hamming distances of a row
    scan = p1 >= 0  # aggregate along the rows too (p1 < 0: not)
    ws = w if scan else 1
    q = max(1, (nd + PATH_MAX_DISPARITIES - 1) // PATH_MAX_DISPARITIES)  # path bins
    ndc = (nd + q - 1) // q
    bt = np.empty((ws, ndc), np.float32)
    fwd = np.empty((ws, ndc), np.float32)
    bwd = np.empty((ws, ndc), np.float32)
    pa = np.empty(ndc, np.float32)
    pb = np.empty(ndc, np.float32)
    pc = np.empty(ndc, np.float32)
    pd = np.empty(ndc, np.float32)
    s_row = np.empty(ndc, np.int32)
    path_row = -1
    colsum[:, :m] = n_ring * pmax
    colsum[:, w + m:] = n_ring * pmax

    def edges_in(y0, y1):  # type: ignore[no-untyped-def]
        return row_start[min(max(y1, 0), h)] > row_start[min(max(y0, 0), h)]

    lag = hw if vertical else 0  # rows of box sums needed below the output row
    j0 = y_first - lag
    # column sums of the window centred on row j0: rows j0 - hw .. j0 + hw, clamped
    for r in range(j0 - hw, j0 + hw + 1):
        yc = min(max(r, 0), h - 1)
        _load_row(ga, gb, va, vb, check_a, check_b, yc, cl, cr, gl, gr, loaded, buf, acc)
        _row_update(cl, cr, gl, gr, dlo, nd, trunc, pmax, m, colsum,
                    ring[(r + base) % n_ring], True, ptmp)
    for j in range(j0, y_last + lag):
        if j > j0:
            r = j + hw  # the new pixel row; its ring slot holds row j - hw - 1
            yc = min(max(r, 0), h - 1)
            needed = edges_in(r - hw - lag, r + hw + lag + 1)
            if needed:
                _load_row(ga, gb, va, vb, check_a, check_b, yc, cl, cr, gl, gr, loaded, buf, acc)
            _row_update(cl, cr, gl, gr, dlo, nd, trunc, pmax, m, colsum,
                        ring[(r + base) % n_ring], needed, ptmp)
        bj = boxes[(j + base) % n_ring]
        if edges_in(j - lag, j + lag + 1):
            for k in range(nd):
                _box(colsum[k], bj[k], t2, t4)
        y = j - lag  # the row whose windows are all complete
        if y < y_first or row_start[y + 1] == row_start[y]:
            continue
        bu = boxes[(y - hw + base) % n_ring]
        bm = boxes[(y + base) % n_ring]
        bd = boxes[(y + hw + base) % n_ring]
        if scan:
            # paths run on every path_step-th row; a row's edge points read those of the
            # nearest such row (their windows share all but a few rows).  The choice
            # depends on y alone, so bands (threads) do not change the result
            y_path = y
            if vertical:
                y_path = min((y + path_step // 2) // path_step * path_step, h - 1)
            if y_path != path_row:
                _scanline(boxes[(y_path + base) % n_ring], m, w, q, np.float32(p1),
                          np.float32(p2), bt, fwd, bwd, pa, pb, pc, pd)
                path_row = y_path
        for i in range(row_start[y], row_start[y + 1]):
            c = cols[i]
            xc = c + m
            k5 = -1
            c5 = big
            k3 = -1
            c3 = big
            n_in = 0
            for k in range(nd):
                xr = c - dlo - k
                if xr < 0 or xr >= w:
                    s5[k] = big
                    s3[k] = big
                    continue
                n_in += 1
                v5, v3 = _least(bu, bm, bd, k, xc, hw, vertical)
                s5[k] = v5
                s3[k] = v3
                if v5 < c5:
                    c5 = v5
                    k5 = k
                if v3 < c3:
                    c3 = v3
                    k3 = k
            f5 = big
            f3 = big
            for k in range(nd):
                if abs(k - k5) > 1 and s5[k] < f5:
                    f5 = s5[k]
                if abs(k - k3) > 1 and s3[k] < f3:
                    f3 = s3[k]
            o = out[i]
            o[0] = k5
            o[1] = c5
            o[2] = f5
            o[3] = s5[k5 - 1] if k5 > 0 else big
            o[4] = s5[k5 + 1] if 0 <= k5 < nd - 1 else big
            o[5] = k3
            o[6] = c3
            o[7] = f3
            o[8] = n_in
            o[9] = -1
            if k5 < 0:
                continue
            # the right pixel of the best disparity against every left pixel
            xr = c - dlo - k5
            kr = -1
            cb = big
            for k in range(nd):
                xl = xr + dlo + k
                if xl < 0 or xl >= w:
                    continue
                v, _ = _least(bu, bm, bd, k, xl + m, hw, vertical)
                if v < cb:
                    cb = v
                    kr = k
            o[9] = kr
            if scan:  # the aggregated costs: best, its cost, the best more than 1 off
                sr_ = s_row
                cq = c // PATH_COLUMN_STEP
                for j in range(ndc):
                    sr_[j] = np.int32(fwd[cq, j] + bwd[cq, j])
                # a bin is in view where one of its disparities is: k in k_lo .. k_hi
                k_lo = max(c - dlo - w + 1, 0)
                k_hi = min(c - dlo, nd - 1)
                js = -1
                cs = big
                for j in range(ndc):
                    if j * q <= k_hi and (j + 1) * q - 1 >= k_lo and sr_[j] < cs:
                        cs = sr_[j]
                        js = j
                fs = big
                for j in range(ndc):
                    if (j * q <= k_hi and (j + 1) * q - 1 >= k_lo and abs(j - js) > 1
                            and sr_[j] < fs):
                        fs = sr_[j]
                o[11] = cs
                o[12] = fs
                if q == 1 or js < 0:
                    o[10] = js
                    o[13] = sr_[js - 1] if js > 0 else big
                    o[14] = sr_[js + 1] if 0 <= js < ndc - 1 else big
                else:  # the bin's best whole disparity by the windows, their parabola
                    ks = -1
                    cb = big
                    for k in range(js * q, min(nd, (js + 1) * q)):
                        if s5[k] < cb:
                            cb = s5[k]
                            ks = k
                    o[10] = ks
                    o[13] = s5[ks - 1] if ks > 0 else big
                    o[14] = s5[ks + 1] if 0 <= ks < nd - 1 else big


@dataclass(frozen=True)
class WindowCosts:
    """Window costs of left edge points over the whole-pixel disparity range, summed up.

    Disparity ``k`` stands for ``d_min + k``; costs are window sums of pixel costs
    (:func:`window_costs`, Notes); ``OUT_OF_VIEW`` where there is no such cost.  Arrays
    have shape ``(N,)``.

    Attributes
    ----------
    d_min, n_disparities : int
    best, cost : ndarray of int
        The best disparity ``k1`` (-1 where every right pixel is outside the image) and
        its cost ``c1``, with all five windows.
    second : ndarray of int
        The least cost more than one disparity away from ``k1``.
    before, after : ndarray of int
        The costs at ``k1 - 1`` and ``k1 + 1`` (for the sub-pixel parabola).
    best_row, cost_row, second_row : ndarray of int
        The same with the three windows along the row only.
    in_view : ndarray of int
        Disparities whose right pixel is inside the image.
    right_best : ndarray of int
        Best disparity of the right pixel ``x - d_min - k1`` against every left pixel
        (the left-right check); -1 where there is none.
    best_path, cost_path, second_path, before_path, after_path : ndarray of int
        The same as ``best`` ... ``after`` for the centred window costs aggregated
        along the row both ways (:func:`window_costs`, Notes); -1 without paths.  Over
        more than :data:`PATH_MAX_DISPARITIES` the paths' disparities are bins:
        ``best_path`` is then the windows' best whole disparity in the best bin, the
        costs are the bins', ``before_path`` and ``after_path`` the windows' (for the
        parabola).
    """

    d_min: int
    n_disparities: int
    best: NDArray[np.int32]
    cost: NDArray[np.int32]
    second: NDArray[np.int32]
    before: NDArray[np.int32]
    after: NDArray[np.int32]
    best_row: NDArray[np.int32]
    cost_row: NDArray[np.int32]
    second_row: NDArray[np.int32]
    in_view: NDArray[np.int32]
    right_best: NDArray[np.int32]
    best_path: NDArray[np.int32]
    cost_path: NDArray[np.int32]
    second_path: NDArray[np.int32]
    before_path: NDArray[np.int32]
    after_path: NDArray[np.int32]


#: the feature columns that :func:`_evidence` fills, in the order it computes them, and
#: the two that the right edge point gives
_EVIDENCE_COLUMNS = np.array([FEATURES.index(name) for name in (
    "uniqueness", "uniqueness_row", "row_agree", "left_right", "out_of_view",
    "path_uniqueness", "path_agree", "path_swapped")], np.int64)
_RIGHT_EDGE, _SIMILARITY = FEATURES.index("right_edge"), FEATURES.index("similarity")

#: cost value of a disparity whose right pixel lies outside the image
OUT_OF_VIEW = 2**30

#: ``(P1, P2)`` of the paths along the rows, per pixel of the window (chosen
#: leave-one-scene-out by ``benchmarks/fit_confidence.py``): a jump costs more than any
#: window, so a path changes disparity by ramps of one pixel at ``P1`` each
PATH_PENALTIES = (5.0, 160.0)

#: paths run on every fifth row, over every second column (a step of the path is two
#: columns); edge points read the nearest path row (at most two rows away, within the
#: nine rows of their windows)
PATH_ROW_STEP = 5
PATH_COLUMN_STEP = 2

#: paths over at most this many disparities: a wider range is binned (a path
#: disparity stands for 2, 3, ... whole ones, its cost their least), so their cost stops
#: growing with the range; the developer scenes (up to 97) are not binned
PATH_MAX_DISPARITIES = 128

#: where the paths' best disparity is more than a pixel from the windows', it is taken
#: instead when its uniqueness exceeds this (leave-one-scene-out, as the penalties)
SWAP_UNIQUENESS = 0.1

#: a search range of more whole disparities than this is first narrowed by a pass at
#: half resolution (:func:`coarse_range`); narrower ones are searched whole
COARSE_MIN_DISPARITIES = 64

#: the narrowed range reaches this many pixels beyond the half-resolution disparities
#: found (one coarse pixel of error each way, twice)
COARSE_MARGIN = 4


def _halve(image: NDArray[np.generic], *, mask: bool = False) -> NDArray[np.generic]:
    """2 x 2 binning (an odd last row or column dropped): the mean, or for a mask the
    pixels whose four sources are all set."""
    h, w = image.shape[0] // 2, image.shape[1] // 2
    if mask:
        return np.ascontiguousarray(image[:2 * h, :2 * w].reshape(h, 2, w, 2).all(axis=(1, 3)))
    # an area resize by exactly one half is the mean of each 2 x 2 block
    return cv2.resize(image[:2 * h, :2 * w].astype(np.float32, copy=False), (w, h),
                      interpolation=cv2.INTER_AREA)


def coarse_range(
    grey_left: NDArray[np.floating],
    grey_right: NDArray[np.floating],
    rows: NDArray[np.integer],
    columns: NDArray[np.integer],
    disparity_range: tuple[int, int],
    *,
    gradient_truncation: int = 64,
    valid_left: NDArray[np.bool_] | None = None,
    valid_right: NDArray[np.bool_] | None = None,
    margin: int = COARSE_MARGIN,
) -> tuple[int, int]:
    """The part of a wide disparity range that the scene holds, from a pass at half size.

    Parameters
    ----------
    grey_left, grey_right : ndarray, shape (H, W)
    rows, columns : ndarray of int, shape (N,)
        Left edge pixels, sorted by row.
    disparity_range : tuple of int
        ``(d_min, d_max)``, whole pixels, inclusive.
    gradient_truncation : int
    valid_left, valid_right : ndarray of bool, shape (H, W), optional
        See :func:`window_costs`.
    margin : int
        Pixels added beyond the disparities found, each way.

    Returns
    -------
    tuple of int
        ``(d_min, d_max)`` within `disparity_range`: the hull of the disparities at
        which the edge points match at half resolution, passing the left-right
        check and backed by a neighbour (another such match within two pixels and
        one disparity), widened by `margin`.  The whole range where none passes.

    Notes
    -----
    Both images binned 2 x 2 (a quarter of the pixels), the edge pixels halved, the
    range halved: the window costs (:func:`window_costs`, centred and side windows,
    no paths) cost about an eighth of the full pass.  A far disparity that no edge
    point holds consistently in both directions is not searched at full size: with a
    generous range given, the full pass costs what the scene needs (a coarse-to-fine
    pruning of the range; a thin object that no half-size edge point matches is lost).

    Examples
    --------
    >>> rng = np.random.default_rng(2)
    >>> left = rng.uniform(0, 127, (64, 160)).astype(np.float32)
    >>> right = np.roll(left, -20, axis=1)
    >>> r, c = np.repeat(np.arange(8, 56, 4), 10), np.tile(np.arange(60, 160, 10), 12)
    >>> coarse_range(left, right, r, c, (0, 100))
    (16, 24)
    """
    d_lo, d_hi = (int(v) for v in disparity_range)
    ga, gb = _halve(np.asarray(grey_left, np.float32)), _halve(np.asarray(grey_right, np.float32))
    h, w = ga.shape
    if h < 2 * HALF_WINDOW + 1 or w < 2 * HALF_WINDOW + 1 or len(rows) == 0:
        return d_lo, d_hi
    marked = np.zeros(h * w, np.bool_)  # the halved edge pixels, each once, by row
    marked[np.minimum(np.asarray(rows, np.int64) // 2, h - 1) * w
           + np.minimum(np.asarray(columns, np.int64) // 2, w - 1)] = True
    key = np.flatnonzero(marked)
    masks = [None if v is None else _halve(np.asarray(v, np.bool_), mask=True)
             for v in (valid_left, valid_right)]
    c_lo, c_hi = d_lo // 2, -(-d_hi // 2)
    wc = window_costs(ga, gb, key // w, key % w, (c_lo, c_hi),
                      gradient_truncation=gradient_truncation, valid_left=masks[0],
                      valid_right=masks[1], path_penalties=None)
    ok = (wc.best >= 0) & (wc.right_best >= 0) & (np.abs(wc.right_best - wc.best) <= 1)
    # an edge is a curve: a match counts where a neighbour within two pixels matches
    # within a pixel of it too, which a lone false match does not
    r, c, d = key[ok] // w + 2, key[ok] % w + 2, wc.best[ok].astype(np.int64)
    held = np.full((h + 4, w + 4), -(1 << 40), np.int64)
    held[r, c] = d
    backed = np.zeros(d.shape, np.bool_)
    for dy in range(-2, 3):
        for dx in range(-2, 3):
            if dy or dx:
                backed |= np.abs(held[r + dy, c + dx] - d) <= 1
    if not np.any(backed):
        return d_lo, d_hi
    found = d[backed] + c_lo
    return (max(d_lo, 2 * int(found.min()) - margin),
            min(d_hi, 2 * int(found.max()) + margin))


def window_costs(
    grey_left: NDArray[np.floating],
    grey_right: NDArray[np.floating],
    rows: NDArray[np.integer],
    columns: NDArray[np.integer],
    disparity_range: tuple[int, int],
    *,
    gradient_truncation: int = 64,
    vertical: bool = True,
    valid_left: NDArray[np.bool_] | None = None,
    valid_right: NDArray[np.bool_] | None = None,
    path_penalties: tuple[float, float] | None = PATH_PENALTIES,
) -> WindowCosts:
    """Side-aware census + gradient window costs at left pixels, every disparity.

    Parameters
    ----------
    grey_left, grey_right : ndarray, shape (H, W)
        Grey images on the seed's 0..127 scale (:func:`robostereo.edges.to_grey`).
    rows, columns : ndarray of int, shape (N,)
        Pixels of the left edge points, sorted by row.
    disparity_range : tuple of int
        ``(d_min, d_max)``, whole pixels, inclusive.
    gradient_truncation : int
        Largest gradient difference counted per pixel pair (grey levels of the Sobel
        derivative on the 0..127 scale).
    vertical : bool
        Also place the window half a window up and down (five placements in all),
        for depth edges across the rows; False: the three placements along the row.
    valid_left, valid_right : ndarray of bool, shape (H, W), optional
        Pixels that hold image data (e.g. inside a rectification's source); a pair
        with an invalid pixel costs nearly the most a pair can.
    path_penalties : tuple of float or None
        ``(P1, P2)`` of the paths along the row, per pixel of the window: the cost of
        a one-pixel change of disparity between neighbouring columns and of a larger
        jump (Notes, 6).  None: no paths.

    Returns
    -------
    WindowCosts

    Notes
    -----
    1. Pixel cost ``c(x, d) = H(C_l(x), C_r(x - d)) + min(|S_l(x) - S_r(x - d)|, T)``
       with ``C`` the 7 x 5 census, ``H`` the Hamming distance and ``S`` the
       horizontal Sobel derivative.
    2. Column sums of ``c`` over nine rows, kept running down the image.
    3. For an edge pixel ``x`` and each ``d``, the sums of nine columns around
       ``x - 4``, ``x`` and ``x + 4``; the lowest is the cost (side-aware windows).
    4. For the right pixel ``x_r = x - d*`` of the best disparity, the same cost
       against the left pixels ``x_r + d`` for every ``d`` (left-right check).
    5. Per point only a summary is kept (:class:`WindowCosts`), and census and Sobel
       rows are made as the pass reaches them: memory is a few rows of costs, whatever
       the range, and no transformed image is stored.
    6. The centred window costs ``C(x, d)`` of the row are also aggregated along it,
       from the left and from the right, as two paths of semi-global matching [3]_
       (eq. 13): ``L(x, d) = C(x, d) + min(L(x', d), L(x', d -/+ 1) + P1,
       min_k L(x', k) + P2) - min_k L(x', k)`` with ``x'`` the previous column; their
       sum is read at the edge points (``best_path`` ...).  A path carries the
       disparity of textured parts of the row into ambiguous ones (repeated patterns,
       weak texture), where a window alone has two near-equal minima.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> left = rng.uniform(0, 127, (30, 60)).astype(np.float32)
    >>> right = np.roll(left, -6, axis=1)
    >>> wc = window_costs(left, right, np.array([15]), np.array([30]), (0, 12))
    >>> int(wc.best[0]) + wc.d_min, int(wc.right_best[0]) + wc.d_min, int(wc.cost[0])
    (6, 6, 0)
    """
    gl = np.ascontiguousarray(grey_left, dtype=np.float32)
    gr = np.ascontiguousarray(grey_right, dtype=np.float32)
    if gl.shape != gr.shape or gl.ndim != 2:
        raise InputError(f"grey images must be (H, W) of one size, got {gl.shape}, {gr.shape}")
    d_lo, d_hi = (int(v) for v in disparity_range)
    if d_lo > d_hi:
        raise InputError(f"disparity_range must have min <= max, got {disparity_range}")
    r = np.ascontiguousarray(rows, dtype=np.int64)
    c = np.ascontiguousarray(columns, dtype=np.int64)
    h, w = gl.shape
    if r.shape != c.shape or r.ndim != 1:
        raise InputError("rows and columns must be 1-D arrays of one length")
    if r.size and (np.any(np.diff(r) < 0) or r.min() < 0 or r.max() >= h or c.min() < 0
                   or c.max() >= w):
        raise InputError("edge pixels must lie in the image and be sorted by row")
    # invalid pixels get a gradient that differs from any by more than the truncation
    # and a census of alternating bits, so that any pair with one costs nearly the most
    masks = []
    for name, valid in (("valid_left", valid_left), ("valid_right", valid_right)):
        if valid is None:
            masks.append(np.ones((1, 1), np.bool_))
            continue
        vm = np.ascontiguousarray(valid, dtype=np.bool_)
        if vm.shape != gl.shape:
            raise InputError(f"{name} must have the images' shape {gl.shape}, got {vm.shape}")
        masks.append(vm)
    checks = [m.shape == gl.shape and not bool(m.all()) for m in masks]
    nd = d_hi - d_lo + 1
    n = r.shape[0]
    out = np.full((n, 15), -1, np.int32)
    if n:
        row_start = np.searchsorted(r, np.arange(h + 1)).astype(np.int64)
        trunc = int(gradient_truncation)
        area = (2 * HALF_WINDOW + 1) ** 2
        if path_penalties is None:
            p1, p2 = -1, -1
        else:
            pp = [float(v) for v in path_penalties]
            if len(pp) != 2 or not all(np.isfinite(pp)) or not 0 <= pp[0] <= pp[1] <= 200:
                raise InputError(f"path_penalties must be (P1, P2) with 0 <= P1 <= P2 <= 200 "
                                 f"per window pixel, got {path_penalties}")
            p1, p2 = round(pp[0] * area), round(pp[1] * area)
        # bands of at least 64 rows, one per thread: a band repeats 2 * HALF_WINDOW rows
        n_bands = max(1, min(n_threads(), h // 64))
        step = -(-h // n_bands)

        def band(y0: int) -> None:
            _stream_rows(gl, gr, masks[0], masks[1], checks[0], checks[1], row_start, c,
                         d_lo, nd, np.int16(trunc), np.int16(34 + trunc), HALF_WINDOW,
                         bool(vertical), p1, p2, PATH_ROW_STEP, y0, min(h, y0 + step), out)

        run_all([lambda y0=y0: band(y0) for y0 in range(0, h, step)])
    cols = dict(zip(("best", "cost", "second", "before", "after", "best_row", "cost_row",
                     "second_row", "in_view", "right_best", "best_path", "cost_path",
                     "second_path", "before_path", "after_path"), out.T, strict=True))
    return WindowCosts(d_min=d_lo, n_disparities=nd, **cols)


@dataclass(frozen=True)
class WindowMatch:
    """Best disparity of every left edge point, its evidence and its confidence.

    Attributes
    ----------
    disparity : ndarray of float, shape (N,)
        Sub-pixel disparity ``x_left - x_right`` of the best window cost: from the
        right edge point it lands on where there is one (edge positions are precise
        to a twentieth of a pixel), else the vertex of the parabola through the costs
        at the best disparity and its two neighbours.  NaN where the whole search
        range is out of view.
    right_edge : ndarray of int, shape (N,)
        Index of that right edge point, -1 where there is none.
    features : ndarray of float, shape (N, F)
        The evidence, columns named by :data:`robostereo.confidence.FEATURES`.
    confidence : ndarray of float, shape (N,)
        Calibrated ``P(correct)`` of the best disparity; NaN where there is none.
    costs : WindowCosts
        The window costs the match was read from.
    """

    disparity: NDArray[np.float64]
    right_edge: NDArray[np.intp]
    features: NDArray[np.float64]
    confidence: NDArray[np.float64]
    costs: WindowCosts


@nb.njit(cache=True, nogil=True)
def _nearest_on_lines(l_line, l_sign, x_right, r_line, r_x, r_sign, n_lines
                      ):  # type: ignore[no-untyped-def]
    n = l_line.shape[0]
    idx = np.full(n, -1, np.int64)
    dist = np.full(n, np.inf)
    start = np.searchsorted(r_line, np.arange(n_lines + 1))
    for i in range(n):
        q = x_right[i]
        ln = l_line[i]
        if not np.isfinite(q) or ln < 0 or ln >= n_lines:
            continue
        a, b = start[ln], start[ln + 1]
        j = a + np.searchsorted(r_x[a:b], q)
        for jj in (j - 1, j):  # the two right points around x_right on the line
            if a <= jj < b and r_sign[jj] == l_sign[i]:
                dd = abs(r_x[jj] - q)
                if dd < dist[i]:
                    dist[i] = dd
                    idx[i] = jj
    return idx, dist


def _nearest_right_edge(left: EdgeSet, right: EdgeSet, x_right: NDArray[np.float64]
                        ) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """Per left edge point, the right edge point next to ``x_right`` on its line (the
    nearer of the two around it, if it has the same contrast sign), and the distance
    (``inf`` where none)."""
    if len(left) == 0 or len(right) == 0:
        return np.full(len(left), -1, dtype=np.intp), np.full(len(left), np.inf)
    n_lines = int(max(int(left.line.max()), int(right.line.max())) + 1)
    idx, dist = _nearest_on_lines(
        np.ascontiguousarray(left.line, np.int64), np.ascontiguousarray(left.sign, np.int8),
        np.ascontiguousarray(x_right, np.float64), np.ascontiguousarray(right.line, np.int64),
        np.ascontiguousarray(right.x, np.float64), np.ascontiguousarray(right.sign, np.int8),
        n_lines)
    return idx.astype(np.intp), dist


@nb.njit(cache=True, nogil=True)
def _unique(c1, c2):  # type: ignore[no-untyped-def]
    """``(c2 - c1) / c2`` clipped to 0..1; 0 where either is out of view."""
    if c1 >= OUT_OF_VIEW or c2 >= OUT_OF_VIEW:
        return 0.0
    return min(max((c2 - c1) / max(c2, 1.0), 0.0), 1.0)


@nb.njit(cache=True, nogil=True)
def _vertex(k, cm, c0, cp, d_lo):  # type: ignore[no-untyped-def]
    """Disparity of the parabola's vertex through the costs at ``k - 1, k, k + 1``."""
    den = cm - 2.0 * c0 + cp
    off = 0.0
    if cm < OUT_OF_VIEW and cp < OUT_OF_VIEW and den > 0:
        off = min(max(0.5 * (cm - cp) / den, -0.5), 0.5)
    return d_lo + k + off


@nb.njit(cache=True, nogil=True)
def _evidence(best, cost, second, before, after, best_row, cost_row, second_row,
              right_best, best_path, cost_path, second_path, before_path, after_path,
              in_view, d_lo, nd, swap_u, feats, cols):  # type: ignore[no-untyped-def]
    """Per point: the whole-pixel disparity refined by its parabola (the paths' where
    they are taken), whether there is one, and into ``feats`` (N, F) the evidence of
    :data:`robostereo.confidence.FEATURES` but the right edge point's two columns, in
    the columns ``cols`` (:data:`_EVIDENCE_COLUMNS`)."""
    n = best.shape[0]
    d_par = np.full(n, np.nan)
    seen = np.zeros(n, np.bool_)
    for i in range(n):
        k1 = best[i]
        s = k1 >= 0
        uniq = _unique(float(cost[i]), float(second[i]))
        if s:
            d_par[i] = _vertex(k1, float(before[i]), float(cost[i]), float(after[i]), d_lo)
        kp = best_path[i]
        u_path = 0.0
        agree = True
        swap = False
        if kp >= 0:
            u_path = _unique(float(cost_path[i]), float(second_path[i]))
            agree = s and abs(kp - k1) <= 1
            swap = not agree and u_path > swap_u
            if swap:
                d_par[i] = _vertex(kp, float(before_path[i]), float(cost_path[i]),
                                   float(after_path[i]), d_lo)
        s = s or swap
        seen[i] = s
        # the right pixel's best disparity is the same or one off (none: only when a
        # single disparity is searched, where there is nothing to disagree with)
        lr_ok = abs(right_best[i] - k1) <= 1 if right_best[i] >= 0 else nd <= 1
        u_row = 0.0
        if s and abs(best_row[i] - k1) <= 1:
            u_row = _unique(float(cost_row[i]), float(second_row[i]))
        f = feats[i]
        f[cols[0]] = uniq
        f[cols[1]] = u_row
        f[cols[2]] = 1.0 if u_row > 0 else 0.0
        f[cols[3]] = 1.0 if lr_ok else 0.0
        f[cols[4]] = 1.0 - in_view[i] / max(nd, 1)
        f[cols[5]] = u_path
        f[cols[6]] = 1.0 if agree else 0.0
        f[cols[7]] = 1.0 if swap else 0.0
    return d_par, seen


def window_match(
    left: EdgeSet,
    right: EdgeSet,
    grey_left: NDArray[np.floating],
    grey_right: NDArray[np.floating],
    disparity_range: tuple[float, float],
    *,
    gradient_truncation: int = 64,
    weights: SimilarityWeights | None = None,
    profile_scale: float | None = 10.0,
    model: ConfidenceModel | None = None,
    valid_left: NDArray[np.bool_] | None = None,
    valid_right: NDArray[np.bool_] | None = None,
    vertical: bool = True,
    path_penalties: tuple[float, float] | None = PATH_PENALTIES,
    coarse: bool = True,
) -> WindowMatch:
    """Best disparity and calibrated confidence of every left edge point.

    Parameters
    ----------
    left, right : EdgeSet
        Edge points of the two images (:func:`robostereo.edges.detect_edges`).
    grey_left, grey_right : ndarray, shape (H, W)
        The grey images they were found in (0..127 scale).
    disparity_range : tuple of float
        ``(min, max)`` disparity; every whole pixel from ``floor(min)`` to ``ceil(max)``
        is scored, and results more than half a pixel outside are dropped.
    gradient_truncation : int
        See :func:`window_costs`.
    weights, profile_scale
        The seed's similarity weights and robostereo's edge-profile factor, for the
        ``similarity`` feature (:func:`robostereo.matching.pair_similarity`).
    model : ConfidenceModel, optional
        Default :data:`robostereo.confidence.DEFAULT_MODEL`.
    valid_left, valid_right : ndarray of bool, shape (H, W), optional
        Pixels that hold image data (see :func:`window_costs`).
    vertical : bool
        Windows above and below too (see :func:`window_costs`).
    path_penalties : tuple of float or None
        Paths along the rows (see :func:`window_costs`); None: none.
    coarse : bool
        Narrow a range of more than :data:`COARSE_MIN_DISPARITIES` whole disparities
        to the part the scene holds by a pass at half size first
        (:func:`coarse_range`); False: search it all.

    Returns
    -------
    WindowMatch

    Notes
    -----
    1. Window costs over the range (:func:`window_costs`), a wide range first
       narrowed at half size (:func:`coarse_range`).
    2. Best disparity ``d1`` (cost ``c1``); ``c2`` the best cost more than one pixel
       away; uniqueness ``(c2 - c1) / c2`` (0 when no such disparity is in view).
    3. Left-right check: the right pixel ``x - d1`` scored against every left pixel;
       its best disparity should be ``d1`` (or one pixel off).
    4. Sub-pixel disparity from the right edge point within half a pixel of
       ``x - d`` (same contrast sign), else from the parabola of the costs.
    5. Paths along the row (:func:`window_costs`, Notes 6): where their best
       disparity is more than a pixel from the windows' and their uniqueness is above
       :data:`SWAP_UNIQUENESS`, theirs is taken (parabola of the path costs, then the
       right edge point there as in 4); their agreement and uniqueness are evidence.
    6. Confidence from the evidence by the calibrated model
       (:mod:`robostereo.confidence`).
    """
    lo, hi = float(disparity_range[0]), float(disparity_range[1])
    d_lo, d_hi = int(np.floor(lo)), int(np.ceil(hi))
    if coarse and d_hi - d_lo + 1 > COARSE_MIN_DISPARITIES:
        d_lo, d_hi = coarse_range(grey_left, grey_right, left.row, left.column, (d_lo, d_hi),
                                  gradient_truncation=gradient_truncation,
                                  valid_left=valid_left, valid_right=valid_right)
    wc = window_costs(grey_left, grey_right, left.row, left.column, (d_lo, d_hi),
                      gradient_truncation=gradient_truncation, valid_left=valid_left,
                      valid_right=valid_right, vertical=vertical,
                      path_penalties=path_penalties)
    n, nd = len(left), wc.n_disparities
    feats = np.zeros((n, len(FEATURES)))
    d_par, seen = _evidence(
        wc.best, wc.cost, wc.second, wc.before, wc.after, wc.best_row, wc.cost_row,
        wc.second_row, wc.right_best, wc.best_path, wc.cost_path, wc.second_path,
        wc.before_path, wc.after_path, wc.in_view, d_lo, nd, SWAP_UNIQUENESS, feats,
        _EVIDENCE_COLUMNS)
    idx, dist = _nearest_right_edge(left, right, left.x - d_par)
    d_edge = left.x - right.x[np.maximum(idx, 0)] if len(right) else d_par
    use_edge = dist <= 0.5  # |d_edge - d_par|: a right edge point within half a pixel
    disparity = np.where(use_edge, d_edge, d_par)
    in_range = (disparity >= lo - 0.5) & (disparity <= hi + 0.5) & seen
    disparity = np.where(in_range, disparity, np.nan)
    right_edge = np.where(use_edge & in_range, idx, -1).astype(np.intp)
    feats[:, _RIGHT_EDGE] = use_edge
    if np.any(use_edge):
        sel = np.nonzero(use_edge)[0]
        feats[sel, _SIMILARITY] = pair_similarity(left, right, sel, idx[sel], weights=weights,
                                                  profile_scale=profile_scale)[4]
    conf = (model or DEFAULT_MODEL)(feats)
    conf = np.where(np.isfinite(disparity), conf, np.nan)
    return WindowMatch(disparity=disparity, right_edge=right_edge, features=feats,
                       confidence=conf, costs=wc)


def warm_up() -> None:
    """Load (or compile) the numba kernels once, on a tiny pair, so that the first real
    match is timed like the others (``robostereo evaluate`` calls it)."""
    from robostereo.pipeline import match_stereo

    g = np.random.default_rng(0).integers(0, 255, (128, 96)).astype(np.uint8)
    match_stereo(g, np.roll(g, -2, axis=1), (0.0, 4.0))
