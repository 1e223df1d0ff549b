"""Simulated hand-eye views from the six-axis arm: a calibration board on the table.

:func:`simulate_handeye_views` renders a chessboard (:data:`BOARD`, or a ChArUco board)
lying on the table (:func:`board_scene`) from tilted views of the UR5-like arm's wrist
camera (:class:`~robostereo.robot.arms.sixaxis.SixAxisArm`) and records the flange pose
of each: a hand-eye views folder, with the truth, for
:func:`~robostereo.robot.handeye.calibrate.calibrate_eye_in_hand`.  Rendered as the
six-axis rig's captures (:func:`~robostereo.robot.simulated.sixaxis_rig.render_six_axis`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, UnreachablePoseError
from robostereo.geometry.camera import Camera, camera_to_dict
from robostereo.geometry.poses import SE3, pose_to_dict
from robostereo.robot.arms.sixaxis import WRIST_CAMERA, WRIST_HAND_EYE, SixAxisArm
from robostereo.robot.handeye import Board, Chessboard, HandEyeViews
from robostereo.robot.simulated.sixaxis_rig import render_six_axis
from robostereo.simulation import Checkerboard, ImagePlane, Scene, TablePlane

__all__ = [
    "BOARD",
    "board_frame",
    "board_scene",
    "simulate_handeye_views",
]

BOARD = Chessboard(inner_corners=(9, 6), square_mm=12.0)
"""The simulated calibration board: 9 x 6 inner corners, 12 mm squares."""
BOARD_ORIGIN_XY = (300.0, 150.0)


def board_scene(
    *, board: Board = BOARD, origin_xy: tuple[float, float] = BOARD_ORIGIN_XY, yaw: float = 0.0
) -> tuple[Scene, Checkerboard | ImagePlane]:
    """A calibration board (2 mm thick) lying on the table, and the board primitive.

    A :class:`Chessboard` is drawn analytically (:class:`Checkerboard`), a
    :class:`Charuco` as its OpenCV image printed at 300 px a square (25 px/mm for 12 mm
    squares; :class:`ImagePlane`).
    """
    cb: Checkerboard | ImagePlane
    if isinstance(board, Chessboard):
        cb = Checkerboard(origin=origin_xy, z=2.0, inner_corners=board.inner_corners,
                          square_mm=board.square_mm, yaw=yaw)
    else:
        px_per_mm = 300.0 / board.square_mm
        img = board.image(px_per_mm).astype(np.float64) / 255.0
        cb = ImagePlane(origin=origin_xy, image=0.08 + 0.77 * img, mm_per_px=1.0 / px_per_mm,
                        z=2.0, yaw=yaw)
    return Scene((TablePlane(z=0.0, albedo=0.3), cb), light_direction=(0.2, -0.1, 1.0)), cb


def board_frame(board: Board) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Board-frame centre (3,) and outline corners (4, 3) that must be in view."""
    q = board.square_mm
    if isinstance(board, Chessboard):
        c, r = board.inner_corners
        x0, x1, y0, y1 = -q, c * q, -q, r * q
    else:
        c, r = board.squares
        x0, x1, y0, y1 = 0.0, c * q, 0.0, r * q
    centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2, 0.0])
    outline = np.array([[x0, y0, 0.0], [x1, y0, 0.0], [x0, y1, 0.0], [x1, y1, 0.0]])
    return centre, outline


def simulate_handeye_views(
    *,
    views: int = 15,
    seed: int = 0,
    arm: SixAxisArm | None = None,
    camera: Camera = WRIST_CAMERA,
    hand_eye: SE3 = WRIST_HAND_EYE,
    board: Board = BOARD,
) -> tuple[HandEyeViews, dict[str, Any]]:
    """Views of a chessboard on the table from the six-axis arm's wrist camera.

    Parameters
    ----------
    views : int
        Number of views (>= 3).
    seed : int
        Seed of the viewpoints and the sensor noise.
    arm, camera, hand_eye, board
        The simulated arm (default a UR5), wrist camera, true ``T_flange_camera``
        and board (a :class:`Chessboard` or a :class:`Charuco`).

    Returns
    -------
    views : HandEyeViews
        Images and the flange poses the arm reports.
    truth : dict
        ``camera`` (mapping), ``hand_eye`` and ``base_board`` (pose mappings), in the
        file forms of :mod:`robostereo.geometry.poses`.

    Notes
    -----
    The camera looks at points within 40 mm of the board centre from 330-430 mm away,
    tilted 12-38 degrees from vertical at azimuths spread round the board, turned up to
    30 degrees about its axis (the board whole in the view, anywhere in the image), so
    that the flange rotates about many axes.  Each camera pose is reached by
    inverse kinematics (``flange = camera @ hand_eye^-1``).
    """
    if isinstance(views, bool) or int(views) != views or views < 3:
        raise InputError(f"views must be an integer >= 3, got {views}")
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise InputError(f"seed must be a whole number >= 0, got {seed}")
    a = arm or SixAxisArm()
    rng = np.random.default_rng([int(seed), 9])
    scene, cb = board_scene(board=board)
    centre_b, outline_b = board_frame(board)
    centre = cb.pose.apply(centre_b)
    outline = cb.pose.apply(outline_b)
    images, poses, names = [], [], []
    q = None
    attempts = 0
    while len(images) < views:
        attempts += 1
        if attempts > 4 * views:
            raise InputError(f"could not place {views} hand-eye views within the arm's reach")
        i = len(images)
        az = 2 * math.pi * i / views + rng.uniform(-0.3, 0.3)
        tilt = math.radians(rng.uniform(12.0, 38.0))
        dist = rng.uniform(330.0, 430.0)
        target = centre + np.array([rng.uniform(-40, 40), rng.uniform(-28, 28), 0.0])
        eye = target + dist * np.array([math.sin(tilt) * math.cos(az),
                                        math.sin(tilt) * math.sin(az), math.cos(tilt)])
        cam_pose = SE3.look_at(eye, target)
        roll = SE3.from_rotvec([0, 0, 0], [0, 0, math.radians(rng.uniform(-30, 30))])
        cam_pose = cam_pose @ roll
        uv, _ = camera.project(outline, cam_pose)
        w, h = camera.image_size
        if not ((uv[:, 0] > 8) & (uv[:, 0] < w - 9) & (uv[:, 1] > 8) & (uv[:, 1] < h - 9)).all():
            continue  # the board (with its margin) must be whole in the view
        try:
            q, flange = a.move_camera(cam_pose, hand_eye, q0=q)
        except UnreachablePoseError:
            continue  # draw another viewpoint
        images.append(render_six_axis(scene, camera, flange @ hand_eye, rng).image)
        poses.append(flange)
        names.append(f"view_{i:02d}.png")
    truth = {
        "camera": camera_to_dict(camera),
        "hand_eye": pose_to_dict(hand_eye),
        "base_board": pose_to_dict(cb.pose),
        "units": "mm",
    }
    v = HandEyeViews(images=tuple(images), flange_poses=tuple(poses), names=tuple(names),
                     board=board, pixel_pitch_mm=camera.pixel_pitch_mm[0],
                     grey_levels=camera.grey_levels)
    return v, truth
