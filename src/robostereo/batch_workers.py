"""The local worker processes of :func:`robostereo.batch.run_batch`: their share of the
cores, their end with the main process, and stopping them at once.

A batch must never leave a process behind or a half-written output: a worker ends
when its parent ends (even killed outright), a SIGTERM makes it remove its temporary
outputs and exit, and an interrupted batch terminates its pool without the pool's
threads printing tracebacks after the one-line message.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from concurrent.futures import ProcessPoolExecutor
from typing import Any

__all__ = ["die_with_parent", "start_worker", "stop_workers", "worker_terminated"]


def start_worker(parent: int, threads: int) -> None:
    """Initializer of a local worker: its share of the cores for the matcher's threads
    (unless ``ROBOSTEREO_THREADS`` is set), and :func:`die_with_parent`."""
    if not os.environ.get("ROBOSTEREO_THREADS", "").strip():
        os.environ["ROBOSTEREO_THREADS"] = str(threads)
    die_with_parent(parent)


def die_with_parent(parent: int) -> None:
    """Initializer of a local worker: end when the main process `parent` ends.

    On Linux the kernel kills the worker when its parent dies (``PR_SET_PDEATHSIG``),
    even by SIGKILL; elsewhere, and as a fallback, a thread checks twice a second that
    the parent is still there.  SIGINT is left to the main process, which stops the
    workers itself (with SIGTERM): a worker then removes its temporary outputs and
    ends at once (exit code 143).
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, worker_terminated)
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))  # PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:
        os._exit(1)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="robostereo-parent-watch", daemon=True).start()


def worker_terminated(signum: int, frame: Any) -> None:
    """SIGTERM in a local worker: no half-written ``.part`` left, no traceback."""
    from robostereo.io import remove_live_parts

    remove_live_parts()
    os._exit(143)


def stop_workers(pool: ProcessPoolExecutor) -> None:
    """Terminate a pool's worker processes now (an interrupted batch).

    The pool's manager thread may then try to settle futures that were just cancelled
    and print a traceback of ``InvalidStateError`` / ``CancelledError`` after the
    one-line "interrupted": exceptions of those two kinds in threads are silenced.
    """
    from concurrent.futures import CancelledError, InvalidStateError

    previous = threading.excepthook

    def quiet(args: threading.ExceptHookArgs) -> None:
        if not isinstance(args.exc_value, CancelledError | InvalidStateError):
            previous(args)

    threading.excepthook = quiet
    handles = list((getattr(pool, "_processes", None) or {}).values())
    for proc in handles:
        proc.terminate()
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in handles:
        proc.join(timeout=5.0)
        if proc.is_alive():
            proc.kill()
