"""Planning a capture: the baseline for a depth accuracy, its direction, and fusing two.

* :func:`plan_baseline` inverts eq. (9) (thesis 3.7): the baseline ``D`` that bounds the
  depth error at a target depth by a wanted accuracy, and the disparity range to
  search for a depth range;
* :func:`best_baseline_direction` picks, from an image of the scene, the direction to
  move the camera so that most edges cross the epipolar lines (an edge parallel to the
  baseline lies along an epipolar line and cannot be matched: the thesis's block lost
  its short edges that way);
* :func:`fuse_located` merges the points of two captures (e.g. with orthogonal
  baselines) into one set, each point keeping its eq. 9 bound.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_positive
from robostereo.geometry.camera import Camera

__all__ = [
    "BaselineDirection",
    "BaselinePlan",
    "FusedPoints",
    "best_baseline_direction",
    "fuse_located",
    "plan_baseline",
]


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

    Returns
    -------
    BaselinePlan

    Raises
    ------
    InputError
        Non-positive inputs, or an accuracy that no baseline reaches (the focal-length
        term ``ds Z / s`` alone exceeds it).

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
    require_positive("depth_mm", depth_mm)
    require_positive("accuracy_mm", accuracy_mm)
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
    D = (baseline_uncertainty_mm * Z + disparity_uncertainty_px * Z * Z / f) / room
    near, far = depth_range_mm if depth_range_mm is not None else (0.8 * Z, 1.2 * Z)
    require_positive("near depth", near)
    if not far >= near:
        raise InputError(f"depth_range_mm must be [near, far] with near <= far, got "
                         f"{[near, far]}")
    drange = (float(math.floor(f * D / far)), float(math.ceil(f * D / near)))
    terms = (baseline_uncertainty_mm * Z / D, focal_term,
             disparity_uncertainty_px * Z * Z / (f * D))
    return BaselinePlan(baseline_mm=D, depth_mm=Z, accuracy_mm=float(accuracy_mm),
                        disparity_px=f * D / Z, disparity_range=drange, bound_terms_mm=terms)


@dataclass(frozen=True)
class BaselineDirection:
    """The baseline direction chosen from an image (:func:`best_baseline_direction`).

    Attributes
    ----------
    direction_deg : float
        Direction in the image, degrees from the image's x axis towards its y axis
        (down), in ``[0, 180)``: move the camera along ``cos * x_c + sin * y_c``.
    matchable_fraction : float
        Share of the edge strength whose edges cross the epipolar lines at
        `min_crossing_deg` or more along that direction.
    matchable_fraction_x : float
        The same for the image's x axis (the usual horizontal baseline).
    scores : ndarray, shape (180,)
        The fraction for every whole degree.
    """

    direction_deg: float
    matchable_fraction: float
    matchable_fraction_x: float
    scores: NDArray[np.float64]


def best_baseline_direction(
    image: ArrayLike, *, min_crossing_deg: float = 30.0, threshold: float = 8.0
) -> BaselineDirection:
    """The baseline direction that makes most of an image's edges cross epipolar lines.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Grey image of the scene, on the 0..127 scale of the thesis (scale 8-bit images
        by 0.5) or any scale with `threshold` to match.
    min_crossing_deg : float
        An edge counts as matchable when it crosses the epipolar lines (the baseline
        direction) at this angle or more; below it the matcher sees it as a smear along
        the line.
    threshold : float
        Least gradient magnitude of an edge pixel (grey levels per pixel).

    Returns
    -------
    BaselineDirection

    Notes
    -----
    Sobel gradients of the image smoothed by a 5 x 5 Gaussian; an edge pixel with
    gradient angle ``g`` crosses a baseline at angle ``t`` at ``90 - |g - t|`` degrees
    (mod 180).  The edge strengths are histogrammed by ``g mod 180`` in 1-degree bins
    and the histogram is summed circularly over ``|g - t| <= 90 - min_crossing_deg``
    for every ``t``.
    """
    img = np.asarray(image, dtype=np.float32)
    if img.ndim != 2:
        raise InputError(f"image must be a grey (H, W) image, got shape {img.shape}")
    if not 0 < min_crossing_deg < 90:
        raise InputError(f"min_crossing_deg must be in (0, 90), got {min_crossing_deg}")
    s = cv2.GaussianBlur(img, (5, 5), 1.0)
    gx = cv2.Sobel(s, cv2.CV_32F, 1, 0, ksize=3) / 8.0
    gy = cv2.Sobel(s, cv2.CV_32F, 0, 1, ksize=3) / 8.0
    mag = np.hypot(gx, gy)
    edge = mag >= threshold
    if not edge.any():
        raise InputError(f"no edges of gradient >= {threshold} in the image")
    ang = np.degrees(np.arctan2(gy[edge], gx[edge])) % 180.0
    hist = np.bincount(np.minimum(ang.astype(int), 179), weights=mag[edge], minlength=180)
    half = round(90 - min_crossing_deg)
    window = np.zeros(180)
    window[: half + 1] = 1.0
    window[180 - half:] = 1.0
    # circular correlation: scores[t] = sum_g hist[g] * window[(g - t) mod 180]
    scores = np.real(np.fft.ifft(np.fft.fft(hist) * np.conj(np.fft.fft(window))))
    scores = np.clip(scores, 0.0, None) / hist.sum()
    best = int(np.argmax(scores))
    return BaselineDirection(direction_deg=float(best), matchable_fraction=float(scores[best]),
                             matchable_fraction_x=float(scores[0]), scores=scores)


@dataclass(frozen=True, eq=False)
class FusedPoints:
    """Points of two captures merged (:func:`fuse_located`).

    Attributes
    ----------
    world : ndarray, shape (M, 3)
        World points, millimetres.
    z_bound : ndarray, shape (M,)
        Each point's eq. 9 bound (from its own capture).
    capture : ndarray of int, shape (M,)
        Which capture (0, 1) each point comes from.
    duplicates : int
        Points of the second capture dropped as within `merge_mm` of one of the first.
    """

    world: NDArray[np.float64]
    z_bound: NDArray[np.float64]
    capture: NDArray[np.int8]
    duplicates: int

    def __len__(self) -> int:
        return int(self.world.shape[0])

    def table(self) -> dict[str, NDArray[Any]]:
        """Columns ``X_w, Y_w, Z_w, z_bound, capture``."""
        return {"X_w": self.world[:, 0], "Y_w": self.world[:, 1], "Z_w": self.world[:, 2],
                "z_bound": self.z_bound, "capture": self.capture}


def fuse_located(first: Any, second: Any, *, merge_mm: float = 0.5) -> FusedPoints:
    """Merge the located points of two captures of one scene into one set.

    Parameters
    ----------
    first, second : Located
        :func:`robostereo.robot.capture.locate` results (world frame, same robot).
    merge_mm : float
        A point of `second` within this distance of a point of `first` is the same
        edge sample seen twice and is dropped (the first keeps its own bound).

    Returns
    -------
    FusedPoints
    """
    from scipy.spatial import cKDTree

    require_positive("merge_mm", merge_mm)
    a, b = np.asarray(first.world), np.asarray(second.world)
    keep = np.ones(len(b), bool)
    if len(a) and len(b):
        d, _ = cKDTree(a).query(b, distance_upper_bound=merge_mm)
        keep = ~np.isfinite(d)
    world = np.vstack([a.reshape(-1, 3), b[keep].reshape(-1, 3)])
    zb = np.concatenate([np.asarray(first.z_bound), np.asarray(second.z_bound)[keep]])
    cap = np.concatenate([np.zeros(len(a), np.int8), np.ones(int(keep.sum()), np.int8)])
    return FusedPoints(world=world, z_bound=zb, capture=cap, duplicates=int((~keep).sum()))
