"""The camera model (the thesis, chapter 2 and 4.1).

The camera is a pinhole looking straight down from a pose that a SCARA robot can
give it: a position ``(x, y, z)`` in the world frame (millimetres, z up) and a yaw
``phi`` about the vertical axis (:class:`robostereo.geometry.poses.Pose`).  The camera
frame has x along the image's rows (to the right), y down the image (along the
columns) and z along the optical axis, which points down (world ``-Z``), so depth is
positive.

With yaw ``phi`` the camera axes, written in the world frame, are::

    x_c = ( cos phi,  sin phi,  0)
    y_c = ( sin phi, -cos phi,  0)
    z_c = ( 0,        0,       -1)

Pixel ``(row i, column j)`` has its centre at image coordinates ``x = j, y = i``;
the principal point defaults to the image centre ``((W - 1) / 2, (H - 1) / 2)``.

A camera is given in one of two forms: *physical* (a focal length and a pixel pitch in
mm, the thesis's) or *in pixels* (``fx, fy, cx, cy`` or ``K``, as calibration tools
give it; :meth:`Camera.from_intrinsics`).  A camera in pixels holds a nominal 1 mm lens
over pixels of ``1/fx`` by ``1/fy`` mm, so every ratio the code forms (``fx``, the
eq. 9 focal term ``ds / s``) is that of its pixels, and no invented unit enters a bound.

A :class:`Camera` is written as a plain mapping, in the form it was given, by
:func:`camera_to_dict` and read back, checked, by :func:`camera_from_dict` (the YAML
files are read and written by :mod:`robostereo.io.cameras`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_finite, require_positive, shown
from robostereo.geometry.mapping_checks import check_keys, get_number, get_pair, is_number
from robostereo.geometry.plausibility import MAX_IMAGE_SIDE_PX, check_focal_px
from robostereo.geometry.poses import SE3

__all__ = [
    "DISTORTION_ROUND_TRIP_PX",
    "SEED_CAMERA",
    "Camera",
    "camera_from_dict",
    "camera_to_dict",
    "wrap_angle",
]

DISTORTION_ROUND_TRIP_PX = 0.01
"""Largest error, pixels, of ``distort(undistort(p))`` on the image border for a lens
model to be accepted: a twentieth of eq. 9's 0.2 px disparity uncertainty, far above
the ~1e-12 px of the fixed-point inverse on real lenses."""


@dataclass(frozen=True)
class Camera:
    """A pinhole camera with a rectangular pixel grid of known pitch.

    Parameters
    ----------
    focal_length_mm : float
        Lens-to-image-plane distance ``s`` (the thesis, 3.6), millimetres.
    pixel_pitch_mm : tuple of float
        Pixel pitch ``(horizontal, vertical)`` in millimetres.  The thesis gives
        17.2 um horizontally; 13.7 um vertically fits a 2/3-inch sensor of
        481 lines (6.6 mm high), see ``docs``.
    image_size : tuple of int
        ``(width, height)`` in pixels; the thesis's PULNiX CCD has 509 x 481.
    principal_point : tuple of float, optional
        ``(cx, cy)`` in pixels; default the image centre.
    grey_levels : int
        Number of grey levels the camera delivers (128 for the thesis's 7-bit system).
    distortion : tuple of float
        Lens distortion in OpenCV's order ``(k1, k2, p1, p2[, k3])`` (Brown-Conrady,
        on normalised coordinates); empty (default) for none.  The thesis's camera has
        none; a real lens calibrated with :func:`cv2.calibrateCamera` does.
    in_pixels : bool
        Given in pixels (:meth:`from_intrinsics`): `focal_length_mm` is then a nominal
        1 mm and `pixel_pitch_mm` ``(1/fx, 1/fy)``, and the camera is written back as
        ``fx, fy, cx, cy``.

    Examples
    --------
    >>> from robostereo.geometry.poses import Pose
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
    in_pixels: bool = False

    @classmethod
    def from_intrinsics(cls, K: ArrayLike, image_size: tuple[int, int], *,
                        distortion: tuple[float, ...] = (), grey_levels: int = 128) -> Camera:
        """A camera given in pixels: its intrinsic matrix and image size.

        Parameters
        ----------
        K : array_like, shape (3, 3)
            ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``, pixels, with pixel centres at
            whole coordinates (OpenCV's and this module's convention); no skew.
        image_size : tuple of int
            ``(width, height)``, pixels.
        distortion, grey_levels
            As for the class.

        Examples
        --------
        >>> cam = Camera.from_intrinsics([[800, 0, 400], [0, 810, 300], [0, 0, 1]], (800, 600))
        >>> cam.fx, cam.fy, cam.principal_point, cam.in_pixels
        (800.0, 810.0, (400.0, 300.0), True)
        """
        try:
            k = np.asarray(K, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"K must be a 3 x 3 matrix of numbers, got {shown(K)}") from None
        if k.shape != (3, 3) or not np.all(np.isfinite(k)):
            raise InputError(f"K must be a finite 3 x 3 matrix, got {shown(K)}")
        if not np.allclose(k[2], [0.0, 0.0, 1.0]) or k[1, 0] != 0.0:
            raise InputError(f"K must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]], got "
                             f"{shown(k.tolist())}")
        if abs(k[0, 1]) > 1e-6 * abs(k[0, 0]):
            raise InputError(f"K has a skew {k[0, 1]:g} (K[0][1]): the camera model has none")
        fx, fy = float(k[0, 0]), float(k[1, 1])
        if not (fx > 0 and fy > 0):
            raise InputError(f"K: fx and fy must be > 0, got {fx:g}, {fy:g}")
        return cls(focal_length_mm=1.0, pixel_pitch_mm=(1.0 / fx, 1.0 / fy),
                   image_size=image_size, principal_point=(float(k[0, 2]), float(k[1, 2])),
                   grey_levels=grey_levels, distortion=tuple(distortion), in_pixels=True)

    def in_pixel_form(self) -> Camera:
        """The same camera given in pixels (the pixel form of a physical camera).

        >>> Camera().in_pixel_form().fx == Camera().fx
        True
        """
        return Camera.from_intrinsics(self.K, self.image_size, distortion=self.distortion,
                                      grey_levels=self.grey_levels)

    def __post_init__(self) -> None:
        require_positive("focal_length_mm", self.focal_length_mm)
        if len(self.pixel_pitch_mm) != 2:
            raise InputError(
                f"pixel_pitch_mm must be (horizontal, vertical), got {self.pixel_pitch_mm}"
            )
        for p in self.pixel_pitch_mm:
            require_positive("pixel_pitch_mm", p)
        w, h = self.image_size
        if int(w) != w or int(h) != h or w < 5 or h < 5 or max(w, h) > MAX_IMAGE_SIDE_PX:
            raise InputError(
                "image_size must be (width, height) of 5 .. "
                f"{MAX_IMAGE_SIDE_PX:,} pixels, got {shown(self.image_size)}"
            )
        object.__setattr__(self, "pixel_pitch_mm", tuple(float(p) for p in self.pixel_pitch_mm))
        object.__setattr__(self, "image_size", (int(w), int(h)))
        check_focal_px(self.fx, self.fy)
        if (
            isinstance(self.grey_levels, bool)
            or not isinstance(self.grey_levels, int | np.integer)
            or not 2 <= self.grey_levels <= 2**16  # bit_depth is 1 .. 16
        ):
            raise InputError(f"grey_levels must be an integer in 2 .. 65536, got "
                             f"{shown(self.grey_levels)}")
        object.__setattr__(self, "grey_levels", int(self.grey_levels))
        object.__setattr__(self, "in_pixels", bool(self.in_pixels))
        if len(self.principal_point) != 2:
            raise InputError(f"principal_point must be (cx, cy), got {self.principal_point}")
        cx, cy = self.principal_point
        if math.isnan(cx) and math.isnan(cy):
            object.__setattr__(self, "principal_point", ((w - 1) / 2.0, (h - 1) / 2.0))
        else:
            require_finite("principal_point", [cx, cy])
            if max(abs(cx), abs(cy)) > 1e7:  # no real camera; triangulation would lose d
                raise InputError(f"principal_point must be within +-1e7 pixels, got "
                             f"{shown((cx, cy))}")
            object.__setattr__(self, "principal_point", (float(cx), float(cy)))
        dist = tuple(float(v) for v in self.distortion)
        if len(dist) not in (0, 4, 5):
            raise InputError(
                f"distortion must be (k1, k2, p1, p2[, k3]) or empty, got {self.distortion}"
            )
        require_finite("distortion", list(dist))
        object.__setattr__(self, "distortion", () if not any(dist) else dist)
        if self.distortion:
            self._check_distortion()

    def _check_distortion(self) -> None:
        """Refuse a lens model that folds the image over or cannot be inverted on it.

        Notes
        -----
        1. Radial model ``rd(r) = r (1 + k1 r^2 + k2 r^4 + k3 r^6)`` on normalised
           radii: it must rise, ``rd'(r) > 0``, from the centre until it reaches the
           image's corner radius ``r_c`` (the farthest pixel corner from the principal
           point, normalised), else points on both sides of the fold land on one pixel
           and the undistorted image is folded over (searched up to ``r = 4 r_c``).
        2. Every grabbed pixel on the image's border must come back from
           :meth:`undistort` to within :data:`DISTORTION_ROUND_TRIP_PX` of itself
           (e.g. ``k1 = 50`` is monotone but the inverse, which rectification and
           locating use, does not converge: 3.3 px off at the seed camera's corner).
        """
        k1, k2, _p1, _p2, k3 = self.dist_coeffs
        w, h = self.image_size
        cx, cy = self.principal_point
        xs = np.array([-0.5 - cx, w - 0.5 - cx]) / self.fx
        ys = np.array([-0.5 - cy, h - 0.5 - cy]) / self.fy
        r_c = float(np.sqrt(np.max(xs**2) + np.max(ys**2)))
        r = np.linspace(0.0, 4.0 * r_c, 4001)
        r2 = r * r
        rd = r * (1.0 + r2 * (k1 + r2 * (k2 + r2 * k3)))
        slope = 1.0 + r2 * (3.0 * k1 + r2 * (5.0 * k2 + r2 * 7.0 * k3))
        reach = np.flatnonzero(rd >= r_c)
        fold = np.flatnonzero(slope <= 0.0)
        end = reach[0] if reach.size else r.size
        if fold.size and fold[0] <= end:
            raise InputError(
                f"distortion {list(self.distortion)} folds the image over: the radial "
                f"model turns back at normalised radius {r[fold[0]]:.3g}, inside the "
                f"image (corner radius {r_c:.3g})")
        if not reach.size:
            raise InputError(f"distortion {list(self.distortion)} never reaches the image's "
                             f"corner radius {r_c:.3g}: not a lens model")
        t = np.linspace(0.0, 1.0, 33)
        u = np.concatenate([t * (w - 1), t * (w - 1), np.zeros_like(t), np.full_like(t, w - 1)])
        v = np.concatenate([np.zeros_like(t), np.full_like(t, h - 1), t * (h - 1), t * (h - 1)])
        n = np.column_stack([(u - cx) / self.fx, (v - cy) / self.fy])
        with np.errstate(all="ignore"):
            back = self.distort(self.undistort(n))
            err = np.abs((back - n) * [self.fx, self.fy]).max(axis=1)
        worst = float(np.nanmax(np.where(np.isfinite(err), err, np.inf)))
        if not worst <= DISTORTION_ROUND_TRIP_PX:
            raise InputError(
                f"distortion {list(self.distortion)} cannot be inverted over the image: "
                f"border pixels come back {worst:.3g} px off (a lens model's inverse "
                f"converges; is the distortion from another camera or in other units?)")

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
        self, points: ArrayLike, pose: SE3
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Project world points into the image.

        Parameters
        ----------
        points : array_like, shape (N, 3)
            World points, millimetres.
        pose : SE3
            Camera pose ``T_world_camera`` (a SCARA :class:`~robostereo.geometry.poses.Pose`
            or any 6-DoF pose).

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
        self, pixels: ArrayLike, depth: ArrayLike, pose: SE3
    ) -> NDArray[np.float64]:
        """World points at the given depths behind image points.

        Parameters
        ----------
        pixels : array_like, shape (N, 2)
            Image coordinates ``(x, y)``.
        depth : array_like, shape (N,)
            Depth along the optical axis, millimetres.
        pose : SE3
            Camera pose ``T_world_camera``.

        Returns
        -------
        ndarray, shape (N, 3)
            World points, millimetres.

        Examples
        --------
        >>> from robostereo.geometry.poses import Pose
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
"""The thesis's camera: 509 x 481 pixels, 25 mm lens, 17.2 x 13.7 um pixels, 7-bit grey."""


