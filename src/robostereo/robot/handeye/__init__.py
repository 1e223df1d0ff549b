"""Eye-in-hand calibration: boards, their views, the solve, the refinement, the checks, the file.

Modules
-------
:mod:`~robostereo.robot.handeye.boards`
    Calibration boards (chessboard, ChArUco), their detection, hand-eye views folders
    (``views.yaml``).
:mod:`~robostereo.robot.handeye.ax_xb`
    AX = XB: the motions of every pair of views and the closed forms (Tsai-Lenz,
    Park-Martin, Daniilidis) for ``T_flange_camera``; their residuals.
:mod:`~robostereo.robot.handeye.calibrate`
    :func:`calibrate_eye_in_hand`: ``calibrateCamera``, AX = XB and the joint
    refinement, with the residual and plausibility checks.
:mod:`~robostereo.robot.handeye.refine`
    The joint reprojection refinement of intrinsics, hand-eye transform and board pose.
:mod:`~robostereo.robot.handeye.checks`
    Residuals the corner noise can explain, views that stand out, implausible results.
:mod:`~robostereo.robot.handeye.handeye_yaml`
    The camera and hand-eye file ``robostereo handeye`` writes (``camera.yaml``).

Imports: :mod:`robostereo.errors`, :mod:`robostereo.geometry` and :mod:`robostereo.io`;
no other part of :mod:`robostereo.robot`.
"""

from robostereo.robot.handeye.ax_xb import (
    DEFAULT_METHOD,
    METHODS,
    HandEyeMethod,
    HandEyeResiduals,
    check_rotation_axes,
    handeye_residuals,
    motion_pairs,
    solve_ax_xb,
)
from robostereo.robot.handeye.boards import (
    MIN_CHARUCO_CORNERS,
    MIN_VIEWS,
    VIEWS_YAML,
    Board,
    Charuco,
    Chessboard,
    HandEyeViews,
    describe_board,
    detect_board,
    detect_chessboard,
    read_views,
    write_views,
)
from robostereo.robot.handeye.calibrate import (
    EyeInHandCalibration,
    calibrate_eye_in_hand,
)
from robostereo.robot.handeye.checks import (
    MAX_REPROJECTION_RMS_PX,
    MAX_ROTATION_RMS_DEG,
    OUTLIER_Z,
    TRANSLATION_FACTOR,
    TRANSLATION_FLOOR_MM,
    check_plausible,
    corner_noise_px,
    outlier_views,
    pose_covariances,
    predicted_pair_translation_mm,
    robust_z,
    view_scores,
)
from robostereo.robot.handeye.handeye_yaml import (
    load_handeye_yaml,
    save_handeye_yaml,
)
from robostereo.robot.handeye.refine import (
    RefinedHandEye,
    project_board,
    refine_eye_in_hand,
)

__all__ = [
    "DEFAULT_METHOD",
    "MAX_REPROJECTION_RMS_PX",
    "MAX_ROTATION_RMS_DEG",
    "METHODS",
    "MIN_CHARUCO_CORNERS",
    "MIN_VIEWS",
    "OUTLIER_Z",
    "TRANSLATION_FACTOR",
    "TRANSLATION_FLOOR_MM",
    "VIEWS_YAML",
    "Board",
    "Charuco",
    "Chessboard",
    "EyeInHandCalibration",
    "HandEyeMethod",
    "HandEyeResiduals",
    "HandEyeViews",
    "RefinedHandEye",
    "calibrate_eye_in_hand",
    "check_plausible",
    "check_rotation_axes",
    "corner_noise_px",
    "describe_board",
    "detect_board",
    "detect_chessboard",
    "handeye_residuals",
    "load_handeye_yaml",
    "motion_pairs",
    "outlier_views",
    "pose_covariances",
    "predicted_pair_translation_mm",
    "project_board",
    "read_views",
    "refine_eye_in_hand",
    "robust_z",
    "save_handeye_yaml",
    "solve_ax_xb",
    "view_scores",
    "write_views",
]
