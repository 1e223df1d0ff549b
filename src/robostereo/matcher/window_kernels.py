"""Numba kernels of the window matcher: pixel costs [1]_, window sums, paths [2]_, evidence.

The compiled part of :mod:`robostereo.matcher.window_costs` (one pass down the image
that leaves a summary of the window costs per left edge point, :func:`stream_rows`,
from the census and Sobel rows of :mod:`robostereo.matcher.window_pixel_kernels`) and
of :mod:`robostereo.matcher.window_match` (the evidence read from that summary,
:func:`evidence`, and the right edge point next to a disparity,
:func:`right_partners`).  Only numba functions and the
constants they compile in; the checks, bands and threads are in the Python modules
that call them.

References
----------
.. [1] R. Zabih and J. Woodfill, "Non-parametric local transforms for computing
   visual correspondence", ECCV 1994.
.. [2] H. Hirschmüller, "Stereo processing by semiglobal matching and mutual
   information", IEEE TPAMI 30(2), 2008.
"""

from __future__ import annotations

from collections import namedtuple
from typing import NamedTuple

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from robostereo.matcher.jit import kernel
from robostereo.matcher.window_pixel_kernels import pixel_row

__all__ = [
    "HALF_WINDOW",
    "INVALID_SOBEL",
    "OUT_OF_VIEW",
    "PATH_COLUMN_STEP",
    "PATH_LANES",
    "PATH_MAX_DISPARITIES",
    "PATH_NONE",
    "PATH_ROW_STEP",
    "SIDE_COLUMNS",
    "STREAM_COLUMNS",
    "RowPixels",
    "StreamImages",
    "StreamSettings",
    "StreamSummary",
    "evidence",
    "right_partners",
    "stream_rows",
]

#: half size of the aggregation window (9 x 9) and the shift of the side windows
HALF_WINDOW = 4

#: cost value of a disparity whose right pixel lies outside the image
OUT_OF_VIEW = 2**30

#: Sobel value of an invalid pixel (minus in the left view, plus in the right): any
#: pair with one differs by more than any truncation, and a pair of two (16000 + 16000)
#: still fits the int16 the difference is taken in (32000 each wrapped to a cost below
#: zero, so that two masked regions matched each other best)
INVALID_SOBEL = 16000

#: paths run on every fifth row, over every second column (a step of the path is two
#: columns); edge points read the nearest path row (at most two rows away, within the
#: nine rows of their windows)
PATH_ROW_STEP = 5
PATH_COLUMN_STEP = 2

#: paths over at most this many disparities: a wider range is binned (a path
#: disparity stands for 2, 3, ... whole ones, its cost their least), so their cost stops
#: growing with the range; the developer scenes (up to 97) are not binned
PATH_MAX_DISPARITIES = 128

#: a path row holds its disparities (bins) in whole blocks of this many uint16 lanes (an
#: AVX2 register), so that a path step runs in vector registers without a scalar tail
PATH_LANES = 16

#: the path cost of a lane past the last disparity, and of a row end's missing neighbour
PATH_NONE = 65535

#: the last columns of :data:`STREAM_COLUMNS`: what each placement saw on its own, only
#: with ``StreamSettings.sides`` (without it the summary array stops before them)
SIDE_COLUMNS: tuple[str, ...] = (
    "placement", "second_placement", "best_left", "cost_left", "best_right", "cost_right",
    "second_best", "right_best_placement",
)

#: the columns of :func:`stream_rows`' summary of an edge point, in order: the fields of
#: :class:`~robostereo.matcher.window_costs.WindowCosts` (its docstring says what each
#: holds): with the five windows, with the three along the row, the disparities in view,
#: the left-right check, the paths, and what each placement saw on its own (only with
#: ``StreamSettings.sides``, :data:`SIDE_COLUMNS`; :func:`_sides`).  Those last eight, per edge
#: point, from the per-disparity costs of the five placements at it and at the right
#: pixel's partners (the pass over all disparities; a sparse pass over a few candidate
#: disparities reads them among those):
#:
#: * ``placement``: the window that gives ``cost`` at ``best``, the first of equals in
#:   the order 0 centred, 1 half a window left, 2 right, 3 up, 4 down (-1: no ``best``);
#: * ``second_placement``: that window's own least cost over the disparities in view
#:   more than one from ``best`` (``OUT_OF_VIEW``: none);
#: * ``best_left``, ``cost_left``: the left-shifted window's own best disparity over
#:   those in view (the first of equals; -1: none) and its cost there;
#:   ``best_right``, ``cost_right`` the right-shifted one's;
#: * ``second_best``: the disparity of ``second`` (the first of equals; -1: none);
#: * ``right_best_placement``: the left-right check with the winning window alone: the
#:   best disparity of the right pixel ``x - d_min - best`` against every left pixel,
#:   both windows placed as the winner (-1: none).
STREAM_COLUMNS: tuple[str, ...] = (
    "best", "cost", "second", "before", "after",
    "best_row", "cost_row", "second_row",
    "in_view",
    "right_best",
    "best_path", "cost_path", "second_path", "before_path", "after_path",
    *SIDE_COLUMNS,
)
#: the summary as named columns, for the kernels that read it (:func:`evidence`): all
#: but :data:`SIDE_COLUMNS`, which the matcher does not read
StreamSummary = namedtuple("StreamSummary", STREAM_COLUMNS[:-len(SIDE_COLUMNS)])
_BEST = STREAM_COLUMNS.index("best")
_COST = STREAM_COLUMNS.index("cost")
_SECOND = STREAM_COLUMNS.index("second")
_BEFORE = STREAM_COLUMNS.index("before")
_AFTER = STREAM_COLUMNS.index("after")
_BEST_ROW = STREAM_COLUMNS.index("best_row")
_COST_ROW = STREAM_COLUMNS.index("cost_row")
_SECOND_ROW = STREAM_COLUMNS.index("second_row")
_IN_VIEW = STREAM_COLUMNS.index("in_view")
_RIGHT_BEST = STREAM_COLUMNS.index("right_best")
_BEST_PATH = STREAM_COLUMNS.index("best_path")
_COST_PATH = STREAM_COLUMNS.index("cost_path")
_SECOND_PATH = STREAM_COLUMNS.index("second_path")
_BEFORE_PATH = STREAM_COLUMNS.index("before_path")
_AFTER_PATH = STREAM_COLUMNS.index("after_path")
_PLACEMENT = STREAM_COLUMNS.index("placement")
_SECOND_PLACEMENT = STREAM_COLUMNS.index("second_placement")
_BEST_LEFT = STREAM_COLUMNS.index("best_left")
_COST_LEFT = STREAM_COLUMNS.index("cost_left")
_BEST_RIGHT = STREAM_COLUMNS.index("best_right")
_COST_RIGHT = STREAM_COLUMNS.index("cost_right")
_SECOND_BEST = STREAM_COLUMNS.index("second_best")
_RIGHT_BEST_PLACEMENT = STREAM_COLUMNS.index("right_best_placement")


