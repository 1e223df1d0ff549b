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

