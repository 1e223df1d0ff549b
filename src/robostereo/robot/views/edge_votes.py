"""The N-view locate's checks by the views' edges, and edge points placed by their votes.

:func:`robostereo.robot.views.locating.locate_views` calls these for each reference view:

* :func:`left_out_views`: the views left out of a point's fit that see it, and those
  that find no edge there (a check of two-view fits, which cannot check themselves,
  and evidence against any fit);
* :func:`edge_votes`: for the reference's edge points that the window search left
  (no fit, a fit refused, or a confidence below the level), every depth at which a
  view's epipolar line crosses an edge of the carried-over orientation and polarity,
  and at each the views whose edge lies where they see the point [1]_;
* :func:`vote_fits`: the depths that enough views agree on, refined by least squares
  over those views' edge points
  (:func:`~robostereo.robot.views.point_refinement.refine_points`);
* :func:`votes_confidence`: the probability that such a point is right.

Why a second way: near an occluding edge (a rim or a hub in front of a web or a table)
the ``2 half_window + 1`` square window holds the occluder and the background, which move
apart between views; no view's window fits at the right depth although every view sees
the edge itself where the point projects, and the window search picks a wrong depth or
none.  An edge point is one-dimensional and belongs to the occluder: its position does
not depend on what lies behind it.

References
----------
.. [1] R. T. Collins, "A space-sweep approach to true multi-image matching", CVPR 1996
   (the views' edge features counted at each depth along a ray).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.matcher.parallel import run_all
from robostereo.robot.views.point_refinement import RefinedPoints, refine_points
from robostereo.robot.views.prepared_views import PreparedViews, ReferenceEdges
from robostereo.robot.views.ray_search import (
    RayMatches,
    carried_normals,
    depth_plane_maps,
    epipolar_sines,
    projection_terms,
    ray_directions,
)
from robostereo.robot.views.views_kernels import edge_near, ray_edge_peaks

__all__ = [
    "VOTES_CONFIDENCE_WEIGHTS",
    "EdgeVotes",
    "edge_votes",
    "left_out_views",
    "vote_fits",
    "votes_confidence",
]

_F = NDArray[np.float64]

VOTES_CONFIDENCE_WEIGHTS = (5.425, -16.551)
"""Logistic weights of :func:`votes_confidence`: intercept, residual RMS (px).

