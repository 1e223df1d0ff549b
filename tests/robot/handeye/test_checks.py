"""Self-checks of the hand-eye calibration: predicted residuals, outliers, bounds."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye import handeye_residuals, motion_pairs, solve_ax_xb
from robostereo.robot.handeye.checks import (
    check_plausible,
    corner_noise_px,
    outlier_views,
    pose_covariances,
    predicted_pair_translation_mm,
    robust_z,
)

K = np.array([[800.0, 0.0, 320.0], [0.0, 800.0, 240.0], [0.0, 0.0, 1.0]])
X = SE3.from_rotvec([25.0, -40.0, 60.0], [0.05, -0.1, 1.0])
W = SE3.from_rotvec([450.0, 60.0, 0.0], [math.pi, 0.0, 0.3])
OBJ = np.array([[i * 20.0, j * 20.0, 0.0] for j in range(5) for i in range(8)])


def _views(rng, n, sigma):
    """Flange poses and noisy corner pixels of `n` views of the board from ~450 mm."""
    flanges, pixels = [], []
    for _ in range(n):
        tilt = rng.normal(size=3) * 0.35
        cam_in_board = SE3.from_rotvec([70.0, 40.0, 0.0], [0.0, 0.0, 0.0]) @ SE3.from_rotvec(
            [0.0, 0.0, 0.0], tilt) @ SE3.from_rotvec([0.0, 0.0, -450.0], [0.0, 0.0, 0.0])
        cam_in_board = cam_in_board @ SE3.from_rotvec([0, 0, 0], [0, 0, rng.uniform(-1, 1)])
        C = cam_in_board.inv()
        uv, _ = cv2.projectPoints(OBJ, C.rotvec, C.translation, K, np.zeros(5))
        pixels.append(uv.reshape(-1, 2) + rng.normal(0.0, sigma, (len(OBJ), 2)))
        flanges.append(W @ cam_in_board @ X.inv())
    return flanges, pixels


def _solve(flanges, pixels):
    rv, tv = [], []
    for p in pixels:
        _, r, t = cv2.solvePnP(OBJ, p, K, np.zeros(5))
        rv.append(r.ravel())
        tv.append(t.ravel())
    C = [SE3.from_rotvec(t, r) for r, t in zip(rv, tv, strict=True)]
    A, B = motion_pairs(flanges, C)
    return rv, tv, A, B


def test_predicted_translation_residual_matches_the_observed_one():
    rng = np.random.default_rng(3)
    ratios = []
    for sigma in (0.05, 0.2):
        flanges, pixels = _views(rng, 14, sigma)
        rv, tv, A, B = _solve(flanges, pixels)
        res = handeye_residuals(A, B, solve_ax_xb(A, B))
        covs = pose_covariances([OBJ] * 14, rv, tv, K, np.zeros(5), sigma)
        pred = predicted_pair_translation_mm(rv, tv, covs)
        assert pred.shape == (91,)
        ratios.append(res.rms_translation_mm / float(np.sqrt(np.mean(pred**2))))
    # the prediction is the residual's level: within a factor 1.6 either way, at two
    # noise levels four times apart (the closed form fits X, so slightly below 1)
    assert all(1 / 1.6 < r < 1.6 for r in ratios), ratios


def test_corner_noise_is_robust_to_a_few_gross_errors():
    rng = np.random.default_rng(0)
    r = rng.normal(0.0, 0.05, 2000)
    r[:40] = 30.0
    assert corner_noise_px(r) == pytest.approx(0.05, rel=0.1)


def test_robust_z_and_outlier_views_name_the_view_that_stands_out():
    z = robust_z([1.0, 1.0, 1.0, 1.0], floor=0.01)
    assert np.all(z == 0.0)
    n = 8
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    tr = np.array([0.2 + (5.0 if 5 in p else 0.0) for p in pairs]) + \
        np.linspace(0, 0.02, len(pairs))
    rot = np.full(len(pairs), 0.02)
    flagged = outlier_views(np.full(n, 0.03), tr, rot, n)
    assert flagged.tolist() == [k == 5 for k in range(n)]
    flagged = outlier_views(np.array([0.03] * 7 + [0.5]), np.full(len(pairs), 0.2), rot, n)
    assert np.flatnonzero(flagged).tolist() == [7]
    with pytest.raises(InputError, match="expected 28 pair residuals"):
        outlier_views(np.zeros(n), tr[:-1], rot[:-1], n)


def test_plausibility_bounds():
    ok = dict(rotation_rms_deg=0.03, translation_rms_mm=0.3,
              predicted_translation_rms_mm=0.1, reprojection_rms_px=0.05, source="v.yaml")
    check_plausible(**ok)
    for key, value, words in [("rotation_rms_deg", 1.5, "rotation RMS 1.5 deg"),
                              ("translation_rms_mm", 40.0, "translation RMS 40 mm > 1 mm"),
                              ("reprojection_rms_px", 2.0, "reprojection RMS 2 px")]:
        with pytest.raises(InputError, match=words) as e:
            check_plausible(**{**ok, key: value}, worst=["view_03.png"])
        msg = str(e.value)
        assert msg.startswith("v.yaml: implausible") and "square_mm" in msg
        assert "unit: m" in msg and msg.endswith("worst views: view_03.png")
        assert "\n" not in msg
    # the bound grows with the predicted noise: 5 times it
    check_plausible(**{**ok, "translation_rms_mm": 4.9, "predicted_translation_rms_mm": 1.0})
