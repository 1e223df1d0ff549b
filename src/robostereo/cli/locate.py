"""``robostereo locate``: the 3-D world coordinates of a capture folder's edge points.

A two-view folder is rectified by its poses and matched (``--fuse`` merges a second
one); a folder of N views has each edge point's ray searched in the other views, every
view as reference.  Each point is written with its eq. 9 depth bound.  Every user error
is an :class:`~robostereo.errors.InputError` (one line, exit code 2, no partial output).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.cli._args import finite
from robostereo.cli._console import stage_reporter
from robostereo.errors import InputError

__all__ = ["add_locate_parser", "run_locate_command", "run_locate_views"]


def add_locate_parser(sub: Any) -> None:
    p = sub.add_parser(
        "locate", help="3-D world coordinates of the edge points of a capture folder",
        description="Rectify a capture folder's two views by their poses, match the edge "
                    "points, and write world and epipolar-frame coordinates with the eq. 9 "
                    "depth bound of every point (CSV; optionally PLY).  A folder of N views "
                    "(capture.yaml with views:): two views as the two-view folder; more by "
                    "the plane sweep (each edge point's ray searched in the other views, "
                    "every view as reference) or by pairs (--matcher pairs: the central "
                    "view paired with each other view through the two-view matcher), each "
                    "point written once with its bound, confidence and view count.",
    )
    p.add_argument("capture", type=Path, metavar="DIR", help="capture folder")
    p.add_argument("-o", "--output", type=Path,
                   help="points CSV (default DIR/located.csv)")
    p.add_argument("--ply", type=Path, help="write the world points as PLY")
    p.add_argument("--fuse", type=Path, metavar="DIR2",
                   help="a second capture of the scene (e.g. an orthogonal baseline): write "
                        "the two point sets merged, each point with its own bound")
    p.add_argument("--matcher", choices=("auto", "pairs", "sweep"), default=None,
                   help="N-view folders: pairs through the two-view matcher or the plane "
                        "sweep (default auto: pairs for two views, the sweep for more)")
    p.add_argument("--threshold", type=finite("--threshold"), default=None,
                   help="edge threshold, grey levels per pixel on the 0..127 scale: lower "
                        "finds more, weaker edge points (default 8.0; see the guide's "
                        "'edge-point density')")
    p.set_defaults(handler=run_locate_command)


def _locate_parameters(args: argparse.Namespace) -> Any:
    """The two-view locate's parameters: the defaults, the edge threshold if given."""
    from robostereo.matcher.parameters import MatchParameters
    from robostereo.robot.capture import LocateParameters

    if args.threshold is None:
        return None
    return LocateParameters(match=MatchParameters(threshold=args.threshold))


def run_locate_command(args: argparse.Namespace) -> int:
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.robot.capture import locate_capture

    for d in (args.capture, args.fuse):
        if d is not None and not d.is_dir():
            raise InputError(f"{d}: capture folder not found")
    from robostereo.robot.views.views_folder import is_views_folder

    if any(d is not None and is_views_folder(d) for d in (args.capture, args.fuse)):
        return run_locate_views(args)
    if args.matcher is not None:
        raise InputError(f"{args.capture / 'capture.yaml'}: --matcher chooses how an N-view "
                         "folder (views:) is matched; this folder has two views (left, "
                         "right), which the two-view matcher locates")
    if args.fuse is not None:
        return _run_locate_fused(args)

    output = args.output if args.output is not None else args.capture / "located.csv"
    outs = check_outputs({"-o": output, "--ply": args.ply}, inputs=_capture_files(args))
    located = locate_capture(args.capture, params=_locate_parameters(args))
    with atomic_outputs(outs) as tmp:  # all outputs or none
        write_csv(tmp["-o"], located.table())
        if "--ply" in tmp:
            write_ply(tmp["--ply"], located.world)
    n_left, n = len(located.result.left_edges), len(located)
    lo, hi = located.disparity_range
    zb = located.z_bound
    bound = f", depth bound {np.median(zb):.1f} mm (median)" if n else ""
    print(f"{args.capture}: disparity {lo:g} .. {hi:g} px, {n_left} edge points, {n} located"
          f"{bound} -> {output}")
    return 0


