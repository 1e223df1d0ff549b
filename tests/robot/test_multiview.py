"""Tests of robostereo.robot.multiview: locating edge points from N views."""

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.experiments import views_block_truth
from robostereo.robot.multiview import (
    LocatedViews,
    ViewsParameters,
    locate_views,
    views_bound,
)
from robostereo.robot.simulated_views import simulate_views
from robostereo.simulation import Box


@pytest.fixture(scope="module")
def block_line():
    sim = simulate_views("block", count=5, pattern="line", span_mm=80.0)
    return sim, locate_views(sim.capture)


def test_five_views_on_a_line_locate_the_block_top_within_the_bounds(block_line):
    sim, loc = block_line
    assert isinstance(loc, LocatedViews) and len(loc) > 100
    on, err, _ = views_block_truth(sim, loc)  # the top outline, 2 mm clear of corners
    assert on.sum() > 100
    assert np.all(np.abs(err[on]) <= loc.bound_mm[on])
    # most top points seen by every view; the mean height right to a fraction of a mm
    assert np.mean(loc.view_count[on] == 5) > 0.9
    top = next(p for p in sim.scene.primitives if isinstance(p, Box))
    assert abs(loc.world[on, 2].mean() - (top.z_base + top.size[2])) < 0.3


def test_located_views_table_has_one_row_per_point(block_line):
    _, loc = block_line
    t = loc.table()
    assert {"X_w", "Y_w", "Z_w", "bound_mm", "confidence", "view_count"} <= set(t)
    assert all(len(v) == len(loc) for v in t.values())
    assert np.all((loc.confidence >= 0) & (loc.confidence <= 1))
    assert np.all(loc.reference[:, None] >= 0)


def test_bound_of_views_on_a_line_shrinks_with_the_spread_of_the_baselines():
    f = 25.0 / 0.0172
    kw = dict(focal_px=f, pixel_pitch_mm=0.0172, disparity_uncertainty_px=0.2,
              baseline_uncertainty_mm=0.0, focal_length_uncertainty_mm=0.0)
    two = views_bound([1000.0], [np.sqrt(2) / (f * 20.0)], **kw)[0]
    # eq. 9's disparity term for two views 20 mm apart
    assert two == pytest.approx(1000.0**2 * 0.2 / (f * 20.0))
    b = np.array([-40.0, -20.0, 0.0, 20.0, 40.0])
    five = views_bound([1000.0], [1.0 / (f * np.sqrt(np.sum((b - b.mean())**2)))], **kw)[0]
    assert five == pytest.approx(1000.0**2 * 0.2 / np.sqrt(2) / (f * np.sqrt(4000.0)))


def test_bad_input_raises_one_line_input_errors():
    with pytest.raises(InputError, match="ViewsCapture"):
        locate_views("not a capture")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="half_window"):
        ViewsParameters(half_window=0)
    with pytest.raises(InputError, match="step_px"):
        ViewsParameters(step_px=-1.0)
