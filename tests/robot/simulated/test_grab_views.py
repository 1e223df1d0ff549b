"""Tests of robostereo.robot.simulated.grab_views: N simulated views in a pattern."""

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.robot.simulated.grab_views import simulate_views


def test_scara_line_views_stay_at_one_height_looking_down_along_the_baseline():
    sim = simulate_views("block", count=4, pattern="line", span_mm=60.0)
    cap = sim.capture
    c = cap.centres
    assert len(cap) == len(sim.renderings) == len(sim.true_poses) == 4
    assert np.ptp(c[:, 2]) < 1e-9
    assert cap.span_mm == pytest.approx(60.0, abs=1e-6)
    # on a line: every centre on the segment between the outermost two
    d = (c[-1] - c[0]) / np.linalg.norm(c[-1] - c[0])
    off = (c - c[0]) - np.outer((c - c[0]) @ d, d)
    assert np.abs(off).max() < 1e-6
    for p in cap.poses:  # optical axis straight down
        assert p.rotation[2, 2] == pytest.approx(-1.0, abs=1e-9)
    # the rendering's truth: the block's top is seen where the scene puts it
    assert all(np.isfinite(r.depth).any() for r in sim.renderings)


def test_scara_cross_spreads_views_in_two_directions():
    sim = simulate_views("pulley", count=5, pattern="cross", span_mm=40.0)
    c = sim.capture.centres - sim.capture.centres[0]
    # the centre view first; the others on two perpendicular arms
    xs = c[1:3, :2]
    ys = c[3:5, :2]
    assert np.linalg.norm(xs[1] - xs[0]) == pytest.approx(40.0, abs=1e-6)
    assert np.linalg.norm(ys[1] - ys[0]) == pytest.approx(40.0, abs=1e-6)
    assert abs(np.dot(xs[1] - xs[0], ys[1] - ys[0])) < 1e-6


def test_six_axis_arc_records_flanges_with_an_estimated_hand_eye_and_faces_the_target():
    sim = simulate_views("block", count=3, pattern="arc", span_mm=60.0, robot="six-axis")
    cap = sim.capture
    assert cap.flanges is not None and cap.hand_eye is not None
    for reported, true in zip(cap.poses, sim.true_poses, strict=True):
        t_err, r_err = reported.distance_to(true)
        assert 0 < t_err < 2.0 and r_err < np.radians(0.2)
    # every true optical axis passes near the six-axis demo's target
    target = np.array([430.0, 120.0, 60.0])
    for p in sim.true_poses:
        v = target - p.translation
        axis = p.rotation[:, 2]
        miss = np.linalg.norm(v - (v @ axis) * axis)
        assert miss < 1.0


@pytest.mark.parametrize("kwargs, word", [
    ({"count": 1}, "count"),
    ({"pattern": "circle"}, "pattern"),
    ({"robot": "delta"}, "robot"),
    ({"span_mm": -5.0}, "span_mm"),
    ({"seed": -1}, "seed"),
])
def test_bad_parameters_raise_one_line_input_errors(kwargs, word):
    with pytest.raises(InputError, match=word) as e:
        simulate_views("block", **kwargs)
    assert "\n" not in str(e.value)
