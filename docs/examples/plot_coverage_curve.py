"""
Coverage against false matches, robostereo and StereoSGBM
=========================================================

How many edge points a matcher gets right depends on how many wrong ones it lets
through.  robostereo ranks its matches by their confidence, so lowering the accepted
confidence traces a curve of coverage (matched share of the edge points with known
ground truth) against the false rate; OpenCV's StereoSGBM, read at the same pixels,
gives one point per setting (:data:`robostereo.evaluation.scorer.SGBM_SWEEP`).  Scored by the
silhouette rule (:mod:`robostereo.evaluation.rules`) on a synthetic pair with occluders,
near depth steps and away from them.
"""

import matplotlib.pyplot as plt

from robostereo import match_stereo
from robostereo.evaluation import sgbm_curve
from robostereo.evaluation.rules import coverage_curve, depth_step_mask
from robostereo.simulation.occluders import occluder_pair

pair = occluder_pair(seed=1)
rng = (0.0, 32.0)
res = match_stereo(pair.left, pair.right, rng)
edges = res.left_edges
near = depth_step_mask(pair.disparity)[edges.row, edges.x.round().astype(int)]

fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained", sharey=True)
for ax, where, subset in ((axes[0], "near depth steps", near), (axes[1], "away", ~near)):
    ours = coverage_curve(edges.row, edges.x, res.edge_disparity, res.edge_confidence,
                          pair.disparity, rule="silhouette", subset=subset)
    theirs = sgbm_curve(pair.left, pair.right, rng, edges.row[subset], edges.x[subset],
                        pair.disparity, rule="silhouette")
    ax.plot(100 * ours.false_rate, 100 * ours.coverage, label="robostereo")
    ax.plot(100 * theirs.false_rate, 100 * theirs.coverage, "o", ms=4, label="SGBM settings")
    ax.set_xlim(0, 10)
    ax.set_xlabel("false matches (%)")
    ax.set_title(f"{where} ({int(subset.sum())} edge points)")
axes[0].set_ylabel("coverage (%)")
axes[0].legend()
plt.show()
