"""Hand-eye views folders: a ChArUco board simulated, written, read back, calibrated from."""

from __future__ import annotations

import math

import yaml

from robostereo.cli import main
from robostereo.geometry.poses import SE3
from robostereo.robot.arms.sixaxis import WRIST_HAND_EYE
from robostereo.robot.handeye.boards import read_views


def test_charuco_views(tmp_path, capsys):
    """A ChArUco board: simulated, written, read back and calibrated from."""
    d = tmp_path / "ch"
    assert main(["simulate-handeye", "--out", str(d), "--views", "6", "--seed", "1",
                 "--board", "charuco"]) == 0
    v = read_views(d)
    assert v.board.squares == (8, 6) and v.board.dictionary == "DICT_5X5_100"
    out = tmp_path / "camera.yaml"
    capsys.readouterr()
    assert main(["handeye", str(d), "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    # 8 x 6 squares: 7 x 5 inner corners, a size a plain chessboard would refuse
    assert printed.startswith("6 views, ChArUco board 8 x 6 squares (DICT_5X5_100), 12 mm "
                              "squares\nChArUco: ")
    assert "the markers' ids fix the corner order, so any board size" in printed
    data = yaml.safe_load(out.read_text())
    assert all(6 <= view["corners"] <= 35 for view in data["views"])
    assert data["left_out_views"] == []
    X = SE3.from_quaternion(data["hand_eye"]["position"], data["hand_eye"]["quaternion"])
    t, r = WRIST_HAND_EYE.distance_to(X)
    # ChArUco corners are found less precisely than the chessboard's (0.07 px RMS)
    assert t < 2.0 and math.degrees(r) < 0.5
    assert max(data["per_view_rms_px"]) < 0.3
