"""The window matcher's answers: paths in repeated patterns, the narrowed search."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic import layered_pair

from robostereo.errors import InputError
from robostereo.evaluation import match_errors
from robostereo.matcher.confidence import DEFAULT_MODEL
from robostereo.matcher.pipeline import MatchParameters, match_stereo
from robostereo.matcher.window_match import COARSE_MIN_DISPARITIES


def test_paths_carry_the_disparity_into_a_repeated_pattern():
    """Stripes of period 8 between two textured parts, shifted 5 px: a window inside
    the stripes matches 5 and 13 alike; the paths along the rows take 5 from the
    textured parts."""
    rng = np.random.default_rng(11)
    h, w, d, period = 60, 240, 5, 8
    scene = rng.uniform(20, 230, (h, w + d)).astype(np.float32)
    stripes = np.where((np.arange(w + d) // (period // 2)) % 2 == 0, 60.0, 190.0)
    scene[:, 80:170] = stripes[80:170]
    left, right = scene[:, :w], scene[:, d:]  # left x shows what right x - d shows
    left, right = (np.clip(im + rng.normal(0, 2.0, im.shape), 0, 255).astype(np.uint8)
                   for im in (left, right))  # sensor noise of each camera
    with_paths = match_stereo(left, right, (0.0, 16.0))
    without = match_stereo(left, right, (0.0, 16.0),
                           params=MatchParameters(paths=False))
    e = with_paths.left_edges
    inside = (e.x > 110) & (e.x < 140) & (e.row > 6) & (e.row < h - 6)
    assert inside.sum() > 50

    def right_share(res):
        return float(np.mean(np.abs(res.edge_disparity[inside] - d) < 1.0))

    # without the paths the two periods are near-equal; with them nearly all are right
    assert right_share(with_paths) > 0.95
    assert right_share(with_paths) > right_share(without) + 0.1


def test_coarse_search_of_a_wide_range_matches_like_the_tight_one():
    """A generous range (0..150) gives the matches of the true range (4..27) with the
    half-size pass, which searches a fifth of the disparities."""
    rng = np.random.default_rng(5)
    shares = {"tight": [], "coarse": [], "whole": []}
    for _ in range(2):
        left, right, gt = layered_pair(rng, height=200, width=360)
        runs = {"tight": match_stereo(left, right, (4.0, 27.0)),
                "coarse": match_stereo(left, right, (0.0, 150.0)),
                "whole": match_stereo(left, right, (0.0, 150.0),
                                      params=MatchParameters(coarse=False))}
        assert runs["coarse"].window.costs.n_disparities < 60
        assert runs["whole"].window.costs.n_disparities == 151
        for k, res in runs.items():
            e = res.left_edges
            known, err = match_errors(e.row, e.x, res.accepted_disparity(), gt)
            shares[k].append(np.mean(err[known] <= 1.0))
    tight, coarse, whole = (float(np.mean(v)) for v in shares.values())
    assert coarse >= tight - 0.02
    assert coarse >= whole - 0.01


def test_coarse_search_only_for_wide_ranges():
    rng = np.random.default_rng(6)
    left, right, _ = layered_pair(rng, height=120, width=240)
    narrow = (0.0, float(COARSE_MIN_DISPARITIES - 1))
    a = match_stereo(left, right, narrow)
    b = match_stereo(left, right, narrow, params=MatchParameters(coarse=False))
    assert np.array_equal(a.edge_disparity, b.edge_disparity, equal_nan=True)
    assert a.window.costs.n_disparities == COARSE_MIN_DISPARITIES
    with pytest.raises(InputError, match="coarse"):
        MatchParameters(coarse=1)  # type: ignore[arg-type]



def test_costs_made_first_give_the_same_match_and_small_chunks_do_too(monkeypatch):
    """``window_match(..., costs=search_costs(...))`` (the grey images let go between)
    answers as the one call, also when the similarity and the confidence are
    computed a few points at a time; without images or costs it is refused."""
    import importlib

    from robostereo.matcher.edges import detect_edges
    from robostereo.matcher.grey_levels import to_grey

    wm_module = importlib.import_module("robostereo.matcher.window_match")

    rng = np.random.default_rng(7)
    left, right, _ = layered_pair(rng, height=100, width=220)
    gl, gr = to_grey(left), to_grey(right)
    el, er = detect_edges(left), detect_edges(right, threshold=6.0)
    for rng_d in ((0.0, 30.0), (0.0, 100.0)):  # the second through the half-size pass
        whole = wm_module.window_match(el, er, gl, gr, rng_d)
        monkeypatch.setattr(wm_module, "SIMILARITY_CHUNK", 7)
        costs = wm_module.search_costs(el, gl, gr, rng_d)
        split = wm_module.window_match(el, er, None, None, rng_d, costs=costs)
        monkeypatch.undo()
        assert np.isfinite(whole.disparity).sum() > 100
        for name in ("disparity", "right_edge", "features", "confidence"):
            assert np.array_equal(getattr(whole, name), getattr(split, name), equal_nan=True)
        assert whole.costs.d_min == split.costs.d_min
        # the evidence is kept in float32; the confidence was scored from it in float64
        assert whole.features.dtype == np.float32
        has = np.isfinite(whole.confidence)
        assert np.allclose(DEFAULT_MODEL(whole.features)[has], whole.confidence[has],
                           rtol=0, atol=1e-6)
    with pytest.raises(InputError, match="grey images or the costs"):
        wm_module.window_match(el, er, None, None, (0.0, 30.0))
