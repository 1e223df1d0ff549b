"""Window costs at edge points: every disparity of the range, side-aware windows.

The thesis compares a left edge point only with right *edge points* (3.2, 3.5).  On
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

The work is done in one pass down the image (the numba kernel
:func:`~robostereo.matcher.window_kernels.stream_rows`): pixel costs of a row
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

import itertools
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.matcher.parallel import n_threads, run_all
from robostereo.matcher.window_kernels import (
    HALF_WINDOW,
    PATH_ROW_STEP,
    SIDE_COLUMNS,
    STREAM_COLUMNS,
    StreamImages,
    StreamSettings,
    stream_rows,
)
from robostereo.matcher.window_pixel_kernels import (
    CENSUS_SIZE,
    census_7x5,
    census_padded,
    sobel,
)

__all__ = [
    "COARSE_MARGIN",
    "MIN_BAND_ROWS",
    "PATH_PENALTIES",
    "POINT_WORK_PX",
    "WindowCosts",
    "band_rows",
    "census_transform",
    "coarse_matches",
    "coarse_range",
    "sobel_x",
    "window_costs",
]

#: ``(P1, P2)`` of the paths along the rows, per pixel of the window (chosen
#: leave-one-scene-out by ``benchmarks/fit_confidence.py``): a jump costs more than any
#: window, so a path changes disparity by ramps of one pixel at ``P1`` each
PATH_PENALTIES = (5.0, 160.0)

#: the narrowed range reaches this many pixels beyond the half-resolution disparities
#: found (one coarse pixel of error each way, twice)
COARSE_MARGIN = 4


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
        return census_7x5(g)
    padded = np.pad(g, ((hh, hh), (hw, hw)), mode="edge")
    return census_padded(padded, g.shape[0], g.shape[1], hw, hh)


def sobel_x(grey: NDArray[np.floating]) -> NDArray[np.int16]:
    """Horizontal 3 x 3 Sobel derivative, rounded to whole grey levels (int16).

    The border is reflected without repeating the edge pixel (OpenCV's
    ``BORDER_REFLECT_101``).

    >>> g = np.tile(np.arange(6, dtype=np.float32), (3, 1))
    >>> sobel_x(g)[1, 2:4].tolist()
    [8, 8]
    """
    return sobel(np.ascontiguousarray(grey, dtype=np.float32))


@dataclass(frozen=True)
class WindowCosts:
    """Window costs of left edge points over the whole-pixel disparity range, summed up.

    Disparity ``k`` stands for ``d_min + k``; costs are window sums of pixel costs
    (:func:`window_costs`, Notes);
    :data:`~robostereo.matcher.window_kernels.OUT_OF_VIEW` where there is no such
    cost.  Arrays have shape ``(N,)``.

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
        more than :data:`~robostereo.matcher.window_kernels.PATH_MAX_DISPARITIES` the
        paths' disparities are bins:
        ``best_path`` is then the windows' best whole disparity in the best bin, the
        costs are the bins', ``before_path`` and ``after_path`` the windows' (for the
        parabola).

    With ``sides`` (:func:`window_costs`) also what each placement of the window saw
    on its own (without: -1 throughout, one read-only array shared by the eight):

    placement : ndarray of int
        The window that gives ``cost`` at ``best``: 0 centred, 1 half a window left,
        2 right, 3 up, 4 down (the first of equal ones); -1 where there is no ``best``.
    second_placement : ndarray of int
        That window's own least cost over the disparities in view more than one from
        ``best``: unlike ``second``, not lowered by another placement that sees another
        surface (at an occluding contour the window on the occluder sees one disparity).
    best_left, cost_left : ndarray of int
        The best disparity of the window shifted half a window left alone, over the
        disparities in view (the first of equals; -1: none), and its cost there.  At an
        occluding contour the side window on the occluder's side sees one surface.
    best_right, cost_right : ndarray of int
        The same for the window shifted half a window right.
    second_best : ndarray of int
        The disparity of ``second`` (the first of equals; -1 where there is none).
    right_best_placement : ndarray of int
        The left-right check with the window of ``placement`` alone: the best disparity
        of the right pixel ``x - d_min - k1`` against every left pixel, both windows
        placed as that one (-1 where there is none).  At an occluding contour the right
        pixel lies on the contour too, and its five windows may prefer the other
        surface; the window on the occluder's side sees the occluder in both views.
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
    placement: NDArray[np.int32]
    second_placement: NDArray[np.int32]
    best_left: NDArray[np.int32]
    cost_left: NDArray[np.int32]
    best_right: NDArray[np.int32]
    cost_right: NDArray[np.int32]
    second_best: NDArray[np.int32]
    right_best_placement: NDArray[np.int32]


