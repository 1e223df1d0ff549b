"""``robostereo batch``: many pairs or capture folders (two views or N), resumable, local
or on Dask.

Parses, calls the library's batch runner (:func:`~robostereo.batch.run_batch`) and
reports; an input that fails is reported (exit code 2 at the end), any other user error
is an :class:`~robostereo.errors.InputError` (one line, exit code 2).
"""

from __future__ import annotations

import argparse
import sys
from contextlib import nullcontext
from pathlib import Path
from typing import Any

from robostereo.cli._args import disparity_range_args, finite, require_at_least

__all__ = ["add_batch_parser", "run_batch_command"]


def add_batch_parser(sub: Any) -> None:
    p = sub.add_parser(
        "batch", help="match many pairs or capture folders, resumable, local or on Dask",
        description="Run the pipeline over every input folder of INPUT_DIR (pair folders: "
                    "left.*, right.*, optional camera.yaml and disparity.yaml; capture "
                    "folders: capture.yaml, left.png, right.png; N-view capture folders: "
                    "capture.yaml with views:, located as robostereo locate does); write "
                    "OUT_DIR/NAME.csv per input and OUT_DIR/summary.csv.  Finished inputs "
                    "are skipped on a rerun.",
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

    drange = disparity_range_args(args)
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
