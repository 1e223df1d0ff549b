"""
Match a rectified pair: edge points, disparity and confidence
=============================================================

A synthetic rectified pair with exact ground truth
(:func:`robostereo.simulation.occluders.occluder_pair`: textured occluders of several
outlines before a slanted plane).  :func:`robostereo.match_stereo` finds the edge points
of the left image along its rows (the thesis, 3.1-3.2), scores every disparity of the
range with side-aware census windows, and gives each edge point its best disparity and
a calibrated confidence; those at ``P(correct) >= 20/21`` are accepted.  Left: the
accepted matches over the left image, coloured by disparity; right: the error of each
against the ground truth, by confidence.
"""

import matplotlib.pyplot as plt
import numpy as np

from robostereo import match_stereo
from robostereo.plots import plot_matches
from robostereo.simulation.occluders import occluder_pair

pair = occluder_pair(seed=0)
res = match_stereo(pair.left, pair.right, (0.0, 32.0))
rows = res.rows
truth = pair.disparity[rows, np.clip(np.rint(res.x_left).astype(int), 0,
                                     pair.disparity.shape[1] - 1)]
print(f"{len(res.left_edges)} left edge points, {len(res)} accepted")

fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.6), layout="constrained")
plot_matches(a, pair.left, res.x_left, rows, res.disparity, size=3)
a.set_title("accepted matches")
b.semilogy(res.confidence, np.abs(res.disparity - truth) + 1e-3, ".", ms=2, color="0.3")
b.set_xlabel("confidence P(correct)")
b.set_ylabel("|disparity error| (px)")
b.set_title("error against the ground truth")
plt.show()
