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
    METRES_AS_MM_BELOW,
    Capture,
    Geometry,
    Rectification,
    capture_from_acquisition,
    capture_to_dict,
    disparity_range_from_depth,
    extras_from_dict,
    extras_to_dict,
    read_capture,
    warn_identity_hand_eye,
    warn_metres,
    warn_units,
    write_capture,
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
    "DISPARITY_UNCERTAINTY_PX",
    "METRES_AS_MM_BELOW",
    "MIN_EDGE_POINTS_FOR_FRACTION",
    "MIN_LOCATED_FRACTION",
    "Capture",
    "Geometry",
    "LocateParameters",
    "Located",
    "Rectification",
    "RectifiedPair",
    "capture_from_acquisition",
    "capture_to_dict",
    "check_shared_scene",
    "disparity_range_from_depth",
    "extras_from_dict",
    "extras_to_dict",
    "fill_invalid_rows",
    "locate",
    "locate_capture",
    "read_capture",
    "rectify_pair",
    "searched_depths",
    "warn_identity_hand_eye",
    "warn_metres",
    "warn_units",
    "write_capture",
]
