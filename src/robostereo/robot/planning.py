"""Planning a capture: the baseline for a depth accuracy, its direction, and fusing two.

* :func:`plan_baseline` inverts eq. (9) (thesis 3.7): the baseline ``D`` that bounds the
  depth error at a target depth by a wanted accuracy, and the disparity range to
  search for a depth range;
* :func:`plan_views` does the same for N views in a pattern
  (:func:`~robostereo.robot.views.viewpoints.view_offsets`): the span whose least-squares depth
  bound over the N views is the wanted accuracy, and the number of views that keeps
  neighbouring views close enough to match easily;
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
    "MIN_PLAN_DISPARITY_PX",
    "NEIGHBOUR_DISPARITY_PX",
    "BaselineDirection",
    "BaselinePlan",
    "FusedPoints",
    "ViewsPlan",
    "best_baseline_direction",
    "fuse_located",
    "plan_baseline",
    "plan_views",
    "views_baseline_factor",
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


NEIGHBOUR_DISPARITY_PX = 20.0 * 25.0 / 0.0172 / 1000.0
"""Largest disparity between neighbouring views that :func:`plan_views` proposes, px: the
thesis's pair (a 20 mm baseline with its 25 mm lens and 17.2 um pixels at 1 m, 4.2),
about 29 px, where its matcher worked.  Closer views match more easily (a smaller
search range, less of the scene hidden from one of them); farther ones are what a
longer span is for."""

MAX_PLAN_VIEWS = 100
"""Most views :func:`plan_views` proposes (:func:`~robostereo.robot.views.viewpoints.view_offsets`'s
limit)."""


@dataclass(frozen=True)
class ViewsPlan:
    """The number of views, their span and pattern for a depth accuracy (:func:`plan_views`).

    Attributes
    ----------
    views : int
        Number of views.
    pattern : str
        ``'line'``, ``'cross'`` or ``'arc'``
        (:func:`~robostereo.robot.views.viewpoints.view_offsets`).
    span_mm : float
        Distance between the outermost viewpoints' optical centres, mm.
    step_mm : float
        Largest distance from a view to its nearest neighbour, mm.
    effective_baseline_mm : float
        The two-view baseline of the same eq. 9 bound (``span_mm`` times
        :func:`views_baseline_factor`), mm.
    depth_mm, accuracy_mm : float
        The target depth and the wanted bound at it, mm.
    step_disparity_px : float
        Disparity between neighbouring views at `depth_mm`, ``f step / Z``.
    disparity_range : tuple of float
        Whole-pixel range ``(low, high)`` to search between neighbouring views for the
        depths ``[near, far]``, px.
    bound_terms_mm : tuple of float
        The three terms of eq. 9 at `depth_mm` (baseline, focal length, disparity) with
        the effective baseline, mm; they add up to `accuracy_mm`.
    """

    views: int
    pattern: str
    span_mm: float
    step_mm: float
    effective_baseline_mm: float
    depth_mm: float
    accuracy_mm: float
    step_disparity_px: float
    disparity_range: tuple[float, float]
    bound_terms_mm: tuple[float, float, float]


def _offsets(pattern: str, count: int, span_mm: float, depth_mm: float) -> NDArray[np.float64]:
    from robostereo.robot.views.viewpoints import view_offsets

    return view_offsets(pattern, count, span_mm,  # type: ignore[arg-type]
                        depth_mm=depth_mm if pattern == "arc" else None)


def _factor_and_step(pattern: str, count: int, span_mm: float,
                     depth_mm: float) -> tuple[float, float]:
    """:func:`views_baseline_factor` and the largest nearest-neighbour distance."""
    # in units of the span (every pattern scales with it, the arc with its depth): the
    # squares stay within floating point at any span
    o = _offsets(pattern, count, 1.0, depth_mm / span_mm)
    xy = o[:, :2] - o[:, :2].mean(axis=0)
    scatter = np.linalg.eigvalsh(xy.T @ xy)  # ascending
    # the least-measured direction among those the views measure at all
    measured = scatter[scatter > 1e-12 * scatter[-1]]
    factor = math.sqrt(2.0 * float(measured[0]))
    d = np.linalg.norm(o[:, None, :] - o[None, :, :], axis=2)
    np.fill_diagonal(d, np.inf)
    return factor, float(d.min(axis=1).max()) * span_mm


def views_baseline_factor(pattern: str, count: int, *, span_mm: float = 1.0,
                          depth_mm: float | None = None) -> float:
    """The two-view baseline, as a multiple of the span, of N views' eq. 9 bound.

    Parameters
    ----------
    pattern : {'line', 'cross', 'arc'}
    count : int
        Number of views, 2..100.
    span_mm : float
        Span of the views (matters for ``'arc'`` only: a line and a cross scale).
    depth_mm : float, optional
        ``'arc'``: the distance to the object (default ``100 span_mm``, nearly a line).

    Returns
    -------
    float
        ``D_eff / S``, with ``D_eff = sqrt(2 sum_i (b_i - mean b)^2)`` for the view
        positions ``b_i`` along the direction the pattern measures worst (among those it
        measures at all).

    Notes
    -----
    An edge point's image position in view ``i`` moves by ``-f b_i / Z`` with the view's
    offset ``b_i`` across the edge, so the least-squares slope of the N positions against
    ``b_i`` gives ``f / Z`` with the error ``sigma_x / sqrt(sum (b_i - mean b)^2)`` for
    an edge localisation error ``sigma_x`` in each view; two views ``D`` apart have
    ``sigma_x sqrt(2) / D``.  N views therefore bound the depth as a pair ``D_eff`` apart
    does (eq. 9 with ``D`` replaced by ``D_eff``; a baseline error ``dD`` of the pair is a
    position error ``dD / sqrt(2)`` of each view, which gives the same).  For N views
    evenly on a line, ``sum = N S^2 (N + 1) / (12 (N - 1))``, so
    ``D_eff / S = sqrt(N (N + 1) / (6 (N - 1)))``: 1 for two views, 1.118 for five.
    The direction is the smaller principal axis of the positions' scatter (x and y in
    the centre camera); a line or an arc measures only along itself (an edge parallel to
    it is unseen, as for a pair), a symmetric cross every direction alike.

    References
    ----------
    Seed 3.7, eq. (9); M. Okutomi and T. Kanade, "A multiple-baseline stereo", IEEE PAMI
    15(4), 1993.

    Examples
    --------
    >>> round(views_baseline_factor("line", 2), 3), round(views_baseline_factor("line", 5), 3)
    (1.0, 1.118)
    >>> round(views_baseline_factor("cross", 5), 3)  # a pair S apart, in x and in y
    1.0
    """
    require_positive("span_mm", span_mm)
    if depth_mm is not None:
        require_positive("depth_mm", depth_mm)
    depth = 100.0 * span_mm if depth_mm is None else depth_mm
    return _factor_and_step(pattern, count, float(span_mm), float(depth))[0]


def plan_views(
    camera: Camera,
    depth_mm: float,
    accuracy_mm: float,
    *,
    views: int | None = None,
    pattern: str = "line",
    depth_range_mm: tuple[float, float] | None = None,
    baseline_uncertainty_mm: float = 0.01,
    focal_length_uncertainty_mm: float = 0.01,
    disparity_uncertainty_px: float = 0.2,
    max_disparity_px: float | None = None,
    neighbour_disparity_px: float = NEIGHBOUR_DISPARITY_PX,
) -> ViewsPlan:
    """The number of views and the span in a pattern whose eq. 9 bound is `accuracy_mm`.

    Parameters
    ----------
    camera : Camera
    depth_mm : float
        Target depth ``Z``, millimetres.
    accuracy_mm : float
        Wanted bound at that depth, millimetres.
    views : int, optional
        Number of views, 2..100; default the fewest that keep neighbouring views at most
        `neighbour_disparity_px` apart at `depth_mm`.
    pattern : {'line', 'cross', 'arc'}
    depth_range_mm, baseline_uncertainty_mm, focal_length_uncertainty_mm,
    disparity_uncertainty_px, max_disparity_px
        As :func:`plan_baseline`; `max_disparity_px` bounds the disparity between the
        outermost views at the near depth (the object must be in every view).
    neighbour_disparity_px : float
        Most disparity between neighbouring views at the target depth when the count is
        proposed (:data:`NEIGHBOUR_DISPARITY_PX`).

    Returns
    -------
    ViewsPlan

    Raises
    ------
    InputError
        The checks of :func:`plan_baseline`; a bad `views` or `pattern`; an arc whose span
        reaches the diameter of its circle; more than 100 views needed; outermost views
        too far apart to both see the object at the near depth.

    Notes
    -----
    1. :func:`plan_baseline` gives the two-view baseline ``D`` of the wanted bound.
    2. N views of span ``S`` bound the depth as a pair ``D_eff = k S`` apart does
       (:func:`views_baseline_factor`), so ``S = D / k``; an arc, whose ``k`` changes a
       little with the span, is solved by repeating ``S <- S D / D_eff(S)``.
    3. Without `views`, N grows from 2 until the step between neighbours, ``S / (N -
       1)`` on a line, shows at most `neighbour_disparity_px` at the target depth.

    The bound assumes every view sees the point with the same edge localisation error,
    independently, and that each view's offset is known to ``dD / sqrt(2)``; it does not
    count the views in which the point is hidden (an occluder): those add nothing.
    With two views on a line this is exactly :func:`plan_baseline`.

    References
    ----------
    Seed 3.7, eq. (9).

    Examples
    --------
    The thesis's camera at 1000 mm, 1 mm wanted:

    >>> p = plan_views(Camera(), 1000.0, 1.0)
    >>> p.views, round(p.span_mm, 1), round(p.step_mm, 1)
    (10, 172.4, 19.2)
    >>> round(plan_views(Camera(), 1000.0, 1.0, views=2).span_mm, 2)
    246.0
    """
    from robostereo.robot.views.viewpoints import PATTERNS

    if pattern not in PATTERNS:
        raise InputError(f"pattern must be one of {', '.join(PATTERNS)}, got {pattern!r}")
    if views is not None and (isinstance(views, bool) or not isinstance(views, int | np.integer)
                              or not 2 <= views <= MAX_PLAN_VIEWS):
        raise InputError(f"views must be a whole number in 2..{MAX_PLAN_VIEWS}, got {views!r}")
    if isinstance(neighbour_disparity_px, bool) or not isinstance(
            neighbour_disparity_px, int | float) or not math.isfinite(neighbour_disparity_px) \
            or not neighbour_disparity_px > 0:
        raise InputError(f"neighbour_disparity_px must be a finite number > 0, got "
                         f"{neighbour_disparity_px!r}")
    two = plan_baseline(camera, depth_mm, accuracy_mm, depth_range_mm=depth_range_mm,
                        baseline_uncertainty_mm=baseline_uncertainty_mm,
                        focal_length_uncertainty_mm=focal_length_uncertainty_mm,
                        disparity_uncertainty_px=disparity_uncertainty_px,
                        max_disparity_px=math.inf)
    Z, f, D = two.depth_mm, camera.fx, two.baseline_mm
    first = 2 if pattern != "cross" else 3
    counts = [int(views)] if views is not None else range(first, MAX_PLAN_VIEWS + 1)
    for n in counts:
        span, step = _span_for(pattern, n, D, Z)
        if views is not None or f * step / Z <= neighbour_disparity_px:
            break
    else:
        raise InputError(
            f"accuracy_mm = {accuracy_mm:g} mm at {Z:g} mm needs a span of {span:.4g} mm: "
            f"more than {MAX_PLAN_VIEWS} views to keep neighbours within "
            f"{neighbour_disparity_px:g} px; give views or a looser accuracy")
    near, far = depth_range_mm if depth_range_mm is not None else (0.8 * Z, 1.2 * Z)
    limit = camera.width if max_disparity_px is None else max_disparity_px
    if f * span / near > limit:
        raise InputError(
            f"near depth {near:g} mm gives a disparity of {f * span / near:.4g} px between "
            f"the outermost views {span:.4g} mm apart, more than the {limit:g} px of the "
            "image: give a farther near depth or a looser accuracy")
    lo, hi = f * step / far, f * step / near
    return ViewsPlan(views=n, pattern=pattern, span_mm=span, step_mm=step,
                     effective_baseline_mm=D, depth_mm=Z, accuracy_mm=float(accuracy_mm),
                     step_disparity_px=f * step / Z,
                     disparity_range=(float(math.floor(lo)), float(math.ceil(hi))),
                     bound_terms_mm=two.bound_terms_mm)


def _span_for(pattern: str, count: int, baseline_mm: float,
              depth_mm: float) -> tuple[float, float]:
    """Span whose effective baseline is `baseline_mm`, and its step (Notes 2 of
    :func:`plan_views`)."""
    first = "line" if pattern == "arc" else pattern  # the arc's start: a line
    span = baseline_mm / _factor_and_step(first, count, baseline_mm, depth_mm)[0]
    if pattern == "arc":
        for _ in range(20):
            if span >= 2.0 * depth_mm:
                raise InputError(f"an arc of {count} views at {depth_mm:g} mm cannot reach an "
                                 f"effective baseline of {baseline_mm:.4g} mm: the span "
                                 "must be shorter than the circle's diameter; use a line")
            k, _ = _factor_and_step(pattern, count, span, depth_mm)
            new = baseline_mm / k
            if abs(new - span) <= 1e-9 * span:
                break
            span = new
    return span, _factor_and_step(pattern, count, span, depth_mm)[1]


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
    try:
        raw = np.asarray(image)
        if raw.dtype.kind not in "biuf":
            raise TypeError
        img = raw.astype(np.float64)
    except (TypeError, ValueError):
        raise InputError(f"image must be a grey (H, W) array of numbers, got "
                         f"{type(image).__name__}") from None
    if img.ndim != 2 or min(img.shape) < 5:
        raise InputError(f"image must be a grey (H, W) image of at least 5 x 5 pixels, got "
                         f"shape {img.shape}")
    if not np.isfinite(img).all():
        raise InputError("image has NaN or infinite grey levels")
    if np.abs(img).max() > 1e30:
        raise InputError(f"image grey levels must be within +-1e30, got {np.abs(img).max():g}")
    img = img.astype(np.float32)
    for name, v in (("min_crossing_deg", min_crossing_deg), ("threshold", threshold)):
        if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
            raise InputError(f"{name} must be a finite number, got {v!r}")
    if not 0 < min_crossing_deg < 90:
        raise InputError(f"min_crossing_deg must be in (0, 90), got {min_crossing_deg}")
    if not threshold > 0:
        raise InputError(f"threshold must be > 0, got {threshold}")
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
        :func:`robostereo.robot.capture.locate_pair.locate` results (world frame, same robot).
    merge_mm : float
        A point of `second` within this distance of a point of `first` is the same
        edge sample seen twice and is dropped (the first keeps its own bound).

    Returns
    -------
    FusedPoints

    Raises
    ------
    InputError
        An argument without ``world`` (N, 3) and ``z_bound`` (N,) arrays of finite
        numbers (a located point is never NaN: NaN would pass the merge unseen), or a
        bad `merge_mm`.

    Notes
    -----
    A k-d tree of `first`'s points (:class:`scipy.spatial.cKDTree`); each point of
    `second` is dropped when its nearest neighbour there is within `merge_mm`.
    """
    from scipy.spatial import cKDTree

    if isinstance(merge_mm, bool) or not isinstance(merge_mm, int | float) \
            or not math.isfinite(merge_mm):
        raise InputError(f"merge_mm must be a finite number > 0, got {merge_mm!r}")
    require_positive("merge_mm", merge_mm)
    a, za = _located_points("first", first)
    b, zb_b = _located_points("second", second)
    keep = np.ones(len(b), bool)
    if len(a) and len(b):
        d, _ = cKDTree(a).query(b, distance_upper_bound=merge_mm)
        keep = ~np.isfinite(d)
    world = np.vstack([a.reshape(-1, 3), b[keep].reshape(-1, 3)])
    zb = np.concatenate([za, zb_b[keep]])
    cap = np.concatenate([np.zeros(len(a), np.int8), np.ones(int(keep.sum()), np.int8)])
    return FusedPoints(world=world, z_bound=zb, capture=cap, duplicates=int((~keep).sum()))


def _located_points(name: str, located: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``world`` (N, 3) and ``z_bound`` (N,) of a Located, checked."""
    try:
        world = np.asarray(located.world, dtype=np.float64)
        bound = np.asarray(located.z_bound, dtype=np.float64)
    except AttributeError:
        raise InputError(f"{name} must be a Located (with world and z_bound), got "
                         f"{type(located).__name__}") from None
    except (TypeError, ValueError):
        raise InputError(f"{name}: world and z_bound must be arrays of numbers") from None
    if world.ndim != 2 or world.shape[1] != 3 or bound.shape != (world.shape[0],):
        raise InputError(f"{name}: world must be (N, 3) and z_bound (N,), got "
                         f"{world.shape} and {bound.shape}")
    if not (np.isfinite(world).all() and np.isfinite(bound).all()):
        raise InputError(f"{name}: world and z_bound must be finite (NaN or inf found)")
    if np.abs(world).max(initial=0.0) > 1e12:
        raise InputError(f"{name}: world points must be within +-1e12 mm")
    return world, bound
