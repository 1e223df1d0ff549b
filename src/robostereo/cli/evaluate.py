"""``robostereo evaluate``: the matcher and StereoSGBM scored on scenes with ground truth.

Parses, loads, calls the library (:func:`~robostereo.evaluation.evaluate_scene`; for a
capture folder with depth maps, recognised by its ``capture.yaml``, locating as
``robostereo locate`` does and :func:`~robostereo.evaluation.evaluate_capture_depth`) and
prints; a scene that fails is reported and skipped (exit code 2 at the end), any other
user error is an :class:`~robostereo.errors.InputError` (one line, exit code 2).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

from robostereo.cli._args import (
    add_matcher_args,
    disparity_range_args,
    finite,
    matcher_params,
)
from robostereo.cli._console import stage_reporter
from robostereo.errors import InputError

__all__ = ["add_evaluate_parser", "run_evaluate"]


def add_evaluate_parser(sub: Any) -> None:
    p = sub.add_parser(
        "evaluate", help="score the matcher and StereoSGBM on scenes with ground truth",
        description="For each scene folder (left/right/gt_disp_left as in the developer "
                    "set, or a Middlebury layout): edge points, % matched, % false by the "
                    "project's rule (or --rule silhouette), disparity RMS, and the same for "
                    "StereoSGBM at the same pixels, with times; 3-D errors in mm with a "
                    "Middlebury calib.txt.  Then "
                    "both rules (the project's and the silhouette rule) near depth steps and "
                    "away, the confidence's calibration error, 3-D distances to the ground-"
                    "truth surface (with calib.txt) and silhouette offsets.  A capture "
                    "folder (capture.yaml) with ground-truth depth maps is located as "
                    "robostereo locate does and scored against its reference view's depth "
                    "map: 3-D errors, the share within each point's bound, the coverage "
                    "of the edge pixels both views see, and the same for StereoSGBM on "
                    "the rectified pair.",
    )
    p.add_argument("scenes", type=Path, nargs="+", metavar="SCENE_DIR",
                   help="scene folders or capture folders with depth maps (other "
                        "arguments, e.g. README.md, are skipped)")
    p.add_argument("--json", action="store_true", help="print JSON instead of tables")
    p.add_argument("--min-disparity", type=finite("--min-disparity"),
                   help="search range (default: the ground truth's)")
    p.add_argument("--max-disparity", type=finite("--max-disparity"))
    p.add_argument("--scale", type=finite("--scale"),
                   help="ground-truth scale d = raw / scale (default: scenes.json or known)")
    p.add_argument("--no-sgbm", action="store_true", help="leave out StereoSGBM")
    p.add_argument("--no-curves", action="store_true",
                   help="only the default operating points (no SGBM settings sweep)")
    p.add_argument("--plot", type=Path, metavar="DIR",
                   help="write each scene's two curves as DIR/SCENE_curves.png (a "
                        "capture's error histogram and coverage image as "
                        "DIR/NAME_depth_errors.png and DIR/NAME_coverage.png)")
    p.add_argument("--rule", choices=("project", "silhouette"), default="project",
                   help="the rule of the figures over all points and of the curves: the "
                        "project's (default, kept for continuity) or the silhouette rule, "
                        "fair to occluding contours; the outline figures give both")
    p.add_argument("--threshold", type=finite("--threshold"), default=None,
                   help="the edge threshold, grey levels per pixel on the 0..127 scale "
                        "(default 8.0); of a capture folder also that of the scored edge "
                        "pixels")
    p.add_argument("--matcher", choices=("auto", "pairs", "sweep"), default=None,
                   help="N-view capture folders: as robostereo locate's --matcher")
    add_matcher_args(p)
    p.set_defaults(handler=run_evaluate)


def run_evaluate(args: argparse.Namespace) -> int:
    import json

    from robostereo.datasets import load_scene
    from robostereo.evaluation import (
        evaluate_scene,
        format_capture_evaluation,
        format_evaluation,
    )
    from robostereo.matcher.parameters import MatchParameters
    from robostereo.plots import save_capture_plots, save_curves
    from robostereo.robot.views.depth_evaluation import evaluate_capture_folder

    drange = disparity_range_args(args)
    if args.plot is not None and not args.plot.is_dir():
        raise InputError(f"--plot {args.plot}: output folder does not exist")
    params = matcher_params(args, MatchParameters())
    if args.threshold is not None:
        params = replace(params, threshold=args.threshold)
    dirs = [s for s in args.scenes if s.is_dir()]
    for s in args.scenes:
        if not s.is_dir():
            print(f"robostereo: note: skipping {s} (not a scene folder)", file=sys.stderr)
    if not dirs:
        raise InputError(f"no scene folders among {', '.join(map(str, args.scenes))}")
    if all((d / "capture.yaml").is_file() for d in dirs):  # options no capture takes
        given = [flag for flag, on in (
            ("--scale", args.scale is not None),
            ("--min-disparity", args.min_disparity is not None),
            ("--max-disparity", args.max_disparity is not None),
            ("--no-curves", args.no_curves), ("--rule", args.rule != "project")) if on]
        if given:
            raise InputError(f"{', '.join(given)}: for scene folders with ground-truth "
                             f"disparities; {dirs[0]} is a capture folder (its depth "
                             "range and depth maps say what these would)")
    results, failed = [], 0
    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        for d in dirs:
            say(f"evaluating {d}")
            if (d / "capture.yaml").is_file():
                try:
                    cev, image = evaluate_capture_folder(
                        d, match=params, matcher=args.matcher, threshold=args.threshold,
                        sgbm=not args.no_sgbm)
                except InputError as e:
                    print(f"robostereo: error: {e}", file=sys.stderr)
                    failed += 1
                    continue
                results.append(cev)
                if not args.json:
                    print(format_capture_evaluation(cev) + "\n", flush=True)
                if args.plot is not None:
                    save_capture_plots(cev, image, args.plot)
                continue
            try:
                scene = load_scene(d, scale=args.scale)
                ev = evaluate_scene(scene, disparity_range=drange, sgbm=not args.no_sgbm,
                                    curve=not args.no_curves, rule=args.rule,
                                    params=replace(params, bit_depth=scene.bit_depth))
            except InputError as e:
                print(f"robostereo: error: {e}", file=sys.stderr)
                failed += 1
                continue
            results.append(ev)
            if not args.json:
                print(format_evaluation(ev) + "\n", flush=True)
            if args.plot is not None:
                save_curves(ev, args.plot / f"{ev.name}_curves.png")
    if args.json:
        print(json.dumps([ev.as_dict() for ev in results], indent=2))
    return 2 if failed else 0