Fitted by ``benchmarks/fit_votes_confidence.py --seeds 0,1,2,3`` on the six-axis arm's
hub-pulley from 5 views on a line and in a cross, 2424 voted points, 45 of them wrong by
the renderings' truth; with one seed held out at a time the expected calibration error
was 0.008-0.010."""


def _inside(uv: _F, h: int, w: int, border: int) -> NDArray[np.bool_]:
    with np.errstate(invalid="ignore"):
        return ((uv[..., 0] >= border) & (uv[..., 1] >= border)
                & (uv[..., 0] <= w - 1 - border) & (uv[..., 1] <= h - 1 - border))


@dataclass(frozen=True, eq=False)
class EdgeVotes:
    """The depth the views' edges agree on best, for each reference edge point.

    Attributes
    ----------
    others : int (V,)
        The other views.
    rho : (M,)
        Inverse depth, 1/mm (NaN: no view's epipolar line crosses a matching edge).
    agree : bool (M, V)
        The views with an edge of the carried-over orientation and polarity within
        ``reject_px`` (normal distance) of the point's projection at `rho`.
    looked : bool (M, V)
        The views in which the point at `rho` falls inside the image.
    measuring : bool (M, V)
        The views whose epipolar line crosses the edge at ``asin(min_sine)`` or more.
    affine : (M, V, 2, 2)
        The depth plane's local map of reference pixel offsets to each view's.
    """

    others: NDArray[np.intp]
    rho: _F
    agree: NDArray[np.bool_]
    looked: NDArray[np.bool_]
    measuring: NDArray[np.bool_]
    affine: _F


def _view_candidates(views: PreparedViews, j: int, a: _F, b: _F, normals: _F, grid: _F,
                     drho: float, threshold: float, border: int
                     ) -> tuple[NDArray[np.intp], _F]:
    """Step 1 of :func:`edge_votes` in view `j` for K points: ``a, b`` (K, 3) their
    projection terms, `normals` (K, 2) their carried normals, `grid` (G,) the inverse
    depths `drho` apart.  Returns each candidate's point (index into the K) and its
    inverse depth.  The peaks are found one ray at a time
    (:func:`~robostereo.robot.views.views_kernels.ray_edge_peaks`): on eight real DTU
    views at 800 x 600 the K x G samples as arrays took 2.1 GB and about a third of
    the CPU time (under cProfile, 40 of 123 s)."""
    if not len(a):
        return np.zeros(0, np.intp), np.zeros(0)
    ii, kk, frac = ray_edge_peaks(views.fine_gx[j], views.fine_gy[j],
                                  np.ascontiguousarray(a), np.ascontiguousarray(b),
                                  np.ascontiguousarray(normals), grid, threshold / 2.0,
                                  int(border))
    return ii, grid[kk] + np.clip(frac, -0.5, 0.5) * drho


def edge_votes(views: PreparedViews, ref: int, edges: ReferenceEdges,
               depth_range: tuple[float, float], *, min_sine: float, threshold: float,
               reject_px: float, border: int, lines: int = 2,
               step_px: float = 0.5) -> EdgeVotes:
    """Each edge point's depth that the most views' edges agree on.

    Notes
    -----
    1. Candidates: in each view whose epipolar line crosses the edge at ``asin(min_sine)``
       or more, the inverse depths over `depth_range` in steps that move the point
       `step_px` in that view; where the gradient along the carried-over normal
       (:attr:`~robostereo.robot.views.prepared_views.PreparedViews.fine_gx`) peaks at
       ``threshold / 2`` or more, refined by a parabola.
    2. At each candidate, every other view in which the point falls `border` pixels
       inside the image looks for the sub-pixel edge point nearest its projection
       (:func:`~robostereo.robot.views.views_kernels.edge_near`, within 2 px); it agrees
       if one lies within `reject_px` along the normal.
    3. Per point the candidate with the most agreeing views, then the fewest that see
       the point and disagree, then the least summed distance.
    """
    n = views.smoothed.shape[0]
    others = np.array([j for j in range(n) if j != ref], dtype=np.intp)
    m, nv = len(edges), len(others)
    h, w = views.smoothed.shape[1:]
    near, far = depth_range
    f = float(views.K[0, 0])
    rays = ray_directions(views, ref, edges.pixel)
    a, b = projection_terms(views, ref, others, rays)
    rho_mid = 2.0 / (near + far)
    aff = depth_plane_maps(views, ref, others, edges.pixel, rho_mid)
    measuring = epipolar_sines(a, b, aff, edges.normal, rho_mid) >= min_sine
    normals = carried_normals(aff, edges.normal)
    point, cand = [np.zeros(0, np.intp)], [np.zeros(0)]
    calls, measured = [], []
    for v, j in enumerate(others):
        idx = np.nonzero(measuring[:, v])[0]
        if not len(idx):
            continue
        drho = step_px / (f * max(float(np.linalg.norm(views.C[j] - views.C[ref])), 1e-9))
        grid = np.arange(1.0 / far, 1.0 / near + drho, drho)
        calls.append(lambda j=int(j), v=v, idx=idx, grid=grid, drho=drho: _view_candidates(
            views, j, a[idx, v], b[idx, v], normals[idx, v], grid, drho, threshold, border))
        measured.append(idx)
    # the views on the matcher's threads, their candidates in the views' order
    for idx, (ii, rho_c) in zip(measured, run_all(calls), strict=True):
        point.append(idx[ii])
        cand.append(rho_c)
    ci, cr = np.concatenate(point), np.concatenate(cand)
    rho = np.full(m, np.nan)
    best_agree, best_look = np.zeros((m, nv), bool), np.zeros((m, nv), bool)
    if len(ci):
        world = views.C[ref] + rays[ci] / cr[:, None]
        agree = np.zeros((len(ci), nv), bool)
        look = np.zeros_like(agree)
        off = np.zeros(agree.shape)
        for v, j in enumerate(others):
            uv, z = views.project(world, int(j))
            nj = normals[ci, v]
            k = np.nonzero((z > 0) & _inside(uv, h, w, border) & np.isfinite(nj).all(axis=1))[0]
            o = _edge_offset(views, int(j), uv[k], nj[k], threshold=threshold,
                             border=border, lines=lines)
            look[k, v] = True
            agree[k, v] = o <= reject_px
            off[k, v] = np.where(agree[k, v], o, 0.0)
        order = np.lexsort((off.sum(axis=1), (look & ~agree).sum(axis=1),
                            -agree.sum(axis=1), ci))
        first = order[np.r_[True, ci[order][1:] != ci[order][:-1]]]
        rho[ci[first]] = cr[first]
        best_agree[ci[first]] = agree[first]
        best_look[ci[first]] = look[first]
    return EdgeVotes(others=others, rho=rho, agree=best_agree, looked=best_look,
                     measuring=measuring, affine=aff)


def vote_fits(views: PreparedViews, ref: int, edges: ReferenceEdges,
              depth_range: tuple[float, float], *, min_votes: int, min_sine: float,
              threshold: float, reject_px: float, max_window_cost: float, border: int,
              lines: int = 2
              ) -> tuple[ReferenceEdges, RayMatches, RefinedPoints, NDArray[np.bool_]]:
    """The edge points at least `min_votes` other views' edges agree on, fitted.

    Returns
    -------
    edges : ReferenceEdges
        The points voted on (a subset of `edges`).
    rays : RayMatches
        Their voted depths as :func:`~robostereo.robot.views.ray_search.search_rays`
        would give them: the agreeing views at cost 0, the others not seen; no window
        costs (NaN).
    fit : RefinedPoints
        :func:`~robostereo.robot.views.point_refinement.refine_points` over the agreeing
        views.
    ok : bool (K,)
        Fits that still rest on ``min_votes + 1`` views (the reference included), one of
        which measures the depth (its epipolar line crosses the edge at
        ``asin(min_sine)`` or more).
    """
    votes = edge_votes(views, ref, edges, depth_range, min_sine=min_sine,
                       threshold=threshold, reject_px=reject_px, border=border, lines=lines)
    sel = (np.isfinite(votes.rho) & (votes.agree.sum(axis=1) >= min_votes)
           & (votes.agree & votes.measuring).any(axis=1))
    k = int(sel.sum())
    sub = edges.subset(sel)
    nan = np.full(k, np.nan)
    rays = RayMatches(others=votes.others, rho=votes.rho[sel],
                      costs=np.where(votes.agree[sel], 0.0, np.nan), combined=nan,
                      kept=np.zeros(k), distinct=nan, affine=votes.affine[sel],
                      rho_second=nan)
    fit = refine_points(views, ref, sub, rays, max_window_cost=max_window_cost,
                        threshold=threshold, reject_px=reject_px, border=border,
                        lines=lines, drop_sigmas=np.inf)
    n_fit = fit.used.sum(axis=1) + fit.used_reference
    ok = fit.ok & (fit.epipolar_sine >= min_sine) & (n_fit >= min_votes + 1)
    return sub, rays, fit, ok


def votes_confidence(residual_px: NDArray[np.float64]) -> _F:
    """Probability that a point placed by edge votes is right: a logistic function of its
    fit's residual RMS (px; :data:`VOTES_CONFIDENCE_WEIGHTS`), shape (M,)."""
    w = VOTES_CONFIDENCE_WEIGHTS
    return 1.0 / (1.0 + np.exp(-(w[0] + w[1] * np.asarray(residual_px, float))))


def left_out_views(views: PreparedViews, ref: int, edges: ReferenceEdges, rays: RayMatches,
                   fit: RefinedPoints, check: NDArray[np.bool_], *, threshold: float,
                   reject_px: float, border: int, lines: int = 2
                   ) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """``(looked, against)``: for the points in `check`, the other views left out of a
    point's fit that are against it or tell it from the next best depth, and those of
    them that have no edge where they see it; int, shape (M,) each (0 outside
    `check`).

    Notes
    -----
    A view along whose epipolar line the edge runs does not vote on the depth (its
    window slides along the edge and fits at every depth, :func:`search_rays`), but it
    still sees the edge: the fitted point must fall on an edge of the carried-over
    orientation and polarity in it.  A wrong depth moves the point along the epipolar
    line, which leaves the edge by the motion times the sine of their angle; on the
    repeated rings of the hub-pulley a wrong two-view match lies tens of pixels away,
    several pixels off the edge.  For each view not in the fit in which the point
    falls `border` pixels or more inside the image: the sub-pixel edge point
    (:func:`~robostereo.robot.views.views_kernels.edge_near`, within 2 px) nearest the
    projection; the view is against the point if there is none or it lies more than
    `reject_px` away along the normal.

    Finding the edge confirms the point only where a wrong depth would not have found
    one: the view counts among those that looked when it is against the point, or
    when it tells the fitted depth from the search's next best one
    (``rays.rho_second``, the depth the distinctness is measured against): that depth
    falls more than `reject_px` off the edge in it and on no edge of its own there.
    Where the edge runs along the view's epipolar line, a wrong depth slides along the
    edge and finds it too; on repeated rings, another ring is there.  On the six-axis
    arm's cross of 5 views of the hub-pulley (noise seed 0), 42 of the 50 points of
    confidence 0.9 or more beyond three bounds were two-view fits that two views left
    out "confirmed"; 24 of them fell under 0.9 once a view whose epipolar line runs
    within 15 degrees of the edge stopped confirming (a vertical edge, the views above
    and below), and this rule leaves 20 (with the refitted weights).
    """
    m = len(edges)
    looked, against = np.zeros(m, np.intp), np.zeros(m, np.intp)
    idx = np.nonzero(check & fit.ok)[0]
    if not len(idx):
        return looked, against
    h, w = views.smoothed.shape[1:]
    normals = carried_normals(rays.affine[idx], edges.normal[idx])
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = 1.0 / (rays.rho_second[idx] * fit.depth[idx])  # next best over fitted depth
    for v, j in enumerate(rays.others):
        uv, z = views.project(fit.world[idx], int(j))
        nj = normals[:, v]
        look = (~fit.used[idx, v] & (z > 0) & np.isfinite(uv).all(axis=1)
                & np.isfinite(nj).all(axis=1) & _inside(uv, h, w, border))
        ii = np.nonzero(look)[0]
        if not len(ii):
            continue
        with np.errstate(invalid="ignore"):
            bad = ~(_edge_offset(views, int(j), uv[ii], nj[ii], threshold=threshold,
                                 border=border, lines=lines) <= reject_px)
        # the search's next best depth seen in this view: off the edge, or on it too
        alt, z_alt = views.project(views.C[ref] + (fit.world[idx[ii]] - views.C[ref])
                                   * scale[ii, None], int(j))
        with np.errstate(invalid="ignore"):
            apart = np.abs(((alt - uv[ii]) * nj[ii]).sum(axis=1))
            tells = ~(apart <= reject_px)  # NaN (no next best depth): it tells
            # (a view against the point counts whatever the next best depth does)
            seen = (tells & ~bad & (z_alt > 0) & np.isfinite(alt).all(axis=1)
                    & _inside(alt, h, w, border))
            if seen.any():  # an edge where the next best depth falls too: no telling
                tells[seen] &= ~(_edge_offset(views, int(j), alt[seen], nj[ii][seen],
                                              threshold=threshold, border=border,
                                              lines=lines) <= reject_px)
        looked[idx[ii]] += bad | tells
        against[idx[ii]] += bad
    return looked, against


def _edge_offset(views: PreparedViews, j: int, uv: _F, normal: _F, *, threshold: float,
                 border: int, lines: int) -> _F:
    """How far along the carried `normal` (K, 2) the edge point of view `j` nearest each
    pixel of `uv` (K, 2) lies from it (searched within 2 px; NaN where there is none),
    pixels, shape (K,)."""
    ex, ey, _, _, found = edge_near(views.fine_gx[j], views.fine_gy[j], uv[:, 0], uv[:, 1],
                                    normal[:, 0], normal[:, 1], 2, threshold / 2.0, border,
                                    lines)
    with np.errstate(invalid="ignore"):
        off = np.abs((ex - uv[:, 0]) * normal[:, 0] + (ey - uv[:, 1]) * normal[:, 1])
    return np.where(found, off, np.nan)
