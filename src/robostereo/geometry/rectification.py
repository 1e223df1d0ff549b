"""The interface the project's three rectifications share.

A rectification takes the two grabbed (original) images of a stereo pair and gives
images whose rows are epipolar lines (the thesis, 2.2).  The project has three:

* :class:`robostereo.geometry.scara_rectification.EpipolarGeometry`: the SCARA pair,
  each view turned by its angle ``theta`` about the optical axis (the thesis, 2.2);
* :class:`robostereo.geometry.pose_rectification.GeneralEpipolarGeometry`: two views
  from general 6-DoF poses (OpenCV's ``stereoRectify`` on the relative pose);
* :class:`robostereo.geometry.calibrated_rectification.Rectification`: a calibrated
  two-camera rig.

Each is a :class:`Rectifier`: points go in and out (:meth:`Rectifier.to_rectified`,
:meth:`Rectifier.from_rectified`), an image goes in and its rectified image comes out
(:meth:`Rectifier.rectify`), and :meth:`Rectifier.valid_mask` tells which rectified
pixels hold data.  ``side`` is ``"left"`` or ``"right"`` throughout.

The module also holds what the rectifications share: the interpolators
:data:`INTERPOLATION` and :func:`maps_valid_mask`.
"""

from __future__ import annotations

from typing import Any, Literal, Protocol, runtime_checkable

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "INTERPOLATION",
    "Rectifier",
    "Side",
    "maps_valid_mask",
]

Side = Literal["left", "right"]
"""Which view of a stereo pair: ``"left"`` or ``"right"``."""

INTERPOLATION = {
    "nearest": cv2.INTER_NEAREST,
    "linear": cv2.INTER_LINEAR,
    "cubic": cv2.INTER_CUBIC,
    "lanczos4": cv2.INTER_LANCZOS4,
}
"""OpenCV interpolator of each ``interpolation`` name that the image rectifiers accept."""


@runtime_checkable
class Rectifier(Protocol):
    """What goes into and comes out of a rectification of a stereo pair.

    Examples
    --------
    >>> from robostereo.geometry.camera import Camera
    >>> from robostereo.geometry.poses import Pose
    >>> from robostereo.geometry.scara_rectification import EpipolarGeometry
    >>> g = EpipolarGeometry.from_poses(Camera(), Pose(-10.0, 0.0, 1000.0, 0.1),
    ...                                 Pose(10.0, 0.0, 1000.0, 0.1))
    >>> isinstance(g, Rectifier)
    True
    >>> p = np.array([[100.0, 200.0]])
    >>> bool(np.allclose(g.from_rectified(g.to_rectified(p, "left"), "left"), p))
    True
    """

    def to_rectified(self, points: ArrayLike, side: Side) -> NDArray[np.float64]:
        """Pixels ``(N, 2)`` of the grabbed image of `side` to its rectified image."""
        ...

    def from_rectified(self, points: ArrayLike, side: Side) -> NDArray[np.float64]:
        """Pixels ``(N, 2)`` of the rectified image of `side` back to the grabbed image."""
        ...

    def rectify(self, image: ArrayLike, side: Side) -> NDArray[Any]:
        """The rectified image of `side` from its grabbed image; pixels outside
        :meth:`valid_mask` are filled (NaN or 0, as each rectification documents)."""
        ...

    def valid_mask(self, side: Side) -> NDArray[np.bool_]:
        """Rectified pixels ``(H, W)`` whose source lies inside the grabbed image."""
        ...


def maps_valid_mask(
    map_x: NDArray[np.floating[Any]],
    map_y: NDArray[np.floating[Any]],
    image_size: tuple[int, int],
) -> NDArray[np.bool_]:
    """Where remap tables sample within the outer pixel centres of the source image.

    Parameters
    ----------
    map_x, map_y : ndarray, shape (H, W)
        Source position ``(x, y)`` of each rectified pixel (``cv2.remap`` tables).
    image_size : tuple of int
        ``(width, height)`` of the source image.

    Returns
    -------
    ndarray of bool, shape (H, W)
        ``0 <= x <= W - 1`` and ``0 <= y <= H - 1``.

    Examples
    --------
    >>> mx = np.array([[-0.5, 0.0, 4.0]]); my = np.zeros((1, 3))
    >>> maps_valid_mask(mx, my, (5, 3))
    array([[False,  True,  True]])
    """
    w, h = image_size
    return (map_x >= 0) & (map_x <= w - 1) & (map_y >= 0) & (map_y <= h - 1)
