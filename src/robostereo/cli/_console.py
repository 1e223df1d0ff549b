"""What the commands show on the terminal while they work."""

from __future__ import annotations

from collections.abc import Callable
from contextlib import AbstractContextManager, nullcontext
from typing import Any

__all__ = ["stage_reporter"]


def stage_reporter(enabled: bool) -> tuple[AbstractContextManager[Any], Callable[[str], None]]:
    """A rich status line on a terminal; silence elsewhere.

    Returns the status line's context and the function that names the current stage.
    """
    if not enabled:
        return nullcontext(), lambda _s: None
    from rich.console import Console

    console = Console(stderr=True)
    status = console.status("starting")

    def say(stage: str) -> None:
        status.update(f"robostereo: {stage}")

    return status, say
