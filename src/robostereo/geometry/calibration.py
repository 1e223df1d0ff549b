"""Calibrated stereo rigs: the intrinsics and relative pose of two cameras.

A :class:`StereoCalibration` holds the two intrinsic matrices, the two distortion
vectors (OpenCV's model) and the pose of the right camera relative to the left one,
``x_right = R @ x_left + T`` (OpenCV's ``stereoCalibrate`` convention), with ``T`` in
millimetres.  It validates itself with the checks of this module
(:func:`check_camera_matrix`, :func:`check_distortion`, :func:`check_rotation`,
:func:`check_translation`, :func:`check_size`), which the file readers of
:mod:`robostereo.io.calibration_files` share.  It can be built from the robot's
:class:`~robostereo.geometry.camera.Camera` and two camera poses
(:meth:`StereoCalibration.from_poses`); :mod:`robostereo.geometry.calibrated_rectification`
rectifies it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, shown
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3

__all__ = [
    "StereoCalibration",
    "check_camera_matrix",
    "check_distortion",
    "check_rotation",
    "check_size",
    "check_translation",
    "frozen_array",
]

_DIST_LENGTHS = (4, 5, 8, 12, 14)
_ROT_TOL = 1e-4
"""Largest accepted ``max|R^T R - I|`` and ``|det R - 1|`` for a rotation read from a file."""


def frozen_array(a: NDArray[np.float64]) -> NDArray[np.float64]:
    """A read-only float copy of `a`."""
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


def check_camera_matrix(source: str, name: str, value: Any) -> NDArray[np.float64]:
    """`value` as a finite, invertible ``(3, 3)`` camera matrix with ``fx, fy > 0``.

    Raises InputError naming `source` and `name`.
    """
    try:
        K = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{source}: {name} must be a 3x3 matrix, got {shown(value)}") from None
    if K.size == 9 and K.ndim in (1, 2):
        K = K.reshape(3, 3)
    if K.shape != (3, 3):
        raise InputError(f"{source}: {name} must be a 3x3 camera matrix, got shape {K.shape}")
    if not np.all(np.isfinite(K)):
        raise InputError(f"{source}: {name} must be finite, got {K.ravel().tolist()}")
    if abs(np.linalg.det(K)) < 1e-12 * max(1.0, float(np.abs(K).max()) ** 3):
        raise InputError(f"{source}: {name} must be invertible, got {K.ravel().tolist()}")
    if K[0, 0] <= 0 or K[1, 1] <= 0:
        raise InputError(
            f"{source}: {name} must have positive focal lengths fx, fy, got "
            f"{K[0, 0]}, {K[1, 1]}"
        )
    return K


def check_distortion(source: str, name: str, value: Any) -> NDArray[np.float64]:
    """`value` as OpenCV distortion coefficients ``(n,)``, n in 4, 5, 8, 12, 14.

    None or empty means no distortion: 5 zeros.

    Raises InputError naming `source` and `name`.
    """
    if value is None:
        return np.zeros(5)
    try:
        D = np.asarray(value, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InputError(f"{source}: {name} must be a vector of numbers, got "
                         f"{shown(value)}") from None
    if D.size == 0:
        return np.zeros(5)
    if D.size not in _DIST_LENGTHS:
        raise InputError(
            f"{source}: {name} must have 4, 5, 8, 12 or 14 distortion coefficients, got {D.size}"
        )
    if not np.all(np.isfinite(D)):
        raise InputError(f"{source}: {name} must be finite, got {D.tolist()}")
    return D


def check_rotation(source: str, name: str, value: Any) -> NDArray[np.float64]:
    """`value` (a ``(3, 3)`` matrix or a Rodrigues 3-vector) as the nearest rotation ``(3, 3)``.

    Raises InputError naming `source` and `name`.
    """
    try:
        R = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{source}: {name} must be a 3x3 rotation, got {shown(value)}") from None
    if R.size == 3 and R.ndim <= 2:  # a Rodrigues vector, as cv2.stereoCalibrate users store
        R = cv2.Rodrigues(R.reshape(3, 1))[0] if np.all(np.isfinite(R)) else R.ravel()
    if R.size == 9 and R.ndim in (1, 2):
        R = R.reshape(3, 3)
    if R.shape != (3, 3):
        raise InputError(f"{source}: {name} must be a 3x3 rotation matrix, got shape {R.shape}")
    if not np.all(np.isfinite(R)):
        raise InputError(f"{source}: {name} must be finite, got {R.ravel().tolist()}")
    ortho = float(np.abs(R.T @ R - np.eye(3)).max())
    det = float(np.linalg.det(R))
    if ortho > _ROT_TOL or abs(det - 1.0) > _ROT_TOL:
        raise InputError(
            f"{source}: {name} must be a rotation (orthonormal, det +1 within {_ROT_TOL:g}), "
            f"got max|R^T R - I| = {ortho:.3g}, det = {det:.6g}"
        )
    u, _, vt = np.linalg.svd(R)  # snap to the nearest rotation (changes ~1e-8 at most)
    return u @ vt


def check_translation(source: str, name: str, value: Any) -> NDArray[np.float64]:
    """`value` as a finite, non-zero translation ``(3,)``.

    Raises InputError naming `source` and `name`.
    """
    try:
        T = np.asarray(value, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InputError(f"{source}: {name} must be 3 numbers, got {shown(value)}") from None
    if T.size != 3:
        raise InputError(f"{source}: {name} must be a 3-vector, got {T.size} values")
    if not np.all(np.isfinite(T)):
        raise InputError(f"{source}: {name} must be finite, got {T.tolist()}")
    if not np.any(T != 0):
        raise InputError(f"{source}: {name} must be non-zero (the baseline), got {T.tolist()}")
    return T


def check_size(source: str, name: str, value: Any) -> tuple[int, int]:
    """`value` as an image size ``(width, height)`` of integers >= 2.

    Raises InputError naming `source` and `name`.
    """
    try:
        v = np.asarray(value, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InputError(f"{source}: {name} must be (width, height), got {shown(value)}") from None
    if v.size != 2 or not np.all(np.isfinite(v)) or np.any(v != np.round(v)) or np.any(v < 2):
        raise InputError(
            f"{source}: {name} must be (width, height), two integers >= 2, got {v.tolist()}"
        )
    return int(v[0]), int(v[1])


@dataclass(frozen=True, eq=False)
class StereoCalibration:
    """Intrinsics and relative pose of a calibrated stereo pair (OpenCV conventions).

    Parameters
    ----------
    K1, K2 : array_like, shape (3, 3)
        Intrinsic matrices of the left and right cameras (pixels).
    D1, D2 : array_like, shape (n,)
        OpenCV distortion coefficients ``(k1, k2, p1, p2[, k3[, k4, k5, k6[, s1..s4[, tx, ty]]]])``,
        ``n`` in 4, 5, 8, 12, 14; ``None`` or empty means no distortion (stored as 5 zeros).
    R : array_like, shape (3, 3)
        Rotation from the left to the right camera frame: ``x_right = R @ x_left + T``.
        Must be orthonormal with ``det = +1`` within 1e-4; it is snapped to the nearest
        rotation.  A Rodrigues 3-vector is also accepted.
    T : array_like, shape (3,)
        Translation of the same transform, **millimetres**, non-zero.  For a horizontal
        rig with the right camera on the right, ``T ~ (-B, 0, 0)``.
    image_size : tuple of int
        ``(width, height)`` of the calibrated images, pixels.
    source : str
        The file (or other origin) named in error messages.

    Raises
    ------
    InputError
        One line naming `source` and the bad field.

    Examples
    --------
    >>> K = [[800.0, 0, 319.5], [0, 800.0, 239.5], [0, 0, 1]]
    >>> c = StereoCalibration(K, None, K, None, np.eye(3), [-60.0, 0, 0], (640, 480))
    >>> c.baseline_mm, c.D1.tolist()
    (60.0, [0.0, 0.0, 0.0, 0.0, 0.0])
    >>> StereoCalibration(K, None, K, None, np.eye(3), [0, 0, 0], (640, 480), source="rig.yml")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: rig.yml: T must be non-zero (the baseline), got [0.0, 0.0, 0.0]
    """

    K1: NDArray[np.float64]
    D1: NDArray[np.float64]
    K2: NDArray[np.float64]
    D2: NDArray[np.float64]
    R: NDArray[np.float64]
    T: NDArray[np.float64]
    image_size: tuple[int, int]
    source: str = field(default="calibration", compare=False)

    def __post_init__(self) -> None:
        s = self.source
        object.__setattr__(self, "K1", frozen_array(check_camera_matrix(s, "K1", self.K1)))
        object.__setattr__(self, "D1", frozen_array(check_distortion(s, "D1", self.D1)))
        object.__setattr__(self, "K2", frozen_array(check_camera_matrix(s, "K2", self.K2)))
        object.__setattr__(self, "D2", frozen_array(check_distortion(s, "D2", self.D2)))
        object.__setattr__(self, "R", frozen_array(check_rotation(s, "R", self.R)))
        object.__setattr__(self, "T", frozen_array(check_translation(s, "T", self.T)))
        object.__setattr__(self, "image_size", check_size(s, "image_size", self.image_size))

    @property
    def baseline_mm(self) -> float:
        """Distance between the optical centres, ``|T|``, millimetres."""
        return float(np.linalg.norm(self.T))

    def allclose(self, other: StereoCalibration, *, rtol: float = 1e-9, atol: float = 1e-9) -> bool:
        """True when every matrix agrees within tolerance and the image sizes are equal."""
        pairs = [(self.K1, other.K1), (self.K2, other.K2), (self.R, other.R), (self.T, other.T)]
        for a, b in ((self.D1, other.D1), (self.D2, other.D2)):
            n = max(a.size, b.size)
            pairs.append((np.pad(a, (0, n - a.size)), np.pad(b, (0, n - b.size))))
        return self.image_size == other.image_size and all(
            np.allclose(a, b, rtol=rtol, atol=atol) for a, b in pairs
        )

    @classmethod
    def from_poses(cls, camera: Camera, left: SE3, right: SE3) -> StereoCalibration:
        """The calibration of one distortion-free robot camera moved to two poses.

        Parameters
        ----------
        camera : Camera
            The pinhole camera (the same at both viewpoints).
        left, right : SE3
            Camera poses ``T_world_camera`` of the left and right viewpoints (world, millimetres).

        Returns
        -------
        StereoCalibration
            ``R = R_r^T R_l`` and ``T = R_r^T (c_l - c_r)`` where ``R_l, R_r`` are the
            pose rotation matrices (camera axes as world columns) and ``c`` the
            optical centres.

        Examples
        --------
        >>> from robostereo.geometry.poses import Pose
        >>> c = StereoCalibration.from_poses(Camera(), Pose(-30, 0, 900), Pose(30, 0, 900))
        >>> c.T.tolist(), c.R.tolist() == np.eye(3).tolist()
        ([-60.0, 0.0, 0.0], True)
        """
        Rl, Rr = left.rotation, right.rotation
        R = Rr.T @ Rl
        T = Rr.T @ (left.position - right.position)
        K = camera.K
        return cls(K, None, K, None, R, T, camera.image_size, source="Camera/Pose")
