"""A small chessboard renderer of the tests' own, independent of robostereo.simulation.

Pinhole camera with one radial distortion term ``k1`` (OpenCV's model; `k1` may also be
``(k1, p1, p2)``, a lens with decentering too), each output
pixel antialiased by supersampling: every sub-sample's distorted position is
undistorted (fixed-point iteration), its ray cast into the board plane and coloured by
the parity of the square it hits.  Flange poses come from camera poses spread round the
board (tilts, azimuths, turns about the optical axis) through a known hand-eye
transform, as a six-axis arm's wrist camera would see it.  Used to check the hand-eye
calibration on data the project's simulator did not make.

ChArUco boards (:func:`render_charuco`, :func:`render_charuco_views`,
:func:`render_charuco_eye_to_hand_views`) are OpenCV's own drawing of the board
(``CharucoBoard.generateImage``) sampled the same way, with 9 sub-samples a pixel in
an n-rooks pattern (every sub-sample on its own row and column, so an edge along the
pixel grid is placed to 1/9 px, not to the 1/3 px of a 3 x 3 grid), and a quarter of
each board under a flat grey patch or out of the frame.
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


Lens = float | tuple[float, float, float]
"""``k1``, or ``(k1, p1, p2)``: OpenCV's radial and decentering terms."""


def _terms(lens: Lens) -> tuple[float, float, float]:
    return (float(lens), 0.0, 0.0) if np.isscalar(lens) else tuple(lens)  # type: ignore[arg-type,return-value]


def _distorted(x: np.ndarray, y: np.ndarray, lens: Lens) -> tuple[np.ndarray, np.ndarray]:
    k1, p1, p2 = _terms(lens)
    r2 = x * x + y * y
    f = 1.0 + k1 * r2
    return (x * f + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
            y * f + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y)


def _undistort(xd: np.ndarray, yd: np.ndarray, lens: Lens) -> tuple[np.ndarray, np.ndarray]:
    k1, p1, p2 = _terms(lens)
    x, y = xd.copy(), yd.copy()
    if p1 == p2 == 0.0:  # the radial lens as it always was: its renders stay bit-identical
        for _ in range(6):
            f = 1.0 + k1 * (x * x + y * y)
            x, y = xd / f, yd / f
        return x, y
    for _ in range(10):  # fixed point: x = xd - (distorted(x) - x)
        u, v = _distorted(x, y, lens)
        x, y = xd - (u - x), yd - (v - y)
    return x, y


def _project(points_cam: np.ndarray, lens: Lens) -> np.ndarray:
    x, y = _distorted(points_cam[:, 0] / points_cam[:, 2], points_cam[:, 1] / points_cam[:, 2],
                      lens)
    return np.column_stack([FOCAL_PX * x + WIDTH / 2, FOCAL_PX * y + HEIGHT / 2])


def rook_offsets(n: int = 9, step: int = 4) -> np.ndarray:
    """`n` sub-sample offsets ``(n, 2)`` with every x and every y distinct (an n-rooks
    pattern: ``y_k`` is ``x`` at ``step k mod n``, `step` coprime with `n`), so that an
    edge along the pixel rows or columns is placed to 1/n px rather than to 1/sqrt(n)
    as on a grid."""
    k = np.arange(n)
    return np.column_stack([(k + 0.5) / n - 0.5, ((step * k) % n + 0.5) / n - 0.5])


