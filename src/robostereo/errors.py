"""Errors that robostereo raises for bad input.

Every check on user input raises :class:`InputError` with a one-line message that
names the offending parameter or file and what was expected; the command-line tool
prints that line and exits with code 2.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from pathlib import Path

__all__ = [
    "InputError",
    "UnreachablePoseError",
    "require_file",
    "require_finite",
    "require_positive",
]


class InputError(ValueError):
    """Bad input: a file, an image or a parameter that cannot be used.

    The message is a single line naming the problem, e.g.
    ``baseline_mm must be a finite number > 0, got -20.0``.
    """


class UnreachablePoseError(InputError):
    """A pose that the robot cannot reach (outside its workspace or joint limits)."""


def require_finite(name: str, value: float | Iterable[float]) -> None:
    """Raise :class:`InputError` unless every number in `value` is finite.

    >>> require_finite("focal_length_mm", 25.0)
    >>> require_finite("pixel_pitch_mm", [0.0172, float("nan")])
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: pixel_pitch_mm must be finite, got [0.0172, nan]
    """
    values = [value] if isinstance(value, int | float) else list(value)
    if not all(isinstance(v, int | float) and math.isfinite(v) for v in values):
        shown = value if isinstance(value, int | float) else values
        raise InputError(f"{name} must be finite, got {shown}")


def require_positive(name: str, value: float) -> None:
    """Raise :class:`InputError` unless `value` is a finite number > 0.

    >>> require_positive("baseline_mm", 20.0)
    >>> require_positive("baseline_mm", -20.0)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: baseline_mm must be a finite number > 0, got -20.0
    """
    if not isinstance(value, int | float) or not math.isfinite(value) or value <= 0:
        raise InputError(f"{name} must be a finite number > 0, got {value}")


def require_file(path: str | os.PathLike[str], what: str = "file") -> Path:
    """The path of an existing, non-empty regular file, or :class:`InputError`.

    >>> require_file("/no/cam.yaml", "camera file")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: /no/cam.yaml: camera file not found (or not a regular file)
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: {what} not found (or not a regular file)")
    if p.stat().st_size == 0:
        raise InputError(f"{p}: {what} is empty")
    return p
