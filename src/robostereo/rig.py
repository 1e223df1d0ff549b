"""Calibrated stereo rigs: from an original (distorted) pair to 3-D edge points.

A user with a calibrated stereo camera has two original images, with lens distortion
and unaligned rows, and a calibration file (OpenCV, ROS or Middlebury; see
:mod:`robostereo.io.calibration_files`).  :func:`match_rig` rectifies the pair with
OpenCV, runs the core matcher (:func:`robostereo.matcher.pipeline.match_stereo`) on the
rectified pair and triangulates through the project's one triangulation path
(:func:`robostereo.geometry.triangulation.triangulate` with
:meth:`~robostereo.geometry.calibrated_rectification.Rectification.stereo_camera`).
Every matched point is reported three ways (:meth:`RigResult.table`):

* in rectified pixels: ``row, x_left, x_right, disparity``;
* as a 3-D point ``X, Y, Z`` in the **original** left camera's frame (millimetres,
  origin at its optical centre, x right, y down, z along its optical axis);
* at its position in the original (distorted) left image, ``x_original, y_original``;
* given the left camera's pose in a robot's base frame (an eye-to-hand calibration,
  :func:`~robostereo.robot.handeye.eye_to_hand.calibrate_eye_to_hand`), also in that
  frame: ``X_base, Y_base, Z_base``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_finite
from robostereo.geometry.calibrated_rectification import (
    Rectification,
    check_image_size,
    rectified_to_original,
    rectify_images,
    rectify_stereo,
)
from robostereo.geometry.calibration import StereoCalibration
from robostereo.geometry.poses import SE3
from robostereo.io.calibration_files import read_calibration
from robostereo.io.images import load_image
from robostereo.matcher.parameters import MatchParameters
from robostereo.matcher.pipeline import MatchResult, match_stereo

__all__ = [
    "RigResult",
    "disparity_range_for_depth",
    "load_rig_pair",
    "match_rig",
    "valid_mask",
]

PathLike = str | Path


def disparity_range_for_depth(
    rect: Rectification, min_depth_mm: float, max_depth_mm: float
) -> tuple[float, float]:
    """The rectified disparity range of the depths ``[min_depth_mm, max_depth_mm]``.

    Parameters
    ----------
    rect : Rectification
    min_depth_mm, max_depth_mm : float
        Nearest and farthest depth of interest (rectified left frame), millimetres.

    Returns
    -------
    tuple of float
        ``(fx B / max_depth - doffs, fx B / min_depth - doffs)``, pixels.

    Examples
    --------
    >>> from robostereo.geometry.calibration import StereoCalibration
    >>> from robostereo.geometry.calibrated_rectification import rectify_stereo
    >>> K = [[800.0, 0, 319.5], [0, 800.0, 239.5], [0, 0, 1]]
    >>> r = rectify_stereo(StereoCalibration(K, None, K, None, np.eye(3), [-60, 0, 0], (640, 480)))
    >>> disparity_range_for_depth(r, 500.0, 2000.0)
    (24.0, 96.0)
    """
    require_finite("depth range", [min_depth_mm, max_depth_mm])
    if not 0 < min_depth_mm <= max_depth_mm:
        raise InputError(
            f"depth range must satisfy 0 < min <= max, got {min_depth_mm} .. {max_depth_mm}"
        )
    fb = rect.fx * rect.baseline_mm
    return fb / max_depth_mm - rect.doffs, fb / min_depth_mm - rect.doffs


def valid_mask(
    rect: Rectification, which: Literal["left", "right"] = "left", *, margin: int = 3
) -> NDArray[np.bool_]:
    """Rectified pixels that sample the original image at least `margin` px inside it.

    Parameters
    ----------
    rect : Rectification
    which : {"left", "right"}
    margin : int
        The mask is eroded by this many pixels, so that the 5x5 smoothing of the
        matcher never mixes in the black fill outside the original image.

    Returns
    -------
    ndarray of bool, shape (H', W')
    """
    mx, my = rect.map_left if which == "left" else rect.map_right
    w, h = rect.calibration.image_size
    ok = (mx >= 0) & (mx <= w - 1) & (my >= 0) & (my <= h - 1)
    if margin > 0:
        k = np.ones((2 * margin + 1, 2 * margin + 1), np.uint8)
        ok = cv2.erode(ok.astype(np.uint8), k, borderType=cv2.BORDER_CONSTANT,
                       borderValue=0).astype(bool)
    return ok


@dataclass(frozen=True)
class RigResult:
    """Matches of a calibrated pair, in rectified pixels, original pixels and millimetres.

    Attributes
    ----------
    match : MatchResult
        The core matcher's result on the rectified pair (all stages inspectable); its
        camera is :meth:`Rectification.stereo_camera`.
    rectification : Rectification
    left_rectified, right_rectified : ndarray, shape (H', W'[, C])
        The rectified images the matcher saw.
    """

    match: MatchResult
    rectification: Rectification
    left_rectified: NDArray[Any]
    right_rectified: NDArray[Any]

    def __len__(self) -> int:
        return len(self.match)

    @property
    def points_rectified(self) -> NDArray[np.float64]:
        """``(x_left, row)`` of each match in the rectified left image, shape ``(K, 2)``."""
        return np.column_stack([self.match.x_left, self.match.rows.astype(float)])

    @property
    def points_original(self) -> NDArray[np.float64]:
        """``(x, y)`` of each match in the original (distorted) left image, ``(K, 2)``."""
        return rectified_to_original(self.points_rectified, self.rectification, "left")

    def points_3d(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """3-D points in the original left camera frame ``(K, 3)`` (mm) and depth bounds.

        Notes
        -----
        1. :func:`robostereo.geometry.triangulation.triangulate` (eq. 6-9) gives the points in the
           epipolar frame of the rectified pair (origin mid-baseline);
        2. ``+B/2`` along X moves the origin to the left optical centre (the rectified
           left frame);
        3. ``R1^T`` rotates them into the original left camera frame.

        The bound is eq. (9)'s, along the rectified optical axis.
        """
        xyz, bound = self.match.triangulated()
        xyz = xyz.copy()
        xyz[:, 0] += 0.5 * self.rectification.baseline_mm
        return xyz @ np.asarray(self.rectification.R1), bound

    def table(self, base_camera: SE3 | None = None) -> dict[str, NDArray[Any]]:
        """Columns per match: ``row, x_left, x_right, disparity, confidence`` (rectified
        pixels), ``x_original, y_original`` (original left image), ``X, Y, Z`` (original
        left camera frame, mm) and ``z_bound`` (mm); with `base_camera` (the left
        camera's ``T_base_camera``, an eye-to-hand calibration's) also ``X_base, Y_base,
        Z_base``: the points in the robot's base frame, mm."""
        cols = {k: v for k, v in self.match.table().items()
                if k in ("row", "x_left", "x_right", "disparity", "confidence")}
        orig = self.points_original
        xyz, bound = self.points_3d()
        cols.update(x_original=orig[:, 0], y_original=orig[:, 1],
                    X=xyz[:, 0], Y=xyz[:, 1], Z=xyz[:, 2], z_bound=bound)
        if base_camera is not None:
            b = base_camera.apply(xyz)
            cols.update(X_base=b[:, 0], Y_base=b[:, 1], Z_base=b[:, 2])
        return cols


