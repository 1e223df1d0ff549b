"""Tests of robostereo.robot.views.views_parameters: the N-view locate's tuning."""

import pytest

from robostereo.errors import InputError
from robostereo.robot.views.views_parameters import ViewsParameters


def test_bad_parameters_raise_one_line_input_errors():
    with pytest.raises(InputError, match="half_window"):
        ViewsParameters(half_window=0)
    with pytest.raises(InputError, match="step_px"):
        ViewsParameters(step_px=-1.0)
    with pytest.raises(InputError, match="min_confidence"):
        ViewsParameters(min_confidence=1.5)
