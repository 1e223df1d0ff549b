"""The matching commands: ``match``, ``rig``, ``evaluate`` and ``batch``.

Each handler parses, loads, calls the library and writes; every user error is an
:class:`~robostereo.errors.InputError` (one line, exit code 2, no partial output).
"""

from __future__ import annotations

import argparse
import sys
from contextlib import nullcontext
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.cli._args import add_matcher_args, finite, matcher_params, require_at_least
from robostereo.cli._console import stage_reporter
from robostereo.errors import InputError

__all__ = [
    "add_batch_parser",
    "add_evaluate_parser",
    "add_match_parser",
    "add_parsers",
    "add_rig_parser",
    "run_batch_command",
    "run_evaluate",
    "run_match",
    "run_rig",
]


def add_parsers(sub: Any) -> None:
    """Add ``match``, ``rig``, ``evaluate`` and ``batch`` to the subcommands `sub`."""
    add_match_parser(sub)
    add_rig_parser(sub)
    add_evaluate_parser(sub)
    add_batch_parser(sub)


def add_match_parser(sub: Any) -> None:
    p = sub.add_parser(
        "match", help="match the edge points of a rectified stereo pair",
        description="Match edge points of a rectified pair (rows are epipolar lines) and "
                    "write them as CSV; with a camera, also 3-D points and depth bounds.",
    )
    p.add_argument("left", type=Path, help="left image (PPM/PGM/PNG/TIFF, 8 or 16 bit)")
    p.add_argument("right", type=Path, help="right image, same size")
    p.add_argument("--min-disparity", type=finite("--min-disparity"), required=True,
                   help="least disparity x_left - x_right, pixels")
    p.add_argument("--max-disparity", type=finite("--max-disparity"), required=True,
                   help="largest disparity, pixels")
    p.add_argument("--camera", type=Path,
                   help="camera YAML (see docs/guide/matching.md) for 3-D points")
    p.add_argument("-o", "--output", type=Path, required=True, help="matched points CSV")
    p.add_argument("--ply", type=Path, help="write the 3-D points as PLY (needs --camera)")
    p.add_argument("--edges", type=Path, help="write every left edge point as CSV")
    p.add_argument("--overlay", type=Path, help="PNG of the matches over the left image")
    p.add_argument("--threshold", type=finite("--threshold"), default=8.0,
                   help="edge threshold, grey levels per pixel on the 0..127 scale (8.0)")
    p.add_argument("--row-step", type=int, default=1, help="use every N-th row (1)")
    add_matcher_args(p)
    p.add_argument("--iterations", type=int, default=5, help="relaxation iterations (5)")
    p.add_argument("--seed-mode", action="store_true",
                   help="the thesis's matcher: relaxation, whole-pixel edges, plain w, one "
                        "threshold")
    p.set_defaults(handler=run_match)


def run_match(args: argparse.Namespace) -> int:
    from robostereo.io import (
        atomic_outputs,
        check_outputs,
        load_image,
        load_stereo_camera,
        write_csv,
        write_ply,
    )
    from robostereo.matcher.parameters import MatchParameters
    from robostereo.matcher.pipeline import match_stereo

    if args.ply is not None and args.camera is None:
        raise InputError("--ply needs --camera: 3-D points need the camera geometry")
    outs = check_outputs(
        {"-o": args.output, "--ply": args.ply, "--edges": args.edges, "--overlay": args.overlay},
        inputs=(args.left, args.right, args.camera),
    )
    left, bits_l = load_image(args.left)
    right, bits_r = load_image(args.right)
    if bits_l != bits_r:
        raise InputError(f"{args.right}: bit depth {bits_r} differs from the left image's {bits_l}")
    camera = load_stereo_camera(args.camera) if args.camera is not None else None
    base = MatchParameters.thesis() if args.seed_mode else MatchParameters()
    params = matcher_params(args, replace(
        base, threshold=args.threshold, row_step=args.row_step, bit_depth=bits_l,
        relaxation=replace(base.relaxation, iterations=args.iterations),
    ))
    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        result = match_stereo(left, right, (args.min_disparity, args.max_disparity),
                              params=params, camera=camera, progress=say)
    n_left, n_right, n = len(result.left_edges), len(result.right_edges), len(result)
    if n_left == 0:
        print(f"robostereo: warning: no edge points in {args.left} above threshold "
              f"{args.threshold}; the result is empty", file=sys.stderr)
    if result.disparity_range != (args.min_disparity, args.max_disparity):
        lo, hi = result.disparity_range
        print(f"robostereo: note: disparity range limited to {lo:g} .. {hi:g} (the image is "
              f"{result.image_shape[1]} pixels wide)", file=sys.stderr)
    if result.grey_map is not None:
        g = result.grey_map
        print(f"robostereo: note: the two views' grey levels differ (median difference "
              f"{g.residual_identity:.1f} grey levels at the matches, {g.residual_mapped:.1f} "
              f"mapped): matched again with {args.right.name}'s corrected (--no-photometric: "
              f"not)", file=sys.stderr)
    table = result.table()
    with atomic_outputs(outs) as tmp:  # all outputs or none
        write_csv(tmp["-o"], table)
        if "--ply" in tmp:
            write_ply(tmp["--ply"], np.column_stack([table["X"], table["Y"], table["Z"]]))
        if "--edges" in tmp:
            write_csv(tmp["--edges"], result.edge_table())
        if "--overlay" in tmp:
            from robostereo.plots import save_overlay

            save_overlay(tmp["--overlay"], left, table["x_left"], table["row"],
                         table["disparity"], title=f"{n} matched edge points")
    pct = 100.0 * n / n_left if n_left else 0.0
    print(f"{args.left.name}: {n_left} edge points left, {n_right} right, {n} matched "
          f"({pct:.1f}%) in {1000 * result.timings['total']:.1f} ms -> {args.output}")
    return 0


