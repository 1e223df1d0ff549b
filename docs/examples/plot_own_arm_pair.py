"""
Your own data: a camera on an arm, two views
============================================

Two real views of DTU MVS scan 24 (Aanæs et al., IJCV 2016), a model house seen by a
camera that an industrial robot arm carried to calibrated positions, shipped as a
two-view capture folder in ``docs/data/dtu_scan24/pair`` (``capture.yaml``,
``left.png``, ``right.png``; made by ``docs/data/make_dtu_captures.py``).
:func:`robostereo.locate_capture` rectifies the two views by their poses, matches the
edge points and triangulates them into the world frame, as ``robostereo locate
docs/data/dtu_scan24/pair -o pair.csv`` does.

There is no ground truth, so the points are checked against a view neither image
came from (``docs/data/dtu_scan24/heldout``): projected into it, a right point lands on
an edge.  Left: the located points over the left view, coloured by depth; right: the
same points in the held-out view, green within 1 px of an edge, red farther.
"""

from pathlib import Path

import cv2
import matplotlib.pyplot as plt
import numpy as np
import yaml

from robostereo import SE3, load_image, locate_capture, read_capture
from robostereo.plots import plot_matches

try:
    HERE = Path(__file__).resolve().parent
except NameError:  # sphinx-gallery runs the example in its folder, without __file__
    HERE = Path.cwd()
DATA = HERE.parent / "data" / "dtu_scan24"

capture = read_capture(DATA / "pair")
located = locate_capture(DATA / "pair")
print(f"{len(located.result.left_edges)} edge points, {len(located)} located, median "
      f"bound {np.median(located.z_bound):.2f} mm")

# the held-out view: its image, its pose (T_world_camera) and the same camera
held = yaml.safe_load((DATA / "heldout" / "view.yaml").read_text())
image, _ = load_image(DATA / "heldout" / held["image"])
pose = SE3.from_quaternion(**held["pose"])
pixels, depth = capture.camera.project(located.world, pose)
edges = cv2.Canny(cv2.GaussianBlur(image, (5, 5), 1.0), 20, 60)
to_edge = cv2.distanceTransform((edges == 0).astype(np.uint8), cv2.DIST_L2, 5)
ij = np.rint(pixels).astype(int)
inside = (depth > 0) & np.all((ij >= 0) & (ij < image.shape[::-1]), axis=1)
on_edge = to_edge[ij[inside, 1], ij[inside, 0]] <= 1.0
print(f"held-out view: {on_edge.mean():.1%} of {inside.sum()} points within 1 px of an edge")

fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.9), layout="constrained")
u, v = located.left_pixel.T
plot_matches(a, capture.left, u, v, located.epipolar_xyz[:, 2], label="depth (mm)", size=1.5)
a.set_title("located points, left view")
b.imshow(image, cmap="gray")
p = pixels[inside]
b.scatter(*p[on_edge].T, s=1.5, c="tab:green", label="within 1 px of an edge")
b.scatter(*p[~on_edge].T, s=3, c="tab:red", label="farther")
b.set_axis_off()
b.legend(loc="lower right", fontsize=8, markerscale=4)
b.set_title(f"held-out view: {on_edge.mean():.1%} on an edge")
plt.show()
