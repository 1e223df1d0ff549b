"""Tests for visibility from the ground truth (robostereo.evaluation.visibility)."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.evaluation.visibility import (
    HIDDEN,
    UNKNOWN,
    VISIBLE,
    cross_check_occlusion,
    edge_visibility,
    left_visibility,
    missing_breakdown,
    zbuffer_occlusion,
)
from robostereo.simulation.occluders import occluder_pair


def test_a_hand_made_row_hides_the_band_left_of_a_sub_pixel_occluder() -> None:
    # background on a slant (0.25 px per pixel), an object 3.3 px nearer from x = 20
    bg = 4.0 + 0.25 * np.arange(40)
    row = bg.copy()
    row[20:30] = bg[20] + 3.3
    hidden = zbuffer_occlusion(row[None, :])[0]
    # the right view puts the object's footprint at 19.5 - 12.3 = 7.2 .. 29.5 - 12.3;
    # background pixel j lands at j - (4 + 0.25 j) = 0.75 j - 4: pixels 15..19
    # (pixel 15 at 7.25, just inside; pixel 14 at 6.5)
    assert np.nonzero(hidden)[0].tolist() == [15, 16, 17, 18, 19]
    # the slanted background and the object hide nothing of themselves
    assert not hidden[20:].any()
    assert not zbuffer_occlusion(bg[None, :]).any()


def test_sub_pixel_disparities_use_the_footprint_not_equal_positions() -> None:
    # an object 2.6 px nearer: no right position equals a background one, yet its
    # footprint (2.9 .. 6.9) covers the right positions of pixels 5, 6 and 7
    g = np.array([[2.0] * 8 + [4.6] * 4 + [2.0] * 6])
    assert np.nonzero(zbuffer_occlusion(g)[0])[0].tolist() == [5, 6, 7]


def test_the_cross_check_agrees_with_the_z_buffer_on_a_consistent_pair() -> None:
    gl = np.array([[2.0] * 8 + [6.0] * 4 + [2.0] * 6])
    gr = np.array([[2.0] * 2 + [6.0] * 4 + [2.0] * 12])
    hid, checked = cross_check_occlusion(gl, gr)
    assert hid[0].tolist() == zbuffer_occlusion(gl)[0].tolist()
    v = left_visibility(gl, gr)
    assert v.agreement() == 1.0
    assert v.state[0, :2].tolist() == [HIDDEN, HIDDEN]  # their right positions are off the image
    assert not checked[0, :2].any() and checked[0, 2:].all()
    gl[0, 15] = np.nan
    assert left_visibility(gl, gr).state[0, 15] == UNKNOWN
    with pytest.raises(InputError, match="gt_right"):
        cross_check_occlusion(gl, gr[:, :5])


@pytest.mark.parametrize("seed", [0, 1])
def test_the_z_buffer_finds_the_occluder_pairs_exact_occlusion(seed: int) -> None:
    p = occluder_pair(seed)
    v = left_visibility(p.disparity)
    hidden = (v.state == HIDDEN) & ~v.out_of_view  # the exact mask leaves the border out
    assert v.out_of_view[:, 0].all() and not v.out_of_view[:, 20:].any()
    both = np.sum(hidden & p.occluded)
    union = np.sum(hidden | p.occluded)
    assert p.occluded.sum() > 500
    assert both / union >= 0.93  # measured 0.96-0.97: pixels whose centre is a boundary's
    assert np.mean(hidden == p.occluded) >= 0.99


def test_right_ground_truth_and_z_buffer_agree_on_real_scenes(real_scenes) -> None:
    for name, scene in real_scenes.items():
        if scene.gt_disparity_right is None:
            continue
        v = left_visibility(scene.gt_disparity, scene.gt_disparity_right)
        assert v.agreement() >= 0.97, name  # measured 0.9875-0.9981
        known = v.state != UNKNOWN
        assert 0.01 < np.mean(v.state[known] == HIDDEN) < 0.3, name


def test_an_edge_is_visible_when_a_pixel_near_it_is() -> None:
    s = np.array([[VISIBLE, HIDDEN, HIDDEN, HIDDEN, HIDDEN, UNKNOWN, VISIBLE]], dtype=np.int8)
    x = [0.5, 1.4, 3.4, 4.4, 5.5]
    assert edge_visibility([0] * 5, x, s, reach=1.0).tolist() == [
        VISIBLE, HIDDEN, HIDDEN, UNKNOWN, VISIBLE]
    # the default reach, 1.5 px, also looks one pixel further on the nearer side
    assert edge_visibility([0] * 5, x, s).tolist() == [
        VISIBLE, VISIBLE, HIDDEN, UNKNOWN, VISIBLE]


def test_the_breakdown_sorts_every_point_not_accepted_once() -> None:
    gt = np.full((1, 10), 5.0)
    x = np.arange(1.0, 9.0)
    best = np.array([5.0, 5.0, 5.1, 8.0, np.nan, 5.0, 5.0, 8.0])
    accepted = np.where(np.arange(8) < 2, best, np.nan)
    vis = np.array([1, 1, 1, 1, 1, 0, -1, 1])
    b = missing_breakdown([0] * 8, x, accepted, best, gt, vis)
    assert (b.counted, b.accepted) == (8, 2)
    assert b.counts == {"hidden": 1, "visibility_unknown": 1, "no_candidate": 1,
                        "best_right_refused": 1, "best_wrong": 2}
    near = np.arange(8) >= 4
    assert missing_breakdown([0] * 8, x, accepted, best, gt, vis, subset=near).counted == 4
    with pytest.raises(InputError, match="visibility"):
        missing_breakdown([0] * 8, x, accepted, best, gt, vis[:3])


def test_half_occluded_outline_points_are_seldom_accepted_on_an_occluder_pair() -> None:
    from robostereo.evaluation.outlines import MethodPoints
    from robostereo.evaluation.rules import depth_step_mask, near_steps
    from robostereo.evaluation.visibility import visibility_figures
    from robostereo.matcher.pipeline import match_stereo

    p = occluder_pair(3)
    res = match_stereo(p.left, p.right, p.disparity_range)
    e = res.left_edges
    near = near_steps(e.row, e.x, depth_step_mask(p.disparity))
    vf = visibility_figures(e.row, e.x, p.disparity, near, left_visibility(p.disparity),
                            [MethodPoints("robostereo", res.accepted_disparity(),
                                          res.edge_disparity, res.edge_confidence)],
                            levels=(0.02,))
    pts, s = vf.near_points, vf.scores["robostereo"]
    assert pts["hidden"] > 30 and pts["visible"] > 3 * pts["hidden"]
    # eight pairs pooled: 0.9 % of the hidden accepted, 60 % of the visible
    assert s["hidden"].matched_fraction < 0.1 < 0.4 < s["visible"].matched_fraction
    b = vf.missing["robostereo"]["near"]
    assert b.counts["hidden"] >= 0.9 * pts["hidden"]
    assert vf.coverage["robostereo"]["visible"][0] >= vf.coverage["robostereo"]["all"][0]
