"""Self-checks of an eye-in-hand calibration: expected residuals, outlier views, bounds.

A wrong square size, flange positions in metres read as millimetres, or images paired
with the wrong flange poses still give SOME transform; what gives them away is that
the AX = XB residuals are far above what the corner noise can explain.  This module
predicts that level (:func:`predicted_pair_translation_mm`), names the views that stand
out (:func:`outlier_views`) and refuses implausible results (:func:`check_plausible`).
Known intrinsics that the views contradict (a focal length 2 % off moves the hand-eye
transform by millimetres, with residuals that still look plausible) are warned about by
:func:`check_intrinsics`.
"""

from __future__ import annotations

from collections.abc import Sequence

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from robostereo.errors import InputError, warn_input

__all__ = [
    "INTRINSICS_FLOORS",
    "INTRINSICS_SIGMAS",
    "MAX_REPROJECTION_RMS_PX",
    "MAX_ROTATION_RMS_DEG",
    "OUTLIER_Z",
    "TRANSLATION_FACTOR",
    "TRANSLATION_FLOOR_MM",
    "check_intrinsics",
    "check_plausible",
    "corner_noise_px",
    "outlier_views",
    "pose_covariances",
    "predicted_pair_translation_mm",
    "robust_z",
    "view_scores",
]

MAX_ROTATION_RMS_DEG = 1.0
"""AX = XB rotation RMS above which a result is refused (normal: 0.01-0.05 deg)."""
TRANSLATION_FACTOR = 5.0
"""A translation RMS above this many times the predicted one is refused."""
TRANSLATION_FLOOR_MM = 1.0
"""...and above this floor (the flange's own repeatability and unmodelled errors)."""
MAX_REPROJECTION_RMS_PX = 1.0
"""Reprojection RMS of the joint refinement above which a result is refused."""
OUTLIER_Z = 3.5
"""Robust z-score above which a view stands out (Iglewicz and Hoaglin's cut-off)."""


def corner_noise_px(residuals: ArrayLike) -> float:
    """The corner noise (one coordinate, pixels): 1.4826 times the median absolute
    residual coordinate (a robust standard deviation), at least 0.005 px.

    >>> round(corner_noise_px([0.1, -0.1, 0.1, -0.1, 5.0]), 4)
    0.1483
    """
    r = np.abs(np.asarray(residuals, dtype=np.float64).ravel())
    return max(1.4826 * float(np.median(r)), 0.005) if r.size else 0.005


def pose_covariances(object_points: Sequence[NDArray[np.float64]],
                     rvecs: Sequence[ArrayLike], tvecs: Sequence[ArrayLike],
                     K: NDArray[np.float64], dist: NDArray[np.float64],
                     noise_px: float) -> NDArray[np.float64]:
    """Covariance of each view's board pose ``(rvec, tvec)`` from the corner noise.

    ``Cov_i = sigma^2 (J_i^T J_i)^-1`` with ``J_i`` the Jacobian of view i's corner
    projections with respect to its rotation vector and translation
    (:func:`cv2.projectPoints`), shape ``(N, 6, 6)`` (rad and mm).
    """
    covs = []
    for o, r, t in zip(object_points, rvecs, tvecs, strict=True):
        _, jac = cv2.projectPoints(np.asarray(o, dtype=np.float64).reshape(-1, 1, 3),
                                   np.asarray(r, dtype=np.float64).reshape(3, 1),
                                   np.asarray(t, dtype=np.float64).reshape(3, 1), K, dist)
        J = jac[:, :6]
        covs.append(noise_px**2 * np.linalg.pinv(J.T @ J))
    return np.asarray(covs)


def _rotation_derivatives(rvec: NDArray[np.float64], h: float = 1e-6) -> NDArray[np.float64]:
    """``dR/dr_k`` for k = 0, 1, 2 (central differences), shape (3, 3, 3)."""
    out = []
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        out.append((Rotation.from_rotvec(rvec + e).as_matrix()
                    - Rotation.from_rotvec(rvec - e).as_matrix()) / (2 * h))
    return np.asarray(out)


