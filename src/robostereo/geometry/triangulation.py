"""Triangulation of matched edge points and the depth error bound (the thesis, 3.6-3.7).

For a rectified pair (epipolar lines are rows) with focal length ``f`` (pixels),
baseline ``D`` and principal points ``(cx, cy)`` (left) and ``(cx + doffs, cy)``
(right), a match ``(x_l, x_r)`` on row ``y`` has the effective disparity
``d = (x_l - cx) - (x_r - cx - doffs)`` and, in the epipolar frame (origin
mid-baseline, X along the baseline, Y down the image, Z along the optical axis):

* eq. (6): ``X = (D / 2) (x_l' + x_r') / d``
* eq. (7): ``Y = (D / 2) (y_l' + y_r') / d * (f_x / f_y)`` (``y_l' = y_r' = y - cy``)
* eq. (8): ``Z = D f / d``  (seed-notes: the thesis's ``x_r + x_l`` numerator is a scan error)

with primed coordinates measured from the principal points.  Signs follow the
image convention: x to the right, y down, depth positive; the thesis's inverted-image
convention gives the same values with the opposite signs (its z = -1007.6 mm).

The depth error bound is eq. (9): ``E_z = |dD dz/dD| + |ds dz/ds| + |d(disp) dz/d(disp)|``
with ``dz/dD = s / disp``, ``dz/ds = D / disp`` and ``dz/d(disp) = -D s / disp**2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_finite, require_nonnegative, require_positive

__all__ = [
    "MAX_BASELINE_MM",
    "MAX_PIXELS",
    "StereoCamera",
    "depth_error_bound",
    "depth_from_disparity",
    "triangulate",
]


def depth_from_disparity(baseline: ArrayLike, focal: ArrayLike, disparity: ArrayLike) -> NDArray:
    """Depth ``z = D s / disp`` (eq. 8 as corrected in seed-notes), in consistent units.

    Examples
    --------
    The thesis's worked example (section 5.2): D = 2.0 cm, s = 2.5 cm,
    x_r - x_l = 0.046 cm:

    >>> round(float(depth_from_disparity(2.0, 2.5, 0.046)), 1)
    108.7
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(baseline, float) * np.asarray(focal, float) / np.asarray(disparity, float)