def _range_args(args: argparse.Namespace) -> tuple[float, float] | None:
    """``--min-disparity`` and ``--max-disparity`` as a range; None if neither is given."""
    lo, hi = args.min_disparity, args.max_disparity
    if (lo is None) != (hi is None):
        raise InputError("give both --min-disparity and --max-disparity, or neither")
    return None if lo is None else (lo, hi)


def add_rig_parser(sub: Any) -> None:
    p = sub.add_parser(
        "rig", help="match an original pair from a calibrated stereo rig",
        description="Rectify an original (distorted) pair with its calibration (OpenCV "
                    "YAML/JSON, ROS camera_info pair, Middlebury calib.txt), match, and "
                    "write points in rectified and original pixels and in millimetres "
                    "(left camera frame).",
    )
    p.add_argument("left", type=Path, help="original left image")
    p.add_argument("right", type=Path, help="original right image")
    p.add_argument("--calibration", type=Path, required=True,
                   help="stereo calibration (OpenCV FileStorage, calib.txt, or ROS left.yaml)")
    p.add_argument("--calibration-right", type=Path,
                   help="the right camera's ROS camera_info YAML (or OpenCV extrinsics)")
    p.add_argument("--min-disparity", type=finite("--min-disparity"),
                   help="least rectified disparity, pixels")
    p.add_argument("--max-disparity", type=finite("--max-disparity"),
                   help="largest rectified disparity, pixels")
    p.add_argument("--min-depth", type=finite("--min-depth"), help="nearest depth, mm")
    p.add_argument("--max-depth", type=finite("--max-depth"), help="farthest depth, mm")
    p.add_argument("-o", "--output", type=Path, required=True, help="matched points CSV")
    p.add_argument("--ply", type=Path, help="write the 3-D points as PLY")
    add_matcher_args(p)
    p.set_defaults(handler=run_rig)


def run_rig(args: argparse.Namespace) -> int:
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.matcher.parameters import MatchParameters
    from robostereo.rig import load_rig_pair, match_rig

    drange = _range_args(args)
    if (args.min_depth is None) != (args.max_depth is None):
        raise InputError("give both --min-depth and --max-depth, or neither")
    depth = None if args.min_depth is None else (args.min_depth, args.max_depth)
    if (drange is None) == (depth is None):
        raise InputError("give a disparity range (--min/--max-disparity) or a depth range "
                         "(--min/--max-depth)")
    outs = check_outputs({"-o": args.output, "--ply": args.ply},
                         inputs=(args.left, args.right, args.calibration, args.calibration_right))
    left, right, calib, bits = load_rig_pair(args.left, args.right, args.calibration,
                                             args.calibration_right)
    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        res = match_rig(left, right, calib, drange, depth_range_mm=depth,
                        params=matcher_params(args, MatchParameters(bit_depth=bits)),
                        names=(str(args.left), str(args.right)), progress=say)
    table = res.table()
    with atomic_outputs(outs) as tmp:  # all outputs or none
        write_csv(tmp["-o"], table)
        if "--ply" in tmp:
            write_ply(tmp["--ply"], np.column_stack([table["X"], table["Y"], table["Z"]]))
    n_left, n = len(res.match.left_edges), len(res)
    pct = 100.0 * n / n_left if n_left else 0.0
    lo, hi = res.match.disparity_range
    print(f"{args.left.name}: rectified, disparity {lo:.1f} .. {hi:.1f} px, {n_left} edge "
          f"points, {n} matched ({pct:.1f}%) in {1000 * res.match.timings['total']:.1f} ms "
          f"-> {args.output}")
    return 0


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
                    "truth surface (with calib.txt) and silhouette offsets.",
    )
    p.add_argument("scenes", type=Path, nargs="+", metavar="SCENE_DIR",
                   help="scene folders (other arguments, e.g. README.md, are skipped)")
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
                   help="write each scene's two curves as DIR/SCENE_curves.png")
    p.add_argument("--rule", choices=("project", "silhouette"), default="project",
                   help="the rule of the figures over all points and of the curves: the "
                        "project's (default, kept for continuity) or the silhouette rule, "
                        "fair to occluding contours; the outline figures give both")
    add_matcher_args(p)
    p.set_defaults(handler=run_evaluate)


