"""The ``robostereo`` command line: parses, loads, calls the library and writes.

Every user error (bad file, bad parameter, bad image) is reported as one line on
standard error, ``robostereo: error: ...``, with exit code 2 and no partial output.
"""

from __future__ import annotations

import argparse
import math
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager, nullcontext
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from robostereo import __version__
from robostereo.errors import InputError

__all__ = ["main"]

Handler = Callable[[argparse.Namespace], int]


def _stage_reporter(enabled: bool) -> tuple[AbstractContextManager[Any], Callable[[str], None]]:
    """A rich status line on a terminal; silence elsewhere."""
    if not enabled:
        return nullcontext(), lambda _s: None
    from rich.console import Console

    console = Console(stderr=True)
    status = console.status("starting")

    def say(stage: str) -> None:
        status.update(f"robostereo: {stage}")

    return status, say


def _finite(name: str, limit: float = math.inf) -> Callable[[str], float]:
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


def add_match_parser(sub: Any) -> None:
    p = sub.add_parser(
        "match", help="match the edge points of a rectified stereo pair",
        description="Match edge points of a rectified pair (rows are epipolar lines) and "
                    "write them as CSV; with a camera, also 3-D points and depth bounds.",
    )
    p.add_argument("left", type=Path, help="left image (PPM/PGM/PNG/TIFF, 8 or 16 bit)")
    p.add_argument("right", type=Path, help="right image, same size")
    p.add_argument("--min-disparity", type=_finite("--min-disparity"), required=True,
                   help="least disparity x_left - x_right, pixels")
    p.add_argument("--max-disparity", type=_finite("--max-disparity"), required=True,
                   help="largest disparity, pixels")
    p.add_argument("--camera", type=Path, help="camera YAML (see README) for 3-D points")
    p.add_argument("-o", "--output", type=Path, required=True, help="matched points CSV")
    p.add_argument("--ply", type=Path, help="write the 3-D points as PLY (needs --camera)")
    p.add_argument("--edges", type=Path, help="write every left edge point as CSV")
    p.add_argument("--overlay", type=Path, help="PNG of the matches over the left image")
    p.add_argument("--threshold", type=_finite("--threshold"), default=8.0,
                   help="edge threshold, grey levels per pixel on the 0..127 scale (8.0)")
    p.add_argument("--row-step", type=int, default=1, help="use every N-th row (1)")
    _add_matcher_args(p)
    p.add_argument("--iterations", type=int, default=5, help="relaxation iterations (5)")
    p.add_argument("--seed-mode", action="store_true",
                   help="the seed's matcher: relaxation, whole-pixel edges, plain w, one "
                        "threshold")
    p.set_defaults(handler=run_match)


def _unit_interval(name: str) -> Callable[[str], float]:
    finite = _finite(name)

    def parse(text: str) -> float:
        v = finite(text)
        if not 0.0 <= v <= 1.0:
            raise argparse.ArgumentTypeError(f"{name} must be in 0..1, got {text!r}")
        return v

    return parse


