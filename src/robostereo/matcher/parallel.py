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
in short interruptible waits; on an interrupt it closes the batch, so that the calls
not yet started never start, waits for the running ones to end (a kernel cannot be
stopped midway; a share of an image takes seconds at most) and then raises the
interrupt.

An interrupt can arrive between any two bytecodes of the main thread, also when the
main thread holds the signals back, because the kernel delivers a signal to any
thread that does not (a Dask or pytest-xdist thread) and Python then runs the handler
on the main thread at once.  So nothing here depends on bookkeeping the main thread
could be cut off in the middle of: each batch counts its running calls itself, under
its own lock, on the worker threads; and the workers are daemon threads started once,
which the interpreter never waits for at exit (a worker started but not yet recorded
when an interrupt came would otherwise keep the process alive for ever).
"""

from __future__ import annotations

import os
import queue
import threading
from collections.abc import Callable, Sequence
from typing import Any, Generic, TypeVar

from robostereo.errors import InputError

__all__ = ["n_threads", "run_all"]

T = TypeVar("T")

_lock = threading.Lock()
_pool: tuple[int, _Pool] | None = None  # (pid, pool)

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


class _Pool:
    """Daemon worker threads taking ``(batch, index)`` items from one queue."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self.queue: queue.SimpleQueue[tuple[_Batch[Any], int] | None] = queue.SimpleQueue()
        for k in range(workers):
            threading.Thread(target=self._work, name=f"robostereo-{k}", daemon=True).start()

    def _work(self) -> None:
        while True:
            item = self.queue.get()
            if item is None:  # the pool was replaced
                return
            batch, i = item
            batch.run(i)
            # hold nothing of a finished batch while waiting for the next: its calls'
            # closures reach their arguments (the images of a whole match)
            del item, batch

    def retire(self) -> None:
        for _ in range(self.workers):
            self.queue.put(None)


def _the_pool(workers: int) -> _Pool:
    global _pool
    with _lock:
        if _pool is None or _pool[0] != os.getpid() or _pool[1].workers != workers:
            # a forked child inherits the pool object but not its threads; a pool of
            # another size (ROBOSTEREO_THREADS changed) lets its threads end
            if _pool is not None and _pool[0] == os.getpid():
                _pool[1].retire()
            _pool = (os.getpid(), _Pool(workers))
        return _pool[1]


def _done() -> None:
    """Stands for a call of a batch that has run."""


class _Batch(Generic[T]):
    """The calls of one :func:`run_all`: results, errors, and a gate.

    A call starts only while the batch is open; the batch closes on the first error
    and on an interrupt of the caller.  ``run`` is the only code on the workers, and
    it keeps the count of running calls under the batch's lock, so a caller cut off
    anywhere can still wait for exactly the calls that started.
    """

    def __init__(self, calls: list[Callable[[], T]]) -> None:
        self.calls = calls
        self.results: list[Any] = [None] * len(calls)
        self.errors: list[BaseException | None] = [None] * len(calls)
        self._cond = threading.Condition()
        self._open = True
        self._running = 0
        self._left = len(calls)

    def run(self, i: int) -> None:
        with self._cond:
            if not self._open:
                self._left -= 1
                self._cond.notify_all()
                return
            self._running += 1
        try:
            self.results[i] = self.calls[i]()
        except BaseException as e:  # handed to the caller
            self.errors[i] = e
        finally:
            self.calls[i] = _done  # the call and what it reaches are let go
            with self._cond:
                self._running -= 1
                self._left -= 1
                if self.errors[i] is not None:
                    self._open = False
                self._cond.notify_all()

    def _settled(self) -> bool:
        return self._running == 0 and (self._left == 0 or not self._open)

    def wait(self) -> None:
        """Until every call has ended, or an error has closed the batch and the started
        calls have ended; in short waits, so that the main thread sees signals."""
        with self._cond:
            while not self._settled():
                self._cond.wait(WAIT_SECONDS)

    def close_and_drain(self) -> None:
        """No call starts any more; wait until the started ones have ended.  A second
        interrupt meanwhile does not cut the wait short (the kernels would run on while
        the interpreter shuts down) and is raised after it."""
        again: BaseException | None = None
        while True:
            try:
                with self._cond:
                    self._open = False
                    while self._running:
                        self._cond.wait(WAIT_SECONDS)
                break
            except BaseException as e:  # KeyboardInterrupt again: keep draining
                again = again or e
        if again is not None:
            raise again

    def outcome(self) -> list[T]:
        """The results in order, or the first error in call order."""
        for err in self.errors:
            if err is not None:
                raise err
        return list(self.results)


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
    pool = _the_pool(n_threads())
    batch = _Batch(calls)
    if threading.current_thread() is threading.main_thread():
        # every call on the pool; the main thread only waits, interruptibly
        try:
            for i in range(len(calls)):
                pool.queue.put((batch, i))
            batch.wait()
        except BaseException:
            batch.close_and_drain()
            raise
    else:
        for i in range(1, len(calls)):
            pool.queue.put((batch, i))
        batch.run(0)
        batch.wait()
    return batch.outcome()
