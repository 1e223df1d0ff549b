"""Would searching each tile of the image over its own disparities pay?  Measured.

Run:  python benchmarks/bench_pruning.py [--tiles 32x64 32x128 64x128] [--margin 8]
                                         [--repeat 5]

The full window pass (:func:`~robostereo.matcher.window_costs.window_costs`) scores
every pixel of a row that an edge point's windows reach at every disparity of the
range, as a dense matcher does; a coarse-to-fine pass would score each tile of the image
over only the disparities a half-size pass found there.  This measures that idea's
premise on every developer scene at its own range, one thread, without building it:

* ``half ms``: CPU time of the half-size pass
  (:func:`~robostereo.matcher.window_costs.coarse_matches`), ``full ms`` of the full
  window pass over the whole range (median of ``--repeat`` rounds of both, as
  ``bench_match.py`` times them);
* per tile size ``RxC`` (rows x columns), each tile's range: the hull of the half-size
  matches whose windows reach it (within ``2 * HALF_WINDOW`` pixels), widened by
  ``--margin`` each way; a tile without one takes its eight neighbours' hull, else the
  whole range;
* ``kept``: the share of the full pass's (pixel, disparity) entries left, over the tiles
  that hold an edge point;
* ``lost``: the share of the edge points with ground truth whose true disparity (rounded)
  the tile's range leaves out, and ``lost right``: of today's accepted matches within
  1 px of the truth (``match_stereo``'s defaults), the share left out: matches the
  pruning would take away;
* ``bound ms``: ``half + kept x full``, what the pruned pass would take at best (every
  part of the full pass shrinking with the entries, none of the bookkeeping a tile's
  own range costs), against ``full ms``.

Quality here does not depend on the machine; the times do (compare within one run).
"""

from __future__ import annotations

import argparse
import os
import time
from functools import partial

import numpy as np
from bench_match import _time_rounds
from scipy.ndimage import maximum_filter, minimum_filter

from robostereo.datasets import available_scenes, find_data_dir, load_scene
from robostereo.matcher.grey_levels import to_grey
from robostereo.matcher.pipeline import match_stereo
from robostereo.matcher.window_costs import coarse_matches, window_costs
from robostereo.matcher.window_kernels import HALF_WINDOW

_NONE = 1 << 30  # a tile's lower bound before any match (upper: -_NONE)


def tile_ranges(rows: np.ndarray, columns: np.ndarray, disparities: np.ndarray,
                shape: tuple[int, int], tile: tuple[int, int], whole: tuple[int, int],
                margin: int) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper disparity of each tile, ``(H / R, W / C)`` each (rounded up)."""
    (h, w), (tr, tc) = shape, tile
    nr, nc = -(-h // tr), -(-w // tc)
    lo = np.full((nr, nc), _NONE, np.int64)
    hi = np.full((nr, nc), -_NONE, np.int64)
    reach = 2 * HALF_WINDOW  # a side window's far column, a window above's far row
    for dy in (-reach, 0, reach):
        for dx in (-reach, 0, reach):
            at = (np.clip((rows + dy) // tr, 0, nr - 1), np.clip((columns + dx) // tc, 0, nc - 1))
            np.minimum.at(lo, at, disparities)
            np.maximum.at(hi, at, disparities)
    empty = lo > hi
    lo = np.where(empty, minimum_filter(lo, size=3, mode="nearest"), lo)
    hi = np.where(empty, maximum_filter(hi, size=3, mode="nearest"), hi)
    empty = lo > hi
    lo = np.where(empty, whole[0], np.maximum(whole[0], lo - margin))
    hi = np.where(empty, whole[1], np.minimum(whole[1], hi + margin))
    return lo, hi


def main() -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--tiles", nargs="*", default=["32x64", "32x128", "64x128"],
                    help="tile sizes, rows x columns")
    ap.add_argument("--margin", type=int, default=8, help="pixels added each way (8)")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    os.environ["ROBOSTEREO_THREADS"] = "1"
    tiles = [tuple(int(v) for v in t.split("x")) for t in args.tiles]
    data = find_data_dir()
    if data is None:
        print("no developer scenes found", flush=True)
        return 2
    head = f"{'scene':<11} {'range':>7} {'half ms':>7} {'full ms':>7}  " + "  ".join(
        f"{f'{r}x{c}: kept lost lost right bound ms':>38}" for r, c in tiles)
    print(head)
    print("-" * len(head))
    for name in available_scenes(data):
        scene = load_scene(data / name)
        res = match_stereo(scene.left, scene.right, scene.disparity_range)
        e = res.left_edges
        ga, gb = to_grey(scene.left), to_grey(scene.right)
        whole = (int(np.floor(res.disparity_range[0])), int(np.ceil(res.disparity_range[1])))
        # -- the half-size matches and the two passes' times
        r, c, d = coarse_matches(ga, gb, e.row, e.column, whole)
        med = _time_rounds({"half": partial(coarse_matches, ga, gb, e.row, e.column, whole),
                            "full": partial(window_costs, ga, gb, e.row, e.column, whole)},
                           args.repeat, time.thread_time)
        half, full = 1000 * med["half"][0], 1000 * med["full"][0]
        # -- the truth at the edge points, today's right matches
        truth = scene.gt_disparity[e.row, e.column]
        known = np.isfinite(truth) & (truth > 0)
        right = res.accepted & known & (np.abs(res.edge_disparity - truth) <= 1.0)
        cells = []
        for tile in tiles:
            lo, hi = tile_ranges(r, c, d, ga.shape, tile, whole, args.margin)
            at = (e.row // tile[0], e.column // tile[1])
            held = np.zeros(lo.shape, bool)
            held[at] = True
            # tile areas (the last row and column of tiles may be cut)
            area = np.outer(np.diff(np.minimum(np.arange(lo.shape[0] + 1) * tile[0],
                                               ga.shape[0])),
                            np.diff(np.minimum(np.arange(lo.shape[1] + 1) * tile[1],
                                               ga.shape[1])))
            kept = float(((hi - lo + 1) * area)[held].sum()
                         / ((whole[1] - whole[0] + 1) * area[held].sum()))
            t = np.rint(truth)
            inside = (t >= lo[at]) & (t <= hi[at])
            lost = 1.0 - float(inside[known].mean()) if known.any() else float("nan")
            lost_right = 1.0 - float(inside[right].mean()) if right.any() else float("nan")
            cells.append(f"{100 * kept:>9.0f}% {100 * lost:>5.1f}% {100 * lost_right:>9.2f}% "
                         f"{half + kept * full:>9.1f}")
        print(f"{name:<11} {f'{whole[0]}..{whole[1]}':>7} {half:>7.1f} {full:>7.1f}  "
              + "  ".join(f"{cell:>38}" for cell in cells), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
