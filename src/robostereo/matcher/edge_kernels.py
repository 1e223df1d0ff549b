"""Numba kernels of the edge stage: gradient peaks along rows and their features.

:func:`robostereo.matcher.edges.detect_edges` calls :func:`strip_points` on each strip of
smoothed rows: the peaks of the row gradient (:func:`gradient_peaks`, thesis 3.1 [1]_) and
what the row gives of their features (:func:`peak_values`, thesis 3.2: sub-pixel
position, sign, magnitude, the grey levels either side); then, on all the peaks,
:func:`peak_links`: connectivity (:func:`connect_sorted`), pattern type
(:func:`pattern_of`) and 5 x 5 mean grey (:func:`mean5_at`).  :func:`edge_points` does
the same on a whole smoothed image at once.  :func:`connect` and :func:`patterns`
serve :func:`robostereo.matcher.edge_features.connectivity` and
:func:`robostereo.matcher.edge_features.pattern_type` on points in any order;
:func:`rgb_to_grey` converts colour images to grey with OpenCV's values (:func:`fma32`).
Only numba functions and the constants they compile in.

References
----------
.. [1] T.-Q. Kim, "A robot vision system for determining 3-D coordinates of
   object points", M.S. thesis, NJIT, 1989, sections 3.1-3.2.
"""

from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from robostereo.matcher.jit import kernel

__all__ = [
    "FINE_DEAD_ZONE_PX",
    "SIDE_OFFSET",
    "SPAN_COLUMNS",
    "blur_column",
    "blur_row",
    "blurred_span",
    "connect",
    "connect_sorted",
    "edge_points",
    "fine_offset",
    "fine_positions",
    "fine_positions_grey",
    "fma32",
    "gradient_peaks",
    "mean5_at",
    "pattern_of",
    "patterns",
    "peak_features",
    "peak_links",
    "peak_values",
    "rgb_to_grey",
    "scaled_grey",
    "strip_points",
]

#: how far (pixels) the grey levels beside an edge are sampled, either side
SIDE_OFFSET = 4

#: pixels: an edge placed on a lightly blurred image (:func:`fine_offset`) moves from its
#: smoothed position only by the part of the move beyond this.  On clean edges the
#: smoothed position is the more precise (on the simulated robot's block the light
#: blur's parabola is off by a few hundredths of a pixel with the sub-pixel phase, which
#: raised the depth RMS from 1.17 to 1.66 mm); the pull of texture at an outline moves
#: the edge by tenths of a pixel.  0.05 leaves the block's edges where they were.
FINE_DEAD_ZONE_PX = 0.05


@intrinsic
def fma32(typingctx, a, b, c):  # type: ignore[no-untyped-def]
    """``a * b + c`` in float32 rounded once (LLVM's ``llvm.fma.f32``): what OpenCV's
    vector loops compute on processors with FMA (``v_fma``, ``v_muladd``)."""
    sig = types.float32(types.float32, types.float32, types.float32)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        f32 = ir.FloatType()
        fn = builder.module.declare_intrinsic("llvm.fma", [f32], ir.FunctionType(f32, [f32] * 3))
        return builder.call(fn, args)

    return sig, codegen


@kernel(nogil=True)
def rgb_to_grey(rgb, out, n):  # type: ignore[no-untyped-def]
    """Grey levels ``0.299 R + 0.587 G + 0.114 B`` of columns ``0 .. n-1`` of an integer
    RGB image, its rows flat (``(H, 3 W)``, ``R G B R G B ...``), into ``out`` ``(H, W)``
    float32, as ``cv2.cvtColor(rgb as float32, COLOR_RGB2GRAY)`` computes them in its
    vector loop (two FMAs in this order); the columns from ``n`` on (the loop's scalar
    tail) are left to OpenCV.  Reads the integers as they are, no float copy of the
    image; the flat rows let the compiler vectorise the three interleaved reads."""
    c0 = np.float32(0.299)
    c1 = np.float32(0.587)
    c2 = np.float32(0.114)
    for y in range(rgb.shape[0]):
        row = rgb[y]
        o = out[y]
        for x in range(n):
            o[x] = fma32(np.float32(row[3 * x + 2]), c2,
                         fma32(np.float32(row[3 * x]), c0, np.float32(row[3 * x + 1]) * c1))


