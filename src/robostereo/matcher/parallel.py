"""Threads for the matcher: the two images' stages side by side, image bands at once.

The matcher's kernels are numba functions compiled ``nogil``, so Python threads run
them on separate cores.  A pool of worker threads is kept per process (made on first
use, made again after a fork); the calling thread always does one share of the work
itself, and work given to the pool never waits on the pool, so concurrent callers
(e.g. a Dask worker's threads) cannot deadlock it.

The number of threads is the number of cores this process may run on, or the
environment variable ``ROBOSTEREO_THREADS`` (1: everything on the calling thread).
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any, TypeVar

from robostereo.errors import InputError

__all__ = ["n_threads", "run_all"]

T = TypeVar("T")

_lock = threading.Lock()
_pool: tuple[int, int, ThreadPoolExecutor] | None = None  # (pid, workers, pool)


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

    The first call runs on the calling thread, the others on the pool.  An exception
    of any call is raised after all have ended.

    >>> run_all([lambda: 1, lambda: 2, lambda: 3])
    [1, 2, 3]
    """
    calls = list(calls)
    n = min(n_threads(), len(calls))
    if n <= 1:
        return [c() for c in calls]
    pool = _executor(n - 1)
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
