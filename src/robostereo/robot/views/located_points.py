"""What the N-view locate reports: :class:`LocatedViews`, each point's bound and confidence.

* :func:`views_bound`: the depth bound of eq. 9 generalised to N views, from the
  least-squares fit's spread (:func:`~robostereo.robot.views.point_refinement.refine_points`);
* :func:`residual_noise_px`, :func:`point_noise_px`: the edge positions' noise the
  fits' residuals show, pooled and per point, which the bound's disparity term takes
  where it exceeds what the capture says;
* :func:`views_confidence`: the probability that a located point is right, a logistic
  function (:data:`CONFIDENCE_WEIGHTS`) of its match's quality, the features
  :func:`confidence_features` gives (:func:`confidence_features_from` for the search's
  fields before the points are gathered).

:func:`~robostereo.robot.views.locating.locate_views` fills them in; the
points voted by the views' edges have a confidence of their own
(:func:`~robostereo.robot.views.edge_votes.votes_confidence`).

References
----------
Kim (1989), the thesis, 3.7 (eq. 6-9).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "CONFIDENCE_WEIGHTS",
    "DISTINCT_FLOOR",
    "MIN_NOISE_FITS",
    "LocatedViews",
    "confidence_features",
    "confidence_features_from",
    "confidence_terms",
    "point_noise_px",
    "residual_noise_px",
    "views_bound",
    "views_confidence",
]

_F = NDArray[np.float64]

DISTINCT_FLOOR = 1e-3
"""The least distinctness :func:`confidence_terms` takes the log of (a best depth a
thousand times better than the next is no surer than that)."""

CONFIDENCE_WEIGHTS = (6.065, -8.304, -1.746, -16.484, -0.842, -0.012, -6.588, -3.152, -0.346)
"""Logistic weights of :func:`views_confidence`: intercept, combined window cost,
distinctness, residual RMS (px), share of the other views used, two-view fit (1 or 0),
share of the views that see the point left out of the fit and against it, unchecked
two-view fit (1 or 0), log of the distinctness (:func:`confidence_terms`).

Fitted by ``benchmarks/fit_views_confidence.py --seeds 0,1,2 --renders dtu
--render-seeds 10,11`` on eight simulated scenes (the hub-pulley from 5 views on a line,
in a cross, from the six-axis arm on a line and in a cross, and from a pair of views;
the block on a line and in a cross; a post before a printed plane), noise seeds 0-2,
and on renders of one family of ``tests/view_renders.py`` (``dtu``: printed textures at
700 mm, views turned and tilted as DTU's) from 3 and 5 views on a line and 5 in a
cross, seeds 10-11, right or wrong by the truth.  With one seed held out at a time the
expected calibration error was 0.001-0.015 on the simulated scenes of 5 views, 0.033-0.039
on the pair, 0.005-0.021 on the renders.  The simulated scenes alone gave the window cost
a positive weight (their untextured views do not tell a right match by it), and on the
real DTU views its points at 0.95-0.99 were right about 82 % of the time; with a
textured family the cost weighs against a match, and held against two views left out
(``benchmarks/bench_real_views.py --held-out``) the reported points' calibration error
went from 0.054 to 0.034.  On render families not fitted (seeds 0-1, the reported
points, right as above) it was 0.002 on ``print`` and ``stripes``, 0.028-0.030 on the
untextured ``base``, ``coarse`` and ``turn``, and 0.046 on the untextured box at 1000 mm
(0.070 before).  The log of the distinctness took the simulated scenes' sure wrong
points (confidence 0.9 or more, seeds held out) from 1018 to 696 (issue 36).  Refitted
when a view left out that cannot tell the depth stopped confirming a fit
(:func:`~robostereo.robot.views.edge_votes.left_out_views`): the real views' error
0.034 -> 0.032, the untextured families' 0.028-0.032 -> 0.031-0.039 (more
under-confident), the six-axis arm's cross's sure wrong points (seeds 0-2) 86, 84, 89
-> 59, 60, 59."""


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
        Other views left out of the fit in which the point falls inside the image and
        that are against it or tell it from the search's next best depth (a view that
        would find an edge at either depth confirms nothing).
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

    def in_views(self, keep: ArrayLike, n: int) -> LocatedViews:
        """These points, located from the views `keep` of a capture of `n`, with
        ``reference`` and ``views`` given in that capture's view indices."""
        k = np.asarray(keep, dtype=np.intp)
        seen = np.zeros((len(self), n), bool)
        seen[:, k] = self.views
        fields = {f: getattr(self, f) for f in self.__dataclass_fields__}
        fields.update(reference=k[self.reference], views=seen)
        return LocatedViews(**fields)

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

    def ply_fields(self) -> dict[str, NDArray[Any]]:
        """The per-point properties a PLY file of these points carries besides x, y, z:
        ``bound_mm``, ``confidence``, ``view_count`` (``locate`` and ``batch`` alike)."""
        return {"bound_mm": self.bound_mm, "confidence": self.confidence,
                "view_count": self.view_count}


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
        (:func:`~robostereo.robot.views.point_refinement.refine_points`).
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


