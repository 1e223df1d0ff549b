"""The matcher's threads: the count is validated, errors reach the caller."""

from __future__ import annotations

import pytest

from robostereo.errors import InputError
from robostereo.matcher.parallel import n_threads, run_all


def test_thread_count_is_validated(monkeypatch):
    monkeypatch.setenv("ROBOSTEREO_THREADS", "zero")
    with pytest.raises(InputError, match="ROBOSTEREO_THREADS"):
        n_threads()
    monkeypatch.setenv("ROBOSTEREO_THREADS", "2")

    def boom() -> int:
        raise ValueError("second call failed")

    # an error on a pool thread reaches the caller, after the other calls have ended
    with pytest.raises(ValueError, match="second call"):
        run_all([lambda: 1, boom])