def _capture_files(args: argparse.Namespace) -> list[Path]:
    """The files of the capture folders a ``locate`` reads (none may be an output)."""
    from robostereo.robot.capture import CAPTURE_YAML

    return [d / n for d in (args.capture, args.fuse) if d is not None
            for n in (CAPTURE_YAML, "left.png", "right.png")]


def _run_locate_fused(args: argparse.Namespace) -> int:
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.robot.capture import locate_capture
    from robostereo.robot.planning import fuse_located

    output = args.output if args.output is not None else args.capture / "located-fused.csv"
    outs = check_outputs({"-o": output, "--ply": args.ply}, inputs=_capture_files(args))
    params = _locate_parameters(args)
    a, b = locate_capture(args.capture, params=params), locate_capture(args.fuse, params=params)
    fused = fuse_located(a, b)
    with atomic_outputs(outs) as tmp:  # all outputs or none
        write_csv(tmp["-o"], fused.table())
        if "--ply" in tmp:
            write_ply(tmp["--ply"], fused.world)
    print(f"{args.capture}: {len(a)} located; {args.fuse}: {len(b)} located; fused "
          f"{len(fused)} points ({fused.duplicates} seen twice) -> {output}")
    return 0


# -- locate on an N-view folder --------------------------------------------------------


def run_locate_views(args: argparse.Namespace) -> int:
    """``locate DIR`` on an N-view folder: every view as reference, the points merged,
    each with its bound, confidence and view count (CSV; optionally PLY)."""
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.robot.capture import CAPTURE_YAML
    from robostereo.robot.views.views_folder import (
        is_views_folder,
        read_views_capture,
        views_folder_files,
    )

    if args.fuse is not None:  # name the folder of N views: either may be it
        nview = args.capture if is_views_folder(args.capture) else args.fuse
        raise InputError(f"{nview / CAPTURE_YAML}: has N views (views:), and --fuse merges "
                         "two-view captures (locate an N-view folder alone: every view pair "
                         "is used)")
    output = args.output if args.output is not None else args.capture / "located.csv"
    outs = check_outputs({"-o": output, "--ply": args.ply},
                         inputs=views_folder_files(args.capture))
    capture = read_views_capture(args.capture)
    from robostereo.robot.views.locating import locate_views
    from robostereo.robot.views.view_pairs import is_pairs
    from robostereo.robot.views.views_parameters import ViewsParameters

    params = ViewsParameters(matcher=args.matcher or "auto")
    if args.threshold is not None:  # the sweep's and the pairs' matcher's alike
        params = replace(params, threshold=args.threshold,
                         pair_match=_locate_parameters(args))

    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        say(f"locating the edge points of {len(capture)} views")
        unit = "pairs" if is_pairs(capture, params) else "reference views"
        located = locate_views(capture, params=params, source=str(
            args.capture / "capture.yaml"), progress=lambda done, total: say(
            f"locating: {done} of {total} {unit} done"))
    table = located.table()
    with atomic_outputs(outs) as tmp:  # all outputs or none
        write_csv(tmp["-o"], table)
        if "--ply" in tmp:
            write_ply(tmp["--ply"], located.world, fields=located.ply_fields())
    n = len(located)
    extra = ""
    if n:
        vc = np.asarray(located.view_count)
        extra = (f", bound {np.median(located.bound_mm):.2f} mm (median), seen by "
                 f"{np.median(vc):g} views (median, {int(vc.min())} .. {int(vc.max())})")
    print(f"{args.capture}: {len(capture)} views, {n} points located{extra} -> {output}")
    return 0
