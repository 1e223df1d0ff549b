"""Hand-eye calibration views: the calibration boards, their corners, views folders.

The input side of eye-in-hand calibration (:mod:`robostereo.robot.handeye.calibrate`):

* the targets: a :class:`Chessboard` or a :class:`Charuco` board (:data:`Board`), their
  inner corners in the board frame and :func:`describe_board` for messages;
* their corners in a grey image: :func:`detect_board` (:func:`detect_chessboard`, OpenCV's
  sector-based chessboard detector, or OpenCV's ChArUco detector);
* a views folder (:class:`HandEyeViews`): the board images with the flange pose the
  robot reported at each, :func:`write_views` and :func:`read_views`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye.charuco import (
    Charuco,
    charuco_view_problem,
    detect_charuco,
    grey_uint8,
)
from robostereo.robot.handeye.corner_refinement import refine_board_corners

__all__ = [
    "MIN_VIEWS",
    "VIEWS_YAML",
    "VIEW_MODES",
    "Board",
    "Chessboard",
    "HandEyeViews",
    "describe_board",
    "detect_board",
    "detect_chessboard",
    "read_views",
    "view_corners",
    "write_views",
]

MIN_VIEWS = 3
"""Fewest usable views: two motions with non-parallel rotation axes need three poses."""


@dataclass(frozen=True)
class Chessboard:
    """A chessboard calibration target.

    Parameters
    ----------
    inner_corners : tuple of int
        ``(columns, rows)`` of inner corners (OpenCV's ``patternSize``).
    square_mm : float
        Side of one square, millimetres.

    The board frame has its origin at the first inner corner, x along the columns,
    y along the rows, z into the board (the right-handed frame of OpenCV's
    ``objectPoints``).  The square diagonally outside the first inner corner is dark,
    the one outside the last is light: that fixes the order of the detected corners.

    Only boards with ``columns + rows`` odd (one count odd, one even, e.g. 9 x 6) are
    accepted: when the sum is even (8 x 6, 7 x 5, any square board) the board looks the
    same turned by 180 degrees, both outside squares have one colour, and the corner
    order of each view would be a guess (the hand-eye transform then comes out
    hundreds of millimetres off); use a ChArUco board (:class:`Charuco`) for those.

    Examples
    --------
    >>> Chessboard((8, 6), 12.0)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: inner_corners 8 x 6: columns + rows is even, so the ...
    """

    inner_corners: tuple[int, int] = (9, 6)
    square_mm: float = 20.0

    def __post_init__(self) -> None:
        c, r = self.inner_corners
        if int(c) != c or int(r) != r or c < 2 or r < 2:
            raise InputError(f"inner_corners must be (columns, rows) >= 2, got "
                             f"{self.inner_corners}")
        if not (math.isfinite(self.square_mm) and self.square_mm > 0):
            raise InputError(f"square_mm must be a finite number > 0, got {self.square_mm}")
        if (int(c) + int(r)) % 2 == 0:
            raise InputError(
                f"inner_corners {int(c)} x {int(r)}: columns + rows is even, so the board "
                "looks the same turned 180 degrees and its corner order cannot be told; use "
                "a board with one odd and one even count of inner corners (e.g. 9 x 6) or "
                "a ChArUco board")
        object.__setattr__(self, "inner_corners", (int(c), int(r)))

    @property
    def object_points(self) -> NDArray[np.float64]:
        """Inner corners in the board frame, shape ``(columns * rows, 3)``, mm."""
        c, r = self.inner_corners
        xs, ys = np.meshgrid(np.arange(c), np.arange(r))
        return np.column_stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)]) * self.square_mm


Board = Chessboard | Charuco


def view_corners(image: ArrayLike, board: Board
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | str:
    """Board corners found in a grey image: ``(object points (K, 3), pixels (K, 2))``,
    or why there are none that give a pose (a short phrase for messages).

    A chessboard must be found whole (:func:`detect_chessboard`, K = columns rows); a
    ChArUco board gives the corners of the part seen (:func:`~robostereo.robot.handeye.
    charuco.detect_charuco`), at least :data:`MIN_CHARUCO_CORNERS` and not on one line
    (:func:`~robostereo.robot.handeye.charuco.charuco_view_problem`).
    """
    if isinstance(board, Chessboard):
        c = detect_chessboard(image, board)
        return "not found" if c is None else (board.object_points, c)
    if not isinstance(board, Charuco):
        raise InputError(f"board must be a Chessboard or a Charuco, got {type(board).__name__}")
    found = detect_charuco(image, board)
    problem = charuco_view_problem(found, board)
    return problem if problem is not None else (found.object_points, found.pixels)


def detect_board(
    image: ArrayLike, board: Board
) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """Board corners found in a grey image: ``(object points (K, 3), pixels (K, 2))``.

    None if the board is not found (a chessboard must be whole; a ChArUco board needs
    :data:`MIN_CHARUCO_CORNERS` corners, not on one line): :func:`view_corners`.
    """
    found = view_corners(image, board)
    return None if isinstance(found, str) else found


def detect_chessboard(image: ArrayLike, board: Chessboard) -> NDArray[np.float64] | None:
    """Sub-pixel inner corners of `board` in a grey image, ``(N, 2)``, or None.

    :func:`cv2.findChessboardCornersSB` (the sector-based detector) finds them, in the
    order of :attr:`Chessboard.object_points`;
    :func:`~robostereo.robot.handeye.corner_refinement.refine_board_corners` places
    them.  The detector's own sub-pixel corners put each view off by one offset shared
    by its corners (0.011-0.020 px in the median view of the tests' renders), which no
    pose takes up in a hand-eye fit: on the renders' eye-in-hand views (seeds 0-11) it
    pulled the focal length 0.1 % low and the hand-eye 0.22-0.55 mm off on five seeds
    of twelve; refined, 0.005-0.089 mm (``tests/board_renders.py``).
    """
    img = grey_uint8(image)
    ok, corners = cv2.findChessboardCornersSB(img, board.inner_corners,
                                              flags=cv2.CALIB_CB_ACCURACY)
    if not ok or corners is None:
        return None
    c = corners.reshape(-1, 2).astype(np.float64)
    # 180-degree ambiguity of the grid: the square diagonally outside the first inner
    # corner is the dark one (robostereo's board convention, :class:`Chessboard`)
    cols, rows = board.inner_corners
    grid = c.reshape(rows, cols, 2)
    out0 = grid[0, 0] - 0.5 * (grid[0, 1] - grid[0, 0]) - 0.5 * (grid[1, 0] - grid[0, 0])
    out1 = grid[-1, -1] + 0.5 * (grid[-1, -1] - grid[-1, -2]) \
        + 0.5 * (grid[-1, -1] - grid[-2, -1])
    g = img.astype(np.float64)
    v0, v1 = (float(cv2.getRectSubPix(g.astype(np.float32), (3, 3), (float(p[0]), float(p[1])))
                    .mean()) for p in (out0, out1))
    c = c[::-1].copy() if v0 > v1 else c
    return refine_board_corners(img, board.object_points[:, :2], c, board.square_mm)


def describe_board(board: Board) -> str:
    """One line naming a board for messages, e.g. ``chessboard 9 x 6`` or ``ChArUco board
    8 x 6 squares (DICT_5X5_100)``."""
    if isinstance(board, Chessboard):
        return f"chessboard {board.inner_corners[0]} x {board.inner_corners[1]}"
    return (f"ChArUco board {board.squares[0]} x {board.squares[1]} squares "
            f"({board.dictionary}{', legacy pattern' if board.legacy else ''})")


# ------------------------------------------------------------------ views folders

VIEWS_YAML = "views.yaml"
VIEW_MODES: tuple[str, ...] = ("eye-in-hand", "eye-to-hand")
"""The two set-ups a views folder can hold (its ``mode`` key)."""


@dataclass(frozen=True, eq=False)
class HandEyeViews:
    """A hand-eye views folder: board images with the flange pose of each.

    Folder format (``DIR/``)::

        views.yaml   board:          {type: chessboard, inner_corners: [cols, rows],
                                      square_mm} or {type: charuco, squares:
                                      [cols, rows], square_mm, marker_mm, dictionary
                                      (e.g. DICT_5X5_100 or 5X5_100), legacy
                                      (optional, default false)}
                     pixel_pitch_mm: horizontal pitch of the sensor, mm (data sheet)
                     grey_levels:    optional, default 256
                     mode:           optional, eye-in-hand (default: the camera on
                                     the flange) or eye-to-hand (a fixed camera, the
                                     board on the flange)
                     views:          - {image: view_00.png, flange: POSE}
                                     ...   POSE in any form of robostereo.geometry.poses
                                     (T_base_flange as the robot reports it; mm, or
                                     the ROS form in m)
        view_00.png ...

    Attributes
    ----------
    images : tuple of ndarray, shape (H, W)
    flange_poses : tuple of SE3
    names : tuple of str
        Image file names.
    board : Chessboard or Charuco
    pixel_pitch_mm : float
    grey_levels : int
    mode : {'eye-in-hand', 'eye-to-hand'}
    """

    images: tuple[NDArray[Any], ...]
    flange_poses: tuple[SE3, ...]
    names: tuple[str, ...]
    board: Board
    pixel_pitch_mm: float = 0.01
    grey_levels: int = 256
    mode: str = "eye-in-hand"

    def __post_init__(self) -> None:
        if self.mode not in VIEW_MODES:
            raise InputError(f"mode must be one of {', '.join(VIEW_MODES)}, got {self.mode!r}")


def write_views(directory: Any, views: HandEyeViews, *, extra: dict[str, Any] | None = None
                ) -> None:
    """Write a views folder (the folder must not exist or be empty; written whole).

    `extra` maps further file names to mappings written as YAML (e.g. ``truth.yaml``).
    """
    import yaml

    from robostereo.geometry.poses import pose_to_dict
    from robostereo.io import write_image_folder

    b = views.board
    board: dict[str, Any]
    if isinstance(b, Chessboard):
        board = {"type": "chessboard", "inner_corners": list(b.inner_corners),
                 "square_mm": float(b.square_mm)}
    else:
        board = {"type": "charuco", "squares": list(b.squares), "square_mm": float(b.square_mm),
                 "marker_mm": float(b.marker_mm), "dictionary": b.dictionary,
                 **({"legacy": True} if b.legacy else {})}
    data = {
        "board": board,
        "pixel_pitch_mm": float(views.pixel_pitch_mm),
        "grey_levels": int(views.grey_levels),
        **({"mode": views.mode} if views.mode != "eye-in-hand" else {}),
        "views": [{"image": n, "flange": pose_to_dict(f)}
                  for n, f in zip(views.names, views.flange_poses, strict=True)],
    }
    texts = {VIEWS_YAML: yaml.safe_dump(data, sort_keys=False)}
    texts.update({fname: yaml.safe_dump(mapping, sort_keys=False)
                  for fname, mapping in (extra or {}).items()})
    write_image_folder(directory, dict(zip(views.names, views.images, strict=True)), texts)


_CHARUCO_KEYS = ("type", "squares", "square_mm", "marker_mm", "dictionary", "legacy")


def _read_board(b: dict[str, Any], kind: str, src: str) -> Board:
    """The ``board`` mapping of views.yaml as a :data:`Board` (one-line InputError)."""
    try:
        if kind == "chessboard":
            return Chessboard(tuple(b["inner_corners"]), float(b["square_mm"]))  # type: ignore[arg-type]
        unknown = sorted(str(k) for k in b if k not in _CHARUCO_KEYS)
        if unknown:
            raise InputError(f"unknown key{'s' if len(unknown) > 1 else ''} "
                             f"{', '.join(unknown)} for a ChArUco board (keys: "
                             f"{', '.join(_CHARUCO_KEYS)})")
        missing = [k for k in _CHARUCO_KEYS[1:5] if k not in b]
        if missing:
            raise InputError(f"a ChArUco board needs {', '.join(missing)} (squares: [columns, "
                             "rows], square_mm, marker_mm, dictionary, e.g. DICT_5X5_100)")
        sq = b["squares"]
        if not isinstance(sq, list) or len(sq) != 2:
            raise InputError(f"squares must be [columns, rows], got {sq!r}")
        return Charuco(tuple(sq), b["square_mm"], b["marker_mm"],  # type: ignore[arg-type]
                       str(b["dictionary"]), b.get("legacy", False))
    except InputError as exc:
        raise InputError(f"{src}: board: {exc}") from None
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{src}: board: missing or bad key ({exc})") from None


def read_views(directory: Any) -> HandEyeViews:
    """Read a views folder (:class:`HandEyeViews`); one-line InputError on bad input."""
    from robostereo.geometry.poses import as_se3, pose_from_dict
    from robostereo.io import read_folder_yaml
    from robostereo.io.images import load_image

    data, ypath = read_folder_yaml(directory, VIEWS_YAML, folder="views")
    d = ypath.parent
    src = str(ypath)
    if not isinstance(data, dict) or "board" not in data or "views" not in data:
        raise InputError(f"{src}: expected a mapping with keys board, pixel_pitch_mm, views")
    b = data["board"]
    kind = b.get("type", "chessboard") if isinstance(b, dict) else None
    if kind not in ("chessboard", "charuco"):
        raise InputError(f"{src}: board must be {{type: chessboard, inner_corners: [c, r], "
                         "square_mm} or {type: charuco, squares: [c, r], square_mm, "
                         "marker_mm, dictionary[, legacy]}")
    board = _read_board(b, kind, src)
    pitch = data.get("pixel_pitch_mm", 0.01)
    if isinstance(pitch, list):
        pitch = pitch[0] if pitch else None
    if (not isinstance(pitch, int | float) or isinstance(pitch, bool)
            or not math.isfinite(pitch) or not pitch > 0):
        raise InputError(f"{src}: pixel_pitch_mm must be a finite number > 0, got {pitch!r}")
    grey = data.get("grey_levels", 256)
    if not isinstance(grey, int) or isinstance(grey, bool) or grey < 2:
        raise InputError(f"{src}: grey_levels must be an integer >= 2, got {grey!r}")
    mode = data.get("mode", "eye-in-hand")
    if mode not in VIEW_MODES:
        raise InputError(f"{src}: mode must be eye-in-hand or eye-to-hand, got {mode!r}")
    views = data["views"]
    if not isinstance(views, list):
        raise InputError(f"{src}: views must be a list of {{image, flange}}")
    images, poses, names = [], [], []
    for i, v in enumerate(views):
        if not isinstance(v, dict) or "image" not in v or "flange" not in v:
            raise InputError(f"{src}: views[{i}] must be a mapping {{image, flange}}")
        name = str(v["image"])
        poses.append(as_se3(pose_from_dict(v["flange"],
                                           source=f"{src}: views[{i}] ({name}): flange")))
        img, _bits = load_image(d / name)
        if img.ndim == 3:
            img = cv2.cvtColor(np.ascontiguousarray(img[..., :3]), cv2.COLOR_RGB2GRAY)
        images.append(np.asarray(img))
        names.append(str(d / name))
    if len(images) < MIN_VIEWS:
        raise InputError(f"{src}: hand-eye needs at least {MIN_VIEWS} usable views, got "
                         f"{len(images)}")
    return HandEyeViews(images=tuple(images), flange_poses=tuple(poses), names=tuple(names),
                        board=board, pixel_pitch_mm=float(pitch), grey_levels=grey,
                        mode=str(mode))
