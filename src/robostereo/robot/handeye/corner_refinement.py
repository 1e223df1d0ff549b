"""Sub-pixel board corners by the gradients' orthogonality, weighted in board squares.

:func:`refine_board_corners` serves both boards: the plain chessboard's corners that
OpenCV's sector-based detector finds
(:func:`~robostereo.robot.handeye.boards.detect_chessboard`) and the ChArUco corners,
whose markers' edges it leaves out
(:func:`~robostereo.robot.handeye.charuco.refine_charuco_corners`).

References
----------
W. Foerstner, E. Guelch, "A fast operator for detection and precise location of
distinct points, corners and centres of circular features", ISPRS 1987 (the
orthogonality condition ``cornerSubPix`` solves).
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["refine_board_corners"]


def refine_board_corners(image: ArrayLike, board_xy_mm: ArrayLike, pixels: ArrayLike,
                         square_mm: float, *, light: ArrayLike | None = None,
                         marker_margin: float = 0.0, iterations: int = 6,
                         sigma_squares: float = 0.15, guard_px: float = 2.0
                         ) -> NDArray[np.float64]:
    """Sub-pixel corners of a board, each weighted in its own squares' frame.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Grey image.
    board_xy_mm : array_like, shape (K, 2)
        The corners on the board, mm (K >= 4, not all on one line).
    pixels : array_like, shape (K, 2)
        Their approximate positions in `image`.
    square_mm : float
        The board's square.
    light : array_like of bool, shape (K, 4), optional
        ChArUco: which of each corner's squares ``(-, -), (+, -), (-, +), (+, +)`` (in
        board x, y) are light and hold a marker; their pixels within `guard_px` of the
        marker are left out.
    marker_margin : float
        ChArUco: the margin between a light square's edge and its marker, in squares.
    iterations : int
        Fixed-point iterations.
    sigma_squares : float
        Gaussian weight's standard deviation, in squares.
    guard_px : float
        Pixels this close to a marker (its edges' blur and the gradient kernel) or to
        the square's far half are left out.

    Returns
    -------
    ndarray, shape (K, 2)
        Refined positions; a corner that would move more than 2 px keeps its start.

    Notes
    -----
    OpenCV's ``cornerSubPix`` finds the point ``c`` that every image gradient ``g_q``
    in a window is orthogonal to (``g_q . (q - c) = 0``: at an edge through the corner
    the gradient is normal to it, elsewhere it is zero).  Here the window and its
    weights follow the board as the view sees it:

    1. A homography from the board points to the pixels gives, at each corner, the
       local map from pixel offsets to board offsets (in squares).
    2. Each pixel ``q`` of a window of half a square round the corner gets the weight
       ``exp(-|a|^2 / 2 sigma^2)`` of its board offset ``a``, and 0 beyond half a
       square (or, with `light`, within `guard_px` of a marker).
    3. ``c = (sum w g g^T)^-1 sum w g g^T q`` (the least-squares solution of the
       orthogonality condition), over all corners at once; repeated.

    On the tests' chessboard renders (``tests/board_renders.py``, 14 views of an
    8 x 5 board, seeds 0-11) OpenCV's sector-based corners were off by 0.011-0.020 px
    in the median view as a whole (one offset shared by the view's corners, which no
    pose can take up in a hand-eye fit), these by 0.003-0.006 px.

    Examples
    --------
    A corner of four squares 20 px wide, started 0.6 px off:

    >>> img = np.full((80, 80), 200.0)
    >>> img[20:40, 20:40] = img[40:60, 40:60] = 40.0
    >>> board = [[0.0, 0.0], [20.0, 0.0], [0.0, 20.0], [20.0, 20.0]]
    >>> px = np.array([[19.5, 19.5], [39.5, 19.5], [19.5, 39.5], [39.5, 39.5]])
    >>> refine_board_corners(img, board, px + 0.6, 20.0)[3].round(2).tolist()
    [39.5, 39.5]
    """
    img = np.asarray(image, dtype=np.float32)
    c = np.asarray(pixels, dtype=np.float64).reshape(-1, 2).copy()
    obj = np.asarray(board_xy_mm, dtype=np.float64).reshape(-1, 2)
    sq = float(square_mm)
    gx = cv2.Sobel(img, cv2.CV_32F, 1, 0, ksize=3) / 8.0
    gy = cv2.Sobel(img, cv2.CV_32F, 0, 1, ksize=3) / 8.0
    H, _ = cv2.findHomography(obj, c)
    if H is None:
        return c
    # Jacobian d pixel / d board (mm) of the homography at each corner
    p = np.column_stack([obj, np.ones(len(obj))]) @ H.T
    s = p[:, 2:3]
    J = (H[None, :2, :2] * s[:, :, None] - p[:, :2, None] * H[None, 2:3, :2]) / s[:, :, None]**2
    det = np.linalg.det(J)
    if not np.all(np.abs(det) > 1e-12):
        return c
    T = np.linalg.inv(J) / sq                          # pixel offset -> squares, (K, 2, 2)
    sq_px = np.sqrt(np.abs(det)) * sq
    half = int(np.clip(np.round(0.5 * sq_px.min()), 3, 15))
    off = np.stack(np.meshgrid(np.arange(-half, half + 1), np.arange(-half, half + 1)),
                   axis=-1).reshape(-1, 2)
    guard = guard_px / sq_px[:, None]
    h, w = img.shape
    start = c.copy()
    lit = None if light is None else np.asarray(light, bool)        # (K, 4)
    for _ in range(iterations):
        q = np.round(c).astype(np.int64)[:, None, :] + off[None]        # (K, P, 2)
        qx, qy = np.clip(q[..., 0], 0, w - 1), np.clip(q[..., 1], 0, h - 1)
        inside = (q[..., 0] == qx) & (q[..., 1] == qy)
        gxq = gx[qy, qx].astype(np.float64)                             # (K, P)
        gyq = gy[qy, qx].astype(np.float64)
        dx, dy = q[..., 0] - c[:, 0:1], q[..., 1] - c[:, 1:2]
        ax = T[:, 0, 0, None] * dx + T[:, 0, 1, None] * dy              # board offsets,
        ay = T[:, 1, 0, None] * dx + T[:, 1, 1, None] * dy              # squares
        far = np.maximum(np.abs(ax), np.abs(ay)) > 0.5 - guard
        keep = inside & ~far
        if lit is not None:
            quad = (ax > 0).astype(np.int64) + 2 * (ay > 0)
            on_light = np.take_along_axis(lit, quad, axis=1)
            m = marker_margin
            keep &= ~(on_light & (np.abs(ax) > m - guard) & (np.abs(ay) > m - guard))
        wt = np.exp(-0.5 * (ax * ax + ay * ay) / sigma_squares**2) * keep
        # the normal equations sum w g g^T c = sum w g g^T q, per corner (2 x 2)
        wx, wy = wt * gxq, wt * gyq
        gq = gxq * q[..., 0] + gyq * q[..., 1]
        axx, axy, ayy = (wx * gxq).sum(1), (wx * gyq).sum(1), (wy * gyq).sum(1)
        bx, by = (wx * gq).sum(1), (wy * gq).sum(1)
        det = axx * ayy - axy * axy
        ok = det > 1e-9 * np.maximum(axx + ayy, 1e-12) ** 2
        safe = np.where(ok, det, 1.0)
        new = np.column_stack([(ayy * bx - axy * by) / safe, (axx * by - axy * bx) / safe])
        c = np.where((ok & (np.linalg.norm(new - start, axis=1) < 2.0))[:, None], new, c)
    return c
