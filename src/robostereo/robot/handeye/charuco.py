"""ChArUco calibration boards: the board, its dictionary, its corners (with ids) in an image.

A ChArUco board is a chessboard with an ArUco marker in every light square; the markers
name the corners next to them, so a view that shows only part of the board still gives
corners in a known order, and no board size looks the same turned 180 degrees (the
plain chessboard's ambiguity, :class:`~robostereo.robot.handeye.boards.Chessboard`).

* :class:`Charuco`: the board (squares, square and marker sizes, the ArUco dictionary,
  OpenCV's legacy pattern flag), validated, and its drawing for printing;
* :func:`dictionary_name`: a dictionary name as written in a file (``5X5_100``,
  ``DICT_5X5_100``) to OpenCV's;
* :func:`detect_charuco`: the corners OpenCV's ``CharucoDetector`` finds, with their ids
  and board points, refined to sub-pixel (:func:`refine_charuco_corners`);
* :func:`charuco_view_problem`: why a view's corners are too few for a pose, or None.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from functools import cached_property
from typing import Any

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError
from robostereo.robot.handeye.corner_refinement import refine_board_corners

__all__ = [
    "DICTIONARIES",
    "MIN_CHARUCO_CORNERS",
    "Charuco",
    "CharucoCorners",
    "charuco_view_problem",
    "detect_charuco",
    "dictionary_name",
    "grey_uint8",
    "refine_charuco_corners",
]

MIN_CHARUCO_CORNERS = 6
"""Fewest ChArUco corners for a view to count; they must also not lie on one line
(:func:`charuco_view_problem`)."""

DICTIONARIES: tuple[str, ...] = tuple(sorted(
    {n.upper(): n for n in dir(cv2.aruco) if n.startswith("DICT_")
     and isinstance(getattr(cv2.aruco, n), int)}.values()))
"""OpenCV's predefined ArUco dictionaries (``DICT_4X4_50`` ... ``DICT_ARUCO_ORIGINAL``,
the AprilTag families)."""


def dictionary_name(name: object) -> str:
    """OpenCV's name of an ArUco dictionary: ``'5x5_100'`` or ``'DICT_5X5_100'`` ->
    ``'DICT_5X5_100'`` (case does not matter).

    >>> dictionary_name("5x5_100"), dictionary_name("DICT_APRILTAG_36H11")
    ('DICT_5X5_100', 'DICT_APRILTAG_36h11')
    >>> dictionary_name("DICT_5X5_99")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: dictionary 'DICT_5X5_99' is not an OpenCV ArUco ...
    """
    key = str(name).strip().upper()
    key = key if key.startswith("DICT_") else "DICT_" + key
    for n in DICTIONARIES:
        if n.upper() == key:
            return n
    raise InputError(f"dictionary {name!r} is not an OpenCV ArUco dictionary (e.g. "
                     f"DICT_5X5_100, 5X5_100, DICT_APRILTAG_36h11)")


@dataclass(frozen=True)
class Charuco:
    """A ChArUco calibration target (a chessboard with ArUco markers in its light squares).

    Parameters
    ----------
    squares : tuple of int
        ``(columns, rows)`` of squares (OpenCV's ``CharucoBoard`` size); the board has
        ``(columns - 1) (rows - 1)`` inner corners, at least :data:`MIN_CHARUCO_CORNERS`.
    square_mm, marker_mm : float
        Side of a square and of a marker, millimetres (``marker_mm < square_mm``).
    dictionary : str
        An OpenCV predefined ArUco dictionary (:func:`dictionary_name`: ``'DICT_5X5_100'``
        or ``'5X5_100'``); it must hold the board's ``columns rows / 2`` markers.
    legacy : bool
        OpenCV's legacy pattern (``CharucoBoard.setLegacyPattern``): boards made with
        OpenCV before 4.6 that have an even number of rows start with a light square
        where today's start with a dark one; their markers are then not found unless
        this is set.

    The board frame is OpenCV's: origin at the board's top-left corner, x along the
    columns, y along the rows, z into the board.  Each detected corner has an id (its
    index in :attr:`object_points`), so a partly seen board still gives corners in a
    known order, and boards of any size can be used (no 180-degree ambiguity).

    Examples
    --------
    >>> b = Charuco((8, 6), 12.0, 9.0, "5X5_100")
    >>> b.dictionary, b.object_points.shape, b.object_points[0].tolist()
    ('DICT_5X5_100', (35, 3), [12.0, 12.0, 0.0])
    >>> Charuco((8, 6), 12.0, 12.0, "DICT_5X5_100")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: marker_mm must be below square_mm, got 12.0 and 12.0
    """

    squares: tuple[int, int] = (8, 6)
    square_mm: float = 12.0
    marker_mm: float = 9.0
    dictionary: str = "DICT_5X5_100"
    legacy: bool = False

    def __post_init__(self) -> None:
        sq = self.squares
        if (not isinstance(sq, tuple | list) or len(sq) != 2
                or not all(isinstance(v, int | float) and not isinstance(v, bool)
                           and float(v).is_integer() for v in sq)):
            raise InputError(f"squares must be [columns, rows] (whole numbers), got {sq!r}")
        c, r = int(sq[0]), int(sq[1])
        if c < 2 or r < 2 or (c - 1) * (r - 1) < MIN_CHARUCO_CORNERS:
            raise InputError(f"squares {c} x {r} is too small: a ChArUco board needs at "
                             f"least {MIN_CHARUCO_CORNERS} inner corners ((columns - 1) "
                             "(rows - 1), e.g. 5 x 4 squares)")
        object.__setattr__(self, "squares", (c, r))
        for name in ("square_mm", "marker_mm"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and not isinstance(v, bool)
                    and math.isfinite(v) and v > 0):
                raise InputError(f"{name} must be a finite number > 0, got {v!r}")
            object.__setattr__(self, name, float(v))
        if not self.marker_mm < self.square_mm:
            raise InputError(f"marker_mm must be below square_mm, got {self.marker_mm} and "
                             f"{self.square_mm}")
        if not isinstance(self.legacy, bool):
            raise InputError(f"legacy must be true or false, got {self.legacy!r}")
        name = dictionary_name(self.dictionary)
        object.__setattr__(self, "dictionary", name)
        size = cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, name)).bytesList.shape[0]
        if c * r // 2 > size:
            raise InputError(f"squares {c} x {r} needs {c * r // 2} markers but {name} has "
                             f"only {size}; use a larger dictionary (e.g. "
                             f"{name.rsplit('_', 1)[0]}_1000)")

    def __getstate__(self) -> dict[str, Any]:
        """The fields only (the cached OpenCV board does not pickle)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    @cached_property
    def _cv(self) -> Any:
        d = cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, self.dictionary))
        b = cv2.aruco.CharucoBoard(self.squares, float(self.square_mm),
                                   float(self.marker_mm), d)
        b.setLegacyPattern(self.legacy)
        return b

    def cv_board(self) -> Any:
        """The :class:`cv2.aruco.CharucoBoard`."""
        return self._cv

    @cached_property
    def object_points(self) -> NDArray[np.float64]:
        """Inner corners in the board frame, shape ``((cols - 1) (rows - 1), 3)``, mm;
        row k is the corner with id k."""
        return np.asarray(self._cv.getChessboardCorners(), dtype=np.float64).reshape(-1, 3)

    @cached_property
    def light_squares(self) -> NDArray[np.bool_]:
        """Which squares hold a marker, shape ``(rows, columns)``."""
        c, r = self.squares
        centres = np.asarray(self._cv.getObjPoints(), dtype=np.float64).reshape(-1, 4, 3)
        cells = np.floor(centres.mean(axis=1)[:, :2] / self.square_mm).astype(int)
        light = np.zeros((r, c), dtype=bool)
        light[cells[:, 1], cells[:, 0]] = True
        return light

    def image(self, px_per_mm: float = 10.0, margin_mm: float = 0.0) -> NDArray[np.uint8]:
        """The board drawn at `px_per_mm` with a white margin, for printing or rendering
        (OpenCV's ``CharucoBoard.generateImage``)."""
        c, r = self.squares
        m = round(margin_mm * px_per_mm)
        size = (round(c * self.square_mm * px_per_mm) + 2 * m,
                round(r * self.square_mm * px_per_mm) + 2 * m)
        return self._cv.generateImage(size, marginSize=m, borderBits=1)


