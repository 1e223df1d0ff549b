"""The confidence model: isotonic fit, monotone in the evidence, calibrated."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic import layered_pair

from robostereo.errors import InputError
from robostereo.evaluation import coverage_curve, match_errors
from robostereo.matcher.confidence import (
    DEFAULT_MODEL,
    FEATURES,
    ConfidenceModel,
    calibration_table,
    fit_confidence,
    isotonic,
    swapped_matches,
)
from robostereo.matcher.pipeline import match_stereo


def test_isotonic_and_the_model():
    _, ky = isotonic([0, 1, 2, 3, 4], [0.0, 1.0, 0.0, 1.0, 1.0])
    assert np.all(np.diff(ky) >= 0) and ky[-1] == 1.0
    with pytest.raises(InputError, match="non-decreasing"):
        ConfidenceModel((0.0, 1.0), (0.9, 0.1))
    with pytest.raises(InputError, match="features"):
        DEFAULT_MODEL(np.zeros((3, 2)))
    # more evidence never lowers the confidence
    f = np.zeros((50, len(FEATURES)))
    f[:, 0] = f[:, 1] = np.linspace(0, 1, 50)
    f[:, 3] = 1.0
    p = DEFAULT_MODEL(f)
    assert np.all(np.diff(p) >= 0) and 0.0 <= p[0] < p[-1] <= 1.0


def _plain_score(m: ConfidenceModel, f: np.ndarray) -> np.ndarray:
    """The score as the class documents it, in numpy (the kernel's reference)."""
    col = {name: f[:, k] for k, name in enumerate(FEATURES)}
    edge = m.right_edge_weight * col["right_edge"] + m.similarity_weight * col["similarity"]
    windows = (np.minimum(col["uniqueness"], col["uniqueness_row"])
               - (1.0 - col["left_right"]) + edge + m.row_agree_weight * col["row_agree"])
    u = col["path_uniqueness"]
    return np.where(col["path_agree"] > 0, windows + m.path_weight * u,
                    np.where(swapped_matches(f), u - 1.0 + m.swap_weight + edge,
                             windows - 1.0))


def test_the_score_kernel_is_the_plain_score_bit_for_bit():
    """Every case of the score (paths agree, swapped, kept), NaN features, weights that
    round: the kernel's scores equal numpy's exactly (the confidences stay the same)."""
    rng = np.random.default_rng(7)
    f = rng.uniform(0, 1, (4000, len(FEATURES)))
    for name in ("row_agree", "left_right", "right_edge", "path_agree", "path_swapped"):
        f[:, FEATURES.index(name)] = rng.integers(0, 2, 4000)
    f[::97, FEATURES.index("uniqueness_row")] = np.nan
    f[::89, FEATURES.index("uniqueness")] = np.nan
    m = ConfidenceModel((-1.0, 0.0, 1.0), (0.1, 0.5, 0.9), right_edge_weight=0.1 / 3,
                        similarity_weight=0.7, row_agree_weight=1e-3, path_weight=0.3,
                        swap_weight=0.61)
    for model in (m, DEFAULT_MODEL):
        got, want = model.score(f), _plain_score(model, f)
        assert np.array_equal(got, want, equal_nan=True)
        assert np.array_equal(model.score(f[::3]), want[::3], equal_nan=True)  # strided
    assert np.isnan(got).sum() > 60 and {0.0, 1.0} <= set(np.round(f[:, 7]))


def test_confidence_on_synthetic_occlusions_is_calibrated_and_informative():
    """Layered pairs the model was not fitted on: the confidence curve fitted on two
    pairs is calibrated on a third, and the most confident matches are the cleanest."""
    rng = np.random.default_rng(77)
    sets = []
    for _ in range(3):
        left, right, gt = layered_pair(rng, height=160, width=300)
        res = match_stereo(left, right, (4.0, 27.0))
        e = res.left_edges
        known, err = match_errors(e.row, e.x, res.edge_disparity, gt)
        take = known & np.isfinite(err)
        sets.append((res.window.features[take], err[take] <= 1.0, res, gt))
    x = np.concatenate([s[0] for s in sets[:2]])
    y = np.concatenate([s[1] for s in sets[:2]])
    model = fit_confidence(x, y)
    f, ok, res, gt = sets[2]
    c, frac, n = calibration_table(model(f), ok)
    ece = np.sum(n[n > 0] * np.abs(c[n > 0] - frac[n > 0])) / n.sum()
    assert ece < 0.1
    e = res.left_edges
    curve = coverage_curve(e.row, e.x, res.edge_disparity, res.edge_confidence, gt)
    assert curve.false_rate[len(curve.false_rate) // 2] < curve.false_rate[-1]


def _swap_model(**swap):
    return ConfidenceModel((-1.0, 0.0, 1.0), (0.1, 0.5, 0.9), **swap)


def test_swapped_matches_read_their_own_curve():
    """Only the matches whose disparity is the paths' read the swap curve; the others
    keep the main curve's confidence, and a malformed swap curve is refused by name."""
    rng = np.random.default_rng(3)
    f = np.zeros((300, len(FEATURES)))
    f[:, 0] = f[:, 1] = rng.uniform(0, 1, 300)
    f[:, FEATURES.index("path_uniqueness")] = rng.uniform(0, 1, 300)
    f[:, FEATURES.index("left_right")] = 1
    kind = rng.integers(0, 3, 300)  # 0 paths agree, 1 paths taken, 2 windows kept
    f[:, FEATURES.index("path_agree")] = kind == 0
    f[:, FEATURES.index("path_swapped")] = kind == 1
    plain = _swap_model()
    own = _swap_model(swap_knots_score=(-1.0, 1.0), swap_knots_probability=(0.7, 1.0))
    swapped = swapped_matches(f)
    assert np.array_equal(swapped, kind == 1)
    assert np.array_equal(own(f)[~swapped], plain(f)[~swapped])
    s = own.score(f)[swapped]
    assert np.allclose(own(f)[swapped], np.interp(s, (-1.0, 1.0), (0.7, 1.0)))
    assert np.all(own(f)[swapped] > plain(f)[swapped])
    for bad in (dict(swap_knots_score=(0.0, 1.0), swap_knots_probability=(0.5,)),
                dict(swap_knots_score=(0.0, 1.0), swap_knots_probability=(0.9, 0.1)),
                dict(swap_knots_score=(0.0,), swap_knots_probability=(1.5,))):
        with pytest.raises(InputError, match="swap_knots"):
            _swap_model(**bad)


def _branches_sample(rng, n):
    """Evidence where the swapped matches are right more often than the others at the
    same score, as on the scenes where the paths see through ambiguous windows."""
    f = np.zeros((n, len(FEATURES)))
    u = rng.uniform(0, 1, n)
    swapped = rng.uniform(0, 1, n) < 0.3
    f[:, 0] = f[:, 1] = f[:, FEATURES.index("path_uniqueness")] = u
    f[:, FEATURES.index("left_right")] = 1
    f[:, FEATURES.index("path_agree")] = ~swapped
    f[:, FEATURES.index("path_swapped")] = swapped
    p = np.where(swapped, 0.6 + 0.4 * u, 0.2 + 0.8 * u)
    return f, rng.uniform(0, 1, n) < p


def test_fitted_swap_curve_calibrates_the_swapped_matches():
    """Fitted on one sample, the swap curve is calibrated on the swapped matches of a
    fresh one (the main curve alone is not), and the other matches' confidences are
    those of the fit without it."""
    rng = np.random.default_rng(5)
    f, ok = _branches_sample(rng, 20000)
    both = fit_confidence(f, ok, weights=(0.0, 0.0, 0.0, 0.5, 0.6), swap_curve=True)
    main = fit_confidence(f, ok, weights=(0.0, 0.0, 0.0, 0.5, 0.6))
    assert both.swap_knots_score and not main.swap_knots_score
    assert both.knots_score == main.knots_score
    g, ok2 = _branches_sample(rng, 20000)
    sw = swapped_matches(g)
    assert np.array_equal(both(g)[~sw], main(g)[~sw])

    def ece(conf, right):
        c, fr, n = calibration_table(conf, right)
        return np.sum(n[n > 0] * np.abs(c[n > 0] - fr[n > 0])) / n.sum()

    assert ece(both(g)[sw], ok2[sw]) < 0.03
    assert ece(main(g)[sw], ok2[sw]) > 0.06
    with pytest.raises(InputError, match="swapped"):
        fit_confidence(f, ok | swapped_matches(f), weights=(0.0, 0.0, 0.0, 0.5, 0.6),
                       swap_curve=True)
