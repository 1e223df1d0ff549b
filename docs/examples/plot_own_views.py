"""
Your own data: N views
======================

Three real views of DTU MVS scan 24 (Aanæs et al., IJCV 2016) from a camera on a robot
arm, shipped as an N-view capture folder in ``docs/data/dtu_scan24/views``
(``capture.yaml`` with ``views:``).  :func:`robostereo.locate_views` takes every view as
reference, searches each edge point's ray in the other views and writes each point
once, as ``robostereo locate docs/data/dtu_scan24/views -o views.csv`` does.

Checked as the two-view example is, against a view none of them came from: the share
of points that land within 1 px of an edge there.  The same two views read as a
``views:`` pair go through the two-view path and give its points exactly; the three
views' plane sweep finds 2.4 times as many, fewer of them on an edge (89 % against
93 %).  Left: the three views' points in the held-out view; right: points and the
held-out share for the two-view folder, the same pair located as N = 2 views, and the
three views.
"""

from pathlib import Path

import cv2
import matplotlib.pyplot as plt
import numpy as np
import yaml

from robostereo import SE3, load_image, locate_capture, locate_views, read_views_capture

try:
    HERE = Path(__file__).resolve().parent
except NameError:  # sphinx-gallery runs the example in its folder, without __file__
    HERE = Path.cwd()
DATA = HERE.parent / "data" / "dtu_scan24"

views = read_views_capture(DATA / "views")
held = yaml.safe_load((DATA / "heldout" / "view.yaml").read_text())
image, _ = load_image(DATA / "heldout" / held["image"])
pose = SE3.from_quaternion(**held["pose"])
edges = cv2.Canny(cv2.GaussianBlur(image, (5, 5), 1.0), 20, 60)
to_edge = cv2.distanceTransform((edges == 0).astype(np.uint8), cv2.DIST_L2, 5)


def held_out(world):
    """Pixels in the held-out view of the points that fall in it, and which lie on an edge."""
    pixels, depth = views.camera.project(world, pose)
    ij = np.rint(pixels).astype(int)
    inside = (depth > 0) & np.all((ij >= 0) & (ij < image.shape[::-1]), axis=1)
    return pixels[inside], to_edge[ij[inside, 1], ij[inside, 0]] <= 1.0


results = {
    "two-view folder\n(pair/)": locate_capture(DATA / "pair").world,
    "the pair as\nN = 2 views": locate_views(read_views_capture(DATA / "pair")).world,
    "three views\n(views/)": locate_views(views).world,
}
checked = {name: held_out(world) for name, world in results.items()}
for name, world in results.items():
    print(f"{name.replace(chr(10), ' ')}: {len(world)} points, "
          f"{checked[name][1].mean():.1%} on an edge in the held-out view")

fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.9), layout="constrained",
                           width_ratios=(1.3, 1))
pixels, on_edge = checked["three views\n(views/)"]
a.imshow(image, cmap="gray")
a.scatter(*pixels[on_edge].T, s=1, c="tab:green", label="within 1 px of an edge")
a.scatter(*pixels[~on_edge].T, s=2, c="tab:red", label="farther")
a.set_axis_off()
a.legend(loc="lower right", fontsize=8, markerscale=4)
a.set_title("three views' points in the held-out view")
names = list(results)
b.bar(names, [len(results[n]) for n in names], color="0.6")
b.set_ylabel("points located")
share = b.twinx()
share.plot(names, [100 * checked[n][1].mean() for n in names], "o-", color="tab:green")
share.set_ylim(0, 100)
share.set_ylabel("% on an edge in the held-out view", color="tab:green")
b.set_title("two views against N views")
plt.show()
