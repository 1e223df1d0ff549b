"""Planning a two-view capture: the baseline for a depth accuracy (eq. 9 inverted).

:func:`plan_baseline` inverts eq. (9) (thesis 3.7): the baseline ``D`` that bounds the
depth error at a target depth by a wanted accuracy, and the disparity range to search
for a depth range (:class:`BaselinePlan`).  N views in a pattern are planned by
:mod:`robostereo.robot.planning.views_plan`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera

__all__ = [
    "MIN_PLAN_DISPARITY_PX",
    "BaselinePlan",
    "plan_baseline",
]


MIN_PLAN_DISPARITY_PX = 1.0
"""Least disparity at the target of a plan: below a pixel the eq. 9 bound still
holds on paper, but edges one pixel apart cannot be told from noise (``d(disp)`` is
0.2 px), so such a plan is refused rather than printed with a baseline of 0.00 mm."""


@dataclass(frozen=True)
class BaselinePlan:
    """The baseline and disparity range of a capture (:func:`plan_baseline`).

    Attributes
    ----------
    baseline_mm : float
        ``D`` that makes the eq. 9 bound at `depth_mm` equal `accuracy_mm`.
    depth_mm, accuracy_mm : float
    disparity_px : float
        Disparity at `depth_mm`, ``f D / Z``.
    disparity_range : tuple of float
        Whole-pixel range to search for ``[near, far]``.
    bound_terms_mm : tuple of float
        The three terms of eq. 9 at `depth_mm`: baseline, focal length, disparity.
    """

    baseline_mm: float
    depth_mm: float
    accuracy_mm: float
    disparity_px: float
    disparity_range: tuple[float, float]
    bound_terms_mm: tuple[float, float, float]


def plan_baseline(
    camera: Camera,
    depth_mm: float,
    accuracy_mm: float,
    *,
    depth_range_mm: tuple[float, float] | None = None,
    baseline_uncertainty_mm: float = 0.01,
    focal_length_uncertainty_mm: float = 0.01,
    disparity_uncertainty_px: float = 0.2,
    max_disparity_px: float | None = None,
) -> BaselinePlan:
    """The baseline ``D`` whose eq. 9 bound at `depth_mm` is `accuracy_mm`.

    Parameters
    ----------
    camera : Camera
    depth_mm : float
        Target depth ``Z`` along the optical axis, millimetres.
    accuracy_mm : float
        Wanted bound ``E_z`` at that depth.
    depth_range_mm : (near, far), optional
        Depths to search; default ``0.8 Z .. 1.2 Z``.
    baseline_uncertainty_mm, focal_length_uncertainty_mm, disparity_uncertainty_px
        ``dD``, ``ds`` (mm) and ``d(disp)`` (px) of eq. 9 (the capture defaults).
    max_disparity_px : float, optional
        Largest disparity a pair can show: default the camera's image width (a point
        further apart than the image is wide is in one view only).

    Returns
    -------
    BaselinePlan

    Raises
    ------
    InputError
        Non-positive or non-finite inputs; an accuracy that no baseline reaches (the
        focal-length term ``ds Z / s`` alone exceeds it); a plan whose baseline or
        disparities are not finite numbers (depths or accuracies near the limits of
        floating point); a disparity at the target under
        :data:`MIN_PLAN_DISPARITY_PX` (an accuracy so loose that no baseline is
        needed); a search range beyond `max_disparity_px` (a near depth too near).

    Notes
    -----
    With ``d = f D / Z`` (f in pixels) eq. 9 reads
    ``E_z = dD Z / D + ds Z / s + d(disp) Z^2 / (f D)``, so
    ``D = (dD Z + d(disp) Z^2 / f) / (E_z - ds Z / s)``.

    References
    ----------
    Seed 3.7, eq. (9).

    Examples
    --------
    The thesis's camera at 1000 mm, 5 mm wanted:

    >>> p = plan_baseline(Camera(), 1000.0, 5.0)
    >>> round(p.baseline_mm, 2), p.disparity_range
    (32.09, (38.0, 59.0))
    """
    for name, v in (("depth_mm", depth_mm), ("accuracy_mm", accuracy_mm)):
        if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
            raise InputError(f"{name} must be a finite number > 0, got {v!r}")
    for name, v in (("baseline_uncertainty_mm", baseline_uncertainty_mm),
                    ("focal_length_uncertainty_mm", focal_length_uncertainty_mm),
                    ("disparity_uncertainty_px", disparity_uncertainty_px)):
        if not (math.isfinite(v) and v >= 0):
            raise InputError(f"{name} must be a finite number >= 0, got {v}")
    Z, f = float(depth_mm), camera.fx
    focal_term = focal_length_uncertainty_mm * Z / camera.focal_length_mm
    room = accuracy_mm - focal_term
    if not room > 0:
        raise InputError(
            f"accuracy_mm = {accuracy_mm:g} mm is unreachable at {Z:g} mm: the focal-length "
            f"uncertainty alone gives {focal_term:.3g} mm (eq. 9)"
        )
    near, far = depth_range_mm if depth_range_mm is not None else (0.8 * Z, 1.2 * Z)
    for name, v in (("near depth", near), ("far depth", far)):
        if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
            raise InputError(f"{name} must be a finite number > 0, got {v!r}")
    if not far >= near:
        raise InputError(f"depth_range_mm must be [near, far] with near <= far, got "
                         f"{[near, far]}")
    with np.errstate(all="ignore"):  # the limits of floating point: checked below
        D = float(np.float64(baseline_uncertainty_mm * Z)
                  + np.float64(disparity_uncertainty_px) * Z * Z / f) / room
        disp = f * D / Z
        hi, lo = f * D / near, f * D / far
    if not (math.isfinite(D) and math.isfinite(hi) and D > 0):
        raise InputError(f"no plan for depth {Z:g} mm and accuracy {accuracy_mm:g} mm: the "
                         f"baseline is not a finite number (D = {D:g} mm)")
    if not disp >= MIN_PLAN_DISPARITY_PX:
        raise InputError(
            f"accuracy_mm = {accuracy_mm:g} mm at {Z:g} mm needs a baseline of only "
            f"{D:.3g} mm, a disparity of {disp:.3g} px (< {MIN_PLAN_DISPARITY_PX:g} px): "
            "too little to measure; ask for a tighter accuracy")
    limit = camera.width if max_disparity_px is None else max_disparity_px
    if hi > limit:
        raise InputError(
            f"near depth {near:g} mm gives a disparity of {hi:.4g} px, more than the "
            f"{limit:g} px of the image: give a farther near depth")
    drange = (float(math.floor(lo)), float(math.ceil(hi)))
    terms = (baseline_uncertainty_mm * Z / D, focal_term,
             disparity_uncertainty_px * Z * Z / (f * D))
    return BaselinePlan(baseline_mm=D, depth_mm=Z, accuracy_mm=float(accuracy_mm),
                        disparity_px=f * D / Z, disparity_range=drange, bound_terms_mm=terms)