def predicted_pair_translation_mm(rvecs: Sequence[ArrayLike], tvecs: Sequence[ArrayLike],
                                  covariances: NDArray[np.float64]) -> NDArray[np.float64]:
    """Expected AX = XB translation residual of each pair ``i < j`` from the corner noise.

    Parameters
    ----------
    rvecs, tvecs : sequence of array_like, shape (3,)
        ``C_i = T_camera_board`` of each view.
    covariances : ndarray, shape (N, 6, 6)
        :func:`pose_covariances`.

    Returns
    -------
    ndarray, shape (N (N - 1) / 2,)
        Root of the expected squared residual, mm, in the order of
        :func:`~robostereo.robot.handeye.ax_xb.motion_pairs`.

    Notes
    -----
    With ``W_i = F_i X C_i`` (the board in the base frame as view i sees it), the pair's
    translation residual is ``|A X(0) - X B(0)| = |W_i(c_i) - W_j(c_i)|``, where
    ``c_i = -R_i^T t_i`` is camera i's centre in the board frame: the two views'
    estimates of the board, compared at camera i (about 400 mm from the board, so the
    board poses' rotation errors dominate).  ``W_i(c_i) = F_i X (0)`` carries no noise;
    the residual's noise is that of ``C_j(c_i)``:

        ``E|e_ij|^2 = tr(G_j Cov_j G_j^T) + tr(H_i Cov_i H_i^T)``

    with ``G_j = d(R_j p + t_j)/d(r_j, t_j)`` at ``p = c_i`` and ``H_i = dc_i/d(r_i,
    t_i)`` (the flange poses exact, the views independent, first order).  On views with
    pure Gaussian corner noise the closed form's residual RMS is 0.84-1.17 times this
    prediction (``tests/robot/handeye/test_checks.py``).

    Examples
    --------
    >>> K = np.array([[800.0, 0, 320], [0, 800, 240], [0, 0, 1]])
    >>> obj = np.array([[i * 20.0, j * 20.0, 0.0] for j in range(5) for i in range(8)])
    >>> rv = [np.array([0.1, 0.0, 0.0]), np.array([0.0, 0.15, 0.3])]
    >>> tv = [np.array([-70.0, -40.0, 450.0])] * 2
    >>> cov = pose_covariances([obj] * 2, rv, tv, K, np.zeros(5), 0.05)
    >>> pred = predicted_pair_translation_mm(rv, tv, cov)
    >>> pred.shape, bool(0.05 < pred[0] < 2.0)
    ((1,), True)
    >>> cov2 = pose_covariances([obj] * 2, rv, tv, K, np.zeros(5), 0.1)
    >>> round(float(predicted_pair_translation_mm(rv, tv, cov2)[0] / pred[0]), 6)
    2.0
    """
    r = [np.asarray(v, dtype=np.float64).ravel() for v in rvecs]
    t = [np.asarray(v, dtype=np.float64).ravel() for v in tvecs]
    n = len(r)
    R = [Rotation.from_rotvec(v).as_matrix() for v in r]
    dR = [_rotation_derivatives(v) for v in r]
    centres = np.array([-R[i].T @ t[i] for i in range(n)])
    # H_i: dc_i/dr = -(dR/dr_k)^T t, dc_i/dt = -R^T
    var_c = np.empty(n)
    for i in range(n):
        H = np.column_stack([-dR[i][k].T @ t[i] for k in range(3)] + [-R[i].T])
        var_c[i] = np.trace(H @ covariances[i] @ H.T)
    out = []
    for i in range(n):
        for j in range(i + 1, n):
            p = centres[i]
            G = np.column_stack([dR[j][k] @ p for k in range(3)] + [np.eye(3)])
            out.append(np.trace(G @ covariances[j] @ G.T) + var_c[i])
    return np.sqrt(np.asarray(out))


def robust_z(values: ArrayLike, *, floor: float = 0.0) -> NDArray[np.float64]:
    """Robust z-scores ``0.6745 (x - median) / MAD`` (Iglewicz and Hoaglin 1993).

    The MAD is held at least `floor` (and above 0), so identical values give z = 0.

    >>> robust_z([1.0, 1.1, 0.9, 1.0, 5.0]).round(2)
    array([ 0.  ,  0.67, -0.67,  0.  , 26.98])
    """
    x = np.asarray(values, dtype=np.float64)
    med = float(np.median(x))
    mad = max(float(np.median(np.abs(x - med))), floor, 1e-12)
    return 0.6745 * (x - med) / mad


