"""Files in and out: images, cameras and poses, calibrations, results.

Modules
-------
:mod:`~robostereo.io.files`
    Atomic writers (CSV tables, PLY point clouds, image folders) and the output checks
    of a command.
:mod:`~robostereo.io.folder_yaml`
    A folder's YAML file (``capture.yaml``): its text, reading it, the files it names.
:mod:`~robostereo.io.images`
    Image files (:func:`load_image`) and PFM disparity maps.
:mod:`~robostereo.io.cameras`
    YAML files of a camera, a pose, a stereo pair of poses and a stereo camera.
:mod:`~robostereo.io.calibration_files`
    Stereo calibration files: OpenCV ``FileStorage``, ROS ``camera_info``,
    Middlebury ``calib.txt``.
:mod:`~robostereo.io.camera_file`
    One camera's OpenCV or ROS ``camera_info`` file, and a capture's ``camera:`` key.

The package may import :mod:`robostereo.geometry`; geometry never imports io.
"""

from robostereo.io.calibration_files import (
    MiddleburyCalib,
    read_calibration,
    read_middlebury_calib,
    read_opencv_calibration,
    read_ros_calibration,
    write_opencv_calibration,
)
from robostereo.io.cameras import (
    load_camera_yaml,
    load_pose_yaml,
    load_stereo_camera,
    load_stereo_poses_yaml,
    save_camera_yaml,
    save_pose_yaml,
    stereo_camera_from_dict,
    stereo_camera_to_dict,
)
from robostereo.io.files import (
    atomic_outputs,
    atomic_path,
    check_outputs,
    remove_live_parts,
    remove_stale_parts,
    write_csv,
    write_image_folder,
    write_ply,
)
from robostereo.io.folder_yaml import (
    folder_file,
    folder_yaml_text,
    plain_values,
    read_folder_yaml,
)
from robostereo.io.images import load_image, read_pfm, write_pfm

__all__ = [
    "MiddleburyCalib",
    "atomic_outputs",
    "atomic_path",
    "check_outputs",
    "folder_file",
    "folder_yaml_text",
    "load_camera_yaml",
    "load_image",
    "load_pose_yaml",
    "load_stereo_camera",
    "load_stereo_poses_yaml",
    "plain_values",
    "read_calibration",
    "read_folder_yaml",
    "read_middlebury_calib",
    "read_opencv_calibration",
    "read_pfm",
    "read_ros_calibration",
    "remove_live_parts",
    "remove_stale_parts",
    "save_camera_yaml",
    "save_pose_yaml",
    "stereo_camera_from_dict",
    "stereo_camera_to_dict",
    "write_csv",
    "write_image_folder",
    "write_opencv_calibration",
    "write_pfm",
    "write_ply",
]
