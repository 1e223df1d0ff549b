"""The ``robostereo`` command line: parses, loads, calls the library and writes.

Every user error (bad file, bad parameter, bad image) is reported as one line on
standard error, ``robostereo: error: ...``, with exit code 2 and no partial output;
input that is used but looks wrong (:class:`~robostereo.errors.PlausibilityWarning`)
as ``robostereo: warning: ...``.  SIGTERM ends a command as SIGINT does: one line,
exit code 143 (130 for SIGINT), nothing half-written: a command's outputs appear all
together or not at all (an interrupt after they are in place leaves them whole).

The commands live by group: :mod:`robostereo.cli.matching` (``match``, ``rig``,
``evaluate``, ``batch``) and :mod:`robostereo.cli.robot` (``demo``, ``capture``,
``locate``, ``handeye``, ``simulate-handeye``, ``plan``); the argument types and checks
they share are in ``robostereo.cli._args``.
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
from robostereo.cli import matching, robot
from robostereo.errors import InputError, PlausibilityWarning

__all__ = ["GROUPS", "Terminated", "build_parser", "main"]

#: the command groups, in the order their commands are listed in ``--help``
GROUPS: tuple[Callable[[Any], None], ...] = (matching.add_parsers, robot.add_parsers)


def build_parser() -> argparse.ArgumentParser:
    """The top-level parser with every command group's subcommands."""
    parser = argparse.ArgumentParser(
        prog="robostereo",
        description="Sparse 3-D edges from two views (after Kim, 1989).",
    )
    parser.add_argument("--version", action="version", version=f"robostereo {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for add in GROUPS:
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