def match_rig(
    left: ArrayLike,
    right: ArrayLike,
    calibration: StereoCalibration | Rectification,
    disparity_range: tuple[float, float] | None = None,
    *,
    depth_range_mm: tuple[float, float] | None = None,
    params: MatchParameters | None = None,
    disparity_uncertainty_px: float = 0.5,
    interpolation: Literal["linear", "cubic"] = "linear",
    zero_disparity: bool | None = None,
    names: tuple[str, str] = ("left image", "right image"),
    progress: Callable[[str], None] | None = None,
) -> RigResult:
    """Rectify, match and triangulate an original pair from a calibrated rig.

    Parameters
    ----------
    left, right : array_like, shape (H, W) or (H, W, C)
        Original images (with lens distortion) of the calibrated size.
    calibration : StereoCalibration or Rectification
        The rig; a :class:`Rectification` is reused as is (rectify once for many pairs).
    disparity_range : tuple of float, optional
        ``(min, max)`` rectified disparity, pixels.
    depth_range_mm : tuple of float, optional
        ``(nearest, farthest)`` depth instead of `disparity_range`
        (:func:`disparity_range_for_depth`).
    params : MatchParameters, optional
        Matcher tuning; default :class:`MatchParameters()`.
    disparity_uncertainty_px : float
        ``d(disp)`` of the eq. (9) bound (0.5 px by default: sub-pixel edges resampled
        once by the rectification; the calibration itself is taken as exact).
    interpolation : {"linear", "cubic"}
        Resampling of the rectification.
    zero_disparity : bool or None
        OpenCV's ``CALIB_ZERO_DISPARITY`` (equal rectified principal points, so
        ``doffs = 0``).  None: True, except for a rig that is already rectified (a
        Middlebury ``calib.txt``: no distortion, ``R = I``), whose images are then used
        as they are and whose disparities keep the file's ``doffs``.
    names : tuple of str
        Names of the two images (files) in error messages.
    progress : callable, optional
        Called with each stage's name.

    Returns
    -------
    RigResult

    Raises
    ------
    InputError
        An image not of the calibrated size (naming it), an empty or missing range.

    Notes
    -----
    1. Check both images against the calibrated size.
    2. :func:`~robostereo.geometry.calibrated_rectification.rectify_stereo` (unless
       given a Rectification) and
       :func:`~robostereo.geometry.calibrated_rectification.rectify_images`: distortion
       removed, rows epipolar.
    3. :func:`~robostereo.matcher.pipeline.match_stereo` on the rectified pair, with
       :meth:`Rectification.stereo_camera` as its camera.
    4. The part of each rectified image with no source (black fill) is passed to the
       matcher as invalid (:func:`valid_mask`): no edge point is taken whose features
       see the fill, so its border makes no false edges.
    5. Points and 3-D through :meth:`RigResult.table` (one triangulation path).

    References
    ----------
    Seed chapter 3 (matching) and 3.6-3.7 (triangulation, eq. 6-9).
    """
    rect = calibration if isinstance(calibration, Rectification) else None
    calib = rect.calibration if rect is not None else calibration
    assert isinstance(calib, StereoCalibration)
    a, b = np.asarray(left), np.asarray(right)
    check_image_size(calib, a.shape, names[0])
    check_image_size(calib, b.shape, names[1])
    say = progress or (lambda _s: None)
    say("rectification")
    if rect is None:
        if zero_disparity is None:
            zero_disparity = bool(np.any(calib.D1) or np.any(calib.D2)
                                  or not np.array_equal(calib.R, np.eye(3)))
        rect = rectify_stereo(calib, zero_disparity=zero_disparity)
    if (disparity_range is None) == (depth_range_mm is None):
        raise InputError("give either a disparity range or a depth range (not both)")
    if depth_range_mm is not None:
        disparity_range = disparity_range_for_depth(rect, *depth_range_mm)
    assert disparity_range is not None
    lr, rr = rectify_images(rect, a, b, interpolation=interpolation)
    camera = rect.stereo_camera(disparity_uncertainty_px=disparity_uncertainty_px)
    res = match_stereo(lr, rr, disparity_range, params=params, camera=camera,
                       valid_left=valid_mask(rect, "left", margin=0),
                       valid_right=valid_mask(rect, "right", margin=0), progress=progress)
    return RigResult(match=res, rectification=rect, left_rectified=lr, right_rectified=rr)


