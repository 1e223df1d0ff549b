"""Bounds on a capture's numbers that a real camera on a real robot stays within.

A number can parse, be finite and positive, and still not describe a capture: a
1,000,000 mm lens, a 1e-300 mm pixel, a depth range from 1e-300 mm, an uncertainty of
1e308 pixels.  Such numbers make the work that follows from them unbounded (an
inverse-depth grid of 10^9 steps, an image side of 10^10 pixels) or its results empty,
so the checks here refuse them with one line naming the key and the limit.  The limits
are far outside every real camera, so no real capture meets them.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from robostereo.errors import InputError, is_finite_number, shown, warn_input

__all__ = [
    "MAX_FOCAL_PX",
    "MAX_IMAGE_SIDE_PX",
    "MAX_PHI_DEG",
    "MAX_TRANSLATION_MM",
    "MIN_FOCAL_PX",
    "PRINTED_ROTATION_TOLERANCE",
    "check_depth_disparities",
    "check_focal_px",
    "check_translation",
    "check_uncertainties",
    "printed_rotation",
]

MAX_FOCAL_PX = 1e6
"""Largest focal length in pixels, ``focal_length_mm / pixel_pitch_mm``.

A 1000 mm telephoto lens on 1 um pixels (smaller than any machine-vision sensor's) is
10^6 px; the thesis's camera has 1453 px.  Beyond it the depth range of any scene spans
more disparities than an image has columns."""

MIN_FOCAL_PX = 1.0
"""Smallest focal length in pixels: under one pixel a pinhole sees more than
+-89.8 degrees across a 509-pixel image, which no lens without fisheye distortion does."""

MAX_IMAGE_SIDE_PX = 100_000
"""Largest image width or height, pixels: seven times the widest sensors made
(a 150-megapixel sensor is 14,204 pixels wide)."""

MAX_TRANSLATION_MM = 1e9
"""Largest pose translation component, mm: 1000 km, beyond any robot's world frame.
Up to it a float resolves 1e-7 mm; 1e308 mm overflows the first difference taken."""

MAX_PHI_DEG = 1e6
"""Largest SCARA yaw ``phi_deg``, degrees: beyond it the float's spacing grows towards a
degree and more, so the angle no longer says where the camera looks."""


def check_translation(translation: tuple[float, ...] | list[float], name: str) -> None:
    """Refuse a translation with a component beyond :data:`MAX_TRANSLATION_MM`.

    >>> check_translation([0.0, 0.0, 1e308], "pose_left")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: pose_left: translation component 1e+308 mm is beyond ...
    """
    for v in translation:
        if not abs(v) <= MAX_TRANSLATION_MM:
            raise InputError(f"{name}: translation component {v:.3g} mm is beyond "
                             f"+-{MAX_TRANSLATION_MM:.0e} mm (1000 km) of the origin: not a "
                             "robot's pose")


def check_focal_px(fx: float, fy: float) -> None:
    """Refuse a focal length in pixels that is not finite or outside
    :data:`MIN_FOCAL_PX` .. :data:`MAX_FOCAL_PX` (the message names the camera keys).

    >>> check_focal_px(1453.5, 1824.8)
    >>> check_focal_px(25.0 / 1e-300, 1824.8)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: focal_length_mm / pixel_pitch_mm = 2.5e+301 px: ...
    """
    for f in (fx, fy):
        if not (math.isfinite(f) and MIN_FOCAL_PX <= f <= MAX_FOCAL_PX):
            raise InputError(
                f"focal_length_mm / pixel_pitch_mm = {f:.3g} px: a real camera's focal length "
                f"is {MIN_FOCAL_PX:g} .. {MAX_FOCAL_PX:.0e} pixels (is a number in other "
                "units?)")


def check_depth_disparities(fx: float, baseline_mm: float, depth_range_mm: tuple[float, float],
                            width: int) -> None:
    """Refuse a depth range whose disparities span more than twice the image width.

    Parameters
    ----------
    fx : float
        Focal length, pixels.
    baseline_mm : float
        The longest baseline between the views, mm.
    depth_range_mm : (near, far)
        Expected depths, mm, ``0 < near <= far``.
    width : int
        Image width, pixels.

    Notes
    -----
    A point seen in both images of a pair has ``x_left`` and ``x_right`` in
    ``0 .. width``, so its disparity ``fx D / z`` lies within ``+-width``: a range
    ``fx D (1/near - 1/far)`` wider than ``2 width`` reaches depths no pair of views
    sees, and the search over it (N views: an inverse-depth grid of one step per pixel
    of disparity) grows with it without bound.

    >>> check_depth_disparities(1453.5, 20.0, (850.0, 1070.0), 509)
    >>> check_depth_disparities(1453.5, 20.0, (1e-3, 1070.0), 509)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: depth_range_mm [0.001, 1070] spans 2.91e+07 px of ...
    """
    near, far = depth_range_mm
    span = math.inf
    try:
        span = fx * baseline_mm * (1.0 / near - 1.0 / far)
    except (OverflowError, ZeroDivisionError):
        pass
    if not span <= 2 * width:
        raise InputError(
            f"depth_range_mm [{near:g}, {far:g}] spans {span:.3g} px of disparity over "
            f"the {baseline_mm:.4g} mm baseline, more than twice the image width ({width} px): "
            "no two views see those depths; give the object's depth range")


MAX_ROTATION_UNCERTAINTY_DEG = 10.0
"""Above it, ``uncertainty: rotation_deg`` (or ``hand_eye_deg``) is no pose uncertainty
but an unknown pose."""


def check_uncertainties(focal_length_mm: float, width: int, *, baseline_mm: float,
                        focal_length_mm_unc: float, disparity_px: float,
                        rotation_deg: float = 0.0, hand_eye_deg: float = 0.0) -> None:
    """Refuse eq. 9's uncertainties that are not finite numbers >= 0 or that leave the
    depth bound empty: ``disparity_px`` above the image width, ``focal_length_mm`` not
    below the focal length.  The message names the ``uncertainty`` key.

    >>> check_uncertainties(25.0, 509, baseline_mm=0.01, focal_length_mm_unc=0.01,
    ...                     disparity_px=1e308)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: uncertainty 'disparity_px' must be a finite number ...
    """
    limits = (("baseline_mm", baseline_mm, math.inf, ""),
              ("focal_length_mm", focal_length_mm_unc, focal_length_mm,
               f" and below the focal length ({focal_length_mm:g} mm)"),
              ("disparity_px", disparity_px, float(width),
               f" and at most the image width ({width} px)"),
              ("rotation_deg", rotation_deg, MAX_ROTATION_UNCERTAINTY_DEG,
               f" and below {MAX_ROTATION_UNCERTAINTY_DEG:g}"),
              ("hand_eye_deg", hand_eye_deg, MAX_ROTATION_UNCERTAINTY_DEG,
               f" and below {MAX_ROTATION_UNCERTAINTY_DEG:g}"))
    for key, v, top, why in limits:
        at_most = key == "disparity_px"  # the image width itself is allowed
        if not (is_finite_number(v) and 0 <= v and (v <= top if at_most else v < top)):
            raise InputError(f"uncertainty '{key}' must be a finite number >= 0{why}, "
                             f"got {shown(v)}")


PRINTED_ROTATION_TOLERANCE = 1e-5
"""Largest ``|R^T R - I|`` entry of a file's ``matrix`` that is re-orthonormalised with
a warning rather than refused.

A rotation printed with 6 decimals has each entry off by at most ``e = 5e-7``; an entry
of ``R^T R - I`` sums three products, so it is off by at most ``2 * 3 * e = 3e-6``
(measured: 3.3e-7 to 8.4e-7 on DTU scan 24's eight extrinsics rounded to 6
decimals, 1.06e-6 on a 0.3 rad turn, 1.01e-6 in the issue's report).  1e-5 takes every
matrix printed with 6 decimals (and most with 5) and refuses one further off, which is
no rounding but a wrong entry."""


def printed_rotation(matrix: Any, source: str, exact: float) -> Any:
    """A file's 4 x 4 pose `matrix` whose rotation is off orthonormal by more than
    `exact` but within :data:`PRINTED_ROTATION_TOLERANCE` (rounding), with its nearest
    rotation and a :class:`~robostereo.errors.PlausibilityWarning` naming `source`;
    anything else as it is (the pose checks it).

    >>> import warnings
    >>> c, s = math.cos(0.3), math.sin(0.3)
    >>> R = np.round([[c, -s, 0], [s, c, 0], [0, 0, 1]], 6)
    >>> M = np.eye(4); M[:3, :3] = R
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     out = printed_rotation(M, "c.yaml: pose", 1e-6)
    >>> float(np.abs(out[:3, :3].T @ out[:3, :3] - np.eye(3)).max()) < 1e-12, len(w)
    (True, 1)
    """
    try:
        M = np.array(matrix, dtype=float)
    except (TypeError, ValueError, OverflowError):
        return matrix
    if M.shape != (4, 4) or not np.all(np.isfinite(M)):
        return matrix
    R = M[:3, :3]
    err = float(np.abs(R.T @ R - np.eye(3)).max())
    if exact < err <= PRINTED_ROTATION_TOLERANCE and np.linalg.det(R) > 0:
        u, _, vt = np.linalg.svd(R)
        M[:3, :3] = u @ vt
        warn_input(f"{source}: matrix: the rotation is orthonormal to {err:.2g} only (printed "
                   "with few decimals?): taken as the nearest rotation")
        return M
    return matrix