MIN_NOISE_FITS = 30
"""The fewest fits of three or more views :func:`residual_noise_px` pools."""


def residual_noise_px(residual_px: ArrayLike, view_count: ArrayLike) -> float | None:
    """The standard deviation of one view's edge position, pooled from the fits' residuals.

    Parameters
    ----------
    residual_px : array_like, shape (M,)
        Each fit's residual RMS over its ``n`` views, pixels
        (:attr:`LocatedViews.residual_px`).
    view_count : array_like, shape (M,)
        ``n``, the views in each fit (the reference's included).

    Returns
    -------
    float or None
        ``sqrt(sum n r^2 / sum (n - 2))`` over the fits of three or more views (each fit
        spends two of its ``n`` positions on ``t`` and ``1 / Z``); None with fewer than
        :data:`MIN_NOISE_FITS` such fits.

    Notes
    -----
    The residuals show the views' disagreement whatever its cause: the edge detector's
    noise, a lens left undistorted, and pose errors across and along the baselines
    (with three or more views a pose off along one baseline moves that view's edge
    against the others').  Two-view fits meet exactly and say nothing.  A wrong match
    can fit its views well, so this measures the noise of the right ones, not gross
    errors.

    Examples
    --------
    Fits of five views each, every residual 0.1 px RMS: ``0.1 sqrt(5 / 3)``.

    >>> round(residual_noise_px(np.full(40, 0.1), np.full(40, 5)), 4)
    0.1291
    >>> residual_noise_px(np.full(40, 0.1), np.full(40, 2)) is None
    True
    """
    r = np.asarray(residual_px, dtype=float)
    n = np.asarray(view_count, dtype=float)
    k = (n >= 3) & np.isfinite(r)
    if int(k.sum()) < MIN_NOISE_FITS:
        return None
    return float(np.sqrt(np.sum(n[k] * r[k] ** 2) / np.sum(n[k] - 2.0)))