class StreamImages(NamedTuple):
    """The pair that :func:`stream_rows` reads."""

    grey_left: np.ndarray  # (H, W) float32
    grey_right: np.ndarray  # (H, W) float32
    valid_left: np.ndarray  # (H, W) bool, or (1, 1) when not checked
    valid_right: np.ndarray  # (H, W) bool, or (1, 1)
    check_left: bool  # pixels outside valid_left cost nearly the most
    check_right: bool


class StreamSettings(NamedTuple):
    """What :func:`stream_rows` computes: disparities, pixel costs, windows, paths."""

    d_min: int  # disparity k stands for d_min + k
    n_disparities: int
    truncation: np.int16  # largest gradient difference of a pixel pair
    pixel_cost_max: np.int16  # cost of a pair that leaves the image: 34 + truncation
    ring_type: type  # the pixel costs' ring: np.uint8 where they fit a byte, else np.int16
    half_window: int
    vertical: bool  # windows half a window up and down too
    p1: int  # path penalties per window (sum of its pixels); p1 < 0: no paths
    p2: int
    path_row_step: int  # paths on every path_row_step-th row
    sides: bool = False  # also what each placement saw on its own (STREAM_COLUMNS)


class RowPixels(NamedTuple):
    """Census and Sobel of the row being added, and the buffers that make them (W,)."""

    census_left: np.ndarray  # (W,) uint64
    census_right: np.ndarray
    sobel_left: np.ndarray  # (W,) int16
    sobel_right: np.ndarray
    hamming: np.ndarray  # (W,) int16, Hamming distances of a row
    padded_rows: np.ndarray  # (5, W + 6) float32, grey rows padded for the census
    loaded_row: np.ndarray  # (1,) int64, the row in the buffers (-1: none)


@intrinsic
def _popcount(typingctx, x):  # type: ignore[no-untyped-def]
    sig = types.uint64(types.uint64)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        fn = builder.module.declare_intrinsic("llvm.ctpop", [ir.IntType(64)])
        return builder.call(fn, args)

    return sig, codegen


@kernel(fastmath=True, nogil=True, inline="always")
def _pixel_update(column_sums, ring_row, census_left, census_right, sobel_left, sobel_right,
                  truncation, hamming):  # type: ignore[no-untyped-def]
    """Replace one ring row of pixel costs and update the column sums, for 1-D rows:
    ``p[x] = H(census_left[x], census_right[x]) + min(|sobel_left[x] - sobel_right[x]|,
    truncation)``.  The Hamming distances go through ``hamming`` so that the rest runs
    in 16-bit vector lanes.  ``ring_row`` is uint8 where every pixel cost fits a byte,
    int16 otherwise (``StreamSettings.ring_type``)."""
    n = column_sums.shape[0]
    for x in range(n):
        hamming[x] = np.int16(_popcount(census_left[x] ^ census_right[x]))
    for x in range(n):
        a = np.int16(sobel_left[x])
        b = np.int16(sobel_right[x])
        gradient = np.int16(max(a, b) - min(a, b))
        pixel = np.int16(hamming[x] + np.int16(min(gradient, truncation)))
        column_sums[x] = np.int16(column_sums[x] + np.int16(pixel - ring_row[x]))
        ring_row[x] = pixel


@kernel(fastmath=True, nogil=True, inline="always")
def _constant_update(column_sums, ring_row, value):  # type: ignore[no-untyped-def]
    for x in range(column_sums.shape[0]):
        column_sums[x] += value - ring_row[x]
        ring_row[x] = value


