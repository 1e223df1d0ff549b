"""Tuning of the N-view locate: :class:`ViewsParameters`.

:func:`~robostereo.robot.views.locating.locate_views` takes one; each attribute says
what it does, its default and how that default was chosen (on simulated captures with
their truth).

References
----------
Kim (1989), the thesis, 3.1 (the edge threshold), 3.5 (the no-match label), 3.7 (eq. 9).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from robostereo.errors import InputError, require_int, require_positive
from robostereo.matcher.edges import check_edge_blur
from robostereo.robot.capture.locate_pair import LocateParameters

__all__ = ["ViewsParameters"]


@dataclass(frozen=True)
class ViewsParameters:
    """Tuning of :func:`~robostereo.robot.views.locating.locate_views`.

    Attributes
    ----------
    matcher : {'auto', 'pairs', 'sweep'}
        ``'pairs'``: the reference paired with each other view through the two-view
        matcher and the pairs' matches combined
        (:func:`~robostereo.robot.views.view_pairs.locate_pairs`); two views then give
        exactly what the two-view path gives.  ``'sweep'``: the plane sweep of every
        view's windows along each reference ray (:mod:`~robostereo.robot.views.locating`'s
        steps); the attributes from `threshold` to `edge_votes` tune it alone.
        ``'auto'`` (the default): ``'pairs'`` for two views, ``'sweep'`` for more.  On
        issue 34's renders (``benchmarks/bench_views.py --renders``, one run over five
        families) two views by the sweep put 0-19 % of their points more than 2 mm off
        where the pair put 0-2.6 %; with three to nine views on textured scenes the pairs
        put 0.04-5.0 % there against the sweep's 0.24-30 %, but on the simulator's
        hub-pulley they matched 78 % of the edge points against 99.96 % and on the real
        DTU views they report no more points than their widest pair (1978 against the
        sweep's 4875): the two-view matcher is sparse on real views (issue 35).  With 3
        and 5 views the pairs' points were within their bounds (at their pixel) 95.0-100 %
        of the time on the render families, the sweep's 99.2-100 % (`bound_sigmas`), and
        on the textured ones the pairs' confidence was calibrated within 0.002 (the
        sweep's 0.011), but on the untextured box they found 0.62-1.16x the outer pair's
        points where the sweep found 4.5-5.7x.
    agree_px : float
        ``'pairs'``: a pair's point joins another pair's within this many pixels in the
        reference image (when their depths agree within their bounds).
    min_pairs : int
        ``'pairs'``: pairs that must agree on a point of a pair other than the widest
        before it is reported (the widest pair's points are all reported; all the pairs
        when there are fewer).
    pair_match : LocateParameters
        ``'pairs'``: the two-view locate's parameters for each pair (the matcher's).
    min_frame_sharpness : float or None
        A view whose strongest edges reach less than this share of the median view's
        (:func:`~robostereo.robot.views.frame_checks.frame_sharpness`: blurred, dark,
        blank, another bit depth) is named in a warning and left out, while two or more
        views remain (with two, it is warned about only).  None: every view is used.
        0.7 lies below every view of twenty captures of sharp views (0.90-1.21) and
        above every view blurred by a Gaussian of sigma 4 px (0.31-0.50), darkened to a
        fifth (0.19-0.25) or blank; of sigma 2 px it catches 15 of 20 (0.53-0.81).
    lone_view_factor : float or None
        With three or more views (both matchers) the reference's pairs are compared on
        depth (:mod:`~robostereo.robot.views.view_agreement`): a view whose pair disagrees
        with every other pair by more than this many times the largest disagreement
        among the others (a pose off along its baseline) is named and left out, while
        three or more views remain; what disagreement is left widens the bounds, with a
        warning.  None: no comparison (and for ``'sweep'``, no pair located).  4: on
        the real DTU views, correct, the largest pair disagrees 1.5-2x the others'
        (0.22 % against 0.11-0.16 %); a view 2 mm off along a 20 mm baseline, 300x.
        Not None also lets the sweep's pose check leave out the one view whose tracked
        places lie off its epipolar lines where the others' do not
        (:func:`~robostereo.robot.views.pose_check.lone_check`; of three views,
        :func:`~robostereo.robot.views.pose_check.lone_of_three`).
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
        points (:func:`~robostereo.robot.views.prepared_views.prepare_views`); None: the
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
        (:func:`~robostereo.robot.views.edge_votes.left_out_views`).  On the six-axis
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
        Least confidence (:func:`~robostereo.robot.views.located_points.views_confidence`)
        of a reported point; the others get the no-match label (thesis 3.5) and are left
        out.  0 reports every point.  The default 0.67 is the least level at which each of
        the hub-pulley scenes of 5 views of ``benchmarks/fit_views_confidence.py`` (SCARA
        and six-axis arm, line and cross, noise seeds 0-2, the capture's whole depth range)
        reports at most the issue's false share: 0.5 % from the SCARA, 1 % from the six-axis
        arm.  Chosen with one seed held out at a time it was 0.66-0.68, and the seed held
        out then had 0.10-0.15 % false on the SCARA, 0.74-1.00 % on the six-axis arm,
        keeping 98.7-100 % of its right points.  A pair of views, every point an unchecked
        two-view fit, pays for it: the SCARA's pulley from 2 views 80 mm apart (whole range,
        the seed held out) keeps 95.4-95.8 % of its fits at 4.90-5.02 % false; such a
        capture can ask for a higher level (two views go to the pairs by default).
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
    bound_sigmas : float or None
        The sweep's bounds take at least this many standard deviations of the edge position
        noise the fits' residuals show
        (:func:`~robostereo.robot.views.located_points.point_noise_px`), where it exceeds
        the capture's ``disparity_uncertainty_px``: the views' disagreement, a lens or pose
        error included, enters every bound.  None: the capture's figures alone.  3, the
        normal's 99.7 %, was chosen before it was measured.  On issue 34's renders
        (``tests/view_renders.py``, 13 families without recorded pose errors, a line and a
        cross of 5, seeds 0 and 1) the points within their bound went from 71.7-100 % to
        96.5-100 %, below 99.5 % only on the untextured box at 700 and 1000 mm (57-142
        points, one to three outside) and on the ``dtu`` line (99.2 %); the median bound
        grew 1.0-2.1x.  The simulator's pulley went from 96.8-99.2 % to 99.0-99.8 %, its
        block was unchanged.  On real DTU views located from views 1, 2, 3 and from 0, 2, 4,
        the two depths of one pixel of view 2 lay within both bounds 89.3 % of the time,
        53.7 % with the capture's figures alone (``benchmarks/bench_real_views.py
        --bound-agreement``); on three DTU views the median bound went from 1.1 to 3.1 mm
        (their residuals show 0.20 px where the capture's 0.2 px of disparity allows 0.14 px
        a view).  Pose errors a fit's views share leave no residual; the same number of
        standard deviations of the offset the pose check's places share across their
        epipolar lines (:func:`~robostereo.robot.views.pose_check.pose_offset_px`) is
        taken for them: with each recorded pose 0.1 degrees and 0.2 mm off (the renders'
        ``error`` family) the points within their bound went from 17.4-100 % to
        93.6-100 %, and none lies beyond three.
    noise_prior_dof : float
        How many residual degrees of freedom the capture's pooled noise counts for beside
        a fit's own ``n - 2``
        (:func:`~robostereo.robot.views.located_points.point_noise_px`).  Between 1 and
        8 the renders' share within bound moved by at most 0.2 points (the pooled noise
        alone left the ``dtu`` line at 98.5 %); 2 lets a fit of four views weigh its own
        residuals as much as the capture's.
    """

    matcher: Literal["auto", "pairs", "sweep"] = "auto"
    agree_px: float = 1.0
    min_pairs: int = 2
    pair_match: LocateParameters = field(default_factory=LocateParameters)
    min_frame_sharpness: float | None = 0.7
    lone_view_factor: float | None = 4.0
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
    min_confidence: float = 0.67
    range_step_px: float | None = 3.0
    opposite_edge_px: float | None = 4.0
    edge_votes: int | None = 3
    bound_sigmas: float | None = 3.0
    noise_prior_dof: float = 2.0

    def __post_init__(self) -> None:
        if self.matcher not in ("auto", "pairs", "sweep"):
            raise InputError(f"matcher must be 'auto', 'pairs' or 'sweep', got "
                             f"{self.matcher!r}")
        require_positive("agree_px", self.agree_px)
        require_int("min_pairs", self.min_pairs, minimum=1)
        if not isinstance(self.pair_match, LocateParameters):
            raise InputError("pair_match must be a LocateParameters, got "
                             f"{type(self.pair_match).__name__}")
        mfs = self.min_frame_sharpness
        if mfs is not None and not (isinstance(mfs, int | float) and 0 < mfs < 1):
            raise InputError(f"min_frame_sharpness must be in (0, 1) or None, got {mfs!r}")
        if self.lone_view_factor is not None:
            require_positive("lone_view_factor", self.lone_view_factor)
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
        if self.bound_sigmas is not None:
            require_positive("bound_sigmas", self.bound_sigmas)
        require_positive("noise_prior_dof", self.noise_prior_dof)
        if self.opposite_edge_px is not None:
            require_positive("opposite_edge_px", self.opposite_edge_px)
        if self.edge_votes is not None:
            require_int("edge_votes", self.edge_votes, minimum=2)
        if not 0 <= self.min_epipolar_angle_deg < 90:
            raise InputError(f"min_epipolar_angle_deg must be in [0, 90), got "
                             f"{self.min_epipolar_angle_deg!r}")
