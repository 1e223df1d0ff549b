"""Fit the confidence of the N-view points placed by edge votes, held out by seed.

Run:  python benchmarks/fit_votes_confidence.py [--seeds 0,1,2,3]

Scenes (simulated, with ground truth): the six-axis arm's hub-pulley from 5 views on a
line and in a cross over 80 mm, for every noise seed of `--seeds`, located with the
default :class:`~robostereo.robot.views.views_parameters.ViewsParameters`; every point placed
by edge votes (:func:`~robostereo.robot.views.edge_votes.vote_fits`, a NaN ``window_cost``) is kept
(the module's weights are set so that none falls below the level while this runs) and
is right or wrong by :func:`robostereo.robot.simulated.views_truth.views_correct`.  The feature is
the fit's residual RMS (px); the weights are fitted by iteratively reweighted least
squares on every seed but one and scored on the one left out (points, wrong ones, mean
confidence against the right share, the wrong ones at or above ``min_confidence``,
expected calibration error over ten bins).  The last line prints the weights fitted on
every seed, which :data:`robostereo.robot.views.edge_votes.VOTES_CONFIDENCE_WEIGHTS` holds.
"""

from __future__ import annotations

import argparse

import numpy as np
from fit_views_confidence import _ece, _fit

import robostereo.robot.views.edge_votes as votes
from robostereo.robot.simulated.grab_views import simulate_views
from robostereo.robot.simulated.views_truth import views_correct
from robostereo.robot.views.locating import locate_views
from robostereo.robot.views.views_parameters import ViewsParameters


def main() -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--seeds", default="0,1,2,3")
    args = ap.parse_args()
    seeds = [int(s) for s in args.seeds.split(",")]
    kept = votes.VOTES_CONFIDENCE_WEIGHTS
    votes.VOTES_CONFIDENCE_WEIGHTS = (50.0, 0.0)  # every voted point reported
    xs, ys, ss = [], [], []
    try:
        for seed in seeds:
            for pattern in ("line", "cross"):
                sim = simulate_views("pulley", count=5, pattern=pattern, span_mm=80.0,
                                     robot="six-axis", seed=seed)
                loc = locate_views(sim.capture)
                voted = np.isnan(loc.window_cost)
                right = views_correct(sim, loc)[voted]
                xs.append(loc.residual_px[voted, None])
                ys.append(right.astype(float))
                ss.append(np.full(int(voted.sum()), seed))
                print(f"six-axis {pattern} seed {seed}: {int(voted.sum())} voted points, "
                      f"{int((~right).sum())} wrong", flush=True)
    finally:
        votes.VOTES_CONFIDENCE_WEIGHTS = kept
    x, y, s = np.concatenate(xs), np.concatenate(ys), np.concatenate(ss)
    level = ViewsParameters().min_confidence
    for held in seeds if len(seeds) > 1 else []:
        tr, te = s != held, s == held
        w = _fit(x[tr], y[tr])
        p = 1.0 / (1.0 + np.exp(-(w[0] + x[te] @ w[1:])))
        print(f"held out seed {held}: {int(te.sum())} points, {int((1 - y[te]).sum())} wrong, "
              f"mean confidence {p.mean():.3f} against {y[te].mean():.3f} right, "
              f"{int((1 - y[te][p >= level]).sum())} wrong at >= {level}, "
              f"ECE {_ece(p, y[te]):.4f}")
    w = _fit(x, y)
    print("weights (every seed):", ", ".join(f"{v:.4g}" for v in w))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