@dataclass(frozen=True, eq=False)
class CharucoCorners:
    """The ChArUco corners found in one view.

    Attributes
    ----------
    ids : ndarray of int, shape (K,)
        Corner ids (rows of :attr:`Charuco.object_points`), ascending.
    pixels : ndarray, shape (K, 2)
        Their sub-pixel image positions ``(x, y)``.
    object_points : ndarray, shape (K, 3)
        Their board-frame points, mm.
    markers : int
        ArUco markers found.
    """

    ids: NDArray[np.int64]
    pixels: NDArray[np.float64]
    object_points: NDArray[np.float64]
    markers: int = 0

    def __post_init__(self) -> None:
        k = self.ids.shape[0]
        if self.ids.shape != (k,) or self.pixels.shape != (k, 2) or \
                self.object_points.shape != (k, 3):
            raise InputError(f"ids (K,), pixels (K, 2) and object_points (K, 3) must agree, "
                             f"got {self.ids.shape}, {self.pixels.shape} and "
                             f"{self.object_points.shape}")


def grey_uint8(image: ArrayLike) -> NDArray[np.uint8]:
    """A grey ``(H, W)`` image as the 8-bit image OpenCV's board detectors take.

    Other dtypes are scaled so that their maximum is 255; 7-bit grey levels (all
    below 128) are doubled.
    """
    img = np.asarray(image)
    if img.ndim != 2:
        raise InputError(f"image must be a grey (H, W) image, got shape {img.shape}")
    if img.dtype != np.uint8:
        top = float(img.max()) if img.size else 1.0
        return np.clip(img.astype(np.float64) * (255.0 / max(top, 1.0)), 0, 255).astype(
            np.uint8)
    if img.size and img.max() < 128:  # 7-bit grey levels: stretch for the detector
        return (img.astype(np.uint16) * 2).astype(np.uint8)
    return img


