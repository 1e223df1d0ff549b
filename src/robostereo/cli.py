"""The ``robostereo`` command line: parses, loads, calls the library and writes.

Every user error (bad file, bad parameter, bad image) is reported as one line on
standard error, ``robostereo: error: ...``, with exit code 2 and no partial output.
"""

from __future__ import annotations

import argparse
import math
import sys
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


def _finite(name: str) -> Callable[[str], float]:
    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{name} must be finite, got {text!r}")
        return v

    return parse


def _check_outputs(*paths: Path | None) -> None:
    for p in paths:
        if p is not None and not p.parent.is_dir():
            raise InputError(f"{p}: output folder {p.parent} does not exist")


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
    p.add_argument("--iterations", type=int, default=5, help="relaxation iterations (5)")
    p.add_argument("--seed-mode", action="store_true",
                   help="the seed's matcher: whole-pixel edges, plain w, one threshold")
    p.set_defaults(handler=run_match)


def run_match(args: argparse.Namespace) -> int:
    from robostereo.io import load_image, load_stereo_camera, write_csv, write_ply
    from robostereo.pipeline import MatchParameters, match_stereo

    if args.ply is not None and args.camera is None:
        raise InputError("--ply needs --camera: 3-D points need the camera geometry")
    _check_outputs(args.output, args.ply, args.edges, args.overlay)
    left, bits_l = load_image(args.left)
    right, bits_r = load_image(args.right)
    if bits_l != bits_r:
        raise InputError(f"{args.right}: bit depth {bits_r} differs from the left image's {bits_l}")
    camera = load_stereo_camera(args.camera) if args.camera is not None else None
    base = MatchParameters.seed() if args.seed_mode else MatchParameters()
    params = replace(
        base, threshold=args.threshold, row_step=args.row_step, bit_depth=bits_l,
        relaxation=replace(base.relaxation, iterations=args.iterations),
    )
    status, say = _stage_reporter(sys.stderr.isatty())
    with status:
        result = match_stereo(left, right, (args.min_disparity, args.max_disparity),
                              params=params, camera=camera, progress=say)
    n_left, n_right, n = len(result.left_edges), len(result.right_edges), len(result)
    if n_left == 0:
        print(f"robostereo: warning: no edge points in {args.left} above threshold "
              f"{args.threshold}; the result is empty", file=sys.stderr)
    table = result.table()
    write_csv(args.output, table)
    if args.ply is not None:
        write_ply(args.ply, np.column_stack([table["X"], table["Y"], table["Z"]]))
    if args.edges is not None:
        write_csv(args.edges, result.edge_table())
    if args.overlay is not None:
        from robostereo.plots import save_overlay

        save_overlay(args.overlay, left, table["x_left"], table["row"], table["disparity"],
                     title=f"{n} matched edge points")
    pct = 100.0 * n / n_left if n_left else 0.0
    print(f"{args.left.name}: {n_left} edge points left, {n_right} right, {n} matched "
          f"({pct:.1f}%) in {1000 * result.timings['total']:.1f} ms -> {args.output}")
    return 0


PARSERS: list[Callable[[Any], None]] = [add_match_parser]


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


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (0 ok, 2 bad input)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.handler(args))
    except InputError as e:
        print(f"robostereo: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("robostereo: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