def run_evaluate(args: argparse.Namespace) -> int:
    import json

    from robostereo.datasets import load_scene
    from robostereo.evaluation import evaluate_scene, format_evaluation
    from robostereo.matcher.parameters import MatchParameters
    from robostereo.plots import save_curves

    drange = _range_args(args)
    if args.plot is not None and not args.plot.is_dir():
        raise InputError(f"--plot {args.plot}: output folder does not exist")
    params = matcher_params(args, MatchParameters())
    dirs = [s for s in args.scenes if s.is_dir()]
    for s in args.scenes:
        if not s.is_dir():
            print(f"robostereo: note: skipping {s} (not a scene folder)", file=sys.stderr)
    if not dirs:
        raise InputError(f"no scene folders among {', '.join(map(str, args.scenes))}")
    results, failed = [], 0
    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        for d in dirs:
            say(f"evaluating {d}")
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


def add_batch_parser(sub: Any) -> None:
    p = sub.add_parser(
        "batch", help="match many pairs or capture folders, resumable, local or on Dask",
        description="Run the pipeline over every input folder of INPUT_DIR (pair folders: "
                    "left.*, right.*, optional camera.yaml and disparity.yaml; capture "
                    "folders: capture.yaml, left.png, right.png); write OUT_DIR/NAME.csv per "
                    "input and OUT_DIR/summary.csv.  Finished inputs are skipped on a rerun.",
    )
    p.add_argument("input_dir", type=Path, metavar="INPUT_DIR")
    p.add_argument("--out", type=Path, required=True, metavar="OUT_DIR", help="output folder")
    p.add_argument("--min-disparity", type=finite("--min-disparity"),
                   help="range for pair folders without disparity.yaml")
    p.add_argument("--max-disparity", type=finite("--max-disparity"))
    p.add_argument("--calibration", type=Path,
                   help="rig calibration for every pair folder (original images)")
    p.add_argument("--calibration-right", type=Path, help="right ROS camera_info YAML")
    p.add_argument("--ply", action="store_true", help="also write NAME.ply where 3-D is known")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="dask.distributed scheduler, e.g. tcp://10.0.0.5:8786 (default: "
                        "local processes)")
    p.add_argument("--workers", type=int, help="local processes (default: all cores)")
    p.set_defaults(handler=run_batch_command)


def run_batch_command(args: argparse.Namespace) -> int:
    from robostereo.batch import BatchOptions, run_batch

    drange = _range_args(args)
    if args.workers is not None:
        require_at_least("--workers", args.workers, 1)
    if args.calibration is not None:
        from robostereo.io.calibration_files import read_calibration

        read_calibration(args.calibration, args.calibration_right)  # fail early, once
    opts = BatchOptions(
        disparity_range=drange, ply=args.ply,
        calibration=None if args.calibration is None else str(args.calibration),
        calibration_right=None if args.calibration_right is None else str(args.calibration_right),
    )
    if sys.stderr.isatty():
        from rich.progress import Progress

        bar = Progress(transient=True)
        task = bar.add_task("robostereo batch", total=None)

        def progress(done: int, total: int, row: dict[str, Any]) -> None:
            bar.update(task, completed=done, total=total, description=f"{row['input']}")
    else:
        bar, progress = nullcontext(), None  # type: ignore[assignment]
    with bar:
        report = run_batch(args.input_dir, args.out, options=opts, scheduler=args.scheduler,
                           workers=args.workers, progress=progress)
    for name in report.failed:
        print(f"robostereo: error: {report.errors[name]}", file=sys.stderr)
    if report.redone:
        k = len(report.redone)
        print(f"robostereo: note: {k} finished input{' was' if k == 1 else 's were'} made "
              "with other options or input files: redone", file=sys.stderr)
    n = len(report.rows)
    print(f"{n} inputs: {len(report.processed) - len(report.failed)} processed, "
          f"{len(report.skipped)} already finished, {len(report.failed)} failed, in "
          f"{report.seconds:.1f} s -> {report.summary}")
    return 2 if report.failed else 0
