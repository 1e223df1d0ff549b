"""Does the side windows' own evidence tell right from wrong matches near depth steps?

Run:  python benchmarks/bench_side_evidence.py [--occluders M] [--rule {project,silhouette}]

The window pass keeps, when asked (``sides``), what each placement of the window saw
at each left edge point (:class:`robostereo.matcher.window_costs.WindowCosts`:
``placement``, ``second_placement``, ``best_left`` ... ``right_best_placement``; the
matcher does not read them).  At an occluding
contour the window on the occluder's side sees one surface, the other side sees the
surface behind, possibly half-occluded (the right view cannot see it).  This measures,
with robostereo's defaults on every developer scene of ../shared/data/stereo (or
$ROBOSTEREO_DATA) and M synthetic occluder pairs (seeds 1000.., as
``fit_confidence.py``), labels by the silhouette rule unless told:

1. per class of the two side windows' best disparities against the best one (``0``
   within a pixel, ``+`` nearer, ``-`` farther; e.g. ``L0 R+``: the right window sees a
   nearer surface, the point may be half-occluded), near depth steps (within 4 px of a
   ground-truth jump of more than 2 px) and away: points, % right, % accepted, and %
   right among those passing the left-right check;
2. for each candidate piece of evidence added to the shipped score
   (:meth:`robostereo.matcher.confidence.ConfidenceModel.score`) with a weight chosen
   leave-one-scene-out (the grid's weight with the largest mean coverage at <= 2 and
   3 % false near steps over the *other* scenes), the held-out scene's coverage at
   <= 2 % false near steps and away; the first row is today's score.  Coverage here is
   the ranking's (the calibration curve does not change it);
3. what the accepted matches that the rule calls false are, near steps and away: how
   many carry a disparity that the ground truth holds (within 1 px) within 4 px of the
   edge on its row or the rows above and below (a surface beside the edge, not a wrong
   one), and how many have unknown ground truth within 4 px on their row.
"""

from __future__ import annotations

import argparse

import numpy as np

from robostereo.datasets import available_scenes, find_data_dir, load_scene
from robostereo.evaluation import RULES, coverage_curve, depth_step_mask, near_steps, rule_errors
from robostereo.matcher.confidence import DEFAULT_MODEL, FEATURES
from robostereo.matcher.grey_levels import to_grey
from robostereo.matcher.pipeline import MatchParameters, match_stereo
from robostereo.matcher.window_costs import window_costs
from robostereo.matcher.window_kernels import OUT_OF_VIEW
from robostereo.simulation.occluders import occluder_pair

#: weights tried for each candidate (0: today's score)
WEIGHTS = (-0.3, -0.1, -0.05, 0.0, 0.05, 0.1, 0.3)
_F = {name: k for k, name in enumerate(FEATURES)}


def _uniqueness(best: np.ndarray, second: np.ndarray) -> np.ndarray:
    c1, c2 = best.astype(float), second.astype(float)
    u = np.clip((c2 - c1) / np.maximum(c2, 1.0), 0.0, 1.0)
    return np.where((c1 >= OUT_OF_VIEW) | (c2 >= OUT_OF_VIEW), 0.0, u)


def _candidates(s: dict) -> dict[str, np.ndarray]:
    """Candidate evidence per point, from the window pass's side columns."""
    wc, f = s["costs"], s["features"]
    b = wc.best
    left, right = wc.best_left - b, wc.best_right - b
    disagree = np.abs(wc.best_left - wc.best_right) > 1
    nearer = np.abs(b - np.maximum(wc.best_left, wc.best_right)) <= 1
    other = np.where(wc.best_left > wc.best_right, wc.best_right, wc.best_left)
    lr_placement = (wc.right_best_placement >= 0) & (np.abs(wc.right_best_placement - b) <= 1)
    return {
        "sides disagree": disagree.astype(float),
        "best is the nearer side's": (disagree & nearer).astype(float),
        "best is the farther side's": (disagree & ~nearer).astype(float),
        "nearer surface on the right": (right > 1).astype(float),
        "nearer surface on the left": (left > 1).astype(float),
        "second best is the other side's": (disagree & (np.abs(wc.second_best - other) <= 1)
                                            ).astype(float),
        "winning window's own uniqueness": (_uniqueness(wc.cost, wc.second_placement)
                                             - f[:, _F["uniqueness"]]),
        "left-right with the winning window": ((f[:, _F["left_right"]] == 0) & lr_placement
                                               ).astype(float),
    }


