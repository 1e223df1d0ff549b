"""Fit the N-view confidence model (logistic) on simulated scenes, leave one scene out.

Run:  python benchmarks/fit_views_confidence.py

Scenes (simulated, with ground truth): the hub-pulley from 5 views on a line, in a cross,
from the six-axis arm on a line and in a cross (a third of its points seen by two views
only) and from a pair of views (every point a two-view fit); the block from 5 views on a
line and in a cross; a post before a printed plane (an occluder) from 5 views on a line.
Each located point is right or wrong by
:func:`robostereo.robot.views_truth.views_correct`; every point is kept
(``min_confidence=0``) and the capture's whole depth range searched
(``range_step_px=None``: the narrowing itself keeps points by this confidence).
The features are those of :func:`robostereo.robot.multiview.views_confidence` (a two-view
fit's residual is zero whatever its match, so the number of views enters as a feature:
without the two two-view scenes the fit would have almost no two-view point to learn
from); the weights are fitted by
iteratively reweighted least squares (a logistic regression) on all scenes but one and
scored on the one left out: the share of wrong points, the mean confidence, and the
expected calibration error over ten bins.  The last line prints the weights fitted on
every scene, which :data:`robostereo.robot.multiview.CONFIDENCE_WEIGHTS` holds.

Then the least confidence of a reported point (``ViewsParameters.min_confidence``): the
least level, in steps of 0.01, at which the mean over the six scenes of 5 views on a line
or in a cross from the SCARA (every scene but the two two-view ones) of their false share
among the points at or above it is at most 0.5 % (the issue's target; each scene counts
once, however many points it has).  The two-view scenes teach the weights only: put in
that mean, they raise the level to 0.94, which drops points the other scenes need (the
occluder's plane points hidden in some views, fitted from three or four views at
confidences near 0.9: found 29 % instead of 80 %).  Chosen on all scenes but one with
the weights fitted on them, and scored on the one left out: its false share and the
share of its right points kept; then chosen with the weights above (the default).
"""

from __future__ import annotations

import numpy as np

from robostereo.robot.multiview import (
    ViewsParameters,
    confidence_features,
    locate_views,
    views_confidence,
)
from robostereo.robot.simulated_views import post_before_a_printed_plane, simulate_views
from robostereo.robot.views_truth import views_correct


def _fit(x: np.ndarray, y: np.ndarray, iterations: int = 50) -> np.ndarray:
    """Logistic regression by IRLS with a small ridge (the intercept is free)."""
    X = np.column_stack([np.ones(len(x)), x])
    w = np.zeros(X.shape[1])
    ridge = 1e-3 * np.eye(X.shape[1])
    ridge[0, 0] = 0.0
    for _ in range(iterations):
        p = 1.0 / (1.0 + np.exp(-(X @ w)))
        s = np.maximum(p * (1 - p), 1e-9)
        H = X.T @ (X * s[:, None]) + ridge
        g = X.T @ (y - p) - ridge @ w
        step = np.linalg.solve(H, g)
        w += step
        if np.abs(step).max() < 1e-8:
            break
    return w


def _ece(p: np.ndarray, y: np.ndarray, bins: int = 10) -> float:
    edges = np.linspace(0, 1, bins + 1)
    k = np.clip(np.digitize(p, edges) - 1, 0, bins - 1)
    return float(sum(abs(p[k == b].mean() - y[k == b].mean()) * (k == b).mean()
                     for b in range(bins) if (k == b).any()))


def _least_confidence(ps: list[np.ndarray], ys: list[np.ndarray], target: float = 0.005
                      ) -> float:
    """Least level (steps of 0.01) whose mean false share over the scenes is <= target."""
    for t in np.round(np.arange(0.0, 1.0, 0.01), 2):
        false = [1.0 - y[p >= t].mean() if (p >= t).any() else 0.0
                 for p, y in zip(ps, ys, strict=True)]
        if np.mean(false) <= target:
            return float(t)
    return 0.99


def _logistic(w: np.ndarray, x: np.ndarray) -> np.ndarray:
    return 1.0 / (1.0 + np.exp(-(w[0] + x @ w[1:])))


def main() -> int:
    scenes = {
        "pulley line": dict(kind="pulley", pattern="line"),
        "pulley cross": dict(kind="pulley", pattern="cross"),
        "pulley six-axis": dict(kind="pulley", pattern="line", robot="six-axis"),
        # mostly two-view fits: for the weights, not the level
        "pulley six-axis cross": dict(kind="pulley", pattern="cross", robot="six-axis"),
        "pulley pair": dict(kind="pulley", pattern="line", count=2),
        "block line": dict(kind="block", pattern="line"),
        "block cross": dict(kind="block", pattern="cross"),
        "occluder line": dict(kind="block", pattern="line", scene=post_before_a_printed_plane()),
    }
    level_scenes = [n for n in scenes if n not in ("pulley six-axis cross", "pulley pair")]
    data = {}
    for name, kw in scenes.items():
        sim = simulate_views(**{"count": 5, "span_mm": 80.0, **kw})
        # every point the search offers, over the capture's whole depth range
        loc = locate_views(sim.capture, params=ViewsParameters(min_confidence=0.0,
                                                                range_step_px=None))
        data[name] = (confidence_features(loc), views_correct(sim, loc).astype(float))
        print(f"{name}: {len(loc)} points, {100 * (1 - data[name][1].mean()):.2f} % wrong",
              flush=True)
    print("held-out scene | points | wrong % | mean confidence | ECE | ECE (current)")
    for name in scenes:
        xs = np.concatenate([data[n][0] for n in scenes if n != name])
        ys = np.concatenate([data[n][1] for n in scenes if n != name])
        w = _fit(xs, ys)
        x, y = data[name]
        p = _logistic(w, x)
        cur = views_confidence(*x.T)
        print(f"{name} | {len(y)} | {100 * (1 - y.mean()):.2f} | {p.mean():.4f} | "
              f"{_ece(p, y):.4f} | {_ece(cur, y):.4f}")
    w = _fit(np.concatenate([d[0] for d in data.values()]),
             np.concatenate([d[1] for d in data.values()]))
    print("weights (all scenes):", tuple(round(float(v), 3) for v in w))
    print("held-out scene | min_confidence (others) | kept % | false % | right kept %")
    for name in scenes:
        others = [n for n in scenes if n != name]
        wf = _fit(np.concatenate([data[n][0] for n in others]),
                  np.concatenate([data[n][1] for n in others]))
        pool = [n for n in others if n in level_scenes]
        t = _least_confidence([_logistic(wf, data[n][0]) for n in pool],
                              [data[n][1] for n in pool])
        x, y = data[name]
        keep = _logistic(wf, x) >= t
        print(f"{name} | {t:.2f} | {100 * keep.mean():.1f} | "
              f"{100 * (1 - y[keep].mean()) if keep.any() else 0.0:.2f} | "
              f"{100 * keep[y == 1].mean():.1f}")
    t = _least_confidence([_logistic(w, data[n][0]) for n in level_scenes],
                          [data[n][1] for n in level_scenes])
    print(f"min_confidence (all scenes): {t:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
