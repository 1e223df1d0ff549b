"""Threads for the matcher: the two images' stages side by side, image bands at once.

The matcher's kernels are numba functions compiled ``nogil``, so Python threads run
them on separate cores.  A pool of worker threads is kept per process (made on first
use, made again after a fork); the calling thread always does one share of the work
itself, and work given to the pool never waits on the pool, so concurrent callers
(e.g. a Dask worker's threads) cannot deadlock it.

The number of threads is the number of cores this process may run on, or the
environment variable ``ROBOSTEREO_THREADS`` (1: everything on the calling thread).

Signals: Python runs signal handlers on the main thread only, between bytecodes, so a
main thread inside a numba kernel would see SIGINT or SIGTERM only when the kernel
ends, and a main thread that gave up while pool threads still ran kernels let the
interpreter shut down under them (a segmentation fault, or numba's traceback).  So
when called on the main thread, :func:`run_all` gives every call to the pool and waits
in short interruptible waits; on an interrupt it cancels the calls not yet started,
waits for the running ones to end (a kernel cannot be stopped midway; a share of an
image takes seconds at most) and then raises the interrupt.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_EXCEPTION, Future, ThreadPoolExecutor, wait
from typing import Any, TypeVar

from robostereo.errors import InputError
from robostereo.io.files import signals_held

__all__ = ["n_threads", "run_all"]

T = TypeVar("T")

_lock = threading.Lock()
_pool: tuple[int, int, ThreadPoolExecutor] | None = None  # (pid, workers, pool)

WAIT_SECONDS = 0.2
"""Longest single wait of the main thread for the pool (a signal is handled at once
anyway; the timeout only bounds a wait that a platform would not interrupt)."""


def n_threads() -> int:
    """Threads the matcher uses: ``ROBOSTEREO_THREADS`` or the cores available.

    >>> n_threads() >= 1
    True
    """
    env = os.environ.get("ROBOSTEREO_THREADS", "").strip()
    if env:
        try:
            n = int(env)
        except ValueError:
            n = 0
        if n < 1:
            raise InputError(f"ROBOSTEREO_THREADS must be a whole number >= 1, got {env!r}")
        return n
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def _executor(workers: int) -> ThreadPoolExecutor:
    global _pool
    with _lock:
        if _pool is None or _pool[0] != os.getpid() or _pool[1] != workers:
            # a forked child inherits the pool object but not its threads; a pool of
            # another size (ROBOSTEREO_THREADS changed) lets its threads end
            if _pool is not None and _pool[0] == os.getpid():
                _pool[2].shutdown(wait=False)
            _pool = (os.getpid(), workers, ThreadPoolExecutor(
                max_workers=workers, thread_name_prefix="robostereo"))
        return _pool[2]


def run_all(calls: Sequence[Callable[[], T]]) -> list[T]:
    """Run the calls at once, up to :func:`n_threads` at a time; their results in order.

    On the main thread every call runs on the pool while the main thread waits
    (interruptibly, see the module notes); on any other thread the first call runs on
    the calling thread and the others on the pool.  An exception of any call is raised
    after all started calls have ended; so is a KeyboardInterrupt (SIGINT, or SIGTERM
    as the command line raises it), after the calls not yet started are cancelled.

    >>> run_all([lambda: 1, lambda: 2, lambda: 3])
    [1, 2, 3]
    """
    calls = list(calls)
    n = min(n_threads(), len(calls))
    if n <= 1:
        return [c() for c in calls]
    if threading.current_thread() is threading.main_thread():
        return _run_waiting(calls, _executor(n_threads()))
    pool = _executor(n_threads())
    futures: list[Future[Any]] = [pool.submit(c) for c in calls[1:]]
    first: list[T] = []
    error: BaseException | None = None
    try:
        first.append(calls[0]())
    except BaseException as e:  # re-raised once the others have ended
        error = e
    rest: list[T] = []
    for f in futures:
        try:
            rest.append(f.result())
        except BaseException as e:
            error = error or e
    if error is not None:
        raise error
    return first + rest


def _run_waiting(calls: list[Callable[[], T]], pool: ThreadPoolExecutor) -> list[T]:
    """Every call on the pool; the caller (the main thread) waits interruptibly."""
    futures: list[Future[Any]] = []
    try:
        # held back: an interrupt inside submit, between a worker's start and its
        # registration, leaves a thread the interpreter waits for forever at exit
        with signals_held():
            for c in calls:
                futures.append(pool.submit(c))
        pending = set(futures)
        while pending:
            done, pending = wait(pending, timeout=WAIT_SECONDS, return_when=FIRST_EXCEPTION)
            if any(f.exception() is not None for f in done):
                break
    except BaseException:
        _cancel_and_drain(futures)
        raise
    _cancel_and_drain(futures)  # after an error: let the started calls end first
    for f in futures:
        err = None if f.cancelled() else f.exception()
        if err is not None:
            raise err
    return [f.result() for f in futures]


def _cancel_and_drain(futures: list[Future[Any]]) -> None:
    """Cancel the calls not started and wait until the started ones have ended; a
    second interrupt meanwhile does not cut the wait short (the kernels would run on
    while the interpreter shuts down) and is raised after it."""
    for f in futures:
        f.cancel()
    again: BaseException | None = None
    while True:
        try:
            wait(futures)
            break
        except BaseException as e:  # KeyboardInterrupt again: keep draining
            again = again or e
    if again is not None:
        raise again