def _board_plane(cam_in_board: SE3, outline: np.ndarray, k1: Lens, supersample: int,
                 offsets: np.ndarray | None = None
                 ) -> tuple[tuple[int, int, int, int], np.ndarray, np.ndarray, np.ndarray]:
    """Pixel box ``(u0, v0, u1, v1)`` round the board `outline` (board frame, (4, 3)) and,
    for each of its sub-samples (a `supersample` grid, or `offsets` (S, 2)), where its
    ray meets the board plane (x, y) and how far along the ray (t > 0: in front)."""
    uv = _project(cam_in_board.inv().apply(outline), k1)
    u0, v0 = np.maximum(np.floor(uv.min(axis=0)).astype(int) - 2, 0)
    u1, v1 = np.minimum(np.ceil(uv.max(axis=0)).astype(int) + 2, [WIDTH, HEIGHT])
    uu, vv = np.meshgrid(np.arange(u0, u1), np.arange(v0, v1))
    if offsets is None:
        s = supersample
        offs = (np.arange(s) + 0.5) / s - 0.5
        shape = (*uu.shape, s, s)
        su = np.broadcast_to(uu[..., None, None] + offs[None, None, None, :], shape).ravel()
        sv = np.broadcast_to(vv[..., None, None] + offs[None, None, :, None], shape).ravel()
    else:
        su = (uu[..., None] + offsets[:, 0]).ravel()
        sv = (vv[..., None] + offsets[:, 1]).ravel()
    x, y = _undistort((su - WIDTH / 2) / FOCAL_PX, (sv - HEIGHT / 2) / FOCAL_PX, k1)
    d = np.column_stack([x, y, np.ones_like(x)]) @ cam_in_board.rotation.T
    o = cam_in_board.translation
    t = -o[2] / d[:, 2]
    px = o[0] + t * d[:, 0]
    py = o[1] + t * d[:, 1]
    return (int(u0), int(v0), int(u1), int(v1)), px, py, t


def _finish(val: np.ndarray, box: tuple[int, int, int, int], samples: int, noise: float,
            rng: np.random.Generator | None) -> np.ndarray:
    """Average the sub-samples into pixels of a grey-110 image, add noise, round."""
    u0, v0, u1, v1 = box
    img = np.full((HEIGHT, WIDTH), 110.0)
    img[v0:v1, u0:u1] = val.reshape(v1 - v0, u1 - u0, samples).mean(axis=2)
    if rng is not None and noise > 0:
        img = img + rng.normal(0.0, noise, img.shape)
    return np.clip(np.round(img), 0, 255).astype(np.uint8)


def render_board(cam_in_board: SE3, inner_corners: tuple[int, int], square_mm: float, *,
                 k1: Lens = K1, supersample: int = 3, noise: float = 1.5,
                 rng: np.random.Generator | None = None) -> np.ndarray:
    """A grey uint8 view (HEIGHT, WIDTH) of the board from ``T_board_camera``."""
    cols, rows = inner_corners
    # the board and its light margin (one square) bound the pixels to render
    m = square_mm
    outline = np.array([[-2 * m, -2 * m, 0], [(cols + 1) * m, -2 * m, 0],
                        [-2 * m, (rows + 1) * m, 0], [(cols + 1) * m, (rows + 1) * m, 0]])
    box, px, py, t = _board_plane(cam_in_board, outline, k1, supersample)
    i = np.floor(px / square_mm)
    j = np.floor(py / square_mm)
    on_board = (i >= -1) & (i < cols) & (j >= -1) & (j < rows)
    in_margin = (i >= -2) & (i < cols + 1) & (j >= -2) & (j < rows + 1)
    dark = ((i + j) % 2 == 0) & on_board  # the square outside the first corner is dark
    val = np.where(dark, 35.0, np.where(in_margin, 215.0, 110.0))
    val = np.where(t > 0, val, 110.0)
    return _finish(val, box, supersample * supersample, noise, rng)


