"""Numba kernels of the window matcher's pixels: census [1]_ and Sobel, of rows and images.

The census (a bit per neighbour, set where it is darker than the centre) and the
horizontal Sobel derivative that the pixel costs of
:func:`robostereo.matcher.window_kernels.stream_rows` compare: of one row, made as the
pass reaches it (:func:`pixel_row`), and of whole images for
:func:`robostereo.matcher.window_costs.census_transform` and
:func:`robostereo.matcher.window_costs.sobel_x`.  Only numba functions and the
constants they compile in.

References
----------
.. [1] R. Zabih and J. Woodfill, "Non-parametric local transforms for computing
   visual correspondence", ECCV 1994.
"""

from __future__ import annotations

import numpy as np

from robostereo.matcher.jit import kernel

__all__ = [
    "CENSUS_SIZE",
    "census_7x5",
    "census_padded",
    "census_row",
    "pixel_row",
    "sobel",
    "sobel_row",
]

#: census neighbourhood (width, height): 7 x 5 minus the centre = 34 bits
CENSUS_SIZE = (7, 5)


@kernel(fastmath=True, nogil=True)
def _census_bits(acc, nbr, centre):  # type: ignore[no-untyped-def]
    for x in range(acc.shape[0]):
        acc[x] = (acc[x] << np.uint64(1)) | np.uint64(nbr[x] < centre[x])


@kernel(nogil=True)
def census_padded(padded, h, w, hw, hh):  # type: ignore[no-untyped-def]
    out = np.zeros((h, w), np.uint64)
    for y in range(h):
        centre = padded[y + hh, hw:hw + w]
        for dy in range(-hh, hh + 1):
            for dx in range(-hw, hw + 1):
                if dy != 0 or dx != 0:
                    _census_bits(out[y], padded[y + hh + dy, hw + dx:hw + dx + w], centre)
    return out


@kernel(fastmath=True, nogil=True, inline="always")
def _flag(neighbour, centre):  # type: ignore[no-untyped-def]
    """``neighbour < centre`` as a 32-bit 0 or 1."""
    return np.uint32(neighbour < centre)


@kernel(fastmath=True, nogil=True)
def census_row(g, y, out, buf):  # type: ignore[no-untyped-def]
    """Row ``y`` of the default 7 x 5 census (Zabih and Woodfill, see the module) of
    ``g`` into ``out`` (W,), the borders replicated.  ``buf`` (5, W + 6) float32
    receives the five rows padded.  Bits in raster order of the neighbourhood (the
    first two in the high word); each pixel's 34 comparisons stay in registers, the
    pixels in vector lanes as wide as the floats.

    The two words are made into 32-bit rows of their own and joined in a second loop:
    made and joined in one loop, the compiler carried every comparison in 64-bit lanes,
    half as many pixels a vector (about twice the time).  The low word is made as five
    rows' words, each from its own comparisons, shifted into place at the end: one chain
    of 32 shifts and ors, each waiting for the one before, took a third longer."""
    h, w = g.shape
    for dy in range(5):
        src = g[min(max(y + dy - 2, 0), h - 1)]
        b = buf[dy]
        b[3:w + 3] = src
        for k in range(3):
            b[k] = src[0]
            b[w + 3 + k] = src[w - 1]
    r0, r1, r2, r3, r4 = buf[0], buf[1], buf[2], buf[3], buf[4]
    words = np.empty((2, w), np.uint32)  # the high and the low word of each pixel
    high, low = words[0], words[1]
    for x in range(w):
        c = r2[x + 3]
        high[x] = (_flag(r0[x], c) << np.uint32(1)) | _flag(r0[x + 1], c)
        # the 32 bits of the low word as five rows' words, each built on its own and
        # placed after: short chains of dependent operations, not one of 64
        top = np.uint32(0)  # r0[x + 2 .. x + 6]: bits 31 .. 27
        for dx in range(2, 7):
            top |= _flag(r0[x + dx], c) << np.uint32(6 - dx)
        second = np.uint32(0)  # r1: bits 26 .. 20
        for dx in range(7):
            second |= _flag(r1[x + dx], c) << np.uint32(6 - dx)
        middle = np.uint32(0)  # r2 without the centre: bits 19 .. 14
        for dx in range(3):
            middle |= _flag(r2[x + dx], c) << np.uint32(5 - dx)
        for dx in range(4, 7):
            middle |= _flag(r2[x + dx], c) << np.uint32(6 - dx)
        fourth = np.uint32(0)  # r3: bits 13 .. 7
        for dx in range(7):
            fourth |= _flag(r3[x + dx], c) << np.uint32(6 - dx)
        last = np.uint32(0)  # r4: bits 6 .. 0
        for dx in range(7):
            last |= _flag(r4[x + dx], c) << np.uint32(6 - dx)
        low[x] = ((top << np.uint32(27)) | (second << np.uint32(20)) | (middle << np.uint32(14))
                  | (fourth << np.uint32(7)) | last)
    for x in range(w):
        out[x] = (np.uint64(high[x]) << np.uint64(32)) | np.uint64(low[x])


@kernel(nogil=True)
def census_7x5(g):  # type: ignore[no-untyped-def]
    h, w = g.shape
    out = np.empty((h, w), np.uint64)
    buf = np.empty((5, w + 6), np.float32)
    for y in range(h):
        census_row(g, y, out[y], buf)
    return out


@kernel(fastmath=True, nogil=True)
def sobel_row(g, y, out):  # type: ignore[no-untyped-def]
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


@kernel(nogil=True)
def sobel(g):  # type: ignore[no-untyped-def]
    h, w = g.shape
    out = np.empty((h, w), np.int16)
    for y in range(h):
        sobel_row(g, y, out[y])
    return out


@kernel(nogil=True)
def pixel_row(grey, y, valid, check, census_bad, sobel_bad, census, sobel_out,
              padded_rows):  # type: ignore[no-untyped-def]
    """Census and Sobel of row ``y``; pixels outside ``valid`` (where ``check``) get
    the values that make every pair with them cost nearly the most."""
    census_row(grey, y, census, padded_rows)
    sobel_row(grey, y, sobel_out)
    if check:
        valid_row = valid[y]
        for x in range(census.shape[0]):
            if not valid_row[x]:
                census[x] = census_bad
                sobel_out[x] = sobel_bad
