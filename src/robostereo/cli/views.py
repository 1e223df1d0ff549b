"""The N-view parts of the robot commands: ``capture --views``, ``locate`` on an N-view
folder, ``demo --views`` and ``plan --views``.

:mod:`robostereo.cli.robot` owns the commands and their parsers; it adds the options
here (:func:`add_views_options`) and hands a command over when they are given.  Every
check runs before any work and raises :class:`~robostereo.errors.InputError` (one line,
exit code 2, nothing written).
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

import numpy as np

from robostereo.cli._args import finite, require_empty_folder, require_seed
from robostereo.cli._console import stage_reporter
from robostereo.errors import InputError

__all__ = [
    "DEFAULT_SPAN_MM",
    "MAX_VIEWS",
    "add_views_options",
    "check_views_options",
    "print_views_demo",
    "run_demo_views",
    "run_locate_views",
    "run_plan_views",
    "uses_views",
    "views_capture",
]

MAX_VIEWS = 100
"""Most views a command takes (:func:`~robostereo.robot.views.viewpoints.view_offsets`'s limit)."""

DEFAULT_SPAN_MM = 80.0
"""Default ``--span``: the many-viewpoints targets' line of five views over 80 mm."""

_ROBOTS = {"adeptone": "scara", "six-axis": "six-axis"}


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


def uses_views(args: argparse.Namespace) -> bool:
    """Whether the command was given ``--views`` (``--pattern`` or ``--span`` alone are
    refused by :func:`check_views_options`)."""
    return getattr(args, "views", None) is not None


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


def _on(pattern: str) -> str:
    """'on a line', 'on a cross', 'on an arc'."""
    return f"on {'an' if pattern[:1] in 'aeiou' else 'a'} {pattern}"


# -- capture ---------------------------------------------------------------------------


def views_capture(args: argparse.Namespace) -> int:
    """``capture --views N``: the simulated robot grabs N views into a views folder."""
    from robostereo.robot.simulated.grab_views import simulate_views
    from robostereo.robot.views.views_folder import write_views_capture

    count, pattern, span = check_views_options(args)
    if args.baseline != 20.0:
        raise InputError("--baseline is for two views; with --views give --span")
    if args.handeye is not None:
        raise InputError("--handeye is for two views; with --views the six-axis arm records "
                         "the hand-eye transform it estimates from simulated board views")
    kw: dict[str, Any] = {}
    if args.robot == "six-axis":
        if args.direction != 0.0 or args.roll != 0.0 or tuple(args.center) != (400.0, 0.0):
            raise InputError("--direction, --roll and --center are for --robot adeptone; "
                             "the six-axis arm takes --tilt")
        if not 0 <= args.tilt < 80:
            raise InputError(f"--tilt must be in [0, 80) degrees, got {args.tilt}")
        from robostereo.robot.simulated.sixaxis_rig import SixAxisViewpoints

        kw["viewpoints"] = SixAxisViewpoints(tilt_deg=args.tilt)
    else:
        from robostereo.robot.simulated.scara_rig import RigSetup

        kw["setup"] = RigSetup(center_xy=(args.center[0], args.center[1]),
                               direction_deg=args.direction, roll_deg=args.roll)
    require_seed(args.seed)
    require_empty_folder(args.out)
    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        say(f"grabbing {count} views ({pattern}, {span:g} mm)")
        sim = simulate_views(args.scene, count=count, pattern=pattern, span_mm=span,
                             robot=_ROBOTS[args.robot], lift_mm=args.lift, seed=args.seed,
                             **kw)
        say("writing the capture folder")
        write_views_capture(args.out, sim.capture)
    cap = sim.capture
    near, far = cap.depth_range_mm
    print(f"{args.out}: {args.scene}, {len(cap)} views {_on(pattern)} spanning {span:g} mm "
          f"(optical centres at most {cap.span_mm:.3f} mm apart), depths {near:g} .. "
          f"{far:g} mm"
          + (", hand-eye estimated from simulated board views"
             if args.robot == "six-axis" else ""))
    return 0


# -- locate ----------------------------------------------------------------------------


def run_locate_views(args: argparse.Namespace) -> int:
    """``locate DIR`` on an N-view folder: every view as reference, the points merged,
    each with its bound, confidence and view count (CSV; optionally PLY)."""
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.robot.views.views_folder import read_views_capture, views_folder_files

    if args.fuse is not None:
        raise InputError(f"--fuse merges two-view captures; {args.capture} has N views "
                         "(locate it alone: every view pair is used)")
    output = args.output if args.output is not None else args.capture / "located.csv"
    outs = check_outputs({"-o": output, "--ply": args.ply},
                         inputs=views_folder_files(args.capture))
    capture = read_views_capture(args.capture)
    from robostereo.robot.views.locate_views import locate_views

    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        say(f"locating the edge points of {len(capture)} views")
        located = locate_views(capture, progress=lambda done, total: say(
            f"locating: {done} of {total} reference views done"))
    table = located.table()
    with atomic_outputs(outs) as tmp:  # all outputs or none
        write_csv(tmp["-o"], table)
        if "--ply" in tmp:
            write_ply(tmp["--ply"], located.world,
                      fields={k: table[k] for k in ("bound_mm", "confidence", "view_count")})
    n = len(located)
    extra = ""
    if n:
        vc = np.asarray(located.view_count)
        extra = (f", bound {np.median(located.bound_mm):.2f} mm (median), seen by "
                 f"{np.median(vc):g} views (median, {int(vc.min())} .. {int(vc.max())})")
    print(f"{args.capture}: {len(capture)} views, {n} points located{extra} -> {output}")
    return 0


# -- demo ------------------------------------------------------------------------------

#: the keys ``demo --views`` prints, and how (label, format)
_DEMO_LINES = (
    ("views", "views", "{}"),
    ("lift_mm", "lift measured, mm", "{:.3f}"),
    ("lift_true_mm", "lift true, mm", "{:.3f}"),
    ("max_abs_error_mm", "block's largest |z error|, mm", "{:.3f}"),
    ("bound_at_max_error_mm", "its bound, mm", "{:.3f}"),
    ("median_bound_mm", "block's median bound, mm", "{:.3f}"),
    ("all_within_bound", "every point within its bound", "{}"),
    ("outline_coverage", "block's top outline covered", "{:.1%}"),
    ("pulley_matched", "pulley matched", "{:.2%}"),
    ("pulley_false", "pulley false", "{:.2%}"),
    ("seconds", "seconds", "{:.1f}"),
)


def run_demo_views(args: argparse.Namespace) -> int:
    """``demo --views N``: the block and the pulley located from N simulated views; the
    figures printed (``--json``: one JSON object), nothing written."""
    count, pattern, span = check_views_options(args)
    require_seed(args.seed)
    if args.out is not None:
        raise InputError("--out: demo --views prints its figures and writes no files")
    from robostereo.experiments import run_views_demo

    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        say(f"rendering {count} views ({pattern}, {span:g} mm) and locating the block and "
            "the pulley")
        result = run_views_demo(count=count, pattern=pattern, span_mm=span,
                                robot=_ROBOTS[args.robot], seed=args.seed)
    if args.json:
        from robostereo.io import plain_values

        print(json.dumps(plain_values(result)))
        return 0
    print_views_demo(result, robot=args.robot)
    return 0


def print_views_demo(result: dict[str, Any], *, robot: str = "adeptone") -> None:
    """Print :func:`~robostereo.experiments.run_views_demo`'s figures, one to a line."""
    arm = "six-axis arm (estimated hand-eye)" if robot == "six-axis" else "AdeptOne"
    print(f"{result['views']} views {_on(result.get('pattern', 'line'))} spanning "
          f"{result.get('span_mm', DEFAULT_SPAN_MM):g} mm, {arm}")
    width = max(len(label) for _, label, _ in _DEMO_LINES)
    for key, label, fmt in _DEMO_LINES:
        if key in result:
            v = result[key]
            text = ("yes" if v else "NO") if isinstance(v, bool | np.bool_) else fmt.format(v)
            print(f"  {label:<{width}}  {text}")


# -- plan ------------------------------------------------------------------------------


def run_plan_views(args: argparse.Namespace, camera: Any, extra: dict[str, float],
                   near: float, far: float) -> int:
    """``plan --views N|auto``: the span (and count) of N views in a pattern."""
    from robostereo.robot.planning import plan_views
    from robostereo.robot.views.viewpoints import PATTERNS

    text = str(args.views).strip().lower()
    views: int | None = None
    if text != "auto":
        try:
            views = int(text)
        except ValueError:
            raise InputError(f"--views must be a whole number in 2..{MAX_VIEWS} or 'auto', "
                             f"got {args.views!r}") from None
        if not 2 <= views <= MAX_VIEWS:
            raise InputError(f"--views must be in 2..{MAX_VIEWS}, got {views}")
    pattern = args.pattern if args.pattern is not None else "line"
    if pattern not in PATTERNS:
        raise InputError(f"--pattern must be one of {', '.join(PATTERNS)}, got {pattern!r}")
    if pattern == "cross" and views is not None and views < 3:
        raise InputError(f"--pattern cross needs --views >= 3, got {views}")
    if args.image is not None:
        raise InputError("--image chooses a two-view baseline direction; with --views a "
                         "cross sees every edge direction")
    plan = plan_views(camera, args.depth, args.accuracy, views=views, pattern=pattern,
                      depth_range_mm=(near, far),
                      disparity_uncertainty_px=args.disparity_uncertainty, **extra)
    out = {
        "views": plan.views,
        "pattern": plan.pattern,
        "span_mm": float(f"{plan.span_mm:.10g}"),
        "step_mm": float(f"{plan.step_mm:.10g}"),
        "effective_baseline_mm": float(f"{plan.effective_baseline_mm:.10g}"),
        "step_disparity_px": float(f"{plan.step_disparity_px:.10g}"),
        "disparity_range": list(plan.disparity_range),
        "bound_terms_mm": [float(f"{v:.10g}") for v in plan.bound_terms_mm],
    }
    if args.json:
        print(json.dumps(out))
        return 0
    t = plan.bound_terms_mm
    print(f"{plan.views} views {_on(plan.pattern)} spanning {plan.span_mm:.4g} mm (neighbours "
          f"{plan.step_mm:.4g} mm apart) for a {args.accuracy:g} mm bound at {args.depth:g} mm:"
          f" as precise as two views {plan.effective_baseline_mm:.4g} mm apart (eq. 9 terms: "
          f"baseline {t[0]:.3f}, focal length {t[1]:.3f}, disparity {t[2]:.3f} mm)")
    print(f"neighbouring views: disparity {plan.step_disparity_px:.1f} px at the target; "
          f"search {plan.disparity_range[0]:g} .. {plan.disparity_range[1]:g} px for depths "
          f"{near:g} .. {far:g} mm")
    return 0