@kernel(nogil=True)
def scaled_grey(img, scale, out):  # type: ignore[no-untyped-def]
    """``out[:] = img.astype(float32) * scale`` for an integer image ``img`` ``(H, W)``
    whose values a float32 holds exactly: one pass, no float copy (float32 ``scale``;
    the same values as the two passes)."""
    for y in range(img.shape[0]):
        row = img[y]
        o = out[y]
        for x in range(img.shape[1]):
            o[x] = np.float32(row[x]) * scale


@kernel(nogil=True)
def pattern_of(u, v, hu, hd):  # type: ignore[no-untyped-def]
    """Pattern type 1..16 of one edge point from its neighbours' offsets ``u`` (above),
    ``v`` (below) and whether it has them
    (:func:`robostereo.matcher.edge_features.pattern_type`)."""
    if hu and hd:
        return 1 + 3 * (u + 1) + (v + 1)
    if hu:
        return 11 + u
    if hd:
        return 14 + v
    return 16


@kernel(nogil=True)
def patterns(u, v, hu, hd):  # type: ignore[no-untyped-def]
    """:func:`pattern_of` of each point of ``(N,)`` arrays; ``(N,)`` int8."""
    out = np.empty(u.shape[0], np.int8)
    for i in range(u.shape[0]):
        out[i] = pattern_of(u[i], v[i], hu[i], hd[i])
    return out


@kernel(nogil=True)
def connect(line, column, sign, n_lines, width):  # type: ignore[no-untyped-def]
    """Connected neighbours above and below of points in any order, through a grid of
    ``(n_lines + 2) x (width + 2)`` indices (:func:`robostereo.matcher.edge_features.connectivity`).

    Returns ``up, down`` (index or -1) and ``up_off, down_off`` (int8 offset -1..1)."""
    n = line.shape[0]
    stride = width + 2
    grid = np.full((n_lines + 2) * stride, -1, dtype=np.int64)
    for i in range(n):
        grid[(line[i] + 1) * stride + column[i] + 1] = i
    up = np.full(n, -1, dtype=np.int64)
    down = np.full(n, -1, dtype=np.int64)
    up_off = np.zeros(n, dtype=np.int8)
    down_off = np.zeros(n, dtype=np.int8)
    for i in range(n):
        base = (line[i] + 1) * stride + column[i] + 1
        for dl in (-1, 1):
            for o in (0, -1, 1):  # straight above (below) first, then -1, then +1
                c = grid[base + dl * stride + o]
                if c >= 0 and sign[c] == sign[i]:
                    if dl < 0:
                        up[i] = c
                        up_off[i] = o
                    else:
                        down[i] = c
                        down_off[i] = o
                    break
    return up, down, up_off, down_off


@kernel(nogil=True)
def _nearest(column, sign, c, sg, j, end):  # type: ignore[no-untyped-def]
    """Among points ``j..end-1`` of one line (columns ascending, the first at column
    ``c - 1`` or beyond) the one of sign ``sg`` at column ``c``, else ``c - 1``, else
    ``c + 1``: its index and offset, or -1 and 0."""
    best = -1
    best_rank = 3
    best_o = 0
    while j < end and column[j] <= c + 1:
        if sign[j] == sg:
            o = column[j] - c
            rank = 0 if o == 0 else (1 if o < 0 else 2)  # 0, then -1, then +1
            if rank < best_rank:
                best, best_rank, best_o = j, rank, o
        j += 1
    return best, best_o


