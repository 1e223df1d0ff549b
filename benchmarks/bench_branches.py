"""Where the confidence rates its matches: the score's three branches, near steps and away.

Run:  python benchmarks/bench_branches.py [--one-curve] [--rule {project,silhouette}]

The confidence score (:class:`robostereo.matcher.confidence.ConfidenceModel`) has three
branches: the paths along the row agree with the windows' disparity; they disagree and
their disparity was taken (``path_swapped``); they disagree and the windows' was kept.
For every developer scene (../shared/data/stereo or $ROBOSTEREO_DATA) at the CLI
defaults, and for each branch near depth steps (within 4 px of a ground-truth jump of
more than 2 px) and away, this prints the matches' count, the share right (by
``--rule``, default the silhouette rule, the confidence's labels), their mean
confidence, the share accepted (``P >= 20/21``), how many of the accepted are wrong,
and the right matches refused as a share of all the counted points of that zone.  A
mean confidence below the share right is a branch the confidence underrates on that
scene.  ``--one-curve`` rates every match on the shipped model's main curve, as before
the swapped matches had their own.
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from robostereo.datasets import available_scenes, find_data_dir, load_scene
from robostereo.evaluation import RULES, depth_step_mask, near_steps, rule_errors
from robostereo.matcher.confidence import DEFAULT_MODEL, FEATURES, swapped_matches
from robostereo.matcher.pipeline import MatchParameters, match_stereo

BRANCHES = ("paths agree", "paths taken", "windows kept")


def branch_of(features: np.ndarray) -> np.ndarray:
    """0, 1 or 2 per row of ``features`` ``(N, F)``: the score's branch (:data:`BRANCHES`)."""
    agree = features[:, FEATURES.index("path_agree")] > 0
    return np.where(agree, 0, np.where(swapped_matches(features), 1, 2))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--one-curve", action="store_true",
                    help="rate every match on the main curve (no curve for swapped matches)")
    ap.add_argument("--rule", choices=RULES, default="silhouette")
    args = ap.parse_args(argv)
    model = (dataclasses.replace(DEFAULT_MODEL, swap_knots_score=(),
                                 swap_knots_probability=())
             if args.one_curve else DEFAULT_MODEL)
    acceptance = MatchParameters().acceptance
    data = find_data_dir()
    print(f"rule: {args.rule}; {'one curve' if args.one_curve else 'the shipped model'}; "
          "per branch: points, % right, mean P, % accepted, accepted wrong, right refused "
          "(% of the zone)")
    print(f"{'scene':11s} {'zone':5s} " + " ".join(f"{b:>38s}" for b in BRANCHES))
    for name in available_scenes(data) if data else []:
        s = load_scene(data / name)
        res = match_stereo(s.left, s.right, s.disparity_range,
                           params=MatchParameters(bit_depth=s.bit_depth))
        e = res.left_edges
        known, err = rule_errors(e.row, e.x, res.edge_disparity, s.gt_disparity,
                                 rule=args.rule)
        take = known & np.isfinite(err)
        f = res.window.features
        conf = np.full(len(e), np.nan)
        conf[take] = model(f[take])
        right = take & (np.nan_to_num(err, nan=np.inf) <= 1.0)
        branch = branch_of(f)
        near = near_steps(e.row, e.x, depth_step_mask(s.gt_disparity))
        for zone, zm in (("near", near), ("away", ~near)):
            cells = []
            for b in range(len(BRANCHES)):
                m = take & zm & (branch == b)
                if not m.any():
                    cells.append(f"{'-':>38s}")
                    continue
                acc = m & (conf >= acceptance)
                refused = int((m & right & ~acc).sum())
                cells.append(f"{int(m.sum()):5d} {100 * right[m].mean():5.1f} "
                             f"{conf[m].mean():5.3f} {100 * acc[m].mean():5.1f} "
                             f"{int((acc & ~right).sum()):3d} "
                             f"{100 * refused / max(int((known & zm).sum()), 1):5.1f}")
            print(f"{name:11s} {zone:5s} " + " ".join(f"{c:>38s}" for c in cells))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
