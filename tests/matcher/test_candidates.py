"""Candidates, similarity indices, initial probabilities and acceptance (seed 3.2-3.5)."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.matcher.candidates import (
    SimilarityWeights,
    assign_matches,
    find_candidates,
    group_max,
    group_sum,
    initial_probabilities,
)
from robostereo.matcher.edges import detect_edges


def _row_image(columns_levels, width=60, height=7):
    """Rows of piecewise-constant grey: ``columns_levels`` = [(start column, level), ...]."""
    row = np.zeros(width)
    for start, level in columns_levels:
        row[start:] = level
    return np.tile(row, (height, 1)).astype(np.uint8)


def test_candidates_same_line_same_sign_inside_range():
    left = _row_image([(30, 200)])                     # one rising edge at 29.5
    right = _row_image([(10, 200), (20, 0), (24, 200), (44, 0)])  # rising 9.5, 23.5; falling
    el, er = detect_edges(left), detect_edges(right)
    c = find_candidates(el, er, (0, 25))
    # every left edge has the two rising right edges (d = 20 and 6) on its own row
    assert np.all(c.counts == 2)
    assert np.all(el.line[c.left] == er.line[c.right])
    assert np.all(er.sign[c.right] == 1)
    assert sorted(set(np.round(c.disparity, 6).tolist())) == [6.0, 20.0]
    narrow = find_candidates(el, er, (5, 10))
    assert np.all(np.round(narrow.disparity, 6) == 6.0)
    assert len(find_candidates(el, er, (30, 40))) == 0


def test_range_keeps_half_a_pixel_beyond_whole_pixel_bounds():
    left = _row_image([(30, 200)])
    right = _row_image([(24, 200)])
    el, er = detect_edges(left), detect_edges(right)
    assert len(find_candidates(el, er, (6.4, 9))) == len(el)     # d = 6 is within 0.5 of 6.4
    assert len(find_candidates(el, er, (6.6, 9))) == 0


def test_similarity_indices_by_hand():
    left = _row_image([(30, 100)])
    right = _row_image([(24, 120)])  # stronger and brighter partner
    el, er = detect_edges(left), detect_edges(right)
    c = find_candidates(el, er, (0, 20), profile_scale=None)
    i = 3  # a middle row: connected above and below on both sides -> pattern difference 0
    k = np.nonzero(c.left == i)[0][0]
    j = c.right[k]
    assert c.gi[k] == pytest.approx(1 / (1 + abs(el.magnitude[i] - er.magnitude[j])))
    assert c.ai[k] == pytest.approx(1 / (1 + abs(el.mean_grey[i] - er.mean_grey[j])))
    assert c.pi[k] == 1.0
    assert c.w[k] == pytest.approx((c.gi[k] + c.pi[k] + c.ai[k]) / 3)
    w2 = find_candidates(el, er, (0, 20), weights=SimilarityWeights(1, 0, 0), profile_scale=None)
    assert w2.w[k] == pytest.approx(c.gi[k])
    # top row: only a lower neighbour on both sides -> still the same type, PI = 1
    assert c.pi[c.left == 0][0] == 1.0


def test_profile_factor_tells_apart_edges_with_other_sides():
    # same rising contrast sign, but the right candidate sits between other grey levels
    left = _row_image([(0, 20), (30, 60)])
    right_good = _row_image([(0, 20), (24, 60)])
    right_bad = _row_image([(0, 80), (24, 120)])
    el = detect_edges(left)
    good = find_candidates(el, detect_edges(right_good), (0, 20))
    bad = find_candidates(el, detect_edges(right_bad), (0, 20))
    assert np.all(good.profile > 0.9) and np.all(bad.profile < 0.01)


def test_initial_probabilities_eq_1_to_3():
    from robostereo.matcher.candidates import Candidates

    w = np.array([0.9, 0.3, 0.6])
    c = Candidates(
        left=np.array([0, 0, 1]), right=np.array([0, 1, 2]), disparity=np.zeros(3),
        gi=w, pi=w, ai=w, profile=np.ones(3), w=w, starts=np.array([0, 2, 3, 3]),
    )
    p, p_none = initial_probabilities(c)
    # edge 0: P(l|m) = 0.9/1.2, 0.3/1.2; P(no match) = 0.1; P0 = P(l|m) * 0.9
    assert p.tolist() == pytest.approx([0.75 * 0.9, 0.25 * 0.9, 0.6])
    assert p_none.tolist() == pytest.approx([0.1, 0.4, 1.0])


def test_group_helpers_handle_empty_groups():
    starts = np.array([0, 0, 3, 3, 4])
    v = np.array([1.0, 5.0, 2.0, 7.0])
    assert group_sum(v, starts).tolist() == [0.0, 8.0, 0.0, 7.0]
    assert group_max(v, starts, empty=-1).tolist() == [-1.0, 5.0, -1.0, 7.0]


def test_assign_one_match_per_right_edge_and_threshold():
    from robostereo.matcher.candidates import Candidates

    c = Candidates(
        left=np.array([0, 1, 2, 2]), right=np.array([7, 7, 8, 9]), disparity=np.arange(4.0),
        gi=np.ones(4), pi=np.ones(4), ai=np.ones(4), profile=np.ones(4), w=np.ones(4),
        starts=np.array([0, 1, 2, 4]),
    )
    prob = np.array([0.9, 0.8, 0.45, 0.4])
    out = assign_matches(c, prob, np.array([0.1, 0.2, 0.15]), 3, min_probability=0.5)
    assert out.tolist() == [0, -1, -1]     # right 7 goes to the more probable left 0
    out = assign_matches(c, prob, np.array([0.1, 0.2, 0.5]), 3, min_probability=0.3)
    assert out.tolist() == [0, -1, -1]     # below its no-match probability
    out = assign_matches(c, prob, np.array([0.1, 0.2, 0.15]), 3, min_probability=0.3)
    assert out.tolist() == [0, -1, 2]


def test_bad_range_and_weights():
    e = detect_edges(_row_image([(30, 200)]))
    with pytest.raises(InputError, match="min <= max"):
        find_candidates(e, e, (10, 2))
    with pytest.raises(InputError, match="finite"):
        find_candidates(e, e, (float("nan"), 2))
    with pytest.raises(InputError, match="weights"):
        SimilarityWeights(-1, 1, 1)


def test_pair_similarity_is_the_seed_formula_and_checks_its_indices(rng):
    """GI, PI, AI, the profile factor and w of random pairs, against the formulas of
    3.2-3.3 written out in NumPy; indices outside the edge sets are refused."""
    from robostereo.matcher.candidates import SimilarityWeights, pair_similarity
    from robostereo.matcher.edge_features import pattern_difference

    img = (rng.uniform(0, 1, (40, 90)) > 0.5).astype(np.uint8) * 200
    left, right = detect_edges(img), detect_edges(np.roll(img, 3, axis=0))
    li, ri = rng.integers(0, len(left), 500), rng.integers(0, len(right), 500)
    weights = SimilarityWeights(2.0, 1.0, 1.0)
    gi, pi, ai, profile, w = pair_similarity(left, right, li, ri, weights=weights,
                                             profile_scale=7.0)
    assert np.allclose(gi, 1 / (1 + np.abs(left.magnitude[li] - right.magnitude[ri])))
    diff = pattern_difference(left.up_offset[li], left.down_offset[li], left.up[li] >= 0,
                              left.down[li] >= 0, right.up_offset[ri], right.down_offset[ri],
                              right.up[ri] >= 0, right.down[ri] >= 0)
    assert np.allclose(pi, 1 / (1 + diff)) and 0 < pi.min() < pi.max() <= 1
    assert np.allclose(ai, 1 / (1 + np.abs(left.mean_grey[li] - right.mean_grey[ri])))
    side = 0.5 * (np.abs(left.grey_before[li] - right.grey_before[ri])
                  + np.abs(left.grey_after[li] - right.grey_after[ri]))
    assert np.allclose(profile, np.exp(-side / 7.0))
    assert np.allclose(w, (0.5 * gi + 0.25 * pi + 0.25 * ai) * profile)
    for bad in ([len(left)], [-1]):
        with pytest.raises(InputError, match="index"):
            pair_similarity(left, right, np.array(bad), np.array([0]))


def test_similarity_of_float32_edge_features_is_taken_in_float64() -> None:
    """The edge sets keep magnitude and the side grey levels in float32; the indices
    are their differences in float64, as with the same values in float64 arrays."""
    import dataclasses

    from robostereo.matcher.candidates import pair_similarity

    rng = np.random.default_rng(3)
    img = rng.integers(0, 256, (40, 120)).astype(np.uint8)
    left, right = detect_edges(img), detect_edges(np.roll(img, -3, axis=1), threshold=6.0)
    assert left.magnitude.dtype == np.float32

    def wide(e):
        return dataclasses.replace(e, **{k: getattr(e, k).astype(np.float64)
                                         for k in ("magnitude", "grey_before", "grey_after")})

    li, ri = rng.integers(0, len(left), 5000), rng.integers(0, len(right), 5000)
    for narrow, widened in zip(pair_similarity(left, right, li, ri),
                               pair_similarity(wide(left), wide(right), li, ri), strict=True):
        assert np.array_equal(narrow, widened)
