"""``robostereo match``: the edge points of a rectified stereo pair, matched.

Parses, loads, calls the library (:func:`~robostereo.matcher.pipeline.match_stereo`) and
writes; every user error is an :class:`~robostereo.errors.InputError` (one line, exit
code 2, no partial output).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.cli._args import add_matcher_args, finite, matcher_params
from robostereo.cli._console import stage_reporter
from robostereo.errors import InputError

__all__ = ["add_match_parser", "run_match"]


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