def _add_matcher_args(p: Any) -> None:
    """``--method``, ``--min-confidence``, ``--no-paths`` and ``--no-coarse``, shared by
    the commands that match."""
    from robostereo.pipeline import DEFAULT_MIN_CONFIDENCE, METHODS

    p.add_argument("--method", choices=METHODS, default=None,
                   help="matcher: window (default; every disparity scored by side-aware "
                        "census windows, calibrated confidence) or relaxation (the seed's)")
    p.add_argument("--min-confidence", type=_unit_interval("--min-confidence"), default=None,
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


def matcher_params(args: argparse.Namespace, base: Any) -> Any:
    """``base`` (MatchParameters) with the ``--method``, ``--min-confidence``,
    ``--no-paths`` and ``--no-coarse`` given."""
    changes: dict[str, Any] = {}
    if getattr(args, "method", None) is not None:
        changes["method"] = args.method
    if getattr(args, "min_confidence", None) is not None:
        changes["min_confidence"] = args.min_confidence
    if getattr(args, "paths", None) is False:
        changes["paths"] = False
    if getattr(args, "coarse", None) is False:
        changes["coarse"] = False
    return replace(base, **changes)


def run_match(args: argparse.Namespace) -> int:
    from robostereo.io import (
        atomic_outputs,
        check_outputs,
        load_image,
        load_stereo_camera,
        write_csv,
        write_ply,
    )
    from robostereo.pipeline import MatchParameters, match_stereo

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
    base = MatchParameters.seed() if args.seed_mode else MatchParameters()
    params = matcher_params(args, replace(
        base, threshold=args.threshold, row_step=args.row_step, bit_depth=bits_l,
        relaxation=replace(base.relaxation, iterations=args.iterations),
    ))
    status, say = _stage_reporter(sys.stderr.isatty())
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


# --- calibrated rigs, evaluation, batch (issue 4) ---------------------------------------


def _range_args(args: argparse.Namespace) -> tuple[float, float] | None:
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
    p.add_argument("--min-disparity", type=_finite("--min-disparity"),
                   help="least rectified disparity, pixels")
    p.add_argument("--max-disparity", type=_finite("--max-disparity"),
                   help="largest rectified disparity, pixels")
    p.add_argument("--min-depth", type=_finite("--min-depth"), help="nearest depth, mm")
    p.add_argument("--max-depth", type=_finite("--max-depth"), help="farthest depth, mm")
    p.add_argument("-o", "--output", type=Path, required=True, help="matched points CSV")
    p.add_argument("--ply", type=Path, help="write the 3-D points as PLY")
    _add_matcher_args(p)
    p.set_defaults(handler=run_rig)


def run_rig(args: argparse.Namespace) -> int:
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.pipeline import MatchParameters
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
    status, say = _stage_reporter(sys.stderr.isatty())
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
                    "project's rule, disparity RMS, and the same for StereoSGBM at the same "
                    "pixels, with times; 3-D errors in mm with a Middlebury calib.txt.",
    )
    p.add_argument("scenes", type=Path, nargs="+", metavar="SCENE_DIR",
                   help="scene folders (other arguments, e.g. README.md, are skipped)")
    p.add_argument("--json", action="store_true", help="print JSON instead of tables")
    p.add_argument("--min-disparity", type=_finite("--min-disparity"),
                   help="search range (default: the ground truth's)")
    p.add_argument("--max-disparity", type=_finite("--max-disparity"))
    p.add_argument("--scale", type=_finite("--scale"),
                   help="ground-truth scale d = raw / scale (default: scenes.json or known)")
    p.add_argument("--no-sgbm", action="store_true", help="leave out StereoSGBM")
    p.add_argument("--no-curves", action="store_true",
                   help="only the default operating points (no SGBM settings sweep)")
    p.add_argument("--plot", type=Path, metavar="DIR",
                   help="write each scene's two curves as DIR/SCENE_curves.png")
    _add_matcher_args(p)
    p.set_defaults(handler=run_evaluate)


