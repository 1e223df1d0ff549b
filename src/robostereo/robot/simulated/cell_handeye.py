"""Simulated eye-to-hand views: a board on the six-axis arm's flange, a camera in the cell.

:func:`simulate_eye_to_hand_views` moves a calibration board that the UR5-like arm
(:class:`~robostereo.robot.arms.sixaxis.SixAxisArm`) carries on its flange
(:data:`FLANGE_BOARD`) through the view of a camera fixed in the cell
(:data:`CELL_CAMERA` at :data:`BASE_CAMERA`), and records the flange pose of each view:
an eye-to-hand views folder, with the truth, for
:func:`~robostereo.robot.handeye.eye_to_hand.calibrate_eye_to_hand`.  Rendered as the
six-axis simulations are (:func:`~robostereo.robot.simulated.sixaxis_rig.render_six_axis`),
in the board's frame: the board lies on its backing plate
(:func:`~robostereo.robot.simulated.sixaxis_handeye.board_scene`) and the camera is
placed where it sees the board from.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from robostereo.errors import InputError, UnreachablePoseError
from robostereo.geometry.camera import Camera, camera_to_dict
from robostereo.geometry.poses import SE3, pose_to_dict
from robostereo.robot.arms.sixaxis import SixAxisArm
from robostereo.robot.handeye import (
    Board,
    Charuco,
    Chessboard,
    HandEyeViews,
    calibrate_eye_to_hand,
)
from robostereo.robot.simulated.sixaxis_handeye import board_frame, board_scene
from robostereo.robot.simulated.sixaxis_rig import render_six_axis

__all__ = [
    "BASE_CAMERA",
    "CELL_BOARD",
    "CELL_CAMERA",
    "CELL_CHARUCO",
    "FLANGE_BOARD",
    "eye_to_hand_session",
    "simulate_eye_to_hand_views",
]

CELL_CAMERA = Camera(
    focal_length_mm=4.0, pixel_pitch_mm=(0.005, 0.005), image_size=(640, 480),
    principal_point=(322.0, 241.5), grey_levels=256, distortion=(-0.1, 0.0, 0.0, 0.0, 0.0),
)
"""The simulated cell camera: 640 x 480 px, 4 mm lens, 5 um pixels (f = 800 px, a 44 x 33
degree view), 8-bit grey, barrel distortion k1 = -0.1."""

BASE_CAMERA = SE3.look_at([420.0, -520.0, 720.0], [430.0, 120.0, 250.0])
"""True ``T_base_camera``: fixed above and beside the working volume, 700-800 mm from
the arm's base, looking obliquely down at the board's working volume."""

FLANGE_BOARD = SE3.from_rotvec([-135.0, -90.0, 45.0], [0.0, 0.0, 0.35]) @ SE3.from_rotvec(
    [0.0, 0.0, 0.0], [math.pi, 0.0, 0.0])
"""True ``T_flange_board``: the board 45 mm out along the tool axis, facing along it
(its z, into the board, back towards the flange), its centre near the tool axis and
turned 20 degrees about it."""

CELL_BOARD = Chessboard(inner_corners=(9, 6), square_mm=30.0)
"""The carried board: 9 x 6 inner corners, 30 mm squares (300 x 210 mm)."""

CELL_CHARUCO = Charuco(squares=(10, 7), square_mm=30.0, marker_mm=22.0,
                       dictionary="DICT_5X5_100")
"""The carried ChArUco board (``simulate-handeye --mode eye-to-hand --board charuco``):
10 x 7 squares of 30 mm (the chessboard's 300 x 210 mm), 22 mm markers."""


def simulate_eye_to_hand_views(
    *,
    views: int = 14,
    seed: int = 0,
    arm: SixAxisArm | None = None,
    camera: Camera = CELL_CAMERA,
    base_camera: SE3 = BASE_CAMERA,
    flange_board: SE3 = FLANGE_BOARD,
    board: Board = CELL_BOARD,
) -> tuple[HandEyeViews, dict[str, Any]]:
    """Views of a board on the six-axis arm's flange from a camera fixed in the cell.

    Parameters
    ----------
    views : int
        Number of views (>= 3).
    seed : int
        Seed of the board poses and the sensor noise.
    arm, camera, base_camera, flange_board, board
        The simulated arm (default a UR5), the fixed camera and its true
        ``T_base_camera``, the true ``T_flange_board`` and the board
        (:data:`CELL_BOARD`, or a ChArUco board such as :data:`CELL_CHARUCO`).

    Returns
    -------
    views : HandEyeViews
        Images and the flange poses the arm reports (``mode='eye-to-hand'``).
    truth : dict
        ``camera`` (mapping), ``base_camera`` and ``flange_board`` (pose mappings).

    Notes
    -----
    The board centre is drawn within +-150 mm across and +-110 mm up and down the
    image of a point on the optical axis, 650-750 mm from the camera; its face is
    turned 15-45 degrees from the line of sight at azimuths spread round, and up to 30
    degrees about its normal; it must be whole in the view and the flange pose
    ``T_base_board flange_board^-1`` within the arm's reach (inverse kinematics), or
    another pose is drawn.
    """
    if isinstance(views, bool) or int(views) != views or views < 3:
        raise InputError(f"views must be an integer >= 3, got {views}")
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise InputError(f"seed must be a whole number >= 0, got {seed}")
    a = arm or SixAxisArm()
    rng = np.random.default_rng([int(seed), 37])
    scene, cb = board_scene(board=board)
    centre_b, outline_b = board_frame(board)
    w, h = camera.image_size
    images, poses, names = [], [], []
    q = None
    attempts = 0
    while len(images) < views:
        attempts += 1
        if attempts > 20 * views:
            raise InputError(f"could not place {views} eye-to-hand views within the arm's "
                             "reach and the camera's view")
        k = len(images)
        c = np.array([rng.uniform(-150, 150), rng.uniform(-110, 110), rng.uniform(650, 750)])
        az = 2 * math.pi * k / views + rng.uniform(-0.3, 0.3)
        tilt = math.radians(rng.uniform(15.0, 45.0))
        z = Rotation.from_rotvec(tilt * np.array([math.cos(az), math.sin(az), 0.0])).apply(
            c / np.linalg.norm(c))
        x = np.cross([0.0, 1.0, 0.0], z)
        x /= np.linalg.norm(x)
        R = np.column_stack([x, np.cross(z, x), z]) @ Rotation.from_rotvec(
            [0.0, 0.0, math.radians(rng.uniform(-30, 30))]).as_matrix()
        board_in_camera = SE3(R, c - R @ centre_b)
        uv, _ = camera.project(board_in_camera.apply(outline_b), SE3.identity())
        if not ((uv[:, 0] > 8) & (uv[:, 0] < w - 9) & (uv[:, 1] > 8) & (uv[:, 1] < h - 9)).all():
            continue  # the board (with its margin) must be whole in the view
        try:
            q, flange = a.move_camera(base_camera @ board_in_camera, flange_board, q0=q)
        except UnreachablePoseError:
            continue
        # render in the board's frame: the camera where the board sees it from
        seen_from = cb.pose @ (flange @ flange_board).inv() @ base_camera
        images.append(render_six_axis(scene, camera, seen_from, rng).image)
        poses.append(flange)
        names.append(f"view_{k:02d}.png")
    truth = {
        "camera": camera_to_dict(camera),
        "base_camera": pose_to_dict(base_camera),
        "flange_board": pose_to_dict(flange_board),
        "units": "mm",
    }
    v = HandEyeViews(images=tuple(images), flange_poses=tuple(poses), names=tuple(names),
                     board=board, pixel_pitch_mm=camera.pixel_pitch_mm[0],
                     grey_levels=camera.grey_levels, mode="eye-to-hand")
    return v, truth


def eye_to_hand_session(*, views: int = 14, seed: int = 0) -> dict[str, float]:
    """A simulated eye-to-hand calibration against its truth (the six-axis demo's line).

    :func:`simulate_eye_to_hand_views` with the chessboard, then
    :func:`~robostereo.robot.handeye.calibrate_eye_to_hand` with the intrinsics free.

    Returns
    -------
    dict
        ``views``; ``base_camera_mm`` / ``base_camera_deg`` and ``flange_board_mm`` /
        ``flange_board_deg``: how far the estimated ``T_base_camera`` and
        ``T_flange_board`` lie from the truth; ``reprojection_rms_px`` (rounded as the
        demo's other figures).
    """
    v, _ = simulate_eye_to_hand_views(views=views, seed=seed)
    cal = calibrate_eye_to_hand(v.images, v.flange_poses, v.board,
                                pixel_pitch_mm=v.pixel_pitch_mm)
    t, r = BASE_CAMERA.distance_to(cal.base_camera)
    tb, rb = FLANGE_BOARD.distance_to(cal.flange_board)
    return {"views": views, "base_camera_mm": round(float(t), 4),
            "base_camera_deg": round(math.degrees(r), 5),
            "flange_board_mm": round(float(tb), 4),
            "flange_board_deg": round(math.degrees(rb), 5),
            "reprojection_rms_px": round(float(cal.reprojection_rms_px), 3)}
