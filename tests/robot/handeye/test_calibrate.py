"""Hand-eye calibration: chessboard views, the views folder, the handeye commands."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.robot.arms.sixaxis import WRIST_HAND_EYE
from robostereo.robot.handeye import (
    calibrate_eye_in_hand,
    read_views,
    write_views,
)
from robostereo.robot.simulated.sixaxis_handeye import simulate_handeye_views


@pytest.fixture(scope="module")
def views():
    return simulate_handeye_views(views=10, seed=1)


def test_calibration_from_simulated_views(views):
    v, truth = views
    assert truth["hand_eye"]["position"] == [32.0, -58.0, 41.0]
    cal = calibrate_eye_in_hand(v.images, v.flange_poses, v.board,
                                pixel_pitch_mm=v.pixel_pitch_mm)
    t, r = WRIST_HAND_EYE.distance_to(cal.hand_eye)
    assert t < 1.0 and math.degrees(r) < 0.1          # the targets
    assert cal.per_view_rms_px.shape == (10,) and cal.per_view_rms_px.max() < 0.2
    assert cal.camera.fx == pytest.approx(1250.0, rel=2e-3)
    assert cal.residuals.rotation_deg.shape == (45,)
    t0, r0 = WRIST_HAND_EYE.distance_to(cal.closed_form)
    assert t0 < 1.0 and math.degrees(r0) < 0.1
    unrefined = calibrate_eye_in_hand(v.images, v.flange_poses, v.board, refine=False)
    assert unrefined.closed_form is None
    assert unrefined.hand_eye.distance_to(cal.closed_form)[0] < 1e-6
    with pytest.raises(InputError, match="at least 3 usable views"):
        calibrate_eye_in_hand(v.images[:2], v.flange_poses[:2], v.board)
    with pytest.raises(InputError, match="tangential must be one of test, fit, zero"):
        calibrate_eye_in_hand(v.images, v.flange_poses, v.board, tangential="maybe")
    blank = np.full_like(v.images[0], 90)
    with pytest.raises(InputError, match="view 3: chessboard 9 x 6 not found"):
        calibrate_eye_in_hand([*v.images[:3], blank], v.flange_poses[:4], v.board)


def test_views_folder_and_commands(views, tmp_path, capsys):
    v, truth = views
    d = tmp_path / "views"
    write_views(d, v, extra={"truth.yaml": truth})
    back = read_views(d)
    assert len(back.images) == 10 and np.array_equal(back.images[4], v.images[4])
    assert back.flange_poses[3].distance_to(v.flange_poses[3])[0] < 1e-6
    out = tmp_path / "camera.yaml"
    assert main(["handeye", str(d), "-o", str(out), "--method", "tsai"]) == 0
    text = capsys.readouterr().out
    assert "reprojection RMS px" in text and "AX = XB residuals over 45" in text
    # the simulator's lens has p1 = 5e-4, p2 = -3e-4: the views show them, they stay
    assert "decentering p1, p2 kept: the views show them at chi-square" in text
    assert "  view_09.png  " in text and "view_00.png - " in text  # views and pairs tables
    data = yaml.safe_load(out.read_text())
    assert set(data) >= {"camera", "hand_eye", "per_view_rms_px", "handeye_residuals",
                         "views", "pairs", "hand_eye_closed_form", "corner_noise_px"}
    assert len(data["pairs"]) == 45 and data["views"][9]["image"] == "view_09.png"
    assert data["pairs"][0]["views"] == ["view_00.png", "view_01.png"]
    assert np.allclose(data["hand_eye"]["position"], [32.0, -58.0, 41.0], atol=1.0)
    assert data["tangential"]["terms"] == "kept" and data["tangential"]["chi2"] > 9.21
    fitted = tmp_path / "fitted.yaml"
    assert main(["handeye", str(d), "-o", str(fitted), "--tangential", "fit"]) == 0
    assert "decentering" not in capsys.readouterr().out
    assert yaml.safe_load(fitted.read_text())["tangential"] == {"terms": "fitted"}
    # a SCARA-like views folder (flange turning about the vertical only) is refused
    spec = yaml.safe_load((d / "views.yaml").read_text())
    for i, view in enumerate(spec["views"]):
        view["flange"] = {"x": 400.0 + i, "y": 10.0 * i, "z": 500.0, "phi_deg": 7.0 * i}
    (d / "views.yaml").write_text(yaml.safe_dump(spec))
    out2 = tmp_path / "scara.yaml"
    assert main(["handeye", str(d), "-o", str(out2)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("robostereo: error: hand-eye: all flange rotations are about one")
    assert err.count("\n") == 1 and not out2.exists()
    spec["views"] = spec["views"][:2]
    (d / "views.yaml").write_text(yaml.safe_dump(spec))
    assert main(["handeye", str(d), "-o", str(out2)]) == 2
    assert "at least 3 usable views, got 2" in capsys.readouterr().err
    assert main(["handeye", str(tmp_path / "none"), "-o", str(out2)]) == 2
    assert "views folder not found" in capsys.readouterr().err


def test_simulate_handeye_command(tmp_path, capsys):
    d = tmp_path / "hv"
    assert main(["simulate-handeye", "--out", str(d), "--views", "3", "--seed", "4"]) == 0
    assert sorted(p.name for p in d.iterdir()) == [
        "truth.yaml", "view_00.png", "view_01.png", "view_02.png", "views.yaml"]
    assert main(["simulate-handeye", "--out", str(d)]) == 2
    assert "not an empty folder" in capsys.readouterr().err
    assert main(["simulate-handeye", "--out", str(tmp_path / "x"), "--views", "2"]) == 2
    assert not (tmp_path / "x").exists()
