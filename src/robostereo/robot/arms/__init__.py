"""Arm models: the thesis's AdeptOne SCARA and a UR5-like six-axis arm.

Modules
-------
:mod:`~robostereo.robot.arms.scara`
    The AdeptOne SCARA (section 4.1): joints, limits, camera mounts, forward and
    inverse kinematics.
:mod:`~robostereo.robot.arms.acquisition`
    The :class:`Robot` and :class:`CameraDevice` protocols, the simulated forearm
    camera and the thesis's acquisition program (:func:`acquire_stereo_pair`).
:mod:`~robostereo.robot.arms.sixaxis`
    A UR5-like six-axis arm (DH parameters, joint limits, inverse kinematics) and its
    wrist camera.

Imports: :mod:`robostereo.errors` and :mod:`robostereo.geometry` only; no other part of
:mod:`robostereo.robot`.
"""

from robostereo.robot.arms.acquisition import (
    CameraDevice,
    Robot,
    SimulatedCamera,
    StereoAcquisition,
    acquire_stereo_pair,
)
from robostereo.robot.arms.scara import (
    ADEPTONE_LIMITS,
    ADEPTONE_LINK1_MM,
    ADEPTONE_LINK2_MM,
    ADEPTONE_REPEATABILITY_MM,
    AdeptOne,
    CameraMount,
    Elbow,
    JointLimits,
    Joints,
)
from robostereo.robot.arms.sixaxis import (
    UR5_DH,
    UR5_LIMITS,
    WRIST_CAMERA,
    WRIST_HAND_EYE,
    DHLink,
    SixAxisArm,
)

__all__ = [
    "ADEPTONE_LIMITS",
    "ADEPTONE_LINK1_MM",
    "ADEPTONE_LINK2_MM",
    "ADEPTONE_REPEATABILITY_MM",
    "UR5_DH",
    "UR5_LIMITS",
    "WRIST_CAMERA",
    "WRIST_HAND_EYE",
    "AdeptOne",
    "CameraDevice",
    "CameraMount",
    "DHLink",
    "Elbow",
    "JointLimits",
    "Joints",
    "Robot",
    "SimulatedCamera",
    "SixAxisArm",
    "StereoAcquisition",
    "acquire_stereo_pair",
]