def detect_charuco(image: ArrayLike, board: Charuco, *, refine: bool = True
                   ) -> CharucoCorners:
    """The ChArUco corners in a grey image, with their ids (possibly none).

    Parameters
    ----------
    image : array_like, shape (H, W)
    board : Charuco
    refine : bool
        Refine the corners with :func:`refine_charuco_corners` (default) rather than
        keep OpenCV's ``cornerSubPix`` positions.

    Returns
    -------
    CharucoCorners
        Every corner OpenCV's ``CharucoDetector.detectBoard`` interpolates between two
        found markers next to it (a partial view gives a subset), ids ascending.

    Notes
    -----
    On the tests' renders (``tests/board_renders.py``: 640 x 480, k1 = -0.1, markers
    0.73-0.75 of the square, 1.5 grey levels of noise, a quarter of the board hidden
    or out of the frame; 6004 corners) the corners are off the truth by 0.078 px RMS
    (95th percentile 0.14 px) as OpenCV refines them, 0.086-0.11 px with a further
    ``cornerSubPix`` (5 x 5 to 11 x 11 windows), and 0.040 px RMS (0.074 px) with
    :func:`refine_charuco_corners`.
    """
    img = grey_uint8(image)
    corners, ids, _mc, mids = cv2.aruco.CharucoDetector(board.cv_board()).detectBoard(img)
    markers = 0 if mids is None else len(mids)
    if corners is None or ids is None or len(ids) == 0:
        return CharucoCorners(np.zeros(0, dtype=np.int64), np.zeros((0, 2)), np.zeros((0, 3)),
                              markers)
    ids = ids.ravel().astype(np.int64)
    order = np.argsort(ids)
    ids = ids[order]
    px = corners.reshape(-1, 2).astype(np.float64)[order]
    if refine and len(ids) >= 4:
        px = refine_charuco_corners(img, board, ids, px)
    return CharucoCorners(ids, px, board.object_points[ids], markers)


