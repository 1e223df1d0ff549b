"""The robot side of robostereo: arm models, camera poses, capture folders.

Submodules
----------
:mod:`~robostereo.robot.scara`
    The seed's AdeptOne SCARA (seed 4.1), the :class:`Robot` and :class:`CameraDevice`
    protocols, the simulated camera and the seed's acquisition program.
:mod:`~robostereo.robot.capture`
    Capture folders and locating object points in the robot's world frame.
:mod:`~robostereo.robot.poses`
    :class:`~robostereo.robot.poses.SE3` rigid transforms (6-DoF poses) and their file
    forms (matrix, quaternion, rotation vector, ROS, the SCARA form).
:mod:`~robostereo.robot.geometry`
    Rectification of two general poses (OpenCV ``stereoRectify`` with distortion).
:mod:`~robostereo.robot.handeye`
    Eye-in-hand calibration: chessboard views, ``calibrateCamera``, AX = XB.
:mod:`~robostereo.robot.sixaxis`
    A UR5-like six-axis arm (DH, joint limits, inverse kinematics) and its wrist camera.
:mod:`~robostereo.robot.planning`
    Eq. 9 inverted for the baseline, the baseline direction, fusing two captures.
:mod:`~robostereo.robot.simulated`
    The simulated six-axis experiments (hand-eye views, tilted captures, the demo).

The names of :mod:`robostereo.robot.scara` are re-exported here, so
``from robostereo.robot import AdeptOne`` works as before the subpackage existed.
"""

from robostereo.robot import scara
from robostereo.robot.scara import *  # noqa: F403 - the names of scara.__all__

__all__ = list(scara.__all__)
