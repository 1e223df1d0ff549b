"""Eye-in-hand calibration from board views: intrinsics and the camera's flange pose.

The thesis's camera pose came from the robot alone (a fixed forearm mount, 4.1).
A camera bolted to any arm's flange needs the flange-to-camera transform
``X = T_flange_camera`` and, unless they are known, the camera's intrinsics and
distortion.

:func:`calibrate_eye_in_hand` runs the whole calibration from board images: corner
detection (:mod:`robostereo.robot.handeye.boards`), :func:`cv2.calibrateCamera`
(intrinsics and distortion, per-view board poses), the AX = XB closed forms of
:mod:`robostereo.robot.handeye.ax_xb`, the plausibility checks of
:mod:`robostereo.robot.handeye.checks` and the joint refinement of
:mod:`robostereo.robot.handeye.refine`; :class:`EyeInHandCalibration` is its result.
The file ``robostereo handeye`` writes from it is read and written by
:mod:`robostereo.robot.handeye.handeye_yaml`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from robostereo.errors import InputError, warn_input
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye.ax_xb import (
    DEFAULT_METHOD,
    HandEyeResiduals,
    handeye_residuals,
    motion_pairs,
    solve_ax_xb,
)
from robostereo.robot.handeye.ax_zb import ROBOT_WORLD_METHODS, solve_ax_zb
from robostereo.robot.handeye.boards import (
    MIN_VIEWS,
    VIEW_MODES,
    Board,
    Chessboard,
    describe_board,
    view_corners,
)
from robostereo.robot.handeye.checks import (
    MAX_ROTATION_RMS_DEG,
    OUTLIER_Z,
    check_intrinsics,
    check_plausible,
    corner_noise_px,
    outlier_views,
    pose_covariances,
    predicted_pair_translation_mm,
    view_scores,
)
from robostereo.robot.handeye.refine import TANGENTIAL_CHOICES, Tangential, refine_eye_in_hand
from robostereo.robot.handeye.view_advice import ViewAdvice, advise_views

__all__ = [
    "ALL_METHODS",
    "EyeInHandCalibration",
    "HandEyeMode",
    "SolveMethod",
    "calibrate_eye_in_hand",
    "solve_views",
]

HandEyeMode = Literal["eye-in-hand", "eye-to-hand"]
SolveMethod = Literal["tsai", "park", "daniilidis", "shah", "li"]
ALL_METHODS: tuple[str, ...] = ("park", "tsai", "daniilidis", *ROBOT_WORLD_METHODS)
"""The closed forms that can start the refinement: the AX = XB ones of
:mod:`~robostereo.robot.handeye.ax_xb` and OpenCV's AX = ZB ones of
:mod:`~robostereo.robot.handeye.ax_zb`."""


@dataclass(frozen=True, eq=False)
class EyeInHandCalibration:
    """Result of :func:`calibrate_eye_in_hand`.

    Attributes
    ----------
    camera : Camera
        Intrinsics and distortion (jointly refined, or the known ones).
    hand_eye : SE3
        ``T_flange_camera``, millimetres (jointly refined unless ``refine=False``).
    method : str
        The closed form that started the refinement.
    reprojection_rms_px : float
        RMS reprojection error of all corners through the final model, pixels.
    per_view_rms_px : ndarray, shape (N,)
        RMS reprojection error of each view, pixels.
    board_poses : tuple of SE3
        ``T_camera_board`` of each view (:func:`cv2.solvePnP` with the final intrinsics).
    residuals : HandEyeResiduals
        AX = XB residuals of every pair of views (those board poses, the final ``X``).
    base_board : SE3
        ``T_base_board``.
    names : tuple of str
        The views kept.
    closed_form : SE3
        ``X`` of the closed form (before the refinement).
    corner_noise_px : float
        Robust standard deviation of a corner coordinate (per-view poses), pixels.
    predicted_translation_rms_mm : float
        AX = XB translation RMS that the corner noise explains (the plausibility bound
        is a multiple of it, :func:`~robostereo.robot.handeye.checks.check_plausible`).
    outliers : tuple of str
        Views whose residuals stand out (robust z-score > 3.5).
    rejected : tuple of str
        Views dropped by ``reject_outliers`` before the final solution.
    corners_per_view : ndarray of int, shape (N,), optional
        Corners used in each view kept (ChArUco boards, whose views may show part of
        the board); None for a chessboard (every view shows all its corners).
    left_out : tuple of str
        Views left out because too few ChArUco corners were found in them (each
        warned about).
    hand_eye_sigma_mm, hand_eye_sigma_deg : float
        How well the views pin the hand-eye transform (the refinement's covariance,
        :class:`~robostereo.robot.handeye.refine.RefinedHandEye`); NaN unrefined.
    advice : ViewAdvice, optional
        What four more views at larger tilts would pin it to, and the flange poses that
        place them (:func:`~robostereo.robot.handeye.view_advice.advise_views`); None
        unrefined.
    tangential : str
        What the refinement did with the decentering terms ``p1, p2``: ``'held'`` at 0
        (the test found them insignificant, or ``tangential='zero'``), ``'kept'`` (the
        test found them significant), ``'fitted'`` (``tangential='fit'``), or ``''``
        (known intrinsics, or unrefined).
    tangential_chi2 : float
        The Wald statistic of ``p1, p2`` in the refinement with them free
        (:func:`~robostereo.robot.handeye.refine.tangential_chi2`); NaN where not
        tested.
    """

    camera: Camera
    hand_eye: SE3
    method: str
    reprojection_rms_px: float
    per_view_rms_px: NDArray[np.float64]
    board_poses: tuple[SE3, ...]
    residuals: HandEyeResiduals
    base_board: SE3
    names: tuple[str, ...] = ()
    closed_form: SE3 | None = None
    corner_noise_px: float = math.nan
    predicted_translation_rms_mm: float = math.nan
    outliers: tuple[str, ...] = ()
    rejected: tuple[str, ...] = ()
    corners_per_view: NDArray[np.int64] | None = None
    left_out: tuple[str, ...] = ()
    hand_eye_sigma_mm: float = math.nan
    hand_eye_sigma_deg: float = math.nan
    advice: ViewAdvice | None = None
    tangential: str = ""
    tangential_chi2: float = math.nan

    def __post_init__(self) -> None:
        n = len(self.board_poses)
        if self.corners_per_view is not None and np.shape(self.corners_per_view) != (n,):
            raise InputError(f"corners_per_view must cover {n} views")
        if self.per_view_rms_px.shape != (n,) or self.residuals.rotation_deg.shape != (
                n * (n - 1) // 2,):
            raise InputError(f"per_view_rms_px and residuals must cover {n} views")
        if self.names and len(self.names) != n:
            raise InputError(f"names must be {n}, got {len(self.names)}")

    @property
    def pairs(self) -> list[tuple[int, int]]:
        """The view pairs ``(i, j)``, ``i < j``, in the order of the residuals."""
        n = len(self.board_poses)
        return [(i, j) for i in range(n) for j in range(i + 1, n)]

    def to_dict(self) -> dict[str, Any]:
        """The ``camera.yaml`` mapping that ``robostereo handeye`` writes."""
        from pathlib import PurePath

        from robostereo.geometry.camera import camera_to_dict
        from robostereo.geometry.poses import pose_to_dict

        names = [PurePath(n).name for n in self.names] or [
            f"view {i}" for i in range(len(self.board_poses))]
        out: dict[str, Any] = {
            "camera": camera_to_dict(self.camera),
            "hand_eye": pose_to_dict(self.hand_eye),
            "method": self.method,
            "refined": self.closed_form is not None,
            "reprojection_rms_px": round(self.reprojection_rms_px, 6),
            "per_view_rms_px": [round(float(v), 6) for v in self.per_view_rms_px],
            "handeye_residuals": {
                "rotation_deg_rms": round(self.residuals.rms_rotation_deg, 6),
                "translation_mm_rms": round(self.residuals.rms_translation_mm, 6),
                "translation_mm_rms_predicted": round(self.predicted_translation_rms_mm, 6),
            },
            "corner_noise_px": round(self.corner_noise_px, 6),
            "views": [{"image": n, "reprojection_rms_px": round(float(v), 6),
                       "outlier": n in {PurePath(o).name for o in self.outliers}}
                      for n, v in zip(names, self.per_view_rms_px, strict=True)],
            "pairs": [{"views": [names[i], names[j]], "rotation_deg": round(float(r), 6),
                       "translation_mm": round(float(t), 6)}
                      for (i, j), r, t in zip(self.pairs, self.residuals.rotation_deg,
                                              self.residuals.translation_mm, strict=True)],
            "rejected_views": [PurePath(n).name for n in self.rejected],
        }
        if self.corners_per_view is not None:  # ChArUco: views of part of the board
            for v, k in zip(out["views"], self.corners_per_view, strict=True):
                v["corners"] = int(k)
            out["left_out_views"] = [PurePath(n).name for n in self.left_out]
        if self.closed_form is not None:
            out["hand_eye_closed_form"] = pose_to_dict(self.closed_form)
        if math.isfinite(self.hand_eye_sigma_mm):  # how well the views pin it
            out["hand_eye_sigma"] = {"translation_mm": round(self.hand_eye_sigma_mm, 6),
                                     "rotation_deg": round(self.hand_eye_sigma_deg, 6)}
        if self.tangential:  # what became of p1, p2 in the refinement
            out["tangential"] = {"terms": self.tangential}
            if math.isfinite(self.tangential_chi2):
                out["tangential"]["chi2"] = round(self.tangential_chi2, 6)
        return out


@dataclass(frozen=True, eq=False)
class _Stage:
    """Per-view poses with fixed intrinsics, and the closed form on them."""

    K: NDArray[np.float64]
    dist: NDArray[np.float64]
    rvecs: list[NDArray[np.float64]]
    tvecs: list[NDArray[np.float64]]
    per_view: NDArray[np.float64]
    noise: float
    X: SE3
    residuals: HandEyeResiduals
    predicted: float
    base_board: SE3


def _board_poses(obj: list, pts: list, size: tuple[int, int], flanges: Sequence[SE3],
                 camera: Camera | None, fix_k3: bool, method: SolveMethod,
                 guess: tuple[NDArray, NDArray, list, list] | None = None, *,
                 zero_tangent: bool = False) -> _Stage:
    if camera is None and guess is None:
        flags = ((cv2.CALIB_FIX_K3 if fix_k3 else 0)
                 | (cv2.CALIB_ZERO_TANGENT_DIST if zero_tangent else 0))
        _, K, dist, rv, tv = cv2.calibrateCamera(obj, pts, size, None, None, flags=flags)
        rvecs, tvecs = [r.ravel() for r in rv], [t.ravel() for t in tv]
    else:
        K, dist, r0, t0 = guess or (camera.K, camera.dist_coeffs, None, None)  # type: ignore[union-attr]
        rvecs, tvecs = [], []
        for k, (o, p) in enumerate(zip(obj, pts, strict=True)):
            if r0 is None:
                _, r, t = cv2.solvePnP(o, p, K, dist, flags=cv2.SOLVEPNP_IPPE)
                _, r, t = cv2.solvePnP(o, p, K, dist, r, t, useExtrinsicGuess=True)
            else:
                _, r, t = cv2.solvePnP(o, p, K, dist, r0[k].copy(), t0[k].copy(),
                                       useExtrinsicGuess=True)
            rvecs.append(r.ravel())
            tvecs.append(t.ravel())
    K, d5 = np.asarray(K, dtype=np.float64), np.zeros(5)
    d5[: min(5, np.asarray(dist).size)] = np.asarray(dist, dtype=np.float64).ravel()[:5]
    dist = d5
    res_px, per_view = [], []
    for o, p, r, t in zip(obj, pts, rvecs, tvecs, strict=True):
        proj, _ = cv2.projectPoints(o, r, t, K, dist)
        d = (proj - p).reshape(-1, 2)
        res_px.append(d)
        per_view.append(float(np.sqrt(np.mean(np.sum(d**2, axis=1)))))
    noise = corner_noise_px(np.concatenate(res_px))
    C = [SE3.from_rotvec(t, r) for r, t in zip(rvecs, tvecs, strict=True)]
    A, B = motion_pairs(list(flanges), C)
    if method in ROBOT_WORLD_METHODS:
        X, _ = solve_ax_zb(flanges, C, method=method)  # type: ignore[arg-type]
    else:
        X = solve_ax_xb(A, B, method=method)  # type: ignore[arg-type]
    covs = pose_covariances(obj, rvecs, tvecs, K, dist, noise)
    pred = predicted_pair_translation_mm(rvecs, tvecs, covs)
    bb = [f @ X @ c for f, c in zip(flanges, C, strict=True)]
    W = SE3(Rotation.from_matrix(np.stack([b.rotation for b in bb])).mean().as_matrix(),
            np.mean([b.translation for b in bb], axis=0))
    return _Stage(K, dist, rvecs, tvecs, np.asarray(per_view), noise, X,
                  handeye_residuals(A, B, X), float(np.sqrt(np.mean(pred**2))), W)


def _worst(labels: Sequence[str], z: NDArray[np.float64]) -> list[str]:
    """The views that stand out, worst first, or else the two with the highest scores."""
    return [labels[i] for i in np.argsort(z)[::-1][: int((z > OUTLIER_Z).sum()) or 2]]


def _check_mode(F: Sequence[SE3], st: _Stage, mode: str, source: str) -> None:
    """Refuse views of the other mode: their rotations fit it, and not this one."""
    rot = st.residuals.rms_rotation_deg
    if rot <= MAX_ROTATION_RMS_DEG:
        return
    C = [SE3.from_rotvec(t, r) for r, t in zip(st.rvecs, st.tvecs, strict=True)]
    A, B = motion_pairs([f.inv() for f in F], C)
    try:
        other = handeye_residuals(A, B, solve_ax_xb(A, B)).rms_rotation_deg
    except InputError:
        return
    if other <= MAX_ROTATION_RMS_DEG:
        o = VIEW_MODES[1 - VIEW_MODES.index(mode)]
        what = ("a fixed camera and the board on the flange" if o == "eye-to-hand"
                else "the camera on the flange and the board fixed")
        raise InputError(f"{source}: the views look {o} ({what}), not {mode}: AX = XB "
                         f"rotation RMS {rot:.3g} deg as {mode}, {other:.2g} deg as {o}; "
                         f"give mode {o} (--mode {o}, or mode: {o} in views.yaml)")


def calibrate_eye_in_hand(
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
    tangential: Tangential = "test",
) -> EyeInHandCalibration:
    """Intrinsics, distortion and ``T_flange_camera`` from views of a calibration board.

    Parameters
    ----------
    images : sequence of array_like, shape (H, W)
        Grey views of the board (one size).
    flange_poses : sequence of SE3
        ``T_base_flange`` the robot reported at each view, millimetres.
    board : Chessboard or Charuco
    pixel_pitch_mm : float
        Horizontal pixel pitch of the sensor (its data sheet), to express the focal
        length in millimetres; the vertical pitch follows from ``fy``.
    grey_levels : int
        Grey levels of the camera (for the :class:`Camera` returned).
    method : {'park', 'tsai', 'daniilidis', 'shah', 'li'}
        Closed form that starts the refinement: AX = XB
        (:func:`~robostereo.robot.handeye.ax_xb.solve_ax_xb`) or OpenCV's AX = ZB
        (:func:`~robostereo.robot.handeye.ax_zb.solve_ax_zb`).
    names : sequence of str, optional
        View names for messages (default ``view 0``, ``view 1``, ...).
    fix_k3 : bool
        Hold the sixth-order radial term ``k3`` at 0 (default): a board that does not
        reach the image corners leaves ``k2`` and ``k3`` free to trade off against each
        other (seen: ``k2 = 0.8, k3 = -8.5`` for a true ``0.03, 0``).
    camera : Camera, optional
        Known intrinsics and distortion: held fixed (only ``X`` and the board pose are
        refined); its image size must be the views'.
    refine : bool
        Run the joint refinement (:func:`~robostereo.robot.handeye.refine.
        refine_eye_in_hand`) after the closed form (default).
    reject_outliers : bool
        Drop the view that stands out most in the closed-form stage (robust z-score
        above 3.5, :func:`~robostereo.robot.handeye.checks.view_scores`) and solve
        again, one view at a time while one stands out, at most a third of the views.
    source : str
        The input's name for messages (e.g. the views.yaml path).
    tangential : {'test', 'fit', 'zero'}
        The decentering terms ``p1, p2`` in the refinement: fitted, then held at 0 unless
        the views show them (``'test'``, the default: Wald's test at 1 %,
        :func:`~robostereo.robot.handeye.refine.tangential_chi2`), always fitted, or held
        at 0 throughout (OpenCV's ``CALIB_ZERO_TANGENT_DIST``).  Freed where the lens has
        none, they trade with the principal point and so with the hand-eye rotation.

    Returns
    -------
    EyeInHandCalibration

    Raises
    ------
    InputError
        Images of different sizes, a chessboard not found in a view (naming it), fewer
        than :data:`MIN_VIEWS` views (for a ChArUco board: views with enough corners),
        flange rotations about one axis only, or an implausible
        result (:func:`~robostereo.robot.handeye.checks.check_plausible`: wrong board
        or square size, flange positions in metres, poses paired with the wrong images).

    Notes
    -----
    1. :func:`~robostereo.robot.handeye.boards.view_corners` in every view: a whole
       chessboard, or the ChArUco corners seen with their board points (a view with
       under 6 of them, or all on one line, is warned about and left out).
    2. :func:`cv2.calibrateCamera` (``k1, k2, p1, p2, k3``; each view with its own
       corners), or :func:`cv2.solvePnP` with the known `camera`, gives
       ``C_i = T_camera_board`` per view.
    3. :func:`~robostereo.robot.handeye.ax_xb.motion_pairs`,
       :func:`~robostereo.robot.handeye.ax_xb.solve_ax_xb` (Tsai-Lenz or Park-Martin
       rotation, then ``(R_A - I) t_X = R_X t_B - t_A``),
       :func:`~robostereo.robot.handeye.ax_xb.handeye_residuals`; with
       `reject_outliers`, the worst view that stands out is dropped and 2-3 repeated.
    4. The corner noise's prediction of the pair translation residuals (:func:`~robostereo.
       robot.handeye.checks.predicted_pair_translation_mm`) bounds them; a result
       beyond the bounds is refused.
    5. Joint refinement of the intrinsics (unless known), ``X`` and ``T_base_board`` on
       all corners, flange poses fixed (Strobl and Hirzinger 2006; Koide and Menegatti
       2019); a reprojection RMS above 1 px is refused.  With ``tangential='test'``,
       refined again with ``p1 = p2 = 0`` where their chi-square is below the 1 %
       quantile.
    6. Final board poses by :func:`cv2.solvePnP` with the final intrinsics, the pair
       residuals with the final ``X``, checked again as in 4 (with known intrinsics,
       against the noise of the views' own :func:`cv2.calibrateCamera` fit, which wrong
       intrinsics do not inflate), the views that stand out named.
    """
    return solve_views(images, flange_poses, board, mode="eye-in-hand",
                       pixel_pitch_mm=pixel_pitch_mm, grey_levels=grey_levels, method=method,
                       names=names, fix_k3=fix_k3, camera=camera, refine=refine,
                       reject_outliers=reject_outliers, source=source,
                       tangential=tangential)


def solve_views(
    images: Sequence[ArrayLike],
    flange_poses: Sequence[SE3],
    board: Board,
    *,
    mode: HandEyeMode = "eye-in-hand",
    pixel_pitch_mm: float = 0.01,
    grey_levels: int = 256,
    method: SolveMethod = DEFAULT_METHOD,
    names: Sequence[str] | None = None,
    fix_k3: bool = True,
    camera: Camera | None = None,
    refine: bool = True,
    reject_outliers: bool = False,
    source: str = "hand-eye views",
    tangential: Tangential = "test",
) -> EyeInHandCalibration:
    """The solve both hand-eye modes share (:func:`calibrate_eye_in_hand`'s steps).

    Eye-to-hand (a fixed camera, the board on the flange: ``C_i = Z^-1 F_i Y``, AX = ZB)
    is eye-in-hand (``C_i = X^-1 F_i^-1 W``) with the flange poses inverted: then the
    pairwise motions ``A = F_j F_i^-1`` and ``B = C_j C_i^-1`` satisfy ``A Z = Z B``,
    the closed forms, checks and joint refinement apply unchanged, and the result's
    ``hand_eye`` is ``Z = T_base_camera``, its ``base_board`` ``Y = T_flange_board``
    (:func:`~robostereo.robot.handeye.eye_to_hand.calibrate_eye_to_hand` names them so).

    Parameters
    ----------
    images, flange_poses, board
        As :func:`calibrate_eye_in_hand` (``flange_poses`` as the robot reports them,
        ``T_base_flange``, in both modes).
    mode : {'eye-in-hand', 'eye-to-hand'}
    pixel_pitch_mm, grey_levels, method, names, fix_k3, camera, refine, reject_outliers, source
    tangential
        As :func:`calibrate_eye_in_hand`.

    Returns
    -------
    EyeInHandCalibration
        With ``hand_eye`` and ``base_board`` in the sense of `mode` (above).

    Raises
    ------
    InputError
        As :func:`calibrate_eye_in_hand`, and views whose rotations fit the other mode
        but not `mode` (naming the mode they look like).
    """
    if mode not in VIEW_MODES:
        raise InputError(f"mode must be one of {', '.join(VIEW_MODES)}, got {mode!r}")
    if tangential not in TANGENTIAL_CHOICES:
        raise InputError(f"tangential must be one of {', '.join(TANGENTIAL_CHOICES)}, got "
                         f"{tangential!r}")
    n = len(images)
    if len(flange_poses) != n:
        raise InputError(f"images and flange_poses must be as many, got {n} and "
                         f"{len(flange_poses)}")
    labels = list(names) if names is not None else [f"view {i}" for i in range(n)]
    if len(labels) != n:
        raise InputError(f"names must be as many as the images ({n}), got {len(labels)}")
    if n < MIN_VIEWS:
        raise InputError(f"hand-eye needs at least {MIN_VIEWS} usable views, got {n}")
    shapes = {np.asarray(im).shape for im in images}
    if len(shapes) != 1:
        raise InputError(f"the views must have one size, got shapes {sorted(shapes)}")
    h, w = next(iter(shapes))[:2]
    if camera is not None and tuple(camera.image_size) != (w, h):
        raise InputError(f"camera: image size {camera.image_size[0]} x "
                         f"{camera.image_size[1]} is not the views' {w} x {h}")
    obj, img_pts, F = [], [], []
    kept, left_out = [], []
    for im, name, f in zip(images, labels, flange_poses, strict=True):
        found = view_corners(np.asarray(im), board)
        if isinstance(found, str):
            if isinstance(board, Chessboard):
                raise InputError(f"{name}: {describe_board(board)} {found}")
            # a ChArUco view may show little of the board: named, left out
            warn_input(f"{name}: {describe_board(board)}: {found}; view left out")
            left_out.append(name)
            continue
        obj.append(found[0].astype(np.float64).reshape(-1, 1, 3))
        img_pts.append(found[1].astype(np.float64).reshape(-1, 1, 2))
        F.append(f.inv() if mode == "eye-to-hand" else f)
        kept.append(name)
    if len(kept) < MIN_VIEWS:
        raise InputError(f"{source}: hand-eye needs at least {MIN_VIEWS} usable views, got "
                         f"{len(kept)}: the {describe_board(board)} is found in too few "
                         f"views ({', '.join(left_out[:3])}{', ...' if len(left_out) > 3 else ''}"
                         "); check the board's squares, marker_mm and dictionary")
    labels, n = kept, len(kept)
    obj32 = [o.astype(np.float32) for o in obj]
    pts32 = [p.astype(np.float32) for p in img_pts]
    if camera is not None:
        check_intrinsics(obj32, pts32, (w, h), camera.K, camera.dist_coeffs,
                         source=f"{source}: the known intrinsics")
    zero = tangential == "zero"
    st = _board_poses(obj32, pts32, (w, h), F, camera, fix_k3, method, zero_tangent=zero)
    _check_mode(F, st, mode, source)
    z = view_scores(st.per_view, st.residuals.translation_mm, st.residuals.rotation_deg, n)
    rejected: list[str] = []
    # one view at a time, the worst first: a wrong view biases X and so the others' scores
    while reject_outliers and z.max() > OUTLIER_Z and len(F) > max(MIN_VIEWS, 2 * n // 3):
        keep = np.flatnonzero(np.arange(len(F)) != int(np.argmax(z)))
        rejected.append(labels[int(np.argmax(z))])
        obj, img_pts, obj32, pts32, F, labels = (
            [seq[i] for i in keep] for seq in (obj, img_pts, obj32, pts32, F, labels))
        st = _board_poses(obj32, pts32, (w, h), F, camera, fix_k3, method,
                          zero_tangent=zero)
        z = view_scores(st.per_view, st.residuals.translation_mm, st.residuals.rotation_deg,
                        len(F))
    check_plausible(rotation_rms_deg=st.residuals.rms_rotation_deg,
                    translation_rms_mm=st.residuals.rms_translation_mm,
                    predicted_translation_rms_mm=st.predicted, reprojection_rms_px=None,
                    source=source, worst=_worst(labels, z), known_intrinsics=camera is not None)
    K, dist, X, W = st.K, st.dist, st.X, st.base_board
    terms, chi2 = "", math.nan
    if refine:
        ref = refine_eye_in_hand([o.reshape(-1, 3) for o in obj],
                                 [p.reshape(-1, 2) for p in img_pts], F, K, dist, X, W,
                                 fix_intrinsics=camera is not None, fix_k3=fix_k3,
                                 tangential=tangential, noise_px=st.noise)
        terms, chi2 = ref.tangential, ref.tangential_chi2
        check_plausible(rotation_rms_deg=0.0, translation_rms_mm=0.0,
                        predicted_translation_rms_mm=st.predicted,
                        reprojection_rms_px=ref.rms_px, source=source,
                        worst=[labels[i] for i in np.argsort(ref.per_view_rms_px)[::-1][:2]])
        K, dist, X, W = ref.K, ref.dist, ref.hand_eye, ref.base_board
        st_final = _board_poses(obj, img_pts, (w, h), F, None, fix_k3, method,
                                guess=(K, dist, st.rvecs, st.tvecs))
        per_view = ref.per_view_rms_px
        rms = ref.rms_px
        sigma = (ref.hand_eye_sigma_mm, ref.hand_eye_sigma_deg)
        advice = advise_views([o.reshape(-1, 3) for o in obj], F, K, dist, X, W,
                              board.object_points, (w, h), ref.variance_px2,
                              fix_intrinsics=camera is not None, fix_k3=fix_k3,
                              fix_tangential=terms == "held", mode=mode,
                              information=ref.information)
    else:
        st_final, per_view = st, st.per_view
        rms = float(np.sqrt(np.mean(per_view**2)))
        sigma = (math.nan, math.nan)
        advice = None
    C = [SE3.from_rotvec(t, r) for r, t in zip(st_final.rvecs, st_final.tvecs, strict=True)]
    res = handeye_residuals(*motion_pairs(F, C), X)
    # the checks again on the final result; with known intrinsics, against the noise of
    # the views' own intrinsics (wrong ones inflate the noise and so their own bound)
    predicted = st.predicted if camera is None else _board_poses(
        obj32, pts32, (w, h), F, None, fix_k3, method).predicted
    check_plausible(rotation_rms_deg=res.rms_rotation_deg,
                    translation_rms_mm=res.rms_translation_mm,
                    predicted_translation_rms_mm=predicted, reprojection_rms_px=None,
                    source=source, known_intrinsics=camera is not None,
                    worst=[labels[i] for i in np.argsort(per_view)[::-1][:2]])
    flagged = outlier_views(per_view, res.translation_mm, res.rotation_deg, len(F))
    fmm = float(K[0, 0]) * pixel_pitch_mm
    cam = camera if camera is not None else Camera(
        focal_length_mm=fmm, pixel_pitch_mm=(pixel_pitch_mm, fmm / float(K[1, 1])),
        image_size=(int(w), int(h)), principal_point=(float(K[0, 2]), float(K[1, 2])),
        grey_levels=grey_levels, distortion=tuple(float(v) for v in dist.ravel()[:5]),
    )
    return EyeInHandCalibration(
        camera=cam, hand_eye=X, method=method, reprojection_rms_px=rms,
        per_view_rms_px=np.asarray(per_view), board_poses=tuple(C), residuals=res,
        base_board=W, names=tuple(labels), closed_form=st.X if refine else None,
        corner_noise_px=st.noise, predicted_translation_rms_mm=predicted,
        outliers=tuple(labels[i] for i in np.flatnonzero(flagged)), rejected=tuple(rejected),
        corners_per_view=None if isinstance(board, Chessboard) else np.array(
            [len(o) for o in obj], dtype=np.int64),
        left_out=tuple(left_out), hand_eye_sigma_mm=sigma[0], hand_eye_sigma_deg=sigma[1],
        advice=advice, tangential=terms, tangential_chi2=chi2,
    )
