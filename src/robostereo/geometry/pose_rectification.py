"""Stereo geometry of two general 6-DoF camera poses (the thesis's 2.2 for any arm).

The thesis's SCARA keeps the camera looking straight down and moves it horizontally, so
each view is rectified by a turn ``theta`` about its optical axis
(:class:`robostereo.geometry.scara_rectification.EpipolarGeometry`).  A six-axis arm
tilts the camera and moves it in all six coordinates; :class:`GeneralEpipolarGeometry`
rectifies such a pair with OpenCV:

1. the relative pose ``T_right_left`` (``x_right = R x_left + T``,
   :func:`robostereo.geometry.poses.relative_pose`);
2. :func:`cv2.stereoRectify` with the camera's intrinsics and distortion
   (``CALIB_ZERO_DISPARITY``, ``alpha = 0``) gives the rotations ``R1``, ``R2`` of the
   two virtual cameras and their common projection; an extra quarter or half turn
   about the optical axis makes the baseline run along +x of the rectified images
   whatever way it runs through the grabbed ones (OpenCV picks rows or columns);
3. :func:`cv2.initUndistortRectifyMap` and :func:`cv2.remap` resample each view.

The rectified pair keeps the camera's pixel scale (its ``fx`` and ``fy``, without
distortion), has rows that are epipolar lines and ``d = x_l - x_r`` positive in front.
Its frame is chosen from the views (:func:`rectified_frame`): the rows both grabbed
images reach once rectified and the columns either reaches, so that every pixel both
views see lies inside it.  Views turned about their optical axes (DTU's neighbours turn
27 deg) come out of rectification turned by as much; the camera's own image size and
principal point would cut their corners off (72 % of the edge pixels both views of the
shipped DTU pair see lay inside them; ``frame="camera"`` keeps that frame).  Its
epipolar frame is the thesis's: origin mid-baseline, X along the baseline from the left
to the right optical centre, Z along the virtual cameras' common optical axis, Y = Z x X;
:meth:`GeneralEpipolarGeometry.to_world` carries eq. (6)-(8) points into the robot's
base frame.  For two SCARA poses (looking down, equal heights) the epipolar frame is
the thesis's exactly; only the resampling differs.  :class:`GeneralEpipolarGeometry`
is a :class:`~robostereo.geometry.rectification.Rectifier`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3, as_se3, relative_pose
from robostereo.geometry.rectification import INTERPOLATION, Side, maps_valid_mask

__all__ = [
    "MAX_FRAME_GROWTH",
    "MIN_OVERLAP_ROWS",
    "GeneralEpipolarGeometry",
    "rectified_frame",
]

MIN_OVERLAP_ROWS = 10
"""Fewest rectified rows that both views must cover for a pair to be matched."""

MAX_FRAME_GROWTH = 0.5
"""How far the rectified frame may reach beyond the camera's own image on each side,
as a fraction of that side: a view turned far out of the baseline's plane maps its far
corners towards infinity, and the frame stops there (at most twice the side)."""

_BORDER_SAMPLES = 64  # points sampled along each side of a grabbed image's border

Frame = Literal["views", "camera"]


def _quarter_turn(b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation about z (multiple of 90 deg) that takes the in-plane direction of `b`
    to +x."""
    k = round(math.atan2(b[1], b[0]) / (math.pi / 2))
    a = -k * math.pi / 2
    c, s = round(math.cos(a)), round(math.sin(a))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _border(size: tuple[int, int]) -> NDArray[np.float64]:
    """Pixel centres along an image's border, ``(4 * _BORDER_SAMPLES, 2)``."""
    w, h = size
    t = np.linspace(0.0, 1.0, _BORDER_SAMPLES)
    x, y = t * (w - 1), t * (h - 1)
    zero, right, bottom = np.zeros_like(t), np.full_like(t, w - 1.0), np.full_like(t, h - 1.0)
    return np.concatenate([np.column_stack([x, zero]), np.column_stack([x, bottom]),
                           np.column_stack([zero, y]), np.column_stack([right, y])])


