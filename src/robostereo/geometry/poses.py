"""Rigid transforms (6-DoF poses), the SCARA pose, and their file forms.

:class:`SE3` is the one pose type: a rotation plus a translation, in the spirit of
spatialmath's ``SE3`` with the rotations handled by :mod:`scipy.spatial.transform`.
``T_a_b`` (read "b in a") maps the coordinates of a point in frame ``b`` to frame
``a``: ``p_a = R @ p_b + t``.  A camera pose is ``T_world_camera``: the columns of
``R`` are the camera's axes (x to the image's right, y down the image, z along the
optical axis) in the world frame and ``t`` is the optical centre.

The thesis's SCARA pose :class:`Pose` ``(x, y, z, phi)`` (a camera looking straight
down with yaw ``phi``, the thesis 2.2 and 4.1) is an :class:`SE3` built from four
numbers; its ``rotation`` is the exact cos/sin matrix.  The conversions are named
``<target>_from_<source>`` as in pytransform3d: :func:`se3_from_scara` and
:func:`scara_from_se3`.  :func:`as_se3` gives the plain (re-orthonormalised)
:class:`SE3` of any pose.

Units: millimetres and radians in the API; files hold millimetres unless they say
``unit: m`` or use the ROS ``geometry_msgs/Transform`` form (metres).

File forms (:func:`pose_from_dict`, one mapping per pose)::

    {x, y, z, phi_deg}                     the thesis's SCARA pose (mm, deg): a camera
                                           looking straight down with yaw phi
    {matrix: [[4 x 4]]}                    homogeneous matrix, last row 0 0 0 1
    {position: [x, y, z], quaternion: [qx, qy, qz, qw]}   ROS order (x, y, z, w)
    {position: [x, y, z], rotvec: [rx, ry, rz]}           rotation vector, radians
    {translation: {x, y, z}, rotation: {x, y, z, w}}      ROS Transform, metres

The position forms take an optional ``unit: mm`` (default) or ``unit: m``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from robostereo.errors import InputError, require_finite, shown, warn_input
from robostereo.geometry.mapping_checks import check_keys, get_number
from robostereo.geometry.plausibility import (
    MAX_PHI_DEG,
    MAX_TRANSLATION_MM,
    check_translation,
    printed_rotation,
)

__all__ = [
    "ORTHONORMAL_TOLERANCE",
    "QUATERNION_TOLERANCE",
    "SE3",
    "Pose",
    "as_se3",
    "pose_from_dict",
    "pose_to_dict",
    "relative_pose",
    "scara_from_se3",
    "scara_pose_from_dict",
    "se3_from_scara",
]

ORTHONORMAL_TOLERANCE = 1e-6
"""Largest ``|R^T R - I|`` entry accepted for a rotation matrix (files hold ~1e-9)."""

QUATERNION_TOLERANCE = 1e-3
"""Largest ``| |q| - 1 |`` of a quaternion that is normalised (with a warning).

