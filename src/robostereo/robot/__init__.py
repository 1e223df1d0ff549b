"""The robot side of robostereo: arms, captures, locating, hand-eye, planning, simulators.

Sub-packages, lowest first (each imports only the ones before it, and the library's
lower layers: errors, geometry, io, matcher, simulation):

:mod:`~robostereo.robot.arms`
    The AdeptOne SCARA (section 4.1) and a UR5-like six-axis arm; the :class:`Robot`
    and :class:`CameraDevice` protocols and the thesis's acquisition program.
:mod:`~robostereo.robot.capture`
    Two views of a camera on an arm: capture folders and :func:`locate_capture`
    (rectify, match, eq. 6-9 in the robot's world frame).
:mod:`~robostereo.robot.handeye`
    Eye-in-hand calibration: boards, views folders, AX = XB, the joint refinement,
    its checks and the camera file it writes.
:mod:`~robostereo.robot.views`
    N viewpoints: N-view captures and folders, :func:`locate_views`, the pose check.
:mod:`~robostereo.robot.planning`
    Eq. 9 inverted for the baseline (or N views' span), the baseline direction, fusing
    two captures (it imports :mod:`~robostereo.robot.views`).
:mod:`~robostereo.robot.importers`
    Other tools' cameras and images (IDR / NeuS, MVSNet, COLMAP) to N-view capture
    folders (imports views).
:mod:`~robostereo.robot.simulated`
    The simulated AdeptOne rig, the six-axis experiments, N simulated views and their
    truth (imports every other part; nothing of the robot side imports it).

Poses (:class:`~robostereo.geometry.poses.SE3`, the SCARA
:class:`~robostereo.geometry.poses.Pose`) and the rectification of two general poses
live in :mod:`robostereo.geometry`.

The names of :mod:`robostereo.robot.arms.scara` and
:mod:`robostereo.robot.arms.acquisition` (the old ``robostereo.robot.scara``) are
re-exported here, so ``from robostereo.robot import AdeptOne`` works as before the
sub-packages existed.
"""

from robostereo.robot.arms import acquisition, scara
from robostereo.robot.arms.acquisition import *  # noqa: F403 - acquisition.__all__
from robostereo.robot.arms.scara import *  # noqa: F403 - the names of scara.__all__

__all__ = [*scara.__all__, *acquisition.__all__]