def view_scores(per_view_rms_px: ArrayLike, pair_translation_mm: ArrayLike,
                pair_rotation_deg: ArrayLike, n_views: int) -> NDArray[np.float64]:
    """How much each view's residuals stand out: the largest of three robust z-scores.

    A view stands out (:func:`outlier_views`) when its reprojection RMS, or the median
    of the AX = XB residuals (translation, or rotation) of the pairs it is in, has a
    robust z-score
    (:func:`robust_z`) above 3.5; only high values count.  The median over a view's
    pairs is not raised by one bad partner, so a wrong view does not drag the others
    along.  The MAD floors are 0.01 px, 0.05 mm and 0.005 deg (below them differences
    are noise).

    Returns
    -------
    ndarray, shape (N,)
    """
    iu = np.triu_indices(n_views, 1)
    tr = np.asarray(pair_translation_mm, dtype=np.float64)
    rot = np.asarray(pair_rotation_deg, dtype=np.float64)
    if iu[0].size != tr.size or tr.size != rot.size:
        raise InputError(f"expected {iu[0].size} pair residuals for {n_views} views, got "
                         f"{tr.size} and {rot.size}")

    def per_view(values: NDArray[np.float64]) -> NDArray[np.float64]:
        m = np.full((n_views, n_views), np.nan)
        m[iu] = values
        m.T[iu] = values
        return np.nanmedian(m, axis=1)

    return np.maximum.reduce([robust_z(per_view_rms_px, floor=0.01),
                              robust_z(per_view(tr), floor=0.05),
                              robust_z(per_view(rot), floor=0.005)])


def outlier_views(per_view_rms_px: ArrayLike, pair_translation_mm: ArrayLike,
                  pair_rotation_deg: ArrayLike, n_views: int) -> NDArray[np.bool_]:
    """Views whose :func:`view_scores` exceed :data:`OUTLIER_Z`, shape (N,)."""
    return view_scores(per_view_rms_px, pair_translation_mm, pair_rotation_deg,
                       n_views) > OUTLIER_Z


def check_plausible(*, rotation_rms_deg: float, translation_rms_mm: float,
                    predicted_translation_rms_mm: float, reprojection_rms_px: float | None,
                    source: str, worst: Sequence[str] = (),
                    known_intrinsics: bool = False) -> None:
    """Raise :class:`InputError` on a hand-eye result the corner noise cannot explain.

    Refused: AX = XB rotation RMS above :data:`MAX_ROTATION_RMS_DEG`; translation RMS
    above ``max(TRANSLATION_FACTOR * predicted, TRANSLATION_FLOOR_MM)`` (the predicted
    RMS of :func:`predicted_pair_translation_mm`); a reprojection RMS of the joint
    refinement above :data:`MAX_REPROJECTION_RMS_PX`.  The one-line message names
    `source`, the figures, the likely causes (with `known_intrinsics`, those first)
    and the `worst` views.

    >>> check_plausible(rotation_rms_deg=0.02, translation_rms_mm=42.0,
    ...                 predicted_translation_rms_mm=0.1, reprojection_rms_px=None,
    ...                 source="views.yaml")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: views.yaml: implausible hand-eye result: AX = XB ...
    """
    bound = max(TRANSLATION_FACTOR * predicted_translation_rms_mm, TRANSLATION_FLOOR_MM)
    why = []
    if not rotation_rms_deg <= MAX_ROTATION_RMS_DEG:
        why.append(f"AX = XB rotation RMS {rotation_rms_deg:.3g} deg > "
                   f"{MAX_ROTATION_RMS_DEG:g} deg")
    if not translation_rms_mm <= bound:
        why.append(f"AX = XB translation RMS {translation_rms_mm:.3g} mm > {bound:.3g} mm "
                   f"(the corner noise explains {predicted_translation_rms_mm:.2g} mm)")
    if reprojection_rms_px is not None and not reprojection_rms_px <= MAX_REPROJECTION_RMS_PX:
        why.append(f"joint reprojection RMS {reprojection_rms_px:.3g} px > "
                   f"{MAX_REPROJECTION_RMS_PX:g} px")
    if not why:
        return
    views = f"; worst views: {', '.join(worst)}" if worst else ""
    first = "the known intrinsics (--intrinsics), " if known_intrinsics else ""
    raise InputError(
        f"{source}: implausible hand-eye result: {'; '.join(why)}; check {first}the board "
        "size and square_mm, the flange positions' unit (unit: m for metres), and the pose "
        f"order and convention (T_base_flange, each with its own image){views}")


