"""Errors that robostereo raises for bad input.

Every check on user input raises :class:`InputError` with a one-line message that
names the offending parameter or file and what was expected; the command-line tool
prints that line and exits with code 2.

Input that can be used but is probably not what was meant (a translation that looks
like metres in a millimetre file, a quaternion normalised, few edge points located)
gives a :class:`PlausibilityWarning` (:func:`warn_input`) with a one-line message; the
command-line tool prints it as ``robostereo: warning: ...`` and goes on.
"""

from __future__ import annotations

import math
import numbers
import os
import reprlib
import warnings
from collections.abc import Iterable
from pathlib import Path
from typing import Any

__all__ = [
    "InputError",
    "PlausibilityWarning",
    "UnreachablePoseError",
    "is_finite_number",
    "require_file",
    "require_finite",
    "require_int",
    "require_nonnegative",
    "require_one_length",
    "require_positive",
    "require_range",
    "shown",
    "warn_input",
]


class InputError(ValueError):
    """Bad input: a file, an image or a parameter that cannot be used.

    The message is a single line naming the problem, e.g.
    ``baseline_mm must be a finite number > 0, got -20.0``.  Line breaks in a
    message (from a value quoted in it) are shown as ``\\n``, so it stays one line.
    """

    def __init__(self, message: object = "", *args: object) -> None:
        text = str(message)
        super().__init__(text.replace("\r", "\\r").replace("\n", "\\n"), *args)


class PlausibilityWarning(UserWarning):
    """Input that is used but is probably not what was meant (one-line message)."""


def warn_input(message: str) -> None:
    """Warn with a one-line :class:`PlausibilityWarning` (shown once per call site and
    message, as Python shows warnings).

    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     warn_input("pose_left: translation looks like metres")
    >>> w[0].category.__name__, str(w[0].message)
    ('PlausibilityWarning', 'pose_left: translation looks like metres')
    """
    warnings.warn(str(message).replace("\n", "\\n"), PlausibilityWarning, stacklevel=2)


class UnreachablePoseError(InputError):
    """A pose that the robot cannot reach (outside its workspace or joint limits)."""


class _BoundedRepr(reprlib.Repr):
    """:mod:`reprlib` with a limit for integers that shows their digit count."""

    def repr_int(self, x: int, level: int) -> str:
        if x.bit_length() <= 64:
            return repr(x)
        # str() of a 5000-digit integer raises (Python's digit limit); its size is enough
        return f"<integer of {x.bit_length()} bits>"


_REPR = _BoundedRepr()
_REPR.maxlevel, _REPR.maxother = 3, 40
_REPR.maxlist = _REPR.maxtuple = _REPR.maxdict = _REPR.maxset = 6
_REPR.maxstring = 60


def shown(value: object, width: int = 60) -> str:
    """A value for an error message: a repr of bounded size, cut to `width` characters.

    Nested lists, mappings, strings and integers are cut before they are written out
    (:mod:`reprlib`), so a value shared many times over (a YAML alias of aliases) or a
    5000-digit integer is shown in a few dozen characters, not expanded.

    >>> shown([0.0172, 0.0137])
    '[0.0172, 0.0137]'
    >>> a = ["x"] * 9
    >>> for _ in range(8):
    ...     a = [a] * 9
    >>> shown(a)
    '[[[[...], [...], [...], [...], [...], [...], ...], [[...]...'
    >>> shown(10**4000)
    '<integer of 13288 bits>'
    """
    r = _REPR.repr(value)
    return r if len(r) <= width else r[:width - 3] + "..."


def is_finite_number(v: object) -> bool:
    """A real number (not a bool) that is finite as a float; an integer too big for a
    float is not.

    >>> is_finite_number(2.5), is_finite_number(float("nan")), is_finite_number(10**400)
    (True, False, False)
    """
    if isinstance(v, bool):
        return False
    try:
        return isinstance(v, numbers.Real) and math.isfinite(v)
    except OverflowError:
        return False


