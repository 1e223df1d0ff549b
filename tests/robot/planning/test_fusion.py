"""Fusing two captures: the block from orthogonal baselines, locate --fuse, bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.robot.capture import write_capture
from robostereo.robot.planning.fusion import fuse_located
from robostereo.robot.simulated.block_experiments import run_fused_block
from robostereo.robot.simulated.scara_rig import RigSetup, block_scene, simulate_capture


def test_orthogonal_baselines_fuse_more_of_the_block():
    g = run_fused_block(seed=0)
    assert g.fused > g.located[0] and g.top_edge_points[2] > 1.15 * g.top_edge_points[0]
    assert g.outline_covered[2] > g.outline_covered[0] + 0.2


def test_plan_and_fused_locate_commands(tmp_path, capsys):
    assert main(["plan", "--depth", "1000", "--accuracy", "5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["baseline_mm"] == pytest.approx(32.09, abs=0.01)
    assert main(["plan", "--depth", "1000", "--accuracy", "0.2"]) == 2
    assert capsys.readouterr().err.startswith("robostereo: error: accuracy_mm = 0.2 mm is")
    scene = block_scene(RigSetup())
    for name, d in (("x", 0.0), ("y", 90.0)):
        sim = simulate_capture("block", setup=RigSetup(direction_deg=d), scene=scene)
        write_capture(tmp_path / name, sim.capture)
    assert main(["locate", str(tmp_path / "x"), "--fuse", str(tmp_path / "y")]) == 0
    text = (tmp_path / "x" / "located-fused.csv").read_text().splitlines()
    assert text[0] == "X_w,Y_w,Z_w,z_bound,capture"
    caps = [line.rsplit(",", 1)[1] for line in text[1:]]
    assert "0" in caps and "1" in caps
    assert main(["locate", str(tmp_path / "x"), "--fuse", str(tmp_path / "none")]) == 2


class _Pts:
    def __init__(self, world, z_bound):
        self.world, self.z_bound = world, z_bound


@pytest.mark.parametrize(("first", "merge"), [
    (_Pts(np.array([[0.0, 0.0, np.nan]]), np.array([1.0])), 0.5),
    (_Pts(np.zeros((2, 3)), np.ones(3)), 0.5),
    (_Pts(np.zeros((2, 2)), np.ones(2)), 0.5),
    (object(), 0.5),
    (_Pts(np.zeros((1, 3)), np.ones(1)), float("nan")),
    (_Pts(np.zeros((1, 3)), np.array([np.inf])), 0.5),
])
def test_fuse_located_refuses_bad_input_and_nan(first, merge):
    good = _Pts(np.ones((2, 3)), np.ones(2))
    with pytest.raises(InputError) as e:
        fuse_located(first, good, merge_mm=merge)
    assert "\n" not in str(e.value)
