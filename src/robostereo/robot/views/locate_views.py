"""Locating edge points from N views (multi-baseline stereo with known poses).

The thesis [3]_ locates an object point from two views (2.2, 3.6) with the eq. 9
bound.  A can grab more views; :func:`locate_views` uses them all, for precision (a long total
baseline [1]_), completeness (views on both sides of an occluder; edges of every
orientation with a cross of viewpoints) and easy matching (short steps between
neighbouring views):

1. every view undistorted, smoothed and differentiated
   (:func:`~robostereo.robot.views.ray_search.prepare_views`);
2. each view in turn is the *reference* (the one nearest the centre of the pattern
   first); its edge points not already located from an earlier reference
   (:func:`~robostereo.robot.views.ray_search.reference_edges`);
3. each edge point's ray searched in inverse depth over the capture's depth range,
   every other view's window scored in that view's own image, the views combined by
   the best half so that occluded views do not vote [2]_
   (:func:`~robostereo.robot.views.ray_search.search_rays`);
4. the 3-D point refined by least squares over the sub-pixel edge points of the views
   that agree (:func:`~robostereo.robot.views.ray_search.refine_points`), its bound
   (:func:`views_bound`, eq. 9 generalised), a confidence;
5. the edge points the search left that enough views' edges agree on, placed by those
   edges (:func:`~robostereo.robot.views.edge_votes.vote_fits`, ``ViewsParameters.edge_votes``);
6. the edge points those views used are marked as located, so the same 3-D point is
   reported once, from the first reference that found it.

References
----------
.. [1] M. Okutomi and T. Kanade, "A multiple-baseline stereo", IEEE PAMI 15(4), 1993.
.. [2] S. B. Kang, R. Szeliski and J. Chai, "Handling occlusions in dense multi-view
   stereo", CVPR 2001.
.. [3] Kim (1989), the thesis, 2.2, 3.1-3.2, 3.6-3.7 (eq. 6-9).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_int, require_positive
from robostereo.matcher.edges import check_edge_blur
from robostereo.robot.views.edge_votes import left_out_views, vote_fits, votes_confidence
from robostereo.robot.views.pose_check import views_epipolar_checks, warn_disagreeing
from robostereo.robot.views.ray_search import (
    prepare_views,
    reference_edges,
    refine_points,
    search_rays,
)
from robostereo.robot.views.viewpoints import ViewsCapture

__all__ = [
    "CONFIDENCE_WEIGHTS",
    "LocatedViews",
    "ViewsParameters",
    "confidence_features",
    "locate_views",
    "reference_order",
    "views_bound",
    "views_confidence",
]

_F = NDArray[np.float64]

CONFIDENCE_WEIGHTS = (7.482, 5.25, -4.392, -19.64, 0.001, -1.09, -7.969, -2.812)
"""Logistic weights of :func:`views_confidence`: intercept, combined window cost,
distinctness, residual RMS (px), share of the other views used, two-view fit (1 or 0),
share of the views that see the point left out of the fit and against it, unchecked
two-view fit (1 or 0).

