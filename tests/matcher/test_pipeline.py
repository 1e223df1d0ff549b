"""The whole matcher on synthetic pairs with known fractional disparity."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic import synthetic_pair

from robostereo.errors import InputError
from robostereo.evaluation import score_matches
from robostereo.geometry.triangulation import StereoCamera
from robostereo.matcher.pipeline import MatchParameters, match_stereo


def _rms_against_truth(res, gt, d):
    e = res.left_edges
    cols = np.clip(np.rint(e.x).astype(int), 0, gt.shape[1] - 1)
    truth = gt[e.row, cols]
    ok = np.isfinite(truth) & np.isfinite(d)
    return float(np.sqrt(np.mean((d[ok] - truth[ok]) ** 2)))


@pytest.mark.parametrize("seed", [0, 1, 2, 3, 4])
def test_synthetic_pairs_window_method(seed):
    """Default matcher: the best disparity of nearly every edge point is right; the
    default acceptance keeps most of them with no false one; sub-pixel accurate."""
    rng = np.random.default_rng(seed)
    left, right, gt = synthetic_pair(rng, disparities=(7.3, 11.65, 9.05), noise=1.0)
    res = match_stereo(left, right, (4, 16))
    e = res.left_edges
    best = score_matches(e.row, e.x, res.accepted_disparity(0.0), gt)
    assert best.counted > 1500
    assert best.matched_fraction >= 0.99 and best.false_fraction <= 0.03
    score = score_matches(e.row, e.x, res.accepted_disparity(), gt)
    assert score.matched_fraction >= 0.8
    assert score.false_fraction <= 0.002
    assert _rms_against_truth(res, gt, res.accepted_disparity()) <= 0.1


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_synthetic_pairs_relaxation_method(seed):
    rng = np.random.default_rng(seed)
    left, right, gt = synthetic_pair(rng, disparities=(7.3, 11.65, 9.05), noise=1.0)
    res = match_stereo(left, right, (4, 16), params=MatchParameters(method="relaxation"))
    e = res.left_edges
    score = score_matches(e.row, e.x, res.disparity_of(res.match), gt)
    assert score.counted > 1500
    assert score.matched_fraction >= 0.99
    assert score.false == 0
    assert _rms_against_truth(res, gt, res.disparity_of(res.match)) <= 0.1
    assert np.array_equal(res.accepted_disparity(), res.disparity_of(res.match),
                          equal_nan=True)


def test_thesis_mode_whole_pixels_is_coarser_than_subpixel(rng):
    left, right, gt = synthetic_pair(rng, disparities=(7.3, 11.65), noise=1.0)
    sub = match_stereo(left, right, (4, 16), params=MatchParameters(method="relaxation"))
    pix = match_stereo(left, right, (4, 16), params=MatchParameters.thesis())
    assert np.all(pix.left_edges.x == np.round(pix.left_edges.x))
    s_sub = score_matches(sub.left_edges.row, sub.left_edges.x, sub.disparity_of(sub.match), gt)
    s_pix = score_matches(pix.left_edges.row, pix.left_edges.x, pix.disparity_of(pix.match), gt)
    assert s_pix.rms > 3 * s_sub.rms
    assert s_pix.false == 0


def test_min_confidence_trades_coverage_for_accuracy(rng):
    left, right, _ = synthetic_pair(rng, height=60, width=200)
    counts = [len(match_stereo(left, right, (4, 16), params=MatchParameters(min_confidence=t)))
              for t in (0.0, 0.5, 0.9, 0.99, 1.0)]
    assert counts == sorted(counts, reverse=True) and counts[0] > counts[-1]
    res = match_stereo(left, right, (4, 16))
    assert len(res) == np.count_nonzero(res.edge_confidence >= res.parameters.acceptance)
    assert np.all(res.confidence >= res.parameters.acceptance)
    assert np.all(res.probability == res.confidence)
    with pytest.raises(InputError, match="min_confidence"):
        MatchParameters(min_confidence=1.5)
    with pytest.raises(InputError, match="method"):
        MatchParameters(method="sgm")
    with pytest.raises(InputError, match="edge_blur_px"):
        MatchParameters(edge_blur_px=-1.0)
    with pytest.raises(InputError, match="relaxation"):
        res.matches_after(1)


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
    for method in ("window", "relaxation"):
        res = match_stereo(left, right, (4, 16), camera=cam,
                           params=MatchParameters(method=method))
        assert len(res.left_edges) > 0 and len(res.right_edges) >= len(res.left_edges)
        table = res.table()
        assert {"row", "x_left", "x_right", "disparity", "confidence", "X", "Y",
                "Z", "z_bound"} <= set(table)
        assert np.allclose(table["Z"], 1000.0 * 50.0 / table["disparity"])
        assert np.allclose(table["disparity"], 8.0, atol=0.1)
        edges = res.edge_table()
        assert len(edges["row"]) == len(res.left_edges)
        assert edges["accepted"].sum() == len(res)
        # the best match is kept for every edge point that has one, accepted or not
        assert np.isfinite(edges["confidence"]).sum() >= len(res)
    assert res.window is None and len(res.candidates) >= len(res)
    assert len(res.relaxation.history) == res.relaxation.iterations + 1
    assert set(res.timings) >= {"edges", "candidates", "relaxation", "total"}
    before = res.matches_after(0)
    assert (before >= 0).sum() <= len(res)
    win = match_stereo(left, right, (4, 16))
    assert win.candidates is None and win.window.features.shape[0] == len(win.left_edges)
    assert set(win.timings) >= {"edges", "window", "total"}
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


def test_parabola_disparities_get_a_wider_depth_bound():
    """A match that lands on no right edge point takes its sub-pixel disparity from a
    cost parabola; its eq. (9) bound uses PARABOLA_DISPARITY_UNCERTAINTY_PX, and with
    it every correct match of a half-pixel synthetic pair is within its bound."""
    from robostereo.geometry.triangulation import triangulate
    from robostereo.matcher.pipeline import PARABOLA_DISPARITY_UNCERTAINTY_PX

    left, right, gt = synthetic_pair(np.random.default_rng(3), disparities=(6.5, 9.25))
    cam = StereoCamera(800.0, 800.0, 60.0, disparity_uncertainty_px=0.2)
    res = match_stereo(left, right, (4.0, 12.0), camera=cam)
    dd = res.disparity_uncertainty_px
    on_edge = res.edge_right[res.matched] >= 0
    assert np.all(dd[on_edge] == 0.2)
    assert np.all(dd[~on_edge] == PARABOLA_DISPARITY_UNCERTAINTY_PX) and (~on_edge).any()
    xyz, bound = res.triangulated()
    g = gt[res.rows, np.rint(res.x_left).astype(int)]
    ok = np.isfinite(g) & (np.abs(res.disparity - g) <= 1.0)
    truth, _ = triangulate(cam, res.x_left, res.x_left - g, res.rows, res.image_shape)
    dz = np.abs(xyz[:, 2] - truth[:, 2])
    assert ok.sum() > 100 and np.all(dz[ok] <= bound[ok])


def test_seed_is_a_deprecated_alias_of_thesis():
    with pytest.warns(DeprecationWarning, match=r"thesis\(\)"):
        old = MatchParameters.seed(threshold=6.0)
    assert old == MatchParameters.thesis(threshold=6.0)
    assert old.method == "relaxation" and old.threshold == 6.0


def test_contour_changes_only_the_acceptance():
    """``contour=True`` keeps every disparity and confidence, accepts a superset (the
    contour's support, :func:`~robostereo.matcher.window_match.contour_accepted`), and
    ``accepted_disparity`` at the same level redoes that acceptance."""
    from robostereo.matcher.window_match import contour_accepted

    rng = np.random.default_rng(7)
    left, right, _ = synthetic_pair(rng, disparities=(7.3, 11.65, 9.05), noise=6.0)
    base = match_stereo(left, right, (4, 16))
    res = match_stereo(left, right, (4, 16), params=MatchParameters(contour=True))
    np.testing.assert_array_equal(res.edge_disparity, base.edge_disparity)
    np.testing.assert_array_equal(res.edge_confidence, base.edge_confidence)
    expect = contour_accepted(base.left_edges, base.edge_disparity, base.edge_confidence,
                              base.parameters.acceptance)
    np.testing.assert_array_equal(res.accepted, expect)
    assert np.all(res.accepted[base.accepted]) and res.accepted.sum() > base.accepted.sum()
    again = res.accepted_disparity(res.parameters.acceptance)
    np.testing.assert_array_equal(np.isfinite(again), res.accepted)
    with pytest.raises(InputError, match="contour"):
        MatchParameters(contour=1)  # type: ignore[arg-type]
