"""Planning: eq. 9 inverted, the baseline direction from an image, fusing two captures."""

from __future__ import annotations

import json

import numpy as np
import pytest

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.triangulation import depth_error_bound
from robostereo.robot.capture import write_capture
from robostereo.robot.planning import best_baseline_direction, fuse_located, plan_baseline
from robostereo.robot.simulated import run_fused_block
from robostereo.robot.simulated_scara import RigSetup, block_scene, simulate_capture


def test_plan_inverts_eq9():
    cam = Camera()
    for depth, acc in ((1000.0, 5.0), (600.0, 1.0), (1500.0, 20.0)):
        p = plan_baseline(cam, depth, acc)
        d = cam.fx * p.baseline_mm / depth
        bound = depth_error_bound(p.baseline_mm, cam.fx, d, baseline_uncertainty=0.01,
                                  focal_uncertainty=0.01 / cam.pixel_pitch_mm[0],
                                  disparity_uncertainty=0.2)
        assert float(bound) == pytest.approx(acc, rel=1e-9)
        lo, hi = p.disparity_range
        assert lo <= cam.fx * p.baseline_mm / (1.2 * depth) and hi >= d / 0.8
    with pytest.raises(InputError, match="unreachable"):
        plan_baseline(cam, 1000.0, 0.3)


def test_direction_crosses_the_edges():
    """Stripes along the image's x axis: a horizontal baseline cannot match them, a
    vertical one can."""
    y = np.arange(120)[:, None] * np.ones((1, 160))
    stripes = np.where((y // 10) % 2 == 0, 20.0, 100.0)
    bd = best_baseline_direction(stripes)
    assert bd.matchable_fraction_x == pytest.approx(0.0, abs=0.01)
    assert abs(bd.direction_deg - 90.0) <= 60.0 and bd.matchable_fraction > 0.99
    with pytest.raises(InputError, match="no edges"):
        best_baseline_direction(np.zeros((20, 20)))


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


@pytest.mark.parametrize(("argv", "words"), [
    (["--depth", "1e200", "--accuracy", "1e200"], "not a finite number"),
    (["--depth", "1e-300", "--accuracy", "1e300"], "not a finite number"),
    (["--depth", "1000", "--accuracy", "5", "--near", "1e-300"], "more than the 509 px"),
    (["--depth", "1000", "--accuracy", "1e300"], "too little to measure"),
    (["--depth", "-5", "--accuracy", "5"], "--depth must be > 0"),
])
def test_plan_numeric_edge_cases_are_refused_with_one_line(argv, words, capsys):
    assert main(["plan", *argv]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("robostereo: error: ") and words in err[0]


def test_plan_takes_the_match_stereo_camera_yaml(tmp_path, capsys):
    cam = Camera()
    pixel = tmp_path / "pixel.yaml"
    pixel.write_text(f"fx: {cam.fx}\nfy: {cam.fy}\nbaseline_mm: 20\n"
                     f"focal_uncertainty_px: {0.01 / cam.pixel_pitch_mm[0]}\n"
                     "baseline_uncertainty_mm: 0.01\n")
    physical = tmp_path / "physical.yaml"
    physical.write_text("focal_length_mm: 25\npixel_pitch_mm: [0.0172, 0.0137]\n"
                        "baseline_mm: 20\n")
    plans = []
    for f in (pixel, physical):
        assert main(["plan", "--depth", "1000", "--accuracy", "5", "--camera", str(f),
                     "--json"]) == 0
        plans.append(json.loads(capsys.readouterr().out))
    # the seed camera in pixels, with its uncertainties: the seed camera's plan
    assert plans[0]["baseline_mm"] == pytest.approx(32.09, abs=0.01)
    assert plans[1]["baseline_mm"] == pytest.approx(32.09, abs=0.01)


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


@pytest.mark.parametrize("image", [
    np.full((20, 20), np.nan), np.zeros((3, 3)), np.zeros((0, 10)), [["a"]],
    np.zeros((10, 10, 3)), np.full((20, 20), 1e300),
])
def test_best_baseline_direction_refuses_bad_images(image):
    with pytest.raises(InputError):
        best_baseline_direction(image)
    with pytest.raises(InputError):
        best_baseline_direction(np.zeros((20, 20)), threshold=float("nan"))
