"""Planning: eq. 9 inverted, the baseline direction from an image, fusing two captures."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.triangulation import depth_error_bound
from robostereo.robot.capture import write_capture
from robostereo.robot.planning import (
    NEIGHBOUR_DISPARITY_PX,
    best_baseline_direction,
    fuse_located,
    plan_baseline,
    plan_views,
    views_baseline_factor,
)
from robostereo.robot.simulated.block_experiments import run_fused_block
from robostereo.robot.simulated.scara_rig import RigSetup, block_scene, simulate_capture
from robostereo.robot.views.viewpoints import view_offsets


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


# -- N views ---------------------------------------------------------------------------


def test_two_views_on_a_line_plan_as_the_two_view_plan():
    cam = Camera()
    for depth, acc in ((1000.0, 5.0), (600.0, 1.0), (1500.0, 20.0)):
        two = plan_baseline(cam, depth, acc)
        p = plan_views(cam, depth, acc, views=2)
        assert p.span_mm == pytest.approx(two.baseline_mm, rel=1e-12)
        assert p.step_mm == pytest.approx(two.baseline_mm, rel=1e-12)
        assert p.disparity_range == two.disparity_range
        assert p.bound_terms_mm == two.bound_terms_mm


@pytest.mark.parametrize(("pattern", "count"), [("line", 3), ("line", 5), ("line", 9),
                                                 ("cross", 5), ("cross", 9), ("arc", 5)])
def test_the_least_squares_depth_of_n_views_scatters_as_the_effective_pair(pattern, count):
    """Monte Carlo: edge positions with equal independent errors in each view, the depth
    from the least-squares slope against the views' offsets, spreads as a pair
    ``D_eff`` apart does (1 / D_eff), within the sampling error."""
    rng = np.random.default_rng(3)
    f, Z, sigma, span = 1453.0, 1000.0, 0.1, 80.0
    o = view_offsets(pattern, count, span, depth_mm=Z)[:, :2]
    k = views_baseline_factor(pattern, count, span_mm=span, depth_mm=Z)
    # the direction the pattern measures worst: the smaller principal axis of the offsets
    c = o - o.mean(axis=0)
    w, v = np.linalg.eigh(c.T @ c)
    n = v[:, int(np.argmax(w > 1e-9 * w[-1]))]
    b = o @ n
    trials = 20000
    x = -f * b[None, :] / Z + rng.normal(0.0, sigma, (trials, count))
    bc = b - b.mean()
    slope = (x - x.mean(axis=1, keepdims=True)) @ bc / (bc @ bc)
    z_views = -f / slope
    # the pair D_eff apart: its disparity error is the difference of two positions
    d_eff = k * span
    disp = f * d_eff / Z + rng.normal(0.0, sigma * np.sqrt(2.0), trials)
    z_pair = f * d_eff / disp
    ratio = np.std(z_views) / np.std(z_pair)
    assert 0.95 < ratio < 1.05, (pattern, count, ratio)


def test_more_views_on_a_line_need_a_shorter_span_and_the_count_keeps_neighbours_close():
    cam = Camera()
    spans = [plan_views(cam, 1000.0, 1.0, views=n).span_mm for n in (2, 5, 9, 17)]
    assert all(a > b for a, b in itertools.pairwise(spans))
    p = plan_views(cam, 1000.0, 1.0)
    assert cam.fx * p.step_mm / 1000.0 <= NEIGHBOUR_DISPARITY_PX
    fewer = plan_views(cam, 1000.0, 1.0, views=p.views - 1)
    assert cam.fx * fewer.step_mm / 1000.0 > NEIGHBOUR_DISPARITY_PX
    assert p.step_disparity_px == pytest.approx(cam.fx * p.step_mm / 1000.0)
    lo, hi = p.disparity_range
    assert lo <= cam.fx * p.step_mm / 1200.0 and hi >= cam.fx * p.step_mm / 800.0
    # a loose accuracy: a short span, and two views are close enough
    assert plan_views(cam, 1000.0, 10.0).views == 2


def test_a_cross_plans_every_edge_direction_alike():
    cam = Camera()
    p = plan_views(cam, 1000.0, 2.0, views=9, pattern="cross")
    o = view_offsets("cross", 9, p.span_mm)
    for deg in (0.0, 30.0, 45.0, 90.0):
        n = np.array([np.cos(np.radians(deg)), np.sin(np.radians(deg))])
        b = o[:, :2] @ n
        d_eff = np.sqrt(2.0 * np.sum((b - b.mean()) ** 2))
        assert d_eff == pytest.approx(p.effective_baseline_mm, rel=1e-9)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"views": 1}, "views must be a whole number in 2..100"),
    ({"views": 101}, "views must be"),
    ({"views": 2.5}, "views must be"),
    ({"pattern": "zigzag"}, "pattern must be one of"),
    ({"neighbour_disparity_px": 0.0}, "neighbour_disparity_px"),
    ({"views": 5, "pattern": "arc", "depth_range_mm": (100.0, 3000.0)}, "disparity of"),
])
def test_bad_view_plans_are_refused_naming_the_parameter(kwargs, message):
    with pytest.raises(InputError, match=message):
        plan_views(Camera(), 1000.0, 1.0, **kwargs)


def test_an_arc_that_cannot_reach_the_span_is_refused():
    with pytest.raises(InputError, match="diameter"):
        plan_views(Camera(), 200.0, 0.095, views=3, pattern="arc",
                   depth_range_mm=(190.0, 210.0), max_disparity_px=1e9)
