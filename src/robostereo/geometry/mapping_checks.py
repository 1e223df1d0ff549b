"""Checked reading of plain mappings (the contents of YAML files).

Each helper raises :class:`~robostereo.errors.InputError` with one line naming the
source (a file name) and the key, so that a bad file is reported where it is wrong.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from robostereo.errors import InputError, shown

__all__ = ["check_keys", "get_number", "get_pair", "is_number"]


def is_number(v: object) -> bool:
    """True for an int or float that is not a bool.

    >>> is_number(2), is_number(2.5), is_number(True), is_number("2")
    (True, True, False, False)
    """
    return isinstance(v, int | float) and not isinstance(v, bool)


def _finite(v: float) -> bool:
    """``math.isfinite``, False for an integer too big for a float."""
    try:
        return math.isfinite(v)
    except OverflowError:
        return False


def get_number(
    data: Mapping[str, Any], key: str, source: str, *, positive: bool = False
) -> float:
    """``data[key]`` as a finite float (``> 0`` if `positive`); InputError otherwise.

    >>> get_number({"z": 1000}, "z", "pose.yaml")
    1000.0
    """
    if key not in data:
        raise InputError(f"{source}: missing key '{key}'")
    v = data[key]
    if not is_number(v) or not _finite(v) or (positive and v <= 0):
        want = "a finite number > 0" if positive else "a finite number"
        raise InputError(f"{source}: key '{key}' must be {want}, got {shown(v)}")
    return float(v)


def get_pair(
    data: Mapping[str, Any],
    key: str,
    source: str,
    *,
    positive: bool = False,
    integer: bool = False,
    what: str = "[a, b]",
) -> tuple[float, float]:
    """``data[key]`` as two finite numbers (integers kept as they are if `integer`).

    >>> get_pair({"image_size": [640, 480]}, "image_size", "cam.yaml", integer=True)
    (640, 480)
    """
    if key not in data:
        raise InputError(f"{source}: missing key '{key}'")
    v = data[key]
    ok = isinstance(v, list | tuple) and len(v) == 2 and all(is_number(e) for e in v)
    if ok:
        ok = all(_finite(e) for e in v)
    if ok and positive:
        ok = all(e > 0 for e in v)
    if ok and integer:
        ok = all(isinstance(e, int) for e in v)
    if not ok:
        kind = "integers" if integer else "finite numbers"
        cond = " > 0" if positive else ""
        raise InputError(f"{source}: key '{key}' must be {what}, two {kind}{cond}, "
                         f"got {shown(v)}")
    return (v[0], v[1]) if integer else (float(v[0]), float(v[1]))


def check_keys(data: object, allowed: tuple[str, ...], source: str, what: str) -> None:
    """Raise InputError unless `data` is a mapping whose keys are all in `allowed`."""
    if not isinstance(data, Mapping):
        raise InputError(f"{source}: a {what} must be a mapping of keys {list(allowed)}")
    unknown = [k for k in data if k not in allowed]
    if unknown:
        raise InputError(f"{source}: unknown key '{unknown[0]}' (allowed: {', '.join(allowed)})")
