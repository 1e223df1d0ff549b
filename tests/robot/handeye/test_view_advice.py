"""Where to put more views: the advice's predicted spread against calibrations that take
the advised views (renders of ``tests/board_renders.py``, not the project's simulator)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from board_renders import (
    BASE_BOARD,
    BASE_CAMERA,
    FLANGE_BOARD,
    X_TRUE,
    render_board,
    render_eye_to_hand_views,
    render_views,
)

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye import (
    Chessboard,
    advise_views,
    calibrate_eye_in_hand,
    calibrate_eye_to_hand,
)
from robostereo.robot.handeye.refine import CornerModel, hand_eye_sigma


def _with_advised(renders, poses, cam_in_board, seed):
    """The renders plus one render at each advised flange pose."""
    rng = np.random.default_rng([seed, 5])
    images, flanges = list(renders.images), list(renders.flange_poses)
    for f in poses:
        images.append(render_board(cam_in_board(f), renders.inner_corners, renders.square_mm,
                                   rng=rng))
        flanges.append(f)
    return images, flanges


def test_advised_views_pin_the_rotation_as_predicted_when_the_views_barely_tilt():
    """Views 0-3 deg from the board's normal: the advice prefers tilted views to more of
    the same, and a calibration that takes them is pinned as it predicted (within 20 %)
    and lands within the rotation target."""
    r = render_views(0, tilt_deg=(0.0, 3.0))
    board = Chessboard(r.inner_corners, r.square_mm)
    cal = calibrate_eye_in_hand(r.images, r.flange_poses, board)
    a = cal.advice
    k = a.best
    assert k is not None and a.view_tilts_deg.max() < 4.0
    assert a.current_deg == pytest.approx(cal.hand_eye_sigma_deg)
    assert a.sigma_deg[k] < 0.95 * a.like_views_deg < 0.95 * a.current_deg
    images, flanges = _with_advised(r, a.flange_poses[k],
                                    lambda f: BASE_BOARD.inv() @ f @ X_TRUE, 0)
    after = calibrate_eye_in_hand(images, flanges, board)
    assert after.hand_eye_sigma_deg == pytest.approx(a.sigma_deg[k], rel=0.2)
    assert after.hand_eye_sigma_mm == pytest.approx(a.sigma_mm[k], rel=0.2)
    assert abs(after.advice.view_tilts_deg[-4:] - a.tilts_deg[k]).max() < 0.5
    assert math.degrees(X_TRUE.distance_to(after.hand_eye)[1]) < 0.05


def test_eye_to_hand_advice_gives_the_flange_poses_the_robot_reports():
    """Eye-to-hand: the advised poses are ``T_base_flange`` (not the solve's inverted
    form); rendered through the true cell they give the predicted spread."""
    r = render_eye_to_hand_views(1)
    board = Chessboard(r.inner_corners, r.square_mm)
    cal = calibrate_eye_to_hand(r.images, r.flange_poses, board)
    a = cal.advice
    k = a.best
    assert a.mode == "eye-to-hand" and k is not None
    images, flanges = _with_advised(
        r, a.flange_poses[k], lambda f: (BASE_CAMERA.inv() @ f @ FLANGE_BOARD).inv(), 1)
    after = calibrate_eye_to_hand(images, flanges, board)
    assert after.hand_eye_sigma_deg == pytest.approx(a.sigma_deg[k], rel=0.2)
    assert abs(after.advice.view_tilts_deg[-4:] - a.tilts_deg[k]).max() < 0.5


def _frontal_views():
    K = np.array([[800.0, 0, 320], [0, 800, 240], [0, 0, 1]])
    X = SE3.from_rotvec([20.0, -30.0, 50.0], [0.1, 0.0, 1.0])
    W = SE3.from_rotvec([400.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    board = np.array([[i * 20.0, j * 20.0, 0.0] for i in range(8) for j in range(5)])
    look = [SE3.look_at([70 + 20 * np.cos(t), 40 + 20 * np.sin(t), -480.0], [70, 40, 0])
            for t in np.linspace(0, 2 * np.pi, 8, endpoint=False)]
    return K, X, W, board, [W @ c @ X.inv() for c in look]


def test_the_two_modes_give_one_advice_in_their_own_pose_forms():
    K, X, W, board, F = _frontal_views()
    args = ([board] * 8, F, K, np.zeros(5), X, W, board, (640, 480), 0.01)
    hand = advise_views(*args)
    fixed = advise_views(*args, mode="eye-to-hand")
    np.testing.assert_allclose(fixed.sigma_deg, hand.sigma_deg)
    for a, b in zip(hand.flange_poses[hand.best], fixed.flange_poses[fixed.best], strict=True):
        assert max(a.distance_to(b.inv())) < 1e-9


def test_the_advice_frees_only_the_intrinsics_the_refinement_freed():
    """Decentering held at 0 (the calibration's test found none): the advice's spreads are
    those of the refinement's covariance without ``p1, p2``, and tighter than with them."""
    K, X, W, board, F = _frontal_views()
    args = ([board] * 8, F, K, np.zeros(5), X, W, board, (640, 480), 0.01)
    free = advise_views(*args)
    held = advise_views(*args, fix_tangential=True)
    info = CornerModel([board] * 8, F).information(K, np.zeros(5), X, W, fix_tangential=True)
    assert info.shape == (18, 18)  # fx, fy, cx, cy, k1, k2 and the two poses
    assert held.current_deg == pytest.approx(hand_eye_sigma(info, 0.01, 6)[1])
    assert held.current_deg < free.current_deg
    assert (held.sigma_deg <= free.sigma_deg * (1 + 1e-9)).all()


def test_a_board_that_cannot_fit_leaves_the_tilt_out_and_bad_tilts_are_refused():
    K, X, W, board, F = _frontal_views()
    small = (200, 150)  # the board fills more than this image at any allowed distance
    a = advise_views([board] * 8, F, K, np.zeros(5), X, W, board * 6.0, small, 0.01,
                     tilts_deg=(30.0,))
    assert np.isnan(a.sigma_deg).all() and a.best is None and a.flange_poses == ((),)
    assert "flange_poses" not in a.to_dict()
    for bad in ((0.0,), (85.0,), (np.nan,)):
        with pytest.raises(InputError, match="tilts_deg"):
            advise_views([board] * 8, F, K, np.zeros(5), X, W, board, (640, 480), 0.01,
                         tilts_deg=bad)