@kernel(fastmath=True, nogil=True, inline="always")
def _row_update(pixels, settings, margin, column_sums, ring_slot,
                fill):  # type: ignore[no-untyped-def]
    """Pixel costs of one row for every disparity into a ring slot, with the column
    sums: ``[k, x + margin]`` pairs left pixel ``x`` with right pixel ``x - d_min - k``;
    pairs that leave the image cost ``settings.pixel_cost_max``, written while the ring
    is first filled (``fill``) only: they stay the same down the image.  ``pixels``
    (:class:`RowPixels`) holds the row's census and Sobel values."""
    census_left, census_right = pixels.census_left, pixels.census_right
    sobel_left, sobel_right = pixels.sobel_left, pixels.sobel_right
    pixel_cost_max = settings.pixel_cost_max
    m = margin
    w = census_left.shape[0]
    for k in range(settings.n_disparities):
        d = settings.d_min + k
        x0 = min(max(d, 0), w)  # left pixels x0 .. x1 - 1 have a right pixel x - d
        x1 = max(min(w + d, w), x0)
        sums = column_sums[k]
        ring_row = ring_slot[k]
        if fill:
            _constant_update(sums[m:m + x0], ring_row[m:m + x0], pixel_cost_max)
            _constant_update(sums[m + x1:m + w], ring_row[m + x1:m + w], pixel_cost_max)
        if x1 > x0:
            _pixel_update(sums[m + x0:m + x1], ring_row[m + x0:m + x1], census_left[x0:x1],
                          census_right[x0 - d:x1 - d], sobel_left[x0:x1],
                          sobel_right[x0 - d:x1 - d], settings.truncation, pixels.hamming)


@kernel(fastmath=True, nogil=True, inline="always")
def _box(col, out, pair_sums, quad_sums):  # type: ignore[no-untyped-def]
    """``out[x] = col[x - 4] + ... + col[x + 4]`` (nine columns) by pair sums."""
    n = col.shape[0]
    for x in range(n - 1):
        pair_sums[x] = col[x] + col[x + 1]
    for x in range(n - 3):
        quad_sums[x] = pair_sums[x] + pair_sums[x + 2]
    for x in range(n - 7):
        pair_sums[x] = quad_sums[x] + quad_sums[x + 4]  # eight columns
    for x in range(n - 8):
        out[x + 4] = pair_sums[x] + col[x + 8]


@kernel(fastmath=True, nogil=True)
def _least(boxes_up, boxes_mid, boxes_down, k, x, hw, vertical):  # type: ignore[no-untyped-def]
    """Least window sum at column ``x``, disparity ``k``: centred and half a window left
    and right on the row's box sums ``boxes_mid`` (returned second), and with
    ``vertical`` also centred on the rows half a window above (``boxes_up``) and below
    (``boxes_down``)."""
    row = np.int32(min(boxes_mid[k, x - hw], min(boxes_mid[k, x], boxes_mid[k, x + hw])))
    if vertical:
        return min(row, np.int32(min(boxes_up[k, x], boxes_down[k, x]))), row
    return row, row


@kernel(fastmath=True, nogil=True)
def _sides(boxes_up, boxes_mid, boxes_down, cost_all, best, best_cost, second, column,
           d_min, hw, margin, vertical, o):  # type: ignore[no-untyped-def]
    """What each placement saw on its own at one edge point, into its summary row ``o``
    (the last eight :data:`STREAM_COLUMNS`, defined there).  ``cost_all`` (nd,) holds
    the least of the five windows per disparity (``OUT_OF_VIEW`` out of view), ``best``,
    ``best_cost`` and ``second`` its best disparity, cost and second cost, ``column``
    the edge pixel's (unpadded); the box sums are padded by ``margin`` columns."""
    big = np.int32(OUT_OF_VIEW)
    nd = cost_all.shape[0]
    w = boxes_mid.shape[1] - 2 * margin
    pc = column + margin
    # -- each side window's own best over the disparities in view, and the disparity of
    #    the second cost
    best_left, cost_left, best_right, cost_right, second_best = -1, big, -1, big, -1
    for k in range(nd):
        if cost_all[k] >= big:
            continue
        v_left = np.int32(boxes_mid[k, pc - hw])
        v_right = np.int32(boxes_mid[k, pc + hw])
        if v_left < cost_left:
            cost_left, best_left = v_left, k
        if v_right < cost_right:
            cost_right, best_right = v_right, k
        if second_best < 0 and abs(k - best) > 1 and cost_all[k] == second:
            second_best = k
    o[_BEST_LEFT], o[_COST_LEFT] = best_left, cost_left
    o[_BEST_RIGHT], o[_COST_RIGHT] = best_right, cost_right
    o[_SECOND_BEST] = second_best
    o[_PLACEMENT], o[_SECOND_PLACEMENT], o[_RIGHT_BEST_PLACEMENT] = -1, big, -1
    if best < 0:
        return
    # -- the window that gives the best cost (the first of equals) and its own second
    if boxes_mid[best, pc] == best_cost:
        placement, boxes, shift = 0, boxes_mid, 0
    elif boxes_mid[best, pc - hw] == best_cost:
        placement, boxes, shift = 1, boxes_mid, -hw
    elif boxes_mid[best, pc + hw] == best_cost:
        placement, boxes, shift = 2, boxes_mid, hw
    elif vertical and boxes_up[best, pc] == best_cost:
        placement, boxes, shift = 3, boxes_up, 0
    else:
        placement, boxes, shift = 4, boxes_down, 0
    own_second = big
    for k in range(nd):
        if abs(k - best) > 1 and cost_all[k] < big:
            own_second = min(own_second, np.int32(boxes[k, pc + shift]))
    # -- the left-right check with that window alone: the right pixel against every left
    #    pixel, both windows placed as the winner
    x_right = column - d_min - best
    right_best, right_cost = -1, big
    for k in range(nd):
        x_left = x_right + d_min + k
        if 0 <= x_left < w:
            v = np.int32(boxes[k, x_left + margin + shift])
            if v < right_cost:
                right_cost, right_best = v, k
    o[_PLACEMENT], o[_SECOND_PLACEMENT], o[_RIGHT_BEST_PLACEMENT] = (placement, own_second,
                                                                     right_best)


