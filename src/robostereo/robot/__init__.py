"""The robot side of robostereo: arm models, camera poses, captures, the simulated rigs.

Submodules
----------
:mod:`~robostereo.robot.scara`
    The thesis's AdeptOne SCARA (section 4.1), the :class:`Robot` and
    :class:`CameraDevice` protocols, the simulated camera and the thesis's acquisition
    program.
:mod:`~robostereo.robot.capture_folder`
    :class:`~robostereo.robot.capture_folder.Capture` (two grabbed views, the camera and
    the poses) and capture folders (``capture.yaml``).
:mod:`~robostereo.robot.capture`
    Locating object points of a capture in the robot's world frame (rectify, match,
    eq. 6-9); re-exports the capture folder names.
:mod:`~robostereo.robot.handeye_views`
    Calibration boards (chessboard, ChArUco), their detection, hand-eye views folders.
:mod:`~robostereo.robot.handeye`
    Eye-in-hand calibration: ``calibrateCamera``, AX = XB and the joint refinement;
    re-exports the names of :mod:`~robostereo.robot.handeye_views`.
:mod:`~robostereo.robot.handeye_refine`
    The joint refinement of intrinsics, hand-eye transform and board pose on the corners.
:mod:`~robostereo.robot.handeye_checks`
    The residuals the corner noise explains, views that stand out, implausible results.
:mod:`~robostereo.robot.sixaxis`
    A UR5-like six-axis arm (DH, joint limits, inverse kinematics) and its wrist camera.
:mod:`~robostereo.robot.planning`
    Eq. 9 inverted for the baseline, the baseline direction, fusing two captures.
:mod:`~robostereo.robot.simulated_scara`
    The simulated AdeptOne rig: the thesis's set-up (:class:`RigSetup`), its block and
    hub-pulley scenes and its captures (:func:`simulate_capture`).
:mod:`~robostereo.robot.simulated`
    The simulated six-axis experiments (hand-eye views, tilted captures, the demo) and
    the block fused from two baselines.
:mod:`~robostereo.robot.views`
    :class:`~robostereo.robot.views.ViewsCapture` (N grabbed views of one camera and
    their poses) and the viewpoint patterns (line, cross, arc).
:mod:`~robostereo.robot.views_folder`
    N-view capture folders: ``capture.yaml`` with a list of views.
:mod:`~robostereo.robot.multiview`
    Locating edge points from N views: each view the reference in turn, the bound of
    eq. 9 generalised; :mod:`~robostereo.robot.multiview_search` holds its stages and
    :mod:`~robostereo.robot.multiview_kernels` their numba kernels.
:mod:`~robostereo.robot.simulated_views`
    The simulated robots grabbing N views in a pattern.
:mod:`~robostereo.robot.views_truth`
    N-view located points scored against a simulated capture's truth.

Poses (:class:`~robostereo.geometry.poses.SE3`, the SCARA
:class:`~robostereo.geometry.poses.Pose`) and the rectification of two general poses
live in :mod:`robostereo.geometry`.

The names of :mod:`robostereo.robot.scara` are re-exported here, so
``from robostereo.robot import AdeptOne`` works as before the subpackage existed.
"""

from robostereo.robot import scara
from robostereo.robot.scara import *  # noqa: F403 - the names of scara.__all__

__all__ = list(scara.__all__)