@kernel(nogil=True)
def connect_sorted(line, column, sign, n_lines):  # type: ignore[no-untyped-def]
    """:func:`connect` of points sorted by ``(line, column)`` with no two at one place,
    without the grid: each line is walked beside the lines above and below, a pointer
    into each that only moves forward.  The same result, in memory of order ``N``."""
    n = line.shape[0]
    starts = np.zeros(n_lines + 1, np.int64)  # points of line l: starts[l] .. starts[l + 1]
    for i in range(n):
        starts[line[i] + 1] += 1
    for k in range(n_lines):
        starts[k + 1] += starts[k]
    up = np.full(n, -1, dtype=np.int32)
    down = np.full(n, -1, dtype=np.int32)
    up_off = np.zeros(n, dtype=np.int8)
    down_off = np.zeros(n, dtype=np.int8)
    for k in range(n_lines):
        pu = starts[k - 1] if k > 0 else 0  # the line above: empty for the first line
        eu = starts[k] if k > 0 else 0
        pd = starts[k + 1]  # the line below: empty for the last line
        ed = starts[k + 2] if k + 1 < n_lines else pd
        for i in range(starts[k], starts[k + 1]):
            c = column[i]
            while pu < eu and column[pu] < c - 1:
                pu += 1
            while pd < ed and column[pd] < c - 1:
                pd += 1
            up[i], up_off[i] = _nearest(column, sign, c, sign[i], pu, eu)
            down[i], down_off[i] = _nearest(column, sign, c, sign[i], pd, ed)
    return up, down, up_off, down_off


@kernel(nogil=True)
def _grown(a, size):  # type: ignore[no-untyped-def]
    out = np.empty(size, a.dtype)
    out[:a.shape[0]] = a
    return out


@kernel(nogil=True)
def _abs_g(s, x):  # type: ignore[no-untyped-def]
    """``|g(x)| = |(s[x + 1] - s[x - 1]) / 2|`` of row ``s`` (float32)."""
    return abs((s[x + 1] - s[x - 1]) * np.float32(0.5))


@kernel(nogil=True)
def _row_flags(s, threshold, m, mag, flags):  # type: ignore[no-untyped-def]
    """Mark the peaks of row ``s`` ``(W,)``: ``flags[x]`` 1 where column ``x`` (``m`` to
    ``W - m - 1``) is one, else 0 (other entries untouched).

    Two passes without branches, which the compiler vectorises: ``|g|`` of columns
    ``m - 1 .. W - m`` into ``mag`` (``mag[k]`` is column ``m - 1 + k``), then the
    three tests of each column, one byte each.  A scan that tests the columns one by
    one, branching on each, was about 2x slower: the tests' outcomes are too irregular
    to predict."""
    n = s.shape[0] - 2 * m + 2
    half = np.float32(0.5)
    s0 = s[m - 2:]
    for k in range(n):
        mag[k] = abs((s0[k + 2] - s0[k]) * half)
    f0 = flags[m:]
    for k in range(n - 2):
        c = mag[k + 1]
        f0[k] = np.uint8(c >= threshold) & np.uint8(c > mag[k]) & np.uint8(c >= mag[k + 2])


@kernel(nogil=True)
def _row_scan(flags, i, columns):  # type: ignore[no-untyped-def]
    """Columns of the marked entries of ``flags`` (``(8 K,)`` uint8, 0 or 1) into
    ``columns`` from index ``i``, ascending; the next index.  Without a branch: every
    column is written at ``columns[i]`` and ``i`` moves on by its mark, so ``columns``
    needs one entry of room beyond the marks.  Testing eight marks at a time, then
    each, was 1.5x slower on motorcycle: the tests mispredict."""
    for x in range(flags.shape[0]):
        columns[i] = x
        i += flags[x]
    return i


