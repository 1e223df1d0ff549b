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
gradients; it is summed over a ``9 x 9`` window placed three ways (centred on the
edge, and shifted half a window left and right) and the lowest of the three is kept:
at a depth boundary only the window on the occluding surface sees one disparity
(side-aware windows, as in multiple-window matching [2]_).

The work is done in one pass down the image (a numba kernel): pixel costs of a row
for all disparities, vertical column sums kept running over a ring of the last nine
rows, and at each row the windows of that row's edge points read from the column
sums.  Cost is therefore linear in the disparity range and the image size, per-image
work (census, gradients) is done once, and memory is a few rows of costs.

References
----------
.. [1] R. Zabih and J. Woodfill, "Non-parametric local transforms for computing
   visual correspondence", ECCV 1994.
.. [2] A. Fusiello, V. Roberto and E. Trucco, "Efficient stereo with multiple
   windowing", CVPR 1997.
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

__all__ = [
    "WindowCosts",
    "WindowMatch",
    "census_transform",
    "sobel_x",
    "window_costs",
    "window_match",
]

#: census neighbourhood (width, height): 7 x 5 minus the centre = 34 bits
CENSUS_SIZE = (7, 5)
#: half size of the aggregation window (9 x 9) and the shift of the side windows
HALF_WINDOW = 4
#: the windows shifted up or down cost this many sixteenths more: they win only where
#: they are clearly better than the windows along the row
VERTICAL_PENALTY = 8


@intrinsic
def _popcount(typingctx, x):  # type: ignore[no-untyped-def]
    sig = types.uint64(types.uint64)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        fn = builder.module.declare_intrinsic("llvm.ctpop", [ir.IntType(64)])
        return builder.call(fn, args)

    return sig, codegen


@nb.njit(cache=True, fastmath=True)
def _census_bits(acc, nbr, centre):  # type: ignore[no-untyped-def]
    for x in range(acc.shape[0]):
        acc[x] = (acc[x] << np.uint64(1)) | np.uint64(nbr[x] < centre[x])


@nb.njit(cache=True)
def _census(padded, h, w, hw, hh):  # type: ignore[no-untyped-def]
    out = np.zeros((h, w), np.uint64)
    for y in range(h):
        centre = padded[y + hh, hw:hw + w]
        for dy in range(-hh, hh + 1):
            for dx in range(-hw, hw + 1):
                if dy != 0 or dx != 0:
                    _census_bits(out[y], padded[y + hh + dy, hw + dx:hw + dx + w], centre)
    return out


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
    g = np.asarray(grey, dtype=np.float32)
    padded = np.pad(g, ((hh, hh), (hw, hw)), mode="edge")
    return _census(padded, g.shape[0], g.shape[1], hw, hh)


def sobel_x(grey: NDArray[np.floating]) -> NDArray[np.int16]:
    """Horizontal 3 x 3 Sobel derivative, rounded to whole grey levels (int16).

    >>> g = np.tile(np.arange(6, dtype=np.float32), (3, 1))
    >>> sobel_x(g)[1, 2:4].tolist()
    [8, 8]
    """
    s = cv2.Sobel(np.asarray(grey, dtype=np.float32), cv2.CV_32F, 1, 0, ksize=3,
                  borderType=cv2.BORDER_REFLECT_101)
    return np.clip(np.rint(s), -32767, 32767).astype(np.int16)


@nb.njit(cache=True, fastmath=True)
def _pixel_update(colsum, ring, cl, cr, gl, gr, trunc):  # type: ignore[no-untyped-def]
    """Replace one ring row of pixel costs and update the column sums, for 1-D rows:
    ``p[x] = H(cl[x], cr[x]) + min(|gl[x] - gr[x]|, trunc)``."""
    for x in range(colsum.shape[0]):
        g = min(abs(np.int16(gl[x]) - np.int16(gr[x])), trunc)
        p = np.int16(_popcount(cl[x] ^ cr[x])) + g
        colsum[x] += p - ring[x]
        ring[x] = p


@nb.njit(cache=True, fastmath=True)
def _constant_update(colsum, ring, value):  # type: ignore[no-untyped-def]
    for x in range(colsum.shape[0]):
        colsum[x] += value - ring[x]
        ring[x] = value


@nb.njit(cache=True, fastmath=True)
def _row_update(cl, cr, gl, gr, d0, nd, trunc, pmax, m, colsum, ring,
                compute):  # type: ignore[no-untyped-def]
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
                          gl[x0:x1], gr[x0 - d:x1 - d], trunc)


@nb.njit(cache=True, fastmath=True)
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


