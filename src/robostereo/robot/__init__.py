"""The robot side of robostereo: arm models, camera poses, capture folders.

Submodules
----------
:mod:`~robostereo.robot.scara`
    The seed's AdeptOne SCARA (seed 4.1), the :class:`Robot` and :class:`CameraDevice`
    protocols, the simulated camera and the seed's acquisition program.
:mod:`~robostereo.robot.capture`
    Capture folders and locating object points in the robot's world frame.

The names of :mod:`robostereo.robot.scara` are re-exported here, so
``from robostereo.robot import AdeptOne`` works as before the subpackage existed.
"""

from robostereo.robot.scara import (
    ADEPTONE_LIMITS,
    ADEPTONE_LINK1_MM,
    ADEPTONE_LINK2_MM,
    ADEPTONE_REPEATABILITY_MM,
    AdeptOne,
    CameraDevice,
    CameraMount,
    Elbow,
    JointLimits,
    Joints,
    Robot,
    SimulatedCamera,
    StereoAcquisition,
    acquire_stereo_pair,
)

__all__ = [
    "ADEPTONE_LIMITS",
    "ADEPTONE_LINK1_MM",
    "ADEPTONE_LINK2_MM",
    "ADEPTONE_REPEATABILITY_MM",
    "AdeptOne",
    "CameraDevice",
    "CameraMount",
    "Elbow",
    "JointLimits",
    "Joints",
    "Robot",
    "SimulatedCamera",
    "StereoAcquisition",
    "acquire_stereo_pair",
]