def require_finite(name: str, value: float | Iterable[float]) -> None:
    """Raise :class:`InputError` unless every number in `value` is finite.

    >>> require_finite("focal_length_mm", 25.0)
    >>> require_finite("pixel_pitch_mm", [0.0172, float("nan")])
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: pixel_pitch_mm must be finite, got [0.0172, nan]
    """
    values = [value] if isinstance(value, numbers.Real) else list(value)
    if not all(is_finite_number(v) or isinstance(v, bool) for v in values):
        raise InputError(f"{name} must be finite, got "
                         f"{shown(value if isinstance(value, numbers.Real) else values)}")


def require_positive(name: str, value: float) -> None:
    """Raise :class:`InputError` unless `value` is a finite number > 0.

    >>> require_positive("baseline_mm", 20.0)
    >>> require_positive("baseline_mm", -20.0)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: baseline_mm must be a finite number > 0, got -20.0
    """
    if not is_finite_number(value) or value <= 0:
        raise InputError(f"{name} must be a finite number > 0, got {shown(value)}")


def require_nonnegative(name: str, value: float) -> None:
    """Raise :class:`InputError` unless `value` is a finite number >= 0.

    >>> require_nonnegative("noise_sigma", 0.0)
    >>> require_nonnegative("noise_sigma", -1.0)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: noise_sigma must be >= 0, got -1.0
    """
    require_finite(name, value)
    if value < 0:
        raise InputError(f"{name} must be >= 0, got {shown(value)}")


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


def require_int(name: str, value: Any, *, minimum: int | None = None) -> int:
    """``value`` as an ``int`` if it is a whole number (an integer type) >= `minimum`.

    Floats, even whole ones like ``2.0``, and booleans are refused: a parameter that
    counts something is an integer.

    >>> require_int("row_step", 2, minimum=1)
    2
    >>> require_int("row_step", 2.0, minimum=1)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: row_step must be an integer >= 1, got 2.0
    """
    bound = "" if minimum is None else f" >= {minimum}"
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InputError(f"{name} must be an integer{bound}, got {shown(value)}")
    v = int(value)
    if minimum is not None and v < minimum:
        raise InputError(f"{name} must be an integer{bound}, got {shown(v)}")
    return v


def _listed(items: Iterable[object]) -> str:
    """``a, b and c``."""
    words = [str(v) for v in items]
    return words[0] if len(words) == 1 else f"{', '.join(words[:-1])} and {words[-1]}"


def require_one_length(names: Iterable[str], *arrays: Any) -> None:
    """Refuse 1-D arrays (anything with a ``size``) of different lengths, naming them.

    >>> require_one_length(("rows", "x"), [1, 2], [3, 4])
    >>> require_one_length(("rows", "x", "disparity"), [1, 2], [3], [4, 5])
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: rows, x and disparity must be of one length, got 2, 1 and 2
    """
    sizes = [len(a) for a in arrays]
    if len(set(sizes)) > 1:
        raise InputError(f"{_listed(names)} must be of one length, got {_listed(sizes)}")


def require_range(name: str, value: Any) -> tuple[float, float]:
    """``(min, max)`` as two floats: a pair of finite real numbers with min <= max.

    >>> require_range("disparity_range", (0, 12))
    (0.0, 12.0)
    >>> require_range("disparity_range", 5)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: disparity_range must be (min, max), two numbers, got 5
    """
    given = shown(value)
    if isinstance(value, str | bytes) or not isinstance(value, Iterable):
        raise InputError(f"{name} must be (min, max), two numbers, got {given}")
    items = list(value)
    if len(items) != 2 or not all(
        isinstance(v, numbers.Real) and not isinstance(v, bool) for v in items
    ):
        raise InputError(f"{name} must be (min, max), two numbers, got {given}")
    if not (is_finite_number(items[0]) and is_finite_number(items[1])):
        raise InputError(f"{name} must be finite, got {given}")
    lo, hi = float(items[0]), float(items[1])
    if lo > hi:
        raise InputError(f"{name} is empty: min {lo} > max {hi}")
    return lo, hi
