"""Argument types and checks shared by the commands.

The argparse types (:func:`finite`, :func:`unit_interval`) refuse a bad value while
parsing: argparse prints the usage and one error line and exits with code 2.  The
checks (:func:`require_at_least`, :func:`require_seed`, :func:`disparity_range_args`,
the output-folder checks) run in a command's handler, at the point where the command has
always checked them, and raise :class:`~robostereo.errors.InputError`: one
``robostereo: error:`` line, exit code 2.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

from robostereo.errors import InputError

__all__ = [
    "add_matcher_args",
    "disparity_range_args",
    "finite",
    "matcher_params",
    "require_at_least",
    "require_empty_folder",
    "require_output_folder",
    "require_positive",
    "require_seed",
    "require_writable",
    "unit_interval",
]


# -- argparse types --------------------------------------------------------------------


def finite(name: str, limit: float = math.inf) -> Callable[[str], float]:
    """An argparse type: a finite number, at most `limit` in magnitude.

    >>> finite("--lift", 1e6)("79.65")
    79.65
    >>> finite("--lift", 1e6)("1e7")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: --lift must be within +-1e+06, got '1e7'
    """

    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{name} must be finite, got {text!r}")
        if abs(v) > limit:
            raise argparse.ArgumentTypeError(f"{name} must be within +-{limit:g}, got {text!r}")
        return v

    return parse


def unit_interval(name: str) -> Callable[[str], float]:
    """An argparse type: a finite number in 0..1.

    >>> unit_interval("--min-confidence")("1.5")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: --min-confidence must be in 0..1, got '1.5'
    """
    as_finite = finite(name)

    def parse(text: str) -> float:
        v = as_finite(text)
        if not 0.0 <= v <= 1.0:
            raise argparse.ArgumentTypeError(f"{name} must be in 0..1, got {text!r}")
        return v

    return parse


# -- the matcher's options -------------------------------------------------------------


def add_matcher_args(p: Any) -> None:
    """``--method``, ``--min-confidence``, ``--no-paths``, ``--no-coarse``, ``--contour``,
    ``--no-photometric`` and ``--no-rows-check``, shared by the commands that match."""
    from robostereo.matcher.parameters import DEFAULT_MIN_CONFIDENCE, METHODS

    p.add_argument("--method", choices=METHODS, default=None,
                   help="matcher: window (default; every disparity scored by side-aware "
                        "census windows, calibrated confidence) or relaxation (the thesis's)")
    p.add_argument("--min-confidence", type=unit_interval("--min-confidence"), default=None,
                   help="least confidence P(correct) of an accepted match; lower: more "
                        "matches, higher: fewer false (default "
                        + ", ".join(f"{k} {v:.3g}" for k, v in DEFAULT_MIN_CONFIDENCE.items())
                        + ")")
    p.add_argument("--no-paths", dest="paths", action="store_false", default=None,
                   help="window method without the paths along the rows: a tenth to a quarter "
                        "faster, worse on repeated patterns and weak texture")
    p.add_argument("--no-coarse", dest="coarse", action="store_false", default=None,
                   help="window method: search a wide disparity range (over 64) whole, "
                        "without first narrowing it by a pass at half size")
    p.add_argument("--contour", action="store_true", default=None,
                   help="window method: also accept a match of confidence >= 0.8 that its "
                        "edge contour supports (neighbours up and down with its disparity, "
                        "accepted on their own): more points, most near depth steps")
    p.add_argument("--no-photometric", dest="photometric", action="store_false", default=None,
                   help="window method: do not compare the two views' grey levels at the "
                        "matches and match again with the right view's corrected where "
                        "they differ (a gain, offset or exposure change between the views)")
    p.add_argument("--no-rows-check", dest="rows_check", action="store_false", default=None,
                   help="window method: do not measure how far the two views' rows disagree "
                        "at the matches (warn and match again with the right view moved "
                        "beyond 0.4 px)")


def matcher_params(args: argparse.Namespace, base: Any) -> Any:
    """``base`` (MatchParameters) with the ``--method``, ``--min-confidence``,
    ``--no-paths``, ``--no-coarse``, ``--contour``, ``--no-photometric`` and
    ``--no-rows-check`` given."""
    changes: dict[str, Any] = {}
    if getattr(args, "method", None) is not None:
        changes["method"] = args.method
    if getattr(args, "min_confidence", None) is not None:
        changes["min_confidence"] = args.min_confidence
    if getattr(args, "paths", None) is False:
        changes["paths"] = False
    if getattr(args, "coarse", None) is False:
        changes["coarse"] = False
    if getattr(args, "contour", None):
        changes["contour"] = True
    if getattr(args, "photometric", None) is False:
        changes["photometric"] = False
    if getattr(args, "rows_check", None) is False:
        changes["rows_check"] = False
    return replace(base, **changes)


# -- checks in the handlers ------------------------------------------------------------


def require_at_least(option: str, value: int, least: int) -> None:
    """Raise :class:`InputError` unless the integer option's `value` is >= `least`.

    >>> require_at_least("--views", 2, 3)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: --views must be >= 3, got 2
    """
    if value < least:
        raise InputError(f"{option} must be >= {least}, got {value}")


def require_positive(option: str, value: float) -> None:
    """Raise :class:`InputError` unless the option's `value` is > 0.

    >>> require_positive("--baseline", -1.0)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: --baseline must be > 0, got -1.0
    """
    if not value > 0:
        raise InputError(f"{option} must be > 0, got {value}")


def require_seed(seed: int) -> None:
    """Raise :class:`InputError` unless ``--seed`` is >= 0 (numpy's generators refuse a
    negative one).

    >>> require_seed(-1)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: --seed must be >= 0, got -1
    """
    require_at_least("--seed", seed, 0)


def disparity_range_args(args: argparse.Namespace) -> tuple[float, float] | None:
    """``--min-disparity`` and ``--max-disparity`` as a range; None if neither is given."""
    lo, hi = args.min_disparity, args.max_disparity
    if (lo is None) != (hi is None):
        raise InputError("give both --min-disparity and --max-disparity, or neither")
    return None if lo is None else (lo, hi)


def _parent(path: Path) -> Path:
    return path.parent if str(path.parent) else Path(".")


def require_empty_folder(out: Path) -> None:
    """Raise :class:`InputError` unless the folder `out` can be created and filled: it
    does not exist or is an empty folder, and its parent folder exists."""
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise InputError(f"{out}: exists and is not an empty folder")
    if not _parent(out).is_dir():
        raise InputError(f"{out}: parent folder {out.parent} does not exist")


def require_output_folder(path: Path) -> None:
    """Raise :class:`InputError` unless the folder that the output file `path` goes into
    exists."""
    folder = _parent(path)
    if not folder.is_dir():
        raise InputError(f"{path}: output folder {folder} does not exist")


def require_writable(folder: Path, what: Path) -> None:
    """Refuse before any work a `folder` (or its nearest existing ancestor) in which no
    file can be made: a probe folder is created and removed at once."""
    import tempfile

    probe = folder
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    try:
        Path(tempfile.mkdtemp(prefix=".robostereo-probe-", dir=probe)).rmdir()
    except OSError as e:
        raise InputError(f"{what}: folder {probe} is not writable ({e.strerror})") from None
