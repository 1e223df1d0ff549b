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

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye.ax_xb import DEFAULT_METHOD, HandEyeResiduals
from robostereo.robot.handeye.boards import Board
from robostereo.robot.handeye.calibrate import EyeInHandCalibration, SolveMethod, solve_views

__all__ = [
    "EyeToHandCalibration",
    "calibrate_eye_to_hand",
]


@dataclass(frozen=True, eq=False)
class EyeToHandCalibration:
    """Result of :func:`calibrate_eye_to_hand`.

    Attributes
    ----------
    camera : Camera
        Intrinsics and distortion (jointly refined, or the known ones).
    base_camera : SE3
        ``Z = T_base_camera``, millimetres (jointly refined unless ``refine=False``).
    flange_board : SE3
        ``Y = T_flange_board``, millimetres.
    method : str
        The closed form that started the refinement.
    reprojection_rms_px : float
    per_view_rms_px : ndarray, shape (N,)
    board_poses : tuple of SE3
        ``T_camera_board`` of each view.
    residuals : HandEyeResiduals
        ``A Z = Z B`` residuals of every pair of views (``A = F_j F_i^-1``,
        ``B = C_j C_i^-1``).
    names : tuple of str
    closed_form : SE3 or None
        ``Z`` of the closed form (None when not refined).
    corner_noise_px, predicted_translation_rms_mm : float
    outliers, rejected : tuple of str
        As :class:`~robostereo.robot.handeye.calibrate.EyeInHandCalibration`.
    """

    camera: Camera
    base_camera: SE3
    flange_board: SE3
    method: str
    reprojection_rms_px: float
    per_view_rms_px: NDArray[np.float64]
    board_poses: tuple[SE3, ...]
    residuals: HandEyeResiduals
    names: tuple[str, ...] = ()
    closed_form: SE3 | None = None
    corner_noise_px: float = math.nan
    predicted_translation_rms_mm: float = math.nan
    outliers: tuple[str, ...] = ()
    rejected: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        n = len(self.board_poses)
        if self.per_view_rms_px.shape != (n,) or self.residuals.rotation_deg.shape != (
                n * (n - 1) // 2,):
            raise InputError(f"per_view_rms_px and residuals must cover {n} views")
        if self.names and len(self.names) != n:
            raise InputError(f"names must be {n}, got {len(self.names)}")

    @classmethod
    def from_solve(cls, cal: EyeInHandCalibration) -> EyeToHandCalibration:
        """Name the frames of :func:`~robostereo.robot.handeye.calibrate.solve_views`'s
        eye-to-hand result (its ``hand_eye`` is ``Z``, its ``base_board`` ``Y``)."""
        return cls(camera=cal.camera, base_camera=cal.hand_eye, flange_board=cal.base_board,
                   method=cal.method, reprojection_rms_px=cal.reprojection_rms_px,
                   per_view_rms_px=cal.per_view_rms_px, board_poses=cal.board_poses,
                   residuals=cal.residuals, names=cal.names, closed_form=cal.closed_form,
                   corner_noise_px=cal.corner_noise_px,
                   predicted_translation_rms_mm=cal.predicted_translation_rms_mm,
                   outliers=cal.outliers, rejected=cal.rejected)

    @property
    def pairs(self) -> list[tuple[int, int]]:
        """The view pairs ``(i, j)``, ``i < j``, in the order of the residuals."""
        n = len(self.board_poses)
        return [(i, j) for i in range(n) for j in range(i + 1, n)]

    def to_dict(self) -> dict[str, Any]:
        """The ``cell.yaml`` mapping ``robostereo handeye --mode eye-to-hand`` writes:
        ``mode``, ``camera``, ``base_camera``, ``flange_board``, then the residuals as
        in the eye-in-hand file."""
        from robostereo.geometry.poses import pose_to_dict

        shared = EyeInHandCalibration(
            camera=self.camera, hand_eye=self.base_camera, method=self.method,
            reprojection_rms_px=self.reprojection_rms_px, per_view_rms_px=self.per_view_rms_px,
            board_poses=self.board_poses, residuals=self.residuals,
            base_board=self.flange_board, names=self.names, closed_form=self.closed_form,
            corner_noise_px=self.corner_noise_px,
            predicted_translation_rms_mm=self.predicted_translation_rms_mm,
            outliers=self.outliers, rejected=self.rejected).to_dict()
        out: dict[str, Any] = {"mode": "eye-to-hand", "camera": shared.pop("camera"),
                               "base_camera": shared.pop("hand_eye"),
                               "flange_board": pose_to_dict(self.flange_board)}
        closed = shared.pop("hand_eye_closed_form", None)
        out.update(shared)
        if closed is not None:
            out["base_camera_closed_form"] = closed
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
       robot.handeye.refine.refine_eye_in_hand` with ``G_i``).

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
                      reject_outliers=reject_outliers, source=source)
    return EyeToHandCalibration.from_solve(cal)
