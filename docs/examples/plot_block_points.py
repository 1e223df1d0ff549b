"""
The precision block in 3-D, at two heights
==========================================

The thesis's accuracy test (5.2, table 5-1) on the simulated AdeptOne: the block is
seen from two viewpoints 20 mm apart at two heights 79.65 mm apart, and every located
edge point is carried into the robot's world frame.  Left: the points of both heights
in 3-D, coloured by height; right: each block edge point's depth error against its
eq. 9 bound (every point must lie under the line).
"""

import matplotlib.pyplot as plt
import numpy as np

from robostereo.experiments import run_block_experiment
from robostereo.plots import plot_points_3d

experiment = run_block_experiment(seed=0)
fig = plt.figure(figsize=(10, 4.2), layout="constrained")
ax3 = fig.add_subplot(1, 2, 1, projection="3d")
world = np.vstack([h.located.world for h in experiment.heights])
plot_points_3d(ax3, world, size=1.0)
ax3.set_title("located edge points, both heights")

ax = fig.add_subplot(1, 2, 2)
for h in experiment.heights:
    b = h.block_points
    ax.plot(h.located.z_bound[b], np.abs(h.z_error[b]), ".", ms=3,
            label=f"lift {h.lift_mm:g} mm: largest {h.max_abs_z_error:.2f} mm")
lim = [0.0, ax.get_xlim()[1]]
ax.plot(lim, lim, "k-", lw=0.8, label="|error| = bound")
ax.set_xlabel("eq. 9 bound (mm)")
ax.set_ylabel("|z error| (mm)")
ax.legend()
plt.show()
