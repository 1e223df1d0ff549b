"""The shared checks of robostereo.errors: bounded echoes of values, huge integers."""

from __future__ import annotations

import time

import pytest

from robostereo.errors import InputError, require_finite, require_positive, require_range, shown


def test_shown_does_not_expand_a_value_shared_many_times() -> None:
    a: list[object] = ["x"] * 9
    for _ in range(9):
        a = [a] * 9  # 3.5e9 elements when expanded
    t0 = time.perf_counter()
    text = shown(a)
    assert time.perf_counter() - t0 < 0.1 and len(text) <= 60


def test_shown_gives_the_size_of_an_integer_too_long_to_print() -> None:
    assert shown(10**5000) == f"<integer of {(10**5000).bit_length()} bits>"
    assert shown(123) == "123" and shown("abc") == "'abc'"


@pytest.mark.parametrize("check", [require_finite, require_positive])
def test_an_integer_too_big_for_a_float_is_not_finite(check) -> None:
    with pytest.raises(InputError, match=r"focal_length_mm must be .*<integer of"):
        check("focal_length_mm", 10**400)


def test_a_range_of_integers_too_big_for_a_float_is_refused() -> None:
    with pytest.raises(InputError, match="depth_range_mm must be finite"):
        require_range("depth_range_mm", (1, 10**400))
