"""The ``robostereo`` command line: parses, loads, calls the library and writes.

Every user error (bad file, bad parameter, bad image) is reported as one line on
standard error, ``robostereo: error: ...``, with exit code 2 and no partial output;
input that is used but looks wrong (:class:`~robostereo.errors.PlausibilityWarning`)
as ``robostereo: warning: ...``.  SIGTERM ends a command as SIGINT does: one line,
exit code 143 (130 for SIGINT), nothing half-written: a command's outputs appear all
together or not at all (an interrupt after they are in place leaves them whole).

Each command lives in its own module, with its parser, its handler and (for ``demo``,
``capture``, ``locate`` and ``plan``) its N-view run: :mod:`robostereo.cli.match`,
:mod:`robostereo.cli.rig_command`, :mod:`robostereo.cli.evaluate`,
:mod:`robostereo.cli.batch_command`, :mod:`robostereo.cli.demo`,
:mod:`robostereo.cli.capture_command`, :mod:`robostereo.cli.locate`,
:mod:`robostereo.cli.handeye_commands` (``handeye`` and ``simulate-handeye``) and
:mod:`robostereo.cli.plan`.  What several commands share is private to the package:
the argument types and checks in ``robostereo.cli._args``, the N-view options
(``--views``, ``--pattern``, ``--span``) in ``robostereo.cli._views_args``, the camera
files of ``handeye --intrinsics`` and ``plan --camera`` in
``robostereo.cli._camera_files``, and the status line in ``robostereo.cli._console``.
"""

from __future__ import annotations

import argparse
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


def _on_sigterm(signum: int, frame: Any) -> None:
    raise Terminated


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
    143 SIGTERM)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _on_sigterm)
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
    except Terminated:
        print("robostereo: terminated", file=sys.stderr)
        return 143
    except KeyboardInterrupt:
        print("robostereo: interrupted", file=sys.stderr)
        return 130
    except SystemError as e:
        # the signal handler ran inside a numba dispatcher's call on this thread, which
        # then reports "returned a result with an exception set": the interrupt it is
        cause = _interrupt_in(e)
        if cause is None:
            raise
        print(f"robostereo: {'terminated' if isinstance(cause, Terminated) else 'interrupted'}",
              file=sys.stderr)
        return 143 if isinstance(cause, Terminated) else 130
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
