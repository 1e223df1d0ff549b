"""``robostereo rig``: an original pair of a calibrated stereo rig, rectified and matched.

Parses, loads, calls the library (:func:`~robostereo.rig.match_rig`) and writes; every
user error is an :class:`~robostereo.errors.InputError` (one line, exit code 2, no
partial output).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.cli._args import (
    add_matcher_args,
    disparity_range_args,
    finite,
    matcher_params,
)
from robostereo.cli._console import stage_reporter
from robostereo.errors import InputError

__all__ = ["add_rig_parser", "run_rig"]


def add_rig_parser(sub: Any) -> None:
    p = sub.add_parser(
        "rig", help="match an original pair from a calibrated stereo rig",
        description="Rectify an original (distorted) pair with its calibration (OpenCV "
                    "YAML/JSON, ROS camera_info pair, Middlebury calib.txt), match, and "
                    "write points in rectified and original pixels and in millimetres "
                    "(left camera frame; with --base-camera also the robot's base frame).",
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
    p.add_argument("--ply", type=Path, help="write the 3-D points as PLY (in the base frame "
                                            "with --base-camera)")
    p.add_argument("--base-camera", type=Path, metavar="CELL_YAML",
                   help="the left camera's eye-to-hand calibration (robostereo handeye --mode "
                        "eye-to-hand): also write the points in the robot's base frame "
                        "(X_base, Y_base, Z_base)")
    add_matcher_args(p)
    p.set_defaults(handler=run_rig)


def run_rig(args: argparse.Namespace) -> int:
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.matcher.parameters import MatchParameters
    from robostereo.rig import load_rig_pair, match_rig

    drange = disparity_range_args(args)
    if (args.min_depth is None) != (args.max_depth is None):
        raise InputError("give both --min-depth and --max-depth, or neither")
    depth = None if args.min_depth is None else (args.min_depth, args.max_depth)
    if (drange is None) == (depth is None):
        raise InputError("give a disparity range (--min/--max-disparity) or a depth range "
                         "(--min/--max-depth)")
    outs = check_outputs({"-o": args.output, "--ply": args.ply},
                         inputs=(args.left, args.right, args.calibration, args.calibration_right,
                                 args.base_camera))
    left, right, calib, bits = load_rig_pair(args.left, args.right, args.calibration,
                                             args.calibration_right)
    base_camera = None
    if args.base_camera is not None:
        from robostereo.robot.handeye import load_base_camera_yaml

        cell, base_camera = load_base_camera_yaml(args.base_camera)
        if tuple(cell.image_size) != tuple(calib.image_size):
            raise InputError(f"{args.base_camera}: camera image size {cell.image_size[0]} x "
                             f"{cell.image_size[1]} is not the rig's {calib.image_size[0]} x "
                             f"{calib.image_size[1]} (calibrate the rig's left camera)")
    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        res = match_rig(left, right, calib, drange, depth_range_mm=depth,
                        params=matcher_params(args, MatchParameters(bit_depth=bits)),
                        names=(str(args.left), str(args.right)), progress=say)
    table = res.table(base_camera)
    xyz = ("X_base", "Y_base", "Z_base") if base_camera is not None else ("X", "Y", "Z")
    with atomic_outputs(outs) as tmp:  # all outputs or none
        write_csv(tmp["-o"], table)
        if "--ply" in tmp:
            write_ply(tmp["--ply"], np.column_stack([table[k] for k in xyz]))
    n_left, n = len(res.match.left_edges), len(res)
    pct = 100.0 * n / n_left if n_left else 0.0
    lo, hi = res.match.disparity_range
    print(f"{args.left.name}: rectified, disparity {lo:.1f} .. {hi:.1f} px, {n_left} edge "
          f"points, {n} matched ({pct:.1f}%) in {1000 * res.match.timings['total']:.1f} ms"
          f"{' (also in the base frame)' if base_camera is not None else ''} -> {args.output}")
    return 0
