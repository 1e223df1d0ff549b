"""Camera model and camera poses (seed chapter 2, 4.1).

The camera is a pinhole looking straight down from a pose that a SCARA robot can
give it: a position ``(x, y, z)`` in the world frame (millimetres, z up) and a yaw
``phi`` about the vertical axis.  The camera frame has x along the image's rows
(to the right), y down the image (along the columns) and z along the optical axis,
which points down (world ``-Z``), so depth is positive.

With yaw ``phi`` the camera axes, written in the world frame, are::

    x_c = ( cos phi,  sin phi,  0)
    y_c = ( sin phi, -cos phi,  0)
    z_c = ( 0,        0,       -1)

Pixel ``(row i, column j)`` has its centre at image coordinates ``x = j, y = i``;
the principal point defaults to the image centre ``((W - 1) / 2, (H - 1) / 2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_finite, require_positive

__all__ = ["SEED_CAMERA", "Camera", "Pose"]


@dataclass(frozen=True)
class Pose:
    """A camera pose in the world frame: optical centre and yaw about vertical.

    Parameters
    ----------
    x, y, z : float
        Optical centre in the world frame, millimetres (z up).
    phi : float
        Yaw of the camera's x axis from the world X axis, radians,
        counter-clockwise seen from above.
    """

    x: float
    y: float
    z: float
    phi: float = 0.0

    def __post_init__(self) -> None:
        require_finite("pose", [self.x, self.y, self.z, self.phi])

    @property
    def position(self) -> NDArray[np.float64]:
        """Optical centre, shape ``(3,)``, millimetres."""
        return np.array([self.x, self.y, self.z], dtype=float)

    @property
    def rotation(self) -> NDArray[np.float64]:
        """``R`` of shape ``(3, 3)`` whose columns are the camera axes in the world.

        A world point ``P`` has camera coordinates ``R.T @ (P - position)``.
        """
        c, s = math.cos(self.phi), math.sin(self.phi)
        return np.array([[c, s, 0.0], [s, -c, 0.0], [0.0, 0.0, -1.0]])


@dataclass(frozen=True)
class Camera:
    """A pinhole camera with square-grid pixels of known pitch.

    Parameters
    ----------
    focal_length_mm : float
        Lens-to-image-plane distance ``s`` (seed 3.6), millimetres.
    pixel_pitch_mm : tuple of float
        Pixel pitch ``(horizontal, vertical)`` in millimetres.  The seed gives
        17.2 um horizontally; 13.7 um vertically fits a 2/3-inch sensor of
        481 lines (6.6 mm high), see ``docs``.
    image_size : tuple of int
        ``(width, height)`` in pixels; the seed's PULNiX CCD has 509 x 481.
    principal_point : tuple of float, optional
        ``(cx, cy)`` in pixels; default the image centre.
    grey_levels : int
        Number of grey levels the camera delivers (128 for the seed's 7-bit system).

    Examples
    --------
    >>> cam = Camera()
    >>> round(cam.fx, 2), cam.principal_point
    (1453.49, (254.0, 240.0))
    >>> pose = Pose(0.0, 0.0, 1000.0)
    >>> cam.project([[0.0, 0.0, 0.0]], pose)[0]
    array([[254., 240.]])
    """

    focal_length_mm: float = 25.0
    pixel_pitch_mm: tuple[float, float] = (0.0172, 0.0137)
    image_size: tuple[int, int] = (509, 481)
    principal_point: tuple[float, float] = field(default=(math.nan, math.nan))
    grey_levels: int = 128

    def __post_init__(self) -> None:
        require_positive("focal_length_mm", self.focal_length_mm)
        if len(self.pixel_pitch_mm) != 2:
            raise InputError(
                f"pixel_pitch_mm must be (horizontal, vertical), got {self.pixel_pitch_mm}"
            )
        for p in self.pixel_pitch_mm:
            require_positive("pixel_pitch_mm", p)
        w, h = self.image_size
        if int(w) != w or int(h) != h or w < 5 or h < 5:
            raise InputError(
                "image_size must be (width, height) of at least 5 pixels, "
                f"got {self.image_size}"
            )
        object.__setattr__(self, "pixel_pitch_mm", tuple(float(p) for p in self.pixel_pitch_mm))
        object.__setattr__(self, "image_size", (int(w), int(h)))
        cx, cy = self.principal_point
        if math.isnan(cx) and math.isnan(cy):
            object.__setattr__(self, "principal_point", ((w - 1) / 2.0, (h - 1) / 2.0))
        else:
            require_finite("principal_point", [cx, cy])
            object.__setattr__(self, "principal_point", (float(cx), float(cy)))

    @property
    def fx(self) -> float:
        """Focal length in horizontal pixels, ``s / pitch_x``."""
        return self.focal_length_mm / self.pixel_pitch_mm[0]

    @property
    def fy(self) -> float:
        """Focal length in vertical pixels, ``s / pitch_y``."""
        return self.focal_length_mm / self.pixel_pitch_mm[1]

    @property
    def width(self) -> int:
        return self.image_size[0]

    @property
    def height(self) -> int:
        return self.image_size[1]

    @property
    def K(self) -> NDArray[np.float64]:
        """Intrinsic matrix, shape ``(3, 3)``."""
        cx, cy = self.principal_point
        return np.array([[self.fx, 0.0, cx], [0.0, self.fy, cy], [0.0, 0.0, 1.0]])

    def project(
        self, points: ArrayLike, pose: Pose
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Project world points into the image.

        Parameters
        ----------
        points : array_like, shape (N, 3)
            World points, millimetres.
        pose : Pose
            Camera pose.

        Returns
        -------
        pixels : ndarray, shape (N, 2)
            Image coordinates ``(x, y)``.
        depth : ndarray, shape (N,)
            Depth along the optical axis, millimetres (positive in front).
        """
        p = np.atleast_2d(np.asarray(points, dtype=float))
        pc = (p - pose.position) @ pose.rotation
        z = pc[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            x = self.fx * pc[:, 0] / z + self.principal_point[0]
            y = self.fy * pc[:, 1] / z + self.principal_point[1]
        return np.column_stack([x, y]), z

    def backproject(
        self, pixels: ArrayLike, depth: ArrayLike, pose: Pose
    ) -> NDArray[np.float64]:
        """World points at the given depths behind image points.

        Parameters
        ----------
        pixels : array_like, shape (N, 2)
            Image coordinates ``(x, y)``.
        depth : array_like, shape (N,)
            Depth along the optical axis, millimetres.
        pose : Pose

        Returns
        -------
        ndarray, shape (N, 3)
            World points, millimetres.

        Examples
        --------
        >>> cam, pose = Camera(), Pose(10.0, -5.0, 900.0, 0.3)
        >>> P = np.array([[12.0, 40.0, 0.0], [-30.0, 2.0, 50.0]])
        >>> uv, z = cam.project(P, pose)
        >>> bool(np.allclose(cam.backproject(uv, z, pose), P))
        True
        """
        uv = np.atleast_2d(np.asarray(pixels, dtype=float))
        z = np.asarray(depth, dtype=float)
        cx, cy = self.principal_point
        pc = np.column_stack([(uv[:, 0] - cx) / self.fx * z, (uv[:, 1] - cy) / self.fy * z, z])
        return pc @ pose.rotation.T + pose.position


SEED_CAMERA = Camera()
"""The seed's camera: 509 x 481 pixels, 25 mm lens, 17.2 x 13.7 um pixels, 7-bit grey."""
