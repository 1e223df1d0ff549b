"""N-view locating on the simulated robots: errors, coverage, pulley figures and times.

Run:  python benchmarks/bench_views.py [--robot scara|six-axis|both] [--counts 2,3,5,9]
      [--patterns line,cross,arc] [--span 80] [--repeat 3] [--seeds 0] [--cpu-time]

For each robot, pattern and view count it runs
:func:`robostereo.experiments.run_views_demo` (the block at two heights and the
hub-pulley, SCARA or six-axis with its estimated hand-eye) for each seed of the
sensor noise (and, six-axis, of the hand-eye views) and prints one row: the
lift, the largest depth error of the block's top outline (all of it, and its long
edges), whether every point lies within its bound, the median bound, the outline
coverage, the pulley's matched and false shares (of the points reported: those whose
confidence reaches ``ViewsParameters.min_confidence``).  Times: the median over `--repeat`
runs of :func:`~robostereo.robot.views.locating.locate_views` on the block (lift 0) and of
the two-view :func:`~robostereo.robot.capture.locate_pair.locate` on the pair of the two outermost
views of the same capture, in one process, interleaved; wall-clock time, or with
``--cpu-time`` the process's CPU time (steadier on a shared machine).  Rows with the
worst largest error first.  Quality does not depend on the machine; the times do.
"""

from __future__ import annotations

import argparse
import statistics
import time
from typing import Any

from robostereo.errors import InputError
from robostereo.experiments import run_views_demo
from robostereo.robot.capture import locate
from robostereo.robot.simulated.grab_views import simulate_views
from robostereo.robot.views.locating import locate_views


def _times(count: int, pattern: str, span: float, robot: str, repeat: int, seed: int,
           clock: Any = time.perf_counter) -> tuple[float, float]:
    sim = simulate_views("block", count=count, pattern=pattern,  # type: ignore[arg-type]
                         span_mm=span, robot=robot, seed=seed)  # type: ignore[arg-type]
    pair = sim.capture.pair(0, count - 1) if pattern != "cross" else sim.capture.pair(1, 2)
    locate_views(sim.capture)
    locate(pair)
    tv, t2 = [], []
    for _ in range(repeat):
        t = clock()
        locate_views(sim.capture)
        tv.append(clock() - t)
        t = clock()
        locate(pair)
        t2.append(clock() - t)
    return statistics.median(tv), statistics.median(t2)


def main() -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--robot", default="both", choices=("scara", "six-axis", "both"))
    ap.add_argument("--counts", default="2,3,5,9")
    ap.add_argument("--patterns", default="line,cross,arc")
    ap.add_argument("--span", type=float, default=80.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--seeds", default="0", help="comma-separated noise seeds")
    ap.add_argument("--cpu-time", action="store_true",
                    help="time the locates by the process's CPU time, not the wall clock")
    args = ap.parse_args()
    robots = ("scara", "six-axis") if args.robot == "both" else (args.robot,)
    rows: list[dict[str, Any]] = []
    for robot in robots:
        for pattern in args.patterns.split(","):
            for count in (int(c) for c in args.counts.split(",")):
                for seed in (int(s) for s in args.seeds.split(",")):
                    try:
                        r = run_views_demo(count=count, pattern=pattern, span_mm=args.span,
                                           robot=robot, seed=seed)
                    except InputError as e:  # e.g. a cross of two views
                        print(f"{robot} {pattern} {count}: {e}", flush=True)
                        break
                    tv, t2 = _times(count, pattern, args.span, robot, args.repeat, seed,
                                    time.process_time if args.cpu_time else time.perf_counter)
                    r.update(t_views=tv, t_two=t2, seed=seed)
                    rows.append(r)
                    print(f"done {robot} {pattern} {count} seed {seed}", flush=True)
    head = ("robot", "pattern", "N", "seed", "lift", "max|err|", "long", "bound@max", "within",
            "med bound", "outline", "pul.match", "pul.false", "t views",
            "t two", "ratio", "(N-1)")
    print(" | ".join(head))
    for r in sorted(rows, key=lambda r: -r["max_abs_error_mm"]):
        print(" | ".join(str(v) for v in (
            r["robot"], r["pattern"], r["views"], r["seed"], f"{r['lift_mm']:.2f}",
            f"{r['max_abs_error_mm']:.2f}", f"{r['max_abs_error_long_edges_mm']:.2f}",
            f"{r['bound_at_max_error_mm']:.2f}", r["all_within_bound"],
            f"{r['median_bound_mm']:.2f}", f"{100 * r['outline_coverage']:.1f}%",
            f"{100 * r['pulley_matched']:.1f}%", f"{100 * r['pulley_false']:.2f}%",
            f"{r['t_views']:.3f}", f"{r['t_two']:.3f}", f"{r['t_views'] / r['t_two']:.1f}",
            r["views"] - 1)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
