"""Edge points along epipolar lines, found and placed to sub-pixel precision (thesis 3.1-3.2).

The rows of a rectified image are its epipolar lines; :func:`detect_edges` finds the
edge points as the peaks of the 1-D intensity gradient along the rows of the smoothed
image (grey levels on the thesis's 0..127 scale and the 5 x 5 filter:
:mod:`robostereo.matcher.grey_levels`), locates them to sub-pixel precision (on request
moved towards the gradient's peak on a lightly blurred image, :func:`fine_weights`) and
gives them their features in an :class:`~robostereo.matcher.edge_features.EdgeSet`
(:mod:`robostereo.matcher.edge_features`).  :func:`usable_pixels` says where those
features see only valid image data.

The loops over the rows and the edge points (gradient peaks in one pass, features,
connectivity) are the numba kernels of :mod:`robostereo.matcher.edge_kernels`.
"""

from __future__ import annotations

from functools import lru_cache

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_int, require_positive
from robostereo.matcher.edge_features import EdgeSet
from robostereo.matcher.edge_kernels import (
    FINE_DEAD_ZONE_PX,
    SIDE_OFFSET,
    blur_column,
    fine_positions,
    fine_positions_grey,
    peak_links,
    strip_points,
)
from robostereo.matcher.grey_levels import OPENCV_LANES, smooth, to_grey

__all__ = [
    "check_edge_blur",
    "detect_edges",
    "fine_weights",
    "usable_pixels",
]

#: edge points lie at least this many pixels inside the left and right borders, so that
#: their features (5 x 5 window, side grey levels) are not cut by the border
BORDER = SIDE_OFFSET + 1

#: how far along the row an edge point's features reach into the image: the side grey
#: levels (SIDE_OFFSET) of the 5 x 5 smoothed image (2 more)
REACH = SIDE_OFFSET + 2


def usable_pixels(valid: ArrayLike) -> NDArray[np.bool_]:
    """Pixels whose edge features see only valid image data.

    Parameters
    ----------
    valid : array_like of bool, shape (H, W)
        True where the image holds data (e.g. inside the source of a rectified image).

    Returns
    -------
    ndarray of bool, shape (H, W)
        ``valid`` eroded by ``REACH`` columns and 2 rows (the 5 x 5 filter), so that
        an edge point there is the scene's, not the border of the invalid region.

    Examples
    --------
    >>> v = np.ones((7, 20), bool); v[:, 15:] = False
    >>> usable_pixels(v)[3].nonzero()[0].tolist()
    [0, 1, 2, 3, 4, 5, 6, 7, 8]
    """
    v = np.asarray(valid, dtype=bool)
    kernel = np.ones((5, 2 * REACH + 1), np.uint8)
    return cv2.erode(v.astype(np.uint8), kernel, borderType=cv2.BORDER_CONSTANT,
                     borderValue=1).astype(bool)


#: the 1-tap kernel of a blur down the columns only
_ONE = np.ones(1, np.float32)
#: image rows blurred at a time for the fine placement: no blurred image is held whole
_FINE_STRIP_ROWS = 64


def check_edge_blur(edge_blur_px: float | None) -> None:
    """Refuse an `edge_blur_px` that is not None or a number in 0..10 (pixels).

    >>> check_edge_blur(0.85); check_edge_blur(None)
    >>> check_edge_blur(-1.0)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: edge_blur_px must be None or a number in 0..10 (pixels), got -1.0
    """
    ok = edge_blur_px is None or (
        isinstance(edge_blur_px, (int, float, np.floating, np.integer))
        and not isinstance(edge_blur_px, bool) and 0.0 <= float(edge_blur_px) <= 10.0)
    if not ok:
        raise InputError(f"edge_blur_px must be None or a number in 0..10 (pixels), got "
                         f"{edge_blur_px!r}")


