"""The ``robostereo`` command line: parses, loads, calls the library and writes.

Every user error (bad file, bad parameter, bad image) is reported as one line on
standard error, ``robostereo: error: ...``, with exit code 2 and no partial output;
input that is used but looks wrong (:class:`~robostereo.errors.PlausibilityWarning`)
as ``robostereo: warning: ...``.  SIGTERM ends a command as SIGINT does: one line,
exit code 143 (130 for SIGINT), nothing half-written: a command's outputs appear all
together or not at all (an interrupt after they are in place leaves them whole).  Once
the first interrupt is being handled, further ones are ignored: a second Ctrl-C cannot
cut the cleanup short or end the program with a traceback.

Each command lives in its own module, with its parser, its handler and (for ``demo``,
``capture``, ``locate`` and ``plan``) its N-view run: :mod:`robostereo.cli.match`,
:mod:`robostereo.cli.rig_command`, :mod:`robostereo.cli.evaluate`,
:mod:`robostereo.cli.batch_command`, :mod:`robostereo.cli.demo`,
:mod:`robostereo.cli.capture_command`, :mod:`robostereo.cli.import_command`,
:mod:`robostereo.cli.locate`,
:mod:`robostereo.cli.handeye_commands` (``handeye`` and ``simulate-handeye``) and
:mod:`robostereo.cli.plan`.  What several commands share is private to the package:
the argument types and checks in ``robostereo.cli._args``, the N-view options
(``--views``, ``--pattern``, ``--span``) in ``robostereo.cli._views_args``, the camera
files of ``handeye --intrinsics`` and ``plan --camera`` in
``robostereo.cli._camera_files``, and the status line in ``robostereo.cli._console``.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import threading
import warnings
from collections.abc import Callable, Sequence
from typing import Any

from robostereo import __version__
from robostereo.cli import (
    batch_command,
    capture_command,
    demo,
    evaluate,
    handeye_commands,
    import_command,
    locate,
    match,
    plan,
    rig_command,
)
from robostereo.errors import InputError, PlausibilityWarning

__all__ = ["COMMANDS", "Terminated", "build_parser", "main"]

#: each command's parser builder, in the order ``--help`` lists the commands
COMMANDS: tuple[Callable[[Any], None], ...] = (
    match.add_match_parser,
    rig_command.add_rig_parser,
    evaluate.add_evaluate_parser,
    batch_command.add_batch_parser,
    demo.add_demo_parser,
    capture_command.add_capture_parser,
    import_command.add_import_parser,
    locate.add_locate_parser,
    handeye_commands.add_handeye_parser,
    handeye_commands.add_simulate_handeye_parser,
    plan.add_plan_parser,
)


def build_parser() -> argparse.ArgumentParser:
    """The top-level parser with every command's subcommand."""
    parser = argparse.ArgumentParser(
        prog="robostereo",
        description="Sparse 3-D edges from two views (after Kim, 1989).",
    )
    parser.add_argument("--version", action="version", version=f"robostereo {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for add in COMMANDS:
        add(sub)
    return parser


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread so that it unwinds like Ctrl-C (SIGINT)."""


#: the signals that end a command: SIGINT (Ctrl-C) and SIGTERM
_INTERRUPTS = (signal.SIGINT, signal.SIGTERM)


#: modules in whose frames an interrupt is not raised but sent again a little later:
#: LLVM calls back into them while numba compiles or loads its cache, and an exception
#: raised inside such a ctypes callback leaves LLVM's state broken (a crash, seen)
_NATIVE_CALLBACKS = ("llvmlite.",)
_RESEND_S = 0.05


def _in_native_callback(frame: Any) -> bool:
    """Whether `frame` or a caller of it runs in one of :data:`_NATIVE_CALLBACKS`."""
    while frame is not None:
        name = frame.f_globals.get("__name__", "")
        if name.startswith(_NATIVE_CALLBACKS):
            return True
        frame = frame.f_back
    return False


def _on_interrupt(signum: int, frame: Any) -> None:
    """The first SIGINT or SIGTERM: ignore any further one from now on, then unwind.

    A second Ctrl-C soon after the first would otherwise land in the unwinding (the
    outputs' temporary files removed, the threads joined, the interpreter's exit) and
    end the program with a ``KeyboardInterrupt`` traceback, or leave a temporary file.
    """
    for s in _INTERRUPTS:
        signal.signal(s, signal.SIG_IGN)
    raise Terminated if signum == signal.SIGTERM else KeyboardInterrupt


def _on_program_interrupt(signum: int, frame: Any) -> None:
    """:func:`_on_interrupt` for the program: one that arrives inside LLVM's callbacks
    (numba compiling) is sent again 50 ms later instead, until it lands where an
    exception can unwind.  (In a process that goes on, :func:`main` called with
    arguments, the signal is the caller's to time and is raised where it lands.)"""
    if _in_native_callback(frame):
        resend = threading.Timer(_RESEND_S, os.kill, (os.getpid(), signum))
        resend.daemon = True
        resend.start()
        return
    _on_interrupt(signum, frame)


def _show_warning(message: Warning | str, category: type[Warning], *rest: Any,
                  **kw: Any) -> None:
    if issubclass(category, PlausibilityWarning):
        print(f"robostereo: warning: {str(message).splitlines()[0]}", file=sys.stderr)
    else:
        _default_show(message, category, *rest, **kw)


_default_show = warnings.showwarning


def _interrupt_in(error: BaseException) -> KeyboardInterrupt | None:
    """The KeyboardInterrupt (SIGINT, or SIGTERM as :class:`Terminated`) that `error`
    was raised from, if any."""
    seen: set[int] = set()
    e: BaseException | None = error
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return e
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return None


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (0 ok, 2 bad input, 130 SIGINT,
    143 SIGTERM).

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments; default ``sys.argv[1:]``: the ``robostereo`` program, which
        exits when this returns.

    Notes
    -----
    On the main thread, SIGTERM (and SIGINT, unless it is ignored or handled by
    someone else) raise :class:`Terminated` (:class:`KeyboardInterrupt`), and the first
    of them makes both ignored while the command unwinds.  Called with `argv` (in a
    process that goes on), the handlers are restored on return; without it (the
    program) they stay ignored after an interrupt, so that a second Ctrl-C during the
    interpreter's exit (worker threads joined, ``atexit``) is quiet too, and nothing the
    exit prints after the one line is shown.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    previous: dict[int, Any] = {}
    interrupted = False
    if threading.current_thread() is threading.main_thread():
        previous = {s: signal.getsignal(s) for s in _INTERRUPTS}
        handler = _on_program_interrupt if argv is None else _on_interrupt
        signal.signal(signal.SIGTERM, handler)
        if previous[signal.SIGINT] is signal.default_int_handler:  # not SIG_IGN (nohup)
            signal.signal(signal.SIGINT, handler)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("always", PlausibilityWarning)
            warnings.showwarning = _show_warning
            return int(args.handler(args))
    except InputError as e:
        print(f"robostereo: error: {str(e).splitlines()[0] if str(e) else 'bad input'}",
              file=sys.stderr)
        return 2
    except OSError as e:  # the file system refused: a missing disk, a full one...
        where = f"{e.filename}: " if e.filename else ""
        print(f"robostereo: error: {where}{e.strerror or e.__class__.__name__}",
              file=sys.stderr)
        return 2
    except KeyboardInterrupt as e:  # Terminated too
        interrupted = True
        return _report_interrupt(e)
    except SystemError as e:
        # the signal handler ran inside a numba dispatcher's call on this thread, which
        # then reports "returned a result with an exception set": the interrupt it is
        cause = _interrupt_in(e)
        if cause is None:
            raise
        interrupted = True
        return _report_interrupt(cause)
    finally:
        if interrupted and argv is None:
            # the program's signals stay ignored (Notes), and what its exit prints after
            # the one line is not shown: work the interrupt cut short (numba's compiler
            # in mid-build) leaves llvmlite objects whose finalizers print tracebacks
            # late in the teardown, where sys.unraisablehook is no longer asked (seen in
            # a clean CI run); the exit itself still runs (pools, semaphores, atexit)
            _silence_stderr()
        else:
            for s, handler in previous.items():
                if handler is not None:
                    signal.signal(s, handler)


def _report_interrupt(cause: KeyboardInterrupt) -> int:
    """The one line of an interrupt, and its exit code (143 SIGTERM, 130 SIGINT)."""
    if threading.current_thread() is threading.main_thread():
        for s in _INTERRUPTS:  # raised without the handler (a library's own): ignore too
            if signal.getsignal(s) in (_on_interrupt, _on_program_interrupt):
                signal.signal(s, signal.SIG_IGN)
    terminated = isinstance(cause, Terminated)
    print(f"robostereo: {'terminated' if terminated else 'interrupted'}", file=sys.stderr)
    return 143 if terminated else 130


def _silence_stderr() -> None:
    """Flush the standard error and point its file descriptor at ``/dev/null``."""
    try:
        sys.stderr.flush()
        null = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(null, sys.stderr.fileno())
        finally:
            os.close(null)
    except (OSError, ValueError, AttributeError):  # no stderr or no descriptor: nothing
        pass
