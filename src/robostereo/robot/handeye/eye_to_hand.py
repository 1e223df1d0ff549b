"""Eye-to-hand calibration: a camera fixed in the cell, the board carried by the flange.

A camera (or a stereo rig's left camera) bolted in the robot's cell sees a board that
the gripper holds.  Its pose in the robot's base frame ``Z = T_base_camera`` is what
puts its points in the robot's frame (``robostereo rig --base-camera``); the board's
pose on the flange ``Y = T_flange_board`` comes with it.  With the flange poses
``F_i = T_base_flange`` and the board poses ``C_i = T_camera_board`` of every view,

    ``Z C_i = F_i Y``   (AX = ZB, the robot-world-hand-eye problem).

:func:`calibrate_eye_to_hand` solves it with the eye-in-hand machinery on the inverted
flange poses (:func:`~robostereo.robot.handeye.calibrate.solve_views`: closed form,
residual and plausibility checks, outlier views, the joint refinement of the
intrinsics, ``Z`` and ``Y`` over every corner's reprojection); :class:`EyeToHandCalibration`
is its result, written by :func:`~robostereo.robot.handeye.handeye_yaml.save_handeye_yaml`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import Any

from numpy.typing import ArrayLike

from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye.ax_xb import DEFAULT_METHOD
from robostereo.robot.handeye.boards import Board
from robostereo.robot.handeye.calibrate import EyeInHandCalibration, SolveMethod, solve_views
from robostereo.robot.handeye.refine import Tangential

__all__ = [
    "EyeToHandCalibration",
    "calibrate_eye_to_hand",
]


@dataclass(frozen=True, eq=False)
class EyeToHandCalibration(EyeInHandCalibration):
    """Result of :func:`calibrate_eye_to_hand`: the shared solve's result with its frames
    named for a fixed camera.

    The attributes are :class:`~robostereo.robot.handeye.calibrate.EyeInHandCalibration`'s
    (``board_poses`` are ``T_camera_board``; ``residuals`` those of ``A Z = Z B``, ``A =
    F_j F_i^-1``, ``B = C_j C_i^-1``; ``closed_form`` is ``Z`` of the closed form), where
    ``hand_eye`` is ``Z = T_base_camera`` and ``base_board`` is ``Y = T_flange_board``;
    :attr:`base_camera` and :attr:`flange_board` name them so.
    """

    @property
    def base_camera(self) -> SE3:
        """``Z = T_base_camera``, millimetres (jointly refined unless ``refine=False``)."""
        return self.hand_eye

    @property
    def flange_board(self) -> SE3:
        """``Y = T_flange_board``, millimetres."""
        return self.base_board

    @classmethod
    def from_solve(cls, cal: EyeInHandCalibration) -> EyeToHandCalibration:
        """:func:`~robostereo.robot.handeye.calibrate.solve_views`'s eye-to-hand result,
        its frames named."""
        return cls(**{f.name: getattr(cal, f.name) for f in fields(cal)})

    def to_dict(self) -> dict[str, Any]:
        """The ``cell.yaml`` mapping ``robostereo handeye --mode eye-to-hand`` writes:
        ``mode``, ``camera``, ``base_camera``, ``flange_board``, then the residuals as
        in the eye-in-hand file."""
        from robostereo.geometry.poses import pose_to_dict

        shared = super().to_dict()
        out: dict[str, Any] = {"mode": "eye-to-hand", "camera": shared.pop("camera"),
                               "base_camera": shared.pop("hand_eye"),
                               "flange_board": pose_to_dict(self.flange_board)}
        closed = shared.pop("hand_eye_closed_form", None)
        sigma = shared.pop("hand_eye_sigma", None)
        out.update(shared)
        if closed is not None:
            out["base_camera_closed_form"] = closed
        if sigma is not None:
            out["base_camera_sigma"] = sigma
        return out


def calibrate_eye_to_hand(
    images: Sequence[ArrayLike],
    flange_poses: Sequence[SE3],
    board: Board,
    *,
    pixel_pitch_mm: float = 0.01,
    grey_levels: int = 256,
    method: SolveMethod = DEFAULT_METHOD,
    names: Sequence[str] | None = None,
    fix_k3: bool = True,
    camera: Camera | None = None,
    refine: bool = True,
    reject_outliers: bool = False,
    source: str = "hand-eye views",
    tangential: Tangential = "test",
) -> EyeToHandCalibration:
    """Intrinsics, ``T_base_camera`` and ``T_flange_board`` from views of a carried board.

    Parameters
    ----------
    images : sequence of array_like, shape (H, W)
        Grey views of the board from the fixed camera (one size).
    flange_poses : sequence of SE3
        ``T_base_flange`` the robot reported at each view, millimetres.
    board : Chessboard or Charuco
        The board on the flange.
    pixel_pitch_mm, grey_levels, method, names, fix_k3, camera, refine, reject_outliers, source
    tangential
        As :func:`~robostereo.robot.handeye.calibrate.calibrate_eye_in_hand` (`method`:
        ``'park'``, ``'tsai'``, ``'daniilidis'``, ``'shah'`` or ``'li'``).

    Returns
    -------
    EyeToHandCalibration

    Raises
    ------
    InputError
        As :func:`~robostereo.robot.handeye.calibrate.calibrate_eye_in_hand`; eye-in-hand
        views (camera on the flange) are refused naming what they look like.

    Notes
    -----
    1. Board corners, :func:`cv2.calibrateCamera` (or the known `camera`) and per-view
       board poses ``C_i``, as eye-in-hand.
    2. With ``G_i = F_i^-1``: ``G_i^-1 Z C_i = Y`` for every view, the eye-in-hand
       equation with ``X = Z`` and ``W = Y``; the motions ``A = G_j^-1 G_i = F_j
       F_i^-1`` and ``B = C_j C_i^-1`` satisfy ``A Z = Z B``, solved by the closed
       forms (Park-Martin by default; OpenCV's Shah or Li AX = ZB on the absolute poses).
    3. The residual checks, outlier views and plausibility refusals of the eye-in-hand
       calibration, on these motions.
    4. Joint refinement of the intrinsics (unless known), ``Z`` and ``Y`` over every
       corner's reprojection ``u_ik = pi(K, d; Z^-1 F_i Y p_k)`` (:func:`~robostereo.
       robot.handeye.refine.refine_eye_in_hand` with ``G_i``), ``p1, p2`` held at 0
       where the views do not show them (`tangential`).

    References
    ----------
    H. Zhuang, Z. Roth, R. Sudhakar, "Simultaneous robot/world and tool/flange
    calibration by solving homogeneous transformation equations of the form AX = YB",
    IEEE Trans. Robotics and Automation 10(4), 1994;
    K. Koide, E. Menegatti, IEEE Robotics and Automation Letters 4(2), 2019 (the
    reprojection form for both modes).
    """
    cal = solve_views(images, flange_poses, board, mode="eye-to-hand",
                      pixel_pitch_mm=pixel_pitch_mm, grey_levels=grey_levels, method=method,
                      names=names, fix_k3=fix_k3, camera=camera, refine=refine,
                      reject_outliers=reject_outliers, source=source,
                      tangential=tangential)
    return EyeToHandCalibration.from_solve(cal)