def rectified_frame(
    camera: Camera, R1: NDArray[np.float64], R2: NDArray[np.float64]
) -> tuple[NDArray[np.float64], tuple[int, int]]:
    """The rectified intrinsics and image size that hold every pixel both views see.

    Parameters
    ----------
    camera : Camera
        The grabbing camera (its ``fx``, ``fy`` kept: the pixel scale does not change).
    R1, R2 : ndarray, shape (3, 3)
        Rotation from each grabbed camera's frame to its rectified camera's frame.

    Returns
    -------
    K_rect : ndarray, shape (3, 3)
        ``fx``, ``fy`` of the camera; the principal point moved so that the frame's
        first row and column are pixel 0.
    size : tuple of int
        ``(width, height)`` of both rectified images.

    Notes
    -----
    1. Points along each grabbed image's border (pixel centres) undistorted and turned
       by ``R_i`` into its rectified camera; those in front of it projected with the
       camera's ``fx``, ``fy`` about the camera's principal point.
    2. Rows: those both outlines reach (a pixel both views see lies on a row of
       both).  Columns: those either reaches (one ``K_rect`` for both views, so that
       ``d = x_l - x_r`` keeps eq. 8's meaning).
    3. Each side clipped to :data:`MAX_FRAME_GROWTH` beyond the camera's own image.
       When the outlines share no row the camera's own frame is kept (the pair then
       fails :meth:`GeneralEpipolarGeometry.check_overlap`).

    Examples
    --------
    Two views of one camera, the right one turned 20 degrees about its optical axis:
    its corners stick out of the camera's own frame, and the frame grows to hold them.

    >>> cam = Camera(image_size=(320, 240))
    >>> turn = SE3.from_rotvec([0.0, 0.0, 0.0], [0.0, 0.0, np.radians(20.0)]).rotation
    >>> K, (w, h) = rectified_frame(cam, np.eye(3), turn)
    >>> bool(w > 320), h
    (True, 240)
    """
    w, h = camera.image_size
    fx, fy = camera.fx, camera.fy
    cx, cy = camera.principal_point
    border = _border((w, h))
    n = camera.undistort(np.column_stack([(border[:, 0] - cx) / fx,
                                          (border[:, 1] - cy) / fy]))
    rays = np.column_stack([n, np.ones(len(n))])
    lo_x, hi_x, lo_y, hi_y = -MAX_FRAME_GROWTH * w, (1 + MAX_FRAME_GROWTH) * w - 1, \
        -MAX_FRAME_GROWTH * h, (1 + MAX_FRAME_GROWTH) * h - 1
    xs, ys = [], []
    for R in (R1, R2):
        r = rays @ R.T
        front = r[:, 2] > 1e-6
        if not front.any():
            return camera.K.copy(), (w, h)
        # a border point behind the rectified camera: the outline runs out to the clip
        x = fx * r[front, 0] / r[front, 2] + cx
        y = fy * r[front, 1] / r[front, 2] + cy
        if front.all():
            xs.append((max(float(x.min()), lo_x), min(float(x.max()), hi_x)))
            ys.append((max(float(y.min()), lo_y), min(float(y.max()), hi_y)))
        else:
            xs.append((lo_x, hi_x))
            ys.append((lo_y, hi_y))
    x0, x1 = min(a for a, _ in xs), max(b for _, b in xs)
    y0, y1 = max(a for a, _ in ys), min(b for _, b in ys)
    if not y1 > y0:
        return camera.K.copy(), (w, h)
    left, top = math.floor(x0), math.floor(y0)
    size = (math.ceil(x1) - left + 1, math.ceil(y1) - top + 1)
    K = np.array([[fx, 0.0, cx - left], [0.0, fy, cy - top], [0.0, 0.0, 1.0]])
    return K, size