@kernel(nogil=True)
def gradient_peaks(smoothed, threshold, m):  # type: ignore[no-untyped-def]
    """Peaks of ``|g|``, ``g(x) = (S(x + 1) - S(x - 1)) / 2`` along each row of
    ``smoothed`` (the lines used, ``(L, W)`` float32):
    strictly above the left neighbour, at least the right one and ``threshold``, at
    least ``m >= 2`` pixels inside the borders (float32 arithmetic, as NumPy's on the
    same arrays).  Returns their lines and columns, ``(N,)`` int64 each, sorted.

    Each row is marked (:func:`_row_flags`) and its marks scanned (:func:`_row_scan`);
    the columns go into an int32 buffer that grows (doubles) before a row that might
    not fit, never inside a row.  The gradients at the peaks are not kept:
    :func:`peak_features` computes them again from ``smoothed``, the same float32
    values, so that the buffer is 4 bytes a peak."""
    n_rows, w = smoothed.shape
    cap = max(256, n_rows * w // 16)  # 6% of the pixels: few images grow it
    buf = np.empty(cap, np.int32)
    counts = np.zeros(n_rows, np.int64)
    mag = np.empty(w, np.float32)
    flags = np.zeros((w + 7) // 8 * 8, np.uint8)  # 0 outside columns m .. w - m - 1
    i = 0
    if w - m > m:
        most = (w - 2 * m + 1) // 2 + 1  # peaks of a row: never two side by side
        for r in range(n_rows):
            if cap - i <= most:  # room for a whole row and one (the scan's last write)
                cap = max(2 * cap, i + most + 1)
                buf = _grown(buf, cap)
            i0 = i
            _row_flags(smoothed[r], threshold, m, mag, flags)
            i = _row_scan(flags, i, buf)
            counts[r] = i - i0
    line = np.empty(i, np.int64)
    column = np.empty(i, np.int64)
    k = 0
    for r in range(n_rows):
        for _ in range(counts[r]):
            line[k] = r
            column[k] = buf[k]
            k += 1
    return line, column


@kernel(nogil=True, inline="always")
def _reflect(i, n):  # type: ignore[no-untyped-def]
    """Index ``i`` reflected into ``0..n-1`` (``cv2.BORDER_REFLECT_101``), then clamped."""
    if i < 0:
        i = -i
    if i > n - 1:
        i = 2 * (n - 1) - i
    return min(max(i, 0), n - 1)


@kernel(nogil=True)
def mean5_at(g, rows, cols):  # type: ignore[no-untyped-def]
    """Mean of the 5 x 5 grey levels of ``g`` ``(H, W)`` around each pixel
    ``(rows[i], cols[i])``, the border reflected (``cv2.BORDER_REFLECT_101``), summed in
    float64 row by row; ``(N,)`` float64."""
    h, w = g.shape
    out = np.empty(rows.shape[0], np.float64)
    for i in range(rows.shape[0]):
        acc = 0.0
        r0 = rows[i]
        c0 = cols[i]
        if 2 <= r0 < h - 2 and 2 <= c0 < w - 2:  # inside: no reflection, the same order
            for y in range(r0 - 2, r0 + 3):
                for x in range(c0 - 2, c0 + 3):
                    acc += g[y, x]
            out[i] = acc / 25.0
            continue
        for dy in range(-2, 3):
            y = _reflect(r0 + dy, h)
            for dx in range(-2, 3):
                acc += g[y, _reflect(c0 + dx, w)]
        out[i] = acc / 25.0
    return out


@kernel(nogil=True, inline="always")
def _peak_at(f, x, sg):  # type: ignore[no-untyped-def]
    """Sub-pixel offset (within half a pixel) of the peak of ``sg * g`` at column ``x``
    of row ``f`` (see :func:`fine_offset`), or NaN where ``x`` holds no peak."""
    half = np.float32(0.5)
    g0 = sg * (f[x + 1] - f[x - 1]) * half
    gm = sg * (f[x] - f[x - 2]) * half
    gp = sg * (f[x + 2] - f[x]) * half
    if not (g0 > 0 and g0 > gm and g0 >= gp):
        return np.nan
    den = gm - np.float32(2.0) * g0 + gp
    v = np.float32(0.0)
    if den < 0:
        v = min(max(half * (gm - gp) / den, -half), half)
    return np.float64(v)


@kernel(nogil=True, inline="always")
def fine_offset(f, c, sg):  # type: ignore[no-untyped-def]
    """Sub-pixel position, relative to column ``c``, of the peak of ``sg * g`` along
    row ``f`` (``g(x) = (f(x + 1) - f(x - 1)) / 2``, ``sg`` the edge's contrast sign)
    nearest ``c`` within a pixel: column ``c`` first, then ``c - 1``, then ``c + 1``;
    a peak is positive, strictly above its left neighbour and at least its right one,
    and is placed by the vertex of the parabola through it and its neighbours (within
    half a pixel).  NaN where there is none (or too near the row's ends)."""
    w = f.shape[0]
    for o in (0, -1, 1):  # unrolled: the three columns in this order
        x = c + o
        if x < 2 or x > w - 3:
            continue
        v = _peak_at(f, x, sg)
        if v == v:
            return o + v
    return np.nan


@kernel(nogil=True, inline="always")
def _span_inside(vert, x0, weights, out):  # type: ignore[no-untyped-def]
    """:func:`blurred_span` where its reads ``vert[x0 .. x0 + 6 + 2 R]`` lie inside the
    row: the seven sums built side by side in registers, tap by tap."""
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = np.float32(0.0)
    for t in range(weights.shape[0]):
        wt = weights[t]
        b = x0 + t
        a0 += wt * vert[b]
        a1 += wt * vert[b + 1]
        a2 += wt * vert[b + 2]
        a3 += wt * vert[b + 3]
        a4 += wt * vert[b + 4]
        a5 += wt * vert[b + 5]
        a6 += wt * vert[b + 6]
    out[0] = a0
    out[1] = a1
    out[2] = a2
    out[3] = a3
    out[4] = a4
    out[5] = a5
    out[6] = a6


@kernel(nogil=True, inline="always")
def _reflected_tap_sum(vert, x0, weights):  # type: ignore[no-untyped-def]
    """``0 + w[0] v[x0] + w[1] v[x0 + 1] + ...`` in float32, each read reflected."""
    w = vert.shape[0]
    acc = np.float32(0.0)
    for t in range(weights.shape[0]):
        acc += weights[t] * vert[_reflect(x0 + t, w)]
    return acc


@kernel(nogil=True, inline="always")
def _span_reflected(vert, x0, weights, out):  # type: ignore[no-untyped-def]
    """:func:`blurred_span` near the row's ends: each read reflected into the row."""
    for j in range(out.shape[0]):
        out[j] = _reflected_tap_sum(vert, x0 + j, weights)


@kernel(nogil=True, inline="always")
def blurred_span(vert, c, weights, out):  # type: ignore[no-untyped-def]
    """One row ``vert`` ``(W,)`` of the grey levels already blurred down the columns,
    blurred along the row by ``weights`` ``(2 R + 1,)`` (borders reflected,
    ``cv2.BORDER_REFLECT_101``) at columns ``c - 3 .. c + 3`` into ``out`` ``(7,)``
    float32: what :func:`fine_offset` reads about column ``c``, without blurring the
    whole row.

    Each output is the float32 sum ``0 + w[0] v[0] + w[1] v[1] + ...`` in that order.
    Inside the row the seven sums are built side by side, tap by tap
    (:func:`_span_inside`): seven chains of additions that the processor overlaps,
    where one sum after another waits on each addition; each in the same order, so
    the same values."""
    rad = weights.shape[0] // 2
    x0 = c - 3 - rad
    if x0 >= 0 and x0 + 7 + 2 * rad <= vert.shape[0]:
        _span_inside(vert, x0, weights, out)
    else:
        _span_reflected(vert, x0, weights, out)


@kernel(nogil=True)
def peak_values(line, column, smoothed, subpixel):  # type: ignore[no-untyped-def]
    """Sub-pixel position, sign, magnitude and the smoothed grey levels before and after
    of the peaks ``(line[i], column[i])`` of :func:`gradient_peaks` on ``smoothed``
    (float32 arithmetic where NumPy's on the same arrays is float32)."""
    n = line.shape[0]
    w = smoothed.shape[1]
    x = np.empty(n, np.float64)
    mag = np.empty(n, np.float32)  # float32 values: the arithmetic is float32
    sign = np.empty(n, np.int8)
    before = np.empty(n, np.float32)  # grey levels of the float32 smoothed image
    after = np.empty(n, np.float32)
    half = np.float32(0.5)
    quarter = np.float32(0.25)
    two = np.float32(2.0)
    for i in range(n):
        s = smoothed[line[i]]
        c = column[i]
        mag_before = _abs_g(s, c - 1)  # |g| at the column's left, the column, its right
        mag_peak = _abs_g(s, c)
        mag_after = _abs_g(s, c + 1)
        gradient = (s[c + 1] - s[c - 1]) * half  # g at the column
        # -- sub-pixel position and magnitude: the vertex of the parabola through |g|
        offset = np.float32(0.0)
        if subpixel:
            curvature = mag_before - two * mag_peak + mag_after
            if curvature < 0:
                offset = half * (mag_before - mag_after) / curvature
                offset = min(max(offset, -half), half)
            mag[i] = mag_peak - quarter * (mag_before - mag_after) * offset
        else:
            mag[i] = mag_peak
        x[i] = c + np.float64(offset)
        # -- contrast sign, grey levels before and after
        sign[i] = 1 if gradient > 0 else (-1 if gradient < 0 else 0)
        before[i] = smoothed[line[i], min(max(column[i] - SIDE_OFFSET, 0), w - 1)]
        after[i] = smoothed[line[i], min(max(column[i] + SIDE_OFFSET, 0), w - 1)]
    return x, sign, mag, before, after


@kernel(nogil=True)
def peak_links(line, column, sign, n_lines, grey, row):  # type: ignore[no-untyped-def]
    """Connectivity (:func:`connect_sorted`), pattern type and 5 x 5 mean grey level of
    ``grey`` at pixel ``(row[i], column[i])`` of all the peaks of an image, sorted by
    line and column."""
    up, down, up_off, down_off = connect_sorted(line, column, sign, n_lines)
    pattern = np.empty(line.shape[0], np.int8)
    for i in range(line.shape[0]):
        pattern[i] = pattern_of(up_off[i], down_off[i], up[i] >= 0, down[i] >= 0)
    mean5 = mean5_at(grey, row, column)
    return up, down, up_off, down_off, pattern, mean5


@kernel(nogil=True)
def peak_features(line, column, smoothed, grey, row_offset, row_step, subpixel,
                  n_lines):  # type: ignore[no-untyped-def]
    """Sub-pixel position, magnitude, sign, connectivity, pattern type, mean grey and
    the grey levels before and after of the peaks of :func:`gradient_peaks`
    (:func:`peak_values`, then :func:`peak_links`)."""
    x, sign, mag, before, after = peak_values(line, column, smoothed, subpixel)
    up, down, up_off, down_off, pattern, mean5 = peak_links(
        line, column, sign, n_lines, grey, row_offset + row_step * line)
    return x, sign, mag, up, down, up_off, down_off, pattern, mean5, before, after


@kernel(nogil=True, inline="always")
def _moved(x, c, sg, span, dead_zone):  # type: ignore[no-untyped-def]
    """Position ``x`` of an edge at column ``c`` of sign ``sg`` moved towards the peak
    of :func:`fine_offset` on ``span`` (about ``c``, at index 3) by the part of the move
    beyond ``dead_zone``; ``x`` where there is no such peak."""
    fo = fine_offset(span, 3, sg)
    if fo == fo:
        move = c + fo - x
        if move > dead_zone:
            return x + (move - dead_zone)
        if move < -dead_zone:
            return x + (move + dead_zone)
    return x


#: a point's seven blurred columns (:func:`blurred_span`) cost about what blurring this
#: many columns of a whole row (:func:`blur_row`) does: a row with more points than its
#: width over this is blurred whole (measured on motorcycle, cloth3 and the synthetic
#: 1280 x 960 pair: about 4, 20 and 110 points a row of 626, 741 and 1280 columns)
SPAN_COLUMNS = 48


@kernel(nogil=True)
def blur_row(vert, weights, out):  # type: ignore[no-untyped-def]
    """Row ``vert`` ``(W,)`` blurred along the row by ``weights`` ``(2 R + 1,)`` into
    ``out`` ``(W,)`` float32, borders reflected (``cv2.BORDER_REFLECT_101``): each
    output the float32 sum ``0 + w[0] v[0] + w[1] v[1] + ...`` in that order, the
    values of :func:`blurred_span` at the same columns.  The columns whose taps lie
    inside the row are summed side by side (vectorised; seven taps unrolled), the
    ``R`` at either end one by one."""
    w = vert.shape[0]
    nt = weights.shape[0]
    rad = nt // 2
    n = w - 2 * rad  # columns rad .. w - rad - 1 read inside the row
    if n > 0:
        o = out[rad:]
        if nt == 7:
            w0, w1, w2, w3, w4, w5, w6 = (weights[0], weights[1], weights[2], weights[3],
                                          weights[4], weights[5], weights[6])
            for x in range(n):
                acc = np.float32(0.0) + w0 * vert[x]
                acc += w1 * vert[x + 1]
                acc += w2 * vert[x + 2]
                acc += w3 * vert[x + 3]
                acc += w4 * vert[x + 4]
                acc += w5 * vert[x + 5]
                acc += w6 * vert[x + 6]
                o[x] = acc
        else:
            for x in range(n):
                o[x] = np.float32(0.0)
            for t in range(nt):
                wt = weights[t]
                vt = vert[t:]
                for x in range(n):
                    o[x] += wt * vt[x]
    for x in range(min(rad, w)):
        out[x] = _reflected_tap_sum(vert, x - rad, weights)
    for x in range(max(w - rad, rad), w):
        out[x] = _reflected_tap_sum(vert, x - rad, weights)


@kernel(nogil=True)
def fine_positions(x, row, column, sign, vert, first_row, weights, dead_zone, lo,
                   hi):  # type: ignore[no-untyped-def]
    """Move the sub-pixel positions ``x[lo:hi]`` (in place) towards the peak of the
    gradient on the lightly blurred grey levels, by the part of the move beyond
    ``dead_zone``.  ``vert`` holds image rows ``first_row ..`` already blurred down the
    columns (those of the points' ``row``); ``weights`` blur them along the row,
    ``sign`` is each point's contrast sign.

    The points go a row at a time (a run of equal ``row``; any order is right, rows
    in runs are fast).  A row with more than its width over :data:`SPAN_COLUMNS`
    points is blurred whole (:func:`blur_row`, vectorised) and its points read their
    seven columns from it; the points of a sparser row, and any whose seven columns
    pass the row's ends, blur their own (:func:`blurred_span`).  The same values
    either way."""
    span = np.empty(7, np.float32)
    blurred = np.empty(vert.shape[1], np.float32)
    i = lo
    while i < hi:
        j = _row_end(row, i, hi)
        _place_row(x, column, sign, vert[row[i] - first_row], weights, dead_zone, i, j,
                   blurred, span)
        i = j


@kernel(nogil=True, inline="always")
def _row_end(row, i, hi):  # type: ignore[no-untyped-def]
    """The end of the run of points ``i ..`` on row ``row[i]``: the first ``j <= hi``
    past ``i`` whose row differs."""
    j = i + 1
    while j < hi and row[j] == row[i]:
        j += 1
    return j


@kernel(nogil=True, inline="always")
def _place_row(x, column, sign, line, weights, dead_zone, i, j, blurred,
               span):  # type: ignore[no-untyped-def]
    """:func:`fine_positions` of the points ``i .. j-1`` of one row, ``line`` ``(W,)``
    its grey levels blurred down the columns; ``blurred`` ``(W,)`` and ``span``
    ``(7,)`` float32 scratch."""
    w = line.shape[0]
    one = np.float32(1.0)
    whole = (j - i) * SPAN_COLUMNS >= w
    if whole:
        blur_row(line, weights, blurred)
    for k in range(i, j):
        c = column[k]
        sg = one if sign[k] > 0 else -one
        if whole and 3 <= c and c + 4 <= w:
            x[k] = _moved(x[k], c, sg, blurred[c - 3:c + 4], dead_zone)
        else:
            blurred_span(line, c, weights, span)
            x[k] = _moved(x[k], c, sg, span, dead_zone)


@kernel(nogil=True)
def blur_column(grey, y, weights, n_fused, out):  # type: ignore[no-untyped-def]
    """Row ``y`` of ``cv2.sepFilter2D(grey, -1, [1], weights,
    borderType=BORDER_REFLECT_101)`` (a blur down the columns by the symmetric
    ``weights`` ``(2 R + 1,)``) into ``out`` ``(W,)``, as OpenCV's symmetric column
    filter sums it: ``w[R] v[0]``, then ``+ w[R + k] (v[k] + v[-k])`` for ``k = 1 ..
    R``, rounded once each (an FMA) in its vector loop, columns ``0 .. n_fused - 1``,
    twice in its scalar tail; rows beyond the image reflected."""
    h, w = grey.shape
    rad = weights.shape[0] // 2
    n = min(n_fused, w)
    centre = grey[y]
    k0 = weights[rad]
    zero = np.float32(0.0)
    for x in range(n):
        out[x] = fma32(centre[x], k0, zero)
    for k in range(1, rad + 1):
        a = grey[_reflect(y + k, h)]
        b = grey[_reflect(y - k, h)]
        kk = weights[rad + k]
        for x in range(n):
            out[x] = fma32(a[x] + b[x], kk, out[x])
    for x in range(n, w):
        acc = k0 * centre[x] + zero
        for k in range(1, rad + 1):
            acc = acc + weights[rad + k] * (grey[_reflect(y + k, h), x]
                                            + grey[_reflect(y - k, h), x])
        out[x] = acc


@kernel(nogil=True)
def fine_positions_grey(x, row, column, sign, grey, weights, dead_zone,
                        n_fused):  # type: ignore[no-untyped-def]
    """:func:`fine_positions` of all the points from the grey levels ``grey`` ``(H, W)``
    float32 themselves: each row with points is blurred down the columns as it comes
    (:func:`blur_column`, OpenCV's values where ``n_fused`` is its vector loop's
    columns), in a buffer of one row; no blurred strip is made."""
    span = np.empty(7, np.float32)
    w = grey.shape[1]
    blurred = np.empty(w, np.float32)
    vert = np.empty(w, np.float32)
    n = x.shape[0]
    i = 0
    while i < n:
        j = _row_end(row, i, n)
        blur_column(grey, row[i], weights, n_fused, vert)
        _place_row(x, column, sign, vert, weights, dead_zone, i, j, blurred, span)
        i = j


@kernel(nogil=True)
def edge_points(smoothed, grey, threshold, m, row_offset, row_step, subpixel, n_lines,
                usable, check):  # type: ignore[no-untyped-def]
    """:func:`gradient_peaks`, with ``check`` only those on ``usable`` pixels, then
    :func:`peak_features`, in one call (one release of the interpreter lock for the
    image, not one per step); also the rows."""
    line, column = gradient_peaks(smoothed, threshold, m)
    row = row_offset + row_step * line
    if check:
        keep = np.empty(line.shape[0], np.bool_)
        for i in range(line.shape[0]):
            keep[i] = usable[row[i], column[i]]
        line, column, row = line[keep], column[keep], row[keep]
    x, sign, mag, up, down, up_off, down_off, pattern, mean5, before, after = peak_features(
        line, column, smoothed, grey, row_offset, row_step, subpixel, n_lines)
    return (line, column, row, x, sign, mag, up, down, up_off, down_off, pattern, mean5,
            before, after)


@kernel(nogil=True)
def strip_points(smoothed, threshold, m, first_line, row_offset, row_step, subpixel,
                 usable, check):  # type: ignore[no-untyped-def]
    """:func:`gradient_peaks` and :func:`peak_values` on a strip of an image's lines:
    ``smoothed`` holds lines ``first_line ..``, with ``check`` only the peaks on
    ``usable`` pixels.  Returns their lines, columns and rows (of the whole image,
    int32), then position, sign, magnitude and the grey levels before and after; the
    features that need the lines above and below come from :func:`peak_links` once
    every strip is done."""
    line, column = gradient_peaks(smoothed, threshold, m)
    if check:
        keep = np.empty(line.shape[0], np.bool_)
        for i in range(line.shape[0]):
            keep[i] = usable[row_offset + row_step * (first_line + line[i]), column[i]]
        line, column = line[keep], column[keep]
    x, sign, mag, before, after = peak_values(line, column, smoothed, subpixel)
    line += first_line
    row = row_offset + row_step * line
    return (line.astype(np.int32), column.astype(np.int32), row.astype(np.int32), x, sign,
            mag, before, after)
