"""The whole matcher on synthetic pairs with known fractional disparity."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic import synthetic_pair

from robostereo.errors import InputError
from robostereo.evaluation import score_matches
from robostereo.pipeline import MatchParameters, match_stereo
from robostereo.triangulation import StereoCamera


@pytest.mark.parametrize("seed", [0, 1, 2, 3, 4])
def test_synthetic_pairs_all_matched_none_false_subpixel_accurate(seed):
    rng = np.random.default_rng(seed)
    left, right, gt = synthetic_pair(rng, disparities=(7.3, 11.65, 9.05), noise=1.0)
    res = match_stereo(left, right, (4, 16))
    e = res.left_edges
    score = score_matches(e.row, e.x, res.disparity_of(res.match), gt)
    assert score.counted > 1500
    assert score.matched_fraction >= 0.99
    assert score.false == 0
    # against the exact fractional disparity (not the nearest-pixel rule)
    cols = np.clip(np.rint(e.x).astype(int), 0, gt.shape[1] - 1)
    truth = gt[e.row, cols]
    d = res.disparity_of(res.match)
    ok = np.isfinite(truth) & np.isfinite(d)
    rms = float(np.sqrt(np.mean((d[ok] - truth[ok]) ** 2)))
    assert rms <= 0.1


def test_seed_mode_whole_pixels_is_coarser_than_subpixel(rng):
    left, right, gt = synthetic_pair(rng, disparities=(7.3, 11.65), noise=1.0)
    sub = match_stereo(left, right, (4, 16))
    pix = match_stereo(left, right, (4, 16), params=MatchParameters.seed())
    assert np.all(pix.left_edges.x == np.round(pix.left_edges.x))
    s_sub = score_matches(sub.left_edges.row, sub.left_edges.x, sub.disparity_of(sub.match), gt)
    s_pix = score_matches(pix.left_edges.row, pix.left_edges.x, pix.disparity_of(pix.match), gt)
    assert s_pix.rms > 3 * s_sub.rms
    assert s_pix.false == 0


def test_bit_depth_and_colour_give_the_same_matches(rng):
    left, right, _ = synthetic_pair(rng, height=60, width=200)
    base = match_stereo(left, right, (4, 16))
    deep = match_stereo(left.astype(np.uint16) * 257, right.astype(np.uint16) * 257, (4, 16))
    rgb = match_stereo(np.dstack([left] * 3), np.dstack([right] * 3), (4, 16))
    for other in (deep, rgb):
        assert len(other) == len(base)
        assert np.allclose(other.disparity, base.disparity, atol=1e-3)


def test_stages_stay_reachable_and_3d_with_camera(rng):
    left, right, _gt = synthetic_pair(rng, height=60, width=200, disparities=(8.0,))
    cam = StereoCamera(fx=1000.0, fy=1000.0, baseline_mm=50.0)
    res = match_stereo(left, right, (4, 16), camera=cam)
    assert len(res.left_edges) > 0 and len(res.right_edges) >= len(res.left_edges)
    assert len(res.candidates) >= len(res)
    assert len(res.relaxation.history) == res.relaxation.iterations + 1
    assert set(res.timings) >= {"edges", "candidates", "relaxation", "total"}
    table = res.table()
    assert {"row", "x_left", "x_right", "disparity", "probability", "X", "Y", "Z",
            "z_bound"} <= set(table)
    assert np.allclose(table["Z"], 1000.0 * 50.0 / table["disparity"])
    assert np.allclose(table["disparity"], 8.0, atol=0.1)
    edges = res.edge_table()
    assert len(edges["row"]) == len(res.left_edges)
    assert np.isnan(edges["x_right"]).sum() == len(res.left_edges) - len(res)
    before = res.matches_after(0)
    assert (before >= 0).sum() <= len(res)
    with pytest.raises(InputError, match="camera"):
        match_stereo(left, right, (4, 16)).triangulated()


def test_no_edges_gives_an_empty_result_not_a_crash():
    flat = np.full((40, 60), 90, np.uint8)
    res = match_stereo(flat, flat, (0, 10))
    assert len(res) == 0 and len(res.left_edges) == 0
    assert res.table()["row"].shape == (0,)


@pytest.mark.parametrize(
    ("left", "right", "rng_", "message"),
    [
        (np.zeros((20, 30), np.uint8), np.zeros((20, 31), np.uint8), (0, 5), "differ in size"),
        (np.zeros((0, 0), np.uint8), np.zeros((0, 0), np.uint8), (0, 5), "empty"),
        (np.zeros((20, 30), np.uint8), np.zeros((20, 30), np.uint8), (6, 5), "empty"),
        (np.zeros((20, 30), np.uint8), np.zeros((20, 30), np.uint8), (0, np.nan), "finite"),
    ],
)
def test_bad_input(left, right, rng_, message):
    with pytest.raises(InputError, match=message):
        match_stereo(left, right, rng_)
