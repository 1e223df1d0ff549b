"""
Your own data: a calibrated rig
===============================

A real pair from a calibrated stereo rig, shipped in ``docs/data/motorcycle``:
Middlebury 2014's *Motorcycle* (Scharstein et al., GCPR 2014), at a quarter size as
scikit-image ships it, with its ``calib.txt``.  :func:`robostereo.load_rig_pair` reads
the images and the calibration, :func:`robostereo.match_rig` rectifies (this rig is
already rectified, so its images are used as they are), matches the edge points and
triangulates them into the left camera's frame.  The same as
``robostereo rig docs/data/motorcycle/im0.png docs/data/motorcycle/im1.png
--calibration docs/data/motorcycle/calib.txt --min-depth 2000 --max-depth 6000 -o
rig.csv``.  Left: the matched edge points over the left image, coloured by depth; right:
the points seen from above.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from robostereo import load_rig_pair, match_rig
from robostereo.plots import plot_matches

try:
    HERE = Path(__file__).resolve().parent
except NameError:  # sphinx-gallery runs the example in its folder, without __file__
    HERE = Path.cwd()
DATA = HERE.parent / "data" / "motorcycle"

left, right, calibration, bits = load_rig_pair(DATA / "im0.png", DATA / "im1.png",
                                               DATA / "calib.txt")
res = match_rig(left, right, calibration, depth_range_mm=(2000.0, 6000.0))
xyz, bound = res.points_3d()  # (K, 3) mm in the left camera's frame, (K,) eq. 9 bound
x, y = res.points_original.T
print(f"{len(res.match.left_edges)} edge points, {len(res)} matched; depth "
      f"{np.percentile(xyz[:, 2], 1):.0f} .. {np.percentile(xyz[:, 2], 99):.0f} mm (1st-99th "
      f"percentile), median bound {np.median(bound):.1f} mm")

fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained",
                           width_ratios=(1.4, 1))
plot_matches(a, left, x, y, xyz[:, 2], label="depth Z (mm)", size=1.5, vmax=5000)
a.set_title("matched edge points, left image")
b.scatter(xyz[:, 0], xyz[:, 2], s=0.5, c="0.2")
b.set_xlabel("X (mm, left camera)")
b.set_ylabel("depth Z (mm)")
b.set_title("seen from above")
plt.show()