Rounding each of the four components to ``k`` decimals moves the norm of a unit
quaternion by at most ``|q . e| <= |e| <= 2 * 0.5 * 10**-k``: 1e-3 for 3 decimals, 1e-4
for 4.  So 1e-3 takes every quaternion printed with 3 or more decimals (1e-6 refused
97.5 % of those printed with 4 decimals); a norm further off is no rounding but a wrong
or missing component, and is refused."""


def _vector(name: str, value: ArrayLike, n: int) -> NDArray[np.float64]:
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be {n} numbers, got {shown(value)}") from None
    if v.shape != (n,) or not np.all(np.isfinite(v)):
        raise InputError(f"{name} must be {n} finite numbers, got {shown(value)}")
    return v


@dataclass(frozen=True, eq=False)
class SE3:
    """A rigid transform ``T_a_b``: ``p_a = rotation @ p_b + translation``.

    Parameters
    ----------
    rotation : array_like, shape (3, 3)
        Proper orthonormal matrix (``R^T R = I`` to :data:`ORTHONORMAL_TOLERANCE`,
        ``det R = +1``); it is re-orthonormalised (nearest rotation) on construction.
    translation : array_like, shape (3,)
        Millimetres.

    Examples
    --------
    >>> T = SE3.from_rotvec([10.0, 0.0, 0.0], [0.0, 0.0, np.pi / 2])
    >>> T.apply([[1.0, 0.0, 0.0]]).round(12) + 0.0
    array([[10.,  1.,  0.]])
    >>> (T @ T.inv()).matrix.round(12) + 0.0
    array([[1., 0., 0., 0.],
           [0., 1., 0., 0.],
           [0., 0., 1., 0.],
           [0., 0., 0., 1.]])
    >>> SE3(np.diag([1.0, 1.0, 2.0]), np.zeros(3))
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: rotation must be orthonormal with det +1 ...
    """

    rotation: NDArray[np.float64]
    translation: NDArray[np.float64]

    def __post_init__(self) -> None:
        try:
            R = np.asarray(self.rotation, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"rotation must be a 3 x 3 matrix, got "
                             f"{shown(self.rotation)}") from None
        if R.shape != (3, 3) or not np.all(np.isfinite(R)):
            raise InputError(f"rotation must be a finite 3 x 3 matrix, got shape {R.shape}")
        err = float(np.abs(R.T @ R - np.eye(3)).max())
        det = float(np.linalg.det(R))
        if err > ORTHONORMAL_TOLERANCE or det <= 0:
            raise InputError(
                "rotation must be orthonormal with det +1 (|R^T R - I| <= "
                f"{ORTHONORMAL_TOLERANCE:g}), got |R^T R - I| = {err:.3g}, det = {det:.6g}"
            )
        u, _, vt = np.linalg.svd(R)
        R = u @ vt
        R.setflags(write=False)
        t = _vector("translation", self.translation, 3).copy()
        check_translation(t, "pose")
        t.setflags(write=False)
        object.__setattr__(self, "rotation", R)
        object.__setattr__(self, "translation", t)

    # ---------------------------------------------------------------- constructors
    @classmethod
    def identity(cls) -> SE3:
        """The identity transform."""
        return SE3(np.eye(3), np.zeros(3))

    @classmethod
    def from_matrix(cls, matrix: ArrayLike) -> SE3:
        """From a homogeneous ``(4, 4)`` matrix (last row ``0 0 0 1``)."""
        try:
            M = np.asarray(matrix, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"matrix must be 4 x 4 numbers, got {shown(matrix)}") from None
        if M.shape != (4, 4) or not np.all(np.isfinite(M)):
            raise InputError(f"matrix must be a finite 4 x 4 matrix, got shape {M.shape}")
        if not np.allclose(M[3], [0.0, 0.0, 0.0, 1.0], atol=1e-9):
            raise InputError(f"matrix: last row must be [0, 0, 0, 1], got {M[3].tolist()}")
        return SE3(M[:3, :3], M[:3, 3])

    @classmethod
    def from_quaternion(cls, position: ArrayLike, quaternion: ArrayLike, *,
                        source: str = "quaternion") -> SE3:
        """From a position (mm) and a unit quaternion ``(x, y, z, w)`` (ROS order).

        Parameters
        ----------
        position : array_like, shape (3,)
        quaternion : array_like, shape (4,)
            ``(x, y, z, w)``.
        source : str
            Name used in the warning and the error (the file and key).

        Raises
        ------
        InputError
            A norm off 1 by more than :data:`QUATERNION_TOLERANCE`.

        Notes
        -----
        A norm within :data:`QUATERNION_TOLERANCE` of 1 is taken as rounding of the
        printed components: the quaternion is normalised, with a
        :class:`~robostereo.errors.PlausibilityWarning` when the norm is off by more
        than 1e-6, the former tolerance (what it took in silence still passes in
        silence; what it refused is normalised aloud).

        Examples
        --------
        >>> SE3.from_quaternion([0, 0, 0], [0, 0, 0.70710678, 0.70710678]).rotvec.round(4)
        array([0.    , 0.    , 1.5708])
        """
        q = _vector("quaternion", quaternion, 4)
        n = float(np.linalg.norm(q))
        if not abs(n - 1.0) <= QUATERNION_TOLERANCE:
            raise InputError(f"{source}: quaternion must have norm 1 (a unit quaternion in "
                             f"ROS order x, y, z, w), got norm {n:.9g}, more than "
                             f"{QUATERNION_TOLERANCE:g} off")
        if abs(n - 1.0) > 1e-6:
            warn_input(f"{source}: quaternion of norm {n:.9g} normalised (components "
                       "rounded when printed?); the order is (x, y, z, w)")
        return SE3(Rotation.from_quat(q / n).as_matrix(), _vector("position", position, 3))

    @classmethod
    def from_rotvec(cls, position: ArrayLike, rotvec: ArrayLike) -> SE3:
        """From a position (mm) and a rotation vector (axis times angle, radians)."""
        r = _vector("rotvec", rotvec, 3)
        return SE3(Rotation.from_rotvec(r).as_matrix(), _vector("position", position, 3))

    @classmethod
    def from_scara(cls, pose: Pose) -> SE3:
        """The plain (re-orthonormalised) SE3 of a SCARA :class:`Pose` (see :func:`as_se3`)."""
        return SE3(pose.rotation, pose.position)

    @classmethod
    def look_at(
        cls, eye: ArrayLike, target: ArrayLike, *, up: ArrayLike = (0.0, 1.0, 0.0)
    ) -> SE3:
        """Camera pose at `eye` with its optical axis through `target`.

        The image's y axis (down the image) points as far from `up` as it can; world
        millimetres.  Raises InputError if `eye` and `target` coincide or the view
        direction is parallel to `up`.
        """
        e = _vector("eye", eye, 3)
        z = _vector("target", target, 3) - e
        nz = float(np.linalg.norm(z))
        if nz < 1e-9:
            raise InputError("look_at: eye and target coincide")
        z /= nz
        x = np.cross(z, -_vector("up", up, 3))
        nx = float(np.linalg.norm(x))
        if nx < 1e-9:
            raise InputError("look_at: the view direction is parallel to up")
        x /= nx
        return SE3(np.column_stack([x, np.cross(z, x), z]), e)

    # ---------------------------------------------------------------- properties
    @property
    def position(self) -> NDArray[np.float64]:
        """``translation``, shape ``(3,)``: for a camera pose, the optical centre (mm)."""
        return self.translation

    @property
    def matrix(self) -> NDArray[np.float64]:
        """Homogeneous matrix, shape ``(4, 4)``."""
        M = np.eye(4)
        M[:3, :3] = self.rotation
        M[:3, 3] = self.translation
        return M

    @property
    def quaternion(self) -> NDArray[np.float64]:
        """Unit quaternion ``(x, y, z, w)`` (ROS order), ``w >= 0``, shape ``(4,)``."""
        q = Rotation.from_matrix(self.rotation).as_quat()
        return -q if q[3] < 0 else q

    @property
    def rotvec(self) -> NDArray[np.float64]:
        """Rotation vector (radians), shape ``(3,)``."""
        return Rotation.from_matrix(self.rotation).as_rotvec()

    @property
    def angle(self) -> float:
        """Rotation angle, radians in ``[0, pi]``."""
        return float(np.linalg.norm(self.rotvec))

    # ---------------------------------------------------------------- algebra
    def inv(self) -> SE3:
        """``T_b_a`` of ``T_a_b``."""
        return SE3(self.rotation.T, -self.rotation.T @ self.translation)

    def __matmul__(self, other: SE3) -> SE3:
        """Composition ``T_a_b @ T_b_c = T_a_c``."""
        if not isinstance(other, SE3):
            return NotImplemented
        return SE3(self.rotation @ other.rotation,
                   self.rotation @ other.translation + self.translation)

    def apply(self, points: ArrayLike) -> NDArray[np.float64]:
        """Map points ``(N, 3)`` (or ``(3,)``) of frame b to frame a."""
        p = np.asarray(points, dtype=float)
        one = p.ndim == 1
        p = np.atleast_2d(p)
        if p.shape[-1] != 3:
            raise InputError(f"points must have shape (N, 3), got {np.shape(points)}")
        out = p @ self.rotation.T + self.translation
        return out[0] if one else out

    def distance_to(self, other: SE3) -> tuple[float, float]:
        """``(translation difference mm, rotation difference rad)`` between two transforms."""
        d = self.inv() @ other
        return float(np.linalg.norm(self.translation - other.translation)), d.angle

    def __repr__(self) -> str:
        t = ", ".join(f"{v:.6g}" for v in self.translation)
        r = ", ".join(f"{v:.6g}" for v in self.rotvec)
        return f"SE3(translation=[{t}], rotvec=[{r}])"


@dataclass(frozen=True)
class Pose(SE3):
    """The thesis's SCARA camera pose: optical centre and yaw about vertical.

    A camera looking straight down (world ``-Z``) from ``(x, y, z)`` with yaw ``phi``;
    it is an :class:`SE3` (``T_world_camera``) whose ``rotation`` is the exact
    cos/sin matrix below (not re-orthonormalised) and whose ``translation`` is
    ``[x, y, z]``.  Equality, hashing and ``repr`` are those of the four numbers.

    Parameters
    ----------
    x, y, z : float
        Optical centre in the world frame, millimetres (z up).
    phi : float
        Yaw of the camera's x axis from the world X axis, radians,
        counter-clockwise seen from above.

    Examples
    --------
    >>> p = Pose(1.0, 2.0, 1000.0)
    >>> p, isinstance(p, SE3), p == Pose(1.0, 2.0, 1000.0, 0.0)
    (Pose(x=1.0, y=2.0, z=1000.0, phi=0.0), True, True)
    >>> p.rotation
    array([[ 1.,  0.,  0.],
           [ 0., -1.,  0.],
           [ 0.,  0., -1.]])
    """

    rotation: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    translation: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    x: float
    y: float
    z: float
    phi: float = 0.0

    def __post_init__(self) -> None:
        require_finite("pose", [self.x, self.y, self.z, self.phi])
        check_translation([self.x, self.y, self.z], "pose")
        c, s = math.cos(self.phi), math.sin(self.phi)
        R = np.array([[c, s, 0.0], [s, -c, 0.0], [0.0, 0.0, -1.0]])
        R.setflags(write=False)
        t = np.array([self.x, self.y, self.z], dtype=float)
        t.setflags(write=False)
        object.__setattr__(self, "rotation", R)
        object.__setattr__(self, "translation", t)

    @property
    def position(self) -> NDArray[np.float64]:
        """Optical centre ``[x, y, z]``, shape ``(3,)``, millimetres."""
        return np.array([self.x, self.y, self.z], dtype=float)


def se3_from_scara(x: float, y: float, z: float, phi: float = 0.0) -> Pose:
    """The SE3 of the SCARA pose ``(x, y, z, phi)``: a :class:`Pose`.

    ``rotation`` has the camera axes ``x_c = (cos phi, sin phi, 0)``,
    ``y_c = (sin phi, -cos phi, 0)``, ``z_c = (0, 0, -1)`` as columns.

    >>> T = se3_from_scara(0.0, 0.0, 1000.0, np.pi / 2)
    >>> isinstance(T, SE3), T.apply([0.0, 0.0, 100.0]).round(12) + 0.0
    (True, array([   0.,    0.,  900.]))
    """
    return Pose(x, y, z, phi)


def scara_from_se3(pose: SE3, *, tolerance: float = ORTHONORMAL_TOLERANCE) -> Pose:
    """The SCARA :class:`Pose` of a camera pose whose optical axis points straight down.

    Parameters
    ----------
    pose : SE3
        ``T_world_camera``; a :class:`Pose` is returned as it is.
    tolerance : float
        Largest accepted difference of the optical axis (third column of the
        rotation) from world ``-Z``, per component.

    Returns
    -------
    Pose
        ``phi = atan2(R[1, 0], R[0, 0])`` (the camera's x axis from world X) and the
        optical centre.

    Raises
    ------
    InputError
        If the optical axis does not point straight down.

    Examples
    --------
    >>> T = SE3.from_rotvec([5.0, 6.0, 900.0], [np.pi, 0.0, 0.0])
    >>> scara_from_se3(T)
    Pose(x=5.0, y=6.0, z=900.0, phi=0.0)
    >>> scara_from_se3(SE3.identity())
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: pose: the optical axis must point straight down ...
    """
    if isinstance(pose, Pose):
        return pose
    if not isinstance(pose, SE3):
        raise InputError(f"pose must be an SE3, got {type(pose).__name__}")
    R = pose.rotation
    axis = R[:, 2]
    if float(np.abs(axis - np.array([0.0, 0.0, -1.0])).max()) > tolerance:
        raise InputError(
            "pose: the optical axis must point straight down (world -Z) for a SCARA "
            f"pose, got {np.round(axis, 6).tolist()}"
        )
    t = pose.translation
    return Pose(float(t[0]), float(t[1]), float(t[2]), math.atan2(R[1, 0], R[0, 0]))


def as_se3(pose: SE3) -> SE3:
    """Any pose as a plain :class:`SE3`.

    A SCARA :class:`Pose` (itself an SE3 with the exact cos/sin rotation) gives
    ``SE3(pose.rotation, pose.position)``, whose rotation is re-orthonormalised; any
    other SE3 is returned as it is.
    """
    if isinstance(pose, Pose):
        return SE3.from_scara(pose)
    if isinstance(pose, SE3):
        return pose
    raise InputError(f"pose must be a Pose or an SE3, got {type(pose).__name__}")


def relative_pose(pose_left: SE3, pose_right: SE3) -> SE3:
    """``T_right_left``: left-camera coordinates to right-camera coordinates.

    OpenCV's ``R, T`` of :func:`cv2.stereoRectify` (``x_right = R x_left + T``).
    """
    return as_se3(pose_right).inv() @ as_se3(pose_left)


# ------------------------------------------------------------------------ files


_SCARA_KEYS = ("x", "y", "z", "phi_deg")
_FORMS = (
    "{x, y, z, phi_deg} (SCARA, mm, deg)",
    "{matrix: 4 x 4}",
    "{position, quaternion: [x, y, z, w]}",
    "{position, rotvec}",
    "{translation: {x, y, z}, rotation: {x, y, z, w}} (ROS, m)",
)


def _unit_scale(data: Mapping[str, Any], source: str) -> float:
    unit = data.get("unit", "mm")
    if unit not in ("mm", "m"):
        raise InputError(f"{source}: key 'unit' must be 'mm' or 'm', got {shown(unit)}")
    return 1000.0 if unit == "m" else 1.0


def _check_only(data: Mapping[str, Any], allowed: set[str], source: str) -> None:
    extra = sorted(str(k) for k in data if k not in allowed)
    if extra:
        raise InputError(f"{source}: unknown key '{extra[0]}' (allowed: "
                         f"{', '.join(sorted(allowed))})")


def _ros_xyz(data: object, keys: Sequence[str], source: str, what: str) -> list[float]:
    if not isinstance(data, Mapping) or any(k not in data for k in keys):
        raise InputError(f"{source}: '{what}' must be a mapping of {', '.join(keys)}")
    return [data[k] for k in keys]


def scara_pose_from_dict(data: Mapping[str, Any], *, source: str = "pose") -> Pose:
    """Build a :class:`Pose` from a mapping ``x, y, z`` (mm) and ``phi_deg`` (degrees).

    The SCARA form alone (other keys are refused); :func:`pose_from_dict` reads every
    form.  ``phi_deg`` may be left out (0 degrees); ``x``, ``y``, ``z`` are required.
    Files hold degrees; :class:`Pose` holds radians.

    >>> scara_pose_from_dict({"x": 0, "y": 10, "z": 1000, "phi_deg": 180}).phi == math.pi
    True
    >>> scara_pose_from_dict({"x": 0, "y": 10}, source="left.yaml")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: left.yaml: missing key 'z'
    """
    check_keys(data, _SCARA_KEYS, source, "pose")
    x = get_number(data, "x", source)
    y = get_number(data, "y", source)
    z = get_number(data, "z", source)
    phi_deg = get_number(data, "phi_deg", source) if "phi_deg" in data else 0.0
    for key, v in (("x", x), ("y", y), ("z", z)):
        if abs(v) > MAX_TRANSLATION_MM:
            raise InputError(f"{source}: key '{key}' = {v:.3g} mm is beyond "
                             f"+-{MAX_TRANSLATION_MM:.0e} mm (1000 km): not a robot's pose")
    if abs(phi_deg) > MAX_PHI_DEG:
        raise InputError(f"{source}: key 'phi_deg' = {phi_deg:.3g} is beyond "
                         f"+-{MAX_PHI_DEG:.0e} degrees, where a float no longer holds an angle")
    return Pose(x, y, z, math.radians(phi_deg))


def pose_from_dict(data: Mapping[str, Any], *, source: str = "pose") -> SE3:
    """Read a pose in any of the file forms of the module docstring.

    Parameters
    ----------
    data : mapping
        One pose mapping.
    source : str
        Name used in error messages.

    Returns
    -------
    SE3
        The SCARA form gives a :class:`Pose` (:func:`scara_pose_from_dict`); every
        other form a plain :class:`SE3` in millimetres.

    Raises
    ------
    InputError
        One line naming `source`: unknown form or key, wrong shape, NaN, a rotation
        that is not orthonormal, a quaternion whose norm is not 1.

    Examples
    --------
    >>> pose_from_dict({"x": 0, "y": 10, "z": 1000, "phi_deg": 90})
    Pose(x=0.0, y=10.0, z=1000.0, phi=1.5707963267948966)
    >>> pose_from_dict({"position": [0, 0, 1000], "quaternion": [1, 0, 0, 0]})
    SE3(translation=[0, 0, 1000], rotvec=[3.14159, 0, 0])
    >>> pose_from_dict({"translation": {"x": 0.1, "y": 0, "z": 0.05},
    ...                 "rotation": {"x": 0, "y": 0, "z": 0, "w": 1}}).translation
    array([100.,   0.,  50.])
    >>> pose_from_dict({"matrix": np.diag([1, 1, 2, 1]).tolist()}, source="a.yaml")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: a.yaml: rotation must be orthonormal with det +1 ...
    """
    if not isinstance(data, Mapping):
        raise InputError(f"{source}: a pose must be a mapping, one of: {'; '.join(_FORMS)}")
    keys = set(data)
    try:
        if keys and keys <= set(_SCARA_KEYS):
            return scara_pose_from_dict(data, source=source)
        if "matrix" in keys:
            _check_only(data, {"matrix", "unit"}, source)
            T = SE3.from_matrix(printed_rotation(data["matrix"], source, ORTHONORMAL_TOLERANCE))
            return SE3(T.rotation, T.translation * _unit_scale(data, source))
        if "position" in keys:
            s = _unit_scale(data, source)
            if "quaternion" in keys:
                _check_only(data, {"position", "quaternion", "unit"}, source)
                T = SE3.from_quaternion(data["position"], data["quaternion"],
                                        source=source)
            elif "rotvec" in keys:
                _check_only(data, {"position", "rotvec", "unit"}, source)
                T = SE3.from_rotvec(data["position"], data["rotvec"])
            else:
                raise InputError("a position needs 'quaternion' [x, y, z, w] or 'rotvec'")
            return SE3(T.rotation, T.translation * s)
        if "translation" in keys and "rotation" in keys:
            _check_only(data, {"translation", "rotation"}, source)
            t = _ros_xyz(data["translation"], ("x", "y", "z"), source, "translation")
            q = _ros_xyz(data["rotation"], ("x", "y", "z", "w"), source, "rotation")
            T = SE3.from_quaternion(t, q, source=source)
            return SE3(T.rotation, T.translation * 1000.0)
    except InputError as exc:
        msg = str(exc)
        raise InputError(msg if msg.startswith(source) else f"{source}: {msg}") from None
    raise InputError(f"{source}: not a pose; expected one of: {'; '.join(_FORMS)}")


def pose_to_dict(pose: SE3) -> dict[str, Any]:
    """A pose as a file mapping: SCARA poses as ``{x, y, z, phi_deg}`` (mm, degrees),
    others as ``{position (mm), quaternion (x, y, z, w)}``.

    >>> pose_to_dict(Pose(1.0, 2.0, 1000.0, math.pi / 2))
    {'x': 1.0, 'y': 2.0, 'z': 1000.0, 'phi_deg': 90.0}
    >>> pose_to_dict(SE3.identity())
    {'position': [0.0, 0.0, 0.0], 'quaternion': [0.0, 0.0, 0.0, 1.0]}
    """
    if isinstance(pose, Pose):
        return {
            "x": float(pose.x),
            "y": float(pose.y),
            "z": float(pose.z),
            "phi_deg": round(math.degrees(pose.phi), 12),
        }
    T = as_se3(pose)
    return {
        "position": [round(float(v), 9) + 0.0 for v in T.translation],
        "quaternion": [round(float(v), 12) + 0.0 for v in T.quaternion],
    }