def samples(left, right, gt, disparity_range, rule: str, bit_depth=None) -> dict:
    """One pair matched by the defaults, with labels, steps and the window columns (the
    pass again with ``sides``, at the same edge points and over the range it searched)."""
    p = MatchParameters(bit_depth=bit_depth)
    res = match_stereo(left, right, disparity_range, params=p)
    e = res.left_edges
    wc = res.window.costs
    grey = [to_grey(im, bit_depth=bit_depth) for im in (left, right)]
    costs = window_costs(*grey, e.row, e.column,
                         (wc.d_min, wc.d_min + wc.n_disparities - 1),
                         gradient_truncation=p.gradient_truncation, sides=True)
    assert np.array_equal(costs.best, wc.best) and np.array_equal(costs.cost, wc.cost)
    known, err = rule_errors(e.row, e.x, res.edge_disparity, gt, rule=rule)
    return dict(rows=e.row, x=e.x, d=res.edge_disparity, gt=gt, known=known,
                right=np.isfinite(err) & (err <= 1.0), matched=np.isfinite(err),
                accepted=res.accepted, features=res.window.features, costs=costs,
                near=near_steps(e.row, e.x, depth_step_mask(gt)))


def coverage(s: dict, score: np.ndarray, subset: np.ndarray, level: float, rule: str) -> float:
    """% of ``subset``'s counted points matched at <= ``level`` false, ranking by score."""
    conf = np.where(np.isfinite(s["d"]), score, np.nan)
    c = coverage_curve(s["rows"], s["x"], s["d"], conf, s["gt"], rule=rule, subset=subset)
    return 100 * c.coverage_at(level)


def class_table(data: dict[str, dict]) -> None:
    def sign(v: np.ndarray) -> np.ndarray:
        return np.where(v > 1, "+", np.where(v < -1, "-", "0"))

    for group, names in (("real", [k for k in data if not k.startswith("occ")]),
                         ("occluders", [k for k in data if k.startswith("occ")])):
        if not names:
            continue
        for where in ("near", "away"):
            print(f"\n{group}, {where} steps: class   points  % right  % accepted  "
                  f"% right | left-right passes")
            table: dict[str, np.ndarray] = {}
            for name in names:
                s = data[name]
                wc = s["costs"]
                key = np.char.add(np.char.add("L", sign(wc.best_left - wc.best)),
                                  np.char.add(" R", sign(wc.best_right - wc.best)))
                sub = s["known"] & s["matched"] & (s["near"] if where == "near" else ~s["near"])
                lr = s["features"][:, _F["left_right"]] > 0
                for k in np.unique(key[sub]):
                    m = sub & (key == k)
                    table.setdefault(str(k), np.zeros(5))
                    table[str(k)] += [m.sum(), (m & s["right"]).sum(), (m & s["accepted"]).sum(),
                                      (m & lr).sum(), (m & lr & s["right"]).sum()]
            for k, t in sorted(table.items()):
                print(f"  {k:28s} {int(t[0]):6d} {100 * t[1] / t[0]:8.1f} {100 * t[2] / t[0]:10.1f}"
                      f"  {100 * t[4] / max(t[3], 1):7.1f}")


