"""The simulated AdeptOne rig: its options in the capture, no application layer needed."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest

from robostereo.cli import main
from robostereo.robot.capture.capture_folder import read_capture


def test_cli_pulley_capture_options(tmp_path):
    d = tmp_path / "pulley"
    assert main(["capture", "--out", str(d), "--scene", "pulley", "--direction", "30",
                 "--roll", "10", "--baseline", "25", "--center", "350", "100"]) == 0
    cap = read_capture(d)
    g = cap.epipolar
    assert g.baseline_mm == pytest.approx(25.0) and math.degrees(g.alpha) == pytest.approx(30.0)
    assert math.degrees(g.theta_l) == pytest.approx(10.0, abs=2.5)
    assert (g.origin[0], g.origin[1]) == pytest.approx((350.0, 100.0))


def test_the_simulated_rigs_import_no_application_module():
    """The library's simulated rigs stand alone: importing them loads none of the
    command line, the experiments, the plots or the batch runner."""
    code = ("import sys, robostereo.robot.simulated.sixaxis_rig, "
            "robostereo.robot.simulated.sixaxis_handeye, "
            "robostereo.robot.simulated.block_experiments, "
            "robostereo.robot.simulated.scara_rig; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] == 'robostereo' and "
            "m.split('.')[1:2] in (['cli'], ['cli_robot'], ['experiments'], ['plots'], "
            "['batch'])))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"
