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


@pytest.mark.parametrize(("key", "value"), [("bound_sigmas", 0.0), ("bound_sigmas", -3.0),
                                            ("bound_sigmas", float("nan")),
                                            ("noise_prior_dof", 0.0),
                                            ("noise_prior_dof", float("inf"))])
def test_a_bound_noise_setting_that_cannot_be_is_refused_naming_it(key, value):
    with pytest.raises(InputError, match=key):
        ViewsParameters(**{key: value})
    ViewsParameters(bound_sigmas=None)  # the capture's figures alone
