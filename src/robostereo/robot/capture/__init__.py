"""Two views of a camera on an arm: capture folders and locating their edge points.

Modules
-------
:mod:`~robostereo.robot.capture.capture_folder`
    :class:`Capture` (two grabbed views, the camera and the two poses) and capture
    folders (``capture.yaml`` beside ``left.png`` and ``right.png``).
:mod:`~robostereo.robot.capture.locate_pair`
    :func:`locate` and :func:`locate_capture`: rectify by the poses (thesis 2.2), match,
    triangulate (eq. 6-8) into the robot's world frame with the eq. 9 bound.

Imports: :mod:`robostereo.errors`, :mod:`robostereo.geometry`, :mod:`robostereo.io` and
:mod:`robostereo.matcher`; no other part of :mod:`robostereo.robot`.

A capture folder ``CAP`` (``robostereo capture`` writes one) is located with::

    from robostereo.robot.capture import locate_capture, read_capture
    located = locate_capture(read_capture("CAP"))
"""

from robostereo.robot.capture.capture_folder import (
    CAPTURE_YAML,
    DISPARITY_UNCERTAINTY_PX,
    Capture,
    Geometry,
    Rectification,
    capture_from_acquisition,
    capture_to_dict,
    disparity_range_from_depth,
    read_capture,
    warn_units,
    write_capture,
)
from robostereo.robot.capture.capture_keys import (
    DEFAULT_FOCAL_UNCERTAINTY_MM,
    METRES_AS_MM_BELOW,
    POSE_CONVENTIONS,
    camera_pose_from_dict,
    check_views_share_scene,
    default_focal_uncertainty_mm,
    extras_from_dict,
    extras_to_dict,
    pose_convention,
    shared_scene_fractions,
    warn_identity_hand_eye,
    warn_metres,
)
from robostereo.robot.capture.locate_pair import (
    MIN_EDGE_POINTS_FOR_FRACTION,
    MIN_LOCATED_FRACTION,
    Located,
    LocateParameters,
    RectifiedPair,
    check_shared_scene,
    fill_invalid_rows,
    locate,
    locate_capture,
    rectify_pair,
    searched_depths,
)

__all__ = [
    "CAPTURE_YAML",
    "DEFAULT_FOCAL_UNCERTAINTY_MM",
    "DISPARITY_UNCERTAINTY_PX",
    "METRES_AS_MM_BELOW",
    "MIN_EDGE_POINTS_FOR_FRACTION",
    "MIN_LOCATED_FRACTION",
    "POSE_CONVENTIONS",
    "Capture",
    "Geometry",
    "LocateParameters",
    "Located",
    "Rectification",
    "RectifiedPair",
    "camera_pose_from_dict",
    "capture_from_acquisition",
    "capture_to_dict",
    "check_shared_scene",
    "check_views_share_scene",
    "default_focal_uncertainty_mm",
    "disparity_range_from_depth",
    "extras_from_dict",
    "extras_to_dict",
    "fill_invalid_rows",
    "locate",
    "locate_capture",
    "pose_convention",
    "read_capture",
    "rectify_pair",
    "searched_depths",
    "shared_scene_fractions",
    "warn_identity_hand_eye",
    "warn_metres",
    "warn_units",
    "write_capture",
]
