"""What each ingredient of the window matcher earns, on every developer scene.

Run:  python benchmarks/ablation.py

Each variant ranks every left edge point's best match by a score and is read as the
coverage it reaches at <= 2, 3 and 5 % false (the project's rule, at the same edge
points).  The ranking does not depend on the calibration curve, so no variant is
fitted to the scenes it is scored on; the weights of the full score are the ones that
``benchmarks/fit_confidence.py`` chose leave-one-scene-out.

* ``relaxation``: the seed's matcher (right edge points as candidates), its probability;
* ``rows, uniqueness``: every disparity, the three windows along the row, ranked by
  uniqueness alone;
* ``+ rows above/below``: the five windows;
* ``+ left-right check``: ranked by uniqueness minus a failed left-right check;
* ``+ edge evidence``: the windows' score (right edge point, its similarity w,
  agreement of the windows along the row);
* ``+ paths along rows``: the window costs also aggregated along the rows (two
  scanline paths of semi-global matching), their disparity where they disagree and
  are unique, their evidence in the score;
* ``+ range narrowed``: the full matcher, a range of more than 64 disparities first
  narrowed by the half-size pass (``robostereo.matcher.window_costs.coarse_range``; the earlier
  variants search the scene's whole range).
"""

from __future__ import annotations

import numpy as np

from robostereo.datasets import available_scenes, find_data_dir, load_scene
from robostereo.evaluation import CURVE_LEVELS, coverage_curve
from robostereo.matcher.confidence import DEFAULT_MODEL, FEATURES
from robostereo.matcher.edges import detect_edges
from robostereo.matcher.grey_levels import to_grey
from robostereo.matcher.pipeline import MatchParameters, match_stereo
from robostereo.matcher.window_match import window_match

F = {n: k for k, n in enumerate(FEATURES)}


def variants(scene):
    p = MatchParameters(bit_depth=scene.bit_depth)
    gl = to_grey(scene.left, bit_depth=scene.bit_depth)
    gr = to_grey(scene.right, bit_depth=scene.bit_depth)
    el = detect_edges(scene.left, grey=gl, threshold=p.threshold)
    er = detect_edges(scene.right, grey=gr, threshold=p.threshold * p.right_threshold_ratio)
    rel = match_stereo(scene.left, scene.right, scene.disparity_range,
                       params=MatchParameters(method="relaxation", bit_depth=scene.bit_depth))
    yield "relaxation", el, rel.edge_disparity, rel.edge_confidence
    row = window_match(el, er, gl, gr, scene.disparity_range, vertical=False,
                       path_penalties=None, coarse=False)
    yield "rows, uniqueness", el, row.disparity, row.features[:, F["uniqueness"]]
    five = window_match(el, er, gl, gr, scene.disparity_range, path_penalties=None,
                        coarse=False)
    f = five.features
    yield "+ rows above/below", el, five.disparity, f[:, F["uniqueness"]]
    yield ("+ left-right check", el, five.disparity,
           f[:, F["uniqueness"]] - (1.0 - f[:, F["left_right"]]))
    yield "+ edge evidence", el, five.disparity, DEFAULT_MODEL.score(f)
    paths = window_match(el, er, gl, gr, scene.disparity_range, coarse=False)
    yield "+ paths along rows", el, paths.disparity, DEFAULT_MODEL.score(paths.features)
    full = window_match(el, er, gl, gr, scene.disparity_range)
    yield "+ range narrowed", el, full.disparity, DEFAULT_MODEL.score(full.features)


def main() -> int:
    data = find_data_dir()
    if data is None:
        print("no developer scenes found", flush=True)
        return 2
    table: dict[str, dict[str, list[float]]] = {}
    for name in available_scenes(data):
        scene = load_scene(data / name)
        for label, e, d, score in variants(scene):
            c = coverage_curve(e.row, e.x, d, score, scene.gt_disparity)
            table.setdefault(label, {})[name] = [c.coverage_at(x) for x in CURVE_LEVELS]
    scenes = list(next(iter(table.values())))
    print(f"{'variant':<20} " + " ".join(f"{n:>17}" for n in scenes)
          + f" {'mean @3%':>9} {'worst @3%':>9}")
    for label, row in table.items():
        at3 = [row[n][1] for n in scenes]
        print(f"{label:<20} " + " ".join(
            "/".join(f"{100 * v:.0f}" for v in row[n]).rjust(17) for n in scenes)
            + f" {100 * np.mean(at3):>9.1f} {100 * np.min(at3):>9.1f}")
    print("(each scene: coverage % at <= 2 / 3 / 5 % false)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
