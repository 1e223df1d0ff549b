"""AX = ZB: the robot-world-hand-eye closed forms (OpenCV's), on absolute poses.

With the flange poses ``F_i = T_base_flange`` and the board poses ``C_i =
T_camera_board`` of every view, both calibrations have two unknown transforms:

* eye-in-hand (camera on the flange, board fixed): ``C_i = X^-1 F_i^-1 W`` with
  ``X = T_flange_camera`` and ``W = T_base_board``;
* eye-to-hand (camera fixed, board on the flange): ``C_i = Z^-1 F_i Y`` with
  ``Z = T_base_camera`` and ``Y = T_flange_board`` -- the same equation with ``F_i``
  inverted, which is how :func:`~robostereo.robot.handeye.calibrate.solve_views`
  treats it.

:func:`solve_ax_zb` solves for both unknowns at once with
:func:`cv2.calibrateRobotWorldHandEye` (Shah 2013, or Li, Wang and Wu 2010), written
for ``C_i = X^-1 G_i W`` with ``G_i`` the given "flange" poses' inverses.  The AX = XB
closed forms of :mod:`robostereo.robot.handeye.ax_xb` solve the pairwise motions
instead and give ``W`` as a mean afterwards.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import cv2
import numpy as np

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye.ax_xb import check_rotation_axes, motion_pairs

__all__ = [
    "ROBOT_WORLD_METHODS",
    "RobotWorldMethod",
    "solve_ax_zb",
]

RobotWorldMethod = Literal["shah", "li"]
ROBOT_WORLD_METHODS: tuple[str, ...] = ("shah", "li")
_CV_METHODS = {"shah": cv2.CALIB_ROBOT_WORLD_HAND_EYE_SHAH,
               "li": cv2.CALIB_ROBOT_WORLD_HAND_EYE_LI}


def solve_ax_zb(flange_poses: Sequence[SE3], board_poses: Sequence[SE3], *,
                method: RobotWorldMethod = "shah") -> tuple[SE3, SE3]:
    """Solve ``C_i = X^-1 F_i^-1 W`` for ``X`` and ``W`` (OpenCV's closed forms).

    Parameters
    ----------
    flange_poses : sequence of SE3
        ``F_i`` (``T_base_flange`` for eye-in-hand; their inverses for eye-to-hand), mm.
    board_poses : sequence of SE3
        ``C_i = T_camera_board`` of each view, mm.
    method : {'shah', 'li'}
        :data:`cv2.CALIB_ROBOT_WORLD_HAND_EYE_SHAH` or ``..._LI``.

    Returns
    -------
    X, W : SE3
        ``T_flange_camera`` and ``T_base_board`` (eye-in-hand), or ``T_base_camera``
        and ``T_flange_board`` (eye-to-hand, with the flange poses inverted).

    Raises
    ------
    InputError
        Unknown method, fewer than 3 views, rotations about one axis only.

    Notes
    -----
    OpenCV's form is ``T_c_w = T_c_g T_g_b T_b_w``: the board poses are ``world2cam``,
    ``F_i^-1`` is ``base2gripper``; ``X`` and ``W`` are the inverses of the returned
    ``gripper2cam`` and ``base2world`` transforms.

    References
    ----------
    M. Shah, "Solving the robot-world/hand-eye calibration problem using the Kronecker
    product", ASME J. Mechanisms and Robotics 5(3), 2013;
    A. Li, L. Wang, D. Wu, "Simultaneous robot-world and hand-eye calibration using
    dual-quaternions and Kronecker product", Int. J. Physical Sciences 5(10), 2010.

    Examples
    --------
    >>> X = SE3.from_rotvec([10.0, -5.0, 80.0], [0.2, -0.1, 0.3])
    >>> W = SE3.from_rotvec([400.0, 50.0, 0.0], [3.1, 0.0, 0.2])
    >>> F = [SE3.from_rotvec([300.0 + 20 * k, 10.0 * k, 400.0], [0.3 * k, 0.2 * k * k, -0.1])
    ...      for k in range(4)]
    >>> C = [X.inv() @ f.inv() @ W for f in F]
    >>> X2, W2 = solve_ax_zb(F, C)
    >>> [round(v, 6) for v in X.distance_to(X2) + W.distance_to(W2)]
    [0.0, 0.0, 0.0, 0.0]
    """
    if method not in _CV_METHODS:
        raise InputError(f"method must be one of {', '.join(ROBOT_WORLD_METHODS)}, got "
                         f"{method!r}")
    if len(flange_poses) != len(board_poses) or len(flange_poses) < 3:
        raise InputError(f"AX = ZB needs at least 3 views with a pose each, got "
                         f"{len(flange_poses)} and {len(board_poses)}")
    check_rotation_axes(motion_pairs(list(flange_poses), list(board_poses))[0])
    g = [f.inv() for f in flange_poses]
    r1, t1, r2, t2 = cv2.calibrateRobotWorldHandEye(
        [c.rotation for c in board_poses], [c.translation.reshape(3, 1) for c in board_poses],
        [x.rotation for x in g], [x.translation.reshape(3, 1) for x in g],
        method=_CV_METHODS[method])
    W = SE3(np.asarray(r1, dtype=np.float64), np.asarray(t1, dtype=np.float64).ravel()).inv()
    X = SE3(np.asarray(r2, dtype=np.float64), np.asarray(t2, dtype=np.float64).ravel()).inv()
    return X, W
