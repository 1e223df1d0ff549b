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



def test_interrupt_on_main_thread_cancels_the_rest_and_waits_for_running_calls(monkeypatch):
    import os
    import signal
    import threading
    import time

    monkeypatch.setenv("ROBOSTEREO_THREADS", "2")
    started: list[int] = []
    ended: list[int] = []
    lock = threading.Lock()

    def call(i: int) -> int:
        with lock:
            started.append(i)
        if i == 0:
            os.kill(os.getpid(), signal.SIGTERM)  # the main thread is waiting meanwhile
        time.sleep(0.2)
        with lock:
            ended.append(i)
        return i

    def on_term(signum, frame):
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, on_term)
    try:
        with pytest.raises(KeyboardInterrupt):
            run_all([lambda i=i: call(i) for i in range(8)])
        # every call that started has ended before the interrupt reached the caller;
        # the calls not yet started never will
        assert sorted(started) == sorted(ended)
        assert len(started) < 8
    finally:
        signal.signal(signal.SIGTERM, previous)
    time.sleep(0.3)
    assert len(started) == len(ended) < 8


def test_error_of_a_later_call_is_raised_not_a_cancellation(monkeypatch):
    monkeypatch.setenv("ROBOSTEREO_THREADS", "2")

    def boom() -> int:
        raise ValueError("third call failed")

    with pytest.raises(ValueError, match="third call"):
        run_all([lambda: 1, lambda: 2, boom, lambda: 4, lambda: 5])