INTRINSICS_SIGMAS = 6.0
"""Known intrinsics further than this many standard deviations from the views' own
estimate (and beyond :data:`INTRINSICS_FLOORS`) are warned about."""
INTRINSICS_FLOORS = {"fx": 0.003, "fy": 0.003, "cx": 3.0, "cy": 3.0, "k1": 0.01}
"""Least disagreement warned about: focal lengths relative (0.3 %), principal point in
pixels, ``k1`` absolute (what the corner detector's bias alone can give)."""


def check_intrinsics(object_points: Sequence[NDArray[np.float64]],
                     image_points: Sequence[NDArray[np.float64]], image_size: tuple[int, int],
                     K: NDArray[np.float64], dist: ArrayLike, *, source: str) -> list[str]:
    """Warn when known intrinsics disagree with what the board views say.

    :func:`cv2.calibrateCameraExtended` on the views alone (no robot poses; ``k3``
    held at 0) estimates ``fx, fy, cx, cy, k1`` and their standard deviations; a
    known value further than :data:`INTRINSICS_SIGMAS` deviations and
    :data:`INTRINSICS_FLOORS` from it gets one :func:`~robostereo.errors.warn_input`
    line naming the parameter, both values and how far apart they are.

    Parameters
    ----------
    object_points, image_points : sequence of ndarray, shape (K_i, 1, 3) and (K_i, 1, 2)
        Board corners (float32) and their pixels per view.
    image_size : tuple of int
        ``(width, height)``.
    K, dist : ndarray
        The known camera matrix ``(3, 3)`` and distortion ``(k1, k2, p1, p2[, k3])``.
    source : str
        The known intrinsics' name for the message (e.g. ``--intrinsics camera.yaml``).

    Returns
    -------
    list of str
        The parameters warned about (empty when they agree).
    """
    _, K2, d2, _, _, sd, _, _ = cv2.calibrateCameraExtended(
        list(object_points), list(image_points), image_size, None, None,
        flags=cv2.CALIB_FIX_K3)
    sd = np.asarray(sd, dtype=np.float64).ravel()
    d = np.asarray(dist, dtype=np.float64).ravel()
    k1 = float(d[0]) if d.size else 0.0
    views = {"fx": (K2[0, 0], sd[0]), "fy": (K2[1, 1], sd[1]), "cx": (K2[0, 2], sd[2]),
             "cy": (K2[1, 2], sd[3]), "k1": (float(np.ravel(d2)[0]), sd[4])}
    given = {"fx": K[0, 0], "fy": K[1, 1], "cx": K[0, 2], "cy": K[1, 2], "k1": k1}
    named = []
    for name, (v, s) in views.items():
        floor = INTRINSICS_FLOORS[name] * (abs(v) if name in ("fx", "fy") else 1.0)
        gap = float(given[name]) - float(v)
        if abs(gap) > max(INTRINSICS_SIGMAS * float(s), floor):
            unit = "" if name == "k1" else " px"
            rel = f", {100 * gap / v:+.1f} %" if name in ("fx", "fy") else ""
            named.append(f"{name} {float(given[name]):.4g}{unit} where the views put it at "
                         f"{float(v):.4g} +- {float(s):.2g}{unit} ({gap:+.3g}{unit}{rel})")
    if named:
        warn_input(f"{source} disagree with the board views: {'; '.join(named)}; the "
                   "hand-eye result follows the intrinsics given (a focal length 2 % off "
                   "moves it by millimetres): check them, or leave them out to estimate them")
    return [n.split()[0] for n in named]