@intrinsic
def _path_block(typingctx, cost, cost_at, prev, prev_at, cur, least, p1, q,
                n_in):  # type: ignore[no-untyped-def]
    """One block of :data:`PATH_LANES` lanes of a path step (:func:`_path_step`) in
    vector registers: ``cur[prev_at + i]`` for ``i < n_in`` from ``cost[cost_at + i]``
    and ``prev[prev_at - 1 + i .. prev_at + 1 + i]``, :data:`PATH_NONE` for the lanes
    ``n_in <= i < PATH_LANES`` (past the last disparity).

    The neighbours come from the blocks before and after, loaded whole and shifted by
    one lane in registers: a load that overlaps two earlier stores (``prev[k - 1]`` as
    its own vector) cannot take their data from the store buffer, and every step of a
    path waits for the one before, so those loads made a step several times slower."""
    sig = types.void(cost, types.intp, prev, types.intp, cur, types.uint16, types.uint16,
                     types.uint16, types.uint16)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        cost_a, cost_at, prev_a, prev_at, cur_a, least, p1, q, n_in = args
        lanes = ir.VectorType(ir.IntType(16), PATH_LANES)
        index = ir.VectorType(ir.IntType(32), PATH_LANES)

        def block(i, array, at):  # the lanes at ``at`` of argument i's data
            data = context.make_array(signature.args[i])(context, builder, array).data
            return builder.bitcast(builder.gep(data, [at]), lanes.as_pointer())

        def splat(value):
            out = ir.Constant(lanes, ir.Undefined)
            for j in range(PATH_LANES):
                out = builder.insert_element(out, value, ir.Constant(ir.IntType(32), j))
            return out

        def least_of(a, b):
            return builder.select(builder.icmp_unsigned("<", a, b), a, b)

        step = ir.Constant(prev_at.type, PATH_LANES)
        before = builder.load(block(2, prev_a, builder.sub(prev_at, step)), align=2)
        mid = builder.load(block(2, prev_a, prev_at), align=2)
        after = builder.load(block(2, prev_a, builder.add(prev_at, step)), align=2)
        left = builder.shuffle_vector(  # prev[k - 1]
            before, mid, ir.Constant(index, [PATH_LANES - 1 + j for j in range(PATH_LANES)]))
        right = builder.shuffle_vector(  # prev[k + 1]
            mid, after, ir.Constant(index, [1 + j for j in range(PATH_LANES)]))
        low = splat(least)
        near = builder.sub(least_of(left, right), low)
        near = builder.add(least_of(near, splat(q)), splat(p1))
        value = builder.add(builder.load(block(0, cost_a, cost_at), align=2),
                            least_of(builder.sub(mid, low), near))
        held = builder.icmp_unsigned(
            "<", ir.Constant(lanes, list(range(PATH_LANES))), splat(n_in))
        value = builder.select(held, value, splat(ir.Constant(ir.IntType(16), PATH_NONE)))
        builder.store(value, block(4, cur_a, prev_at), align=2)
        return context.get_dummy_value()

    return sig, codegen


@kernel(fastmath=True, nogil=True, inline="always")
def _path_step(costs, x_cost, paths, x_prev, x_cur, nd, p1,
               q):  # type: ignore[no-untyped-def]
    """One step of a scanline path (semi-global matching, [2]_ eq. 13):
    ``cur[k] = cost[k] + min(prev[k], prev[k -/+ 1] + p1, min(prev) + p2) - min(prev)``,
    as ``cost[k] + min(prev[k] - least, min(prev[k -/+ 1] - least, q) + p1)`` with
    ``least = min(prev)`` and ``q = p2 - p1``: every term stays within 0 ..
    ``max(cost) + p2``, so the whole numbers run in uint16 vector lanes (see
    :func:`_scanline`).

    ``cost`` is row ``x_cost`` of ``costs`` (C, n), ``prev`` and ``cur`` the distinct
    rows ``x_prev`` and ``x_cur`` of ``paths`` (C, n + 2 PATH_LANES), all uint16:
    disparity ``k < nd`` is ``cost[k]`` and ``prev[PATH_LANES + k]``; ``n`` is
    ``nd`` rounded up to a multiple of :data:`PATH_LANES`.  The lanes before and after
    the disparities hold :data:`PATH_NONE`, and the step keeps them there, so that every
    lane runs the same arithmetic without a branch: a neighbour of ``PATH_NONE`` is
    never the nearer one, nor is it below the least.  The sums wrap in uint16 as they
    always did (only window sums below zero can make them)."""
    n = costs.shape[1]
    prev = paths[x_prev]
    least = prev[PATH_LANES]
    for k in range(n):
        least = min(least, prev[PATH_LANES + k])
    cost, cur = costs[x_cost], paths[x_cur]
    for k in range(0, n, PATH_LANES):
        _path_block(cost, k, prev, PATH_LANES + k, cur, least, p1, q,
                    np.uint16(min(nd - k, PATH_LANES)))