def point_noise_px(residual_px: ArrayLike, view_count: ArrayLike, pooled_px: float, *,
                   prior_dof: float) -> _F:
    """Each fit's edge position noise: its own residuals with the capture's as a prior.

    Parameters
    ----------
    residual_px, view_count : array_like, shape (M,)
        As :func:`residual_noise_px`.
    pooled_px : float
        The capture's noise, :func:`residual_noise_px`.
    prior_dof : float
        The degrees of freedom `pooled_px` counts for beside a fit's own ``n - 2``.

    Returns
    -------
    ndarray, shape (M,)
        ``max(pooled, sqrt((prior_dof pooled^2 + n r^2) / (prior_dof + n - 2)))``;
        `pooled_px` where ``n < 3`` (a fit of two views has no residual).

    Notes
    -----
    The posterior of a normal variance under a scaled inverse chi-squared prior
    ([1]_, 2.6): a fit whose views disagree more than the capture's do gets the wider
    bound it shows.  The noise is not even over a capture: on a render of five views on
    a line with poses jittered as an arm's (``tests/view_renders.py``'s ``dtu``, seed
    0), the fits whose own residuals were above the capture's were outside their
    three-sigma bound of the pooled noise 5.4 % of the time, the others 0.4 %.  A fit
    that agrees better than the capture keeps the capture's noise: three or four
    positions cannot show a small one.

    References
    ----------
    .. [1] Gelman, Carlin, Stern, Dunson, Vehtari & Rubin, *Bayesian Data Analysis*,
       3rd ed., 2013, section 2.6 (a normal variance, the mean known; here the fit's
       ``n - 2`` degrees of freedom).

    Examples
    --------
    >>> point_noise_px([0.0, 0.3, 0.1], [5, 5, 2], 0.1, prior_dof=2.0).round(3).tolist()
    [0.1, 0.307, 0.1]
    """
    r = np.nan_to_num(np.asarray(residual_px, dtype=float))
    n = np.asarray(view_count, dtype=float)
    dof = np.maximum(n - 2.0, 0.0)
    own = np.where(n >= 3, n * r**2, 0.0)
    post = np.sqrt((prior_dof * pooled_px**2 + own) / (prior_dof + dof))
    return np.maximum(pooled_px, post)


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
        A logistic function (:data:`CONFIDENCE_WEIGHTS`) of the seven and the log of the
        distinctness (:func:`confidence_terms`).

    Notes
    -----
    Two views' edge points always meet in one 3-D point, so a two-view fit's residual is
    zero whether the match is right or wrong: it has no degrees of freedom and is no
    evidence.  The two-view indicator lets the model take that back (on the six-axis
    arm's cross of 5 views, a fifth of its two-view points were wrong against 1 % of
    the others, all with zero residual).  What checks such a fit is the views left out
    of it: a view along whose epipolar line the edge runs cannot vote on the depth but
    must still see an edge where the point falls.  A two-view fit with a view against
    it is not reported (``ViewsParameters.check_two_view_fits``); one that no view left
    out can tell from the search's next best depth is unchecked (refitted when that
    replaced "no other view sees it", the unchecked two-view fit's weight went from
    -1.8 to -3.2 and the two-view fit's own from -1.4 to 0); a fit of three or more
    views that a view left out finds no edge for is often a fit to the wrong one of two
    edges.
    """
    terms = confidence_terms(np.column_stack(np.broadcast_arrays(
        *(np.asarray(v, float) for v in (combined, distinct, residual_px, used_share,
                                           two_view, against_share, unchecked)))))
    w = np.asarray(CONFIDENCE_WEIGHTS)
    s = w[0] + terms @ w[1:]
    return 1.0 / (1.0 + np.exp(-s))


def confidence_terms(features: ArrayLike) -> _F:
    """The logistic's terms: the seven features and the log of the distinctness.

    Parameters
    ----------
    features : array_like, shape (M, 7)
        :func:`confidence_features`'s columns.

    Returns
    -------
    ndarray, shape (M, 8)
        The features, then ``log(distinct)`` with the distinctness clipped to
        ``[DISTINCT_FLOOR, 1]`` (NaN stays NaN: a point placed by edge votes).

    Notes
    -----
    The distinctness enters twice because its effect is not linear: a best depth ten or
    a hundred times better than the next (0.1 or 0.01) says much the same, while one
    barely better (0.3 and up: on a repeated structure, often the wrong copy) says a
    great deal.

    Examples
    --------
    >>> t = confidence_terms([[0.02, 0.5, 0.03, 1.0, 0.0, 0.0, 0.0],
    ...                       [0.02, 1e-6, 0.03, 1.0, 0.0, 0.0, 0.0]])
    >>> t.shape, bool(np.isclose(t[0, 7], np.log(0.5))), bool(np.isclose(t[1, 7], np.log(1e-3)))
    ((2, 8), True, True)
    """
    f = np.asarray(features, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.column_stack([f, np.log(np.clip(f[:, 1], DISTINCT_FLOOR, 1.0))])


def confidence_features(located: LocatedViews) -> _F:
    """The features of :func:`views_confidence` for each located point, shape (M, 7):
    window cost, distinctness, residual RMS (px), share of the other views used,
    two-view fit (1.0 or 0.0), share of the views that see the point left out and
    against it, unchecked two-view fit (1.0 or 0.0)."""
    return confidence_features_from(located.window_cost, located.distinct, located.residual_px,
                     located.view_count, located.views_seen, located.views_checked,
                     located.views_against)


def confidence_features_from(combined: _F, distinct: _F, residual_px: _F,
                             view_count: NDArray[np.intp], views_seen: NDArray[np.intp],
                             looked: NDArray[np.intp], against: NDArray[np.intp]) -> _F:
    """:func:`confidence_features` from the points' fields, each shape (M,): the window
    cost, distinctness, residual RMS (px), views in the fit (the reference included),
    other views that see the window, views left out that see the point and those of
    them against it; shape (M, 7)."""
    share = (view_count - 1) / np.maximum(views_seen, 1)
    two = view_count <= 2
    against_share = against / np.maximum(view_count - 1 + looked, 1)
    return np.column_stack([combined, distinct, residual_px, share, two, against_share,
                            two & (looked == 0)]).astype(float)
