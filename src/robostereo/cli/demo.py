"""``robostereo demo``: the thesis's experiments on the simulated robots.

On the AdeptOne (the thesis's SCARA) it prints table 5-1 and the hub-pulley's figures
and writes the figures; with ``--robot six-axis`` it runs the block experiment on the
six-axis arm with an estimated hand-eye transform and writes its two capture folders
and ``handeye.yaml``; with ``--views N`` it locates the block and the pulley from N
views in a pattern and prints the figures (nothing written).  Every user error is an
:class:`~robostereo.errors.InputError` (one line, exit code 2, no partial output).
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.cli._args import require_seed, require_writable
from robostereo.cli._console import stage_reporter
from robostereo.cli._views_args import (
    DEFAULT_SPAN_MM,
    ROBOTS,
    add_views_options,
    check_views_options,
    on_pattern,
)
from robostereo.errors import InputError

__all__ = ["add_demo_parser", "print_views_demo", "run_demo_command", "run_demo_views"]


def add_demo_parser(sub: Any) -> None:
    p = sub.add_parser(
        "demo", help="run the thesis's experiments on the simulated AdeptOne (no files needed)",
        description="Render the precision block at two heights 79.65 mm apart and the "
                    "hub-pulley as the simulated AdeptOne's forearm camera sees them from "
                    "two viewpoints 20 mm apart, locate the edge points, and print table 5-1 "
                    "and the hub-pulley's % matched and % false per iteration; write the "
                    "figures to the output folder.  With --views N: locate the block (at two "
                    "heights) and the pulley from N views in a pattern and print the "
                    "figures (nothing written).",
    )
    p.add_argument("--out", type=Path,
                   help="folder for the figures (created; default ./robostereo-out)")
    p.add_argument("--seed", type=int, default=0, help="sensor-noise seed (0)")
    p.add_argument("--robot", choices=("adeptone", "six-axis"), default="adeptone",
                   help="the thesis's SCARA (adeptone, default) or the six-axis arm's block "
                        "experiment with an estimated hand-eye transform")
    p.add_argument("--json", action="store_true",
                   help="six-axis or --views: print one JSON object")
    add_views_options(p)
    p.set_defaults(handler=run_demo_command)


def run_demo_command(args: argparse.Namespace) -> int:
    from rich.console import Console

    if args.views is not None or args.pattern is not None or args.span is not None:
        return run_demo_views(args)
    if args.out is None:
        args.out = Path("robostereo-out")
    if args.robot != "six-axis" and args.json:
        raise InputError("--json needs --robot six-axis or --views")
    require_seed(args.seed)
    if args.out.exists() and not args.out.is_dir():
        raise InputError(f"{args.out}: exists and is not a folder")
    if args.robot == "six-axis":
        return _run_demo_six_axis(args)

    from robostereo.experiments import print_demo_report, run_demo, save_demo_figures

    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        say("rendering and matching the block and the hub-pulley")
        result = run_demo(seed=args.seed)
    print_demo_report(result, Console())
    args.out.mkdir(parents=True, exist_ok=True)
    paths = save_demo_figures(result, args.out)
    print(f"figures: {', '.join(str(p) for p in paths)}")
    return 0


def _run_demo_six_axis(args: argparse.Namespace) -> int:
    from robostereo.io import check_outputs
    from robostereo.robot.handeye import save_handeye_yaml
    from robostereo.robot.simulated.block_experiments import run_six_axis_block
    from robostereo.robot.simulated.cell_handeye import eye_to_hand_session

    for name in ("capture-low", "capture-high"):
        d = args.out / name
        if d.exists() and not (d / "capture.yaml").is_file():
            raise InputError(f"{d}: exists and is not a capture folder")
    require_writable(args.out, args.out)  # before the simulation's 10-15 s of work
    if args.out.is_dir():
        check_outputs({"--out": args.out / "handeye.yaml"})
    res = run_six_axis_block(seed=args.seed)
    args.out.mkdir(parents=True, exist_ok=True)
    # the two capture folders and handeye.yaml: all written, or none
    _replace_captures({args.out / "capture-low": res.heights[0].sim.capture,
                       args.out / "capture-high": res.heights[1].sim.capture},
                      then=lambda: save_handeye_yaml(args.out / "handeye.yaml",
                                                     res.calibration))
    s = res.summary()
    s["eye_to_hand"] = eye_to_hand_session(seed=args.seed)
    if args.json:
        print(json.dumps(s))
        return 0
    d = s["pose_difference"]
    print("six-axis arm (UR5-like, simulated), wrist camera 640 x 480 with lens distortion")
    print(f"  camera tilted {s['camera_tilt_deg']:.1f} deg from vertical; right minus left "
          f"view: {d['dx_mm']:.1f}, {d['dy_mm']:.1f}, {d['dz_mm']:.1f} mm, "
          f"{d['droll_deg']:.2f}, {d['dpitch_deg']:.2f}, {d['dyaw_deg']:.2f} deg")
    print(f"  hand-eye ({s['handeye_method']}, estimated from simulated views): error "
          f"{s['handeye_translation_error_mm']:.3f} mm, "
          f"{s['handeye_rotation_error_deg']:.4f} deg; board reprojection RMS "
          f"{s['reprojection_rms_px']:.3f} px")
    e = s["eye_to_hand"]
    print(f"  eye-to-hand (a fixed camera, the board on the flange, {e['views']} simulated "
          f"views): T_base_camera error {e['base_camera_mm']:.3f} mm, "
          f"{e['base_camera_deg']:.4f} deg; reprojection RMS {e['reprojection_rms_px']:.3f} px")
    print(f"  block top edge points: {s['block_points'][0]} (low), {s['block_points'][1]} "
          "(high)")
    print(f"  lift: measured {s['lift_mm']:.2f} mm, true {s['lift_true_mm']:.2f} mm "
          f"(error {s['lift_mm'] - s['lift_true_mm']:+.2f} mm)")
    print(f"  largest |z error| {s['max_abs_error_mm']:.2f} mm, its eq. 9 bound "
          f"{s['bound_at_max_error_mm']:.2f} mm; every point within its bound: "
          f"{'yes' if s['all_within_bound'] else 'NO'}")
    print(f"captures: {args.out / 'capture-low'}, {args.out / 'capture-high'}; "
          f"calibration: {args.out / 'handeye.yaml'}")
    return 0


def _replace_captures(captures: dict[Path, Any], then: Any = None) -> None:
    """Write every capture folder beside its target first (and run `then`, the last
    output, inside an atomic block), then rename them all into place: all or none."""
    from robostereo.robot.capture import write_capture

    temps = {t: t.with_name(f".{t.name}.new") for t in captures}
    try:
        for target, capture in captures.items():
            tmp = temps[target]
            if tmp.exists():
                shutil.rmtree(tmp)
            write_capture(tmp, capture)
            if target.exists() and not (target / "capture.yaml").is_file():
                raise InputError(f"{target}: exists and is not a capture folder")
        if then is not None:
            then()
    except BaseException:
        for tmp in temps.values():
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    for target, tmp in temps.items():
        if target.exists():
            shutil.rmtree(target)
        tmp.rename(target)


# -- demo --views N --------------------------------------------------------------------


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
                                robot=ROBOTS[args.robot], seed=args.seed)
    if args.json:
        from robostereo.io import plain_values

        print(json.dumps(plain_values(result)))
        return 0
    print_views_demo(result, robot=args.robot)
    return 0


def print_views_demo(result: dict[str, Any], *, robot: str = "adeptone") -> None:
    """Print :func:`~robostereo.experiments.run_views_demo`'s figures, one to a line."""
    arm = "six-axis arm (estimated hand-eye)" if robot == "six-axis" else "AdeptOne"
    print(f"{result['views']} views {on_pattern(result.get('pattern', 'line'))} spanning "
          f"{result.get('span_mm', DEFAULT_SPAN_MM):g} mm, {arm}")
    width = max(len(label) for _, label, _ in _DEMO_LINES)
    for key, label, fmt in _DEMO_LINES:
        if key in result:
            v = result[key]
            text = ("yes" if v else "NO") if isinstance(v, bool | np.bool_) else fmt.format(v)
            print(f"  {label:<{width}}  {text}")