@nb.njit(cache=True, fastmath=True, inline="always")
def _least(b_up, b_mid, b_down, x, hw, vertical):  # type: ignore[no-untyped-def]
    """Least of the window sums placed at ``x - hw, x, x + hw`` on the three rows of
    box sums (only the middle row unless ``vertical``)."""
    v = np.int32(min(b_mid[x - hw], min(b_mid[x], b_mid[x + hw])))
    if vertical:
        v = min(v, np.int32(min(b_up[x], b_down[x])))
    return v


@nb.njit(cache=True, fastmath=True)
def _stream(cl, cr, gl, gr, row_start, cols, dlo, nd, trunc, pmax, hw, vertical,
            out_of_view, cost, rcost, xr_out, row_cost):  # type: ignore[no-untyped-def]
    h, w = cl.shape
    n_ring = 2 * hw + 1
    m = 2 * hw
    wp = w + 2 * m
    base = 4 * n_ring  # keeps ring indices of negative rows positive
    ring = np.zeros((n_ring, nd, wp), np.int16)   # pixel costs of the last 2 hw + 1 rows
    colsum = np.zeros((nd, wp), np.int16)         # their column sums
    boxes = np.zeros((n_ring, nd, wp), np.int16)  # window sums of the last 2 hw + 1 rows
    t2 = np.zeros(wp, np.int16)
    t4 = np.zeros(wp, np.int16)
    colsum[:, :m] = n_ring * pmax
    colsum[:, w + m:] = n_ring * pmax

    def edges_in(y0, y1):  # type: ignore[no-untyped-def]
        return row_start[min(max(y1, 0), h)] > row_start[min(max(y0, 0), h)]

    lag = hw if vertical else 0  # rows of box sums needed below the output row
    j0 = -lag
    # column sums of the window centred on row j0: rows j0 - hw .. j0 + hw, clamped
    for r in range(j0 - hw, j0 + hw + 1):
        yc = min(max(r, 0), h - 1)
        _row_update(cl[yc], cr[yc], gl[yc], gr[yc], dlo, nd, trunc, pmax, m, colsum,
                    ring[(r + base) % n_ring], True)
    for j in range(j0, h + lag):
        if j > j0:
            r = j + hw  # the new pixel row; its ring slot holds row j - hw - 1
            yc = min(max(r, 0), h - 1)
            _row_update(cl[yc], cr[yc], gl[yc], gr[yc], dlo, nd, trunc, pmax, m, colsum,
                        ring[(r + base) % n_ring],
                        edges_in(r - hw - lag, r + hw + lag + 1))
        bj = boxes[(j + base) % n_ring]
        if edges_in(j - lag, j + lag + 1):
            for k in range(nd):
                _box(colsum[k], bj[k], t2, t4)
        y = j - lag  # the row whose windows are all complete
        if y < 0 or row_start[y + 1] == row_start[y]:
            continue
        b_up = boxes[(y - hw + base) % n_ring]
        b_mid = boxes[(y + base) % n_ring]
        b_down = boxes[(y + hw + base) % n_ring]
        for i in range(row_start[y], row_start[y + 1]):
            c = cols[i]
            kbest = 0
            vbest = out_of_view
            for k in range(nd):
                xr = c - dlo - k
                if xr < 0 or xr >= w:
                    v = out_of_view
                    row_cost[i, k] = out_of_view
                else:
                    v = _least(b_up[k], b_mid[k], b_down[k], c + m, hw, vertical)
                    row_cost[i, k] = _least(b_up[k], b_mid[k], b_down[k], c + m, hw, False)
                cost[i, k] = v
                if v < vbest:
                    vbest = v
                    kbest = k
            xr = c - dlo - kbest
            xr_out[i] = xr
            # the right pixel of the best disparity against every left pixel
            for k in range(nd):
                xl = xr + dlo + k
                if xl < 0 or xl >= w:
                    rcost[i, k] = out_of_view
                else:
                    rcost[i, k] = _least(b_up[k], b_mid[k], b_down[k], xl + m, hw, vertical)


@dataclass(frozen=True)
class WindowCosts:
    """Window costs of left edge points over the whole-pixel disparity range.

    Attributes
    ----------
    d_min : int
        Disparity of column 0 of the cost arrays.
    cost : ndarray of int32, shape (N, D)
        Side-aware window cost of each left edge point at disparity ``d_min + k``;
        ``2**30`` where the right pixel falls outside the image.
    right_cost : ndarray of int32, shape (N, D)
        Cost of the right pixel of each point's best disparity against the left
        pixel at ``d_min + k`` (the left-right check's costs).
    right_column : ndarray of int, shape (N,)
        That right pixel's column.
    row_cost : ndarray of int32, shape (N, D)
        The cost with the three windows along the row only.
    """

    d_min: int
    cost: NDArray[np.int32]
    right_cost: NDArray[np.int32]
    right_column: NDArray[np.intp]
    row_cost: NDArray[np.int32]

    @property
    def n_disparities(self) -> int:
        return int(self.cost.shape[1])


