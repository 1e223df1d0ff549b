"""Planning a pair: eq. 9 inverted for the baseline, and the plan command."""

from __future__ import annotations

import json

import pytest

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.triangulation import depth_error_bound
from robostereo.robot.planning.baseline_plan import plan_baseline


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
