"""Locating edge points from N views (multi-baseline stereo with known poses).

The thesis [3]_ locates an object point from two views (2.2, 3.6) with the eq. 9
bound.  A robot can grab more views; :func:`locate_views` uses them all, for precision (a
long total baseline [1]_), completeness (views on both sides of an occluder; edges of every
orientation with a cross of viewpoints) and easy matching (short steps between
neighbouring views):

1. every view undistorted, smoothed and differentiated
   (:func:`~robostereo.robot.views.prepared_views.prepare_views`);
2. each view in turn is the *reference* (the one nearest the centre of the pattern
   first); its edge points not already located from an earlier reference
   (:func:`~robostereo.robot.views.prepared_views.reference_edges`);
3. each edge point's ray searched in inverse depth over the capture's depth range,
   every other view's window scored in that view's own image, the views combined by
   the best half so that occluded views do not vote [2]_
   (:func:`~robostereo.robot.views.ray_search.search_rays`);
4. the 3-D point refined by least squares over the sub-pixel edge points of the views
   that agree (:func:`~robostereo.robot.views.point_refinement.refine_points`), its bound
   (:func:`~robostereo.robot.views.located_points.views_bound`, eq. 9 generalised), a
   confidence (:func:`~robostereo.robot.views.located_points.views_confidence`);
5. the edge points the search left that enough views' edges agree on, placed by those
   edges (:func:`~robostereo.robot.views.edge_votes.vote_fits`, ``ViewsParameters.edge_votes``);
6. the edge points those views used are marked as located, so the same 3-D point is
   reported once, from the first reference that found it;
7. every bound widened to at least ``ViewsParameters.bound_sigmas`` standard deviations
   of the edge position noise the fits' residuals show
   (:func:`~robostereo.robot.views.located_points.point_noise_px`), and by what the
   reference's pairs disagree on beyond it.

Its tuning is :class:`~robostereo.robot.views.views_parameters.ViewsParameters`, its
result :class:`~robostereo.robot.views.located_points.LocatedViews`.

References
----------
.. [1] M. Okutomi and T. Kanade, "A multiple-baseline stereo", IEEE PAMI 15(4), 1993.
.. [2] S. B. Kang, R. Szeliski and J. Chai, "Handling occlusions in dense multi-view
   stereo", CVPR 2001.
.. [3] Kim (1989), the thesis, 2.2, 3.1-3.2, 3.6-3.7 (eq. 6-9).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, PlausibilityWarning, warn_input
from robostereo.robot.capture.capture_keys import hand_eye_bound_mm, rotation_disparity_px
from robostereo.robot.views.edge_votes import left_out_views, vote_fits, votes_confidence
from robostereo.robot.views.frame_checks import usable_views
from robostereo.robot.views.located_points import (
    LocatedViews,
    confidence_features_from,
    point_noise_px,
    residual_noise_px,
    views_bound,
    views_confidence,
)
from robostereo.robot.views.point_refinement import refine_points
from robostereo.robot.views.pose_check import (
    lone_check,
    lone_of_three,
    pose_offset_px,
    views_epipolar_checks,
    warn_disagreeing,
)
from robostereo.robot.views.prepared_views import prepare_views, reference_edges
from robostereo.robot.views.ray_search import search_rays
from robostereo.robot.views.view_agreement import DOUBTFUL_CONFIDENCE, PairAgreement
from robostereo.robot.views.view_pairs import (
    is_pairs,
    locate_pairs,
    pair_parts,
    views_agreement,
    warn_disagreement,
)
from robostereo.robot.views.viewpoints import ViewsCapture
from robostereo.robot.views.views_parameters import ViewsParameters

__all__ = [
    "MIN_VIEWS_LOCATED_FRACTION",
    "locate_views",
    "reference_order",
    "warn_few_located",
]

MIN_VIEWS_LOCATED_FRACTION = 0.1
"""Fewest of the first reference view's edge points located by its own search, as a
fraction, before :func:`locate_views` warns that the poses are probably in the other
convention or order (measured in ``warn_few_located``'s Notes)."""

MIN_VIEWS_EDGE_POINTS = 200
"""Edge points of the first reference below which the fraction says nothing."""


def warn_few_located(capture: ViewsCapture, ref: int, located: int, edges: int) -> None:
    """Warn when the first reference view located under
    :data:`MIN_VIEWS_LOCATED_FRACTION` of its edge points: the poses are probably
    world-to-camera read as camera-to-world (``pose_convention``) or in the wrong order.

    Notes
    -----
    The first reference's own search (before edge votes) located 74-88 % of its edge
    points on the simulated arms' right poses (block and pulley, SCARA and six-axis,
    2-5 views) and 47-49 % on DTU scan 24's views 0, 1, 2 at half size; the same DTU
    views with their world-to-camera extrinsics read as camera poses located 1.0 %
    (78 of 8017; 32 points in all, where the right poses give 4832) with nothing
    else said.  10 % lies five times below the worst right capture and ten times above
    the mix-up; a scene of few or occluded edges can fall below it rightly, hence a
    warning.
    """
    if edges < MIN_VIEWS_EDGE_POINTS or located >= MIN_VIEWS_LOCATED_FRACTION * edges:
        return
    name = capture.names[ref] if capture.names is not None else str(ref)
    warn_input(f"view {name}: {located} of its {edges} edge points located "
               f"({100.0 * located / edges:.1f} %, under "
               f"{100 * MIN_VIEWS_LOCATED_FRACTION:g} %): are the poses world-to-camera "
               "(set 'pose_convention: world_to_camera') or in the wrong order?")


def reference_order(capture: ViewsCapture) -> NDArray[np.intp]:
    """Views in the order they serve as reference: nearest the pattern's centre first
    (a central view sees most of the scene's points from both sides)."""
    c = capture.centres
    d = np.linalg.norm(c - c.mean(axis=0), axis=1)
    return np.argsort(d, kind="stable").astype(np.intp)


def _empty(n: int) -> LocatedViews:
    z = np.zeros(0)
    return LocatedViews(world=np.zeros((0, 3)), bound_mm=z, confidence=z,
                        view_count=np.zeros(0, np.intp), reference=np.zeros(0, np.intp),
                        pixel=np.zeros((0, 2)), depth_mm=z, views=np.zeros((0, n), bool),
                        residual_px=z, window_cost=z, distinct=z,
                        views_seen=np.zeros(0, np.intp), views_checked=np.zeros(0, np.intp),
                        views_against=np.zeros(0, np.intp))


def locate_views(capture: ViewsCapture, *, params: ViewsParameters | None = None,
                 progress: Callable[[int, int], None] | None = None,
                 source: str = "capture") -> LocatedViews:
    """Locate the edge points of N views in the world, each with a bound and a confidence.

    Parameters
    ----------
    capture : ViewsCapture
        N >= 2 views with their poses and the expected depth range.
    params : ViewsParameters, optional
    progress : callable, optional
        ``progress(done, total)`` after each reference view (``'sweep'``) or pair
        (``'pairs'``).
    source : str
        The capture's name in warnings and errors (its file, when read from one).

    Returns
    -------
    LocatedViews
        ``params.matcher`` ``'pairs'`` (``'auto'``'s for two views): the widest pair's
        points and those ``min_pairs`` pairs agree on
        (:func:`~robostereo.robot.views.view_pairs.locate_pairs`); ``'sweep'``
        (``'auto'``'s for more): the points whose confidence reaches
        ``params.min_confidence``.

    Raises
    ------
    InputError
        `capture` not a :class:`ViewsCapture`, `params` not :class:`ViewsParameters`.

    Notes
    -----
    ``'pairs'``: :mod:`~robostereo.robot.views.view_pairs`'s steps; two views give the
    two-view path's (:func:`robostereo.robot.capture.locate_pair.locate`) points exactly.
    ``'sweep'``: the module's steps 1-7.

    References
    ----------
    Kim (1989), the thesis, 2.2, 3.6-3.7; Okutomi & Kanade 1993; Kang, Szeliski &
    Chai 2001.
    """
    if not isinstance(capture, ViewsCapture):
        raise InputError(f"capture must be a ViewsCapture, got {type(capture).__name__}")
    p = params if params is not None else ViewsParameters()
    if not isinstance(p, ViewsParameters):
        raise InputError(f"params must be a ViewsParameters, got {type(p).__name__}")
    # -- a view grabbed twice, a failed frame (blurred, dark, blank): named, left out
    keep = usable_views(capture, p.min_frame_sharpness, source)
    if len(keep) < len(capture):
        rest = locate_views(capture.subset(keep), progress=progress, source=source,
                            params=replace(p, min_frame_sharpness=None))
        return rest.in_views(keep, len(capture))
    if is_pairs(capture, p):
        return locate_pairs(capture, params=p, progress=progress, source=source)
    # -- the reference's pairs compared on depth: a view off along its baseline named and
    #    left out, what the others disagree by carried by the bounds
    doubtful, agreed = False, None  # the pairs' agreement, held against the bounds below
    if len(capture) >= 3 and p.lone_view_factor is not None:
        lone, agreed = _pair_check(capture, p, source)
        if lone is not None:
            return _without(capture, lone, p, progress, source)
    n = len(capture)
    views = prepare_views(capture, p.edge_blur_px, p.opposite_edge_px)
    h, w = views.smoothed.shape[1:]
    border = p.half_window + 2
    claimed = np.zeros((n, h, w), bool)
    sine_min = np.sin(np.radians(p.min_epipolar_angle_deg))
    parts: list[dict[str, Any]] = []
    order = reference_order(capture)
    depth_range = capture.depth_range_mm
    # -- the poses against the images: corners of the first reference tracked into the
    #    other views, their distance from the epipolar lines the poses give; one view
    #    off them is left out (of three: off the other two's too), more make no point
    #    sure
    checks = views_epipolar_checks(views, int(order[0]), depth_range)
    off = [c for c in checks if c.disagrees]
    c = None
    if p.lone_view_factor is not None:
        c = lone_check(checks, p.lone_view_factor) or lone_of_three(
            views, checks, depth_range, p.lone_view_factor)
    if c is not None:
        warn_input(f"{source}: view {capture.view_name(c.other)}: places tracked into it "
                   f"from view {capture.view_name(c.view)} lie {c.distance_px:.2f} px, "
                   f"{c.angle_deg:.2f} degrees off the epipolar lines its pose gives, where "
                   "the other views agree: it is left out")
        return _without(capture, c.other, p, progress, source)
    warn_disagreeing(checks)
    doubtful = doubtful or bool(off)
    # the first reference's edge points serve the narrowing pass too
    first = reference_edges(views, int(order[0]), p.threshold, border, p.edge_lines)
    if p.range_step_px is not None:
        depth_range = _scene_range(capture, views, int(order[0]), first, p, border)
    first_located = 0
    for done, ref in enumerate(order):
        ref = int(ref)
        edges = (first if done == 0 else
                 reference_edges(views, ref, p.threshold, border, p.edge_lines))
        edges = edges.subset(~claimed[ref, edges.grid[:, 1], edges.grid[:, 0]])
        if len(edges):
            rays = search_rays(views, ref, edges, depth_range,
                               half_window=p.half_window, step_px=p.step_px,
                               min_sine=float(sine_min), combine=p.combine,
                               coarse_px=p.coarse_step_px)
            fit = refine_points(views, ref, edges, rays, max_window_cost=p.max_window_cost,
                                threshold=p.threshold, reject_px=p.reject_px, border=border,
                                lines=p.edge_lines,
                                drop_sigmas=p.drop_sigmas or math.inf)
            ok, looks = _checked(views, ref, edges, rays, fit, p, border, float(sine_min))
            if done == 0:
                first_located = int(ok.sum())
            if ok.any():
                _report(parts, claimed, _collect(capture, views, ref, edges, rays, fit, ok,
                                                 n, looks), p, ref, edges, rays, fit, ok)
            if p.edge_votes is not None and n > p.edge_votes and not ok.all():
                _voted(parts, claimed, capture, views, ref, edges.subset(~ok), depth_range,
                       p, border, float(sine_min))
        if progress is not None:
            progress(done + 1, n)
    warn_few_located(capture, int(order[0]), first_located, len(first))
    if not parts:
        return _empty(n)
    cat = {k: np.concatenate([q[k] for q in parts]) for k in parts[0]}
    # -- the bound: eq. 9 over the fit's spread with what the capture says, and at
    #    least the disparity noise the fits' residuals show (the views' disagreement,
    #    pose errors included), then what the pairs disagree by beyond it
    count = cat["views"].sum(axis=1)
    depth = cat["depth"]
    stated = _bound(capture, views, cat, capture.disparity_uncertainty_px)
    bound = stated
    noise = residual_noise_px(cat["rms"], count) if p.bound_sigmas is not None else None
    if noise is not None:
        noise_px = point_noise_px(cat["rms"], count, noise, prior_dof=p.noise_prior_dof)
        # what the residuals show, and what the poses' offsets across the epipolar
        # lines say they may be off along them by (a fit absorbs a pose error its
        # views share, and its residuals do not show it)
        shown = np.maximum(p.bound_sigmas * math.sqrt(2.0) * noise_px,
                           p.bound_sigmas * pose_offset_px(views, checks,
                                                            capture.depth_range_mm))
        bound = _bound(capture, views, cat,
                       np.maximum(capture.disparity_uncertainty_px, shown))
    if agreed is not None:
        ref, others, agreement = agreed
        worst = float(agreement.beyond_noise.max())
        bound = bound + _beyond(worst, bound, depth) * depth
        # what the capture's own uncertainties miss, more than doubling their bound: said,
        # and no point is sure (however much of it the residuals already show)
        own = float(np.median(stated))
        missed_mm = _beyond(worst, stated, depth) * float(np.median(depth))
        if missed_mm > own:
            warn_disagreement(capture, ref, others, agreement,
                              int(np.argmax(agreement.beyond_noise)), source,
                              carried_mm=missed_mm, typical_mm=own)
            doubtful = True
    if doubtful:  # the views disagree and none can be blamed: no point is sure
        cat["conf"] = np.minimum(cat["conf"], DOUBTFUL_CONFIDENCE)
    return LocatedViews(world=cat["world"], bound_mm=bound, confidence=cat["conf"],
                        view_count=count.astype(np.intp), reference=cat["ref"],
                        pixel=cat["pixel"], depth_mm=cat["depth"], views=cat["views"],
                        residual_px=cat["rms"], window_cost=cat["combined"],
                        distinct=cat["distinct"], views_seen=cat["seen"].astype(np.intp),
                        views_checked=cat["looked"], views_against=cat["against"])


def _without(capture: ViewsCapture, view: int, p: ViewsParameters,
             progress: Callable[[int, int], None] | None, source: str) -> LocatedViews:
    """The capture located without `view` (named in a warning), in the whole capture's
    view indices.

    Two views left go to the pairs matcher, whose bounds are the two-view path's: the
    offset their tracked places share across the epipolar lines
    (:func:`~robostereo.robot.views.pose_check.pose_offset_px`) enters its disparity
    uncertainty, as it enters the sweep's bounds (the named view is seldom the only
    one off: on a line of 3 with every pose turned 0.1 degree, the pair left put 334
    points at confidence 0.9 or more beyond three bounds, none with it)."""
    keep = np.array([k for k in range(len(capture)) if k != view])
    rest = capture.subset(keep)
    if len(rest) == 2 and p.bound_sigmas is not None:
        views = prepare_views(rest, p.edge_blur_px, p.opposite_edge_px)
        near_far = rest.depth_range_mm
        offset_px = p.bound_sigmas * pose_offset_px(
            views, views_epipolar_checks(views, 0, near_far), near_far)
        if offset_px > rest.disparity_uncertainty_px:
            rest = replace(rest, disparity_uncertainty_px=offset_px)
    return locate_views(rest, params=p, progress=progress,
                        source=source).in_views(keep, len(capture))


def _bound(capture: ViewsCapture, views: Any, cat: dict[str, Any],
           disparity_px: float | NDArray[np.float64]) -> NDArray[np.float64]:
    """Each point's depth bound (:func:`views_bound`, the rotation's and the hand-eye's
    terms added) with the disparity uncertainty `disparity_px`, mm, shape (M,)."""
    f = float(views.K[0, 0])
    bound = views_bound(cat["depth"], cat["rho_std"], focal_px=f,
                        pixel_pitch_mm=capture.camera.pixel_pitch_mm[0],
                        disparity_uncertainty_px=disparity_px
                        + rotation_disparity_px(f, capture.rotation_uncertainty_deg),
                        baseline_uncertainty_mm=capture.baseline_uncertainty_mm,
                        focal_length_uncertainty_mm=capture.focal_length_uncertainty_mm)
    return bound + hand_eye_bound_mm(cat["depth"], capture.hand_eye_uncertainty_deg)


def _beyond(worst: float, bound: NDArray[np.float64], depth: NDArray[np.float64]) -> float:
    """How far the pairs' worst relative disagreement `worst` exceeds the median
    relative bound ``bound / depth`` (0 if it does not)."""
    return max(worst - float(np.median(bound / depth)), 0.0)


def _pair_check(capture: ViewsCapture, p: ViewsParameters, source: str
                ) -> tuple[int | None, tuple[int, list[int], PairAgreement] | None]:
    """The pairs' agreement for the sweep: the lone view to leave out (or None) and the
    reference, its pairs' views and their agreement (None with no two pairs), which the
    sweep holds against its own bounds.  The pairs' own warnings (a pair that locates
    little) are the sweep's business and dropped."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PlausibilityWarning)
            ref, views, parts = pair_parts(capture, p, source)
    except InputError:
        return None, None
    if len(parts) < 2:
        return None, None
    lone, agreement, _ = views_agreement(capture, ref, views, parts, p, source,
                                         bounds=False)
    return lone, (ref, views, agreement)


def _scene_range(capture: ViewsCapture, views: Any, ref: int, edges: Any,
                 p: ViewsParameters, border: int) -> tuple[float, float]:
    """The part of the capture's depth range the scene holds, from a coarse search of
    every fourth of view `ref`'s edge points `edges` (see ``ViewsParameters.range_step_px``)."""
    near, far = capture.depth_range_mm
    step = float(p.range_step_px)  # type: ignore[arg-type]
    edges = edges.subset(np.arange(0, len(edges), 4))
    sine_min = float(np.sin(np.radians(p.min_epipolar_angle_deg)))
    if not len(edges):
        return near, far
    rays = search_rays(views, ref, edges, (near, far), half_window=p.half_window,
                       step_px=step, min_sine=sine_min, combine=p.combine, coarse_px=step)
    fit = refine_points(views, ref, edges, rays, max_window_cost=p.max_window_cost,
                        threshold=p.threshold, reject_px=p.reject_px, border=border,
                        lines=p.edge_lines, drop_sigmas=p.drop_sigmas or math.inf)
    ok, looks = _checked(views, ref, edges, rays, fit, p, border, float(sine_min))
    if not ok.any():
        return near, far
    part = _collect(capture, views, ref, edges, rays, fit, ok, len(capture), looks)
    depth = part["depth"][part["conf"] >= p.min_confidence]
    if not len(depth):
        return near, far
    # a coarse step of inverse depth either side, as the search steps them
    reach = float(np.max(np.linalg.norm(views.C - views.C[ref], axis=1)))
    margin = step / (float(views.K[0, 0]) * reach)
    # the middle 99 % of them: a few confident wrong points lie anywhere in the range
    d_lo, d_hi = np.quantile(depth, [0.005, 0.995])
    lo = 1.0 / min(1.0 / float(d_lo) + margin, 1.0 / near)
    hi = 1.0 / max(1.0 / float(d_hi) - margin, 1.0 / far)
    return lo, hi


def _checked(views: Any, ref: int, edges: Any, rays: Any, fit: Any, p: ViewsParameters,
             border: int, sine_min: float
             ) -> tuple[NDArray[np.bool_], tuple[NDArray[np.intp], NDArray[np.intp]]]:
    """The fits that measure depth, rest on enough views and (two-view fits) no view
    contradicts; with the views left out that see each point and those against it."""
    ok = fit.ok & (fit.epipolar_sine >= sine_min)
    # a fit of two views cannot check its match: ask for a third where one exists
    n_fit = fit.used.sum(axis=1) + fit.used_reference
    ok &= n_fit >= np.minimum(p.min_views, 1 + np.isfinite(rays.costs).sum(axis=1))
    looked, against = left_out_views(views, ref, edges, rays, fit, ok,
                                     threshold=p.threshold, reject_px=p.reject_px,
                                     border=border, lines=p.edge_lines)
    if p.check_two_view_fits:
        # and where none votes, a view that cannot vote must still see an edge there
        ok &= ~((n_fit <= 2) & (against > 0))
    return ok, (looked, against)


def _voted(parts: list[dict[str, Any]], claimed: NDArray[np.bool_], capture: ViewsCapture,
           views: Any, ref: int, edges: Any, depth_range: tuple[float, float],
           p: ViewsParameters, border: int, sine_min: float) -> None:
    """The edge points the window search left that ``p.edge_votes`` views' edges agree on
    (:func:`~robostereo.robot.views.edge_votes.vote_fits`), added to `parts` and claimed."""
    edges, rays, fit, ok = vote_fits(
        views, ref, edges, depth_range, min_votes=int(p.edge_votes),  # type: ignore[arg-type]
        min_sine=sine_min, threshold=p.threshold, reject_px=p.reject_px,
        max_window_cost=p.max_window_cost, border=border, lines=p.edge_lines)
    looks = left_out_views(views, ref, edges, rays, fit, ok, threshold=p.threshold,
                           reject_px=p.reject_px, border=border, lines=p.edge_lines)
    ok &= looks[1] == 0  # no window evidence: every view that sees the point must agree
    if ok.any():
        _report(parts, claimed, _collect(capture, views, ref, edges, rays, fit, ok,
                                         len(capture), looks, voted=True),
                p, ref, edges, rays, fit, ok)


def _report(parts: list[dict[str, Any]], claimed: NDArray[np.bool_], part: dict[str, Any],
            p: ViewsParameters, ref: int, edges: Any, rays: Any, fit: Any,
            ok: NDArray[np.bool_]) -> None:
    """Add `part`'s points (the true entries of `ok`) to `parts` and claim their edge
    points; the no-match label: one less likely right than ``p.min_confidence`` is left
    out and claims nothing (`ok` cleared), so another reference may find it."""
    sure = part["conf"] >= p.min_confidence
    ok[np.nonzero(ok)[0][~sure]] = False
    parts.append({k: v[sure] for k, v in part.items()})
    _claim(claimed, ref, rays.others, edges, fit, ok)


def _collect(capture: ViewsCapture, views: Any, ref: int, edges: Any, rays: Any, fit: Any,
             ok: NDArray[np.bool_], n: int,
             looks: tuple[NDArray[np.intp], NDArray[np.intp]],
             voted: bool = False) -> dict[str, Any]:
    """One reference's located points as arrays (`voted`: placed by edge votes)."""
    m = int(ok.sum())
    seen = np.zeros((m, n), bool)
    seen[:, ref] = fit.used_reference[ok]
    seen[:, rays.others] = fit.used[ok]
    world = fit.world[ok]
    pix, _ = capture.camera.project(world, capture.poses[ref])
    n_seen = np.isfinite(rays.costs[ok]).sum(axis=1)
    count = seen.sum(axis=1)
    looked, against = looks[0][ok], looks[1][ok]
    conf = (votes_confidence(fit.residual_rms[ok]) if voted else
            views_confidence(*confidence_features_from(rays.combined[ok], rays.distinct[ok],
                                        fit.residual_rms[ok], count, n_seen, looked,
                                        against).T))
    return {"world": world, "depth": fit.depth[ok], "rho_std": fit.rho_std_unit[ok],
            "views": seen, "ref": np.full(m, ref, np.intp), "pixel": pix,
            "combined": rays.combined[ok], "distinct": rays.distinct[ok],
            "rms": fit.residual_rms[ok], "seen": n_seen, "conf": conf,
            "looked": looked, "against": against}


def _claim(claimed: NDArray[np.bool_], ref: int, others: NDArray[np.intp], edges: Any,
           fit: Any, ok: NDArray[np.bool_]) -> None:
    """Mark the edge pixels (and their grid neighbours) the located points used."""
    h, w = claimed.shape[1:]
    g = edges.grid[ok]
    claimed[ref, g[:, 1], g[:, 0]] = True
    for v, j in enumerate(others):
        use = fit.seen[ok, v]
        e = fit.edge[ok][use, v]
        if not len(e):
            continue
        x = np.rint(e[:, 0]).astype(np.intp)
        y = np.rint(e[:, 1]).astype(np.intp)
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                claimed[j, np.clip(y + dy, 0, h - 1), np.clip(x + dx, 0, w - 1)] = True