@kernel(fastmath=True, nogil=True)
def _scanline(boxes, margin, width, bin_size, p1, p2, costs, from_left,
              from_right):  # type: ignore[no-untyped-def]
    """Window costs of one row aggregated along it, both ways (two paths of
    semi-global matching): ``L_left`` into ``from_left`` and ``L_right`` into
    ``from_right``, on every :data:`PATH_COLUMN_STEP`-th column.  The two paths are
    stepped in one loop (independent chains), in uint16: a path cost is at most the
    largest window sum (int16) plus ``p2`` (``0 <= p1 <= p2 <= 32768``), below 65536.
    With ``bin_size > 1`` a path disparity is a bin of ``bin_size`` whole ones, its cost
    the least of theirs (wide ranges).

    ``costs`` (C, n) uint16 receives the row's costs, ``from_left`` and ``from_right``
    (C, n + 2 PATH_LANES) uint16 the paths, disparity (bin) ``k`` at
    ``[x, PATH_LANES + k]``, for ``C`` at least the columns of the paths and ``n`` the
    disparities (bins) rounded up to :data:`PATH_LANES`; the caller fills all three
    with :data:`PATH_NONE` once (see :func:`_path_step`), and this leaves every lane
    that holds no disparity as it is.
    """
    nd_fine = boxes.shape[0]
    nd = (nd_fine + bin_size - 1) // bin_size
    n_columns = (width + PATH_COLUMN_STEP - 1) // PATH_COLUMN_STEP
    q = np.uint16(p2 - p1)
    p1 = np.uint16(p1)
    # the row's window sums on every PATH_COLUMN_STEP-th column, disparity fastest
    if bin_size == 1:  # a column at a time: the writes run on, the reads stay in cache
        for x in range(n_columns):
            for k in range(nd_fine):
                costs[x, k] = np.uint16(boxes[k, margin + PATH_COLUMN_STEP * x])
    else:
        for x in range(n_columns):
            for j in range(nd):
                costs[x, j] = np.uint16(PATH_NONE)
        for k in range(nd_fine):
            src = boxes[k]
            j = k // bin_size
            for x in range(n_columns):
                costs[x, j] = min(costs[x, j], np.uint16(src[margin + PATH_COLUMN_STEP * x]))
    # the paths start at the row's two ends with the costs there, then step a column at
    # a time, each into its own row of from_left, from_right
    last = n_columns - 1
    for k in range(nd):
        from_left[0, PATH_LANES + k] = costs[0, k]
        from_right[last, PATH_LANES + k] = costs[last, k]
    for x in range(1, n_columns):
        _path_step(costs, x, from_left, x - 1, x, nd, p1, q)
        _path_step(costs, last - x, from_right, last - x + 1, last - x, nd, p1, q)


@kernel(nogil=True)
def _load_row(images, y, pixels):  # type: ignore[no-untyped-def]
    """Census and Sobel rows ``y`` of both images (:class:`StreamImages`) into
    ``pixels`` (:class:`RowPixels`), once per row."""
    if pixels.loaded_row[0] != y:
        pixel_row(images.grey_left, y, images.valid_left, images.check_left,
                   np.uint64(0xAAAAAAAAAAAAAAAA), np.int16(-INVALID_SOBEL), pixels.census_left,
                   pixels.sobel_left, pixels.padded_rows)
        pixel_row(images.grey_right, y, images.valid_right, images.check_right,
                   np.uint64(0x5555555555555555), np.int16(INVALID_SOBEL), pixels.census_right,
                   pixels.sobel_right, pixels.padded_rows)
        pixels.loaded_row[0] = y


