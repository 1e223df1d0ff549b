"""Hand-eye calibration (eye-in-hand and eye-to-hand): boards, views, solve, checks, file.

Modules
-------
:mod:`~robostereo.robot.handeye.boards`
    Calibration boards (chessboard, ChArUco), their corners in a view, hand-eye views
    folders (``views.yaml``).
:mod:`~robostereo.robot.handeye.charuco`
    ChArUco boards: dictionaries, detection with corner ids (partial views), sub-pixel
    corners that ignore the markers.
:mod:`~robostereo.robot.handeye.corner_refinement`
    Sub-pixel corners of either board by the gradients' orthogonality, weighted in each
    corner's own squares.
:mod:`~robostereo.robot.handeye.ax_xb`
    AX = XB: the motions of every pair of views and the closed forms (Tsai-Lenz,
    Park-Martin, Daniilidis) for ``T_flange_camera``; their residuals.
:mod:`~robostereo.robot.handeye.ax_zb`
    AX = ZB: OpenCV's robot-world-hand-eye closed forms (Shah, Li) on absolute poses.
:mod:`~robostereo.robot.handeye.calibrate`
    :func:`calibrate_eye_in_hand`: ``calibrateCamera``, AX = XB and the joint
    refinement, with the residual and plausibility checks (:func:`solve_views`, the
    solve both modes share).
:mod:`~robostereo.robot.handeye.eye_to_hand`
    :func:`calibrate_eye_to_hand`: a fixed camera, the board on the flange
    (``T_base_camera`` and ``T_flange_board``).
:mod:`~robostereo.robot.handeye.refine`
    The joint reprojection refinement of intrinsics, hand-eye transform and board pose;
    the corners' model and how well the views pin the transform.
:mod:`~robostereo.robot.handeye.view_advice`
    Where to put more views: the transform's spread with four tilted views added, and
    the flange poses that place them.
:mod:`~robostereo.robot.handeye.checks`
    Residuals the corner noise can explain, views that stand out, implausible results.
:mod:`~robostereo.robot.handeye.handeye_yaml`
    The camera and hand-eye file ``robostereo handeye`` writes (``camera.yaml``, or
    ``cell.yaml`` for eye-to-hand).

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
from robostereo.robot.handeye.ax_zb import (
    ROBOT_WORLD_METHODS,
    RobotWorldMethod,
    solve_ax_zb,
)
from robostereo.robot.handeye.boards import (
    MIN_VIEWS,
    VIEW_MODES,
    VIEWS_YAML,
    Board,
    Chessboard,
    HandEyeViews,
    describe_board,
    detect_board,
    detect_chessboard,
    read_views,
    view_corners,
    write_views,
)
from robostereo.robot.handeye.calibrate import (
    ALL_METHODS,
    EyeInHandCalibration,
    HandEyeMode,
    SolveMethod,
    calibrate_eye_in_hand,
    solve_views,
)
from robostereo.robot.handeye.charuco import (
    DICTIONARIES,
    MIN_CHARUCO_CORNERS,
    Charuco,
    CharucoCorners,
    charuco_view_problem,
    detect_charuco,
    dictionary_name,
    refine_charuco_corners,
)
from robostereo.robot.handeye.checks import (
    INTRINSICS_FLOORS,
    INTRINSICS_SIGMAS,
    MAX_REPROJECTION_RMS_PX,
    MAX_ROTATION_RMS_DEG,
    OUTLIER_Z,
    TRANSLATION_FACTOR,
    TRANSLATION_FLOOR_MM,
    check_intrinsics,
    check_plausible,
    corner_noise_px,
    outlier_views,
    pose_covariances,
    predicted_pair_translation_mm,
    robust_z,
    view_scores,
)
from robostereo.robot.handeye.corner_refinement import refine_board_corners
from robostereo.robot.handeye.eye_to_hand import (
    EyeToHandCalibration,
    calibrate_eye_to_hand,
)
from robostereo.robot.handeye.handeye_yaml import (
    handeye_yaml_text,
    load_base_camera_yaml,
    load_handeye_with_sigma,
    load_handeye_yaml,
    save_handeye_yaml,
    view_advice_text,
)
from robostereo.robot.handeye.refine import (
    INTRINSICS,
    TANGENTIAL_CHOICES,
    TANGENTIAL_LEVEL,
    CornerModel,
    RefinedHandEye,
    Tangential,
    free_intrinsics,
    hand_eye_sigma,
    project_board,
    refine_eye_in_hand,
    tangential_chi2,
    tangential_threshold,
)
from robostereo.robot.handeye.view_advice import ADVICE_TILTS_DEG, ViewAdvice, advise_views

__all__ = [
    "ADVICE_TILTS_DEG",
    "ALL_METHODS",
    "DEFAULT_METHOD",
    "DICTIONARIES",
    "INTRINSICS",
    "INTRINSICS_FLOORS",
    "INTRINSICS_SIGMAS",
    "MAX_REPROJECTION_RMS_PX",
    "MAX_ROTATION_RMS_DEG",
    "METHODS",
    "MIN_CHARUCO_CORNERS",
    "MIN_VIEWS",
    "OUTLIER_Z",
    "ROBOT_WORLD_METHODS",
    "TANGENTIAL_CHOICES",
    "TANGENTIAL_LEVEL",
    "TRANSLATION_FACTOR",
    "TRANSLATION_FLOOR_MM",
    "VIEWS_YAML",
    "VIEW_MODES",
    "Board",
    "Charuco",
    "CharucoCorners",
    "Chessboard",
    "CornerModel",
    "EyeInHandCalibration",
    "EyeToHandCalibration",
    "HandEyeMethod",
    "HandEyeMode",
    "HandEyeResiduals",
    "HandEyeViews",
    "RefinedHandEye",
    "RobotWorldMethod",
    "SolveMethod",
    "Tangential",
    "ViewAdvice",
    "advise_views",
    "calibrate_eye_in_hand",
    "calibrate_eye_to_hand",
    "charuco_view_problem",
    "check_intrinsics",
    "check_plausible",
    "check_rotation_axes",
    "corner_noise_px",
    "describe_board",
    "detect_board",
    "detect_charuco",
    "detect_chessboard",
    "dictionary_name",
    "free_intrinsics",
    "hand_eye_sigma",
    "handeye_residuals",
    "handeye_yaml_text",
    "load_base_camera_yaml",
    "load_handeye_with_sigma",
    "load_handeye_yaml",
    "motion_pairs",
    "outlier_views",
    "pose_covariances",
    "predicted_pair_translation_mm",
    "project_board",
    "read_views",
    "refine_board_corners",
    "refine_charuco_corners",
    "refine_eye_in_hand",
    "robust_z",
    "save_handeye_yaml",
    "solve_ax_xb",
    "solve_ax_zb",
    "solve_views",
    "tangential_chi2",
    "tangential_threshold",
    "view_advice_text",
    "view_corners",
    "view_scores",
    "write_views",
]