def run_evaluate(args: argparse.Namespace) -> int:
    import json

    from robostereo.datasets import load_scene
    from robostereo.evaluation import evaluate_scene, format_evaluation
    from robostereo.pipeline import MatchParameters
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
    status, say = _stage_reporter(sys.stderr.isatty())
    with status:
        for d in dirs:
            say(f"evaluating {d}")
            try:
                scene = load_scene(d, scale=args.scale)
                ev = evaluate_scene(scene, disparity_range=drange, sgbm=not args.no_sgbm,
                                    curve=not args.no_curves,
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
    p.add_argument("--min-disparity", type=_finite("--min-disparity"),
                   help="range for pair folders without disparity.yaml")
    p.add_argument("--max-disparity", type=_finite("--max-disparity"))
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
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if args.calibration is not None:
        from robostereo.calibration import read_calibration

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


# --- the robot system: demo, capture, locate (issue 3) -----------------------------------


def add_demo_parser(sub: Any) -> None:
    p = sub.add_parser(
        "demo", help="run the seed's experiments on the simulated AdeptOne (no files needed)",
        description="Render the precision block at two heights 79.65 mm apart and the "
                    "hub-pulley as the simulated AdeptOne's forearm camera sees them from "
                    "two viewpoints 20 mm apart, locate the edge points, and print table 5-1 "
                    "and the hub-pulley's % matched and % false per iteration; write the "
                    "figures to the output folder.",
    )
    p.add_argument("--out", type=Path, default=Path("robostereo-out"),
                   help="folder for the figures (created; default ./robostereo-out)")
    p.add_argument("--seed", type=int, default=0, help="sensor-noise seed (0)")
    p.add_argument("--robot", choices=("adeptone", "six-axis"), default="adeptone",
                   help="the seed's SCARA (adeptone, default) or the six-axis arm's block "
                        "experiment with an estimated hand-eye transform")
    p.add_argument("--json", action="store_true", help="six-axis: print one JSON object")
    p.set_defaults(handler=run_demo_command)


def run_demo_command(args: argparse.Namespace) -> int:
    from rich.console import Console

    if args.robot == "six-axis":
        from robostereo.cli_robot import run_demo_six_axis

        return run_demo_six_axis(args)
    if args.json:
        raise InputError("--json needs --robot six-axis")

    from robostereo.experiments import print_demo_report, run_demo, save_demo_figures

    if args.seed < 0:
        raise InputError(f"--seed must be >= 0, got {args.seed}")
    if args.out.exists() and not args.out.is_dir():
        raise InputError(f"{args.out}: exists and is not a folder")
    status, say = _stage_reporter(sys.stderr.isatty())
    with status:
        say("rendering and matching the block and the hub-pulley")
        result = run_demo(seed=args.seed)
    print_demo_report(result, Console())
    args.out.mkdir(parents=True, exist_ok=True)
    paths = save_demo_figures(result, args.out)
    print(f"figures: {', '.join(str(p) for p in paths)}")
    return 0


def add_capture_parser(sub: Any) -> None:
    p = sub.add_parser(
        "capture", help="grab two views with the (simulated) robot into a capture folder",
        description="Move the AdeptOne's forearm camera to -D/2 and +D/2 about the centre "
                    "along the baseline direction, grab an image at each (rendered by the "
                    "simulator) and write DIR/left.png, DIR/right.png and DIR/capture.yaml.",
    )
    p.add_argument("--out", type=Path, required=True, metavar="DIR",
                   help="capture folder to create (must not exist, or be empty)")
    p.add_argument("--scene", choices=("block", "pulley"), default="block",
                   help="simulated object (block)")
    p.add_argument("--lift", type=_finite("--lift", 1e6), default=0.0,
                   help="block: raise of its top, mm (0; the seed's second set: 79.65)")
    p.add_argument("--baseline", type=_finite("--baseline", 1e6), default=20.0,
                   help="baseline D, mm (20)")
    p.add_argument("--direction", type=_finite("--direction", 1e6), default=0.0,
                   help="baseline direction from world X, degrees (0)")
    p.add_argument("--roll", type=_finite("--roll", 1e6), default=0.0,
                   help="camera yaw against the baseline at the centre, degrees (0)")
    p.add_argument("--center", type=_finite("--center", 1e6), nargs=2, default=(400.0, 0.0),
                   metavar=("X", "Y"), help="mid-baseline point, world mm (400 0)")
    p.add_argument("--seed", type=int, default=0, help="sensor-noise seed (0)")
    p.add_argument("--robot", choices=("adeptone", "six-axis"), default="adeptone",
                   help="simulated robot (adeptone: the seed's SCARA)")
    p.add_argument("--tilt", type=_finite("--tilt"), default=25.0,
                   help="six-axis: camera tilt from vertical, degrees (25)")
    p.add_argument("--handeye", type=Path,
                   help="six-axis: record this camera file's camera and hand_eye "
                        "(robostereo handeye's output) instead of the truth")
    p.set_defaults(handler=run_capture_command)


def run_capture_command(args: argparse.Namespace) -> int:
    from robostereo.experiments import RigSetup, simulate_capture
    from robostereo.robot.capture import write_capture

    if args.robot == "six-axis":
        from robostereo.cli_robot import run_capture_six_axis

        if args.direction != 0.0 or args.roll != 0.0 or tuple(args.center) != (400.0, 0.0):
            raise InputError("--direction, --roll and --center are for --robot adeptone; "
                             "the six-axis arm takes --baseline, --tilt and --handeye")
        if args.baseline == 20.0:  # the SCARA default; the six-axis views stand 40 mm apart
            args.baseline = 40.0
        return run_capture_six_axis(args)

    if args.seed < 0:
        raise InputError(f"--seed must be >= 0, got {args.seed}")
    out = args.out
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise InputError(f"{out}: exists and is not an empty folder")
    if not (out.parent if str(out.parent) else Path(".")).is_dir():
        raise InputError(f"{out}: parent folder {out.parent} does not exist")
    setup = RigSetup(center_xy=(args.center[0], args.center[1]), baseline_mm=args.baseline,
                     direction_deg=args.direction, roll_deg=args.roll)
    sim = simulate_capture(args.scene, setup=setup, lift_mm=args.lift, seed=args.seed)
    write_capture(out, sim.capture)
    g = sim.capture.epipolar
    print(f"{out}: {args.scene}, D = {g.baseline_mm:.3f} mm, alpha = "
          f"{math.degrees(g.alpha):.3f} deg, theta_l = {math.degrees(g.theta_l):.3f} deg, "
          f"theta_r = {math.degrees(g.theta_r):.3f} deg")
    return 0


def add_locate_parser(sub: Any) -> None:
    p = sub.add_parser(
        "locate", help="3-D world coordinates of the edge points of a capture folder",
        description="Rectify a capture folder's two views by their poses, match the edge "
                    "points, and write world and epipolar-frame coordinates with the eq. 9 "
                    "depth bound of every point (CSV; optionally PLY).",
    )
    p.add_argument("capture", type=Path, metavar="DIR", help="capture folder")
    p.add_argument("-o", "--output", type=Path,
                   help="points CSV (default DIR/located.csv)")
    p.add_argument("--ply", type=Path, help="write the world points as PLY")
    p.add_argument("--fuse", type=Path, metavar="DIR2",
                   help="a second capture of the scene (e.g. an orthogonal baseline): write "
                        "the two point sets merged, each point with its own bound")
    p.set_defaults(handler=run_locate_command)


def run_locate_command(args: argparse.Namespace) -> int:
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.robot.capture import locate_capture

    if args.fuse is not None:
        from robostereo.cli_robot import run_locate_fused

        return run_locate_fused(args)

    if not args.capture.is_dir():
        raise InputError(f"{args.capture}: capture folder not found")
    output = args.output if args.output is not None else args.capture / "located.csv"
    inputs = [args.capture / n for n in ("capture.yaml", "left.png", "right.png")]
    outs = check_outputs({"-o": output, "--ply": args.ply}, inputs=inputs)
    located = locate_capture(args.capture)
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


def _robot_parsers(sub: Any) -> None:
    """The any-arm subcommands (issue 9): handeye, simulate-handeye, plan."""
    from robostereo import cli_robot

    cli_robot.add_handeye_parser(sub)
    cli_robot.add_simulate_handeye_parser(sub)
    cli_robot.add_plan_parser(sub)


PARSERS: list[Callable[[Any], None]] = [add_match_parser]
PARSERS += [add_rig_parser, add_evaluate_parser, add_batch_parser]
PARSERS += [add_demo_parser, add_capture_parser, add_locate_parser]
PARSERS += [_robot_parsers]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="robostereo",
        description="Sparse 3-D edges from two views (after Kim, 1989).",
    )
    parser.add_argument("--version", action="version", version=f"robostereo {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for add in PARSERS:
        add(sub)
    return parser


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread so that it unwinds like Ctrl-C (SIGINT)."""


def _on_sigterm(signum: int, frame: Any) -> None:
    raise Terminated


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (0 ok, 2 bad input, 130 SIGINT,
    143 SIGTERM)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        return int(args.handler(args))
    except InputError as e:
        print(f"robostereo: error: {str(e).splitlines()[0] if str(e) else 'bad input'}",
              file=sys.stderr)
        return 2
    except OSError as e:  # the file system refused: a missing disk, a full one...
        where = f"{e.filename}: " if e.filename else ""
        print(f"robostereo: error: {where}{e.strerror or e.__class__.__name__}",
              file=sys.stderr)
        return 2
    except Terminated:
        print("robostereo: terminated", file=sys.stderr)
        return 143
    except KeyboardInterrupt:
        print("robostereo: interrupted", file=sys.stderr)
        return 130
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
