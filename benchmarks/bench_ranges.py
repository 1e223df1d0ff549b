"""A generous disparity range against each scene's own: searched, time and quality.

Run:  python benchmarks/bench_ranges.py [--repeat N] [--high D]

Every developer scene of ../shared/data/stereo (or $ROBOSTEREO_DATA) is matched at its
own range and at ``0..D`` (default 256), each with the half-size narrowing of the range
(``MatchParameters.coarse``, the default) and without it.  Per run it prints the range
the full pass searched, the median time of ``match_stereo``, the default operating
point (matched / false, the project's rule) and the coverage at <= 2, 3 and 5 % false
of the confidence curve.  Quality here does not depend on the machine; the times do
(quote medians, compare within one run).
"""

from __future__ import annotations

import argparse
import statistics
import time

from robostereo.datasets import available_scenes, find_data_dir, load_scene
from robostereo.evaluation import CURVE_LEVELS, coverage_curve, score_matches
from robostereo.matcher.pipeline import MatchParameters, match_stereo


def main() -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="timed runs per setting (5)")
    ap.add_argument("--high", type=float, default=256.0, help="top of the generous range")
    args = ap.parse_args()
    data = find_data_dir()
    if data is None:
        print("no developer scenes found", flush=True)
        return 2
    print(f"{'scene':<11} {'range':>9} {'narrowing':>9} {'searched':>9} {'ms':>7} "
          f"{'matched/false %':>15} {'@2/3/5 % false':>16}")
    for name in available_scenes(data):
        scene = load_scene(data / name)
        for rng in (scene.disparity_range, (0.0, args.high)):
            for coarse in (True, False):
                p = MatchParameters(coarse=coarse, bit_depth=scene.bit_depth)
                res = match_stereo(scene.left, scene.right, rng, params=p)
                times = []
                for _ in range(args.repeat):
                    t = time.perf_counter()
                    match_stereo(scene.left, scene.right, rng, params=p)
                    times.append(time.perf_counter() - t)
                e, wc = res.left_edges, res.window.costs
                sc = score_matches(e.row, e.x, res.accepted_disparity(), scene.gt_disparity)
                c = coverage_curve(e.row, e.x, res.edge_disparity, res.edge_confidence,
                                   scene.gt_disparity)
                searched = f"{wc.d_min}..{wc.d_min + wc.n_disparities - 1}"
                point = f"{100 * sc.matched_fraction:.1f}/{100 * sc.false_fraction:.2f}"
                curve = "/".join(f"{100 * c.coverage_at(x):.1f}" for x in CURVE_LEVELS)
                print(f"{name:<11} {f'{rng[0]:.0f}..{rng[1]:.0f}':>9} "
                      f"{'on' if coarse else 'off':>9} {searched:>9} "
                      f"{1000 * statistics.median(times):>7.1f} {point:>15} {curve:>16}",
                      flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