def _halve(image: NDArray[np.generic], *, mask: bool = False) -> NDArray[np.generic]:
    """2 x 2 binning (an odd last row or column dropped): the mean, or for a mask the
    pixels whose four sources are all set."""
    h, w = image.shape[0] // 2, image.shape[1] // 2
    if mask:
        return np.ascontiguousarray(image[:2 * h, :2 * w].reshape(h, 2, w, 2).all(axis=(1, 3)))
    # an area resize by exactly one half is the mean of each 2 x 2 block
    return cv2.resize(image[:2 * h, :2 * w].astype(np.float32, copy=False), (w, h),
                      interpolation=cv2.INTER_AREA)


#: the work of an edge point's reading, in pixels of a row's pixel costs and sums (per
#: disparity both): on motorcycle and synthetic 1280 x 960 a point's reading took as long
#: as about 26 and 15 pixels' share of the pass
POINT_WORK_PX = 20

#: least rows of a band: a band makes 2 * HALF_WINDOW rows again that the band above made
MIN_BAND_ROWS = 64


def band_rows(row_start: NDArray[np.int64], width: int, n_bands: int) -> NDArray[np.int64]:
    """Row bands of about equal work for the window pass's threads.

    Parameters
    ----------
    row_start : ndarray of int64, shape (H + 1,)
        The edge points of row ``y`` are ``row_start[y] .. row_start[y + 1] - 1``.
    width : int
        Image width ``W``.
    n_bands : int
        Bands wanted; fewer where the image has fewer than ``MIN_BAND_ROWS`` rows a band.

    Returns
    -------
    ndarray of int64, shape (B + 1,)
        Band ``j`` is the rows ``ends[j] .. ends[j + 1] - 1``; ``ends[0] = 0``,
        ``ends[-1] = H``, every band at least :data:`MIN_BAND_ROWS` rows.

    Notes
    -----
    A row's work is its pixels where an edge point's windows reach it (within
    ``2 * HALF_WINDOW`` rows) plus :data:`POINT_WORK_PX` a point on it; the bands split
    the sum into equal parts.  Bands do not change the result
    (:func:`~robostereo.matcher.window_kernels.stream_rows` reads its rows by ``y``
    alone); equal rows left a thread idle where edge points crowd one half (motorcycle:
    6313 points above the middle, 3476 below, 19.7 against 12.5 ms).

    Examples
    --------
    >>> counts = np.r_[np.full(200, 5), np.full(200, 40)]  # points crowd the lower half
    >>> band_rows(np.r_[0, np.cumsum(counts)], 100, 2).tolist()
    [0, 278, 400]
    """
    h = row_start.shape[0] - 1
    n = max(1, min(int(n_bands), h // MIN_BAND_ROWS))
    if n == 1:
        return np.array([0, h], np.int64)
    counts = np.diff(row_start)
    reach = 2 * HALF_WINDOW
    near = np.convolve((counts > 0).astype(np.int64), np.ones(2 * reach + 1, np.int64), "same")
    work = np.cumsum(np.where(near > 0, width, 0) + POINT_WORK_PX * counts)
    if work[-1] == 0:
        return np.linspace(0, h, n + 1).round().astype(np.int64)
    ends = np.searchsorted(work, work[-1] * np.arange(1, n) / n) + 1
    # at least MIN_BAND_ROWS rows a band: clamped from the top, then from the bottom
    ends = np.maximum(ends, MIN_BAND_ROWS * np.arange(1, n))
    ends = np.minimum(ends, h - MIN_BAND_ROWS * np.arange(n - 1, 0, -1))
    return np.r_[0, ends, h].astype(np.int64)


def coarse_matches(
    grey_left: NDArray[np.floating],
    grey_right: NDArray[np.floating],
    rows: NDArray[np.integer],
    columns: NDArray[np.integer],
    disparity_range: tuple[int, int],
    *,
    gradient_truncation: int = 64,
    valid_left: NDArray[np.bool_] | None = None,
    valid_right: NDArray[np.bool_] | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """The edge points' matches at half size that both directions and a neighbour back.

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

    Returns
    -------
    rows, columns, disparities : ndarray of int64, shape (M,)
        At full size (twice the half-size pixel and disparity), sorted by row: the
        halved edge pixels whose best disparity at half resolution passes the left-right
        check and is backed by a neighbour (another such match within two pixels and
        one disparity).  Empty where the images are smaller than a window at half size
        or there are no edge points.

    Notes
    -----
    Both images binned 2 x 2 (a quarter of the pixels), the edge pixels halved (each
    halved pixel once), the range halved: the window costs (:func:`window_costs`,
    centred and side windows, no paths).  A lone false match is rarely backed: an edge
    is a curve, and its neighbours match within a pixel of each other.

    Examples
    --------
    >>> rng = np.random.default_rng(2)
    >>> left = rng.uniform(0, 127, (64, 160)).astype(np.float32)
    >>> right = np.roll(left, -20, axis=1)
    >>> r, c = np.repeat(np.arange(8, 56, 4), 10), np.tile(np.arange(60, 160, 10), 12)
    >>> _, _, d = coarse_matches(left, right, r, c, (0, 100))
    >>> d.size > 100, sorted(set(d.tolist()))
    (True, [20])
    """
    d_lo, d_hi = (int(v) for v in disparity_range)
    ga, gb = _halve(np.asarray(grey_left, np.float32)), _halve(np.asarray(grey_right, np.float32))
    h, w = ga.shape
    none = np.zeros(0, np.int64)
    if h < 2 * HALF_WINDOW + 1 or w < 2 * HALF_WINDOW + 1 or len(rows) == 0:
        return none, none, none
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
    # within a pixel of it too, which a lone false match does not (the matches' best
    # disparities on a grid of the halved image with a margin of two, -2 where there is
    # none: half a byte a full-size pixel, let go before the full pass)
    r, c, d = key[ok] // w + 2, key[ok] % w + 2, wc.best[ok].astype(np.int64)
    grid = np.full((h + 4, w + 4), -2, np.int16 if c_hi - c_lo < 2**15 - 1 else np.int32)
    grid[r, c] = d
    backed = np.zeros(d.shape, np.bool_)
    for dy in range(-2, 3):
        for dx in range(-2, 3):
            if dy or dx:
                backed |= np.abs(grid[r + dy, c + dx] - d) <= 1
    return 2 * (r[backed] - 2), 2 * (c[backed] - 2), 2 * (d[backed] + c_lo)


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
    grey_left, grey_right, rows, columns, disparity_range, gradient_truncation
        See :func:`coarse_matches`.
    valid_left, valid_right
        See :func:`coarse_matches`.
    margin : int
        Pixels added beyond the disparities found, each way.

    Returns
    -------
    tuple of int
        ``(d_min, d_max)`` within `disparity_range`: the hull of the disparities of
        :func:`coarse_matches` (the edge points' matches at half resolution that the
        left-right check and a neighbour back), widened by `margin`.  The whole range
        where there are none.

    Notes
    -----
    The half-size pass (:func:`coarse_matches`) takes a sixth to a third of the time
    of the full pass over the whole range on the developer scenes, not an eighth: the
    pixels are a quarter and the disparities half, but every halved edge point is still
    read over the whole range (``docs/guide/algorithm.md``, W8).  A far
    disparity that no edge point holds consistently in both directions is not searched
    at full size: with a generous range given, the full pass costs what the scene needs
    (a coarse-to-fine pruning of the range; a thin object that no half-size edge point
    matches is lost).

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
    _, _, found = coarse_matches(grey_left, grey_right, rows, columns, (d_lo, d_hi),
                                 gradient_truncation=gradient_truncation,
                                 valid_left=valid_left, valid_right=valid_right)
    if found.size == 0:
        return d_lo, d_hi
    return max(d_lo, int(found.min()) - margin), min(d_hi, int(found.max()) + margin)


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
    sides: bool = False,
) -> WindowCosts:
    """Side-aware census + gradient window costs at left pixels, every disparity.

    Parameters
    ----------
    grey_left, grey_right : ndarray, shape (H, W)
        Grey images on the thesis's 0..127 scale (:func:`robostereo.matcher.grey_levels.to_grey`).
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
    sides : bool
        Also keep what each placement saw on its own (:class:`WindowCosts`:
        ``placement`` ... ``right_best_placement``; Notes, 7), for measuring evidence
        at occluding contours; the matcher does not read them.

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
       from the left and from the right, as two paths of semi-global matching
       (Hirschmüller 2008, eq. 13): ``L(x, d) = C(x, d) + min(L(x', d), L(x', d -/+ 1) + P1,
       min_k L(x', k) + P2) - min_k L(x', k)`` with ``x'`` the previous column; their
       sum is read at the edge points (``best_path`` ...).  A path carries the
       disparity of textured parts of the row into ambiguous ones (repeated patterns,
       weak texture), where a window alone has two near-equal minima.
    7. With ``sides``: the winning placement and its own second cost, the best
       disparity of each side window alone, the disparity of the second cost, and the
       left-right check with the winning placement alone.  At an occluding contour the
       window on the occluder's side sees one surface; the other side may see a surface
       the right view cannot (half-occlusion).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> left = rng.uniform(0, 127, (30, 60)).astype(np.float32)
    >>> right = np.roll(left, -6, axis=1)
    >>> wc = window_costs(left, right, np.array([15]), np.array([30]), (0, 12))
    >>> int(wc.best[0]) + wc.d_min, int(wc.right_best[0]) + wc.d_min, int(wc.cost[0])
    (6, 6, 0)
    """
    # -- checks: one image size, a range, edge pixels in the image sorted by row
    gl = np.ascontiguousarray(grey_left, dtype=np.float32)
    gr = np.ascontiguousarray(grey_right, dtype=np.float32)
    if gl.shape != gr.shape or gl.ndim != 2:
        raise InputError(f"grey images must be (H, W) of one size, got {gl.shape}, {gr.shape}")
    d_lo, d_hi = (int(v) for v in disparity_range)
    if d_lo > d_hi:
        raise InputError(f"disparity_range must have min <= max, got {disparity_range}")
    r, c = np.asarray(rows), np.asarray(columns)
    h, w = gl.shape
    if r.shape != c.shape or r.ndim != 1:
        raise InputError("rows and columns must be 1-D arrays of one length")
    if r.size and (np.any(r[1:] < r[:-1]) or r.min() < 0 or r.max() >= h or c.min() < 0
                   or c.max() >= w):
        raise InputError("edge pixels must lie in the image and be sorted by row")
    r = np.ascontiguousarray(r, dtype=np.int32)  # an EdgeSet's are: no copy
    c = np.ascontiguousarray(c, dtype=np.int32)
    # -- masks: invalid pixels get a gradient that differs from any by more than the
    # truncation and a census of alternating bits, so that any pair with one costs
    # nearly the most
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
    # (N, columns) summary; what each placement saw only when asked for (the matcher
    # does not read it: eight more int32 a point at its peak memory otherwise)
    names = STREAM_COLUMNS if sides else STREAM_COLUMNS[:-len(SIDE_COLUMNS)]
    out = np.full((n, len(names)), -1, np.int32)
    if n:
        # (H + 1,); rows sought as int32, as r: int64 ones would make numpy search an
        # int64 copy of r (8 bytes a point, at the match's peak)
        row_start = np.searchsorted(r, np.arange(h + 1, dtype=np.int32)).astype(np.int64)
        trunc = int(gradient_truncation)
        area = (2 * HALF_WINDOW + 1) ** 2
        # path penalties per window pixel -> per window sum
        if path_penalties is None:
            p1, p2 = -1, -1
        else:
            pp = [float(v) for v in path_penalties]
            if len(pp) != 2 or not all(np.isfinite(pp)) or not 0 <= pp[0] <= pp[1] <= 200:
                raise InputError(f"path_penalties must be (P1, P2) with 0 <= P1 <= P2 <= 200 "
                                 f"per window pixel, got {path_penalties}")
            p1, p2 = round(pp[0] * area), round(pp[1] * area)
        images = StreamImages(gl, gr, masks[0], masks[1], checks[0], checks[1])
        # the ring of pixel costs in bytes where every cost fits one: a census distance
        # of at most 34 bits, 64 where an invalid pixel's pattern meets another
        most = (64 if checks[0] or checks[1] else 34) + trunc
        byte_ring = most <= np.iinfo(np.uint8).max
        settings = StreamSettings(
            d_min=d_lo, n_disparities=nd, truncation=np.int16(trunc),
            pixel_cost_max=np.int16(34 + trunc),
            ring_type=np.uint8 if byte_ring else np.int16,
            half_window=HALF_WINDOW,
            vertical=bool(vertical), p1=p1, p2=p2, path_row_step=PATH_ROW_STEP,
            sides=bool(sides))
        # -- one pass down the image per band of rows, a band per thread, the bands of
        #    about equal work (band_rows)
        ends = band_rows(row_start, w, n_threads()).tolist()

        def band(y0: int, y1: int) -> None:
            stream_rows(images, settings, row_start, c, y0, y1, out)

        run_all([lambda y0=y0, y1=y1: band(y0, y1)
                 for y0, y1 in itertools.pairwise(ends)])
    cols = dict(zip(names, out.T, strict=True))
    none = np.broadcast_to(np.int32(-1), (n,))  # -1 throughout, read-only, no memory
    cols.update({name: none for name in STREAM_COLUMNS if name not in cols})
    return WindowCosts(d_min=d_lo, n_disparities=nd, **cols)
