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


def test_the_pool_lets_go_of_a_batch_that_has_run(monkeypatch):
    # an idle worker must not keep the last batch's calls, and through their closures
    # the arguments of a whole match (its images), alive until the next batch
    import gc
    import time
    import weakref

    monkeypatch.setenv("ROBOSTEREO_THREADS", "2")

    class Payload:
        pass

    payload = Payload()
    ref = weakref.ref(payload)
    assert run_all([lambda p=payload: id(p), lambda p=payload: id(p)]) == [id(payload)] * 2
    del payload
    for _ in range(100):  # the workers drop it after they have told the caller
        gc.collect()
        if ref() is None:
            break
        time.sleep(0.02)
    assert ref() is None


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


def test_interrupt_taken_by_another_thread_still_waits_for_every_started_call(monkeypatch):
    # A thread that does not hold the signals back (as Dask's, or pytest-xdist's) takes a
    # process-directed SIGTERM, and Python runs the handler on the main thread at once,
    # wherever it is; the calls that started must still all end before the interrupt
    # reaches the caller.  A few hundred tries catch a race that hits 1 in 20.
    import os
    import signal
    import threading
    import time

    stop = threading.Event()
    foreign = threading.Thread(target=stop.wait, daemon=True)
    foreign.start()

    def on_term(signum, frame):
        raise KeyboardInterrupt

    lock = threading.Lock()
    started: list[int] = []
    ended: list[int] = []

    def call(i: int) -> int:
        with lock:
            started.append(i)
        if i == 0:
            os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.0005)
        with lock:
            ended.append(i)
        return i

    previous = signal.signal(signal.SIGTERM, on_term)
    lost = 0
    try:
        for k in range(200):
            # a pool of another size each time: a fresh pool starts its workers while
            # the calls are handed over, where the race was
            monkeypatch.setenv("ROBOSTEREO_THREADS", str(2 + k % 2))
            with lock:
                started.clear()
                ended.clear()
            try:
                run_all([lambda i=i: call(i) for i in range(64)])
            except KeyboardInterrupt:
                pass
            with lock:
                lost += sorted(started) != sorted(ended)
    finally:
        signal.signal(signal.SIGTERM, previous)
        stop.set()
    assert lost == 0
