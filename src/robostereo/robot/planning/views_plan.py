"""Planning N views: the span whose eq. 9 bound over N views is a wanted accuracy.

:func:`plan_views` does what
:func:`~robostereo.robot.planning.baseline_plan.plan_baseline` does (eq. 9 inverted,
thesis 3.7) for N views in a pattern
(:func:`~robostereo.robot.views.viewpoints.view_offsets`): the span whose least-squares
depth bound over the N views is the wanted accuracy, and the number of views that
keeps neighbouring views close enough to match easily (:class:`ViewsPlan`).
:func:`views_baseline_factor` gives the two-view baseline whose bound the N views'
equals.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_positive
from robostereo.geometry.camera import Camera
from robostereo.robot.planning.baseline_plan import plan_baseline

__all__ = [
    "NEIGHBOUR_DISPARITY_PX",
    "ViewsPlan",
    "plan_views",
    "views_baseline_factor",
]


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
        As :func:`~robostereo.robot.planning.baseline_plan.plan_baseline`; `max_disparity_px` bounds
        the disparity between the outermost views at the near depth (the object must be
        in every view).
    neighbour_disparity_px : float
        Most disparity between neighbouring views at the target depth when the count is
        proposed (:data:`NEIGHBOUR_DISPARITY_PX`).

    Returns
    -------
    ViewsPlan

    Raises
    ------
    InputError
        The checks of :func:`~robostereo.robot.planning.baseline_plan.plan_baseline`; a bad `views`
        or `pattern`; an arc whose span reaches the diameter of its circle; more than 100
        views needed; outermost views too far apart to both see the object at the near
        depth.

    Notes
    -----
    1. :func:`~robostereo.robot.planning.baseline_plan.plan_baseline` gives the two-view baseline
       ``D`` of the wanted bound.
    2. N views of span ``S`` bound the depth as a pair ``D_eff = k S`` apart does
       (:func:`views_baseline_factor`), so ``S = D / k``; an arc, whose ``k`` changes a
       little with the span, is solved by repeating ``S <- S D / D_eff(S)``.
    3. Without `views`, N grows from 2 until the step between neighbours, ``S / (N -
       1)`` on a line, shows at most `neighbour_disparity_px` at the target depth.

    The bound assumes every view sees the point with the same edge localisation error,
    independently, and that each view's offset is known to ``dD / sqrt(2)``; it does not
    count the views in which the point is hidden (an occluder): those add nothing.
    With two views on a line this is exactly
    :func:`~robostereo.robot.planning.baseline_plan.plan_baseline`.

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
