"""Planning N views: the span and count of a pattern for a depth accuracy."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.robot.planning.baseline_plan import plan_baseline
from robostereo.robot.planning.views_plan import (
    NEIGHBOUR_DISPARITY_PX,
    plan_views,
    views_baseline_factor,
)
from robostereo.robot.views.viewpoints import view_offsets


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
