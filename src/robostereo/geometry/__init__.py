"""Geometry under one roof: cameras, poses, rectifications, triangulation.

Modules
-------
:mod:`~robostereo.geometry.camera`
    The pinhole :class:`Camera` (with lens distortion) and its mapping form.
:mod:`~robostereo.geometry.poses`
    :class:`SE3`, the one pose type; the thesis's SCARA pose :class:`Pose` (an SE3),
    the conversions between them and the file forms of a pose.
:mod:`~robostereo.geometry.mapping_checks`
    Checked reading of the plain mappings that files hold.
:mod:`~robostereo.geometry.rectification`
    :class:`Rectifier`, the interface the three rectifications share.
:mod:`~robostereo.geometry.scara_rectification`
    The SCARA pair rectified by a turn about each optical axis
    (:class:`EpipolarGeometry`, the thesis 2.2).
:mod:`~robostereo.geometry.pose_rectification`
    Two views from general 6-DoF poses (:class:`GeneralEpipolarGeometry`).
:mod:`~robostereo.geometry.calibration`
    A calibrated two-camera rig (:class:`StereoCalibration`) and its checks.
:mod:`~robostereo.geometry.calibrated_rectification`
    OpenCV's rectification of a calibrated rig (:class:`Rectification`) and its
    point maps.
:mod:`~robostereo.geometry.triangulation`
    Depth and 3-D points from disparity, with the eq. (9) error bound.

Files are read and written by :mod:`robostereo.io`; nothing here imports it.
"""

from robostereo.geometry.calibrated_rectification import (
    Rectification,
    check_image_size,
    original_to_rectified,
    points_in_left_camera,
    rectified_to_original,
    rectify_images,
    rectify_stereo,
    triangulate_rectified,
)
from robostereo.geometry.calibration import StereoCalibration
from robostereo.geometry.camera import (
    SEED_CAMERA,
    Camera,
    camera_from_dict,
    camera_to_dict,
    wrap_angle,
)
from robostereo.geometry.pose_rectification import MIN_OVERLAP_ROWS, GeneralEpipolarGeometry
from robostereo.geometry.poses import (
    SE3,
    Pose,
    as_se3,
    pose_from_dict,
    pose_to_dict,
    relative_pose,
    scara_from_se3,
    se3_from_scara,
)
from robostereo.geometry.rectification import INTERPOLATION, Rectifier
from robostereo.geometry.scara_rectification import (
    EpipolarGeometry,
    epipolar_to_image,
    image_to_epipolar,
    rectification_matrix,
    rectified_valid_mask,
    rectify_image,
)
from robostereo.geometry.triangulation import (
    StereoCamera,
    depth_error_bound,
    depth_from_disparity,
    triangulate,
)

__all__ = [
    "INTERPOLATION",
    "MIN_OVERLAP_ROWS",
    "SE3",
    "SEED_CAMERA",
    "Camera",
    "EpipolarGeometry",
    "GeneralEpipolarGeometry",
    "Pose",
    "Rectification",
    "Rectifier",
    "StereoCalibration",
    "StereoCamera",
    "as_se3",
    "camera_from_dict",
    "camera_to_dict",
    "check_image_size",
    "depth_error_bound",
    "depth_from_disparity",
    "epipolar_to_image",
    "image_to_epipolar",
    "original_to_rectified",
    "points_in_left_camera",
    "pose_from_dict",
    "pose_to_dict",
    "rectification_matrix",
    "rectified_to_original",
    "rectified_valid_mask",
    "rectify_image",
    "rectify_images",
    "rectify_stereo",
    "relative_pose",
    "scara_from_se3",
    "se3_from_scara",
    "triangulate",
    "triangulate_rectified",
    "wrap_angle",
]
