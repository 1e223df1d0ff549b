"""Coverage against false rate on every developer scene: robostereo against StereoSGBM.

Run:  python benchmarks/bench_curves.py [SCENE_DIR ...]

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
smallest first.
"""

from __future__ import annotations

import sys
from pathlib import Path

from robostereo.datasets import available_scenes, find_data_dir, load_scene
from robostereo.evaluation import CURVE_LEVELS, evaluate_scene
from robostereo.matcher.pipeline import MatchParameters


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if args:
        dirs = [Path(a) for a in args]
    else:
        data = find_data_dir()
        if data is None:
            print("no scenes: give scene folders or set $ROBOSTEREO_DATA", file=sys.stderr)
            return 2
        dirs = [data / n for n in available_scenes(data)]
    rows = []
    for d in dirs:
        scene = load_scene(d)
        win = evaluate_scene(scene)
        rel = evaluate_scene(scene, sgbm=False,
                             params=MatchParameters(method="relaxation",
                                                    bit_depth=scene.bit_depth))
        lead = win.coverage_at("robostereo", 0.03) - win.coverage_at("sgbm", 0.03)
        rows.append((lead, scene.name, win, rel))
    levels = "  ".join(f"<={100 * f:g}%" for f in CURVE_LEVELS)
    print(f"{'scene':<11} {'method':<11} {'matched':>8} {'false':>7} {'RMS px':>7} "
          f"{'ms':>7}   coverage at {levels}")
    for _, name, win, rel in sorted(rows, key=lambda r: r[0]):
        for label, ev, key, m in (("window", win, "robostereo", win.methods[0]),
                                  ("relaxation", rel, "robostereo", rel.methods[0]),
                                  ("SGBM", win, "sgbm", win.methods[1])):
            cov = "".join(f"{100 * ev.coverage_at(key, f):>8.1f}" for f in CURVE_LEVELS)
            print(f"{name:<11} {label:<11} {m.matched_percent:>7.1f}% {m.false_percent:>6.2f}% "
                  f"{m.rms_px:>7.3f} {1000 * m.seconds:>7.1f}   {'':>11}{cov}")
        name = ""
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