def render_views(seed: int, *, views: int = 14, inner_corners: tuple[int, int] = (8, 5),
                 square_mm: float = 20.0, hand_eye: SE3 = X_TRUE,
                 base_board: SE3 = BASE_BOARD,
                 tilt_deg: tuple[float, float] = (12.0, 38.0), lens: Lens = K1) -> Renders:
    """`views` renders of the board from a wrist camera on a six-axis-like arm, tilted
    `tilt_deg` from the board's normal, through `lens`."""
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
        tilt = math.radians(rng.uniform(*tilt_deg))
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
        uv = _project(cam_in_board.inv().apply(outline), lens)
        if not ((uv[:, 0] > 4) & (uv[:, 0] < WIDTH - 5) & (uv[:, 1] > 4)
                & (uv[:, 1] < HEIGHT - 5)).all():
            continue
        images.append(render_board(cam_in_board, inner_corners, square_mm, k1=lens, rng=rng))
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
                             tilt_deg: tuple[float, float] = (15.0, 45.0),
                             lens: Lens = K1) -> Renders:
    """`views` renders of a board carried by the flange, seen by a fixed camera through
    `lens`.

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
        uv = _project(board_in_cam.apply(outline), lens)
        if not ((uv[:, 0] > 4) & (uv[:, 0] < WIDTH - 5) & (uv[:, 1] > 4)
                & (uv[:, 1] < HEIGHT - 5)).all():
            continue
        images.append(render_board(board_in_cam.inv(), inner_corners, square_mm, k1=lens,
                                   rng=rng))
        flanges.append(base_camera @ board_in_cam @ flange_board.inv())
    return Renders(tuple(images), tuple(flanges), inner_corners, square_mm)


# -- ChArUco boards: OpenCV's own drawing of the board, warped into the camera ----------

CHARUCO_PX_PER_MM = 20.0
"""Resolution of the board image the ChArUco renders sample (0.05 mm a pixel)."""


@dataclass(frozen=True)
class CharucoRenders:
    """Views of a ChArUco board, with the truth of each view."""

    images: tuple[np.ndarray, ...]
    flange_poses: tuple[SE3, ...]
    squares: tuple[int, int]
    square_mm: float
    marker_mm: float
    dictionary: str
    camera_board: tuple[SE3, ...]
    """``T_camera_board`` of each view."""
    hidden: tuple[int, ...]
    """Which quarter of the board each view hides (0-3: the quarter at board corner
    (0, 0), (w, 0), (0, h), (w, h)), or -1."""


def charuco_image(squares: tuple[int, int], square_mm: float, marker_mm: float,
                  dictionary: str, px_per_mm: float = CHARUCO_PX_PER_MM) -> np.ndarray:
    """OpenCV's drawing of the board (``CharucoBoard.generateImage``, no margin), uint8."""
    import cv2

    d = cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, dictionary))
    b = cv2.aruco.CharucoBoard(squares, square_mm, marker_mm, d)
    size = (round(squares[0] * square_mm * px_per_mm), round(squares[1] * square_mm * px_per_mm))
    return b.generateImage(size, marginSize=0, borderBits=1)


def charuco_corners_in_image(cam_in_board: SE3, squares: tuple[int, int], square_mm: float,
                             k1: float = K1) -> np.ndarray:
    """True pixels ``(K, 2)`` of the board's inner corners in OpenCV's id order."""
    c, r = squares
    xs, ys = np.meshgrid(np.arange(1, c), np.arange(1, r))
    obj = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)]) * square_mm
    return _project(cam_in_board.inv().apply(obj), k1)


def render_charuco(cam_in_board: SE3, board_image: np.ndarray, square_mm: float, *,
                   hide: tuple[float, float, float, float] | None = None,
                   px_per_mm: float = CHARUCO_PX_PER_MM, k1: float = K1, samples: int = 9,
                   noise: float = 1.5, rng: np.random.Generator | None = None) -> np.ndarray:
    """A grey uint8 view (HEIGHT, WIDTH) of a ChArUco board from ``T_board_camera``.

    The board frame is OpenCV's (origin at the board's corner, x along the columns, y
    along the rows); `board_image` (:func:`charuco_image`) is sampled bilinearly (its
    pixel (i, j) covers board ``[j, j + 1) x [i, i + 1)`` / `px_per_mm`), black 35, white
    215, within a light margin of one square on grey 110.  `hide` ``(x0, y0, x1, y1)``
    (board frame, mm) is covered by a flat grey (128) patch lying on the board.
    """
    from scipy.ndimage import map_coordinates

    h_px, w_px = board_image.shape
    w, h = w_px / px_per_mm, h_px / px_per_mm
    m = square_mm
    outline = np.array([[-m, -m, 0], [w + m, -m, 0], [-m, h + m, 0], [w + m, h + m, 0]])
    box, px, py, t = _board_plane(cam_in_board, outline, k1, 0, rook_offsets(samples))
    on_board = (px >= 0) & (px < w) & (py >= 0) & (py < h)
    in_margin = (px >= -m) & (px < w + m) & (py >= -m) & (py < h + m)
    grey = map_coordinates(board_image.astype(np.float64),
                           [py * px_per_mm - 0.5, px * px_per_mm - 0.5], order=1, mode="nearest")
    val = np.where(on_board, 35.0 + grey * (180.0 / 255.0), np.where(in_margin, 215.0, 110.0))
    if hide is not None:
        x0, y0, x1, y1 = hide
        val = np.where((px >= x0) & (px < x1) & (py >= y0) & (py < y1), 128.0, val)
    val = np.where(t > 0, val, 110.0)
    return _finish(val, box, samples, noise, rng)


