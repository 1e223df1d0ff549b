"""Coverage against false rate on every developer scene: robostereo against StereoSGBM.

Run:  python benchmarks/bench_curves.py [--rule {project,silhouette}] [--write-results PATH]
                                       [SCENE_DIR ...]

Per scene (default: all of ../shared/data/stereo or $ROBOSTEREO_DATA), the table that
``robostereo evaluate`` prints, in one row per method: the default operating point
(% matched, % false, disparity RMS, time) and the coverage reached at <= 2, 3 and 5 %
false, for

* ``window``: robostereo's default matcher, its confidence swept;
* ``relaxation``: the seed's matcher as robostereo ran it before the window method
  (its probability swept), for comparison;
* ``SGBM``: OpenCV's StereoSGBM (blockSize 5, P1 = 8*25, P2 = 32*25, the same range)
  read at the same edge pixels, its uniquenessRatio 0..60 and left-right check off/on
  swept (its default point: uniquenessRatio 10).

Rows are sorted with the scenes where robostereo's lead over SGBM at <= 3 % false is
smallest first.  ``--rule`` picks the scoring rule (the project's, default, or the
silhouette rule of :mod:`robostereo.evaluation.rules`); a second table splits each
method's default point and curve between edge points near a depth step (within 4 px of
a ground-truth jump of more than 2 px) and away, by the same rule.  ``--write-results
PATH`` also writes the first table as the results page's data file
(``docs/results/real_scenes.json``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from results_file import write_results

from robostereo.datasets import available_scenes, find_data_dir, load_scene
from robostereo.evaluation import CURVE_LEVELS, OUTLINE_LEVELS, RULES, evaluate_scene
from robostereo.matcher.pipeline import MatchParameters


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("scenes", nargs="*", type=Path, metavar="SCENE_DIR")
    ap.add_argument("--rule", choices=RULES, default="project",
                    help="scoring rule (default: the project's)")
    ap.add_argument("--write-results", type=Path, metavar="PATH",
                    help="also write the first table as JSON (docs/results/real_scenes.json)")
    args = ap.parse_args(argv)
    if args.scenes:
        dirs = args.scenes
    else:
        data = find_data_dir()
        if data is None:
            ap.error("no scenes: give scene folders or set $ROBOSTEREO_DATA")
        dirs = [data / n for n in available_scenes(data)]
    rows = []
    for d in dirs:
        scene = load_scene(d)
        win = evaluate_scene(scene, rule=args.rule)
        rel = evaluate_scene(scene, sgbm=False, rule=args.rule,
                             params=MatchParameters(method="relaxation",
                                                    bit_depth=scene.bit_depth))
        lead = win.coverage_at("robostereo", 0.03) - win.coverage_at("sgbm", 0.03)
        rows.append((lead, scene.name, win, rel))
    rows.sort(key=lambda r: r[0])
    print(f"rule: {args.rule}")
    levels = "  ".join(f"<={100 * f:g}%" for f in CURVE_LEVELS)
    print(f"{'scene':<11} {'method':<11} {'matched':>8} {'false':>7} {'RMS px':>7} "
          f"{'ms':>7}   coverage at {levels}")
    for _, name, win, rel in rows:
        for label, ev, key, m in (("window", win, "robostereo", win.methods[0]),
                                  ("relaxation", rel, "robostereo", rel.methods[0]),
                                  ("SGBM", win, "sgbm", win.methods[1])):
            cov = "".join(f"{100 * ev.coverage_at(key, f):>8.1f}" for f in CURVE_LEVELS)
            print(f"{name:<11} {label:<11} {m.matched_percent:>7.1f}% {m.false_percent:>6.2f}% "
                  f"{m.rms_px:>7.3f} {1000 * m.seconds:>7.1f}   {'':>11}{cov}")
            name = ""
    lv = "".join(f"{'<=' + format(100 * f, 'g') + '%':>8s}" for f in OUTLINE_LEVELS)
    print(f"\nnear / away from depth steps, rule: {args.rule}")
    print(f"{'scene':<11} {'method':<11} {'near':>5} {'matched':>8} {'false':>7} {'ECE':>6}"
          f"{lv}   {'away':>5} {'matched':>8} {'false':>7} {'ECE':>6}{lv}")
    for _, name, win, rel in rows:
        for label, ev, key in (("window", win, "robostereo"), ("relaxation", rel, "robostereo"),
                               ("SGBM", win, "sgbm")):
            f = ev.outlines.figures(key, args.rule)
            sides = []
            for sc, ece, cov in ((f.near, f.ece_near, f.coverage_near),
                                 (f.away, f.ece_away, f.coverage_away)):
                e = "-" if ece is None else format(ece, ".3f")
                sides.append(f"{sc.counted:>5} {100 * sc.matched_fraction:>7.1f}% "
                             f"{100 * sc.false_fraction:>6.2f}% {e:>6}"
                             + "".join(f"{100 * c:>7.1f}%" for c in cov))
            print(f"{name:<11} {label:<11} {sides[0]}   {sides[1]}")
            name = ""
    if args.write_results:
        write_results(args.write_results, sys.argv[1:] if argv is None else argv,
                      rule=args.rule, levels_percent=[100 * f for f in CURVE_LEVELS],
                      scenes=[{"scene": name, "window": _figures(win, "robostereo", 0),
                               "relaxation": _figures(rel, "robostereo", 0),
                               "sgbm": _figures(win, "sgbm", 1)}
                              for _, name, win, rel in rows])
    return 0


def _figures(ev, key: str, index: int) -> dict[str, object]:
    """One method's default point and curve, as the results page's data file has them."""
    m = ev.methods[index]
    return {"matched_percent": m.matched_percent, "false_percent": m.false_percent,
            "rms_px": m.rms_px, "ms": 1000 * m.seconds,
            "coverage_percent": [100 * ev.coverage_at(key, f) for f in CURVE_LEVELS]}


if __name__ == "__main__":
    raise SystemExit(main())
