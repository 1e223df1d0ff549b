"""Smoothing, edge points along epipolar lines and their features (thesis 3.1-3.2).

Images come in as ``(H, W)`` (or ``(H, W, 3|4)`` colour) arrays of any integer bit
depth; they are converted to grey and scaled to the thesis's 0..127 grey scale so that
the thesis's gradient threshold of 8.0 means the same contrast at any bit depth.  The
rows of a rectified image are its epipolar lines; edge points are the peaks of the
1-D intensity gradient along the rows of the smoothed image, located to sub-pixel
precision.

Each edge point ``P[i, j](d, s, m, p, a)`` (thesis 3.2) carries its position ``d``
(here ``x``, pixels), contrast sign ``s``, gradient magnitude ``m``, connectivity
pattern type ``p`` (1..16) and 5 x 5 mean grey level ``a``; robostereo adds the
grey levels on either side of the edge, which tell edges apart better than one mean.

The loops over the rows and the edge points (gradient peaks in one pass, features,
connectivity) are the numba kernels of :mod:`robostereo.matcher.edge_kernels`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache, lru_cache

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_int, require_positive
from robostereo.matcher.edge_kernels import (
    FINE_DEAD_ZONE_PX,
    SIDE_OFFSET,
    blur_column,
    connect,
    fine_positions,
    fine_positions_grey,
    patterns,
    peak_links,
    rgb_to_grey,
    scaled_grey,
    strip_points,
)

__all__ = [
    "SEED_KERNEL",
    "EdgeSet",
    "check_edge_blur",
    "connectivity",
    "detect_edges",
    "fine_weights",
    "pattern_difference",
    "pattern_type",
    "smooth",
    "to_grey",
    "usable_pixels",
]

_SEED_WEIGHTS = np.array(
    [
        [2, 2, 2, 2, 2],
        [2, 10, 10, 10, 2],
        [2, 10, 15, 10, 2],
        [2, 10, 10, 10, 2],
        [2, 2, 2, 2, 2],
    ],
    dtype=float,
)
SEED_KERNEL: NDArray[np.float64] = _SEED_WEIGHTS / _SEED_WEIGHTS.sum()
"""The thesis's 5 x 5 averaging-Gaussian filter (figure 3-1), normalised by its sum.

