"""Where to put more views: the hand-eye transform's spread with views added.

The joint refinement (:mod:`robostereo.robot.handeye.refine`) leaves ``X``'s rotation
trading against the principal point where the views turn little about the board: a
shift of ``(cx, cy)`` by ``f delta`` and a turn of ``X`` by ``delta`` change the
corners' pixels only to second order.  Views tilted further from the board's normal
separate the two.  How far is a question of the views at hand, their number, the lens
and the board, so it is answered by the fit's own covariance rather than by a rule:
the information ``J^T J`` of the views taken adds that of candidate views (four, at one
tilt from the board's normal, about the board's x and y axes, at the views' median
distance, every corner in the image), and ``s^2 (J^T J)^-1`` says what ``X``'s
standard deviations would become [1]_ (the planning use of the covariance in
photogrammetric network design [2]_).  The flange poses that place those views are
given, in the robot's form, to be sent to the arm.

References
----------
.. [1] R. Hartley and A. Zisserman, *Multiple View Geometry*, 2nd ed., 2003, 5.2.4.
.. [2] C. S. Fraser, "Network design considerations for non-topographic
   photogrammetry", Photogrammetric Engineering and Remote Sensing 50(8), 1984.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3, pose_to_dict
from robostereo.robot.handeye.refine import (
    CornerModel,
    free_intrinsics,
    hand_eye_sigma,
    project_board,
)

__all__ = [
    "ADVICE_TILTS_DEG",
    "ViewAdvice",
    "advise_views",
]

ADVICE_TILTS_DEG = (20.0, 30.0, 40.0, 50.0)
"""Tilts from the board's normal that :func:`advise_views` tries, deg: beyond 50 the
corners foreshorten and the detectors lose them."""

_MARGIN_PX = 8.0            # every corner this far inside the image
_FARTHEST = 2.0             # a candidate may stand up to this times the median distance
# turned +-20 deg about the optical axis: squares along the pixel grid place their edges
# worst (a sensor's pixels, a renderer's samples), and turns vary the distortion's pull
_ROLLS = tuple(SE3.from_rotvec([0.0, 0.0, 0.0], [0.0, 0.0, math.radians(r)])
               for r in (20.0, -20.0, 20.0, -20.0))


@dataclass(frozen=True, eq=False)
class ViewAdvice:
    """What four more views at each tilt would make of the hand-eye transform's spread.

    Attributes
    ----------
    tilts_deg : ndarray, shape (T,)
        Candidate tilts of the optical axis from the board's normal, deg.
    sigma_mm, sigma_deg : ndarray, shape (T,)
        Predicted largest standard deviation of ``X``'s translation (mm) and rotation
        (deg) with the four views added; NaN where the board does not fit the image.
    flange_poses : tuple of tuple of SE3
        For each tilt, the four flange poses (``T_base_flange`` as the robot reports
        it, in the calibration's mode) that place the views.
    current_mm, current_deg : float
        The same figures for the views taken (the calibration's ``hand_eye_sigma``).
    view_tilts_deg : ndarray, shape (N,)
        The tilts of the views taken, deg.
    like_views_mm, like_views_deg : float
        The figures with four more views at the views' median tilt: what more views
        alone bring, to set the tilts' gain against.
    mode : str
        ``'eye-in-hand'`` or ``'eye-to-hand'``.
    """

    tilts_deg: NDArray[np.float64]
    sigma_mm: NDArray[np.float64]
    sigma_deg: NDArray[np.float64]
    flange_poses: tuple[tuple[SE3, ...], ...]
    current_mm: float
    current_deg: float
    view_tilts_deg: NDArray[np.float64]
    like_views_mm: float = math.nan
    like_views_deg: float = math.nan
    mode: str = "eye-in-hand"

    def __post_init__(self) -> None:
        t = len(self.tilts_deg)
        if not (len(self.sigma_mm) == len(self.sigma_deg) == len(self.flange_poses) == t):
            raise InputError(f"ViewAdvice: tilts, sigmas and flange poses must be as many "
                             f"({t})")

    @property
    def best(self) -> int | None:
        """Index of the tilt to add: the least rotation spread, the smaller tilt when two
        are within 5 % of it; None if no tilt fits."""
        ok = np.isfinite(self.sigma_deg)
        if not ok.any():
            return None
        least = float(np.nanmin(self.sigma_deg))
        return int(np.flatnonzero(ok & (self.sigma_deg <= 1.05 * least))[0])

    def to_dict(self) -> dict[str, Any]:
        """The advice file ``robostereo handeye --advise`` writes (YAML-ready)."""
        k = self.best
        out: dict[str, Any] = {
            "mode": self.mode,
            "current_sigma": {"translation_mm": round(self.current_mm, 6),
                              "rotation_deg": round(self.current_deg, 6)},
            "view_tilts_deg": [round(float(v), 2) for v in self.view_tilts_deg],
            "like_views_sigma": (None if not math.isfinite(self.like_views_deg) else
                                 {"translation_mm": round(self.like_views_mm, 6),
                                  "rotation_deg": round(self.like_views_deg, 6)}),
            "candidates": [
                {"tilt_deg": float(t),
                 "sigma": (None if not math.isfinite(float(s_deg)) else
                           {"translation_mm": round(float(s_mm), 6),
                            "rotation_deg": round(float(s_deg), 6)})}
                for t, s_mm, s_deg in zip(self.tilts_deg, self.sigma_mm, self.sigma_deg,
                                          strict=True)],
        }
        if k is not None:
            out["advised_tilt_deg"] = float(self.tilts_deg[k])
            out["flange_poses"] = [pose_to_dict(f) for f in self.flange_poses[k]]
        return out


def _tilt_deg(cam_in_board: SE3) -> float:
    """Angle of the optical axis from the board's normal (+z, away from the camera)."""
    return math.degrees(math.acos(float(np.clip(cam_in_board.rotation[2, 2], -1.0, 1.0))))


def _outline(board_points: NDArray[np.float64]) -> NDArray[np.float64]:
    """The board's outline ``(4, 3)``: its corners' rectangle grown by one square (the
    outer squares and quiet zone a detector needs to see)."""
    d = np.linalg.norm(board_points[:, None, :2] - board_points[None, :, :2], axis=2)
    d[d == 0] = np.inf
    step = float(np.median(d.min(axis=1))) if len(board_points) > 1 else 0.0
    lo = board_points[:, :2].min(axis=0) - step
    hi = board_points[:, :2].max(axis=0) + step
    return np.array([[lo[0], lo[1], 0], [hi[0], lo[1], 0], [lo[0], hi[1], 0],
                     [hi[0], hi[1], 0]])


def _fits(points_cam: NDArray[np.float64], K: NDArray[np.float64], dist: NDArray[np.float64],
          size: tuple[int, int]) -> bool:
    if (points_cam[:, 2] <= 1.0).any():
        return False
    uv = project_board(points_cam, K, dist)
    w, h = size
    return bool(((uv[:, 0] >= _MARGIN_PX) & (uv[:, 0] <= w - 1 - _MARGIN_PX)
                 & (uv[:, 1] >= _MARGIN_PX) & (uv[:, 1] <= h - 1 - _MARGIN_PX)).all())


def advise_views(
    object_points: Sequence[NDArray[np.float64]],
    flange_poses: Sequence[SE3],
    K: NDArray[np.float64],
    dist: NDArray[np.float64],
    hand_eye: SE3,
    base_board: SE3,
    board_points: NDArray[np.float64],
    image_size: tuple[int, int],
    variance_px2: float,
    *,
    fix_intrinsics: bool = False,
    fix_k3: bool = True,
    fix_tangential: bool = False,
    mode: str = "eye-in-hand",
    tilts_deg: Sequence[float] = ADVICE_TILTS_DEG,
    information: NDArray[np.float64] | None = None,
) -> ViewAdvice:
    """Predict ``X``'s spread with four more views at each of `tilts_deg`.

    Parameters
    ----------
    object_points : sequence of ndarray, shape (K_i, 3)
        The corners each view taken shows, board frame, mm.
    flange_poses : sequence of SE3
        Their flange poses in the eye-in-hand form of
        :func:`~robostereo.robot.handeye.calibrate.solve_views` (eye-to-hand: inverted).
    K, dist, hand_eye, base_board
        The calibration (``X`` and ``W`` in the same form).
    board_points : ndarray, shape (M, 3)
        Every corner of the board, board frame, mm (a candidate view shows them all).
    image_size : (int, int)
        ``(width, height)``, pixels.
    variance_px2 : float
        The corners' residual variance (one coordinate, px^2).
    fix_intrinsics, fix_k3, fix_tangential : bool
        As the refinement held them.
    mode : {'eye-in-hand', 'eye-to-hand'}
        The robot's form of the flange poses returned.
    tilts_deg : sequence of float
        Candidate tilts, deg in (0, 80).
    information : ndarray, shape (P, P), optional
        The views' ``J^T J`` when the caller has it
        (:attr:`~robostereo.robot.handeye.refine.RefinedHandEye.information`); else it
        is computed from `object_points`.

    Returns
    -------
    ViewAdvice

    Notes
    -----
    1. The views taken give ``T_board_camera_i = W^-1 F_i X``: their tilts and their
       median distance ``d`` from the board's centre.
    2. For each tilt ``t`` and azimuth 0, 90, 180, 270 deg (about the board's x and y
       axes) a camera at ``d`` (moved back in 5 % steps, up to ``2 d``, until every
       corner is at least 8 px inside the image) looks at the centre, its x axis along
       the board's; its flange pose is ``F = W T_board_camera X^-1``.
       Each is turned 20 deg about its optical axis, alternately each way: squares
       along the pixel grid place their edges worst.
    3. ``J^T J`` of the views taken plus that of the four (:meth:`CornerModel.
       information`) gives the covariance ``s^2 (J^T J)^-1`` and its largest standard
       deviations (:func:`~robostereo.robot.handeye.refine.hand_eye_sigma`).
    4. The same four at the views' median tilt say what more views alone would bring.

    Examples
    --------
    >>> K = np.array([[800.0, 0, 320], [0, 800, 240], [0, 0, 1]])
    >>> X = SE3.from_rotvec([20.0, -30.0, 50.0], [0.1, 0.0, 1.0])
    >>> W = SE3.from_rotvec([400.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    >>> board = np.array([[i * 20.0, j * 20.0, 0.0] for i in range(8) for j in range(5)])

    Eight views tilted 2.4 deg round the board: the rotation is poorly pinned, and four
    tilted views pin it far better than four more of the same:

    >>> look = [SE3.look_at([70 + 20 * np.cos(a), 40 + 20 * np.sin(a), -480.0], [70, 40, 0])
    ...         for a in np.linspace(0, 2 * np.pi, 8, endpoint=False)]
    >>> F = [W @ c @ X.inv() for c in look]
    >>> adv = advise_views([board] * 8, F, K, np.zeros(5), X, W, board, (640, 480), 0.01)
    >>> float(adv.tilts_deg[adv.best]), len(adv.flange_poses[adv.best])
    (20.0, 4)
    >>> [round(float(v), 2) for v in (adv.current_deg, adv.like_views_deg, adv.sigma_deg[adv.best])]
    [0.88, 0.72, 0.16]
    """
    tilts = np.asarray(tilts_deg, dtype=np.float64)
    if tilts.ndim != 1 or not ((tilts > 0) & (tilts < 80)).all():
        raise InputError(f"tilts_deg must be degrees in (0, 80), got {list(tilts_deg)}")
    if mode not in ("eye-in-hand", "eye-to-hand"):
        raise InputError(f"mode must be eye-in-hand or eye-to-hand, got {mode!r}")
    board_points = np.asarray(board_points, dtype=np.float64).reshape(-1, 3)
    held = {"fix_intrinsics": fix_intrinsics, "fix_k3": fix_k3,
            "fix_tangential": fix_tangential}
    n_intr = int(free_intrinsics(**held).sum())

    # the views taken: their information, tilts and distance
    info = information if information is not None else CornerModel(
        object_points, flange_poses).information(K, dist, hand_eye, base_board, **held)
    current = hand_eye_sigma(info, variance_px2, n_intr)
    W_inv = base_board.inv()
    cams = [W_inv @ f @ hand_eye for f in flange_poses]      # T_board_camera
    centre = board_points.mean(axis=0)
    d = float(np.median([np.linalg.norm(c.translation - centre) for c in cams]))
    outline = _outline(board_points)

    # four candidates per tilt, and what they add
    def added(t: float) -> tuple[float, float, tuple[SE3, ...]]:
        cand = []
        for a, roll in zip(np.radians([0.0, 90.0, 180.0, 270.0]), _ROLLS, strict=True):
            way = np.array([math.sin(t) * math.cos(a), math.sin(t) * math.sin(a),
                            -math.cos(t)])
            for s in np.arange(1.0, _FARTHEST + 1e-9, 0.05):
                c = SE3.look_at(centre + s * d * way, centre) @ roll
                if _fits(c.inv().apply(outline), K, dist, image_size):
                    cand.append(c)
                    break
        if len(cand) < 4:
            return math.nan, math.nan, ()
        F = [base_board @ c @ hand_eye.inv() for c in cand]
        more = CornerModel([board_points] * 4, F).information(
            K, dist, hand_eye, base_board, **held)
        mm, deg = hand_eye_sigma(info + more, variance_px2, n_intr)
        return mm, deg, tuple(f.inv() if mode == "eye-to-hand" else f for f in F)

    rows = [added(t) for t in np.radians(tilts)]
    view_tilts = np.array([_tilt_deg(c) for c in cams])
    like = added(math.radians(float(np.median(view_tilts))))
    return ViewAdvice(tilts_deg=tilts, sigma_mm=np.array([r[0] for r in rows]),
                      sigma_deg=np.array([r[1] for r in rows]),
                      flange_poses=tuple(r[2] for r in rows), current_mm=current[0],
                      current_deg=current[1], view_tilts_deg=view_tilts,
                      like_views_mm=like[0], like_views_deg=like[1], mode=mode)
