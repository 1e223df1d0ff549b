"""AX = XB: the camera's pose on the robot's flange from paired motions (closed forms).

The thesis's camera pose came from the robot alone (a fixed forearm mount, 4.1).
A camera bolted to any arm's flange needs the flange-to-camera transform
``X = T_flange_camera``.  With the flange poses ``F_i = T_base_flange`` the robot
reports and the board poses ``C_i = T_camera_board`` seen in each view,
``F_i X C_i = T_base_board`` is the same for every view, so for every pair of views

    ``A X = X B``,   ``A = F_j^-1 F_i``,   ``B = C_j C_i^-1``.

OpenCV 5's Python package no longer exposes ``calibrateHandEye``; this module
solves AX = XB with the published closed forms on numpy and scipy:

* ``'tsai'``: Tsai and Lenz (1989), rotation from the modified Rodrigues vectors;
* ``'park'``: Park and Martin (1994), rotation from the logarithms,
  ``R_X = (M^T M)^(-1/2) M^T`` with ``M = sum beta_i alpha_i^T``;
* ``'daniilidis'``: Daniilidis (1999), rotation and translation together from the
  null space of the stacked dual-quaternion equations.

For ``'tsai'`` and ``'park'`` the translation is the least-squares solution of
``(R_A - I) t_X = R_X t_B - t_A``.  All pairs of views are used.

:func:`motion_pairs` makes the motions of every pair of views, :func:`solve_ax_xb`
solves for ``X`` (refusing rotations about one axis, :func:`check_rotation_axes`) and
:func:`handeye_residuals` measures how well an ``X`` fits.  The whole calibration from
board images is :func:`~robostereo.robot.handeye.calibrate.calibrate_eye_in_hand`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import sqrtm
from scipy.spatial.transform import Rotation

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3

__all__ = [
    "DEFAULT_METHOD",
    "METHODS",
    "HandEyeMethod",
    "HandEyeResiduals",
    "check_rotation_axes",
    "handeye_residuals",
    "motion_pairs",
    "solve_ax_xb",
]

HandEyeMethod = Literal["tsai", "park", "daniilidis"]
METHODS: tuple[str, ...] = ("tsai", "park", "daniilidis")
DEFAULT_METHOD: HandEyeMethod = "park"
"""The default method: the most accurate of the three on the simulated views (see
the hand-eye table in docs/guide/robot.md; Park-Martin and Daniilidis are within a few
percent, Tsai-Lenz behind)."""
MIN_AXIS_SPREAD_DEG = 2.0  # least angle between the motions' rotation axes


def _skew(v: NDArray[np.float64]) -> NDArray[np.float64]:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def motion_pairs(
    flange_poses: Sequence[SE3], board_poses: Sequence[SE3]
) -> tuple[list[SE3], list[SE3]]:
    """The motions ``A = F_j^-1 F_i`` and ``B = C_j C_i^-1`` of every pair ``i < j``.

    Parameters
    ----------
    flange_poses : sequence of SE3
        ``F_i = T_base_flange`` of each view (mm).
    board_poses : sequence of SE3
        ``C_i = T_camera_board`` of each view (mm), e.g. from :func:`cv2.calibrateCamera`.

    Returns
    -------
    A, B : list of SE3
        ``n (n - 1) / 2`` motions each.
    """
    if len(flange_poses) != len(board_poses):
        raise InputError(f"flange_poses and board_poses must be as many, got "
                         f"{len(flange_poses)} and {len(board_poses)}")
    A, B = [], []
    n = len(flange_poses)
    for i in range(n):
        for j in range(i + 1, n):
            A.append(flange_poses[j].inv() @ flange_poses[i])
            B.append(board_poses[j] @ board_poses[i].inv())
    return A, B


def check_rotation_axes(A: Sequence[SE3], *, min_spread_deg: float = MIN_AXIS_SPREAD_DEG) -> None:
    """Refuse motions whose rotations are (nearly) all about one axis.

    Rotations about one axis only (as any SCARA gives: every flange rotation is about
    the vertical) leave the hand-eye rotation's turn about that axis and the
    translation along it undetermined.

    Raises
    ------
    InputError
        Fewer than two motions with a rotation of at least 1 degree, or their axes all
        within `min_spread_deg` of one line.
    """
    axes = []
    for a in A:
        rv = a.rotvec
        ang = float(np.linalg.norm(rv))
        if ang > math.radians(1.0):
            axes.append(rv / ang)
    if len(axes) < 2:
        raise InputError("hand-eye: the flange hardly rotates between the views (need "
                         "rotations of at least 1 deg about two different axes)")
    ax = np.asarray(axes)
    # spread: largest angle between an axis and the principal axis (sign-free)
    _, _, vt = np.linalg.svd(ax, full_matrices=False)
    cosines = np.abs(ax @ vt[0])
    spread = math.degrees(math.acos(min(1.0, float(cosines.min()))))
    if spread < min_spread_deg:
        raise InputError(
            f"hand-eye: all flange rotations are about one axis (spread {spread:.2f} deg < "
            f"{min_spread_deg:g} deg), as a SCARA's are; tilt the flange about at least "
            "two different axes between the views"
        )


def _translation(A: Sequence[SE3], B: Sequence[SE3], R: NDArray[np.float64]) -> NDArray:
    M = np.vstack([a.rotation - np.eye(3) for a in A])
    rhs = np.concatenate([R @ b.translation - a.translation for a, b in zip(A, B, strict=True)])
    t, *_ = np.linalg.lstsq(M, rhs, rcond=None)
    return t


def _tsai(A: Sequence[SE3], B: Sequence[SE3]) -> SE3:
    rows, rhs = [], []
    for a, b in zip(A, B, strict=True):
        ra, rb = a.rotvec, b.rotvec
        ta, tb = np.linalg.norm(ra), np.linalg.norm(rb)
        pa = 2.0 * math.sin(ta / 2) * (ra / ta) if ta > 1e-12 else np.zeros(3)
        pb = 2.0 * math.sin(tb / 2) * (rb / tb) if tb > 1e-12 else np.zeros(3)
        rows.append(_skew(pa + pb))
        rhs.append(pb - pa)
    pc_, *_ = np.linalg.lstsq(np.vstack(rows), np.concatenate(rhs), rcond=None)
    pc = 2.0 * pc_ / math.sqrt(1.0 + float(pc_ @ pc_))
    n2 = float(pc @ pc)
    R = (1.0 - n2 / 2.0) * np.eye(3) + 0.5 * (np.outer(pc, pc)
                                              + math.sqrt(4.0 - n2) * _skew(pc))
    return SE3(R, _translation(A, B, R))


def _park(A: Sequence[SE3], B: Sequence[SE3]) -> SE3:
    M = np.zeros((3, 3))
    for a, b in zip(A, B, strict=True):
        M += np.outer(b.rotvec, a.rotvec)
    R = np.real(np.linalg.inv(sqrtm(M.T @ M))) @ M.T
    u, _, vt = np.linalg.svd(R)
    # the nearest rotation (det +1): garbled poses can make the nearest orthogonal
    # matrix a reflection, which the plausibility checks then catch
    R = u @ np.diag([1.0, 1.0, float(np.sign(np.linalg.det(u @ vt)))]) @ vt
    return SE3(R, _translation(A, B, R))


def _dual_quaternion(T: SE3) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    x, y, z, w = Rotation.from_matrix(T.rotation).as_quat()
    q = np.array([w, x, y, z])
    t = np.concatenate([[0.0], T.translation])
    return q, 0.5 * _qmul(t, q)


def _qmul(p: NDArray[np.float64], q: NDArray[np.float64]) -> NDArray[np.float64]:
    pw, pv = p[0], p[1:]
    qw, qv = q[0], q[1:]
    return np.concatenate([[pw * qw - pv @ qv], pw * qv + qw * pv + np.cross(pv, qv)])


def _daniilidis(A: Sequence[SE3], B: Sequence[SE3]) -> SE3:
    rows = []
    for a, b in zip(A, B, strict=True):
        qa, qa_d = _dual_quaternion(a)
        qb, qb_d = _dual_quaternion(b)
        if qa[0] * qb[0] < 0:  # one sign for both (A and B turn by the same angle)
            qb, qb_d = -qb, -qb_d
        va, vb, va_d, vb_d = qa[1:], qb[1:], qa_d[1:], qb_d[1:]
        S = np.zeros((6, 8))
        S[:3, 0] = va - vb
        S[:3, 1:4] = _skew(va + vb)
        S[3:, 0] = va_d - vb_d
        S[3:, 1:4] = _skew(va_d + vb_d)
        S[3:, 4] = va - vb
        S[3:, 5:8] = _skew(va + vb)
        rows.append(S)
    _, _, vt = np.linalg.svd(np.vstack(rows))
    v7, v8 = vt[-2], vt[-1]
    u1, w1, u2, w2 = v7[:4], v7[4:], v8[:4], v8[4:]
    a_ = u1 @ w1
    b_ = u1 @ w2 + u2 @ w1
    c_ = u2 @ w2
    disc = max(b_ * b_ - 4 * a_ * c_, 0.0)
    if abs(a_) < 1e-15:
        roots = [-c_ / b_] if abs(b_) > 1e-15 else [0.0]
    else:
        roots = [(-b_ + math.sqrt(disc)) / (2 * a_), (-b_ - math.sqrt(disc)) / (2 * a_)]
    vals = [s * s * (u1 @ u1) + 2 * s * (u1 @ u2) + u2 @ u2 for s in roots]
    k = int(np.argmax(vals))
    s = roots[k]
    l2 = 1.0 / math.sqrt(vals[k])
    l1 = s * l2
    q = l1 * u1 + l2 * u2
    q_d = l1 * w1 + l2 * w2
    q_conj = q * np.array([1.0, -1.0, -1.0, -1.0])
    t = 2.0 * _qmul(q_d, q_conj)[1:]
    R = Rotation.from_quat([q[1], q[2], q[3], q[0]]).as_matrix()
    return SE3(R, t)


_SOLVERS = {"tsai": _tsai, "park": _park, "daniilidis": _daniilidis}


def solve_ax_xb(
    A: Sequence[SE3], B: Sequence[SE3], *, method: HandEyeMethod = DEFAULT_METHOD
) -> SE3:
    """Solve ``A_i X = X B_i`` for the rigid transform ``X`` (closed forms).

    Parameters
    ----------
    A, B : sequence of SE3
        Paired motions (:func:`motion_pairs`): flange motions ``A_i`` and camera
        motions ``B_i``, millimetres.
    method : {'park', 'tsai', 'daniilidis'}
        Tsai-Lenz, Park-Martin or Daniilidis (module docstring).

    Returns
    -------
    SE3
        ``X = T_flange_camera``.

    Raises
    ------
    InputError
        Unknown method, fewer than two motions, rotations about one axis only.

    References
    ----------
    R. Tsai, R. Lenz, IEEE Trans. Robotics and Automation 5(3), 1989;
    F. Park, B. Martin, IEEE Trans. Robotics and Automation 10(5), 1994;
    K. Daniilidis, Int. J. Robotics Research 18(3), 1999.

    Examples
    --------
    >>> X = SE3.from_rotvec([10.0, -5.0, 80.0], [0.2, -0.1, 0.3])
    >>> A = [SE3.from_rotvec([1, 2, 3], [0.5, 0, 0]), SE3.from_rotvec([0, 5, 1], [0, 0.4, 0.2])]
    >>> B = [X.inv() @ a @ X for a in A]
    >>> [round(v, 9) for v in X.distance_to(solve_ax_xb(A, B, method="tsai"))]
    [0.0, 0.0]
    """
    if method not in _SOLVERS:
        raise InputError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if len(A) != len(B) or len(A) < 2:
        raise InputError(f"hand-eye needs at least 2 paired motions, got {len(A)} and {len(B)}")
    check_rotation_axes(A)
    return _SOLVERS[method](A, B)


@dataclass(frozen=True)
class HandEyeResiduals:
    """How well ``X`` fits ``A_i X = X B_i``.

    Attributes
    ----------
    rotation_deg : ndarray, shape (M,)
        Angle of ``(A_i X)^-1 (X B_i)`` per motion, degrees.
    translation_mm : ndarray, shape (M,)
        Norm of its translation ``|R_A t_X + t_A - R_X t_B - t_X|``, millimetres.
    """

    rotation_deg: NDArray[np.float64]
    translation_mm: NDArray[np.float64]

    @property
    def rms_rotation_deg(self) -> float:
        return float(np.sqrt(np.mean(self.rotation_deg**2)))

    @property
    def rms_translation_mm(self) -> float:
        return float(np.sqrt(np.mean(self.translation_mm**2)))


def handeye_residuals(A: Sequence[SE3], B: Sequence[SE3], X: SE3) -> HandEyeResiduals:
    """AX = XB residuals of `X` on each motion pair (:class:`HandEyeResiduals`)."""
    rot, tr = [], []
    for a, b in zip(A, B, strict=True):
        lhs, rhs = a @ X, X @ b
        rot.append(math.degrees((lhs.inv() @ rhs).angle))
        tr.append(float(np.linalg.norm(lhs.translation - rhs.translation)))
    return HandEyeResiduals(np.asarray(rot), np.asarray(tr))
