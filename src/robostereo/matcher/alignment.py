"""Are the rows epipolar lines?  The vertical offset between the views at matched places.

The matcher searches along rows (thesis 3.1): a rectified pair whose rows disagree by a
fraction of a pixel -- a pose or hand-eye slightly off before rectification, a rig whose
calibration has drifted -- is matched on windows that no longer line up.  It does not
fail loudly: on the developer scenes a 1 px offset takes the default point from 0.0-0.6 %
to 1.0-6.5 % false (`docs/guide/results.md`).

The accepted matches of a first match give places that both views see.  The matches on
vertical edges cannot tell a vertical offset (the aperture problem), and a row offset
keeps precisely those, so :func:`row_offset` keeps the places whose neighbourhood has
grey-level structure in both directions (the structure tensor's smaller eigenvalue, as
Shi and Tomasi choose features [1]_) and tracks them from the left view into the right
with Lucas-Kanade [2]_, starting at the matched disparity.  The median vertical motion is
the rows' offset.  Rows may also disagree by an amount that changes across the image --
a small rotation between the views about the optical axis tilts them, a focal length
off in one view stretches them -- so the motions are also fitted by a plane in the
image (an offset at the centre, a tilt to the side edges, a stretch to the top and
bottom), kept where its slopes are beyond their noise.

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

from robostereo.errors import (
    require_finite,
    require_int,
    require_nonnegative,
    require_one_length,
)
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
#: whole rows searched either side before Lucas-Kanade starts (its own reach is a pixel
#: or two; a hand-eye 2 degrees off about the optical axis puts rows 2-3 px apart)
_ROW_SEARCH = 5


@dataclass(frozen=True)
class RowOffset:
    """How far the right view's rows are from the left's, at matched places.

    The right view shows at row ``y + offset_px + tilt_px u + stretch_px v`` what the
    left shows at row ``y``, with ``u = (x - cx) / cx`` and ``v = (y - cy) / cy`` (-1 at
    the left and top edges, 1 at the right and bottom ones; ``cx, cy`` the image's
    centre).

    Attributes
    ----------
    offset_px : float
        Vertical motion from the left view to the right (pixels, down positive): the
        median of the places' motions, or the plane's value at the image's centre where
        it tilts or stretches.
    spread_px : float
        Half the interquartile range of the places' vertical motions (about the plane,
        where it tilts or stretches).
    n_places : int
        Places tracked.
    tilt_px, stretch_px : float
        How much more the offset is at the right edge and at the bottom than at the
        centre (as much less at the left edge and the top); 0 unless the places show it
        beyond three standard errors.

    Examples
    --------
    >>> RowOffset(0.9, 0.1, 120).misaligned, RowOffset(0.1, 0.1, 120).misaligned
    (True, False)
    >>> RowOffset(0.5, 1.5, 57).misaligned  # three standard errors are 1.1 px
    False
    >>> r = RowOffset(0.0, 0.1, 60, tilt_px=1.2)  # a rotation: 0 at the centre
    >>> round(r.rms_px, 2), r.misaligned
    (0.69, True)
    """

    offset_px: float
    spread_px: float
    n_places: int
    tilt_px: float = 0.0
    stretch_px: float = 0.0

    def __post_init__(self) -> None:
        require_finite("offset_px", self.offset_px)
        require_nonnegative("spread_px", self.spread_px)
        require_finite("tilt_px", self.tilt_px)
        require_finite("stretch_px", self.stretch_px)
        require_int("n_places", self.n_places, minimum=0)

    @property
    def varies(self) -> bool:
        """Whether the offset changes across the image (a tilt or a stretch)."""
        return self.tilt_px != 0.0 or self.stretch_px != 0.0

    @property
    def rms_px(self) -> float:
        """The offset's root mean square over the image: ``sqrt(offset^2 + (tilt^2 +
        stretch^2) / 3)`` (``u`` and ``v`` uniform on -1..1)."""
        return float(np.sqrt(self.offset_px ** 2
                             + (self.tilt_px ** 2 + self.stretch_px ** 2) / 3.0))

    @property
    def standard_error_px(self) -> float:
        """The median's standard error: ``1.2533 sigma / sqrt(n)``, ``sigma`` from the
        interquartile range (``1.4826 spread_px``), as for normal scatter."""
        return float(1.2533 * 1.4826 * self.spread_px / np.sqrt(max(self.n_places, 1)))

    @property
    def misaligned(self) -> bool:
        """At least :data:`MIN_TRACKED` places and the rows more than
        :data:`ROW_TOLERANCE_PX` apart (root mean square over the image), beyond their
        noise: an offset more than three standard errors from 0, or a tilt or stretch
        (kept only beyond three standard errors).  A scene with few places that show
        vertical structure, say an untextured block, gives a wide scatter and no
        verdict."""
        if self.n_places < MIN_TRACKED or self.rms_px <= ROW_TOLERANCE_PX:
            return False
        return bool(self.varies or abs(self.offset_px) > 3.0 * self.standard_error_px)

    def describe(self) -> str:
        """The offset in words, for a warning.

        >>> RowOffset(-0.2, 0.1, 60, tilt_px=1.1).describe()
        '-0.20 px at the centre, 1.10 px more at the right edge and as much less at the left'
        """
        if not self.varies:
            side = "lower" if self.offset_px > 0 else "higher"
            return f"{self.offset_px:+.2f} px (the right view {side})"
        parts = [f"{self.offset_px:+.2f} px at the centre"]
        if self.tilt_px:
            parts.append(f"{self.tilt_px:.2f} px more at the right edge and as much less at "
                         "the left")
        if self.stretch_px:
            parts.append(f"{self.stretch_px:.2f} px more at the bottom and as much less at "
                         "the top")
        return ", ".join(parts)


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
    1. Up to 120 of the matches, evenly spaced (480 where fewer than
       :data:`MIN_TRACKED` of those are tracked), on the images' grey levels (a colour image's
       green channel); at each, the smaller eigenvalue of the grey levels' structure
       tensor over an 11 x 11 window (central differences).
    2. Each place is tracked into the right view by Lucas-Kanade over that window
       (:func:`~robostereo.matcher.alignment_kernels.track_kernel`), starting at
       ``(x - disparity, row + v0)``, ``v0`` the whole row offset within 5 px whose
       window differs least.
    3. The better-structured half of the places whose track converged within 2 px of
       its match gives the median vertical motion and its spread.
    4. The same motions fitted by a plane ``offset + tilt u + stretch v`` (least squares,
       the places more than three robust deviations off left out, twice, starting from
       the median); where a slope is more than three of its standard errors from 0, the
       plane is the estimate (a slope within its noise is set to 0 and the rest refitted),
       if it leaves the places less scattered than the median does.  A slope is only
       fitted where the places span at least a quarter of the image in its direction
       (10th to 90th percentile): read from a narrow band, it would be extrapolated to the edges.
    5. Where that estimate tilts or stretches, steps 1-4 again with twice as many
       places: a slope's noise decides how far the second match moves the rows at the
       edges (reindeer's rows tilted 1.17 px at the side edges were read as 0.72 px from
       the 48 places the first reading tracked, and the second match stayed 1.15 % false;
       as 0.97 px from 98, 0.52 %).  A constant offset is read well from the first
       places; read from more, its small slopes can pass their standard errors without
       being real (reindeer moved 2 px showed a 0.5 px tilt), so it is not read again.

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
    require_one_length(("rows", "x", "disparity"), y, xs, d)
    # the grey levels as given (the green channel of a colour image: the rows' offset is
    # the same in every channel)
    ga = a[..., 1] if a.ndim == 3 else a
    gb = b[..., 1] if b.ndim == 3 else b
    # -- 1.-2. structure and Lucas-Kanade at evenly spaced places, the better-structured
    #    half kept; four times as many where too few of them are tracked (rows far
    #    apart leave many first matches wrong)
    for most in (_MAX_PLACES, 4 * _MAX_PLACES):
        tracked = _tracked(ga, gb, y, xs, d, most)
        if tracked is not None or y.size <= most:
            break
    if tracked is None:
        return None
    estimate = _estimate(*tracked, ga.shape[:2])
    # -- 5. a slope: read twice as many places (its noise is what decides how far the
    #    second match moves the rows at the edges)
    if estimate.varies and y.size > most:
        again = _tracked(ga, gb, y, xs, d, 2 * most)
        if again is not None:
            estimate = _estimate(*again, ga.shape[:2])
    return estimate


def _estimate(xr: np.ndarray, y: np.ndarray, dy: np.ndarray, shape: tuple[int, ...]
              ) -> RowOffset:
    """The rows' offset from tracked places (right columns `xr`, rows `y`, vertical
    motions `dy`, (n,) each) in images of `shape` ``(H, W)``: :func:`row_offset`'s
    steps 3-4."""
    # -- 3. the median and its spread (the quartiles as the nearest order statistics)
    med, spread = _median_spread(dy)
    constant = RowOffset(med, spread, int(dy.size))
    # -- 4. a plane over the image, where its slopes are beyond their noise
    h, w = shape
    # the places where the right view shows them: the rows' offset is the right view's
    u = (xr - 0.5 * (w - 1)) / max(0.5 * (w - 1), 1.0)
    v = (y - 0.5 * (h - 1)) / max(0.5 * (h - 1), 1.0)
    tilt, stretch = _covers(u), _covers(v)
    if not (tilt or stretch) or _plain_rms(dy, u, v) < 0.75 * ROW_TOLERANCE_PX:
        return constant  # no plane that the rows could be called apart by
    plane = _plane(dy, u, v, med, tilt, stretch)
    if plane is None:
        return constant
    (offset, tilt_px, stretch_px), residuals = plane
    _, spread = _median_spread(residuals)
    return RowOffset(offset, spread, int(dy.size), tilt_px=tilt_px, stretch_px=stretch_px)


def _tracked(ga: np.ndarray, gb: np.ndarray, y: np.ndarray, xs: np.ndarray, d: np.ndarray,
             most: int) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Up to `most` of the matches ``(xs, y, d)`` (n,), evenly spaced, tracked from `ga`
    into `gb`: the right columns, the rows and the vertical motions of the places whose
    track converged within 2 px of their match, (k,) each; None where fewer than
    :data:`MIN_TRACKED`."""
    if y.size > most:  # evenly spaced
        pick = np.arange(most) * (y.size - 1) // (most - 1)
        y, xs, d = y[pick], xs[pick], d[pick]
    keep = np.isfinite(xs) & np.isfinite(d)
    y, xs, d = y[keep], xs[keep], d[keep]
    if y.size < MIN_TRACKED:
        return None
    xi = np.rint(xs).astype(np.int64)
    _, dx, dy, ok = track_kernel(ga, gb, xi, y.astype(np.int64), d,
                                 _WINDOW // 2, 10, _ROW_SEARCH)
    best = ok & (np.abs(dx + d) <= 2.0)
    if best.sum() < MIN_TRACKED:
        return None
    # where the right view shows the places: the rows' offset is the right view's
    return (xi + dx)[best], y[best], dy[best]


def _median_spread(values: np.ndarray) -> tuple[float, float]:
    """Median and half the interquartile range (the quartiles as the nearest order
    statistics) of ``values`` (n,)."""
    z = np.sort(values)
    n = z.size
    return (float(0.5 * (z[(n - 1) // 2] + z[n // 2])),
            float(0.5 * (z[(3 * n) // 4] - z[n // 4])))


def _plain_rms(dy: np.ndarray, u: np.ndarray, v: np.ndarray) -> float:
    """The root mean square over the image of a plain least-squares plane through the
    motions: where it is well under the tolerance (the rows as they should be), the
    robust fit is not needed."""
    coef = np.linalg.lstsq(np.column_stack([np.ones_like(u), u, v]), dy, rcond=None)[0]
    return float(np.sqrt(coef[0] ** 2 + (coef[1] ** 2 + coef[2] ** 2) / 3.0))


def _covers(t: np.ndarray) -> bool:
    """Whether places at ``t`` (-1..1 across the image) span at least a quarter of it
    (10th to 90th percentile): a slope read from a narrow band would be extrapolated to
    the image's edges (the simulated block's places, in a band a sixth of the image
    wide, gave a tilt of 7.5 px from motions that were noise)."""
    lo, hi = np.percentile(t, [10, 90])
    return bool(hi - lo >= 0.5)


def _plane(dy: np.ndarray, u: np.ndarray, v: np.ndarray, start: float, tilt: bool = True,
           stretch: bool = True) -> tuple[tuple[float, float, float], np.ndarray] | None:
    """``dy ~ offset + tilt u + stretch v`` (all (n,)), fitted robustly from the constant
    `start` (with only the slopes asked for: `tilt`, `stretch`); slopes within three
    standard errors of 0 are dropped and the rest refitted.
    None where no slope is kept, or where the plane leaves the places more scattered
    than the constant does (robust deviations of all places: motions that are noise, say
    tracks on texture that repeats down the image, can still show a slope beyond its
    standard error).  Returns the coefficients and every place's residual."""
    design = np.column_stack([np.ones_like(u), u, v])
    scatter_constant = _deviation(dy - start)
    use = [0] + ([1] if tilt else []) + ([2] if stretch else [])
    coef = np.array([start, 0.0, 0.0])
    while len(use) > 1:
        a = design[:, use]
        fit = coef[use]
        for _ in range(2):  # leave out the places far off the current fit, refit
            r = dy - a @ fit
            sigma = max(_deviation(r), 0.02)
            keep = np.abs(r) <= 3.0 * sigma
            if keep.sum() < MIN_TRACKED:
                return None
            fit = np.linalg.lstsq(a[keep], dy[keep], rcond=None)[0]
        r = dy[keep] - a[keep] @ fit
        sigma = max(_deviation(r), 0.02)
        gram = a[keep].T @ a[keep]
        if np.linalg.cond(gram) > 1e8:
            return None
        se = sigma * np.sqrt(np.diag(np.linalg.inv(gram)))
        coef = np.zeros(3)
        coef[use] = fit
        weak = [j for k, j in enumerate(use) if j > 0 and abs(fit[k]) <= 3.0 * se[k]]
        if not weak:
            residuals = dy - design @ coef
            if _deviation(residuals) >= scatter_constant:
                return None
            return (float(coef[0]), float(coef[1]), float(coef[2])), residuals
        use = [j for j in use if j not in weak]
    return None


def _deviation(r: np.ndarray) -> float:
    """Robust standard deviation of `r` (n,): 1.4826 times its median absolute deviation."""
    return 1.4826 * float(np.median(np.abs(r - np.median(r))))


def moved_rows(image: ArrayLike, offset_px: float, tilt_px: float = 0.0,
               stretch_px: float = 0.0) -> np.ndarray:
    """``image`` ``(H, W)`` or ``(H, W, C)`` moved up by ``offset_px + tilt_px u +
    stretch_px v`` rows at ``(x, y)`` (see :class:`RowOffset`; linear interpolation,
    the border row repeated): what the right view would show were its rows the left's.
    Same dtype.

    >>> moved_rows(np.arange(12, dtype=np.float32).reshape(4, 3), 1.0)[:, 0].tolist()
    [3.0, 6.0, 9.0, 9.0]
    >>> moved_rows(np.arange(12, dtype=np.float32).reshape(4, 3), 0.0, 1.0)[0].tolist()
    [0.0, 1.0, 5.0]
    """
    im = np.asarray(image)
    h, w = im.shape[:2]
    cx, cy = 0.5 * (w - 1), 0.5 * (h - 1)
    a = float(tilt_px) / max(cx, 1.0)  # rows per column
    b = float(stretch_px) / max(cy, 1.0)  # rows per row
    shift = np.float32([[1.0, 0.0, 0.0],
                        [a, 1.0 + b, float(offset_px) - a * cx - b * cy]])
    return cv2.warpAffine(im, shift, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                          borderMode=cv2.BORDER_REPLICATE)
