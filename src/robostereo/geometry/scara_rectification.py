"""Rectification of the SCARA pair: each view turned by its angle theta (the thesis, 2.2).

The thesis's SCARA keeps the camera looking straight down, so the two views of a pair
differ from the epipolar frame by a turn about the optical axis only.  This module holds

* the epipolar frame of two viewpoints, :class:`EpipolarGeometry` (the thesis, 2.2), a
  :class:`~robostereo.geometry.rectification.Rectifier`;
* the pixel map of the turn, :func:`rectification_matrix`, and the exact point maps
  between an image and its rectified version (:func:`image_to_epipolar`,
  :func:`epipolar_to_image`);
* rectification of each image by its angle ``theta`` (:func:`rectify_image`) and the
  pixels that hold data (:func:`rectified_valid_mask`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_finite
from robostereo.geometry.camera import Camera, wrap_angle
from robostereo.geometry.poses import SE3, Pose, scara_from_se3
from robostereo.geometry.rectification import INTERPOLATION, Side

__all__ = [
    "EpipolarGeometry",
    "epipolar_to_image",
    "image_to_epipolar",
    "rectification_matrix",
    "rectified_valid_mask",
    "rectify_image",
]


def rectification_matrix(camera: Camera, theta: float) -> NDArray[np.float64]:
    """Pixel map ``A = K M(theta) K^-1`` from an image to its rectified image.

    Parameters
    ----------
    camera : Camera
    theta : float
        ``phi - alpha``, radians: the camera's yaw relative to the baseline direction.

    Returns
    -------
    ndarray, shape (3, 3)
        Affine matrix (last row ``[0, 0, 1]``) taking homogeneous pixel coordinates of the
        real camera (yaw ``phi``) to those of the virtual camera with the same optical
        centre and intrinsics and yaw ``alpha``.

    Notes
    -----
    With camera axes ``x_c = (cos phi, sin phi, 0)``, ``y_c = (sin phi, -cos phi, 0)``,
    ``z_c = (0, 0, -1)`` the rotation from the real to the virtual camera frame is
    ``R_alpha^T R_phi = [[cos t, sin t, 0], [-sin t, cos t, 0], [0, 0, 1]]`` with
    ``t = theta``: a rotation about the optical axis, so depth is unchanged and the
    normalised image coordinates rotate by ``M(theta)``.  Pixels are not square
    (``fx != fy``), so in pixels the map is the affine ``K M K^-1``, not a rotation.

    References
    ----------
    The thesis, 2.2: the normal (pixel) frame and the epipolar frame differ by a rotation about
    the z axis by ``theta_l = phi_l - alpha`` (``theta_r``).

    Examples
    --------
    A quarter turn is not a rotation of the pixel grid (17.2 x 13.7 um pixels):

    >>> A = rectification_matrix(Camera(), math.pi / 2)
    >>> np.round(A[:2, :2], 4) + 0.0
    array([[ 0.    ,  0.7965],
           [-1.2555,  0.    ]])
    """
    c, s = math.cos(theta), math.sin(theta)
    rot = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    K = camera.K
    cx, cy = camera.principal_point
    K_inv = np.array(
        [[1.0 / camera.fx, 0.0, -cx / camera.fx], [0.0, 1.0 / camera.fy, -cy / camera.fy],
         [0.0, 0.0, 1.0]]
    )
    return K @ rot @ K_inv


def _points2(points: ArrayLike, name: str = "points") -> NDArray[np.float64]:
    p = np.asarray(points, dtype=float)
    if p.ndim == 1 and p.shape[0] == 2:
        p = p[None, :]
    if p.ndim != 2 or p.shape[1] != 2:
        raise InputError(f"{name} must have shape (N, 2), got {p.shape}")
    return p


def image_to_epipolar(points: ArrayLike, camera: Camera, theta: float) -> NDArray[np.float64]:
    """Map image points of a camera with yaw ``phi`` to its rectified (epipolar) image.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Pixel coordinates ``(x, y)`` in the image taken with yaw ``phi``.
    camera : Camera
    theta : float
        ``phi - alpha``, radians (:attr:`EpipolarGeometry.theta_l` or ``theta_r``).

    Returns
    -------
    ndarray, shape (N, 2)
        Pixel coordinates in the rectified image: exactly where the virtual camera at the
        same optical centre with yaw ``alpha`` sees the same world point.  The rectified
        rows are epipolar lines.

    Notes
    -----
    1. normalise ``n = K^-1 p``; 2. rotate ``n' = M(theta) n`` with
    ``M = [[cos, sin], [-sin, cos]]``; 3. ``p' = K n'``.  See
    :func:`rectification_matrix`.

    References
    ----------
    The thesis, 2.2 (theta_l = phi_l - alpha, theta_r = phi_r - alpha).

    Examples
    --------
    >>> cam = Camera()
    >>> p = np.array([[300.0, 100.0]])
    >>> q = image_to_epipolar(p, cam, 0.4)
    >>> bool(np.allclose(epipolar_to_image(q, cam, 0.4), p))
    True
    """
    p = _points2(points)
    A = rectification_matrix(camera, theta)
    return p @ A[:2, :2].T + A[:2, 2]


def epipolar_to_image(points: ArrayLike, camera: Camera, theta: float) -> NDArray[np.float64]:
    """Inverse of :func:`image_to_epipolar`: rectified pixels to pixels of the real image.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Pixel coordinates in the rectified image.
    camera : Camera
    theta : float
        ``phi - alpha``, radians.

    Returns
    -------
    ndarray, shape (N, 2)
        Pixel coordinates in the image taken with yaw ``phi``.
    """
    return image_to_epipolar(points, camera, -theta)


def _source_coordinates(
    camera: Camera, theta: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    A = rectification_matrix(camera, -theta)  # rectified pixel -> real pixel
    w, h = camera.image_size
    xs, ys = np.meshgrid(np.arange(w, dtype=float), np.arange(h, dtype=float))
    return A[0, 0] * xs + A[0, 1] * ys + A[0, 2], A[1, 0] * xs + A[1, 1] * ys + A[1, 2]


def rectified_valid_mask(camera: Camera, theta: float) -> NDArray[np.bool_]:
    """Pixels of the rectified image whose source lies inside the real image.

    Returns
    -------
    ndarray of bool, shape (H, W)
        True where the source position lies within the outer pixel centres of the
        real image, ``0 <= x <= W - 1`` and ``0 <= y <= H - 1``.

    Examples
    --------
    >>> bool(rectified_valid_mask(Camera(), 0.0).all())
    True
    """
    sx, sy = _source_coordinates(camera, theta)
    w, h = camera.image_size
    eps = 1e-9
    return (sx >= -eps) & (sx <= w - 1 + eps) & (sy >= -eps) & (sy <= h - 1 + eps)


def rectify_image(
    image: ArrayLike,
    camera: Camera,
    theta: float,
    *,
    interpolation: Literal["nearest", "linear", "cubic", "lanczos4"] = "cubic",
    fill_value: float = math.nan,
) -> NDArray[np.float64]:
    """The image that a virtual camera with yaw ``alpha`` at the same place would see.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Grey image taken with yaw ``phi`` (any real dtype; ``(H, W)`` must match
        ``camera.image_size``).
    camera : Camera
    theta : float
        ``phi - alpha``, radians.
    interpolation : {'cubic', 'linear', 'nearest', 'lanczos4'}
        OpenCV interpolator.  Cubic (default) or linear for measurement.
    fill_value : float
        Value of rectified pixels whose source position falls outside the real image
        (beyond its outer pixel centres); NaN by default, so that these pixels cannot
        pass for image content.

    Returns
    -------
    ndarray of float64, shape (H, W)
        Rectified image, same size and intrinsics as the input; its rows are epipolar
        lines.  No clipping: cubic interpolation may overshoot the input's range slightly.

    Notes
    -----
    1. ``A^-1 = K M(-theta) K^-1`` maps each rectified pixel to its source position
       (:func:`epipolar_to_image`).
    2. ``cv2.warpAffine(..., WARP_INVERSE_MAP)`` samples the image there in float64;
       where the interpolation support reaches past the image border the edge pixels are
       replicated (``BORDER_REPLICATE``).
    3. Pixels whose source position is outside the image are set to `fill_value`
       (:func:`rectified_valid_mask`).

    OpenCV quantises the sampling positions to 1/32 pixel, so the warped content can be
    off the exact point map by up to about 0.016 pixel; use :func:`image_to_epipolar`
    on measured points when that matters.

    References
    ----------
    The thesis, 2.2, 4.2.1: each image is rotated by its theta so that its epipolar lines are
    the rows (the thesis draws rulers along the epipolar lines instead).

    Examples
    --------
    >>> cam = Camera(image_size=(9, 7))
    >>> img = np.arange(63, dtype=float).reshape(7, 9)
    >>> bool(np.allclose(rectify_image(img, cam, 0.0), img))
    True
    """
    img = np.asarray(image)
    w, h = camera.image_size
    if img.ndim != 2 or img.shape != (h, w):
        raise InputError(f"image must have shape (H, W) = ({h}, {w}), got {img.shape}")
    if interpolation not in INTERPOLATION:
        raise InputError(
            f"interpolation must be one of {sorted(INTERPOLATION)}, got {interpolation!r}"
        )
    require_finite("theta", float(theta))
    src = img.astype(np.float64, copy=False)
    A_inv = rectification_matrix(camera, -theta)[:2, :]
    out = cv2.warpAffine(
        src,
        A_inv,
        (w, h),
        flags=INTERPOLATION[interpolation] | cv2.WARP_INVERSE_MAP,
        borderMode=cv2.BORDER_REPLICATE,
    )
    out[~rectified_valid_mask(camera, theta)] = fill_value
    return out


@dataclass(frozen=True)
class EpipolarGeometry:
    """The epipolar frame of two viewpoints of one camera (the thesis, 2.2, figure 4-2).

    Build it with :meth:`from_poses`.  The frame has its origin at the midpoint of the two
    optical centres, X along the baseline ``(cos alpha, sin alpha, 0)`` (from the left
    to the right viewpoint), Z along the optical axis (world ``-Z``, down) and
    ``Y = Z x X``: the axes of a virtual camera with yaw ``alpha``.

    Attributes
    ----------
    camera : Camera
    pose_left, pose_right : Pose
        The two viewpoints; "left" is the one at ``-D/2`` along X.
    alpha : float
        ``atan2(y_r - y_l, x_r - x_l)``, radians, in ``(-pi, pi]``.
    theta_l, theta_r : float
        ``phi_l - alpha``, ``phi_r - alpha``, radians, wrapped into ``(-pi, pi]``.
    baseline_mm : float
        ``D``, distance between the optical centres projected on the horizontal plane.
    origin : tuple of float
        Midpoint of the two optical centres, world millimetres.

    Examples
    --------
    >>> g = EpipolarGeometry.from_poses(Camera(), Pose(-10.0, 0.0, 1000.0, 0.1),
    ...                                 Pose(10.0, 0.0, 1000.0, 0.12))
    >>> round(g.alpha, 12), round(g.theta_l, 12), round(g.theta_r, 12), g.baseline_mm
    (0.0, 0.1, 0.12, 20.0)
    >>> g.to_world([[0.0, 0.0, 1000.0]])
    array([[0., 0., 0.]])
    """

    camera: Camera
    pose_left: Pose
    pose_right: Pose
    alpha: float
    theta_l: float
    theta_r: float
    baseline_mm: float
    origin: tuple[float, float, float]

    @classmethod
    def from_poses(cls, camera: Camera, pose_left: SE3, pose_right: SE3) -> EpipolarGeometry:
        """Epipolar frame of the viewpoints `pose_left` and `pose_right`.

        The poses are SCARA poses (:class:`~robostereo.geometry.poses.Pose`), or camera
        poses looking straight down that :func:`~robostereo.geometry.poses.scara_from_se3`
        turns into them.

        Raises
        ------
        InputError
            If the optical centres coincide in the horizontal plane (``D = 0``), or a
            pose does not look straight down.

        Notes
        -----
        ``alpha = atan2(y_r - y_l, x_r - x_l)``, ``theta_l = phi_l - alpha``,
        ``theta_r = phi_r - alpha``, ``D = hypot(x_r - x_l, y_r - y_l)``.

        References
        ----------
        The thesis, 2.2 (alpha, theta_l, theta_r), 4.1 and figure 4-2 (viewpoints at ``+-D/2``).
        """
        pose_left, pose_right = scara_from_se3(pose_left), scara_from_se3(pose_right)
        dx = pose_right.x - pose_left.x
        dy = pose_right.y - pose_left.y
        D = math.hypot(dx, dy)
        if not D > 1e-9:
            raise InputError(
                "baseline: the two optical centres coincide in the horizontal plane "
                f"(D = {D} mm); alpha is undefined"
            )
        alpha = math.atan2(dy, dx)
        origin = 0.5 * (pose_left.position + pose_right.position)
        return cls(
            camera=camera,
            pose_left=pose_left,
            pose_right=pose_right,
            alpha=alpha,
            theta_l=wrap_angle(pose_left.phi - alpha),
            theta_r=wrap_angle(pose_right.phi - alpha),
            baseline_mm=D,
            origin=(float(origin[0]), float(origin[1]), float(origin[2])),
        )

    @property
    def rotation(self) -> NDArray[np.float64]:
        """``(3, 3)``: columns are the epipolar X, Y, Z axes in the world."""
        return Pose(0.0, 0.0, 0.0, self.alpha).rotation

    def virtual_pose(self, side: Literal["left", "right"]) -> Pose:
        """Pose of the rectified (virtual) camera: same optical centre, yaw ``alpha``."""
        p = self._pose(side)
        return Pose(p.x, p.y, p.z, self.alpha)

    def valid_mask(self, side: Side) -> NDArray[np.bool_]:
        """Rectified pixels of one view whose source lies inside its image
        (:func:`rectified_valid_mask` with its theta)."""
        return rectified_valid_mask(self.camera, self.theta(side))

    def theta(self, side: Literal["left", "right"]) -> float:
        """``theta_l`` or ``theta_r``."""
        if side not in ("left", "right"):
            raise InputError(f"side must be 'left' or 'right', got {side!r}")
        return self.theta_l if side == "left" else self.theta_r

    def _pose(self, side: str) -> Pose:
        if side not in ("left", "right"):
            raise InputError(f"side must be 'left' or 'right', got {side!r}")
        return self.pose_left if side == "left" else self.pose_right

    def to_world(self, points_epi: ArrayLike) -> NDArray[np.float64]:
        """Epipolar-frame points to world points (lift triangulated points, the thesis, 3.6).

        Parameters
        ----------
        points_epi : array_like, shape (N, 3)
            ``(X, Y, Z)`` in the epipolar frame, millimetres (Z = depth below the
            mid-baseline point, positive in front of the camera).

        Returns
        -------
        ndarray, shape (N, 3)
            World points, millimetres: ``origin + R @ p``.
        """
        p = np.asarray(points_epi, dtype=float)
        if p.ndim == 1 and p.shape[0] == 3:
            p = p[None, :]
        if p.ndim != 2 or p.shape[1] != 3:
            raise InputError(f"points_epi must have shape (N, 3), got {p.shape}")
        return p @ self.rotation.T + np.asarray(self.origin)

    def from_world(self, points: ArrayLike) -> NDArray[np.float64]:
        """World points ``(N, 3)`` to the epipolar frame ``(N, 3)``: ``R^T (P - origin)``."""
        p = np.asarray(points, dtype=float)
        if p.ndim == 1 and p.shape[0] == 3:
            p = p[None, :]
        if p.ndim != 2 or p.shape[1] != 3:
            raise InputError(f"points must have shape (N, 3), got {p.shape}")
        return (p - np.asarray(self.origin)) @ self.rotation

    def to_rectified(self, points: ArrayLike, side: Literal["left", "right"]) -> NDArray:
        """Image points ``(N, 2)`` of one view to its rectified image (``image_to_epipolar``)."""
        return image_to_epipolar(points, self.camera, self.theta(side))

    def from_rectified(self, points: ArrayLike, side: Literal["left", "right"]) -> NDArray:
        """Rectified points ``(N, 2)`` back to the image of one view."""
        return epipolar_to_image(points, self.camera, self.theta(side))

    def rectify(
        self,
        image: ArrayLike,
        side: Literal["left", "right"],
        *,
        interpolation: Literal["nearest", "linear", "cubic", "lanczos4"] = "cubic",
        fill_value: float = math.nan,
    ) -> NDArray[np.float64]:
        """Rectify the image of one view (:func:`rectify_image` with its theta)."""
        return rectify_image(
            image, self.camera, self.theta(side), interpolation=interpolation,
            fill_value=fill_value,
        )
