"""The baseline direction chosen from an image so that its edges cross the epipolar lines."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.robot.planning.baseline_direction import best_baseline_direction


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


@pytest.mark.parametrize("image", [
    np.full((20, 20), np.nan), np.zeros((3, 3)), np.zeros((0, 10)), [["a"]],
    np.zeros((10, 10, 3)), np.full((20, 20), 1e300),
])
def test_best_baseline_direction_refuses_bad_images(image):
    with pytest.raises(InputError):
        best_baseline_direction(image)
    with pytest.raises(InputError):
        best_baseline_direction(np.zeros((20, 20)), threshold=float("nan"))