@dataclass(frozen=True, eq=False)
class GeneralEpipolarGeometry:
    """Rectification of two views of one camera from two general poses.

    Build it with :meth:`from_poses`.

    Attributes
    ----------
    camera : Camera
        The grabbing camera (intrinsics and distortion).
    pose_left, pose_right : SE3
        ``T_world_camera`` of the two views (world millimetres).
    R1, R2 : ndarray, shape (3, 3)
        Rotation from each grabbed camera's frame to its rectified camera's frame.
    K_rect : ndarray, shape (3, 3)
        Intrinsics of both rectified views: the grabbing camera's ``fx``, ``fy``, the
        principal point of the rectified frame (:func:`rectified_frame`), no distortion.
    size_rect : tuple of int
        ``(width, height)`` of both rectified images.
    baseline_mm : float
        ``D``, the distance between the optical centres.
    origin : ndarray, shape (3,)
        Mid-baseline point, world millimetres.
    rotation : ndarray, shape (3, 3)
        Columns: the epipolar frame's X, Y, Z axes in the world.

    Examples
    --------
    Two views 30 mm apart, tilted 25 degrees, looking at the origin:

    >>> from robostereo.geometry.camera import Camera
    >>> cam = Camera(image_size=(320, 240), pixel_pitch_mm=(0.02, 0.02))
    >>> a = SE3.look_at([-15.0, -400.0, 900.0], [0.0, 0.0, 0.0])
    >>> b = SE3.look_at([15.0, -390.0, 905.0], [0.0, 0.0, 0.0])
    >>> g = GeneralEpipolarGeometry.from_poses(cam, a, b)
    >>> round(g.baseline_mm, 3)
    32.016
    >>> P = np.array([[10.0, 20.0, 30.0]])
    >>> pl = g.to_rectified(cam.project(P, a)[0], "left")
    >>> pr = g.to_rectified(cam.project(P, b)[0], "right")
    >>> bool(abs(pl[0, 1] - pr[0, 1]) < 1e-6), bool(pl[0, 0] > pr[0, 0])  # same row, d > 0
    (True, True)
    """

    camera: Camera
    pose_left: SE3
    pose_right: SE3
    R1: NDArray[np.float64]
    R2: NDArray[np.float64]
    K_rect: NDArray[np.float64]
    size_rect: tuple[int, int]
    baseline_mm: float
    origin: NDArray[np.float64]
    rotation: NDArray[np.float64]

    @classmethod
    def from_poses(
        cls, camera: Camera, pose_left: SE3, pose_right: SE3, *, frame: Frame = "views"
    ) -> GeneralEpipolarGeometry:
        """Rectify the views at `pose_left` and `pose_right` (camera poses, world mm).

        Parameters
        ----------
        camera : Camera
        pose_left, pose_right : SE3
        frame : {'views', 'camera'}
            The rectified images' frame: ``'views'`` holds every pixel both views see
            (:func:`rectified_frame`); ``'camera'`` keeps the camera's ``K`` and image
            size (the frame of 0.1, which cuts off the corners of views turned
            about their optical axes).

        Raises
        ------
        InputError
            Zero baseline (the optical centres coincide), or an unknown `frame`.

        Notes
        -----
        ``T_right_left = T_world_right^-1 T_world_left``; :func:`cv2.stereoRectify`
        on ``K``, the distortion and ``(R, T)`` of it; ``R_i <- Q R_i`` with ``Q`` the
        quarter turn taking the baseline ``R1 (c_r - c_l)`` to +x; ``K_rect`` and the
        size from :func:`rectified_frame` (or ``K`` and the camera's size).

        References
        ----------
        The thesis, 2.2 (the epipolar frame; rectification by theta is the SCARA case).
        """
        if frame not in ("views", "camera"):
            raise InputError(f"frame must be 'views' or 'camera', got {frame!r}")
        tl, tr = as_se3(pose_left), as_se3(pose_right)
        rel = relative_pose(tl, tr)
        D = float(np.linalg.norm(tr.translation - tl.translation))
        if not D > 1e-9:
            raise InputError(f"baseline: the two optical centres coincide (D = {D} mm)")
        K = camera.K
        dist = camera.dist_coeffs
        size = camera.image_size
        R1, R2, _P1, _P2, _Q, _r1, _r2 = cv2.stereoRectify(
            K, dist, K, dist, size, rel.rotation, rel.translation.reshape(3, 1),
            flags=cv2.CALIB_ZERO_DISPARITY, alpha=0.0,
        )
        # baseline (left to right centre) in the left camera's frame, then rectified
        b_left = tl.rotation.T @ (tr.translation - tl.translation)
        Q = _quarter_turn(R1 @ b_left)
        R1, R2 = Q @ R1, Q @ R2
        # the rectified views keep the grabbing camera's pixel scale (fx, fy): no
        # resampling to another scale, so edge thresholds and eq. 9's d(disp) mean what
        # they mean for the grabbed images (P1's zoom is not used); the frame is moved
        # and grown to hold both views
        if frame == "views":
            K_rect, size_rect = rectified_frame(camera, R1, R2)
        else:
            K_rect, size_rect = camera.K.copy(), camera.image_size
        rot_epi = tl.rotation @ R1.T  # rectified-left axes in the world
        origin = 0.5 * (tl.translation + tr.translation)
        return cls(camera=camera, pose_left=tl, pose_right=tr, R1=R1, R2=R2, K_rect=K_rect,
                   size_rect=size_rect, baseline_mm=D, origin=origin, rotation=rot_epi)

    # --------------------------------------------------------------------- frames
    def _R(self, side: Side) -> NDArray[np.float64]:
        if side not in ("left", "right"):
            raise InputError(f"side must be 'left' or 'right', got {side!r}")
        return self.R1 if side == "left" else self.R2

    def to_world(self, points_epi: ArrayLike) -> NDArray[np.float64]:
        """Epipolar-frame points ``(N, 3)`` (mm, origin mid-baseline) to the world."""
        p = np.atleast_2d(np.asarray(points_epi, dtype=float))
        if p.shape[-1] != 3:
            raise InputError(f"points_epi must have shape (N, 3), got {p.shape}")
        return p @ self.rotation.T + self.origin

    def from_world(self, points: ArrayLike) -> NDArray[np.float64]:
        """World points ``(N, 3)`` to the epipolar frame: ``R^T (P - origin)``."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        return (p - self.origin) @ self.rotation

    def to_rectified(self, points: ArrayLike, side: Side) -> NDArray[np.float64]:
        """Grabbed-image pixels ``(N, 2)`` of one view to its rectified image."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        cam = self.camera
        cx, cy = cam.principal_point
        n = cam.undistort(np.column_stack([(p[:, 0] - cx) / cam.fx, (p[:, 1] - cy) / cam.fy]))
        ray = np.column_stack([n, np.ones(len(n))]) @ self._R(side).T
        with np.errstate(divide="ignore", invalid="ignore"):
            uv = ray[:, :2] / ray[:, 2:3]
        K = self.K_rect
        return np.column_stack([K[0, 0] * uv[:, 0] + K[0, 2], K[1, 1] * uv[:, 1] + K[1, 2]])

    def from_rectified(self, points: ArrayLike, side: Side) -> NDArray[np.float64]:
        """Rectified pixels ``(N, 2)`` back to the grabbed (distorted) image."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        K = self.K_rect
        ray = np.column_stack([(p[:, 0] - K[0, 2]) / K[0, 0], (p[:, 1] - K[1, 2]) / K[1, 1],
                               np.ones(len(p))]) @ self._R(side)
        with np.errstate(divide="ignore", invalid="ignore"):
            n = self.camera.distort(ray[:, :2] / ray[:, 2:3])
        cam = self.camera
        cx, cy = cam.principal_point
        return np.column_stack([cam.fx * n[:, 0] + cx, cam.fy * n[:, 1] + cy])

    # --------------------------------------------------------------------- images
    def _maps(self, side: Side) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
        mx, my = cv2.initUndistortRectifyMap(
            self.camera.K, self.camera.dist_coeffs, self._R(side), self.K_rect,
            self.size_rect, cv2.CV_32FC1,
        )
        return mx, my

    def valid_mask(self, side: Side) -> NDArray[np.bool_]:
        """Rectified pixels whose source lies within the grabbed image's pixel centres."""
        mx, my = self._maps(side)
        return maps_valid_mask(mx, my, self.camera.image_size)

    def rectify(
        self,
        image: ArrayLike,
        side: Side,
        *,
        interpolation: Literal["nearest", "linear", "cubic", "lanczos4"] = "linear",
        fill_value: float = math.nan,
    ) -> NDArray[np.float64]:
        """Undistort and rectify the grabbed image of one view, shape ``(H, W)`` of
        :attr:`size_rect`.

        Pixels whose source lies outside the grabbed image are `fill_value`.
        """
        img = np.asarray(image, dtype=np.float64)
        w, h = self.camera.image_size
        if img.shape != (h, w):
            raise InputError(f"image must have shape (H, W) = ({h}, {w}), got {img.shape}")
        if interpolation not in INTERPOLATION:
            raise InputError(
                f"interpolation must be one of {sorted(INTERPOLATION)}, got {interpolation!r}"
            )
        mx, my = self._maps(side)
        out = cv2.remap(img, mx, my, INTERPOLATION[interpolation],
                        borderMode=cv2.BORDER_REPLICATE)
        out[~maps_valid_mask(mx, my, (w, h))] = fill_value
        return out

    def check_overlap(self) -> None:
        """Raise InputError if the pair cannot be rectified into rows: an epipole inside
        an image (the baseline runs along the view, e.g. the camera moved forward), or
        fewer than :data:`MIN_OVERLAP_ROWS` rectified rows that hold data in both
        views."""
        cam = self.camera
        w, h = cam.image_size
        for side, pose, other in (("left", self.pose_left, self.pose_right),
                                  ("right", self.pose_right, self.pose_left)):
            c = (other.translation - pose.translation) @ pose.rotation  # in this camera
            if abs(c[2]) > 1e-12:
                u = cam.fx * c[0] / c[2] + cam.principal_point[0]
                v = cam.fy * c[1] / c[2] + cam.principal_point[1]
                if -0.5 <= u <= w - 0.5 and -0.5 <= v <= h - 0.5:
                    raise InputError(
                        f"the baseline (D = {self.baseline_mm:.4g} mm) runs along the "
                        f"{side} view: the other camera's centre projects inside its image "
                        f"at ({u:.0f}, {v:.0f}), so no rectification makes rows; move the "
                        "camera across its view, not along it")
        vl, vr = self.valid_mask("left"), self.valid_mask("right")
        both = int(np.count_nonzero((vl.sum(axis=1) >= 10) & (vr.sum(axis=1) >= 10)))
        if both < MIN_OVERLAP_ROWS:
            b = self.pose_left.rotation.T @ (self.pose_right.translation
                                             - self.pose_left.translation)
            tilt = math.degrees(math.asin(min(1.0, abs(b[2]) / float(np.linalg.norm(b)))))
            raise InputError(
                f"the two views do not overlap once rectified: {both} rectified rows are "
                f"seen by both (need at least {MIN_OVERLAP_ROWS}); the baseline (D = "
                f"{self.baseline_mm:.4g} mm) runs {tilt:.0f} deg out of the left image "
                "plane and rectification turns the views by as much"
            )