def refine_charuco_corners(image: ArrayLike, board: Charuco, ids: ArrayLike,
                           pixels: ArrayLike, *, iterations: int = 6, sigma_squares: float = 0.15,
                           guard_px: float = 2.0) -> NDArray[np.float64]:
    """Sub-pixel ChArUco corners that ignore the markers' edges.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Grey image.
    board : Charuco
    ids : array_like of int, shape (K,)
        Corner ids (K >= 4, not all on one line).
    pixels : array_like, shape (K, 2)
        Their approximate positions (OpenCV's).
    iterations, sigma_squares, guard_px
        As :func:`~robostereo.robot.handeye.corner_refinement.refine_board_corners`.

    Returns
    -------
    ndarray, shape (K, 2)
        Refined positions (a corner that would move more than 2 px keeps its start).

    Notes
    -----
    ``cornerSubPix``'s condition, that every image gradient in a window is orthogonal
    to the corner's offset from it, holds at a chessboard corner.  The markers' edges
    lie 0.1-0.2 squares from a ChArUco corner and break it (seen: 0.074 px RMS against
    the truth, 0.036 px without them).  Here each corner's window is weighted in its
    own squares' frame and the pixels of a light square within `guard_px` of its marker
    are left out (:func:`~robostereo.robot.handeye.corner_refinement.refine_board_corners`).

    References
    ----------
    W. Foerstner, E. Guelch, "A fast operator for detection and precise location of
    distinct points, corners and centres of circular features", ISPRS 1987 (the
    orthogonality condition ``cornerSubPix`` solves).
    """
    ids = np.asarray(ids, dtype=np.int64).ravel()
    # which of the corner's squares (-,-), (+,-), (-,+), (+,+) are light
    cols = board.squares[0]
    i, j = ids % (cols - 1), ids // (cols - 1)
    L = board.light_squares
    light = np.stack([L[j, i], L[j, i + 1], L[j + 1, i], L[j + 1, i + 1]], axis=1)
    return refine_board_corners(image, board.object_points[ids, :2], pixels,
                                float(board.square_mm), light=light,
                                marker_margin=(1.0 - board.marker_mm / board.square_mm) / 2.0,
                                iterations=iterations, sigma_squares=sigma_squares,
                                guard_px=guard_px)


def charuco_view_problem(corners: CharucoCorners, board: Charuco) -> str | None:
    """Why a view's ChArUco corners cannot give a pose, or None if they can.

    Too few: under :data:`MIN_CHARUCO_CORNERS` corners; on one line: their board points'
    RMS distance from the best-fitting line is under a quarter of a square (three
    corners on each of two rows give half a square).

    >>> b = Charuco((8, 6), 12.0, 9.0, "DICT_5X5_100")
    >>> row = CharucoCorners(np.arange(7), np.zeros((7, 2)), b.object_points[:7])
    >>> charuco_view_problem(row, b)
    'its 7 ChArUco corners lie on one line'
    """
    k = len(corners.ids)
    if k < MIN_CHARUCO_CORNERS:
        return (f"{k} ChArUco corner{'s' if k != 1 else ''} found ({corners.markers} "
                f"markers), under {MIN_CHARUCO_CORNERS}")
    xy = corners.object_points[:, :2] - corners.object_points[:, :2].mean(axis=0)
    spread = np.linalg.svd(xy, compute_uv=False)[-1] / math.sqrt(k)
    if spread < 0.25 * board.square_mm:
        return f"its {k} ChArUco corners lie on one line"
    return None
