"""The relaxation rule (seed 3.4): coefficients, normalisation and its effect."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.matcher.candidates import find_candidates, group_sum, initial_probabilities
from robostereo.matcher.edges import detect_edges
from robostereo.matcher.relaxation import (
    RelaxationParameters,
    connectivity_coefficient,
    neighbours,
    relax,
)


def test_coefficient_table_of_section_3_4_1():
    t, f = True, False
    cases = {
        # (M-N connected, Q-R connected, Q elsewhere, R elsewhere): b
        (t, t, f, f): 1.0, (t, f, t, f): 0.2, (t, f, f, t): 0.2, (t, f, t, t): 0.0,
        (t, f, f, f): 0.2,
        (f, f, f, f): 1.0, (f, f, t, f): 0.2, (f, f, t, t): 0.2, (f, t, f, f): 0.0,
    }
    for (mn, qr, qe, re), b in cases.items():
        got = connectivity_coefficient(np.array([mn]), np.array([qr]), np.array([qe]),
                                       np.array([re]))
        assert got.item() == b, (mn, qr, qe, re)


def _pair_with_a_tempting_distractor():
    """A vertical edge, and in the right image on row 5 only a closer look-alike.

    The true partner (d = 6) is a connected chain; on row 5 it is weaker, and a
    distractor (d = 13) with exactly the left edge's contrast stands alone.
    """
    h, w = 11, 70
    left = np.zeros((h, w))
    left[:, 40:] = 120
    right = np.zeros((h, w))
    right[:, 34:] = 120
    right[5, 34:] = 100          # weaker true partner on row 5
    right[5, 20:27] = 0
    right[5, 27:34] = 120        # distractor: a rising edge at 26.5 (d = 13.5)
    right[5, 27:] = 120
    right[5, 20:27] = 0
    return left.astype(np.uint8), right.astype(np.uint8)


def test_relaxation_lets_connected_neighbours_outvote_similarity():
    left, right = _pair_with_a_tempting_distractor()
    el, er = detect_edges(left, threshold=4), detect_edges(right, threshold=4)
    c = find_candidates(el, er, (0, 20), profile_scale=None)
    p0, p0n = initial_probabilities(c)
    row5 = np.nonzero(el.row == 5)[0][0]
    sl = slice(c.starts[row5], c.starts[row5 + 1])
    d5 = c.disparity[sl]
    assert len(d5) == 2
    true_k = c.starts[row5] + int(np.argmin(np.abs(d5 - 6)))
    other_k = c.starts[row5] + int(np.argmin(np.abs(d5 - 13.5)))
    res = relax(el, er, c, p0, p0n, params=RelaxationParameters(iterations=5, tolerance=0))
    hist = np.array(res.history)
    assert hist[-1, true_k] > hist[-1, other_k]
    assert hist[-1, true_k] > hist[0, true_k] and hist[-1, other_k] < hist[0, other_k]
    assert res.iterations == 5


def test_probabilities_and_no_match_sum_to_one_every_iteration(rng):
    from synthetic import synthetic_pair

    left, right, _ = synthetic_pair(rng, height=40, width=160)
    el, er = detect_edges(left), detect_edges(right, threshold=6)
    c = find_candidates(el, er, (0, 16))
    p0, p0n = initial_probabilities(c)
    res = relax(el, er, c, p0, p0n, params=RelaxationParameters(iterations=4, tolerance=0))
    has = c.counts > 0
    for p, pn in zip(res.history, res.none_history, strict=True):
        total = group_sum(p, c.starts) + pn
        assert np.allclose(total[has], 1.0)
        assert np.all(p >= 0) and np.all(pn >= 0)


def test_early_stop_when_settled():
    left, right = _pair_with_a_tempting_distractor()
    el, er = detect_edges(left, threshold=4), detect_edges(right, threshold=4)
    c = find_candidates(el, er, (0, 20))
    p0, p0n = initial_probabilities(c)
    res = relax(el, er, c, p0, p0n, params=RelaxationParameters(iterations=200, tolerance=1e-3))
    assert 1 <= res.iterations < 200
    assert len(res.history) == res.iterations + 1


def test_neighbours_are_connected_or_nearest_within_radius():
    img = np.zeros((30, 60), np.uint8)
    img[:, 20:] = 200
    img[10:20, 20:22] = 0   # rows 10-19: 2 px to the right -> not connected, case II
    img[20:, 20:40] = 0     # rows 20-29: far away -> no neighbour across the jump
    e = detect_edges(img, row_step=10, row_offset=5, threshold=4)
    assert e.row.tolist() == [5, 15, 25]
    n, m, conn = neighbours(e, radius=3)
    pairs = {(int(a), int(b), bool(k)) for a, b, k in zip(n, m, conn, strict=True)}
    assert pairs == {(0, 1, False), (1, 0, False)}


def test_parameters_are_checked():
    with pytest.raises(InputError, match="iterations"):
        RelaxationParameters(iterations=-1)
    with pytest.raises(InputError, match="no_match_support"):
        RelaxationParameters(no_match_support=-0.5)
