"""The N-view options that several commands share: ``--views``, ``--pattern`` and
``--span`` (:func:`add_views_options`), their checks (:func:`check_views_options`), and
how the N-view commands name a pattern and a robot.

``demo``, ``capture`` and ``plan`` add the options (``locate`` reads N views from the
folder); each command's own N-view run lives in its module.  Every check runs before
any work and raises :class:`~robostereo.errors.InputError` (one line, exit code 2,
nothing written).
"""

from __future__ import annotations

import argparse
from typing import Any

from robostereo.cli._args import finite
from robostereo.errors import InputError

__all__ = [
    "DEFAULT_SPAN_MM",
    "MAX_VIEWS",
    "ROBOTS",
    "add_views_options",
    "check_views_options",
    "on_pattern",
]


MAX_VIEWS = 100
"""Most views a command takes (:func:`~robostereo.robot.views.viewpoints.view_offsets`'s limit)."""

DEFAULT_SPAN_MM = 80.0
"""Default ``--span``: the many-viewpoints targets' line of five views over 80 mm."""

#: the library's robot of each ``--robot`` choice
ROBOTS = {"adeptone": "scara", "six-axis": "six-axis"}


def add_views_options(p: Any, *, plan: bool = False) -> None:
    """``--views``, ``--pattern`` and (not for ``plan``) ``--span`` on the parser `p`."""
    from robostereo.robot.views.viewpoints import PATTERNS

    if plan:
        p.add_argument("--views", metavar="N|auto",
                       help="plan N views (2..100) or 'auto' (the fewest whose neighbours "
                            "stay within the thesis pair's disparity); without it, the "
                            "two-view plan")
    else:
        p.add_argument("--views", type=int, metavar="N",
                       help=f"grab N views (2..{MAX_VIEWS}) in a pattern instead of two")
    p.add_argument("--pattern", metavar="|".join(PATTERNS),
                   help="with --views: the viewpoints on a line (along the baseline "
                        "direction), a cross, or an arc about the object (line)")
    if not plan:
        p.add_argument("--span", type=finite("--span", 1e6), metavar="MM",
                       help=f"with --views: distance between the outermost viewpoints, mm "
                            f"({DEFAULT_SPAN_MM:g})")


def check_views_options(args: argparse.Namespace) -> tuple[int, str, float]:
    """``--views``, ``--pattern`` and ``--span``, checked: ``(count, pattern, span_mm)``.

    Raises
    ------
    InputError
        ``--pattern`` or ``--span`` without ``--views``; ``--views`` out of 2..100; an
        unknown pattern; a span that is not > 0; a cross of fewer than 3 views.
    """
    from robostereo.robot.views.viewpoints import PATTERNS

    span = getattr(args, "span", None)
    if args.views is None:
        given = [o for o, v in (("--pattern", args.pattern), ("--span", span)) if v is not None]
        if given:
            raise InputError(f"{' and '.join(given)} need{'s' if len(given) == 1 else ''} "
                             "--views N")
        return 0, "line", DEFAULT_SPAN_MM
    count = args.views
    if not 2 <= count <= MAX_VIEWS:
        raise InputError(f"--views must be in 2..{MAX_VIEWS}, got {count}")
    pattern = args.pattern if args.pattern is not None else "line"
    if pattern not in PATTERNS:
        raise InputError(f"--pattern must be one of {', '.join(PATTERNS)}, got {pattern!r}")
    if pattern == "cross" and count < 3:
        raise InputError(f"--pattern cross needs --views >= 3, got {count}")
    span = DEFAULT_SPAN_MM if span is None else span
    if not span > 0:
        raise InputError(f"--span must be > 0 mm, got {span:g}")
    return count, pattern, float(span)


def on_pattern(pattern: str) -> str:
    """'on a line', 'on a cross', 'on an arc'."""
    return f"on {'an' if pattern[:1] in 'aeiou' else 'a'} {pattern}"
