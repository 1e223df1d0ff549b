"""The edge points' features and their container (thesis 3.2).

Each edge point ``P[i, j](d, s, m, p, a)`` (thesis 3.2) carries its position ``d``
(here ``x``, pixels), contrast sign ``s``, gradient magnitude ``m``, connectivity
pattern type ``p`` (1..16) and 5 x 5 mean grey level ``a``; robostereo adds the
grey levels on either side of the edge, which tell edges apart better than one mean.
:class:`EdgeSet` holds them for the edge points of one image
(:func:`~robostereo.matcher.edges.detect_edges` finds them); :func:`connectivity`,
:func:`pattern_type` and :func:`pattern_difference` are the thesis's connectivity of an
edge point to the lines above and below, its pattern type and the difference of two
patterns.  The loops over the points are the numba kernels of
:mod:`robostereo.matcher.edge_kernels`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.matcher.edge_kernels import connect, patterns

__all__ = [
    "EdgeSet",
    "connectivity",
    "pattern_difference",
    "pattern_type",
]


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