def false_accepted(data: dict[str, dict]) -> None:
    print("\naccepted matches false by the rule: count (% of accepted) | of them, with their "
          "disparity in the ground truth within 4 px (rows +-1) | with unknown ground truth "
          "within 4 px on the row")
    for name, s in data.items():
        if name.startswith("occ"):
            continue
        gt = s["gt"]
        h, w = gt.shape
        line = f"{name:11s}"
        for where, sub in (("near", s["near"]), ("away", ~s["near"])):
            acc = s["known"] & s["accepted"] & sub
            false = np.nonzero(acc & s["matched"] & ~s["right"])[0]
            beside = unknown = 0
            for i in false:
                cols = np.arange(int(np.floor(s["x"][i])) - 3, int(np.floor(s["x"][i])) + 5)
                cols = cols[(cols >= 0) & (cols < w) & (np.abs(cols - s["x"][i]) <= 4)]
                r = int(s["rows"][i])
                g = gt[max(r - 1, 0):min(r + 2, h)][:, cols]
                beside += bool(np.any(np.abs(g[np.isfinite(g)] - s["d"][i]) <= 1.0))
                unknown += bool(np.any(~np.isfinite(gt[r, cols])))
            line += (f"   {where}: {len(false):3d} ({100 * len(false) / max(acc.sum(), 1):4.2f} %)"
                     f" | {beside:3d} | {unknown:3d}")
        print(line)


def held_out(data: dict[str, dict], rule: str) -> None:
    real = [k for k in data if not k.startswith("occ")]
    base = {k: DEFAULT_MODEL.score(s["features"]) for k, s in data.items()}
    cands = {k: _candidates(s) for k, s in data.items()}
    names: list[str] = ["today's score", *next(iter(cands.values()))]
    print(f"\nheld out, coverage at <= 2 % false ({rule} rule), near steps | away; "
          f"weight chosen on the other scenes")
    print(f"{'evidence':36s} " + " ".join(f"{k[:10]:>10s}" for k in real) + " |  "
          + " ".join(f"{k[:6]:>6s}" for k in real))

    def merit(name: str, w: float, keys: list[str]) -> float:
        vals = []
        for k in keys:
            s = data[k]
            sc = base[k] + (w * cands[k][name] if w else 0.0)
            vals += [coverage(s, sc, s["near"], level, rule) for level in (0.02, 0.03)]
        return float(np.mean(vals))

    for name in names:
        near, away, chosen = [], [], []
        for k in real:
            s = data[k]
            if name == "today's score":
                w = 0.0
            else:
                others = [o for o in data if o != k]
                w = max(WEIGHTS, key=lambda v, o=others: merit(name, v, o))
            sc = base[k] + (w * cands[k][name] if name != "today's score" else 0.0)
            near.append(coverage(s, sc, s["near"], 0.02, rule))
            away.append(coverage(s, sc, ~s["near"], 0.02, rule))
            chosen.append(w)
        ws = "" if name == "today's score" else f"  w {min(chosen):+.2f}..{max(chosen):+.2f}"
        print(f"{name:36s} " + " ".join(f"{v:10.1f}" for v in near) + " |  "
              + " ".join(f"{v:6.1f}" for v in away) + ws)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--occluders", type=int, default=8,
                    help="synthetic occluder pairs, seeds 1000.. (8)")
    ap.add_argument("--rule", choices=RULES, default="silhouette")
    args = ap.parse_args(argv)
    data: dict[str, dict] = {}
    found = find_data_dir()
    for name in available_scenes(found) if found else []:
        s = load_scene(found / name)
        data[name] = samples(s.left, s.right, s.gt_disparity, s.disparity_range, args.rule,
                             s.bit_depth)
    for k in range(args.occluders):
        p = occluder_pair(1000 + k)
        data[f"occluders-{k}"] = samples(p.left, p.right, p.disparity, p.disparity_range,
                                         args.rule)
    if not any(not k.startswith("occ") for k in data):
        print("no developer scenes found (set ROBOSTEREO_DATA)")
        return 1
    class_table(data)
    held_out(data, args.rule)
    false_accepted(data)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