#: cost value of a disparity whose right pixel lies outside the image
OUT_OF_VIEW = 2**30


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
    census_left: NDArray[np.uint64] | None = None,
    census_right: NDArray[np.uint64] | None = None,
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
    census_left, census_right : ndarray of uint64, optional
        Census transforms, if already computed.

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

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> left = rng.uniform(0, 127, (30, 60)).astype(np.float32)
    >>> right = np.roll(left, -6, axis=1)
    >>> wc = window_costs(left, right, np.array([15]), np.array([30]), (0, 12))
    >>> int(np.argmin(wc.cost[0])) + wc.d_min, int(np.argmin(wc.right_cost[0])) + wc.d_min
    (6, 6)
    """
    gl = np.asarray(grey_left, dtype=np.float32)
    gr = np.asarray(grey_right, dtype=np.float32)
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
    cl = census_transform(gl) if census_left is None else census_left
    cr = census_transform(gr) if census_right is None else census_right
    sl, sr = sobel_x(gl), sobel_x(gr)
    # invalid pixels: a gradient that differs from any by more than the truncation and
    # a census of alternating bits, so that any pair with one costs nearly the most
    for valid, sob, cen, sign in ((valid_left, sl, cl, -1), (valid_right, sr, cr, 1)):
        if valid is not None:
            bad = ~np.asarray(valid, dtype=bool)
            if bad.shape != gl.shape:
                raise InputError(f"valid masks must have the images' shape {gl.shape}")
            if bad.any():
                if census_left is not None or census_right is not None:
                    cen = cen.copy()
                sob[bad] = sign * 32000
                cen[bad] = np.uint64(0x5555555555555555 if sign > 0 else 0xAAAAAAAAAAAAAAAA)
                if sign < 0:
                    cl = cen
                else:
                    cr = cen
    nd = d_hi - d_lo + 1
    n = r.shape[0]
    cost = np.empty((n, nd), np.int32)
    rcost = np.empty((n, nd), np.int32)
    xr = np.empty(n, np.int64)
    row_cost = np.empty((n, nd), np.int32)
    if n:
        row_start = np.searchsorted(r, np.arange(h + 1)).astype(np.int64)
        trunc = int(gradient_truncation)
        pmax = np.int16(34 + trunc)
        _stream(cl, cr, sl, sr, row_start, c, d_lo, nd, np.int16(trunc), pmax, HALF_WINDOW,
                bool(vertical), np.int32(OUT_OF_VIEW), cost, rcost, xr, row_cost)
    return WindowCosts(d_min=d_lo, cost=cost, right_cost=rcost, right_column=xr.astype(np.intp),
                       row_cost=row_cost)


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


def _nearest_right_edge(left: EdgeSet, right: EdgeSet, x_right: NDArray[np.float64]
                        ) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """Per left edge point, the same-sign right edge point on its row nearest to
    ``x_right``, and the distance (``inf`` where none)."""
    n = len(left)
    idx = np.full(n, -1, dtype=np.intp)
    dist = np.full(n, np.inf)
    if n == 0 or len(right) == 0:
        return idx, dist
    finite = np.abs(x_right[np.isfinite(x_right)])
    span = 4.0 * (max(float(np.max(right.x)), float(np.max(finite, initial=0.0))) + 10.0)
    key_r = right.line * span + right.x
    q = np.where(np.isfinite(x_right), left.line * span + x_right, -np.inf)
    j = np.searchsorted(key_r, q)
    for jj in (np.clip(j - 1, 0, len(right) - 1), np.clip(j, 0, len(right) - 1)):
        dd = np.abs(key_r[jj] - q)
        ok = (right.sign[jj] == left.sign) & (right.line[jj] == left.line) & (dd < dist)
        dist = np.where(ok, dd, dist)
        idx = np.where(ok, jj, idx)
    return idx, dist


def _uniqueness(cost: NDArray[np.float64], best: NDArray[np.intp]) -> NDArray[np.float64]:
    """``(c2 - c1) / c2`` of the best cost ``c1`` and the best ``c2`` more than one
    disparity away; 0 where there is no such cost in view."""
    n, nd = cost.shape
    if n == 0:
        return np.zeros(0)
    c1 = cost[np.arange(n), best]
    far = np.abs(np.arange(nd)[None, :] - best[:, None]) > 1
    c2 = np.min(np.where(far, cost, np.inf), axis=1, initial=np.inf)
    with np.errstate(invalid="ignore", divide="ignore"):
        u = np.where(np.isfinite(c2) & np.isfinite(c1), (c2 - c1) / np.maximum(c2, 1.0), 0.0)
    return np.clip(u, 0.0, 1.0)


def _row_agreement(wc: WindowCosts, best: NDArray[np.intp]) -> NDArray[np.float64]:
    """1 where the windows along the row alone give the same best disparity (or one
    pixel off), and their own uniqueness there; 0 elsewhere."""
    if wc.row_cost.shape[0] == 0:
        return np.zeros(0)
    rc = wc.row_cost.astype(np.float64)
    rc[wc.row_cost >= OUT_OF_VIEW] = np.inf
    kb = np.argmin(rc, axis=1)
    return np.where(np.abs(kb - best) <= 1, _uniqueness(rc, kb), 0.0)


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

    Returns
    -------
    WindowMatch

    Notes
    -----
    1. Window costs over the range (:func:`window_costs`).
    2. Best disparity ``d1`` (cost ``c1``); ``c2`` the best cost more than one pixel
       away; uniqueness ``(c2 - c1) / c2`` (0 when no such disparity is in view).
    3. Left-right check: the right pixel ``x - d1`` scored against every left pixel;
       its best disparity should be ``d1`` (or one pixel off).
    4. Sub-pixel disparity from the right edge point within one pixel of ``x - d``
       (same contrast sign), else from the parabola of the costs.
    5. Confidence from the features by the calibrated logistic model
       (:mod:`robostereo.confidence`).
    """
    lo, hi = float(disparity_range[0]), float(disparity_range[1])
    d_lo, d_hi = int(np.floor(lo)), int(np.ceil(hi))
    wc = window_costs(grey_left, grey_right, left.row, left.column, (d_lo, d_hi),
                      gradient_truncation=gradient_truncation, valid_left=valid_left,
                      valid_right=valid_right)
    n, nd = wc.cost.shape
    cost = wc.cost.astype(np.float64)
    out = wc.cost >= OUT_OF_VIEW
    cost[out] = np.inf
    ar = np.arange(n)
    k1 = np.argmin(cost, axis=1) if nd else np.zeros(n, np.intp)
    c1 = cost[ar, k1] if n else np.zeros(0)
    seen = np.isfinite(c1)
    uniq = _uniqueness(cost, k1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cm = cost[ar, np.clip(k1 - 1, 0, max(nd - 1, 0))] if n else c1
        cp = cost[ar, np.clip(k1 + 1, 0, max(nd - 1, 0))] if n else c1
        den = cm - 2.0 * c1 + cp
        inner = (k1 > 0) & (k1 < nd - 1) & np.isfinite(den) & (den > 0)
        off = np.where(inner, 0.5 * (cm - cp) / np.where(inner, den, 1.0), 0.0)
    d_par = d_lo + k1 + np.clip(off, -0.5, 0.5)
    d_par = np.where(seen, d_par, np.nan)
    rc = wc.right_cost.astype(np.float64)
    rc[wc.right_cost >= OUT_OF_VIEW] = np.inf
    kr = np.argmin(rc, axis=1) if nd else k1
    lr = np.abs(kr - k1)
    idx, dist = _nearest_right_edge(left, right, left.x - d_par)
    has = dist <= 1.0
    d_edge = left.x - right.x[np.maximum(idx, 0)] if len(right) else d_par
    use_edge = has & (np.abs(d_edge - d_par) <= 0.5)
    disparity = np.where(use_edge, d_edge, d_par)
    in_range = (disparity >= lo - 0.5) & (disparity <= hi + 0.5) & seen
    disparity = np.where(in_range, disparity, np.nan)
    right_edge = np.where(use_edge & in_range, idx, -1).astype(np.intp)
    sim = np.zeros(n)
    if np.any(use_edge):
        sel = np.nonzero(use_edge)[0]
        sim[sel] = pair_similarity(left, right, sel, idx[sel], weights=weights,
                                   profile_scale=profile_scale)[4]
    u_row = _row_agreement(wc, k1)
    feats = np.column_stack([
        uniq,
        u_row,
        (u_row > 0).astype(float),
        (lr <= 1).astype(float),
        use_edge.astype(float),
        sim,
        out.mean(axis=1) if nd else np.ones(n),
    ]) if n else np.zeros((0, len(FEATURES)))
    conf = (model or DEFAULT_MODEL)(feats)
    conf = np.where(np.isfinite(disparity), conf, np.nan)
    return WindowMatch(disparity=disparity, right_edge=right_edge, features=feats,
                       confidence=conf, costs=wc)
