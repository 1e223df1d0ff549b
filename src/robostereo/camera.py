"""Camera model and camera poses (seed chapter 2, 4.1).

The camera is a pinhole looking straight down from a pose that a SCARA robot can
give it: a position ``(x, y, z)`` in the world frame (millimetres, z up) and a yaw
``phi`` about the vertical axis.  The camera frame has x along the image's rows
(to the right), y down the image (along the columns) and z along the optical axis,
which points down (world ``-Z``), so depth is positive.

With yaw ``phi`` the camera axes, written in the world frame, are::

    x_c = ( cos phi,  sin phi,  0)
    y_c = ( sin phi, -cos phi,  0)
    z_c = ( 0,        0,       -1)

Pixel ``(row i, column j)`` has its centre at image coordinates ``x = j, y = i``;
the principal point defaults to the image centre ``((W - 1) / 2, (H - 1) / 2)``.

The module also holds

* YAML files for a :class:`Camera` and for a :class:`Pose` (:func:`load_camera_yaml`,
  :func:`save_camera_yaml`, :func:`load_pose_yaml`, :func:`save_pose_yaml`);
* the epipolar frame of two viewpoints, :class:`EpipolarGeometry` (seed 2.2);
* rectification of each image by its angle ``theta`` (:func:`rectify_image`) and the
  exact point maps between an image and its rectified version
  (:func:`image_to_epipolar`, :func:`epipolar_to_image`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import cv2
import numpy as np
import yaml
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_finite, require_positive

__all__ = [
    "SEED_CAMERA",
    "Camera",
    "EpipolarGeometry",
    "Pose",
    "camera_from_dict",
    "camera_to_dict",
    "epipolar_to_image",
    "image_to_epipolar",
    "load_camera_yaml",
    "load_pose_yaml",
    "load_stereo_poses_yaml",
    "pose_from_dict",
    "pose_to_dict",
    "rectification_matrix",
    "rectified_valid_mask",
    "rectify_image",
    "save_camera_yaml",
    "save_pose_yaml",
    "wrap_angle",
]


@dataclass(frozen=True)
class Pose:
    """A camera pose in the world frame: optical centre and yaw about vertical.

    Parameters
    ----------
    x, y, z : float
        Optical centre in the world frame, millimetres (z up).
    phi : float
        Yaw of the camera's x axis from the world X axis, radians,
        counter-clockwise seen from above.
    """

    x: float
    y: float
    z: float
    phi: float = 0.0

    def __post_init__(self) -> None:
        require_finite("pose", [self.x, self.y, self.z, self.phi])

    @property
    def position(self) -> NDArray[np.float64]:
        """Optical centre, shape ``(3,)``, millimetres."""
        return np.array([self.x, self.y, self.z], dtype=float)

    @property
    def rotation(self) -> NDArray[np.float64]:
        """``R`` of shape ``(3, 3)`` whose columns are the camera axes in the world.

        A world point ``P`` has camera coordinates ``R.T @ (P - position)``.
        """
        c, s = math.cos(self.phi), math.sin(self.phi)
        return np.array([[c, s, 0.0], [s, -c, 0.0], [0.0, 0.0, -1.0]])


@dataclass(frozen=True)
class Camera:
    """A pinhole camera with a rectangular pixel grid of known pitch.

    Parameters
    ----------
    focal_length_mm : float
        Lens-to-image-plane distance ``s`` (seed 3.6), millimetres.
    pixel_pitch_mm : tuple of float
        Pixel pitch ``(horizontal, vertical)`` in millimetres.  The seed gives
        17.2 um horizontally; 13.7 um vertically fits a 2/3-inch sensor of
        481 lines (6.6 mm high), see ``docs``.
    image_size : tuple of int
        ``(width, height)`` in pixels; the seed's PULNiX CCD has 509 x 481.
    principal_point : tuple of float, optional
        ``(cx, cy)`` in pixels; default the image centre.
    grey_levels : int
        Number of grey levels the camera delivers (128 for the seed's 7-bit system).
    distortion : tuple of float
        Lens distortion in OpenCV's order ``(k1, k2, p1, p2[, k3])`` (Brown-Conrady,
        on normalised coordinates); empty (default) for none.  The seed's camera has
        none; a real lens calibrated with :func:`cv2.calibrateCamera` does.

    Examples
    --------
    >>> cam = Camera()
    >>> round(cam.fx, 2), cam.principal_point
    (1453.49, (254.0, 240.0))
    >>> pose = Pose(0.0, 0.0, 1000.0)
    >>> cam.project([[0.0, 0.0, 0.0]], pose)[0]
    array([[254., 240.]])
    """

    focal_length_mm: float = 25.0
    pixel_pitch_mm: tuple[float, float] = (0.0172, 0.0137)
    image_size: tuple[int, int] = (509, 481)
    principal_point: tuple[float, float] = field(default=(math.nan, math.nan))
    grey_levels: int = 128
    distortion: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        require_positive("focal_length_mm", self.focal_length_mm)
        if len(self.pixel_pitch_mm) != 2:
            raise InputError(
                f"pixel_pitch_mm must be (horizontal, vertical), got {self.pixel_pitch_mm}"
            )
        for p in self.pixel_pitch_mm:
            require_positive("pixel_pitch_mm", p)
        w, h = self.image_size
        if int(w) != w or int(h) != h or w < 5 or h < 5:
            raise InputError(
                "image_size must be (width, height) of at least 5 pixels, "
                f"got {self.image_size}"
            )
        object.__setattr__(self, "pixel_pitch_mm", tuple(float(p) for p in self.pixel_pitch_mm))
        object.__setattr__(self, "image_size", (int(w), int(h)))
        if (
            isinstance(self.grey_levels, bool)
            or not isinstance(self.grey_levels, int | np.integer)
            or self.grey_levels < 2
        ):
            raise InputError(f"grey_levels must be an integer >= 2, got {self.grey_levels}")
        object.__setattr__(self, "grey_levels", int(self.grey_levels))
        if len(self.principal_point) != 2:
            raise InputError(f"principal_point must be (cx, cy), got {self.principal_point}")
        cx, cy = self.principal_point
        if math.isnan(cx) and math.isnan(cy):
            object.__setattr__(self, "principal_point", ((w - 1) / 2.0, (h - 1) / 2.0))
        else:
            require_finite("principal_point", [cx, cy])
            if max(abs(cx), abs(cy)) > 1e7:  # no real camera; triangulation would lose d
                raise InputError(f"principal_point must be within +-1e7 pixels, got {cx, cy}")
            object.__setattr__(self, "principal_point", (float(cx), float(cy)))
        dist = tuple(float(v) for v in self.distortion)
        if len(dist) not in (0, 4, 5):
            raise InputError(
                f"distortion must be (k1, k2, p1, p2[, k3]) or empty, got {self.distortion}"
            )
        require_finite("distortion", list(dist))
        object.__setattr__(self, "distortion", () if not any(dist) else dist)

    @property
    def dist_coeffs(self) -> NDArray[np.float64]:
        """Distortion as OpenCV's ``(5,)`` vector ``k1, k2, p1, p2, k3`` (zeros if none)."""
        d = np.zeros(5)
        d[: len(self.distortion)] = self.distortion
        return d

    def distort(self, normalised: ArrayLike) -> NDArray[np.float64]:
        """Apply the lens distortion to normalised coordinates ``(N, 2)`` -> ``(N, 2)``."""
        n = np.asarray(normalised, dtype=float)
        if not self.distortion:
            return n.copy()
        k1, k2, p1, p2, k3 = self.dist_coeffs
        x, y = n[..., 0], n[..., 1]
        r2 = x * x + y * y
        radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
        xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x)
        yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y
        return np.stack([xd, yd], axis=-1)

    def undistort(self, distorted: ArrayLike, *, iterations: int = 30) -> NDArray[np.float64]:
        """Invert :meth:`distort` (fixed-point iteration, to ~1e-12 for lens-like values).

        Examples
        --------
        >>> cam = Camera(distortion=(-0.2, 0.05, 0.001, -0.002, 0.0))
        >>> n = np.array([[0.1, -0.08], [-0.12, 0.09]])
        >>> bool(np.allclose(cam.undistort(cam.distort(n)), n, atol=1e-12))
        True
        """
        d = np.asarray(distorted, dtype=float)
        if not self.distortion:
            return d.copy()
        k1, k2, p1, p2, k3 = self.dist_coeffs
        xd, yd = d[..., 0], d[..., 1]
        x, y = xd.copy(), yd.copy()
        for _ in range(iterations):  # fixed-point on whole arrays, not on pixels
            r2 = x * x + y * y
            radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
            x = (xd - 2.0 * p1 * x * y - p2 * (r2 + 2.0 * x * x)) / radial
            y = (yd - p1 * (r2 + 2.0 * y * y) - 2.0 * p2 * x * y) / radial
        return np.stack([x, y], axis=-1)

    @property
    def fx(self) -> float:
        """Focal length in horizontal pixels, ``s / pitch_x``."""
        return self.focal_length_mm / self.pixel_pitch_mm[0]

    @property
    def fy(self) -> float:
        """Focal length in vertical pixels, ``s / pitch_y``."""
        return self.focal_length_mm / self.pixel_pitch_mm[1]

    @property
    def width(self) -> int:
        return self.image_size[0]

    @property
    def height(self) -> int:
        return self.image_size[1]

    @property
    def K(self) -> NDArray[np.float64]:
        """Intrinsic matrix, shape ``(3, 3)``."""
        cx, cy = self.principal_point
        return np.array([[self.fx, 0.0, cx], [0.0, self.fy, cy], [0.0, 0.0, 1.0]])

    def project(
        self, points: ArrayLike, pose: Pose
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Project world points into the image.

        Parameters
        ----------
        points : array_like, shape (N, 3)
            World points, millimetres.
        pose : Pose
            Camera pose.

        Returns
        -------
        pixels : ndarray, shape (N, 2)
            Image coordinates ``(x, y)``.
        depth : ndarray, shape (N,)
            Depth along the optical axis, millimetres (positive in front).
        """
        p = np.atleast_2d(np.asarray(points, dtype=float))
        pc = (p - pose.position) @ pose.rotation
        z = pc[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            n = self.distort(np.column_stack([pc[:, 0] / z, pc[:, 1] / z]))
            x = self.fx * n[:, 0] + self.principal_point[0]
            y = self.fy * n[:, 1] + self.principal_point[1]
        return np.column_stack([x, y]), z

    def backproject(
        self, pixels: ArrayLike, depth: ArrayLike, pose: Pose
    ) -> NDArray[np.float64]:
        """World points at the given depths behind image points.

        Parameters
        ----------
        pixels : array_like, shape (N, 2)
            Image coordinates ``(x, y)``.
        depth : array_like, shape (N,)
            Depth along the optical axis, millimetres.
        pose : Pose

        Returns
        -------
        ndarray, shape (N, 3)
            World points, millimetres.

        Examples
        --------
        >>> cam, pose = Camera(), Pose(10.0, -5.0, 900.0, 0.3)
        >>> P = np.array([[12.0, 40.0, 0.0], [-30.0, 2.0, 50.0]])
        >>> uv, z = cam.project(P, pose)
        >>> bool(np.allclose(cam.backproject(uv, z, pose), P))
        True
        """
        uv = np.atleast_2d(np.asarray(pixels, dtype=float))
        z = np.asarray(depth, dtype=float)
        cx, cy = self.principal_point
        n = self.undistort(np.column_stack([(uv[:, 0] - cx) / self.fx, (uv[:, 1] - cy) / self.fy]))
        pc = np.column_stack([n[:, 0] * z, n[:, 1] * z, z])
        return pc @ pose.rotation.T + pose.position


SEED_CAMERA = Camera()
"""The seed's camera: 509 x 481 pixels, 25 mm lens, 17.2 x 13.7 um pixels, 7-bit grey."""


def wrap_angle(angle: float) -> float:
    """Wrap an angle in radians into ``(-pi, pi]``.

    >>> round(wrap_angle(3 * math.pi / 2), 6)
    -1.570796
    >>> wrap_angle(math.pi) == math.pi
    True
    """
    a = math.remainder(float(angle), 2.0 * math.pi)
    return math.pi if a == -math.pi else a


# --------------------------------------------------------------------------------------
# YAML files
# --------------------------------------------------------------------------------------

_CAMERA_KEYS = (
    "focal_length_mm", "pixel_pitch_mm", "image_size", "principal_point", "grey_levels",
    "distortion",
)
_POSE_KEYS = ("x", "y", "z", "phi_deg")


def _is_number(v: object) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _get_number(
    data: Mapping[str, Any], key: str, source: str, *, positive: bool = False
) -> float:
    if key not in data:
        raise InputError(f"{source}: missing key '{key}'")
    v = data[key]
    if not _is_number(v) or not math.isfinite(v) or (positive and v <= 0):
        want = "a finite number > 0" if positive else "a finite number"
        raise InputError(f"{source}: key '{key}' must be {want}, got {v!r}")
    return float(v)


def _get_pair(
    data: Mapping[str, Any],
    key: str,
    source: str,
    *,
    positive: bool = False,
    integer: bool = False,
    what: str = "[a, b]",
) -> tuple[float, float]:
    if key not in data:
        raise InputError(f"{source}: missing key '{key}'")
    v = data[key]
    ok = isinstance(v, list | tuple) and len(v) == 2 and all(_is_number(e) for e in v)
    if ok:
        ok = all(math.isfinite(e) for e in v)
    if ok and positive:
        ok = all(e > 0 for e in v)
    if ok and integer:
        ok = all(isinstance(e, int) for e in v)
    if not ok:
        kind = "integers" if integer else "finite numbers"
        cond = " > 0" if positive else ""
        raise InputError(f"{source}: key '{key}' must be {what}, two {kind}{cond}, got {v!r}")
    return (v[0], v[1]) if integer else (float(v[0]), float(v[1]))


def _check_keys(data: object, allowed: tuple[str, ...], source: str, what: str) -> None:
    if not isinstance(data, Mapping):
        raise InputError(f"{source}: a {what} must be a mapping of keys {list(allowed)}")
    unknown = [k for k in data if k not in allowed]
    if unknown:
        raise InputError(f"{source}: unknown key '{unknown[0]}' (allowed: {', '.join(allowed)})")


def camera_to_dict(camera: Camera) -> dict[str, Any]:
    """A :class:`Camera` as a plain mapping of the keys of the camera YAML file.

    Examples
    --------
    >>> camera_to_dict(Camera())  # doctest: +NORMALIZE_WHITESPACE
    {'focal_length_mm': 25.0, 'pixel_pitch_mm': [0.0172, 0.0137], 'image_size': [509, 481],
     'principal_point': [254.0, 240.0], 'grey_levels': 128}
    """
    out: dict[str, Any] = {
        "focal_length_mm": float(camera.focal_length_mm),
        "pixel_pitch_mm": [float(p) for p in camera.pixel_pitch_mm],
        "image_size": [int(n) for n in camera.image_size],
        "principal_point": [float(c) for c in camera.principal_point],
        "grey_levels": int(camera.grey_levels),
    }
    if camera.distortion:
        out["distortion"] = [float(v) for v in camera.distortion]
    return out


def camera_from_dict(data: Mapping[str, Any], *, source: str = "camera") -> Camera:
    """Build a :class:`Camera` from a mapping with the keys of the camera YAML file.

    Parameters
    ----------
    data : mapping
        Keys ``focal_length_mm`` (> 0), ``pixel_pitch_mm`` ``[x, y]`` (mm, > 0),
        ``image_size`` ``[width, height]`` (integers), optional ``principal_point``
        ``[cx, cy]`` (pixels; default the image centre) and optional ``grey_levels``
        (integer >= 2; default 128).
    source : str
        Name used in error messages (the file name when loading a file).

    Returns
    -------
    Camera

    Raises
    ------
    InputError
        One line naming `source` and the key: missing, unknown, NaN, negative or of the
        wrong type.

    Examples
    --------
    >>> cam = camera_from_dict({"focal_length_mm": 16, "pixel_pitch_mm": [0.01, 0.01],
    ...                         "image_size": [640, 480]})
    >>> cam.principal_point, cam.grey_levels
    ((319.5, 239.5), 128)
    >>> camera_from_dict({"focal_length_mm": -16}, source="cam.yaml")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: cam.yaml: key 'focal_length_mm' must be a finite number > 0, ...
    """
    _check_keys(data, _CAMERA_KEYS, source, "camera")
    f = _get_number(data, "focal_length_mm", source, positive=True)
    pitch = _get_pair(data, "pixel_pitch_mm", source, positive=True, what="[x, y]")
    size = _get_pair(data, "image_size", source, positive=True, integer=True, what="[w, h]")
    pp: tuple[float, float] = (math.nan, math.nan)
    if "principal_point" in data and data["principal_point"] is not None:
        pp = _get_pair(data, "principal_point", source, what="[cx, cy]")
    grey = data.get("grey_levels", 128)
    if not isinstance(grey, int) or isinstance(grey, bool) or grey < 2:
        raise InputError(f"{source}: key 'grey_levels' must be an integer >= 2, got {grey!r}")
    dist = data.get("distortion") or ()
    if not isinstance(dist, list | tuple) or not all(_is_number(v) for v in dist):
        raise InputError(f"{source}: key 'distortion' must be [k1, k2, p1, p2(, k3)], "
                         f"got {dist!r}")
    try:
        return Camera(
            focal_length_mm=f,
            pixel_pitch_mm=pitch,
            image_size=(int(size[0]), int(size[1])),
            principal_point=pp,
            grey_levels=grey,
            distortion=tuple(dist),
        )
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from None


def pose_to_dict(pose: Pose) -> dict[str, float]:
    """A :class:`Pose` as a mapping ``x, y, z`` (mm), ``phi_deg`` (degrees).

    >>> pose_to_dict(Pose(1.0, 2.0, 1000.0, math.pi / 2))
    {'x': 1.0, 'y': 2.0, 'z': 1000.0, 'phi_deg': 90.0}
    """
    return {
        "x": float(pose.x),
        "y": float(pose.y),
        "z": float(pose.z),
        "phi_deg": round(math.degrees(pose.phi), 12),
    }


def pose_from_dict(data: Mapping[str, Any], *, source: str = "pose") -> Pose:
    """Build a :class:`Pose` from a mapping ``x, y, z`` (mm) and ``phi_deg`` (degrees).

    ``phi_deg`` may be left out (0 degrees); ``x``, ``y``, ``z`` are required.  Files
    hold degrees; :class:`Pose` holds radians.

    >>> pose_from_dict({"x": 0, "y": 10, "z": 1000, "phi_deg": 180}).phi == math.pi
    True
    >>> pose_from_dict({"x": 0, "y": 10}, source="left.yaml")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: left.yaml: missing key 'z'
    """
    _check_keys(data, _POSE_KEYS, source, "pose")
    x = _get_number(data, "x", source)
    y = _get_number(data, "y", source)
    z = _get_number(data, "z", source)
    phi_deg = _get_number(data, "phi_deg", source) if "phi_deg" in data else 0.0
    return Pose(x, y, z, math.radians(phi_deg))


def _read_yaml(path: str | os.PathLike[str], what: str) -> Any:
    name = os.fspath(path)
    try:
        with open(name, encoding="utf-8") as fh:
            text = fh.read()
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise InputError(f"{name}: cannot read {what} file ({reason})") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{name}: not a valid YAML {what} file{where}") from None


class _Dumper(yaml.SafeDumper):
    """Block-style mappings with flow-style ``[a, b]`` lists."""


_Dumper.add_representer(
    list, lambda d, v: d.represent_sequence("tag:yaml.org,2002:seq", v, flow_style=True)
)


def _write_yaml(data: Mapping[str, Any], path: str | os.PathLike[str], what: str) -> None:
    name = os.fspath(path)
    try:
        with open(name, "w", encoding="utf-8") as fh:
            yaml.dump(dict(data), fh, Dumper=_Dumper, sort_keys=False, default_flow_style=False)
    except OSError as exc:
        raise InputError(f"{name}: cannot write {what} file ({exc.strerror})") from None


def load_camera_yaml(path: str | os.PathLike[str]) -> Camera:
    """Read a :class:`Camera` from a YAML file (keys as in :func:`camera_from_dict`).

    Raises
    ------
    InputError
        Unreadable file, invalid YAML, or a missing / bad key; the message names the
        file and the key.
    """
    return camera_from_dict(_read_yaml(path, "camera"), source=os.fspath(path))


def save_camera_yaml(camera: Camera, path: str | os.PathLike[str]) -> None:
    """Write a :class:`Camera` to a YAML file that :func:`load_camera_yaml` reads back."""
    _write_yaml(camera_to_dict(camera), path, "camera")


def load_pose_yaml(path: str | os.PathLike[str]) -> Pose:
    """Read a :class:`Pose` from a YAML file with keys ``x, y, z`` (mm), ``phi_deg``."""
    return pose_from_dict(_read_yaml(path, "pose"), source=os.fspath(path))


def save_pose_yaml(pose: Pose, path: str | os.PathLike[str]) -> None:
    """Write a :class:`Pose` to a YAML file (``phi`` in degrees as ``phi_deg``)."""
    _write_yaml(pose_to_dict(pose), path, "pose")


def load_stereo_poses_yaml(path: str | os.PathLike[str]) -> tuple[Pose, Pose]:
    """Read the two viewpoints ``left:`` and ``right:`` (each a pose mapping) of a file."""
    name = os.fspath(path)
    data = _read_yaml(path, "poses")
    _check_keys(data, ("left", "right"), name, "stereo pose file")
    out = []
    for side in ("left", "right"):
        if side not in data:
            raise InputError(f"{name}: missing key '{side}'")
        out.append(pose_from_dict(data[side], source=f"{name}: {side}"))
    return out[0], out[1]


# --------------------------------------------------------------------------------------
# Epipolar frames and rectification (seed 2.2)
# --------------------------------------------------------------------------------------


def rectification_matrix(camera: Camera, theta: float) -> NDArray[np.float64]:
    """Pixel map ``A = K M(theta) K^-1`` from an image to its rectified image.

    Parameters
    ----------
    camera : Camera
    theta : float
        ``phi - alpha``, radians: the camera's yaw relative to the baseline direction.

    Returns
    -------
    ndarray, shape (3, 3)
        Affine matrix (last row ``[0, 0, 1]``) taking homogeneous pixel coordinates of the
        real camera (yaw ``phi``) to those of the virtual camera with the same optical
        centre and intrinsics and yaw ``alpha``.

    Notes
    -----
    With camera axes ``x_c = (cos phi, sin phi, 0)``, ``y_c = (sin phi, -cos phi, 0)``,
    ``z_c = (0, 0, -1)`` the rotation from the real to the virtual camera frame is
    ``R_alpha^T R_phi = [[cos t, sin t, 0], [-sin t, cos t, 0], [0, 0, 1]]`` with
    ``t = theta``: a rotation about the optical axis, so depth is unchanged and the
    normalised image coordinates rotate by ``M(theta)``.  Pixels are not square
    (``fx != fy``), so in pixels the map is the affine ``K M K^-1``, not a rotation.

    References
    ----------
    Seed 2.2: the normal (pixel) frame and the epipolar frame differ by a rotation about
    the z axis by ``theta_l = phi_l - alpha`` (``theta_r``).

    Examples
    --------
    A quarter turn is not a rotation of the pixel grid (17.2 x 13.7 um pixels):

    >>> A = rectification_matrix(Camera(), math.pi / 2)
    >>> np.round(A[:2, :2], 4) + 0.0
    array([[ 0.    ,  0.7965],
           [-1.2555,  0.    ]])
    """
    c, s = math.cos(theta), math.sin(theta)
    rot = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    K = camera.K
    cx, cy = camera.principal_point
    K_inv = np.array(
        [[1.0 / camera.fx, 0.0, -cx / camera.fx], [0.0, 1.0 / camera.fy, -cy / camera.fy],
         [0.0, 0.0, 1.0]]
    )
    return K @ rot @ K_inv


def _points2(points: ArrayLike, name: str = "points") -> NDArray[np.float64]:
    p = np.asarray(points, dtype=float)
    if p.ndim == 1 and p.shape[0] == 2:
        p = p[None, :]
    if p.ndim != 2 or p.shape[1] != 2:
        raise InputError(f"{name} must have shape (N, 2), got {p.shape}")
    return p


def image_to_epipolar(points: ArrayLike, camera: Camera, theta: float) -> NDArray[np.float64]:
    """Map image points of a camera with yaw ``phi`` to its rectified (epipolar) image.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Pixel coordinates ``(x, y)`` in the image taken with yaw ``phi``.
    camera : Camera
    theta : float
        ``phi - alpha``, radians (:attr:`EpipolarGeometry.theta_l` or ``theta_r``).

    Returns
    -------
    ndarray, shape (N, 2)
        Pixel coordinates in the rectified image: exactly where the virtual camera at the
        same optical centre with yaw ``alpha`` sees the same world point.  The rectified
        rows are epipolar lines.

    Notes
    -----
    1. normalise ``n = K^-1 p``; 2. rotate ``n' = M(theta) n`` with
    ``M = [[cos, sin], [-sin, cos]]``; 3. ``p' = K n'``.  See
    :func:`rectification_matrix`.

    References
    ----------
    Seed 2.2 (theta_l = phi_l - alpha, theta_r = phi_r - alpha).

    Examples
    --------
    >>> cam = Camera()
    >>> p = np.array([[300.0, 100.0]])
    >>> q = image_to_epipolar(p, cam, 0.4)
    >>> bool(np.allclose(epipolar_to_image(q, cam, 0.4), p))
    True
    """
    p = _points2(points)
    A = rectification_matrix(camera, theta)
    return p @ A[:2, :2].T + A[:2, 2]


def epipolar_to_image(points: ArrayLike, camera: Camera, theta: float) -> NDArray[np.float64]:
    """Inverse of :func:`image_to_epipolar`: rectified pixels to pixels of the real image.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Pixel coordinates in the rectified image.
    camera : Camera
    theta : float
        ``phi - alpha``, radians.

    Returns
    -------
    ndarray, shape (N, 2)
        Pixel coordinates in the image taken with yaw ``phi``.
    """
    return image_to_epipolar(points, camera, -theta)


_INTERPOLATION = {
    "nearest": cv2.INTER_NEAREST,
    "linear": cv2.INTER_LINEAR,
    "cubic": cv2.INTER_CUBIC,
    "lanczos4": cv2.INTER_LANCZOS4,
}


def _source_coordinates(
    camera: Camera, theta: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    A = rectification_matrix(camera, -theta)  # rectified pixel -> real pixel
    w, h = camera.image_size
    xs, ys = np.meshgrid(np.arange(w, dtype=float), np.arange(h, dtype=float))
    return A[0, 0] * xs + A[0, 1] * ys + A[0, 2], A[1, 0] * xs + A[1, 1] * ys + A[1, 2]


def rectified_valid_mask(camera: Camera, theta: float) -> NDArray[np.bool_]:
    """Pixels of the rectified image whose source lies inside the real image.

    Returns
    -------
    ndarray of bool, shape (H, W)
        True where the source position lies within the outer pixel centres of the
        real image, ``0 <= x <= W - 1`` and ``0 <= y <= H - 1``.

    Examples
    --------
    >>> bool(rectified_valid_mask(Camera(), 0.0).all())
    True
    """
    sx, sy = _source_coordinates(camera, theta)
    w, h = camera.image_size
    eps = 1e-9
    return (sx >= -eps) & (sx <= w - 1 + eps) & (sy >= -eps) & (sy <= h - 1 + eps)


def rectify_image(
    image: ArrayLike,
    camera: Camera,
    theta: float,
    *,
    interpolation: Literal["nearest", "linear", "cubic", "lanczos4"] = "cubic",
    fill_value: float = math.nan,
) -> NDArray[np.float64]:
    """The image that a virtual camera with yaw ``alpha`` at the same place would see.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Grey image taken with yaw ``phi`` (any real dtype; ``(H, W)`` must match
        ``camera.image_size``).
    camera : Camera
    theta : float
        ``phi - alpha``, radians.
    interpolation : {'cubic', 'linear', 'nearest', 'lanczos4'}
        OpenCV interpolator.  Cubic (default) or linear for measurement.
    fill_value : float
        Value of rectified pixels whose source position falls outside the real image
        (beyond its outer pixel centres); NaN by default, so that these pixels cannot
        pass for image content.

    Returns
    -------
    ndarray of float64, shape (H, W)
        Rectified image, same size and intrinsics as the input; its rows are epipolar
        lines.  No clipping: cubic interpolation may overshoot the input's range slightly.

    Notes
    -----
    1. ``A^-1 = K M(-theta) K^-1`` maps each rectified pixel to its source position
       (:func:`epipolar_to_image`).
    2. ``cv2.warpAffine(..., WARP_INVERSE_MAP)`` samples the image there in float64;
       where the interpolation support reaches past the image border the edge pixels are
       replicated (``BORDER_REPLICATE``).
    3. Pixels whose source position is outside the image are set to `fill_value`
       (:func:`rectified_valid_mask`).

    OpenCV quantises the sampling positions to 1/32 pixel, so the warped content can be
    off the exact point map by up to about 0.016 pixel; use :func:`image_to_epipolar`
    on measured points when that matters.

    References
    ----------
    Seed 2.2, 4.2.1: each image is rotated by its theta so that its epipolar lines are
    the rows (the seed draws rulers along the epipolar lines instead).

    Examples
    --------
    >>> cam = Camera(image_size=(9, 7))
    >>> img = np.arange(63, dtype=float).reshape(7, 9)
    >>> bool(np.allclose(rectify_image(img, cam, 0.0), img))
    True
    """
    img = np.asarray(image)
    w, h = camera.image_size
    if img.ndim != 2 or img.shape != (h, w):
        raise InputError(f"image must have shape (H, W) = ({h}, {w}), got {img.shape}")
    if interpolation not in _INTERPOLATION:
        raise InputError(
            f"interpolation must be one of {sorted(_INTERPOLATION)}, got {interpolation!r}"
        )
    require_finite("theta", float(theta))
    src = img.astype(np.float64, copy=False)
    A_inv = rectification_matrix(camera, -theta)[:2, :]
    out = cv2.warpAffine(
        src,
        A_inv,
        (w, h),
        flags=_INTERPOLATION[interpolation] | cv2.WARP_INVERSE_MAP,
        borderMode=cv2.BORDER_REPLICATE,
    )
    out[~rectified_valid_mask(camera, theta)] = fill_value
    return out


@dataclass(frozen=True)
class EpipolarGeometry:
    """The epipolar frame of two viewpoints of one camera (seed 2.2, figure 4-2).

    Build it with :meth:`from_poses`.  The frame has its origin at the midpoint of the two
    optical centres, X along the baseline ``(cos alpha, sin alpha, 0)`` (from the left
    to the right viewpoint), Z along the optical axis (world ``-Z``, down) and
    ``Y = Z x X``: the axes of a virtual camera with yaw ``alpha``.

    Attributes
    ----------
    camera : Camera
    pose_left, pose_right : Pose
        The two viewpoints; "left" is the one at ``-D/2`` along X.
    alpha : float
        ``atan2(y_r - y_l, x_r - x_l)``, radians, in ``(-pi, pi]``.
    theta_l, theta_r : float
        ``phi_l - alpha``, ``phi_r - alpha``, radians, wrapped into ``(-pi, pi]``.
    baseline_mm : float
        ``D``, distance between the optical centres projected on the horizontal plane.
    origin : tuple of float
        Midpoint of the two optical centres, world millimetres.

    Examples
    --------
    >>> g = EpipolarGeometry.from_poses(Camera(), Pose(-10.0, 0.0, 1000.0, 0.1),
    ...                                 Pose(10.0, 0.0, 1000.0, 0.12))
    >>> round(g.alpha, 12), round(g.theta_l, 12), round(g.theta_r, 12), g.baseline_mm
    (0.0, 0.1, 0.12, 20.0)
    >>> g.to_world([[0.0, 0.0, 1000.0]])
    array([[0., 0., 0.]])
    """

    camera: Camera
    pose_left: Pose
    pose_right: Pose
    alpha: float
    theta_l: float
    theta_r: float
    baseline_mm: float
    origin: tuple[float, float, float]

    @classmethod
    def from_poses(cls, camera: Camera, pose_left: Pose, pose_right: Pose) -> EpipolarGeometry:
        """Epipolar frame of the viewpoints `pose_left` and `pose_right`.

        Raises
        ------
        InputError
            If the optical centres coincide in the horizontal plane (``D = 0``).

        Notes
        -----
        ``alpha = atan2(y_r - y_l, x_r - x_l)``, ``theta_l = phi_l - alpha``,
        ``theta_r = phi_r - alpha``, ``D = hypot(x_r - x_l, y_r - y_l)``.

        References
        ----------
        Seed 2.2 (alpha, theta_l, theta_r), 4.1 and figure 4-2 (viewpoints at ``+-D/2``).
        """
        dx = pose_right.x - pose_left.x
        dy = pose_right.y - pose_left.y
        D = math.hypot(dx, dy)
        if not D > 1e-9:
            raise InputError(
                "baseline: the two optical centres coincide in the horizontal plane "
                f"(D = {D} mm); alpha is undefined"
            )
        alpha = math.atan2(dy, dx)
        origin = 0.5 * (pose_left.position + pose_right.position)
        return cls(
            camera=camera,
            pose_left=pose_left,
            pose_right=pose_right,
            alpha=alpha,
            theta_l=wrap_angle(pose_left.phi - alpha),
            theta_r=wrap_angle(pose_right.phi - alpha),
            baseline_mm=D,
            origin=(float(origin[0]), float(origin[1]), float(origin[2])),
        )

    @property
    def rotation(self) -> NDArray[np.float64]:
        """``(3, 3)``: columns are the epipolar X, Y, Z axes in the world."""
        return Pose(0.0, 0.0, 0.0, self.alpha).rotation

    def virtual_pose(self, side: Literal["left", "right"]) -> Pose:
        """Pose of the rectified (virtual) camera: same optical centre, yaw ``alpha``."""
        p = self._pose(side)
        return Pose(p.x, p.y, p.z, self.alpha)

    def theta(self, side: Literal["left", "right"]) -> float:
        """``theta_l`` or ``theta_r``."""
        if side not in ("left", "right"):
            raise InputError(f"side must be 'left' or 'right', got {side!r}")
        return self.theta_l if side == "left" else self.theta_r

    def _pose(self, side: str) -> Pose:
        if side not in ("left", "right"):
            raise InputError(f"side must be 'left' or 'right', got {side!r}")
        return self.pose_left if side == "left" else self.pose_right

    def to_world(self, points_epi: ArrayLike) -> NDArray[np.float64]:
        """Epipolar-frame points to world points (lift triangulated points, seed 3.6).

        Parameters
        ----------
        points_epi : array_like, shape (N, 3)
            ``(X, Y, Z)`` in the epipolar frame, millimetres (Z = depth below the
            mid-baseline point, positive in front of the camera).

        Returns
        -------
        ndarray, shape (N, 3)
            World points, millimetres: ``origin + R @ p``.
        """
        p = np.asarray(points_epi, dtype=float)
        if p.ndim == 1 and p.shape[0] == 3:
            p = p[None, :]
        if p.ndim != 2 or p.shape[1] != 3:
            raise InputError(f"points_epi must have shape (N, 3), got {p.shape}")
        return p @ self.rotation.T + np.asarray(self.origin)

    def from_world(self, points: ArrayLike) -> NDArray[np.float64]:
        """World points ``(N, 3)`` to the epipolar frame ``(N, 3)``: ``R^T (P - origin)``."""
        p = np.asarray(points, dtype=float)
        if p.ndim == 1 and p.shape[0] == 3:
            p = p[None, :]
        if p.ndim != 2 or p.shape[1] != 3:
            raise InputError(f"points must have shape (N, 3), got {p.shape}")
        return (p - np.asarray(self.origin)) @ self.rotation

    def to_rectified(self, points: ArrayLike, side: Literal["left", "right"]) -> NDArray:
        """Image points ``(N, 2)`` of one view to its rectified image (``image_to_epipolar``)."""
        return image_to_epipolar(points, self.camera, self.theta(side))

    def from_rectified(self, points: ArrayLike, side: Literal["left", "right"]) -> NDArray:
        """Rectified points ``(N, 2)`` back to the image of one view."""
        return epipolar_to_image(points, self.camera, self.theta(side))

    def rectify(
        self,
        image: ArrayLike,
        side: Literal["left", "right"],
        *,
        interpolation: Literal["nearest", "linear", "cubic", "lanczos4"] = "cubic",
        fill_value: float = math.nan,
    ) -> NDArray[np.float64]:
        """Rectify the image of one view (:func:`rectify_image` with its theta)."""
        return rectify_image(
            image, self.camera, self.theta(side), interpolation=interpolation,
            fill_value=fill_value,
        )
