"""The simulated eye-to-hand session: a board on the six-axis arm's flange, a fixed camera."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import yaml

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.robot.handeye import (
    calibrate_eye_to_hand,
    load_base_camera_yaml,
    load_handeye_yaml,
    read_views,
    write_views,
)
from robostereo.robot.simulated.cell_handeye import (
    BASE_CAMERA,
    CELL_CAMERA,
    CELL_CHARUCO,
    FLANGE_BOARD,
    simulate_eye_to_hand_views,
)


@pytest.fixture(scope="module")
def session():
    return simulate_eye_to_hand_views(views=14, seed=1)


def test_simulated_session_calibrates_to_its_truth(session):
    v, truth = session
    assert v.mode == "eye-to-hand" and len(v.images) == 14
    assert v.images[0].shape == (480, 640)
    assert set(truth) >= {"camera", "base_camera", "flange_board"}
    # every view: the board at 650-750 mm from the camera (its centre)
    for f in v.flange_poses:
        centre = (BASE_CAMERA.inv() @ f @ FLANGE_BOARD).apply(np.array([[120.0, 75.0, 0.0]]))
        assert 640.0 < np.linalg.norm(centre) < 790.0
    cal = calibrate_eye_to_hand(v.images, v.flange_poses, v.board,
                                pixel_pitch_mm=v.pixel_pitch_mm)
    t, r = BASE_CAMERA.distance_to(cal.base_camera)
    # measured (seeds 0-2, 14 views): refined 0.13-0.41 mm, 0.015-0.027 deg (seed 1:
    # 0.16 mm); closed form 0.32-1.06 mm; known intrinsics 0.09-0.13 mm, 0.003-0.007 deg
    assert t < 0.35 and math.degrees(r) < 0.08, (t, math.degrees(r))
    ty, ry = FLANGE_BOARD.distance_to(cal.flange_board)
    assert ty < 0.2 and math.degrees(ry) < 0.05
    assert cal.camera.fx == pytest.approx(CELL_CAMERA.fx, rel=2e-3)
    known = calibrate_eye_to_hand(v.images, v.flange_poses, v.board, camera=CELL_CAMERA)
    tk, rk = BASE_CAMERA.distance_to(known.base_camera)
    assert tk < 0.25 and math.degrees(rk) < 0.02, (tk, math.degrees(rk))
    # how well the views pin it (the fit's covariance): seeds 0-2 gave 0.11-0.14 mm and
    # 0.021-0.025 deg against errors of 0.13-0.41 mm and 0.015-0.027 deg
    assert 0.03 < cal.hand_eye_sigma_mm < 0.4 and 0.005 < cal.hand_eye_sigma_deg < 0.08
    assert t < 5 * cal.hand_eye_sigma_mm and math.degrees(r) < 5 * cal.hand_eye_sigma_deg
    sigma = cal.to_dict()["base_camera_sigma"]
    assert sigma == {"translation_mm": round(cal.hand_eye_sigma_mm, 6),
                     "rotation_deg": round(cal.hand_eye_sigma_deg, 6)}
    assert "hand_eye_sigma" not in cal.to_dict()


def test_handeye_command_writes_the_cell_file_and_refuses_the_other_mode(session, tmp_path,
                                                                         capsys):
    v, truth = session
    d = tmp_path / "views"
    write_views(d, v, extra={"truth.yaml": truth})
    assert yaml.safe_load((d / "views.yaml").read_text())["mode"] == "eye-to-hand"
    assert read_views(d).mode == "eye-to-hand"
    out = tmp_path / "cell.yaml"
    assert main(["handeye", str(d), "-o", str(out)]) == 0  # the mode from views.yaml
    text = capsys.readouterr().out
    assert "camera in the base frame (park" in text and "board on the flange:" in text
    assert "AX = ZB residuals over 91 view pairs" in text
    data = yaml.safe_load(out.read_text())
    assert list(data)[:4] == ["mode", "camera", "base_camera", "flange_board"]
    assert "hand_eye" not in data and "base_camera_closed_form" in data
    camera, Z = load_base_camera_yaml(out)
    assert BASE_CAMERA.distance_to(Z)[0] < 0.35 and camera.image_size == (640, 480)
    with pytest.raises(InputError, match=r"an eye-to-hand calibration \(base_camera\), not "
                                         r"the hand_eye this needs"):
        load_handeye_yaml(out)
    bad = tmp_path / "bad.yaml"
    assert main(["handeye", str(d), "--mode", "eye-in-hand", "-o", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and not bad.exists()
    assert "the views look eye-to-hand (a fixed camera and the board on the flange)" in err
    # known intrinsics 2 % off in focal length: warned about naming the parameter, and
    # refused (the final residuals against the views' own noise), nothing written
    wrong = tmp_path / "wrong.yaml"
    cam = dict(data["camera"], focal_length_mm=4.08, principal_point=[322.0, 241.5],
               distortion=[-0.1, 0.0, 0.0, 0.0, 0.0], pixel_pitch_mm=[0.005, 0.005])
    wrong.write_text(yaml.safe_dump({"camera": cam}))
    capsys.readouterr()
    assert main(["handeye", str(d), "--intrinsics", str(wrong), "-o",
                 str(tmp_path / "w.yaml")]) == 2
    err = capsys.readouterr().err
    assert "robostereo: warning: " in err
    assert re.search(r"fx 816 px where the views put it at (79\d|80\d)\.\d", err), err
    assert "check the known intrinsics (--intrinsics)" in err
    assert not (tmp_path / "w.yaml").exists()
    # an eye-in-hand file read as the cell's camera is refused by name
    hand = tmp_path / "hand.yaml"
    hand.write_text(yaml.safe_dump({"camera": data["camera"], "hand_eye": data["base_camera"]}))
    with pytest.raises(InputError, match=r"an eye-in-hand calibration \(hand_eye\)"):
        load_base_camera_yaml(hand)


def test_simulate_handeye_eye_to_hand_command(tmp_path, capsys):
    out = tmp_path / "cell_views"
    assert main(["simulate-handeye", "--mode", "eye-to-hand", "--views", "4", "--seed", "3",
                 "--out", str(out)]) == 0
    assert "4 eye-to-hand views of a chessboard" in capsys.readouterr().out
    v = read_views(out)
    assert v.mode == "eye-to-hand" and len(v.images) == 4
    truth = yaml.safe_load((out / "truth.yaml").read_text())
    assert np.allclose(truth["base_camera"]["position"], BASE_CAMERA.translation)


def test_simulated_charuco_board_on_the_flange_calibrates_the_fixed_camera(tmp_path, capsys):
    d = tmp_path / "c"
    assert main(["simulate-handeye", "--mode", "eye-to-hand", "--board", "charuco",
                 "--views", "10", "--seed", "2", "--out", str(d)]) == 0
    assert "10 eye-to-hand views of a charuco" in capsys.readouterr().out
    v = read_views(d)
    assert v.board == CELL_CHARUCO and v.mode == "eye-to-hand"
    out = tmp_path / "cell.yaml"
    assert main(["handeye", str(d), "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "ChArUco board 10 x 7 squares (DICT_5X5_100)" in printed
    assert "the markers' ids fix the corner order" in printed
    _, Z = load_base_camera_yaml(out)
    t, r = BASE_CAMERA.distance_to(Z)
    # measured (seed 0, 14 views): 0.05 mm
    assert t < 0.5 and math.degrees(r) < 0.05, (t, math.degrees(r))
