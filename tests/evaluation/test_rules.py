"""Tests for the scoring rules (robostereo.evaluation.rules): hand-built rows and maps."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.evaluation import score_matches as reexported
from robostereo.evaluation.rules import (
    coverage_curve,
    depth_step_mask,
    expected_calibration_error,
    match_errors,
    near_steps,
    rule_errors,
    score_matches,
    silhouette_errors,
)
from robostereo.matcher.pipeline import match_stereo

#: a silhouette row: foreground (disparity 20) on pixels 0..9, unknown at 10, background
#: (disparity 12) from 11; grey levels 200 | 60, the intensity edge at x = 11.4
SIL_GT = np.array([[20.0] * 10 + [np.nan] + [12.0] * 9])


def test_the_silhouette_rule_accepts_a_contour_matched_with_the_nearer_disparity() -> None:
    # matched with the foreground's 20: at x = 10.9 the project's rule sees pixels 10
    # (unknown), 11, 12 (background) and calls it false; the silhouette rule also sees
    # pixel 9 (1.9 px away) and calls it right; at 11.4 pixel 9 is 2.4 px away: false
    # by both.  A background edge at 12 with 12.5 is right by both.
    rows, x, d = [0, 0, 0], [11.4, 10.9, 12.0], [20.0, 20.0, 12.5]
    kp, ep = match_errors(rows, x, d, SIL_GT)
    ks, es = silhouette_errors(rows, x, d, SIL_GT)
    assert kp.tolist() == ks.tolist() == [True, True, True]
    assert ep.tolist() == [8.0, 8.0, 0.5]
    assert es.tolist() == [8.0, 0.0, 0.5]
    proj = score_matches(rows, x, d, SIL_GT)
    sil = score_matches(rows, x, d, SIL_GT, rule="silhouette")
    assert (proj.counted, proj.matched, proj.false) == (3, 3, 2)
    assert (sil.counted, sil.matched, sil.false) == (3, 3, 1)
    assert reexported is score_matches


def test_the_silhouette_rule_still_calls_a_wrong_disparity_false() -> None:
    # a background edge given a disparity between the surfaces is wrong under both rules
    k, e = silhouette_errors([0], [10.9], [16.0], SIL_GT)
    assert k.tolist() == [True] and e.tolist() == [4.0]
    assert score_matches([0], [10.9], [16.0], SIL_GT, rule="silhouette").false == 1
    # the radius: pixels j with |j - x| <= radius, the map's border respected
    assert silhouette_errors([0], [0.0], [20.0], SIL_GT, radius=0.0)[1].tolist() == [0.0]
    assert silhouette_errors([0], [18.8], [12.0], SIL_GT)[1].tolist() == [0.0]


def test_a_point_whose_nearest_pixel_is_unknown_is_not_counted_by_either_rule() -> None:
    for rule in ("project", "silhouette"):
        s = score_matches([0], [10.2], [20.0], SIL_GT, rule=rule)
        assert (s.counted, s.matched, s.false) == (0, 0, 0)


def test_unknown_rule_and_bad_subset_are_refused() -> None:
    with pytest.raises(InputError, match="rule must be one of project, silhouette"):
        rule_errors([0], [1.0], [20.0], SIL_GT, rule="kitti")
    with pytest.raises(InputError, match="subset"):
        score_matches([0], [1.0], [20.0], SIL_GT, subset=[1])
    with pytest.raises(InputError, match="x must be finite and inside the map"):
        silhouette_errors([0], [19.6], [20.0], SIL_GT)


def test_subsets_split_the_score_and_the_curve() -> None:
    gt = np.full((1, 8), 5.0)
    rows, x = [0] * 4, [1.0, 2.0, 3.0, 4.0]
    d, conf = [5.0, 9.0, 5.2, np.nan], [0.9, 0.2, 0.8, 0.99]
    near = np.array([True, True, False, False])
    a = score_matches(rows, x, d, gt, subset=near)
    b = score_matches(rows, x, d, gt, subset=~near)
    assert (a.counted, a.matched, a.false) == (2, 2, 1)
    assert (b.counted, b.matched, b.false) == (2, 1, 0)
    c = coverage_curve(rows, x, d, conf, gt, subset=near)
    assert c.coverage.tolist() == [0.5, 1.0] and c.false_rate.tolist() == [0.0, 0.5]


def test_step_mask_marks_a_nine_pixel_band_around_a_jump_of_more_than_two_px() -> None:
    gt = np.full((20, 30), 10.0)
    gt[:, 15:] = 12.5  # a step of 2.5 px between columns 14 and 15
    m = depth_step_mask(gt)
    assert m[10].nonzero()[0].tolist() == list(range(10, 20))  # 14-4 .. 15+4
    assert m.all(axis=0)[10:20].all()
    # a jump of exactly 2 px is no step; unknown pixels make none
    assert not depth_step_mask(np.where(gt > 11, 12.0, gt)).any()
    gt2 = gt.copy()
    gt2[:, 14] = np.nan
    assert not depth_step_mask(gt2).any()
    inf = gt.copy()
    inf[:, 14] = np.inf
    assert not depth_step_mask(inf).any()


def test_step_mask_connectivity_decides_diagonal_neighbours() -> None:
    gt = np.full((9, 9), np.nan)
    gt[4, 4], gt[5, 5] = 3.0, 9.0  # only diagonal neighbours are known
    assert not depth_step_mask(gt, radius=0).any()
    m8 = depth_step_mask(gt, radius=0, connectivity=8)
    assert sorted(zip(*m8.nonzero(), strict=True)) == [(4, 4), (5, 5)]
    with pytest.raises(InputError, match="connectivity must be 4 or 8"):
        depth_step_mask(gt, connectivity=6)


def test_near_steps_reads_the_nearest_pixel() -> None:
    m = np.zeros((3, 6), dtype=bool)
    m[2, 4] = True
    assert near_steps([2, 2, 2, 1], [3.6, 3.4, 4.4, 4.0], m).tolist() == [True, False, True,
                                                                          False]


def test_ece_is_small_for_a_calibrated_predictor_and_large_for_an_overconfident_one() -> None:
    rng = np.random.default_rng(7)
    p = rng.uniform(0, 1, 20000)
    right = rng.uniform(0, 1, p.size) < p
    assert expected_calibration_error(p, right) < 0.02
    # always 95 % sure, right 60 % of the time: ECE near 0.35
    right2 = rng.uniform(0, 1, p.size) < 0.6
    assert expected_calibration_error(np.full(p.size, 0.95), right2) == pytest.approx(
        0.35, abs=0.02)
    # by hand: two bins, each off by 0.25
    assert expected_calibration_error([0.25, 0.25, 0.75, 0.75], [True, True, True, True],
                                      bins=2) == pytest.approx(0.5)
    assert np.isnan(expected_calibration_error([], []))
    with pytest.raises(InputError, match="confidence must be finite numbers in"):
        expected_calibration_error([1.5], [True])


def test_silhouette_rule_never_calls_more_false_than_the_project_rule(real_scenes) -> None:
    """Its pixels include the project's three, so per point its error is no larger; near
    steps it calls fewer matches false over the scenes together (by design: silhouettes)."""
    fewer = 0
    for name, scene in sorted(real_scenes.items()):
        res = match_stereo(scene.left, scene.right, scene.disparity_range)
        e, d, gt = res.left_edges, res.accepted_disparity(), scene.gt_disparity
        _, ep = match_errors(e.row, e.x, d, gt)
        _, es = silhouette_errors(e.row, e.x, d, gt)
        both = np.isfinite(ep)
        assert np.array_equal(both, np.isfinite(es)), name
        assert np.all(es[both] <= ep[both]), name
        near = near_steps(e.row, e.x, depth_step_mask(gt))
        p = score_matches(e.row, e.x, d, gt, subset=near)
        s = score_matches(e.row, e.x, d, gt, subset=near, rule="silhouette")
        assert s.matched == p.matched and s.false <= p.false, name
        fewer += p.false - s.false
    assert len(real_scenes) < 3 or fewer > 0
