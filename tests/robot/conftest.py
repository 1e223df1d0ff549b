"""Shared fixtures of the robot tests: simulated captures that take long to render."""

from __future__ import annotations

import pytest

from robostereo.robot.simulated.grab_views import SimulatedViews, simulate_views


@pytest.fixture(scope="session")
def six_axis_pulley_cross() -> SimulatedViews:
    """The six-axis arm's hub-pulley from a cross of 5 views over 80 mm, noise seed 5 (a
    seed neither confidence was fitted on)."""
    return simulate_views("pulley", count=5, pattern="cross", span_mm=80.0,
                          robot="six-axis", seed=5)