def depth_error_bound(
    baseline: ArrayLike,
    focal: ArrayLike,
    disparity: ArrayLike,
    *,
    baseline_uncertainty: ArrayLike,
    focal_uncertainty: ArrayLike,
    disparity_uncertainty: ArrayLike,
) -> NDArray:
    """Worst-case depth error, eq. (9), in the units of the inputs.

    Parameters
    ----------
    baseline, focal, disparity : array_like
        ``D``, ``s`` and ``x_l - x_r`` (any consistent length unit, or pixels for
        ``focal`` and ``disparity`` with ``baseline`` in mm).
    baseline_uncertainty, focal_uncertainty, disparity_uncertainty : array_like
        ``dD``, ``ds`` and ``d(disp)``.

    Returns
    -------
    ndarray
        ``|dD s/disp| + |ds D/disp| + |d(disp) D s/disp**2|``.

    Examples
    --------
    The thesis's worked example: dD = ds = 0.001 cm, d(disp) = 0.00172 cm (one pixel):

    >>> round(float(depth_error_bound(2.0, 2.5, 0.046, baseline_uncertainty=0.001,
    ...     focal_uncertainty=0.001, disparity_uncertainty=0.00172)), 2)
    4.16
    """
    b = np.asarray(baseline, float)
    f = np.asarray(focal, float)
    d = np.asarray(disparity, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return (
            np.abs(np.asarray(baseline_uncertainty, float) * f / d)
            + np.abs(np.asarray(focal_uncertainty, float) * b / d)
            + np.abs(np.asarray(disparity_uncertainty, float) * b * f / d**2)
        )


MAX_PIXELS = 1e7
"""Largest focal length, principal point or ``doffs`` of a :class:`StereoCamera`, in
pixels: beyond it no real camera, and the arithmetic of triangulation loses the
disparity."""

MAX_BASELINE_MM = 1e9
"""Largest baseline of a :class:`StereoCamera` (1000 km)."""


@dataclass(frozen=True)
class StereoCamera:
    """Geometry of a rectified stereo pair, for triangulation (the thesis, 3.6-3.7).

    Build it from the thesis's physical quantities with :meth:`from_physical` or from
    pixel intrinsics (a calibrated, rectified rig) directly.

    Parameters
    ----------
    fx, fy : float
        Focal length in horizontal and vertical pixels.
    baseline_mm : float
        Distance ``D`` between the optical centres, millimetres.
    cx, cy : float or None
        Left principal point, pixels; None = the image centre at use.
    doffs : float
        ``cx_right - cx_left``, pixels (Middlebury's ``doffs``).
    focal_uncertainty_px : float
        ``ds`` expressed in horizontal pixels.
    baseline_uncertainty_mm : float
        ``dD``.
    disparity_uncertainty_px : float
        ``d(disp)``: the thesis used one pixel; sub-pixel edges warrant less.

    Raises
    ------
    InputError
        ``fx``, ``fy`` or ``baseline_mm`` not a finite number > 0, a NaN or infinite
        value, a negative uncertainty, ``fx, fy, cx, cy, doffs`` beyond
        :data:`MAX_PIXELS` or a baseline beyond :data:`MAX_BASELINE_MM`.

    Examples
    --------
    >>> cam = StereoCamera.from_physical()
    >>> round(cam.fx, 2), cam.baseline_mm, round(cam.focal_uncertainty_px, 3)
    (1453.49, 20.0, 0.581)
    """

    fx: float
    fy: float
    baseline_mm: float
    cx: float | None = None
    cy: float | None = None
    doffs: float = 0.0
    focal_uncertainty_px: float = 0.0
    baseline_uncertainty_mm: float = 0.0
    disparity_uncertainty_px: float = 1.0

    def __post_init__(self) -> None:
        require_positive("fx", self.fx)
        require_positive("fy", self.fy)
        require_positive("baseline_mm", self.baseline_mm)
        for name in ("cx", "cy"):
            v = getattr(self, name)
            if v is not None:
                require_finite(name, v)
        require_finite("doffs", self.doffs)
        for name in ("fx", "fy", "cx", "cy", "doffs"):
            v = getattr(self, name)
            if v is not None and abs(v) > MAX_PIXELS:
                raise InputError(f"{name} must be within +-{MAX_PIXELS:g} pixels, got {v:g}")
        if self.baseline_mm > MAX_BASELINE_MM:
            raise InputError(
                f"baseline_mm must be at most {MAX_BASELINE_MM:g}, got {self.baseline_mm:g}"
            )
        for name in ("focal_uncertainty_px", "baseline_uncertainty_mm",
                     "disparity_uncertainty_px"):
            require_nonnegative(name, getattr(self, name))

    @classmethod
    def from_physical(
        cls,
        focal_length_mm: float = 25.0,
        pixel_pitch_mm: tuple[float, float] = (0.0172, 0.0137),
        baseline_mm: float = 20.0,
        *,
        principal_point: tuple[float, float] | None = None,
        focal_length_uncertainty_mm: float = 0.01,
        baseline_uncertainty_mm: float = 0.01,
        disparity_uncertainty_px: float = 1.0,
    ) -> StereoCamera:
        """From the thesis's quantities: lens-to-image distance ``s``, pixel pitch, ``D``.

        Defaults are the thesis's (section 5.2): s = 25 mm, 17.2 um pixels, D = 20 mm,
        ``ds = dD = 0.01 mm``, ``d(disp)`` = one pixel.
        """
        require_positive("focal_length_mm", focal_length_mm)
        if len(pixel_pitch_mm) != 2:
            raise InputError(f"pixel_pitch_mm must be (horizontal, vertical), got {pixel_pitch_mm}")
        px, py = (float(v) for v in pixel_pitch_mm)
        require_positive("pixel_pitch_mm", px)
        require_positive("pixel_pitch_mm", py)
        require_finite("focal_length_uncertainty_mm", focal_length_uncertainty_mm)
        cx, cy = principal_point if principal_point is not None else (None, None)
        return cls(
            fx=focal_length_mm / px, fy=focal_length_mm / py, baseline_mm=float(baseline_mm),
            cx=cx, cy=cy, focal_uncertainty_px=abs(focal_length_uncertainty_mm) / px,
            baseline_uncertainty_mm=baseline_uncertainty_mm,
            disparity_uncertainty_px=disparity_uncertainty_px,
        )

    def principal_point(self, image_shape: tuple[int, ...]) -> tuple[float, float]:
        """``(cx, cy)`` of the left image, the image centre where not given."""
        h, w = image_shape[:2]
        cx = (w - 1) / 2.0 if self.cx is None else float(self.cx)
        cy = (h - 1) / 2.0 if self.cy is None else float(self.cy)
        return cx, cy


def _coordinates(name: str, values: ArrayLike) -> NDArray[np.float64]:
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a 1-D array of numbers") from None
    if a.ndim != 1:
        raise InputError(f"{name} must be a 1-D array of numbers, got shape {a.shape}")
    return a


def triangulate(
    camera: StereoCamera,
    x_left: ArrayLike,
    x_right: ArrayLike,
    rows: ArrayLike,
    image_shape: tuple[int, ...],
    *,
    disparity_uncertainty_px: ArrayLike | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """3-D points in the epipolar frame and their depth bounds (eq. 6-9).

    Parameters
    ----------
    camera : StereoCamera
    x_left, x_right : array_like, shape (N,)
        Matched positions along the row, pixels.
    rows : array_like, shape (N,)
        Image rows (y) of the matches.
    image_shape : tuple
        ``(H, W)`` of the images (for the default principal point).
    disparity_uncertainty_px : array_like, optional
        Per-point ``d(disp)``; default ``camera.disparity_uncertainty_px``.

    Returns
    -------
    xyz : ndarray, shape (N, 3)
        ``(X, Y, Z)`` in millimetres, origin mid-baseline, Z the depth.
    z_bound : ndarray, shape (N,)
        Depth error bound of eq. (9), millimetres.
        Points with a disparity ``<= 0`` or not finite (NaN or infinite input), or whose
        depth under- or overflows (absurd coordinates), get NaN coordinates and bound.

    Raises
    ------
    InputError
        Coordinates that are not 1-D arrays of one length, a bad `image_shape`.
    TypeError
        `camera` not a :class:`StereoCamera`.

    Examples
    --------
    A point 1000 mm in front of the thesis's cameras, midway between them; its bound
    is 0.5 + 0.4 + 34.4 mm (dD, ds and one pixel of disparity):

    >>> cam = StereoCamera.from_physical()
    >>> d = cam.fx * 20.0 / 1000.0          # disparity of a point at Z = 1000 mm
    >>> xyz, zb = triangulate(cam, [254 + d / 2], [254 - d / 2], [240], (481, 509))
    >>> xyz.round(6).tolist(), round(float(zb[0]), 1)
    ([[0.0, 0.0, 1000.0]], 35.3)
    """
    if not isinstance(camera, StereoCamera):
        raise TypeError(f"camera must be a StereoCamera, got {type(camera).__name__}")
    xl, xr, y = (_coordinates(n, v) for n, v in
                 (("x_left", x_left), ("x_right", x_right), ("rows", rows)))
    if not xl.shape == xr.shape == y.shape:
        raise InputError(f"x_left, x_right and rows must have one length, got "
                         f"{xl.shape[0]}, {xr.shape[0]}, {y.shape[0]}")
    if (not isinstance(image_shape, tuple | list) or len(image_shape) < 2
            or not all(isinstance(v, int | np.integer) and not isinstance(v, bool) and v > 0
                       for v in image_shape[:2])):
        raise InputError(f"image_shape must be (H, W) of positive integers, got {image_shape!r}")
    cx, cy = camera.principal_point(image_shape)
    xlp = xl - cx
    xrp = xr - cx - camera.doffs
    d = xlp - xrp
    b = camera.baseline_mm
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        z = b * camera.fx / d
        x = 0.5 * b * (xlp + xrp) / d
        yy = b * (camera.fx / camera.fy) * (y - cy) / d
    dd = camera.disparity_uncertainty_px if disparity_uncertainty_px is None else (
        disparity_uncertainty_px)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # huge coordinates
        bound = depth_error_bound(
            b, camera.fx, d, baseline_uncertainty=camera.baseline_uncertainty_mm,
            focal_uncertainty=camera.focal_uncertainty_px, disparity_uncertainty=dd,
        )
    xyz = np.column_stack([x, yy, z])
    # behind the cameras, an infinite coordinate, or a depth that under- or overflows
    bad = ~((d > 0) & np.isfinite(d) & (z > 0) & np.isfinite(z))
    if bad.any():
        xyz[bad] = math.nan
        bound = np.where(bad, math.nan, bound)
    return xyz, bound