def wrap_angle(angle: float) -> float:
    """Wrap an angle in radians into ``(-pi, pi]``.

    >>> round(wrap_angle(3 * math.pi / 2), 6)
    -1.570796
    >>> wrap_angle(math.pi) == math.pi
    True
    """
    a = math.remainder(float(angle), 2.0 * math.pi)
    return math.pi if a == -math.pi else a



_CAMERA_KEYS = (
    "focal_length_mm", "pixel_pitch_mm", "image_size", "principal_point", "grey_levels",
    "distortion",
)
_PIXEL_KEYS = ("fx", "fy", "cx", "cy", "K", "image_size", "grey_levels", "distortion")


def camera_to_dict(camera: Camera) -> dict[str, Any]:
    """A :class:`Camera` as a plain mapping of the keys of the camera YAML file, in the
    form it was given: physical, or ``fx, fy, cx, cy`` for a camera in pixels.

    Examples
    --------
    >>> camera_to_dict(Camera().in_pixel_form())  # doctest: +ELLIPSIS
    {'fx': 1453.48..., 'fy': 1824.81..., 'cx': 254.0, 'cy': 240.0, 'image_size': [509, 481], ...}
    >>> camera_to_dict(Camera())  # doctest: +NORMALIZE_WHITESPACE
    {'focal_length_mm': 25.0, 'pixel_pitch_mm': [0.0172, 0.0137], 'image_size': [509, 481],
     'principal_point': [254.0, 240.0], 'grey_levels': 128}
    """
    out: dict[str, Any]
    if camera.in_pixels:
        cx, cy = camera.principal_point
        out = {"fx": float(camera.fx), "fy": float(camera.fy), "cx": float(cx),
               "cy": float(cy), "image_size": [int(n) for n in camera.image_size],
               "grey_levels": int(camera.grey_levels)}
        if camera.distortion:
            out["distortion"] = [float(v) for v in camera.distortion]
        return out
    out = {
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
        Physical form: keys ``focal_length_mm`` (> 0), ``pixel_pitch_mm`` ``[x, y]``
        (mm, > 0), ``image_size`` ``[width, height]`` (integers), optional
        ``principal_point`` ``[cx, cy]`` (pixels; default the image centre).  Pixel form:
        ``fx, fy, cx, cy`` (pixels) or ``K`` (3 x 3), and ``image_size``.  Both take an
        optional ``grey_levels`` (integer >= 2; default 128) and ``distortion``
        ``[k1, k2, p1, p2(, k3)]``.
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
    >>> cam = camera_from_dict({"fx": 1600, "fy": 1600, "cx": 319.5, "cy": 239.5,
    ...                         "image_size": [640, 480]})
    >>> cam.fx, cam.in_pixels
    (1600.0, True)
    >>> camera_from_dict({"focal_length_mm": -16}, source="cam.yaml")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: cam.yaml: key 'focal_length_mm' must be a finite number > 0, ...
    """
    if isinstance(data, Mapping) and ("fx" in data or "K" in data):
        return _pixel_camera_from_dict(data, source)
    check_keys(data, _CAMERA_KEYS, source, "camera")
    f = get_number(data, "focal_length_mm", source, positive=True)
    pitch = get_pair(data, "pixel_pitch_mm", source, positive=True, what="[x, y]")
    size = get_pair(data, "image_size", source, positive=True, integer=True, what="[w, h]")
    pp: tuple[float, float] = (math.nan, math.nan)
    if "principal_point" in data and data["principal_point"] is not None:
        pp = get_pair(data, "principal_point", source, what="[cx, cy]")
    grey, dist = _grey_and_distortion(data, source)
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


def _grey_and_distortion(data: Mapping[str, Any], source: str) -> tuple[int, tuple[Any, ...]]:
    grey = data.get("grey_levels", 128)
    if not isinstance(grey, int) or isinstance(grey, bool) or not 2 <= grey <= 2**16:
        raise InputError(f"{source}: key 'grey_levels' must be an integer in 2 .. 65536, "
                         f"got {shown(grey)}")
    dist = data.get("distortion") or ()
    if not isinstance(dist, list | tuple) or not all(is_number(v) for v in dist):
        raise InputError(f"{source}: key 'distortion' must be [k1, k2, p1, p2(, k3)], "
                         f"got {shown(dist)}")
    return grey, tuple(dist)


def _pixel_camera_from_dict(data: Mapping[str, Any], source: str) -> Camera:
    """The pixel form of :func:`camera_from_dict`: ``fx, fy, cx, cy`` or ``K``."""
    check_keys(data, _PIXEL_KEYS, source, "camera in pixels")
    if "K" in data:
        both = [k for k in ("fx", "fy", "cx", "cy") if k in data]
        if both:
            raise InputError(f"{source}: give K or fx, fy, cx, cy, not both (key '{both[0]}')")
        K = data["K"]
    else:
        fx, fy, cx, cy = (get_number(data, k, source, positive=k in ("fx", "fy"))
                          for k in ("fx", "fy", "cx", "cy"))
        K = [[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]]
    size = get_pair(data, "image_size", source, positive=True, integer=True, what="[w, h]")
    grey, dist = _grey_and_distortion(data, source)
    try:
        return Camera.from_intrinsics(K, (int(size[0]), int(size[1])), distortion=dist,
                                      grey_levels=grey)
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from None