def fine_weights(edge_blur_px: float | None) -> NDArray[np.float32] | None:
    """The 1-D Gaussian whose separable blur places the sub-pixel edge points, or None
    for the thesis's smoothed image (see ``edge_blur_px`` of :func:`detect_edges`).

    Parameters
    ----------
    edge_blur_px : float or None
        Gaussian sigma, pixels; 0: the grey levels as they are.

    Returns
    -------
    ndarray of float32, shape (2 R + 1,), or None
        ``cv2.getGaussianKernel`` cut at ``R = ceil(3 sigma)`` (at 0.85 px what the
        edge points read differs from ``cv2.GaussianBlur``'s, cut at ``4 sigma``, by
        about 1e-5 of the full scale).

    Examples
    --------
    >>> fine_weights(None), fine_weights(0.0).tolist(), fine_weights(0.85).shape
    (None, [1.0], (7,))
    """
    if edge_blur_px is None:
        return None
    if edge_blur_px == 0:
        return np.ones(1, np.float32)
    size = 2 * int(np.ceil(3.0 * float(edge_blur_px))) + 1
    return cv2.getGaussianKernel(size, float(edge_blur_px), cv2.CV_32F).ravel()


@lru_cache(maxsize=16)
def _kernel_blur_agrees(weights: bytes) -> bool:
    """Whether :func:`blur_column` gives this machine's OpenCV values for the float32
    `weights` (their bytes): symmetric, and equal on random grey levels, 61 columns
    (see :func:`~robostereo.matcher.grey_levels._kernel_grey_agrees`; a size OpenCV
    filters another way fails too)."""
    wt = np.frombuffer(weights, np.float32)
    if wt.size < 3 or not np.array_equal(wt, wt[::-1]):
        return False
    probe = np.random.default_rng(2).uniform(0, 127, (2 * wt.size + 3, 61)).astype(np.float32)
    want = cv2.sepFilter2D(probe, -1, _ONE, wt, borderType=cv2.BORDER_REFLECT_101)
    got = np.empty_like(probe)
    for y in range(probe.shape[0]):
        blur_column(probe, y, wt, 61 // OPENCV_LANES * OPENCV_LANES, got[y])
    return bool(np.array_equal(got.view(np.uint32), want.view(np.uint32)))


def _place_finely(x: NDArray[np.float64], row: NDArray[np.integer],
                  column: NDArray[np.integer], sign: NDArray[np.int8],
                  grey: NDArray[np.floating], weights: NDArray[np.float32]) -> None:
    """Move the edge points' ``x`` ``(N,)`` in place towards the gradient's peak on the
    grey levels blurred by `weights` (``edge_blur_px`` of :func:`detect_edges`).

    The points come row by row (``row`` non-decreasing).  Where
    :func:`_kernel_blur_agrees`, the kernel blurs each row with points down the columns
    as it comes (:func:`fine_positions_grey`, one call).  Else OpenCV blurs strips of
    rows in turn, each with the rows its blur reads beyond it, so no blurred image is
    held whole; a strip's rows come out as they would from the whole image.
    """
    if (weights.size > 1 and grey.dtype == np.float32 and grey.flags.c_contiguous
            and _kernel_blur_agrees(weights.tobytes())):
        fine_positions_grey(x, row, column, sign, grey, weights, FINE_DEAD_ZONE_PX,
                            grey.shape[1] // OPENCV_LANES * OPENCV_LANES)
        return
    h = grey.shape[0]
    rad = weights.size // 2
    starts = np.arange(0, h, _FINE_STRIP_ROWS)
    # the bounds in the rows' own dtype: int64 bounds would make numpy search an int64
    # copy of the rows (8 bytes a point)
    bounds = np.searchsorted(row, np.append(starts, h).astype(row.dtype))
    for a, lo, hi in zip(starts.tolist(), bounds[:-1].tolist(), bounds[1:].tolist(),
                         strict=True):
        if lo == hi:
            continue
        s0, s1 = max(a - rad, 0), min(a + _FINE_STRIP_ROWS + rad, h)
        strip = np.ascontiguousarray(grey[s0:s1], np.float32)
        if weights.size > 1:
            strip = cv2.sepFilter2D(strip, -1, _ONE, weights,
                                    borderType=cv2.BORDER_REFLECT_101)
        fine_positions(x, row, column, sign, strip, s0, weights, FINE_DEAD_ZONE_PX, lo, hi)


#: image rows smoothed at a time by the edge stage: no smoothed image is held whole
_EDGE_STRIP_ROWS = 64


def _strip_points(grey: NDArray[np.float32], threshold: np.float32, row_offset: int,
                  row_step: int, n_lines: int, subpixel: bool, usable: NDArray[np.bool_],
                  check: bool) -> list[NDArray]:
    """:func:`~robostereo.matcher.edge_kernels.strip_points` over the lines of `grey`,
    a strip of :data:`_EDGE_STRIP_ROWS` rows at a time, each smoothed with the two rows
    its filter reads beyond it (so its rows come out as the whole image's would):
    lines, columns, rows, positions, signs, magnitudes and the grey levels before and
    after of all the peaks, ``(N,)`` each, in line order.  Each strip's points are
    copied into arrays made with the room the strips so far foretell (remade larger
    where that falls short) and cut to size at the end, not joined from the strips'
    parts (which would hold every point twice).  Where every row is a line
    (`row_step` 1, `row_offset` 0) the rows are the lines' array itself."""
    h = grey.shape[0]
    per_strip = max(1, _EDGE_STRIP_ROWS // row_step)
    same_rows = row_step == 1 and row_offset == 0
    out: list[NDArray] = []
    n = 0
    for k0 in range(0, n_lines, per_strip):
        k1 = min(n_lines, k0 + per_strip)
        y0, y1 = row_offset + k0 * row_step, row_offset + (k1 - 1) * row_step + 1
        s0, s1 = max(y0 - 2, 0), min(y1 + 2, h)
        strip = smooth(grey[s0:s1])
        lines = np.ascontiguousarray(strip[y0 - s0:y1 - s0:row_step])
        del strip
        part = strip_points(lines, threshold, BORDER, k0, row_offset, row_step, subpixel,
                            usable, check)
        if same_rows:  # the rows (third) are the lines (first)
            part = part[:2] + part[3:]
        k = part[0].shape[0]
        # room for the points the lines so far foretell for the whole image, a quarter
        # more; made again from the count so far where that was too little
        room = max(n + k, 1024, (n + k) * n_lines * 5 // (4 * k1))
        if not out:
            out = [np.empty(room, a.dtype) for a in part]
        elif n + k > out[0].shape[0]:
            for a in out:
                a.resize(room, refcheck=False)
        for a, b in zip(out, part, strict=True):
            a[n:n + k] = b
        n += k
    for a in out:  # the room not used given back (realloc: no copy)
        a.resize(n, refcheck=False)
    if same_rows:
        out.insert(2, out[0])
    return out


def detect_edges(
    image: ArrayLike,
    *,
    threshold: float = 8.0,
    row_step: int = 1,
    row_offset: int = 0,
    bit_depth: int | None = None,
    subpixel: bool = True,
    grey: NDArray[np.float32] | None = None,
    valid: ArrayLike | None = None,
    edge_blur_px: float | None = None,
) -> EdgeSet:
    """Find edge points along the rows (epipolar lines) of an image (thesis 3.1-3.2).

    Parameters
    ----------
    image : array_like, shape (H, W) or (H, W, 3|4)
        Rectified image: its rows are epipolar lines.
    threshold : float
        Least gradient magnitude of an edge point, grey levels per pixel on the thesis's
        0..127 scale (thesis: 8.0; figure 4-3 also shows 6).
    row_step : int
        Spacing of the epipolar lines in rows (1 = every row).
    row_offset : int
        First row used.
    bit_depth : int, optional
        Bit depth of the input grey levels (see :func:`~robostereo.matcher.grey_levels.to_grey`).
    subpixel : bool
        Locate edges to sub-pixel precision (default) or at whole pixels, as the thesis.
    grey : ndarray, optional
        The image already converted by :func:`~robostereo.matcher.grey_levels.to_grey` (saves
        the conversion).
    valid : array_like of bool, shape (H, W), optional
        Pixels that hold image data (e.g. the part of a rectified image that has a
        source).  Invalid pixels may hold anything; edge points whose features would
        see them are not reported (:func:`usable_pixels`).
    edge_blur_px : float or None
        None (the default here, the thesis's way): the sub-pixel position is the
        smoothed gradient's peak.  A number: the edge points are still found on the
        smoothed image, but each is moved towards the peak of the gradient of the grey
        levels blurred by a Gaussian of this sigma (pixels; 0: not blurred), the peak
        of the same sign nearest its column within a pixel, by the part of the move
        beyond :data:`~robostereo.matcher.edge_kernels.FINE_DEAD_ZONE_PX` (0.05 px;
        none where there is no such peak).  The 5 x 5 filter spreads an edge's gradient about 2 px
        either side, so texture beside the edge pulls the peak; at an object's
        outline the texture behind differs between the two views and the pull does
        not cancel in the disparity.  :class:`~robostereo.matcher.parameters.MatchParameters`
        passes its own (0.85 by default).

    Returns
    -------
    EdgeSet

    Raises
    ------
    InputError
        An image :func:`~robostereo.matcher.grey_levels.to_grey` refuses or smaller than
        5 x 5 pixels, a threshold that is not a finite number > 0, a `row_step` or
        `row_offset` that is not an integer (>= 1, in ``0..H-1``), a `valid` mask of
        another shape, an `edge_blur_px` that is not None or in 0..10.

    Notes
    -----
    1. Convert to grey on the 0..127 scale and smooth with the 5 x 5 filter of
       figure 3-1.
    2. On every ``row_step``-th row take the gradient along the row,
       ``g(x) = (S(x + 1) - S(x - 1)) / 2``.
    3. An edge point is a local maximum of ``|g|`` along the row (strictly above the
       left neighbour, at least the right one) with ``|g| >= threshold``, at least
       ``BORDER`` (5) pixels inside the left and right borders.
    4. Sub-pixel position: the vertex of the parabola through ``|g|`` at the peak and
       its two neighbours; the magnitude is the parabola's peak value.  With
       `edge_blur_px`, the position then moves towards the vertex of the same parabola
       on the lightly blurred image's gradient, less the dead zone (the magnitude
       stays the smoothed one's).
    5. Features: contrast sign ``sign(g)``, connectivity to the lines above and below
       (:func:`~robostereo.matcher.edge_features.connectivity`) and pattern type
       (:func:`~robostereo.matcher.edge_features.pattern_type`), the 5 x 5 mean grey
       level of the unsmoothed image, and the smoothed grey levels four pixels before
       and after the edge.

    References
    ----------
    .. [1] T.-Q. Kim, "A robot vision system for determining 3-D coordinates of
       object points", M.S. thesis, NJIT, 1989, sections 3.1-3.2, figure 3-1.

    Examples
    --------
    >>> img = np.zeros((9, 20), np.uint8); img[:, 10:] = 200
    >>> e = detect_edges(img)
    >>> len(e), e.x[:2].round(3).tolist(), e.sign[0].item(), e.pattern[[0, 4, 8]].tolist()
    (9, [9.5, 9.5], 1, [14, 5, 11])
    """
    require_positive("threshold", threshold)
    row_step = require_int("row_step", row_step, minimum=1)
    row_offset = require_int("row_offset", row_offset, minimum=0)
    check_edge_blur(edge_blur_px)
    g0 = to_grey(image, bit_depth=bit_depth) if grey is None else grey
    h, w = g0.shape
    if h < 5 or w < 5:
        raise InputError(f"image must be at least 5 x 5 pixels, got {w} x {h}")
    if not 0 <= row_offset < h:
        raise InputError(f"row_offset must be in 0..{h - 1}, got {row_offset}")
    thr = np.float32(min(float(threshold), float(np.finfo(np.float32).max)))  # no overflow
    n_lines = len(range(row_offset, h, row_step))
    usable = np.ones((1, 1), np.bool_)
    if valid is not None:
        vm = np.asarray(valid, dtype=bool)
        if vm.shape != (h, w):
            raise InputError(f"valid mask must have the image's shape {(h, w)}, got {vm.shape}")
        usable = usable_pixels(vm)
    k, j, r, x, sign, mag, before, after = _strip_points(
        g0, thr, int(row_offset), int(row_step), int(n_lines), bool(subpixel), usable,
        valid is not None)
    up, down, up_off, down_off, pattern, mean5 = peak_links(k, j, sign, int(n_lines), g0, r)
    weights = fine_weights(edge_blur_px) if subpixel else None
    if weights is not None:
        _place_finely(x, r, j, sign, g0, weights)
    return EdgeSet(
        line=k, row=r, x=x, column=j, sign=sign, magnitude=mag, pattern=pattern,
        up=up, down=down, up_offset=up_off, down_offset=down_off, mean_grey=mean5,
        grey_before=before,
        grey_after=after, row_step=int(row_step), row_offset=int(row_offset),
        n_lines=int(n_lines),
    )
