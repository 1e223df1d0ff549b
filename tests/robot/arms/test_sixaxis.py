"""The six-axis arm, the renderer's camera effects, and the six-axis demo."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml

from robostereo.cli import main
from robostereo.errors import InputError, UnreachablePoseError
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.arms.sixaxis import UR5_DH, WRIST_CAMERA, SixAxisArm
from robostereo.robot.capture import read_capture
from robostereo.robot.simulated.sixaxis_rig import SixAxisViewpoints
from robostereo.simulation import Checkerboard, Scene, TablePlane, render


def test_forward_kinematics_known_pose():
    """UR5 zero pose: the arm stretched along -x; flange at (-817.25, -191.45, -5.491)."""
    T = SixAxisArm().forward(np.zeros(6))
    d = [link.d for link in UR5_DH]
    a = [link.a for link in UR5_DH]
    assert np.allclose(T.translation, [a[1] + a[2], -(d[3] + d[5]), d[0] - d[4]])


def test_inverse_kinematics_round_trip_and_limits():
    arm = SixAxisArm()
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = np.radians([rng.uniform(-60, 60), rng.uniform(-120, -60), rng.uniform(40, 120),
                        rng.uniform(-150, -30), rng.uniform(-120, -60), rng.uniform(-90, 90)])
        T = arm.forward(q)
        q2 = arm.inverse(T, q0=q + rng.normal(size=6) * 0.2)
        t, r = T.distance_to(arm.forward(q2))
        assert t < 1e-5 and r < 1e-7 and arm.violation(q2) is None
    with pytest.raises(UnreachablePoseError, match="unreachable pose"):
        arm.inverse(SE3.from_rotvec([1500.0, 0.0, 200.0], [math.pi, 0.0, 0.0]))
    assert "joint 3" in arm.violation(np.array([0, 0, 4.0, 0, 0, 0]))


def test_distorted_rendering_matches_projection():
    """A chessboard seen through the distorting wrist camera: its corners are where
    Camera.project (with distortion) puts them."""
    from robostereo.robot.handeye import Chessboard, detect_chessboard

    cb = Checkerboard(origin=(0.0, 0.0), z=2.0, inner_corners=(9, 6), square_mm=12.0)
    scene = Scene((TablePlane(z=0.0, albedo=0.3), cb))
    pose = SE3.look_at([20.0, -180.0, 330.0], [60.0, -25.0, 0.0])
    img = render(scene, WRIST_CAMERA, pose, blur_sigma_px=0.8).image
    corners = detect_chessboard(img, Chessboard((9, 6), 12.0))
    assert corners is not None
    truth, _ = WRIST_CAMERA.project(cb.pose.apply(Chessboard((9, 6), 12.0).object_points), pose)
    assert np.abs(corners - truth).max() < 0.15
    plain = Camera(**{**WRIST_CAMERA.__dict__, "distortion": ()})
    truth0, _ = plain.project(cb.pose.apply(Chessboard((9, 6), 12.0).object_points), pose)
    assert np.abs(corners - truth0).max() > 0.5  # the distortion is visible


def test_vignetting_and_options():
    scene = Scene((TablePlane(z=0.0, albedo=0.5),), light_direction=(0, 0, 1))
    cam = Camera(image_size=(64, 48))
    pose = SE3.look_at([0.0, 0.0, 1000.0], [0.0, 0.0, 0.0])
    flat = render(scene, cam, pose, supersample=1, blur_sigma_px=0.0).intensity
    vig = render(scene, cam, pose, supersample=1, blur_sigma_px=0.0, vignetting=0.3).intensity
    assert vig[24, 32] == pytest.approx(flat[24, 32], rel=1e-3)
    assert vig[0, 0] == pytest.approx(0.7 * flat[0, 0], rel=0.01)
    with pytest.raises(InputError, match="vignetting"):
        render(scene, cam, pose, vignetting=1.5)


def test_viewpoints_differ_in_all_six_coordinates():
    left, right = SixAxisViewpoints().camera_poses()
    d = right.translation - left.translation
    assert np.all(np.abs(d) > 1.0)
    rel = (left.inv() @ right).rotvec
    assert np.all(np.abs(rel) > 0.005)
    tilt = math.degrees(math.acos(-left.rotation[2, 2]))
    assert tilt >= 20.0


def test_six_axis_capture_command(tmp_path, capsys):
    d = tmp_path / "cap"
    assert main(["capture", "--robot", "six-axis", "--out", str(d), "--seed", "1"]) == 0
    data = yaml.safe_load((d / "capture.yaml").read_text())
    assert {"flange_left", "flange_right", "hand_eye"} <= set(data)
    assert len(data["camera"]["distortion"]) == 5
    cap = read_capture(d)
    assert not cap.is_scara
    assert main(["locate", str(d)]) == 0
    assert "located" in capsys.readouterr().out
    assert main(["capture", "--robot", "six-axis", "--out", str(tmp_path / "far"),
                 "--baseline", "2000"]) == 2
    assert "unreachable pose" in capsys.readouterr().err
    assert not (tmp_path / "far").exists()


def test_six_axis_demo(tmp_path, capsys):
    """The issue's targets, with the hand-eye transform estimated from simulated views."""
    out = tmp_path / "demo"
    assert main(["demo", "--robot", "six-axis", "--out", str(out), "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert abs(s["lift_mm"] - s["lift_true_mm"]) <= 1.0
    assert s["max_abs_error_mm"] <= 5.0 and s["all_within_bound"] is True
    assert s["handeye_translation_error_mm"] <= 1.0 and s["handeye_rotation_error_deg"] <= 0.1
    assert s["camera_tilt_deg"] >= 20.0 and min(s["block_points"]) > 100
    # the eye-to-hand line (issue 37): a fixed camera calibrated within its targets
    e = s["eye_to_hand"]
    assert e["views"] == 14 and e["base_camera_mm"] < 0.3 and e["base_camera_deg"] < 0.05
    for name in ("capture-low", "capture-high"):
        data = yaml.safe_load((out / name / "capture.yaml").read_text())
        # the recorded hand-eye transform is the estimate, not the truth
        assert data["hand_eye"]["position"] != [32.0, -58.0, 41.0]
    assert main(["demo", "--json"]) == 2
    assert "--json needs --robot six-axis" in capsys.readouterr().err


def test_six_axis_capture_refuses_scara_options(tmp_path, capsys):
    assert main(["capture", "--robot", "six-axis", "--out", str(tmp_path / "c"),
                 "--direction", "30"]) == 2
    assert "--direction, --roll and --center are for --robot adeptone" in capsys.readouterr().err
    assert not (tmp_path / "c").exists()