@kernel(fastmath=True, nogil=True)
def stream_rows(images, settings, row_start, columns, y_first, y_last,
                out):  # type: ignore[no-untyped-def]
    """One pass down rows ``y_first .. y_last - 1`` of a pair; ``out[i]`` receives the
    summary of each left edge point ``i`` on them.

    Parameters
    ----------
    images : StreamImages
        The grey images and their valid pixels.
    settings : StreamSettings
        Disparities, cost truncation, windows and paths.
    row_start : ndarray of int64, shape (H + 1,)
        The edge points of row ``y`` are ``row_start[y] .. row_start[y + 1] - 1``.
    columns : ndarray of int64, shape (N,)
        Their columns.
    y_first, y_last : int
        The band of rows whose edge points this pass summarises.
    out : ndarray of int32, shape (N, len(STREAM_COLUMNS))
        The summary, columns named by :data:`STREAM_COLUMNS` (the fields of
        :class:`~robostereo.matcher.window_costs.WindowCosts`); rows of edge points
        outside the band are left alone.  Without ``settings.sides`` it may stop before
        :data:`SIDE_COLUMNS`, which are then not written.

    Notes
    -----
    Census and Sobel rows are made as the pass needs them; pixel costs are kept for
    the last ``2 * half_window + 1`` rows only (a ring, in bytes where they fit:
    ``settings.ring_type``), with their running column sums, and window sums for as
    many rows.  A row that no edge point's window reads
    (no edge point within ``half_window`` rows of it, ``2 * half_window`` with the
    windows above and below) is not made at all: the pass costs nothing over rows
    without edge points.
    """
    grey_left = images.grey_left
    d_min = settings.d_min
    nd = settings.n_disparities
    pixel_cost_max = settings.pixel_cost_max
    hw = settings.half_window
    vertical = settings.vertical
    p1 = settings.p1
    p2 = settings.p2
    path_step = settings.path_row_step
    h, w = grey_left.shape
    n_ring = 2 * hw + 1
    m = 2 * hw  # margin of the padded rows: a side window reaches 2 hw columns out
    padded_width = w + 2 * m
    big = np.int32(OUT_OF_VIEW)
    ring_base = 4 * n_ring  # keeps ring indices of negative rows positive

    # -- buffers: the ring of pixel costs and window sums, the row's census and Sobel
    # pixel costs of the last n_ring rows, in uint8 where they fit (settings.ring_type)
    ring = np.zeros((n_ring, nd, padded_width), settings.ring_type)
    column_sums = np.zeros((nd, padded_width), np.int16)   # their column sums
    boxes = np.zeros((n_ring, nd, padded_width), np.int16)  # window sums, last n_ring rows
    pair_sums = np.zeros(padded_width, np.int16)
    quad_sums = np.zeros(padded_width, np.int16)
    cost_all = np.empty(nd, np.int32)  # per disparity: least of the five windows
    cost_along = np.empty(nd, np.int32)  # least of the three along the row
    pixels = RowPixels(
        np.empty(w, np.uint64), np.empty(w, np.uint64),  # census of the row being added
        np.empty(w, np.int16), np.empty(w, np.int16),  # Sobel of it
        np.empty(w, np.int16),  # Hamming distances of a row
        np.empty((5, w + 6), np.float32),  # padded grey rows for the census
        np.full(1, -1, np.int64),
    )
    paths = p1 >= 0  # aggregate along the rows too (p1 < 0: not)
    path_width = (w + PATH_COLUMN_STEP - 1) // PATH_COLUMN_STEP if paths else 1  # columns
    bin_size = max(1, (nd + PATH_MAX_DISPARITIES - 1) // PATH_MAX_DISPARITIES)
    n_bins = (nd + bin_size - 1) // bin_size
    path_lanes = (n_bins + PATH_LANES - 1) // PATH_LANES * PATH_LANES
    path_costs = np.full((path_width, path_lanes), PATH_NONE, np.uint16)
    # bin j at PATH_LANES + j, a block of PATH_NONE on either side (_path_step)
    from_left = np.full((path_width, path_lanes + 2 * PATH_LANES), PATH_NONE, np.uint16)
    from_right = np.full((path_width, path_lanes + 2 * PATH_LANES), PATH_NONE, np.uint16)
    path_sum = np.empty(n_bins, np.int32)
    path_row = -1  # the row whose paths are in from_left, from_right
    column_sums[:, :m] = n_ring * pixel_cost_max
    column_sums[:, w + m:] = n_ring * pixel_cost_max

    def edges_in(y0, y1):  # type: ignore[no-untyped-def]
        return row_start[min(max(y1, 0), h)] > row_start[min(max(y0, 0), h)]

    lag = hw if vertical else 0  # rows of box sums needed below the output row
    first_box_row = y_first - lag

    # -- column sums of the window centred on the first row: rows j0 - hw .. j0 + hw,
    #    clamped to the image
    for r in range(first_box_row - hw, first_box_row + hw + 1):
        source_row = min(max(r, 0), h - 1)
        _load_row(images, source_row, pixels)
        _row_update(pixels, settings, m, column_sums, ring[(r + ring_base) % n_ring], True)

    for box_row in range(first_box_row, y_last + lag):
        # -- pixel costs of the new row into the ring, column sums updated: only where
        #    a window of an edge point will read them.  A row no window reads is left
        #    out, its ring slot and the column sums as they were (the sums stay the sums
        #    of the ring), so the pass costs nothing over rows without edge points: a
        #    window sum that is read covers rows that were all made
        r = box_row + hw  # the new pixel row; its ring slot holds row box_row - hw - 1
        if box_row > first_box_row and edges_in(r - hw - lag, r + hw + lag + 1):
            _load_row(images, min(max(r, 0), h - 1), pixels)
            _row_update(pixels, settings, m, column_sums, ring[(r + ring_base) % n_ring],
                        False)

        # -- window sums of nine columns of box_row, every disparity
        boxes_new = boxes[(box_row + ring_base) % n_ring]
        if edges_in(box_row - lag, box_row + lag + 1):
            for k in range(nd):
                _box(column_sums[k], boxes_new[k], pair_sums, quad_sums)
        y = box_row - lag  # the row whose windows are all complete
        if y < y_first or row_start[y + 1] == row_start[y]:
            continue
        boxes_up = boxes[(y - hw + ring_base) % n_ring]
        boxes_mid = boxes[(y + ring_base) % n_ring]
        boxes_down = boxes[(y + hw + ring_base) % n_ring]

        # -- the paths along the row: on every path_step-th row; a row's edge points
        #    read those of the nearest such row (their windows share all but a few
        #    rows).  The choice depends on y alone, so bands (threads) do not change
        #    the result
        if paths:
            y_path = y
            if vertical:
                y_path = min((y + path_step // 2) // path_step * path_step, h - 1)
            if y_path != path_row:
                _scanline(boxes[(y_path + ring_base) % n_ring], m, w, bin_size,
                          p1, p2, path_costs, from_left, from_right)
                path_row = y_path

        for i in range(row_start[y], row_start[y + 1]):
            column = columns[i]
            padded_column = column + m
            # -- every disparity: the least of the five windows and of the three along
            #    the row, their best disparities and the disparities in view
            best = -1
            best_cost = big
            best_row = -1
            best_row_cost = big
            n_in_view = 0
            for k in range(nd):
                x_right = column - d_min - k
                if x_right < 0 or x_right >= w:
                    cost_all[k] = big
                    cost_along[k] = big
                    continue
                n_in_view += 1
                v_all, v_along = _least(boxes_up, boxes_mid, boxes_down, k, padded_column,
                                        hw, vertical)
                cost_all[k] = v_all
                cost_along[k] = v_along
                if v_all < best_cost:
                    best_cost = v_all
                    best = k
                if v_along < best_row_cost:
                    best_row_cost = v_along
                    best_row = k
            # -- the second best: the least more than one disparity from the best
            second = big
            second_row = big
            for k in range(nd):
                if abs(k - best) > 1 and cost_all[k] < second:
                    second = cost_all[k]
                if abs(k - best_row) > 1 and cost_along[k] < second_row:
                    second_row = cost_along[k]
            o = out[i]
            o[_BEST] = best
            o[_COST] = best_cost
            o[_SECOND] = second
            o[_BEFORE] = cost_all[best - 1] if best > 0 else big
            o[_AFTER] = cost_all[best + 1] if 0 <= best < nd - 1 else big
            o[_BEST_ROW] = best_row
            o[_COST_ROW] = best_row_cost
            o[_SECOND_ROW] = second_row
            o[_IN_VIEW] = n_in_view
            o[_RIGHT_BEST] = -1
            if settings.sides:
                _sides(boxes_up, boxes_mid, boxes_down, cost_all, best, best_cost, second,
                       column, d_min, hw, m, vertical, o)
            if best < 0:
                continue
            # -- left-right check: the right pixel of the best disparity against every
            #    left pixel
            x_right = column - d_min - best
            right_best = -1
            right_cost = big
            for k in range(nd):
                x_left = x_right + d_min + k
                if x_left < 0 or x_left >= w:
                    continue
                v, _ = _least(boxes_up, boxes_mid, boxes_down, k, x_left + m, hw, vertical)
                if v < right_cost:
                    right_cost = v
                    right_best = k
            o[_RIGHT_BEST] = right_best
            if paths:
                # -- the aggregated costs: the best bin, its cost, the best more than
                #    one bin off
                path_column = column // PATH_COLUMN_STEP
                for j in range(n_bins):
                    path_sum[j] = (np.int32(from_left[path_column, PATH_LANES + j])
                                   + np.int32(from_right[path_column, PATH_LANES + j]))
                # a bin is in view where one of its disparities is: k in k_lo .. k_hi
                k_lo = max(column - d_min - w + 1, 0)
                k_hi = min(column - d_min, nd - 1)
                best_bin = -1
                best_bin_cost = big
                for j in range(n_bins):
                    if (j * bin_size <= k_hi and (j + 1) * bin_size - 1 >= k_lo
                            and path_sum[j] < best_bin_cost):
                        best_bin_cost = path_sum[j]
                        best_bin = j
                second_bin_cost = big
                for j in range(n_bins):
                    if (j * bin_size <= k_hi and (j + 1) * bin_size - 1 >= k_lo
                            and abs(j - best_bin) > 1 and path_sum[j] < second_bin_cost):
                        second_bin_cost = path_sum[j]
                o[_COST_PATH] = best_bin_cost
                o[_SECOND_PATH] = second_bin_cost
                if bin_size == 1 or best_bin < 0:
                    o[_BEST_PATH] = best_bin
                    o[_BEFORE_PATH] = path_sum[best_bin - 1] if best_bin > 0 else big
                    o[_AFTER_PATH] = (path_sum[best_bin + 1] if 0 <= best_bin < n_bins - 1
                                      else big)
                else:  # the bin's best whole disparity by the windows, their parabola
                    best_in_bin = -1
                    bin_cost = big
                    for k in range(best_bin * bin_size, min(nd, (best_bin + 1) * bin_size)):
                        if cost_all[k] < bin_cost:
                            bin_cost = cost_all[k]
                            best_in_bin = k
                    o[_BEST_PATH] = best_in_bin
                    o[_BEFORE_PATH] = cost_all[best_in_bin - 1] if best_in_bin > 0 else big
                    o[_AFTER_PATH] = (cost_all[best_in_bin + 1] if 0 <= best_in_bin < nd - 1
                                      else big)


@kernel(nogil=True, inline="always")
def _nearest_on_line(x, sign, first, end, right_x, right_sign):  # type: ignore[no-untyped-def]
    """The right edge point of contrast sign ``sign`` among ``first .. end - 1`` (one
    line, sorted by x) nearest to ``x`` of the two around it, and its distance
    (``-1, inf``: none)."""
    nearest = -1
    distance = np.inf
    at, top = first, end  # the first point at x or beyond (np.searchsorted, side left),
    while at < top:       # searched here: numba's np.searchsorted made an array a call
        mid = (at + top) >> 1
        if right_x[mid] < x:
            at = mid + 1
        else:
            top = mid
    for j in (at - 1, at):  # the two right points around x on the line
        if first <= j < end and right_sign[j] == sign:
            dd = abs(right_x[j] - x)
            if dd < distance:
                distance = dd
                nearest = j
    return nearest, distance


@kernel(nogil=True)
def right_partners(x_left, left_line, left_sign, d_par, seen, lo, hi, line_start, right_x,
                   right_sign, disparity, right_edge, partner, features,
                   column):  # type: ignore[no-untyped-def]
    """The right edge point each left edge point's disparity lands on, and the
    sub-pixel disparity from it, for ``K`` points at once (the window matcher's steps
    4 and 5 after :func:`evidence`, in one pass, no temporary of every point).

    Per point ``i``: the right edge point of its line and sign nearest to
    ``x_left[i] - d_par[i]`` (among the two around it; ``line_start`` (L + 1,) the
    right points of line ``l`` are ``line_start[l] .. line_start[l + 1] - 1``); within
    half a pixel it is the partner, ``partner[i]`` (else -1), ``features[i, column]``
    1 (else 0), and the disparity is ``x_left[i] - right_x[partner]`` instead of
    ``d_par[i]``.  ``disparity[i]`` is NaN where that lies outside ``lo - 0.5 .. hi +
    0.5`` or ``seen[i]`` is False; ``right_edge[i]`` the partner where the disparity is
    kept, else -1."""
    n_lines = line_start.shape[0] - 1
    for i in range(x_left.shape[0]):
        x = x_left[i] - d_par[i]
        line = left_line[i]
        j = -1
        dist = np.inf
        if np.isfinite(x) and 0 <= line < n_lines:
            j, dist = _nearest_on_line(x, left_sign[i], line_start[line], line_start[line + 1],
                                       right_x, right_sign)
        use = dist <= 0.5
        d = x_left[i] - right_x[j] if use else d_par[i]
        kept = d >= lo - 0.5 and d <= hi + 0.5 and seen[i]
        disparity[i] = d if kept else np.nan
        features[i, column] = 1.0 if use else 0.0
        partner[i] = j if use else -1
        right_edge[i] = j if use and kept else -1


@kernel(nogil=True)
def _unique(best, second):  # type: ignore[no-untyped-def]
    """``(second - best) / second`` clipped to 0..1; 0 where either is out of view."""
    if best >= OUT_OF_VIEW or second >= OUT_OF_VIEW:
        return 0.0
    return min(max((second - best) / max(second, 1.0), 0.0), 1.0)


@kernel(nogil=True)
def _vertex(k, before, cost, after, d_min):  # type: ignore[no-untyped-def]
    """Disparity of the parabola's vertex through the costs at ``k - 1, k, k + 1``."""
    curvature = before - 2.0 * cost + after
    offset = 0.0
    if before < OUT_OF_VIEW and after < OUT_OF_VIEW and curvature > 0:
        offset = min(max(0.5 * (before - after) / curvature, -0.5), 0.5)
    return d_min + k + offset


@kernel(nogil=True)
def evidence(summary, d_min, nd, swap_uniqueness, features,
             columns):  # type: ignore[no-untyped-def]
    """Per point: the whole-pixel disparity refined by its parabola (the paths' where
    they are taken) and whether there is one, both ``(N,)``, and into ``features``
    (N, F) the evidence of :data:`robostereo.matcher.confidence.FEATURES` but the right
    edge point's two columns, in the columns ``columns`` (8,) (the caller's table of
    them, in the order written here).  ``summary`` is a :data:`StreamSummary` of the
    window costs."""
    best, cost, second = summary.best, summary.cost, summary.second
    before, after, in_view = summary.before, summary.after, summary.in_view
    right_best = summary.right_best
    best_path = summary.best_path
    n = best.shape[0]
    disparity = np.full(n, np.nan)
    has_disparity = np.zeros(n, np.bool_)
    for i in range(n):
        # -- the windows' best disparity and its parabola
        k_best = best[i]
        has = k_best >= 0
        uniqueness = _unique(float(cost[i]), float(second[i]))
        if has:
            disparity[i] = _vertex(k_best, float(before[i]), float(cost[i]), float(after[i]),
                                   d_min)
        # -- the paths: their agreement, and their disparity where they disagree and
        #    are unique enough
        k_path = best_path[i]
        path_uniqueness = 0.0
        path_agree = True
        path_swapped = False
        if k_path >= 0:
            path_uniqueness = _unique(float(summary.cost_path[i]),
                                      float(summary.second_path[i]))
            path_agree = has and abs(k_path - k_best) <= 1
            path_swapped = not path_agree and path_uniqueness > swap_uniqueness
            if path_swapped:
                disparity[i] = _vertex(k_path, float(summary.before_path[i]),
                                       float(summary.cost_path[i]),
                                       float(summary.after_path[i]), d_min)
        has = has or path_swapped
        has_disparity[i] = has
        # -- the right pixel's best disparity is the same or one off (none: only when a
        #    single disparity is searched, where there is nothing to disagree with)
        left_right = abs(right_best[i] - k_best) <= 1 if right_best[i] >= 0 else nd <= 1
        # -- the three windows along the row, where they agree
        row_uniqueness = 0.0
        if has and abs(summary.best_row[i] - k_best) <= 1:
            row_uniqueness = _unique(float(summary.cost_row[i]), float(summary.second_row[i]))
        f = features[i]
        f[columns[0]] = uniqueness
        f[columns[1]] = row_uniqueness
        f[columns[2]] = 1.0 if row_uniqueness > 0 else 0.0  # row_agree
        f[columns[3]] = 1.0 if left_right else 0.0
        f[columns[4]] = 1.0 - in_view[i] / max(nd, 1)  # out_of_view
        f[columns[5]] = path_uniqueness
        f[columns[6]] = 1.0 if path_agree else 0.0
        f[columns[7]] = 1.0 if path_swapped else 0.0
    return disparity, has_disparity