def _quarter(k: int, w: float, h: float, rng: np.random.Generator,
             square_mm: float) -> tuple[float, float, float, float]:
    """Board-frame rectangle of quarter `k`, its inner edges moved up to a third of a
    square either way (so they do not always run along the corner lines)."""
    cx = w / 2 + rng.uniform(-1, 1) * square_mm / 3
    cy = h / 2 + rng.uniform(-1, 1) * square_mm / 3
    big = 10 * square_mm
    x0, x1 = (-big, cx) if k in (0, 2) else (cx, w + big)
    y0, y1 = (-big, cy) if k in (0, 1) else (cy, h + big)
    return (x0, y0, x1, y1)


def _in_image(uv: np.ndarray, margin: float = 4.0) -> np.ndarray:
    return ((uv[:, 0] > margin) & (uv[:, 0] < WIDTH - 1 - margin) & (uv[:, 1] > margin)
            & (uv[:, 1] < HEIGHT - 1 - margin))


def _look(eye: np.ndarray, target: np.ndarray, roll_deg: float, up=(0.0, 1.0, 0.0)) -> SE3:
    z = (target - eye) / np.linalg.norm(target - eye)
    x = np.cross(up, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    roll = Rotation.from_rotvec([0, 0, math.radians(roll_deg)]).as_matrix()
    return SE3(np.column_stack([x, y, z]) @ roll, eye)


def render_charuco_views(seed: int, *, views: int = 14, squares: tuple[int, int] = (9, 6),
                         square_mm: float = 20.0, marker_mm: float = 15.0,
                         dictionary: str = "DICT_5X5_100", hide: str | None = "patch",
                         hand_eye: SE3 = X_TRUE, base_board: SE3 = BASE_BOARD
                         ) -> CharucoRenders:
    """`views` renders of a ChArUco board from a wrist camera (as :func:`render_views`).

    `hide`: ``'patch'`` covers a quarter of the board (one per view, in turn) with a
    grey patch; ``'frame'`` aims the camera so that one board corner, and up to about a
    quarter of the board, falls out of the frame (the camera 300-420 mm away); None
    shows the whole board.
    """
    rng = np.random.default_rng([seed, 79])
    img_b = charuco_image(squares, square_mm, marker_mm, dictionary)
    w, h = squares[0] * square_mm, squares[1] * square_mm
    centre = np.array([w / 2, h / 2, 0.0])
    m = square_mm
    outline = np.array([[-m, -m, 0], [w + m, -m, 0], [-m, h + m, 0], [w + m, h + m, 0]])
    corners4 = np.array([[0, 0, 0], [w, 0, 0], [0, h, 0], [w, h, 0]], dtype=float)
    images, flanges, poses, hidden = [], [], [], []
    while len(images) < views:
        k = len(images)
        quarter = k % 4 if hide else -1
        az = 2 * math.pi * k / views + rng.uniform(-0.3, 0.3)
        tilt = math.radians(rng.uniform(12.0, 38.0))
        if hide == "frame":
            dist = rng.uniform(300.0, 420.0)
            opposite = corners4[3 - quarter]
            target = centre + rng.uniform(0.2, 0.7) * (opposite - centre)
        else:
            dist = rng.uniform(420.0, 520.0)
            target = centre + np.array([rng.uniform(-30, 30), rng.uniform(-20, 20), 0.0])
        eye = target + dist * np.array([math.sin(tilt) * math.cos(az),
                                        math.sin(tilt) * math.sin(az), -math.cos(tilt)])
        cam_in_board = _look(eye, target, rng.uniform(-30, 30))
        if hide == "frame":
            keep = [c for i, c in enumerate(corners4) if i != quarter] + [centre]
            ok = (_in_image(_project(cam_in_board.inv().apply(np.array(keep)), K1)).all()
                  and not _in_image(_project(cam_in_board.inv().apply(
                      corners4[quarter:quarter + 1]), K1), 0.0).any())
        else:
            ok = _in_image(_project(cam_in_board.inv().apply(outline), K1)).all()
        if not ok:
            continue
        patch = _quarter(quarter, w, h, rng, square_mm) if hide == "patch" else None
        images.append(render_charuco(cam_in_board, img_b, square_mm, hide=patch, rng=rng))
        flanges.append(base_board @ cam_in_board @ hand_eye.inv())
        poses.append(cam_in_board.inv())
        hidden.append(quarter)
    return CharucoRenders(tuple(images), tuple(flanges), squares, square_mm, marker_mm,
                          dictionary, tuple(poses), tuple(hidden))


def render_charuco_eye_to_hand_views(seed: int, *, views: int = 14,
                                     squares: tuple[int, int] = (10, 7),
                                     square_mm: float = 30.0, marker_mm: float = 22.0,
                                     dictionary: str = "DICT_5X5_100",
                                     hide: str | None = "patch",
                                     base_camera: SE3 = BASE_CAMERA,
                                     flange_board: SE3 = FLANGE_BOARD) -> CharucoRenders:
    """`views` renders of a carried ChArUco board from a fixed camera (as
    :func:`render_eye_to_hand_views`, 650-750 mm away; ``'frame'``: 450-600 mm, the
    board centre moved out towards the image border until one corner leaves it)."""
    rng = np.random.default_rng([seed, 80])
    img_b = charuco_image(squares, square_mm, marker_mm, dictionary)
    w, h = squares[0] * square_mm, squares[1] * square_mm
    centre_b = np.array([w / 2, h / 2, 0.0])
    m = square_mm
    outline = np.array([[-m, -m, 0], [w + m, -m, 0], [-m, h + m, 0], [w + m, h + m, 0]])
    corners4 = np.array([[0, 0, 0], [w, 0, 0], [0, h, 0], [w, h, 0]], dtype=float)
    images, flanges, poses, hidden = [], [], [], []
    while len(images) < views:
        k = len(images)
        quarter = k % 4 if hide else -1
        if hide == "frame":
            c = np.array([rng.uniform(-250, 250), rng.uniform(-190, 190),
                          rng.uniform(450, 600)])
        else:
            c = np.array([rng.uniform(-150, 150), rng.uniform(-110, 110),
                          rng.uniform(650, 750)])
        az = 2 * math.pi * k / views + rng.uniform(-0.3, 0.3)
        tilt = math.radians(rng.uniform(15.0, 45.0))
        z = Rotation.from_rotvec(tilt * np.array([math.cos(az), math.sin(az), 0.0])).apply(
            c / np.linalg.norm(c))
        x = np.cross([0.0, 1.0, 0.0], z)
        x /= np.linalg.norm(x)
        y = np.cross(z, x)
        roll = Rotation.from_rotvec([0, 0, math.radians(rng.uniform(-30, 30))]).as_matrix()
        R = np.column_stack([x, y, z]) @ roll
        board_in_cam = SE3(R, c - R @ centre_b)
        if hide == "frame":
            keep = [q for i, q in enumerate(corners4) if i != quarter] + [centre_b]
            ok = (_in_image(_project(board_in_cam.apply(np.array(keep)), K1)).all()
                  and not _in_image(_project(board_in_cam.apply(
                      corners4[quarter:quarter + 1]), K1), 0.0).any())
        else:
            ok = _in_image(_project(board_in_cam.apply(outline), K1)).all()
        if not ok:
            continue
        patch = _quarter(quarter, w, h, rng, square_mm) if hide == "patch" else None
        images.append(render_charuco(board_in_cam.inv(), img_b, square_mm, hide=patch, rng=rng))
        flanges.append(base_camera @ board_in_cam @ flange_board.inv())
        poses.append(board_in_cam)
        hidden.append(quarter)
    return CharucoRenders(tuple(images), tuple(flanges), squares, square_mm, marker_mm,
                          dictionary, tuple(poses), tuple(hidden))
