"""robostereo: sparse 3-D edges from stereo pairs, after Kim (1989).

A camera carried by a SCARA robot to two viewpoints (or any rectified or calibrated
stereo pair) gives two images; edge points found along epipolar lines are matched
with similarity indices and a connectivity relaxation rule, then triangulated into
3-D points with a per-point depth error bound.

Conventions used throughout
---------------------------
* images are ``(H, W)`` arrays; pixel ``(row i, column j)`` has its centre at
  ``x = j, y = i``;
* 2-D points are ``(N, 2)`` arrays of ``(x, y)``;
* disparity is ``d = x_left - x_right`` (pixels, positive for points in front);
* world and camera-frame coordinates are millimetres; camera frames have x to the
  image's right, y down the image, z along the optical axis (depth positive).
"""

from robostereo.errors import InputError, UnreachablePoseError

__version__ = "0.1.0"

__all__ = ["InputError", "UnreachablePoseError", "__version__"]