Fitted by ``benchmarks/fit_views_confidence.py --seeds 0,1,2`` on eight simulated scenes
(the hub-pulley from 5 views on a line, in a cross, from the six-axis arm on a line and
in a cross, and from a pair of views; the block on a line and in a cross; a post before
a printed plane), noise seeds 0-2, right or wrong by the renderings' truth.  With one
seed held out at a time the expected calibration error was 0.0004-0.022 (the pair the
worst).  The five features before these two (fitted once on seed 0, before the edge
points moved off the thesis's smoothed image and before two-view fits were checked)
put the six-axis arm's fits that a view left out finds no edge for (53-61 % right over
seeds 0-6 of its cross of 5) at a mean confidence of 0.64-0.67, and its two-view fits
that the views left out confirm (99.2 % right) at 0.89-0.91."""


@dataclass(frozen=True)
class ViewsParameters:
    """Tuning of :func:`locate_views`.

    Attributes
    ----------
    threshold : float
        Least gradient magnitude of an edge point on the thesis's 0..127 grey scale
        (the matcher's, thesis 3.1: 8.0).
    half_window : int
        The window is ``2 half_window + 1`` pixels square (default 3: 7 x 7).
    step_px : float
        Inverse-depth step of the search, as the largest image motion it causes in any
        view, pixels.
    coarse_step_px : float
        The search first steps this far (pixels, in the farthest view), then at
        `step_px` about the best coarse depth; equal to `step_px` (the default): one
        fine search.  2.0 made the six-axis demo's three locates 2.3 x faster (5.9 to
        2.5 s) but its pulley's false share rose from 3.4 to 4.4 %.
    max_window_cost : float
        A view enters the fit only if its window's ``1 - ZNCC`` at the best depth is at
        most this (0.5: a correlation of 0.5).
    reject_px : float
        A view whose edge point lies farther than this (pixels, normal distance) from
        the fitted point is dropped and the point fitted again.
    min_epipolar_angle_deg : float
        An edge must cross the epipolar line of at least one used view at this angle or
        more (an edge along every epipolar line has no measurable depth: thesis 3.1
        matches along rows only).
    edge_lines : int
        Each sub-pixel edge point is averaged along its edge over this many grid lines
        either side (0: none).  On the simulated block, 2 brought the spread of one
        view's edge positions from 0.013 to 0.009 px.
    drop_sigmas : float or None
        If given, one at a time the view (the reference included) whose residual is
        largest is dropped while it exceeds this many times the residuals' robust spread
        (1.4826 times their median over every point fitted to three or more views) and
        three or more views remain: an edge point moved by a neighbouring edge (a side
        face seen nearly edge-on) disagrees with the views that see it cleanly.  Off by
        default: on the simulated block (5 views on a line over 80 mm) 4 took the lift's
        error from 0.095 to 0.056 mm but the largest error from 0.53-0.60 to 0.88 mm
        (a point 3.5 mm from a corner that dropped the one unbiased view).
    edge_blur_px : float or None
        Gaussian sigma (pixels) of the images whose gradient places the sub-pixel edge
        points (:func:`~robostereo.robot.views.ray_search.prepare_views`); None: the
        thesis's smoothed images, which the search uses.  The thesis's 5 x 5 filter
        merges an edge with a second one within about 2 px (a face seen nearly
        edge-on) and moved it by up to 0.12 px on the simulated block; without any blur
        the edge points are noisier.  The default 0.7 was chosen leave-one-scene-out
        among 0, 0.3, 0.5, 0.7 and None by the mean largest depth error of the block's
        long edges over nine simulated captures of 5 views (the SCARA on a line, seeds
        0-3, and in a cross, seeds 0-1; the six-axis arm on a line, seeds 0-1, and in
        a cross): 0.7 in seven folds, 0.5 in two; its mean 0.50 mm against 0.55 (0),
        0.51 (0.5) and 0.62 mm (None).  The SCARA (image blur 0.6 px) did best with
        0.5-0.7, the six-axis arm (0.9 px, noisier) with 0 (0.71 against 0.77 mm on
        its line).
    check_two_view_fits : bool
        A fit of two views is reported only if every other view in which the point
        falls inside the image (most of them views that cannot vote: the edge runs
        along their epipolar line) finds an edge within `reject_px` of it
        (:func:`~robostereo.robot.views.ray_search.contradicted`).  On the six-axis
        arm's hub-pulley from a cross of 5 views (every point kept) this turned away
        1053 of its 1212 wrong two-view fits and 2 of its 5230 right ones.
    min_views : int
        Views a point's fit must rest on (the reference included), when that many see
        its window: a fit of two views matches exactly whatever it is given, so it
        cannot reveal a wrong match; a third view can (default 3).
    range_step_px : float or None
        If given, the capture's depth range is first narrowed to the part the scene
        holds: a quarter of the first reference's edge points are searched in steps of
        this many pixels and fitted, and the range becomes that of the middle 99 % of
        the depths of those whose confidence reaches `min_confidence`, widened by one
        such step either side (within the capture's range).  None: the capture's
        range as given.  With 3 (the default), 5 views on a line over 80 mm: the
        six-axis demo's pulley (depth range 220-540 mm, the scene 400-535 mm) took
        2.8 s instead of 8.5 s, 1.37 % false instead of 1.41 %, 97.1 % matched instead
        of 96.7 %; the SCARA's pulley 1.0 s instead of 1.4 s, the same points.
    opposite_edge_px : float or None
        An edge point with an edge of opposite polarity within this many pixels along its
        normal (a thin bar, a narrow gap, a ring just beside an occluding rim) is placed
        by a fit of two blurred steps to the grey profile across it, with the view's
        blur estimated from its isolated edges
        (:func:`~robostereo.robot.views.edge_profiles.two_step_edges`), in the reference and in
        every view that enters the fit: the two edges' gradients overlap through the
        blur and push each other's peak apart, by an amount that changes with the gap's
        width and so with the viewpoint.  None: the gradient's peak as elsewhere.  The
        default 4 was chosen leave-one-capture-out among None, 2, 3 and 4 over the
        hub-pulley from 5 views (both robots, a line and a cross, seeds 0-3), by the
        share of edge points without a right point plus the false share: 4 in every
        fold (3 within 0.02 points of it, 2 and None far behind; with a slower blur
        estimate, which differed from today's by up to 0.03 px).  On the six-axis arm
        it took the false share from 0.88-1.19 % to 0.41-0.73 % on a line and from
        0.83-1.02 % to 0.54-0.69 % on a cross; the matched share fell by up to 0.38
        points on the cross, where wrong points near an occluding rim no longer pass
        (the share of edge points with a *right* point rose by 0.10-0.26 points).  The
        SCARA's pulley kept its figures within 0.04 points (its cross's false share
        0.09-0.13 % fell to 0.01 %).
    combine : {'best-half', 'all'}
        How the views' window costs at one depth combine: the mean of the best half of
        the views that see the window (Kang, Szeliski & Chai 2001: a view in which the
        point is hidden does not vote), or of all of them (Okutomi & Kanade's sum).
    min_confidence : float
        Least confidence (:func:`views_confidence`) of a reported point; the others get
        the no-match label (thesis 3.5) and are left out.  0 reports every point.  The
        default 0.71 is the least level at which each of the hub-pulley scenes of 5 views
        of ``benchmarks/fit_views_confidence.py`` (SCARA and six-axis arm, line and
        cross, noise seeds 0-2, the capture's whole depth range) reports at most the
        issue's false share: 0.5 % from the SCARA, 1 % from the six-axis arm.  Chosen
        with one seed held out at a time it was 0.70-0.71, and the seed held out then
        had 0.05-0.15 % false on the SCARA, 0.68-0.99 % on the six-axis arm, keeping
        98.8-100 % of its right points.  A pair of views, every point an unchecked
        two-view fit, pays for it: the SCARA's pulley from 2 views 80 mm apart
        (whole range) reports 7606 points at 4.90 % false instead of 7334 at 4.12 %
        with the earlier five features and 0.79, the six-axis arm's 22.6 % instead of
        20.6 %; such a capture can ask for a higher level.
    edge_votes : int or None
        The reference's edge points the window search leaves (near an occluding edge its
        window holds the occluder and the background, which move apart between views)
        are placed where this many other views' edges agree and no view that sees the
        point disagrees (:func:`~robostereo.robot.views.edge_votes.vote_fits`); their
        ``window_cost`` and ``distinct`` are NaN, their confidence
        :func:`~robostereo.robot.views.edge_votes.votes_confidence`.  None: off; with
        N - 1 below it (a pair, three views) nothing changes.  With 3 (the default) the
        six-axis arm's pulley from a cross of 5 views went from 97.83-98.18 % matched at
        0.65-0.80 % false to 98.09-98.31 % at 0.67-0.81 % (seeds 0-7), its line of 5
        from 98.58-98.81 % to 98.69-98.93 % at 0.62-0.85 %.
    """

    threshold: float = 8.0
    half_window: int = 3
    step_px: float = 0.75
    coarse_step_px: float = 0.75
    max_window_cost: float = 0.5
    reject_px: float = 0.5
    min_epipolar_angle_deg: float = 15.0
    edge_lines: int = 2
    drop_sigmas: float | None = None
    edge_blur_px: float | None = 0.7
    check_two_view_fits: bool = True
    combine: Literal["best-half", "all"] = "best-half"
    min_views: int = 3
    min_confidence: float = 0.71
    range_step_px: float | None = 3.0
    opposite_edge_px: float | None = 4.0
    edge_votes: int | None = 3

    def __post_init__(self) -> None:
        require_positive("threshold", self.threshold)
        hw = self.half_window
        if isinstance(hw, bool) or not isinstance(hw, int | np.integer) or not 1 <= hw <= 10:
            raise InputError(f"half_window must be an integer in 1..10, got {hw!r}")
        require_positive("step_px", self.step_px)
        require_positive("coarse_step_px", self.coarse_step_px)
        if not 0 < self.max_window_cost <= 2:
            raise InputError(f"max_window_cost must be in (0, 2], got {self.max_window_cost!r}")
        require_positive("reject_px", self.reject_px)
        el = self.edge_lines
        if isinstance(el, bool) or not isinstance(el, int | np.integer) or not 0 <= el <= 5:
            raise InputError(f"edge_lines must be an integer in 0..5, got {el!r}")
        mv = self.min_views
        if isinstance(mv, bool) or not isinstance(mv, int | np.integer) or mv < 2:
            raise InputError(f"min_views must be an integer >= 2, got {mv!r}")
        if not 0.0 <= self.min_confidence <= 1.0:
            raise InputError(f"min_confidence must be in 0..1, got {self.min_confidence!r}")
        if self.combine not in ("best-half", "all"):
            raise InputError(f"combine must be 'best-half' or 'all', got {self.combine!r}")
        if self.drop_sigmas is not None:
            require_positive("drop_sigmas", self.drop_sigmas)
        if self.range_step_px is not None:
            require_positive("range_step_px", self.range_step_px)
        check_edge_blur(self.edge_blur_px)
        if self.opposite_edge_px is not None:
            require_positive("opposite_edge_px", self.opposite_edge_px)
        if self.edge_votes is not None:
            require_int("edge_votes", self.edge_votes, minimum=2)
        if not 0 <= self.min_epipolar_angle_deg < 90:
            raise InputError(f"min_epipolar_angle_deg must be in [0, 90), got "
                             f"{self.min_epipolar_angle_deg!r}")


@dataclass(frozen=True, eq=False)
class LocatedViews:
    """Edge points located from N views.

    Attributes
    ----------
    world : ndarray, shape (M, 3)
        World points, mm.
    bound_mm : ndarray, shape (M,)
        Depth bound along the reference's optical axis (:func:`views_bound`), mm.
    confidence : ndarray, shape (M,)
        Probability that the point is right (:func:`views_confidence`).
    view_count : ndarray of int, shape (M,)
        Views that saw the point (the reference included).
    reference : ndarray of int, shape (M,)
        The reference view each point was found from.
    pixel : ndarray, shape (M, 2)
        ``(x, y)`` in the reference view's grabbed image.
    depth_mm : ndarray, shape (M,)
        Depth along the reference's optical axis, mm.
    views : ndarray of bool, shape (M, N)
        Which views saw each point.
    residual_px : ndarray, shape (M,)
        RMS of the fit's normal residuals, pixels.
    window_cost : ndarray, shape (M,)
        The views' combined ``1 - ZNCC`` at the point's depth (NaN: placed by edge votes,
        ``ViewsParameters.edge_votes``).
    distinct : ndarray, shape (M,)
        That cost over the best one at least three depth steps away (small: distinct;
        NaN: placed by edge votes).
    views_seen : ndarray of int, shape (M,)
        Other views whose image holds the point's window.
    views_checked : ndarray of int, shape (M,)
        Other views left out of the fit in which the point falls inside the image.
    views_against : ndarray of int, shape (M,)
        Those of them that find no edge where they see the point
        (:func:`~robostereo.robot.views.edge_votes.left_out_views`).
    """

    world: _F
    bound_mm: _F
    confidence: _F
    view_count: NDArray[np.intp]
    reference: NDArray[np.intp]
    pixel: _F
    depth_mm: _F
    views: NDArray[np.bool_]
    residual_px: _F
    window_cost: _F
    distinct: _F
    views_seen: NDArray[np.intp]
    views_checked: NDArray[np.intp]
    views_against: NDArray[np.intp]

    def __len__(self) -> int:
        return int(self.world.shape[0])

    def subset(self, keep: ArrayLike) -> LocatedViews:
        """The points selected by `keep` (boolean mask or indices, shape (M,))."""
        k = np.asarray(keep)
        return LocatedViews(**{f: getattr(self, f)[k] for f in self.__dataclass_fields__})

    def table(self) -> dict[str, NDArray[Any]]:
        """Columns for a CSV: ``X_w, Y_w, Z_w`` (world mm), ``bound_mm``, ``confidence``,
        ``view_count``, ``reference``, ``u, v`` (reference's grabbed image), ``depth_mm``,
        ``residual_px``."""
        return {
            "X_w": self.world[:, 0], "Y_w": self.world[:, 1], "Z_w": self.world[:, 2],
            "bound_mm": self.bound_mm, "confidence": self.confidence,
            "view_count": self.view_count, "reference": self.reference,
            "u": self.pixel[:, 0], "v": self.pixel[:, 1], "depth_mm": self.depth_mm,
            "residual_px": self.residual_px,
        }


def views_bound(depth_mm: ArrayLike, rho_std_unit: ArrayLike, *, focal_px: float,
                pixel_pitch_mm: float, disparity_uncertainty_px: float,
                baseline_uncertainty_mm: float, focal_length_uncertainty_mm: float
                ) -> _F:
    """Eq. 9 generalised to N views: ``Z dD / D_eff + Z ds / s + Z^2 dd / (f D_eff)``.

    Parameters
    ----------
    depth_mm : array_like, shape (M,)
        ``Z``, depth along the reference's optical axis.
    rho_std_unit : array_like, shape (M,)
        ``sqrt([(J^T J)^-1]_rho)`` of the least-squares fit in ``(t, 1/Z)`` per pixel of
        edge position error in each view
        (:func:`~robostereo.robot.views.ray_search.refine_points`).
    focal_px, pixel_pitch_mm : float
        ``f`` in pixels and the pixel pitch (``s = f pitch`` in mm).
    disparity_uncertainty_px, baseline_uncertainty_mm, focal_length_uncertainty_mm : float
        ``d(disp)``, ``dD`` and ``ds`` of eq. 9.

    Returns
    -------
    ndarray, shape (M,)

    Notes
    -----
    A disparity is the difference of two edge positions, so each view's position is
    given ``d(disp) / sqrt 2``; the fit's inverse depth then has the spread
    ``rho_std_unit d(disp) / sqrt 2`` and the depth ``Z^2`` times that.  The effective
    baseline ``D_eff`` is the one for which eq. 9's disparity term equals this.  For two
    views and an edge across the baseline, ``rho_std_unit = sqrt 2 / (f D)``: eq. 9
    exactly.  For views on a line at ``b_i`` it is ``1 / (f sqrt(sum (b_i - mean b)^2))``:
    the least-squares slope of the edge positions against the baseline.

    Examples
    --------
    Two views 20 mm apart at 1000 mm with the thesis's camera equal eq. 9 (35.3 mm for
    one pixel of disparity, 0.5 + 0.4 + 34.4 mm):

    >>> f = 25.0 / 0.0172
    >>> float(views_bound([1000.0], [np.sqrt(2) / (f * 20.0)], focal_px=f,
    ...     pixel_pitch_mm=0.0172, disparity_uncertainty_px=1.0,
    ...     baseline_uncertainty_mm=0.01, focal_length_uncertainty_mm=0.01)[0]).__round__(1)
    35.3
    """
    z = np.asarray(depth_mm, dtype=float)
    u = np.asarray(rho_std_unit, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        disp_term = z**2 * u * disparity_uncertainty_px / np.sqrt(2.0)
        d_eff = np.sqrt(2.0) / (focal_px * u)
        return (z * baseline_uncertainty_mm / d_eff
                + z * focal_length_uncertainty_mm / (focal_px * pixel_pitch_mm) + disp_term)


def views_confidence(combined: ArrayLike, distinct: ArrayLike, residual_px: ArrayLike,
                     used_share: ArrayLike, two_view: ArrayLike, against_share: ArrayLike,
                     unchecked: ArrayLike) -> _F:
    """Probability that a located point is right, from its match's quality.

    Parameters
    ----------
    combined, distinct, residual_px, used_share : array_like, shape (M,)
        The combined window cost, the distinctness of the best depth (its cost over the
        next best's), the fit's residual RMS (pixels) and the share of the other views
        whose edge point agreed.
    two_view : array_like, shape (M,)
        1 where the fit rests on two views (the reference and one other), else 0.
    against_share : array_like, shape (M,)
        Of the other views that see the point (those in the fit and those left out in
        which it falls inside the image), the share left out that find no edge where
        they see it (:func:`~robostereo.robot.views.edge_votes.left_out_views`).
    unchecked : array_like, shape (M,)
        1 where a two-view fit has no other view in which the point falls, else 0.

    Returns
    -------
    ndarray, shape (M,)
        A logistic function of the seven (:data:`CONFIDENCE_WEIGHTS`).

    Notes
    -----
    Two views' edge points always meet in one 3-D point, so a two-view fit's residual is
    zero whether the match is right or wrong: it has no degrees of freedom and is no
    evidence.  The two-view indicator lets the model take that back (on the six-axis
    arm's cross of 5 views, a fifth of its two-view points were wrong against 1 % of
    the others, all with zero residual).  What checks such a fit is the views left out
    of it: a view along whose epipolar line the edge runs cannot vote on the depth but
    must still see an edge where the point falls.  A two-view fit with a view against
    it is not reported (``ViewsParameters.check_two_view_fits``); one that no other view
    sees is unchecked; a fit of three or more views that a view left out finds no edge
    for is often a fit to the wrong one of two edges.
    """
    w = CONFIDENCE_WEIGHTS
    s = (w[0] + w[1] * np.asarray(combined, float) + w[2] * np.asarray(distinct, float)
         + w[3] * np.asarray(residual_px, float) + w[4] * np.asarray(used_share, float)
         + w[5] * np.asarray(two_view, float) + w[6] * np.asarray(against_share, float)
         + w[7] * np.asarray(unchecked, float))
    return 1.0 / (1.0 + np.exp(-s))


def confidence_features(located: LocatedViews) -> _F:
    """The features of :func:`views_confidence` for each located point, shape (M, 7):
    window cost, distinctness, residual RMS (px), share of the other views used,
    two-view fit (1.0 or 0.0), share of the views that see the point left out and
    against it, unchecked two-view fit (1.0 or 0.0)."""
    return _features(located.window_cost, located.distinct, located.residual_px,
                     located.view_count, located.views_seen, located.views_checked,
                     located.views_against)


def _features(combined: _F, distinct: _F, residual_px: _F, view_count: NDArray[np.intp],
              views_seen: NDArray[np.intp], looked: NDArray[np.intp],
              against: NDArray[np.intp]) -> _F:
    """:func:`confidence_features` from the points' fields, all (M,): (M, 7)."""
    share = (view_count - 1) / np.maximum(views_seen, 1)
    two = view_count <= 2
    against_share = against / np.maximum(view_count - 1 + looked, 1)
    return np.column_stack([combined, distinct, residual_px, share, two, against_share,
                            two & (looked == 0)]).astype(float)


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
                 progress: Callable[[int, int], None] | None = None) -> LocatedViews:
    """Locate the edge points of N views in the world, each with a bound and a confidence.

    Parameters
    ----------
    capture : ViewsCapture
        N >= 2 views with their poses and the expected depth range.
    params : ViewsParameters, optional
    progress : callable, optional
        ``progress(done, total)`` after each reference view.

    Returns
    -------
    LocatedViews
        The points whose confidence reaches ``params.min_confidence``.

    Raises
    ------
    InputError
        `capture` not a :class:`ViewsCapture`, `params` not :class:`ViewsParameters`.

    Notes
    -----
    See the module's steps 1-6.  Two-view captures are located the same way (their
    results differ from :func:`robostereo.robot.capture.locate_pair.locate`'s, which rectifies and
    runs the matcher of chapter 3 and stays as it is).

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
    n = len(capture)
    views = prepare_views(capture, p.edge_blur_px, p.opposite_edge_px)
    h, w = views.smoothed.shape[1:]
    border = p.half_window + 2
    claimed = np.zeros((n, h, w), bool)
    cam = capture.camera
    sine_min = np.sin(np.radians(p.min_epipolar_angle_deg))
    parts: list[dict[str, Any]] = []
    order = reference_order(capture)
    depth_range = capture.depth_range_mm
    # -- the poses against the images: corners of the first reference tracked into the
    #    other views, their distance from the epipolar lines the poses give
    warn_disagreeing(views_epipolar_checks(views, int(order[0]), depth_range))
    # the first reference's edge points serve the narrowing pass too
    first = reference_edges(views, int(order[0]), p.threshold, border, p.edge_lines)
    if p.range_step_px is not None:
        depth_range = _scene_range(capture, views, int(order[0]), first, p, border)
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
            if ok.any():
                _report(parts, claimed, _collect(capture, views, ref, edges, rays, fit, ok,
                                                 n, looks), p, ref, edges, rays, fit, ok)
            if p.edge_votes is not None and n > p.edge_votes and not ok.all():
                _voted(parts, claimed, capture, views, ref, edges.subset(~ok), depth_range,
                       p, border, float(sine_min))
        if progress is not None:
            progress(done + 1, n)
    if not parts:
        return _empty(n)
    cat = {k: np.concatenate([q[k] for q in parts]) for k in parts[0]}
    bound = views_bound(cat["depth"], cat["rho_std"], focal_px=float(views.K[0, 0]),
                        pixel_pitch_mm=cam.pixel_pitch_mm[0],
                        disparity_uncertainty_px=capture.disparity_uncertainty_px,
                        baseline_uncertainty_mm=capture.baseline_uncertainty_mm,
                        focal_length_uncertainty_mm=capture.focal_length_uncertainty_mm)
    count = cat["views"].sum(axis=1)
    return LocatedViews(world=cat["world"], bound_mm=bound, confidence=cat["conf"],
                        view_count=count.astype(np.intp), reference=cat["ref"],
                        pixel=cat["pixel"], depth_mm=cat["depth"], views=cat["views"],
                        residual_px=cat["rms"], window_cost=cat["combined"],
                        distinct=cat["distinct"], views_seen=cat["seen"].astype(np.intp),
                        views_checked=cat["looked"], views_against=cat["against"])


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
            views_confidence(*_features(rays.combined[ok], rays.distinct[ok],
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
