"""Grey levels on the thesis's scale and its smoothing filter (thesis 3.1).

Images come in as ``(H, W)`` (or ``(H, W, 3|4)`` colour) arrays of any integer bit
depth; :func:`to_grey` converts them to grey and scales them to the thesis's 0..127 grey
scale, so that the thesis's gradient threshold of 8.0 means the same contrast at any bit
depth.  :func:`smooth` applies the thesis's 5 x 5 averaging-Gaussian filter
(:data:`SEED_KERNEL`, figure 3-1) on which the edge points are found
(:mod:`robostereo.matcher.edges`).

Colour images of the common integer dtypes are converted by the numba kernel
:func:`~robostereo.matcher.edge_kernels.rgb_to_grey` where it gives this machine's
OpenCV values, else by OpenCV a block of rows at a time.
"""

from __future__ import annotations

from functools import cache

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_int
from robostereo.matcher.edge_kernels import rgb_to_grey, scaled_grey

__all__ = [
    "SEED_KERNEL",
    "smooth",
    "to_grey",
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

#: pixels of a colour image converted at a time (a float buffer of 96 KiB, not a float
#: copy of the whole image: the 3 MiB buffers of two images converted side by side were
#: a third of the matcher's peak memory on a colour scene, and a 384 KiB block still a
#: tenth of it on tsukuba; a few dozen calls an image cost about 0.02 ms more; the grey
#: levels do not depend on the block)
_GREY_BLOCK_PIXELS = 1 << 13


#: the integer dtypes whose every value a float32 holds exactly
_EXACT_INTEGERS = (np.uint8, np.int8, np.uint16, np.int16)
#: lanes of OpenCV's float32 vector loops that :func:`rgb_to_grey` reproduces (and the
#: edge points' fine placement, :func:`~robostereo.matcher.edge_kernels.blur_column`)
OPENCV_LANES = 8


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
        n = w // OPENCV_LANES * OPENCV_LANES  # the columns of OpenCV's vector loop
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
