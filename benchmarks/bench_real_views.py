"""N-view locating on real robot-arm views: CPU time and peak memory against the pair.

Run:  python benchmarks/bench_real_views.py [--data ../shared/data/robot/dtu_scan24]
      [--counts 2,3,5,8] [--scale 0.5] [--repeat 3] [--matcher auto|pairs|sweep]

The eight DTU views of scan 24 in ``--data`` (``cameras_sphere.npz`` and ``image/``),
read by :func:`robostereo.robot.importers.idr.read_idr` and scaled by ``--scale`` (0.5:
800 x 600) with the depth range 500-850 mm, located by
:func:`robostereo.robot.views.locating.locate_views` from the first N of
``0, 1, 2, 3, 4, 5, 6, 7`` for each N of ``--counts``, and the classic pair: views 1 and 2
(neighbours turned 29 degrees about their axes), the two-view path through the same
function.  Each row: the points, the median of ``--repeat`` runs' process CPU time
(after one warm-up run), the ratio against the pair's and against N - 1 (issue 34: at
most N - 1 times the pair's) and the peak resident memory of a fresh process that reads
the views and locates them once (``ru_maxrss``: numba's and OpenCV's allocations too,
and the interpreter's own, about 160 MB with the imports).  All rows come from one
process (the memory runs from its children).  The machine's load moves the times, not
the ratios much; quote medians.
"""

from __future__ import annotations

import argparse
import multiprocessing
import resource
import statistics
import sys
import time
import warnings
from pathlib import Path
from typing import Any

DEFAULT_DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "robot" / "dtu_scan24"
PAIR = (1, 2)


def _capture(data: Path, views: tuple[int, ...], scale: float) -> Any:
    from robostereo.robot.importers.idr import read_idr
    from robostereo.robot.importers.imported_views import views_capture_from_imported

    imported = read_idr(data / "cameras_sphere.npz", data / "image")
    return views_capture_from_imported(imported, select=list(views), scale=scale,
                                       depth_range_mm=(500.0, 850.0))


def _params(matcher: str) -> Any:
    from robostereo.robot.views.views_parameters import ViewsParameters

    return ViewsParameters(matcher=matcher)  # type: ignore[arg-type]


def _peak_child(data: Path, views: tuple[int, ...], scale: float, matcher: str,
                out: Any) -> None:
    """Read and locate once in this (fresh) process; send its peak RSS in MB."""
    from robostereo.robot.views.locating import locate_views

    warnings.simplefilter("ignore")
    locate_views(_capture(data, views, scale), params=_params(matcher))
    out.send(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0)


def _peak_mb(data: Path, views: tuple[int, ...], scale: float, matcher: str) -> float:
    ctx = multiprocessing.get_context("spawn")
    recv, send = ctx.Pipe(duplex=False)
    p = ctx.Process(target=_peak_child, args=(data, views, scale, matcher, send))
    p.start()
    peak = recv.recv()
    p.join()
    return float(peak)


def _cpu(data: Path, views: tuple[int, ...], scale: float, matcher: str,
         repeat: int) -> tuple[int, float]:
    from robostereo.robot.views.locating import locate_views

    cap = _capture(data, views, scale)
    params = _params(matcher)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        located = locate_views(cap, params=params)  # compile and warm the caches
        times = []
        for _ in range(repeat):
            t = time.process_time()
            locate_views(cap, params=params)
            times.append(time.process_time() - t)
    return len(located.world), statistics.median(times)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA)
    ap.add_argument("--counts", default="2,3,5,8", help="comma-separated view counts")
    ap.add_argument("--scale", type=float, default=0.5)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--matcher", default="auto", choices=("auto", "pairs", "sweep"))
    args = ap.parse_args(argv)
    if not (args.data / "cameras_sphere.npz").is_file():
        print(f"no DTU views in {args.data}", file=sys.stderr)
        return 2
    counts = [int(c) for c in args.counts.split(",")]
    pair_points, pair_cpu = _cpu(args.data, PAIR, args.scale, "auto", args.repeat)
    pair_mb = _peak_mb(args.data, PAIR, args.scale, "auto")
    print("views | matcher | points | cpu s | x pair | x pair / (N - 1) | peak MB")
    print("--- | --- | --- | --- | --- | --- | ---")
    print(f"pair {PAIR[0]}-{PAIR[1]} | two-view | {pair_points} | {pair_cpu:.2f} | 1.0 | "
          f"1.0 | {pair_mb:.0f}", flush=True)
    for n in counts:
        views = tuple(range(n))
        points, cpu = _cpu(args.data, views, args.scale, args.matcher, args.repeat)
        mb = _peak_mb(args.data, views, args.scale, args.matcher)
        ratio = cpu / pair_cpu
        print(f"{n} | {args.matcher} | {points} | {cpu:.2f} | {ratio:.1f} | "
              f"{ratio / max(n - 1, 1):.1f} | {mb:.0f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
