"""A small chessboard renderer of the tests' own, independent of robostereo.simulation.

Pinhole camera with one radial distortion term ``k1`` (OpenCV's model), each output
pixel antialiased by supersampling: every sub-sample's distorted position is
undistorted (fixed-point iteration), its ray cast into the board plane and coloured by
the parity of the square it hits.  Flange poses come from camera poses spread round the
board (tilts, azimuths, turns about the optical axis) through a known hand-eye
transform, as a six-axis arm's wrist camera would see it.  Used to check the hand-eye
calibration on data the project's simulator did not make.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from robostereo.geometry.poses import SE3

WIDTH, HEIGHT = 640, 480
FOCAL_PX = 800.0
K1 = -0.1
X_TRUE = SE3.from_rotvec([25.0, -40.0, 62.0], [0.05, -0.08, 1.1])
"""The true ``T_flange_camera`` of the renders."""
BASE_BOARD = SE3.from_rotvec([450.0, 60.0, 5.0], [0.02, -0.01, 0.4])
"""The true ``T_base_board`` (board frame: origin at the first inner corner)."""


@dataclass(frozen=True)
class Renders:
    images: tuple[np.ndarray, ...]
    flange_poses: tuple[SE3, ...]
    inner_corners: tuple[int, int]
    square_mm: float


def _undistort(xd: np.ndarray, yd: np.ndarray, k1: float) -> tuple[np.ndarray, np.ndarray]:
    x, y = xd.copy(), yd.copy()
    for _ in range(6):
        f = 1.0 + k1 * (x * x + y * y)
        x, y = xd / f, yd / f
    return x, y


def _project(points_cam: np.ndarray, k1: float) -> np.ndarray:
    x = points_cam[:, 0] / points_cam[:, 2]
    y = points_cam[:, 1] / points_cam[:, 2]
    f = 1.0 + k1 * (x * x + y * y)
    return np.column_stack([FOCAL_PX * x * f + WIDTH / 2, FOCAL_PX * y * f + HEIGHT / 2])


def render_board(cam_in_board: SE3, inner_corners: tuple[int, int], square_mm: float, *,
                 k1: float = K1, supersample: int = 3, noise: float = 1.5,
                 rng: np.random.Generator | None = None) -> np.ndarray:
    """A grey uint8 view (HEIGHT, WIDTH) of the board from ``T_board_camera``."""
    cols, rows = inner_corners
    img = np.full((HEIGHT, WIDTH), 110.0)
    # the board and its light margin (one square) bound the pixels to render
    m = square_mm
    outline = np.array([[-2 * m, -2 * m, 0], [(cols + 1) * m, -2 * m, 0],
                        [-2 * m, (rows + 1) * m, 0], [(cols + 1) * m, (rows + 1) * m, 0]])
    uv = _project(cam_in_board.inv().apply(outline), k1)
    u0, v0 = np.maximum(np.floor(uv.min(axis=0)).astype(int) - 2, 0)
    u1, v1 = np.minimum(np.ceil(uv.max(axis=0)).astype(int) + 2, [WIDTH, HEIGHT])
    s = supersample
    offs = (np.arange(s) + 0.5) / s - 0.5
    uu, vv = np.meshgrid(np.arange(u0, u1), np.arange(v0, v1))
    shape = (*uu.shape, s, s)
    su = np.broadcast_to(uu[..., None, None] + offs[None, None, None, :], shape).ravel()
    sv = np.broadcast_to(vv[..., None, None] + offs[None, None, :, None], shape).ravel()
    x, y = _undistort((su - WIDTH / 2) / FOCAL_PX, (sv - HEIGHT / 2) / FOCAL_PX, k1)
    d = np.column_stack([x, y, np.ones_like(x)]) @ cam_in_board.rotation.T
    o = cam_in_board.translation
    t = -o[2] / d[:, 2]
    px = o[0] + t * d[:, 0]
    py = o[1] + t * d[:, 1]
    i = np.floor(px / square_mm)
    j = np.floor(py / square_mm)
    on_board = (i >= -1) & (i < cols) & (j >= -1) & (j < rows)
    in_margin = (i >= -2) & (i < cols + 1) & (j >= -2) & (j < rows + 1)
    dark = ((i + j) % 2 == 0) & on_board  # the square outside the first corner is dark
    val = np.where(dark, 35.0, np.where(in_margin, 215.0, 110.0))
    val = np.where(t > 0, val, 110.0)
    block = val.reshape(v1 - v0, u1 - u0, s * s).mean(axis=2)
    img[v0:v1, u0:u1] = block
    if rng is not None and noise > 0:
        img = img + rng.normal(0.0, noise, img.shape)
    return np.clip(np.round(img), 0, 255).astype(np.uint8)


def render_views(seed: int, *, views: int = 14, inner_corners: tuple[int, int] = (8, 5),
                 square_mm: float = 20.0, hand_eye: SE3 = X_TRUE,
                 base_board: SE3 = BASE_BOARD) -> Renders:
    """`views` renders of the board from a wrist camera on a six-axis-like arm."""
    rng = np.random.default_rng([seed, 77])
    cols, rows = inner_corners
    centre = np.array([(cols - 1) * square_mm / 2, (rows - 1) * square_mm / 2, 0.0])
    m = square_mm
    outline = np.array([[-2 * m, -2 * m, 0], [(cols + 1) * m, -2 * m, 0],
                        [-2 * m, (rows + 1) * m, 0], [(cols + 1) * m, (rows + 1) * m, 0]])
    images, flanges = [], []
    while len(images) < views:
        k = len(images)
        az = 2 * math.pi * k / views + rng.uniform(-0.3, 0.3)
        tilt = math.radians(rng.uniform(12.0, 38.0))
        dist = rng.uniform(420.0, 520.0)
        target = centre + np.array([rng.uniform(-30, 30), rng.uniform(-20, 20), 0.0])
        # the board's z points away from the camera side: the camera sits at -z
        eye = target + dist * np.array([math.sin(tilt) * math.cos(az),
                                        math.sin(tilt) * math.sin(az), -math.cos(tilt)])
        z = (target - eye) / np.linalg.norm(target - eye)
        x = np.cross([0.0, 1.0, 0.0], z)
        x /= np.linalg.norm(x)
        y = np.cross(z, x)
        roll = Rotation.from_rotvec([0, 0, math.radians(rng.uniform(-30, 30))]).as_matrix()
        cam_in_board = SE3(np.column_stack([x, y, z]) @ roll, eye)
        uv = _project(cam_in_board.inv().apply(outline), K1)
        if not ((uv[:, 0] > 4) & (uv[:, 0] < WIDTH - 5) & (uv[:, 1] > 4)
                & (uv[:, 1] < HEIGHT - 5)).all():
            continue
        images.append(render_board(cam_in_board, inner_corners, square_mm, rng=rng))
        flanges.append(base_board @ cam_in_board @ hand_eye.inv())
    return Renders(tuple(images), tuple(flanges), inner_corners, square_mm)


# -- eye-to-hand: a fixed camera, the board on the flange -------------------------------

BASE_CAMERA = SE3.from_rotvec([520.0, -610.0, 640.0], [-2.05, 0.35, -0.2])
"""The true ``T_base_camera`` of the eye-to-hand renders (a camera fixed in the cell,
looking obliquely down at the robot's working volume)."""
FLANGE_BOARD = SE3.from_rotvec([-95.0, -70.0, 48.0], [3.05, 0.1, 0.4])
"""The true ``T_flange_board``: the board's face looks along the tool axis (board z,
into the board, about -flange z), its first corner off the flange centre."""


def render_eye_to_hand_views(seed: int, *, views: int = 14,
                             inner_corners: tuple[int, int] = (9, 6), square_mm: float = 30.0,
                             base_camera: SE3 = BASE_CAMERA, flange_board: SE3 = FLANGE_BOARD,
                             tilt_deg: tuple[float, float] = (15.0, 45.0)) -> Renders:
    """`views` renders of a board carried by the flange, seen by a fixed camera.

    The board centre moves within +-150 mm across and +-110 mm up and down the image of
    a point on the optical axis, 650-750 mm from the camera; its face is turned
    `tilt_deg` from the line of sight at azimuths spread round, and up to 30 degrees
    about its normal; the flange pose is ``base_camera @ T_camera_board @
    flange_board^-1``.
    """
    rng = np.random.default_rng([seed, 78])
    cols, rows = inner_corners
    m = square_mm
    centre_b = np.array([(cols - 1) * m / 2, (rows - 1) * m / 2, 0.0])
    outline = np.array([[-2 * m, -2 * m, 0], [(cols + 1) * m, -2 * m, 0],
                        [-2 * m, (rows + 1) * m, 0], [(cols + 1) * m, (rows + 1) * m, 0]])
    images, flanges = [], []
    while len(images) < views:
        k = len(images)
        c = np.array([rng.uniform(-150, 150), rng.uniform(-110, 110), rng.uniform(650, 750)])
        az = 2 * math.pi * k / views + rng.uniform(-0.3, 0.3)
        tilt = math.radians(rng.uniform(*tilt_deg))
        # board z (into the board) points away from the camera, tilted off the line of sight
        z = Rotation.from_rotvec(tilt * np.array([math.cos(az), math.sin(az), 0.0])).apply(
            c / np.linalg.norm(c))
        x = np.cross([0.0, 1.0, 0.0], z)
        x /= np.linalg.norm(x)
        y = np.cross(z, x)
        roll = Rotation.from_rotvec([0, 0, math.radians(rng.uniform(-30, 30))]).as_matrix()
        R = np.column_stack([x, y, z]) @ roll
        board_in_cam = SE3(R, c - R @ centre_b)
        uv = _project(board_in_cam.apply(outline), K1)
        if not ((uv[:, 0] > 4) & (uv[:, 0] < WIDTH - 5) & (uv[:, 1] > 4)
                & (uv[:, 1] < HEIGHT - 5)).all():
            continue
        images.append(render_board(board_in_cam.inv(), inner_corners, square_mm, rng=rng))
        flanges.append(base_camera @ board_in_cam @ flange_board.inv())
    return Renders(tuple(images), tuple(flanges), inner_corners, square_mm)
