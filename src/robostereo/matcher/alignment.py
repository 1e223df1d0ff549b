"""Are the rows epipolar lines?  The vertical offset between the views at matched places.

The matcher searches along rows (thesis 3.1): a rectified pair whose rows disagree by a
fraction of a pixel -- a pose or hand-eye slightly off before rectification, a rig whose
calibration has drifted -- is matched on windows that no longer line up.  It does not
fail loudly: on the developer scenes a 1 px offset takes the default point from 0.0-0.6 %
to 1.0-6.5 % false (`docs/guide/accuracy.md`).

The accepted matches of a first match give places that both views see.  The matches on
vertical edges cannot tell a vertical offset (the aperture problem), and a row offset
keeps precisely those, so :func:`row_offset` keeps the places whose neighbourhood has
grey-level structure in both directions (the structure tensor's smaller eigenvalue, as
Shi and Tomasi choose features [1]_) and tracks them from the left view into the right
with Lucas-Kanade [2]_, starting at the matched disparity.  The median vertical motion is
the rows' offset.

References
----------
.. [1] J. Shi and C. Tomasi, "Good features to track", CVPR 1994.
.. [2] B. D. Lucas and T. Kanade, "An iterative image registration technique with an
   application to stereo vision", IJCAI 1981 (``cv2.calcOpticalFlowPyrLK``).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import ArrayLike

from robostereo.errors import InputError, require_finite, require_int
from robostereo.matcher.alignment_kernels import track_kernel

__all__ = ["MIN_TRACKED", "ROW_TOLERANCE_PX", "RowOffset", "moved_rows", "row_offset"]

#: rows of the two views that disagree by more than this (pixels) are reported and
#: corrected: 0.5 px already takes reindeer's default point to 2.8 % false, while the
#: estimate on the developer scenes as they are is -0.15..+0.18 px
ROW_TOLERANCE_PX: float = 0.4
#: least number of places tracked for an estimate
MIN_TRACKED: int = 30
#: places read (evenly spaced over the accepted matches), of which the better-structured
#: half is tracked
_MAX_PLACES = 120
#: Lucas-Kanade window (pixels)
_WINDOW = 11


@dataclass(frozen=True)
class RowOffset:
    """How far the right view's rows are from the left's, at matched places.

    Attributes
    ----------
    offset_px : float
        Median vertical motion from the left view to the right (pixels, down
        positive): the right view shows at row ``y + offset_px`` what the left shows at
        row ``y``.
    spread_px : float
        Half the interquartile range of the places' vertical motions.
    n_places : int
        Places tracked.

    Examples
    --------
    >>> RowOffset(0.9, 0.1, 120).misaligned, RowOffset(0.1, 0.1, 120).misaligned
    (True, False)
    >>> RowOffset(0.5, 1.5, 57).misaligned  # three standard errors are 1.1 px
    False
    """

    offset_px: float
    spread_px: float
    n_places: int

    def __post_init__(self) -> None:
        require_finite("offset_px", self.offset_px)
        require_finite("spread_px", self.spread_px)
        if self.spread_px < 0:
            raise InputError(f"spread_px must be >= 0, got {self.spread_px}")
        require_int("n_places", self.n_places, minimum=0)

    @property
    def standard_error_px(self) -> float:
        """The median's standard error: ``1.2533 sigma / sqrt(n)``, ``sigma`` from the
        interquartile range (``1.4826 spread_px``), as for normal scatter."""
        return float(1.2533 * 1.4826 * self.spread_px / np.sqrt(max(self.n_places, 1)))

    @property
    def misaligned(self) -> bool:
        """At least :data:`MIN_TRACKED` places, the rows more than
        :data:`ROW_TOLERANCE_PX` apart, and the offset more than three standard errors
        from 0 (a scene with few places that show vertical structure, say an untextured
        block, gives a wide scatter and no verdict)."""
        return bool(self.n_places >= MIN_TRACKED and abs(self.offset_px) > ROW_TOLERANCE_PX
                    and abs(self.offset_px) > 3.0 * self.standard_error_px)


def row_offset(left: ArrayLike, right: ArrayLike, rows: ArrayLike, x: ArrayLike,
               disparity: ArrayLike) -> RowOffset | None:
    """The vertical offset between the two views at matched places.

    Parameters
    ----------
    left, right : array_like, shape (H, W) or (H, W, 3|4)
        The images as given to :func:`~robostereo.matcher.pipeline.match_stereo`.
    rows, x, disparity : array_like, shape (N,)
        Matches (the accepted ones of a first match): left ``(x, row)`` sees right
        ``(x - disparity, row)``.

    Returns
    -------
    RowOffset or None
        None where fewer than :data:`MIN_TRACKED` places could be tracked.

    Notes
    -----
    1. Up to 120 of the matches, evenly spaced, on the images' grey levels (a colour image's
       green channel); at each, the smaller eigenvalue of the grey levels' structure
       tensor over an 11 x 11 window (central differences).
    2. Each place is tracked into the right view by Lucas-Kanade over that window
       (:func:`~robostereo.matcher.alignment_kernels.track_kernel`), starting at
       ``(x - disparity, row)``.
    3. The better-structured half of the places whose track converged within 2 px of
       its match gives the median vertical motion and its spread.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> left = cv2.GaussianBlur(rng.integers(0, 256, (120, 200)).astype(np.uint8), (5, 5), 1)
    >>> right = np.roll(np.roll(left, -9, axis=1), 1, axis=0)  # 9 px disparity, 1 px lower
    >>> y, x = np.mgrid[20:100:8, 30:170:8]
    >>> r = row_offset(left, right, y.ravel(), x.ravel().astype(float), np.full(y.size, 9.0))
    >>> round(r.offset_px, 1), r.misaligned
    (1.0, True)
    """
    a, b = np.asarray(left), np.asarray(right)
    y = np.asarray(rows, dtype=np.intp).ravel()
    xs = np.asarray(x, dtype=float).ravel()
    d = np.asarray(disparity, dtype=float).ravel()
    if not y.shape == xs.shape == d.shape:
        raise InputError(f"rows, x and disparity must be of one length, got {y.size}, "
                         f"{xs.size} and {d.size}")
    if y.size > _MAX_PLACES:  # evenly spaced
        pick = np.arange(_MAX_PLACES) * (y.size - 1) // (_MAX_PLACES - 1)
        y, xs, d = y[pick], xs[pick], d[pick]
    keep = np.isfinite(xs) & np.isfinite(d)
    y, xs, d = y[keep], xs[keep], d[keep]
    if y.size < MIN_TRACKED:
        return None
    # the grey levels as given (the green channel of a colour image: the rows' offset is
    # the same in every channel)
    ga = a[..., 1] if a.ndim == 3 else a
    gb = b[..., 1] if b.ndim == 3 else b
    xi = np.rint(xs).astype(np.int64)
    # -- 1.-2. structure and Lucas-Kanade at every place; the better-structured half kept
    _, dx, dy, ok = track_kernel(ga, gb, xi, y.astype(np.int64), d, _WINDOW // 2, 10)
    best = ok & (np.abs(dx + d) <= 2.0)
    dy = dy[best]
    if dy.size < MIN_TRACKED:
        return None
    # -- 3. the median and its spread (the quartiles as the nearest order statistics)
    dy = np.sort(dy)
    n = dy.size
    med = 0.5 * (dy[(n - 1) // 2] + dy[n // 2])
    return RowOffset(float(med), float(0.5 * (dy[(3 * n) // 4] - dy[n // 4])), int(n))


def moved_rows(image: ArrayLike, offset_px: float) -> np.ndarray:
    """``image`` ``(H, W)`` or ``(H, W, C)`` moved up by ``offset_px`` rows (linear
    interpolation, the border row repeated): what the right view would show were its
    rows the left's.  Same dtype.

    >>> moved_rows(np.arange(12, dtype=np.float32).reshape(4, 3), 1.0)[:, 0].tolist()
    [3.0, 6.0, 9.0, 9.0]
    """
    im = np.asarray(image)
    h, w = im.shape[:2]
    shift = np.float32([[1.0, 0.0, 0.0], [0.0, 1.0, float(offset_px)]])
    return cv2.warpAffine(im, shift, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                          borderMode=cv2.BORDER_REPLICATE)
