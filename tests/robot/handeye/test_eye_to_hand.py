"""Eye-to-hand calibration on renders the project's simulator did not make.

The views come from ``tests/board_renders.py`` (the tests' own ray caster: pinhole,
k1 = -0.1, 640 x 480, f 800 px): a 9 x 6 chessboard with 30 mm squares carried by the
flange, 14 views 650-750 mm from a fixed camera with a known ``T_base_camera``.
"""

from __future__ import annotations

import math

import pytest
from board_renders import (
    BASE_CAMERA,
    FLANGE_BOARD,
    render_eye_to_hand_views,
    render_views,
)

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye import (
    Chessboard,
    calibrate_eye_in_hand,
    calibrate_eye_to_hand,
    solve_ax_zb,
)

TRUE_CAMERA = Camera(focal_length_mm=4.0, pixel_pitch_mm=(0.005, 0.005), image_size=(640, 480),
                     principal_point=(320.0, 240.0), distortion=(-0.1, 0.0, 0.0, 0.0, 0.0))


@pytest.fixture(scope="module")
def renders():
    return {seed: render_eye_to_hand_views(seed) for seed in range(3)}


def _board(r):
    return Chessboard(r.inner_corners, r.square_mm)


def _errors(truth, T):
    t, r = truth.distance_to(T)
    return t, math.degrees(r)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_camera_in_the_base_frame_within_the_targets_on_independent_renders(renders, seed):
    r = renders[seed]
    cal = calibrate_eye_to_hand(r.images, r.flange_poses, _board(r), pixel_pitch_mm=0.005)
    t, rot = _errors(BASE_CAMERA, cal.base_camera)
    t0, r0 = _errors(BASE_CAMERA, cal.closed_form)
    ty, ry = _errors(FLANGE_BOARD, cal.flange_board)
    # measured (seeds 0-2): refined 0.08-0.23 mm, 0.015-0.050 deg; closed form
    # 0.36-1.6 mm, 0.008-0.031 deg; the board on the flange 0.03-0.06 mm
    assert t < 0.35 and rot < 0.07, (t, rot)
    assert t0 < 3.0 and r0 < 0.2, (t0, r0)
    assert ty < 0.2 and ry < 0.05, (ty, ry)
    assert cal.camera.fx == pytest.approx(800.0, rel=2e-3)
    assert cal.camera.distortion[0] == pytest.approx(-0.1, abs=0.015)
    assert cal.reprojection_rms_px < 0.1 and cal.per_view_rms_px.shape == (14,)
    assert cal.residuals.rotation_deg.shape == (91,) and not cal.rejected


def test_known_intrinsics_pin_the_camera_to_a_tenth_of_a_millimetre(renders):
    for r in renders.values():
        cal = calibrate_eye_to_hand(r.images, r.flange_poses, _board(r), camera=TRUE_CAMERA)
        assert cal.camera is TRUE_CAMERA
        t, rot = _errors(BASE_CAMERA, cal.base_camera)
        assert t < 0.3 and rot < 0.03, (t, rot)


@pytest.mark.parametrize("method", ["shah", "li", "tsai", "daniilidis"])
def test_every_closed_form_starts_the_same_refinement(renders, method):
    r = renders[1]
    ref = calibrate_eye_to_hand(r.images, r.flange_poses, _board(r), pixel_pitch_mm=0.005)
    cal = calibrate_eye_to_hand(r.images, r.flange_poses, _board(r), pixel_pitch_mm=0.005,
                                method=method)
    assert cal.method == method
    t0, r0 = _errors(BASE_CAMERA, cal.closed_form)
    assert t0 < 3.0 and r0 < 0.2, (t0, r0)
    assert ref.base_camera.distance_to(cal.base_camera)[0] < 1e-3


def test_opencv_ax_zb_solves_exact_poses_in_both_modes():
    F = [SE3.from_rotvec([300.0 + 40 * k, -50.0 * k, 400.0 + 10 * k],
                         [0.3 * math.sin(k), 0.25 * math.cos(k), 0.2 * k]) for k in range(6)]
    C = [BASE_CAMERA.inv() @ f @ FLANGE_BOARD for f in F]
    Z, Y = solve_ax_zb([f.inv() for f in F], C, method="li")
    assert BASE_CAMERA.distance_to(Z)[0] < 1e-6 and FLANGE_BOARD.distance_to(Y)[0] < 1e-6
    with pytest.raises(InputError, match="method must be one of shah, li"):
        solve_ax_zb(F, C, method="park")  # type: ignore[arg-type]


def test_views_of_the_other_mode_are_refused_saying_what_they_look_like(renders):
    r = renders[0]
    with pytest.raises(InputError, match=r"^views\.yaml: the views look eye-to-hand \(a fixed "
                                         r"camera and the board on the flange\), not "
                                         r"eye-in-hand: AX = XB rotation RMS [\d.]+ deg"):
        calibrate_eye_in_hand(r.images, r.flange_poses, _board(r), source="views.yaml")
    hand = render_views(0)
    with pytest.raises(InputError, match=r"the views look eye-in-hand \(the camera on the "
                                         r"flange and the board fixed\), not eye-to-hand"):
        calibrate_eye_to_hand(hand.images, hand.flange_poses,
                              Chessboard(hand.inner_corners, hand.square_mm))


@pytest.mark.parametrize("slip", ["square 3 mm for 30", "flange in metres"])
def test_unit_slips_are_refused_not_answered(renders, slip):
    r = renders[0]
    board, flanges = _board(r), list(r.flange_poses)
    if slip.startswith("square"):
        board = Chessboard(board.inner_corners, board.square_mm / 10)
    else:
        flanges = [SE3(f.rotation, f.translation / 1000.0) for f in flanges]
    with pytest.raises(InputError, match=r"^renders: implausible hand-eye result: .*"
                                         r"translation RMS .*square_mm.*unit: m"):
        calibrate_eye_to_hand(r.images, flanges, board, source="renders")


def test_a_view_with_the_wrong_flange_pose_is_named_and_can_be_rejected(renders):
    r = renders[2]
    flanges = list(r.flange_poses)
    flanges[6] = flanges[6] @ SE3.from_rotvec([3.0, -2.0, 1.0], [0.01, 0.0, 0.0])
    names = [f"view_{i:02d}.png" for i in range(14)]
    with pytest.raises(InputError, match=r"worst views: view_06\.png"):
        calibrate_eye_to_hand(r.images, flanges, _board(r), names=names)
    cal = calibrate_eye_to_hand(r.images, flanges, _board(r), names=names,
                                reject_outliers=True, pixel_pitch_mm=0.005)
    assert cal.rejected == ("view_06.png",) and len(cal.names) == 13
    t, rot = _errors(BASE_CAMERA, cal.base_camera)
    assert t < 0.8 and rot < 0.12, (t, rot)
