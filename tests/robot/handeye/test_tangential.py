"""The decentering terms' test (``refine.tangential_chi2``) at its edges."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye.refine import (
    RefinedHandEye,
    free_intrinsics,
    tangential_chi2,
    tangential_threshold,
)

K = np.array([[800.0, 0, 320], [0, 800, 240], [0, 0, 1]])


def _refined(p, information, variance=0.01):
    return RefinedHandEye(K, np.array([-0.1, 0.0, *p, 0.0]), SE3.identity(), SE3.identity(),
                          np.zeros(1), 0.1, variance_px2=variance, information=information)


def test_the_threshold_is_the_chi_square_quantile_of_two_degrees():
    assert tangential_threshold() == pytest.approx(9.2103, abs=1e-4)
    assert tangential_threshold(0.05) == pytest.approx(5.9915, abs=1e-4)


def test_terms_the_views_cannot_constrain_count_for_nothing():
    info = np.diag([1.0] * 6 + [4e6, 0.0] + [1.0] * 12)  # p2 unconstrained
    chi2 = tangential_chi2(_refined((1e-4, 5e-3), info))
    assert chi2 == pytest.approx((1e-4 / 5e-5) ** 2)  # p1 alone: 4


def test_exactly_fitted_corners_keep_any_decentering():
    info = np.eye(20)
    assert math.isinf(tangential_chi2(_refined((1e-4, 0.0), info, variance=0.0)))
    assert tangential_chi2(_refined((0.0, 0.0), info, variance=0.0)) == 0.0


def test_a_refinement_without_the_terms_free_is_refused():
    held = int(free_intrinsics(fix_tangential=True).sum()) + 12
    with pytest.raises(InputError, match="p1 and p2 free"):
        tangential_chi2(_refined((0.0, 0.0), np.eye(held)))
    with pytest.raises(InputError, match="information matrix"):
        tangential_chi2(_refined((0.0, 0.0), None))
