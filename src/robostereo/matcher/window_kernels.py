"""Numba kernels of the window matcher: census, Sobel, window sums, paths, evidence.

The compiled part of :mod:`robostereo.matcher.window_costs` (one pass down the image
that leaves a summary of the window costs per left edge point, :func:`stream_rows`) and
of :mod:`robostereo.matcher.window_match` (the evidence read from that summary,
:func:`evidence`, and the right edge point next to a disparity,
:func:`nearest_on_lines`).  Only numba functions and the constants they compile in;
the checks, bands and threads are in the Python modules that call them.

References
----------
.. [1] R. Zabih and J. Woodfill, "Non-parametric local transforms for computing
   visual correspondence", ECCV 1994.
.. [2] H. Hirschmüller, "Stereo processing by semiglobal matching and mutual
   information", IEEE TPAMI 30(2), 2008.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

__all__ = [
    "CENSUS_SIZE",
    "HALF_WINDOW",
    "OUT_OF_VIEW",
    "PATH_COLUMN_STEP",
    "PATH_MAX_DISPARITIES",
    "PATH_ROW_STEP",
    "census_7x5",
    "census_padded",
    "evidence",
    "nearest_on_lines",
    "sobel",
    "stream_rows",
]

#: census neighbourhood (width, height): 7 x 5 minus the centre = 34 bits
CENSUS_SIZE = (7, 5)
#: half size of the aggregation window (9 x 9) and the shift of the side windows
HALF_WINDOW = 4

#: cost value of a disparity whose right pixel lies outside the image
OUT_OF_VIEW = 2**30

#: paths run on every fifth row, over every second column (a step of the path is two
#: columns); edge points read the nearest path row (at most two rows away, within the
#: nine rows of their windows)
PATH_ROW_STEP = 5
PATH_COLUMN_STEP = 2

#: paths over at most this many disparities: a wider range is binned (a path
#: disparity stands for 2, 3, ... whole ones, its cost their least), so their cost stops
#: growing with the range; the developer scenes (up to 97) are not binned
PATH_MAX_DISPARITIES = 128

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
def census_padded(padded, h, w, hw, hh):  # type: ignore[no-untyped-def]
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
def census_7x5(g):  # type: ignore[no-untyped-def]
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
def sobel(g):  # type: ignore[no-untyped-def]
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
    """One step of a scanline path (semi-global matching, [2]_ eq. 13):
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
def stream_rows(ga, gb, va, vb, check_a, check_b, row_start, cols, dlo, nd, trunc, pmax,
                 hw, vertical, p1, p2, path_step, y_first, y_last,
                 out):  # type: ignore[no-untyped-def]
    """One pass down rows ``y_first .. y_last - 1`` of the grey images ``ga``, ``gb``;
    ``out[i]`` receives the summary of each edge point ``i`` on them (see
    :class:`~robostereo.matcher.window_costs.WindowCosts`).  Census and Sobel rows
    are made as the pass needs them."""
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


@nb.njit(cache=True, nogil=True)
def nearest_on_lines(l_line, l_sign, x_right, r_line, r_x, r_sign, n_lines
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
def evidence(best, cost, second, before, after, best_row, cost_row, second_row,
              right_best, best_path, cost_path, second_path, before_path, after_path,
              in_view, d_lo, nd, swap_u, feats, cols):  # type: ignore[no-untyped-def]
    """Per point: the whole-pixel disparity refined by its parabola (the paths' where
    they are taken), whether there is one, and into ``feats`` (N, F) the evidence of
    :data:`robostereo.matcher.confidence.FEATURES` but the right edge point's two
    columns, in the columns ``cols`` (the caller's table of them)."""
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