def load_rig_pair(
    left_path: PathLike,
    right_path: PathLike,
    calibration_path: PathLike,
    calibration_right_path: PathLike | None = None,
) -> tuple[NDArray[Any], NDArray[Any], StereoCalibration, int]:
    """Read an original pair and its calibration, checking sizes and bit depths.

    Parameters
    ----------
    left_path, right_path : str or Path
        The original images.
    calibration_path : str or Path
        OpenCV FileStorage YAML/XML/JSON, Middlebury ``calib.txt`` or the left ROS
        ``camera_info`` YAML (:func:`~robostereo.io.calibration_files.read_calibration`).
    calibration_right_path : str or Path, optional
        The right ROS ``camera_info`` YAML (or OpenCV's extrinsics file).

    Returns
    -------
    left, right : ndarray
    calibration : StereoCalibration
    bit_depth : int

    Raises
    ------
    InputError
        Unreadable files, a bad calibration (non-invertible or NaN matrix...), an image
        not of the calibrated size, different bit depths: one line naming the file.
    """
    calib = read_calibration(calibration_path, calibration_right_path)
    left, bits_l = load_image(left_path)
    right, bits_r = load_image(right_path)
    check_image_size(calib, left.shape, left_path)
    check_image_size(calib, right.shape, right_path)
    if bits_l != bits_r:
        raise InputError(f"{right_path}: bit depth {bits_r} differs from the left image's {bits_l}")
    return left, right, calib, bits_l