The weights 2 (16 border cells), 10 (8 inner cells) and 15 (centre) add up to 127;
seed-notes says 126, an arithmetic slip: dividing by the true sum keeps a constant
image constant."""

#: grey levels of the thesis's vision system: 0..127 (7 bit)
SEED_GREY_LEVELS = 128

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


#: pixels of a colour image converted at a time (a float buffer of 96 KiB, not a float
#: copy of the whole image: the 3 MiB buffers of two images converted side by side were
#: a third of the matcher's peak memory on a colour scene, and a 384 KiB block still a
#: tenth of it on tsukuba; a few dozen calls an image cost about 0.02 ms more; the grey
#: levels do not depend on the block)
_GREY_BLOCK_PIXELS = 1 << 13


#: the integer dtypes whose every value a float32 holds exactly
_EXACT_INTEGERS = (np.uint8, np.int8, np.uint16, np.int16)
#: lanes of OpenCV's float32 vector loops that :func:`rgb_to_grey` reproduces
_LANES = 8


def _colour_to_grey(rgb: np.ndarray, kernel: bool | None = None) -> NDArray[np.float32]:
    """``cv2.cvtColor(rgb as float32, RGB2GRAY)``.  With `kernel` (by default for
    C-contiguous RGB images of the integer dtypes a float32 holds exactly, where
    :func:`_kernel_grey_agrees`) :func:`rgb_to_grey` reads the integers as they are
    (one pass, about twice as fast) and OpenCV does the rows' tails; else OpenCV
    converts a float32 copy of a block of rows at a time."""
    if rgb.dtype == np.float32:
        return cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2GRAY)
    if kernel is None:
        kernel = (rgb.dtype in _EXACT_INTEGERS and rgb.shape[2] == 3
                  and rgb.flags.c_contiguous and _kernel_grey_agrees())
    h, w = rgb.shape[:2]
    grey = np.empty((h, w), np.float32)
    if kernel:
        n = w // _LANES * _LANES  # the columns of OpenCV's vector loop
        rgb_to_grey(rgb.reshape(h, 3 * w), grey, n)
        if n < w:
            grey[:, n:] = cv2.cvtColor(rgb[:, n:].astype(np.float32), cv2.COLOR_RGB2GRAY)
        return grey
    rows = max(1, _GREY_BLOCK_PIXELS // max(w, 1))
    buf = np.empty((min(h, rows), w, 3), np.float32)
    with np.errstate(over="ignore"):  # beyond float32: inf, refused by the caller
        for y0 in range(0, h, rows):
            y1 = min(h, y0 + rows)
            part = buf[:y1 - y0]
            np.copyto(part, rgb[y0:y1], casting="unsafe")
            cv2.cvtColor(part, cv2.COLOR_RGB2GRAY, dst=grey[y0:y1])
    return grey


@cache
def _kernel_grey_agrees() -> bool:
    """Whether :func:`rgb_to_grey` gives this machine's OpenCV values (OpenCV's loops
    follow the processor) on random colours, 61 columns: a vector loop of 4, 8, 16 or
    32 lanes would end at a different column."""
    probe = np.random.default_rng(0).integers(0, 256, (4, 61, 3), np.uint8)
    return bool(np.array_equal(_colour_to_grey(probe, True).view(np.uint32),
                               _colour_to_grey(probe, False).view(np.uint32)))


def to_grey(image: ArrayLike, *, bit_depth: int | None = None, name: str = "image") -> NDArray[
    np.float32
]:
    """Convert an image to grey on the thesis's 0..127 scale.

    Parameters
    ----------
    image : array_like, shape (H, W) or (H, W, 3) or (H, W, 4)
        Grey or colour (RGB or RGBA) image, integer or float.
    bit_depth : int, optional
        Bits per grey level of the input: its grey levels are on the scale
        ``0 .. 2**bit_depth - 1``, integer or float.  Default: 8 for ``uint8``, 16 for
        ``uint16``; a **float image without bit_depth has full scale 1.0** (grey
        levels 0..1, as most image libraries write floats) and values outside 0..1
        are refused.  The simulated camera's 7-bit images use ``bit_depth=7``.
    name : str
        Name used in error messages.

    Returns
    -------
    ndarray of float32, shape (H, W)
        Grey levels scaled by ``127 / (2**bit_depth - 1)`` (by 127 for floats of full
        scale 1.0): full scale at any bit depth becomes the thesis's 127.

    Raises
    ------
    InputError
        A shape other than (H, W) or (H, W, 3|4), an empty image, a dtype that is not
        real integer or float (bool, complex, object), NaN or infinite grey levels,
        other integer dtypes without `bit_depth`, a float image outside 0..1 without
        `bit_depth`, a `bit_depth` outside 1..32.

    Examples
    --------
    >>> to_grey(np.array([[0, 255]], dtype=np.uint8))
    array([[  0., 127.]], dtype=float32)
    >>> to_grey(np.array([[0, 65535]], dtype=np.uint16))
    array([[  0., 127.]], dtype=float32)
    >>> to_grey(np.array([[0.0, 1.0]])), to_grey(np.array([[0.0, 255.0]]), bit_depth=8)
    (array([[  0., 127.]], dtype=float32), array([[  0., 127.]], dtype=float32))
    """
    arr = np.asarray(image)
    if arr.dtype.kind not in "uif":
        raise InputError(
            f"{name} must hold real grey levels (an integer or float dtype), got {arr.dtype}"
        )
    if bit_depth is not None:
        bit_depth = require_int("bit_depth", bit_depth, minimum=1)
    if arr.ndim == 3 and arr.shape[2] in (3, 4):
        if arr.shape[2] == 4:
            arr = arr[:, :, :3]
        grey = _colour_to_grey(arr)
    elif arr.ndim == 2:
        grey = None  # integers a float32 holds exactly: converted and scaled below at once
        if arr.dtype not in _EXACT_INTEGERS:
            with np.errstate(over="ignore"):
                grey = arr.astype(np.float32)
    else:
        raise InputError(
            f"{name} must be a grey (H, W) or colour (H, W, 3|4) image, got shape {arr.shape}"
        )
    if arr.shape[0] * arr.shape[1] == 0:
        raise InputError(f"{name} is empty (shape {arr.shape})")
    unit_float = bit_depth is None and arr.dtype.kind == "f"
    if bit_depth is None:
        if arr.dtype == np.uint8 or arr.dtype == np.int8:
            bit_depth = 8
        elif arr.dtype in (np.uint16, np.int16):
            bit_depth = 16
        elif np.issubdtype(arr.dtype, np.integer):
            raise InputError(f"{name}: bit_depth must be given for {arr.dtype} images")
        else:
            bit_depth = 7
    if not 1 <= bit_depth <= 32:
        raise InputError(f"bit_depth must be in 1..32, got {bit_depth}")
    scale = np.float32(1.0 if bit_depth == 7 else (SEED_GREY_LEVELS - 1) / (2.0**bit_depth - 1))
    if grey is None:  # one pass: the values of astype(float32), then *= scale
        scaled_grey(arr, scale, grey := np.empty(arr.shape, np.float32))
        return grey
    if arr.dtype.kind == "f" and not np.isfinite(grey).all():  # integers always are
        raise InputError(f"{name} contains NaN or infinite grey levels")
    if unit_float:
        lo, hi = float(arr.min()), float(arr.max())
        if lo < 0.0 or hi > 1.0:
            raise InputError(
                f"{name}: a float image without bit_depth must have grey levels in 0..1 "
                f"(full scale 1.0), got {lo:g} .. {hi:g}; pass bit_depth for 0..2**b-1 floats"
            )
        grey *= np.float32(SEED_GREY_LEVELS - 1)
    elif bit_depth != 7:
        grey *= scale
    return grey


def smooth(grey: NDArray[np.floating]) -> NDArray[np.float32]:
    """Smooth with the thesis's 5 x 5 averaging-Gaussian filter (figure 3-1).

    Parameters
    ----------
    grey : ndarray, shape (H, W)

    Returns
    -------
    ndarray of float32, shape (H, W)
        The filtered image; borders are reflected (``BORDER_REFLECT_101``).

    Examples
    --------
    >>> img = np.zeros((9, 9), np.float32); img[4, 4] = 127.0
    >>> smooth(img)[4, 4], smooth(img)[2, 2]
    (np.float32(15.0), np.float32(2.0))
    """
    return cv2.filter2D(
        np.asarray(grey, dtype=np.float32), -1, SEED_KERNEL, borderType=cv2.BORDER_REFLECT_101
    )


@dataclass(frozen=True)
class EdgeSet:
    """Edge points of one image with their features (thesis 3.2, ``P[i, j](d, s, m, p, a)``).

    All arrays have shape ``(N,)`` and are sorted by ``(line, x)``.  Indices are int32
    and the features computed in float32 are kept in float32 (the position and the
    mean grey level, summed in float64, stay float64): 52 bytes a point, 48 where every
    row is a line (``row_step`` 1, ``row_offset`` 0: ``row`` is then the array ``line``
    itself, so writing into one writes into both).

    Attributes
    ----------
    line : ndarray of int32
        Index ``i`` of the epipolar line (0, 1, ... over the sampled rows).
    row : ndarray of int32
        Image row of the line, ``line * row_step + row_offset``.
    x : ndarray of float64
        Sub-pixel position along the row (pixels; the thesis's distance ``d``).
    column : ndarray of int32
        Pixel column of the gradient peak.
    sign : ndarray of int8
        Contrast sign: +1 where the grey level rises along the row, -1 where it falls.
    magnitude : ndarray of float32
        Gradient magnitude at the peak (grey levels per pixel, 0..127 scale).
    pattern : ndarray of int8
        Connectivity pattern type 1..16 (see :func:`pattern_type`).
    up, down : ndarray of int32
        Index of the connected edge point on the line above / below, -1 if none.
    up_offset, down_offset : ndarray of int8
        Column offset -1, 0 or +1 of that neighbour; 0 where there is none.
    mean_grey : ndarray of float64
        Mean grey level of the 5 x 5 window centred on the edge pixel.
    grey_before, grey_after : ndarray of float32
        Smoothed grey level ``SIDE_OFFSET`` pixels before and after the edge along the row.
    row_step, row_offset : int
        Sampling of the epipolar lines: rows ``row_offset, row_offset + row_step, ...``.
    n_lines : int
        Number of sampled lines.
    """

    line: NDArray[np.int32]
    row: NDArray[np.int32]
    x: NDArray[np.float64]
    column: NDArray[np.int32]
    sign: NDArray[np.int8]
    magnitude: NDArray[np.float32]
    pattern: NDArray[np.int8]
    up: NDArray[np.int32]
    down: NDArray[np.int32]
    up_offset: NDArray[np.int8]
    down_offset: NDArray[np.int8]
    mean_grey: NDArray[np.float64]
    grey_before: NDArray[np.float32]
    grey_after: NDArray[np.float32]
    row_step: int = 1
    row_offset: int = 0
    n_lines: int = 0

    def __len__(self) -> int:
        return int(self.x.shape[0])

    @property
    def points(self) -> NDArray[np.float64]:
        """Edge positions as ``(N, 2)`` image points ``(x, y)``."""
        return np.column_stack([self.x, self.row.astype(float)])


def pattern_type(up_offset: ArrayLike, down_offset: ArrayLike, has_up: ArrayLike,
                 has_down: ArrayLike) -> NDArray[np.int8]:
    """Connectivity pattern type 1..16 (thesis 3.2, figure 3-2c as read in seed-notes).

    Types 1-9: connected above and below, ``1 + 3 (u + 1) + (v + 1)`` for offsets
    ``u, v`` in {-1, 0, 1}; 10-12: above only, ``11 + u``; 13-15: below only,
    ``14 + v``; 16: connected to neither.

    Examples
    --------
    >>> pattern_type([0, -1, 1, 0], [0, 0, 0, 1], [True, True, True, False],
    ...              [True, True, False, False]).tolist()
    [5, 2, 12, 16]
    """
    u, v, hu, hd = np.broadcast_arrays(np.asarray(up_offset, dtype=np.int64),
                                       np.asarray(down_offset, dtype=np.int64),
                                       np.asarray(has_up, dtype=bool),
                                       np.asarray(has_down, dtype=bool))
    out = patterns(u.ravel(), v.ravel(), hu.ravel(), hd.ravel())
    return out.reshape(u.shape)


def pattern_difference(
    up_l: ArrayLike, down_l: ArrayLike, has_up_l: ArrayLike, has_down_l: ArrayLike,
    up_r: ArrayLike, down_r: ArrayLike, has_up_r: ArrayLike, has_down_r: ArrayLike,
) -> NDArray[np.int8]:
    """Difference 0..6 of two connectivity patterns (thesis 3.2 (b)).

    The upper neighbours are compared first: 0 when both are absent or at the same
    offset, 1 or 2 when both are present with offsets one or two apart, 3 when one
    is connected and the other is not; then the lower ones; the two are added.

    Examples
    --------
    >>> pattern_difference(0, 0, True, True, 0, 0, True, True).item()
    0
    >>> pattern_difference(-1, 0, True, True, 1, 0, True, False).item()
    5
    """
    def one(a, b, ha, hb):
        a = np.asarray(a, np.int16)
        b = np.asarray(b, np.int16)
        ha = np.asarray(ha, bool)
        hb = np.asarray(hb, bool)
        return np.where(ha & hb, np.abs(a - b), np.where(ha == hb, 0, 3))

    return (one(up_l, up_r, has_up_l, has_up_r) + one(down_l, down_r, has_down_l, has_down_r)
            ).astype(np.int8)


def connectivity(
    line: NDArray[np.intp], column: NDArray[np.intp], sign: NDArray[np.int8], n_lines: int,
    width: int,
) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.int8], NDArray[np.int8]]:
    """Connect each edge point to edge points on the lines above and below.

    Two edge points on neighbouring lines are connected when their pixel columns
    differ by at most one and their contrast signs agree (thesis 3.2 (b)).  Where
    several qualify, the one straight above (below) is preferred, then the one at
    offset -1, then +1.

    Returns
    -------
    up, down : ndarray of int, shape (N,)
        Index of the connected edge point above / below, -1 if none.
    up_offset, down_offset : ndarray of int8, shape (N,)
        Its column offset -1, 0 or +1 (0 where none).
    """
    up, down, up_off, down_off = connect(
        np.ascontiguousarray(line, dtype=np.int64), np.ascontiguousarray(column, dtype=np.int64),
        np.ascontiguousarray(sign, dtype=np.int8), int(n_lines), int(width))
    return up.astype(np.intp), down.astype(np.intp), up_off, down_off


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
    (see :func:`_kernel_grey_agrees`; a size OpenCV filters another way fails too)."""
    wt = np.frombuffer(weights, np.float32)
    if wt.size < 3 or not np.array_equal(wt, wt[::-1]):
        return False
    probe = np.random.default_rng(2).uniform(0, 127, (2 * wt.size + 3, 61)).astype(np.float32)
    want = cv2.sepFilter2D(probe, -1, _ONE, wt, borderType=cv2.BORDER_REFLECT_101)
    got = np.empty_like(probe)
    for y in range(probe.shape[0]):
        blur_column(probe, y, wt, 61 // _LANES * _LANES, got[y])
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
                            grey.shape[1] // _LANES * _LANES)
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
        Bit depth of the input grey levels (see :func:`to_grey`).
    subpixel : bool
        Locate edges to sub-pixel precision (default) or at whole pixels, as the thesis.
    grey : ndarray, optional
        The image already converted by :func:`to_grey` (saves the conversion).
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
        An image :func:`to_grey` refuses or smaller than 5 x 5 pixels, a threshold that
        is not a finite number > 0, a `row_step` or `row_offset` that is not an integer
        (>= 1, in ``0..H-1``), a `valid` mask of another shape, an `edge_blur_px`
        that is not None or in 0..10.

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
       (:func:`connectivity`) and pattern type (:func:`pattern_type`), the 5 x 5 mean
       grey level of the unsmoothed image, and the smoothed grey levels four pixels
       before and after the edge.

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
