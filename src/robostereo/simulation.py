"""A simulated camera: analytic scenes rendered by ray casting, with ground truth.

The simulator stands in for the seed's PULNiX camera on the AdeptOne robot
(seed chapters 4 and 5): a pinhole :class:`~robostereo.camera.Camera` at a
:class:`~robostereo.camera.Pose` looks down on a scene of analytic primitives
(a table plane, boxes, vertical cylinders and tubes, horizontal discs and annuli
with holes) lit by a directional light and an ambient term.  :func:`render`
returns the 7-bit grey image together with the exact depth and the primitive
hit at every pixel centre, so that edges, disparities and 3-D points measured
from the images can be checked against the truth.

World coordinates are millimetres with Z up; the table top is at ``z = 0`` in
the scenes built here.  The camera conventions are those of
:mod:`robostereo.camera`: pixel ``(row i, column j)`` has its centre at
``x = j, y = i`` and a world point ``P`` has camera coordinates
``R.T @ (P - position)`` with ``R = pose.rotation``.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.ndimage import gaussian_filter

from robostereo.camera import Camera, Pose
from robostereo.errors import InputError, require_finite, require_nonnegative, require_positive
from robostereo.robot.poses import SE3

__all__ = [
    "BlockScene",
    "Box",
    "Checkerboard",
    "Cylinder",
    "Disc",
    "ImagePlane",
    "NoiseTexture",
    "PulleyScene",
    "Rendering",
    "Scene",
    "TablePlane",
    "hub_pulley_scene",
    "render",
    "sample_offsets",
    "seed_block_scene",
    "true_disparity",
]

_EPS = 1e-9
_Arr = NDArray[np.float64]


def _require_albedo(albedo: float) -> None:
    require_finite("albedo", albedo)
    if not 0.0 <= albedo <= 1.0:
        raise InputError(f"albedo must be in [0, 1], got {albedo}")


def _pair(name: str, value: Sequence[float]) -> tuple[float, float]:
    if len(value) != 2:
        raise InputError(f"{name} must be (x, y), got {value}")
    require_finite(name, [float(v) for v in value])
    return float(value[0]), float(value[1])


# --------------------------------------------------------------------------- texture


@dataclass(frozen=True, eq=False)
class NoiseTexture:
    """A smooth, periodic grey-level pattern for the table (procedural texture).

    The albedo at world ``(x, y)`` is multiplied by ``1 + amplitude * v(x, y)``,
    where ``v`` is the bilinear interpolation of ``values`` on a periodic grid of
    cell size ``cell_mm``.  Build one with :meth:`from_rng` so that the pattern is
    fixed when the scene is built and rendering stays deterministic.

    Parameters
    ----------
    values : ndarray, shape (n, m)
        Pattern values, scaled to ``[-1, 1]``; rows along world y, columns along x.
    cell_mm : float
        Grid spacing in millimetres.
    amplitude : float
        Relative albedo modulation, in ``[0, 1)``.
    """

    values: _Arr
    cell_mm: float = 4.0
    amplitude: float = 0.15

    def __post_init__(self) -> None:
        v = np.array(self.values, dtype=float)
        if v.ndim != 2 or min(v.shape) < 2 or not np.all(np.isfinite(v)):
            raise InputError(f"values must be a finite 2-D array of at least 2 x 2, got {v.shape}")
        v.setflags(write=False)
        object.__setattr__(self, "values", v)
        require_positive("cell_mm", self.cell_mm)
        if not 0.0 <= self.amplitude < 1.0:
            raise InputError(f"amplitude must be in [0, 1), got {self.amplitude}")

    @classmethod
    def from_rng(
        cls,
        rng: np.random.Generator,
        *,
        size: int = 64,
        cell_mm: float = 4.0,
        amplitude: float = 0.15,
        smooth_cells: float = 1.5,
    ) -> NoiseTexture:
        """Gaussian-smoothed white noise on a ``size x size`` periodic grid.

        Examples
        --------
        >>> t = NoiseTexture.from_rng(np.random.default_rng(0), size=16)
        >>> t.values.shape, float(np.abs(t.values).max())
        ((16, 16), 1.0)
        """
        if not isinstance(rng, np.random.Generator):
            raise InputError("rng must be a numpy.random.Generator")
        if int(size) != size or size < 2:
            raise InputError(f"size must be an integer >= 2, got {size}")
        noise = rng.standard_normal((int(size), int(size)))
        v = gaussian_filter(noise, smooth_cells, mode="wrap")
        v -= v.mean()
        v /= np.abs(v).max()
        return cls(v, cell_mm=cell_mm, amplitude=amplitude)

    def factor(self, x: _Arr, y: _Arr) -> _Arr:
        """Albedo factor ``1 + amplitude * v`` at world points, same shape as `x`."""
        n, m = self.values.shape
        u = np.asarray(x, dtype=float) / self.cell_mm
        w = np.asarray(y, dtype=float) / self.cell_mm
        u0 = np.floor(u)
        w0 = np.floor(w)
        fu = u - u0
        fw = w - w0
        j0 = u0.astype(np.int64) % m
        i0 = w0.astype(np.int64) % n
        j1 = (j0 + 1) % m
        i1 = (i0 + 1) % n
        v = self.values
        val = (v[i0, j0] * (1 - fu) + v[i0, j1] * fu) * (1 - fw) + (
            v[i1, j0] * (1 - fu) + v[i1, j1] * fu
        ) * fw
        return 1.0 + self.amplitude * val


# --------------------------------------------------------------------------- primitives
#
# Every primitive has ``_bounds()`` (a (2, 3) array of world min/max corners, or None
# when unbounded) and ``_hit(o, dx, dy, dz)`` which returns the ray parameter t of the
# nearest intersection in front of the origin (inf where the ray misses) and the
# surface normal (three arrays or scalars, any orientation).  Rays are
# ``o + t * d`` with d scaled so that t is the depth along the optical axis.


@dataclass(frozen=True)
class TablePlane:
    """The infinite horizontal plane ``z = z`` (the table top).

    Parameters
    ----------
    z : float
        Height of the plane, millimetres.
    albedo : float
        Grey reflectance in ``[0, 1]``.
    texture : NoiseTexture or None
        Optional albedo modulation.
    """

    z: float = 0.0
    albedo: float = 0.3
    texture: NoiseTexture | None = None

    def __post_init__(self) -> None:
        require_finite("z", self.z)
        _require_albedo(self.albedo)

    def _bounds(self) -> _Arr | None:
        return None

    def _hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (self.z - o[2]) / dz
        t = np.where(t > _EPS, t, np.inf)
        return t, (0.0, 0.0, 1.0)

    def _albedo_at(self, x: _Arr, y: _Arr) -> _Arr | float:
        if self.texture is None:
            return self.albedo
        return self.albedo * self.texture.factor(x, y)


@dataclass(frozen=True)
class Disc:
    """A horizontal, infinitely thin disc or annulus with circular holes.

    The surface is the set of points at height `z` whose distance to `center`
    lies in ``[inner_radius, radius]`` and that are in none of the holes.

    Parameters
    ----------
    center : tuple of float
        ``(x, y)`` of the centre, millimetres.
    z : float
        Height, millimetres.
    radius : float
        Outer radius, millimetres.
    inner_radius : float
        Inner radius (0 for a full disc).
    holes : tuple of (dx, dy, r)
        Circular holes, centres relative to `center`, millimetres.
    albedo : float
        Grey reflectance in ``[0, 1]``.
    """

    center: tuple[float, float]
    z: float
    radius: float
    inner_radius: float = 0.0
    holes: tuple[tuple[float, float, float], ...] = ()
    albedo: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _pair("center", self.center))
        require_finite("z", self.z)
        require_positive("radius", self.radius)
        if not 0.0 <= self.inner_radius < self.radius:
            raise InputError(
                f"inner_radius must be in [0, radius={self.radius}), got {self.inner_radius}"
            )
        holes = tuple(tuple(float(v) for v in h) for h in self.holes)
        for h in holes:
            if len(h) != 3 or not all(math.isfinite(v) for v in h) or h[2] <= 0:
                raise InputError(f"holes must be (dx, dy, r) with r > 0, got {h}")
        object.__setattr__(self, "holes", holes)
        _require_albedo(self.albedo)

    def _bounds(self) -> _Arr | None:
        cx, cy = self.center
        r = self.radius
        return np.array([[cx - r, cy - r, self.z], [cx + r, cy + r, self.z]])

    def _hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (self.z - o[2]) / dz
        px = o[0] + t * dx - self.center[0]
        py = o[1] + t * dy - self.center[1]
        r2 = px * px + py * py
        ok = (t > _EPS) & (r2 <= self.radius**2) & (r2 >= self.inner_radius**2)
        for hx, hy, hr in self.holes:
            ok &= (px - hx) ** 2 + (py - hy) ** 2 > hr * hr
        return np.where(ok, t, np.inf), (0.0, 0.0, 1.0)

    def _albedo_at(self, x: _Arr, y: _Arr) -> float:
        return self.albedo


@dataclass(frozen=True)
class Cylinder:
    """A vertical solid cylinder, or a tube when ``inner_radius > 0``.

    Its top is a disc (annulus for a tube) at ``z_base + height``; a tube's
    bore shows its inner wall and whatever lies below.

    Parameters
    ----------
    center : tuple of float
        ``(x, y)`` of the axis, millimetres.
    z_base : float
        Height of the bottom face, millimetres.
    radius : float
        Outer radius, millimetres.
    height : float
        Height, millimetres.
    inner_radius : float
        Bore radius (0 for a solid cylinder).
    albedo : float
        Grey reflectance in ``[0, 1]``.
    """

    center: tuple[float, float]
    z_base: float
    radius: float
    height: float
    inner_radius: float = 0.0
    albedo: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _pair("center", self.center))
        require_finite("z_base", self.z_base)
        require_positive("radius", self.radius)
        require_positive("height", self.height)
        if not 0.0 <= self.inner_radius < self.radius:
            raise InputError(
                f"inner_radius must be in [0, radius={self.radius}), got {self.inner_radius}"
            )
        _require_albedo(self.albedo)

    @property
    def z_top(self) -> float:
        """Height of the top face, millimetres."""
        return self.z_base + self.height

    def _bounds(self) -> _Arr | None:
        cx, cy = self.center
        r = self.radius
        return np.array([[cx - r, cy - r, self.z_base], [cx + r, cy + r, self.z_top]])

    def _hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
        ox, oy = o[0] - self.center[0], o[1] - self.center[1]
        z0, z1 = self.z_base, self.z_top
        a = dx * dx + dy * dy
        b = 2.0 * (ox * dx + oy * dy)
        best = np.full(np.shape(dx), np.inf)
        nx = np.zeros_like(best)
        ny = np.zeros_like(best)
        nz = np.zeros_like(best)

        def take(t: _Arr, mx: _Arr | float, my: _Arr | float, mz: float) -> None:
            closer = t < best
            best[closer] = t[closer]
            nx[closer] = np.broadcast_to(mx, best.shape)[closer]
            ny[closer] = np.broadcast_to(my, best.shape)[closer]
            nz[closer] = mz

        ri = self.inner_radius
        with np.errstate(divide="ignore", invalid="ignore"):
            # walls: the outer one is entered (near root), the bore's seen from inside (far)
            for radius, sign in ((self.radius, -1.0), (ri, 1.0)):
                if radius <= 0:
                    continue
                c = ox * ox + oy * oy - radius * radius
                disc = b * b - 4.0 * a * c
                t = (-b + sign * np.sqrt(disc)) / (2.0 * a)
                z = o[2] + t * dz
                ok = (a > 1e-18) & (disc >= 0) & (t > _EPS) & (z >= z0) & (z <= z1)
                t = np.where(ok, t, np.inf)
                px = ox + t * dx
                py = oy + t * dy
                take(t, -sign * px / radius, -sign * py / radius, 0.0)
            # caps (annuli for a tube)
            for zc, mz in ((z1, 1.0), (z0, -1.0)):
                t = (zc - o[2]) / dz
                px = ox + t * dx
                py = oy + t * dy
                r2 = px * px + py * py
                ok = (t > _EPS) & (r2 <= self.radius**2) & (r2 >= ri * ri)
                take(np.where(ok, t, np.inf), 0.0, 0.0, mz)
        return best, (nx, ny, nz)

    def _albedo_at(self, x: _Arr, y: _Arr) -> float:
        return self.albedo


@dataclass(frozen=True)
class Box:
    """A box standing on ``z_base``, axis-aligned in a frame yawed about vertical.

    Parameters
    ----------
    center : tuple of float
        ``(x, y)`` of the centre of the footprint, millimetres.
    z_base : float
        Height of the bottom face, millimetres.
    size : tuple of float
        ``(sx, sy, sz)``: extent along the box's local x, y (before yaw) and height.
    yaw : float
        Rotation of the local x axis from world X, radians, counter-clockwise from above.
    albedo : float
        Grey reflectance in ``[0, 1]``.
    texture : NoiseTexture or None
        Optional albedo modulation (by world ``x, y`` of the surface point).
    """

    center: tuple[float, float]
    z_base: float
    size: tuple[float, float, float]
    yaw: float = 0.0
    albedo: float = 0.8
    texture: NoiseTexture | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _pair("center", self.center))
        require_finite("z_base", self.z_base)
        require_finite("yaw", self.yaw)
        if len(self.size) != 3:
            raise InputError(f"size must be (sx, sy, sz), got {self.size}")
        for s in self.size:
            require_positive("size", s)
        object.__setattr__(self, "size", tuple(float(s) for s in self.size))
        _require_albedo(self.albedo)

    @property
    def z_top(self) -> float:
        """Height of the top face, millimetres."""
        return self.z_base + self.size[2]

    def corners(self) -> _Arr:
        """The 8 corners in the world, shape ``(8, 3)``."""
        hx, hy, sz = self.size[0] / 2, self.size[1] / 2, self.size[2]
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        out = []
        for lx in (-hx, hx):
            for ly in (-hy, hy):
                for lz in (0.0, sz):
                    out.append(
                        [
                            self.center[0] + c * lx - s * ly,
                            self.center[1] + s * lx + c * ly,
                            self.z_base + lz,
                        ]
                    )
        return np.array(out)

    def _bounds(self) -> _Arr | None:
        p = self.corners()
        return np.array([p.min(axis=0), p.max(axis=0)])

    def _hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        ox, oy = o[0] - self.center[0], o[1] - self.center[1]
        lo = (c * ox + s * oy, -s * ox + c * oy, o[2] - self.z_base)
        ld = (c * dx + s * dy, -s * dx + c * dy, dz)
        hx, hy, sz = self.size[0] / 2, self.size[1] / 2, self.size[2]
        slabs = ((-hx, hx), (-hy, hy), (0.0, sz))
        tmins, tmaxs = [], []
        with np.errstate(divide="ignore", invalid="ignore"):
            for (a, b), oo, d in zip(slabs, lo, ld, strict=True):
                d = np.asarray(d, dtype=float)
                t1 = (a - oo) / d
                t2 = (b - oo) / d
                inside = (oo >= a) & (oo <= b)
                parallel = d == 0
                lo_in, hi_in = np.where(inside, -np.inf, np.inf), np.where(inside, np.inf, -np.inf)
                tmins.append(np.where(parallel, lo_in, np.minimum(t1, t2)))
                tmaxs.append(np.where(parallel, hi_in, np.maximum(t1, t2)))
        tmin = np.stack(tmins)
        axis = np.argmax(tmin, axis=0)
        t_near = np.take_along_axis(tmin, axis[None], axis=0)[0]
        t_far = np.minimum(np.minimum(tmaxs[0], tmaxs[1]), tmaxs[2])
        ok = (t_near <= t_far) & (t_near > _EPS)
        t = np.where(ok, t_near, np.inf)
        # local normal: -sign(d) along the entering axis; then yaw back to the world
        lnx = np.where(axis == 0, -np.sign(ld[0]), 0.0)
        lny = np.where(axis == 1, -np.sign(ld[1]), 0.0)
        lnz = np.where(axis == 2, -np.sign(ld[2]), 0.0)
        return t, (c * lnx - s * lny, s * lnx + c * lny, lnz)

    def _albedo_at(self, x: _Arr, y: _Arr) -> _Arr | float:
        if self.texture is None:
            return self.albedo
        return self.albedo * self.texture.factor(x, y)


class _FlatPatch:
    """A flat rectangle at height ``z``, turned by ``yaw`` about ``origin``: its local
    frame, bounds and ray hits; a subclass gives its ``_extent`` in that frame."""

    origin: tuple[float, float]
    yaw: float
    z: float

    def _extent(self) -> tuple[float, float, float, float]:
        raise NotImplementedError

    def _local(self, x: _Arr, y: _Arr) -> tuple[_Arr, _Arr]:
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        px, py = x - self.origin[0], y - self.origin[1]
        return c * px + s * py, s * px - c * py

    def _bounds(self) -> _Arr | None:
        x0, x1, y0, y1 = self._extent()
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        pts = np.array([[bx, by] for bx in (x0, x1) for by in (y0, y1)])
        wx = self.origin[0] + c * pts[:, 0] + s * pts[:, 1]
        wy = self.origin[1] + s * pts[:, 0] - c * pts[:, 1]
        return np.array([[wx.min(), wy.min(), self.z], [wx.max(), wy.max(), self.z]])

    def _hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (self.z - o[2]) / dz
        bx, by = self._local(o[0] + t * dx, o[1] + t * dy)
        x0, x1, y0, y1 = self._extent()
        ok = (t > _EPS) & (bx >= x0) & (bx <= x1) & (by >= y0) & (by <= y1)
        return np.where(ok, t, np.inf), (0.0, 0.0, 1.0)


@dataclass(frozen=True)
class Checkerboard(_FlatPatch):
    """A flat chessboard calibration target lying on a horizontal plane.

    The board's inner corners are ``(i * square_mm, j * square_mm)`` in the board
    frame, ``i < columns``, ``j < rows``; the board frame has its origin at the first
    inner corner, x at `yaw` from world X, y at ``yaw - 90 deg`` and z down into the
    table (OpenCV's right-handed object frame seen from above), so
    ``T_world_board = (Rz(yaw) diag(1, -1, -1), origin)``.  The square at board
    ``(-, -)`` of the first inner corner is dark; one square of light margin surrounds
    the outer squares.

    Parameters
    ----------
    origin : tuple of float
        ``(x, y)`` of the first inner corner, world millimetres.
    z : float
        Height of the board's surface, millimetres.
    inner_corners : tuple of int
        ``(columns, rows)`` of inner corners.
    square_mm : float
    yaw : float
        Radians.
    dark, light : float
        Albedo of the dark and the light squares (the margin is light).
    """

    origin: tuple[float, float]
    z: float = 0.0
    inner_corners: tuple[int, int] = (9, 6)
    square_mm: float = 20.0
    yaw: float = 0.0
    dark: float = 0.08
    light: float = 0.85

    def __post_init__(self) -> None:
        object.__setattr__(self, "origin", _pair("origin", self.origin))
        require_finite("z", self.z)
        require_positive("square_mm", self.square_mm)
        require_finite("yaw", self.yaw)
        _require_albedo(self.dark)
        _require_albedo(self.light)

    def _extent(self) -> tuple[float, float, float, float]:
        q = self.square_mm
        c, r = self.inner_corners
        return -2 * q, c * q + q, -2 * q, r * q + q

    def _albedo_at(self, x: _Arr, y: _Arr) -> _Arr:
        bx, by = self._local(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        q = self.square_mm
        c, r = self.inner_corners
        i, j = np.floor(bx / q), np.floor(by / q)
        inside = (i >= -1) & (i <= c - 1) & (j >= -1) & (j <= r - 1)
        dark = inside & ((i + j) % 2 == 0)
        return np.where(dark, self.dark, self.light)

    @property
    def pose(self) -> SE3:
        """``T_world_board`` (the frame of the inner corners), millimetres."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        R = np.array([[c, s, 0.0], [s, -c, 0.0], [0.0, 0.0, -1.0]])
        return SE3(R, np.array([self.origin[0], self.origin[1], self.z]))


@dataclass(frozen=True, eq=False)
class ImagePlane(_FlatPatch):
    """A flat printed target (e.g. a ChArUco board) lying on a horizontal plane.

    The grey image is printed with its top-left corner at `origin`, image x at `yaw`
    from world X and image y at ``yaw - 90 deg``; pixel ``(row i, column j)`` covers
    ``[j, j + 1) x [i, i + 1)`` times `mm_per_px` in the board frame, whose z points
    down into the table (``T_world_board = (Rz(yaw) diag(1, -1, -1), origin)``, the
    frame of OpenCV's board object points).  A light margin of `margin_mm` surrounds it.

    Parameters
    ----------
    origin : tuple of float
        World ``(x, y)`` of the image's top-left corner, millimetres.
    image : ndarray, shape (H, W)
        Albedo per pixel in ``[0, 1]`` (an 8-bit board image divided by 255 and
        scaled to the paper's reflectance).
    mm_per_px : float
    z, yaw : float
    margin_mm : float
    margin_albedo : float
    """

    origin: tuple[float, float]
    image: _Arr
    mm_per_px: float
    z: float = 2.0
    yaw: float = 0.0
    margin_mm: float = 10.0
    margin_albedo: float = 0.85

    def __post_init__(self) -> None:
        object.__setattr__(self, "origin", _pair("origin", self.origin))
        img = np.array(self.image, dtype=float)
        if img.ndim != 2 or not np.all(np.isfinite(img)) or img.min() < 0 or img.max() > 1:
            raise InputError("image must be a 2-D array of albedos in [0, 1]")
        img.setflags(write=False)
        object.__setattr__(self, "image", img)
        require_positive("mm_per_px", self.mm_per_px)
        require_finite("z", self.z)
        require_finite("yaw", self.yaw)
        _require_albedo(self.margin_albedo)

    def _extent(self) -> tuple[float, float, float, float]:
        h, w = self.image.shape
        m = self.margin_mm
        return -m, w * self.mm_per_px + m, -m, h * self.mm_per_px + m

    def _albedo_at(self, x: _Arr, y: _Arr) -> _Arr:
        bx, by = self._local(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        h, w = self.image.shape
        j = np.floor(bx / self.mm_per_px).astype(np.int64)
        i = np.floor(by / self.mm_per_px).astype(np.int64)
        inside = (i >= 0) & (i < h) & (j >= 0) & (j < w)
        vals = self.image[np.clip(i, 0, h - 1), np.clip(j, 0, w - 1)]
        return np.where(inside, vals, self.margin_albedo)

    @property
    def pose(self) -> SE3:
        """``T_world_board`` (origin at the image's top-left corner), millimetres."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        R = np.array([[c, s, 0.0], [s, -c, 0.0], [0.0, 0.0, -1.0]])
        return SE3(R, np.array([self.origin[0], self.origin[1], self.z]))


Primitive = TablePlane | Disc | Cylinder | Box | Checkerboard | ImagePlane


# --------------------------------------------------------------------------- scenes


@dataclass(frozen=True)
class Scene:
    """Primitives, a directional light and an ambient term.

    The radiance of a surface point with albedo ``a`` and unit normal ``n``
    (turned towards the camera) is
    ``a * (ambient + light_intensity * max(0, n . l))`` with ``l`` the unit
    direction towards the light; 1.0 maps to the camera's top grey level.
    No shadows are cast.

    Parameters
    ----------
    primitives : tuple
        :class:`TablePlane`, :class:`Disc`, :class:`Cylinder` and :class:`Box`
        objects; the label of a primitive is its index in this tuple.
    light_direction : tuple of float
        Direction towards the light (normalised on construction).
    light_intensity : float
        Directional light strength, ``>= 0``.
    ambient : float
        Ambient light, ``>= 0``.
    background : float
        Radiance of rays that hit nothing, in ``[0, 1]``.
    """

    primitives: tuple[Primitive, ...]
    light_direction: tuple[float, float, float] = (0.3, -0.2, 1.0)
    light_intensity: float = 0.8
    ambient: float = 0.15
    background: float = 0.0

    def __post_init__(self) -> None:
        prims = tuple(self.primitives)
        for p in prims:
            if not isinstance(p, TablePlane | Disc | Cylinder | Box | Checkerboard | ImagePlane):
                raise InputError(
                    "primitives must be TablePlane, Disc, Cylinder, Box, Checkerboard or "
                    "ImagePlane objects, "
                    f"got {type(p).__name__}"
                )
        object.__setattr__(self, "primitives", prims)
        ld = np.asarray(self.light_direction, dtype=float)
        if ld.shape != (3,) or not np.all(np.isfinite(ld)) or np.linalg.norm(ld) == 0:
            raise InputError(
                f"light_direction must be a non-zero (x, y, z), got {self.light_direction}"
            )
        ld = ld / np.linalg.norm(ld)
        object.__setattr__(self, "light_direction", tuple(float(v) for v in ld))
        for name in ("light_intensity", "ambient"):
            require_nonnegative(name, getattr(self, name))
        require_finite("background", self.background)
        if not 0.0 <= self.background <= 1.0:
            raise InputError(f"background must be in [0, 1], got {self.background}")


@dataclass(frozen=True, kw_only=True)
class BlockScene(Scene):
    """The seed's precision block on a table (see :func:`seed_block_scene`).

    Attributes
    ----------
    top_z : float
        Height of the block's top face, millimetres.
    left_x, right_x : float
        World x of the block's left and right faces, millimetres.
    front_y, back_y : float
        World y of the block's faces at low and high y, millimetres.
    width : float
        ``right_x - left_x``, millimetres.
    view_pose : Pose
        The mid-baseline camera pose of the seed's view of the block.
    block_label, table_label : int
        Labels of the block and the table in a :class:`Rendering`.
    """

    top_z: float
    left_x: float
    right_x: float
    front_y: float
    back_y: float
    width: float
    view_pose: Pose
    block_label: int = 1
    table_label: int = 0


@dataclass(frozen=True, kw_only=True)
class PulleyScene(Scene):
    """A hub pulley on a table (see :func:`hub_pulley_scene`).

    Attributes
    ----------
    center : tuple of float
        ``(x, y)`` of the pulley's axis, millimetres.
    top_z : float
        Height of the highest face (the hub's top), millimetres.
    outer_radius : float
        Radius of the rim, millimetres.
    view_pose : Pose
        A camera pose centred above the pulley.
    """

    center: tuple[float, float]
    top_z: float
    outer_radius: float
    view_pose: Pose


def seed_block_scene(
    *,
    lift_mm: float = 0.0,
    camera_height_mm: float = 1050.0,
    center_xy: tuple[float, float] = (0.0, 0.0),
    offset_xy: tuple[float, float] = (-43.3, -22.5),
    width_mm: float = 23.6,
    length_mm: float = 80.0,
    height_mm: float = 50.0,
    block_albedo: float = 0.85,
    table_albedo: float = 0.3,
    texture_rng: np.random.Generator | None = None,
) -> BlockScene:
    """The precision rectangular block of the seed's accuracy test (seed 5.2, table 5-1).

    A block `width_mm` wide along world X and `length_mm` long along Y stands on
    a table at ``z = 0``; its top is at ``height_mm + lift_mm``.  The view pose is
    the mid-baseline camera position at `camera_height_mm` above the table, so the
    block's top is ``camera_height_mm - height_mm - lift_mm`` below the camera
    (1000 mm with the defaults, 920.35 mm with ``lift_mm=79.65``).

    Parameters
    ----------
    lift_mm : float
        Raise of the block's top towards the camera (seed: 79.65 mm between the two
        data sets); realised as a taller block.  Must be ``> -height_mm``.
    camera_height_mm : float
        Height of the view pose above the table, millimetres.
    center_xy : tuple of float
        World ``(x, y)`` of the centre of the block's footprint.
    offset_xy : tuple of float
        Position of the block centre relative to the view pose's ``(x, y)``.  The
        default puts the block left of and below the image centre as in table 5-1
        (faces at x = -55.1 and -31.5 mm, epipolar y from about +62 to -17 mm);
        ``(0, 0)`` centres it.
    width_mm, length_mm, height_mm : float
        Block size along X, along Y and height (at ``lift_mm = 0``).
    block_albedo, table_albedo : float
        Reflectances: a bright block on a darker table.
    texture_rng : numpy.random.Generator or None
        If given, the table gets a :class:`NoiseTexture` drawn from it.

    Returns
    -------
    BlockScene
        Label 0 is the table, label 1 the block.

    Notes
    -----
    With the seed's camera (``fx`` = 1453.5 px) the block is about 34 px wide and,
    with ``fy`` = 1824.8 px, 146 px tall at 1000 mm, crossing 18 rows at a spacing
    of 8 rows.  The seed reports the second data set *farther* from the camera
    (mean z 1007.6 then 1086.3 mm) although it says the object was lifted; here a
    positive `lift_mm` brings the top nearer, a negative one takes it away.

    References
    ----------
    Seed chapter 5.2 and table 5-1.

    Examples
    --------
    >>> s = seed_block_scene()
    >>> s.top_z, round(s.left_x, 2), round(s.right_x, 2), s.width
    (50.0, -11.8, 11.8, 23.6)
    >>> s.view_pose  # the block's faces at x = -55.1 and -31.5 mm from the view pose
    Pose(x=43.3, y=22.5, z=1050.0, phi=0.0)
    >>> seed_block_scene(lift_mm=79.65).top_z
    129.65
    """
    require_finite("lift_mm", lift_mm)
    require_positive("camera_height_mm", camera_height_mm)
    for name, v in (("width_mm", width_mm), ("length_mm", length_mm), ("height_mm", height_mm)):
        require_positive(name, v)
    if height_mm + lift_mm <= 0:
        raise InputError(f"lift_mm must be > -height_mm = {-height_mm}, got {lift_mm}")
    cx, cy = _pair("center_xy", center_xy)
    ox, oy = _pair("offset_xy", offset_xy)
    top = height_mm + lift_mm
    if top >= camera_height_mm:
        raise InputError(
            f"camera_height_mm must exceed the block top {top} mm, got {camera_height_mm}"
        )
    texture = None if texture_rng is None else NoiseTexture.from_rng(texture_rng)
    table = TablePlane(z=0.0, albedo=table_albedo, texture=texture)
    block = Box(center=(cx, cy), z_base=0.0, size=(width_mm, length_mm, top), albedo=block_albedo)
    return BlockScene(
        primitives=(table, block),
        top_z=top,
        left_x=cx - width_mm / 2,
        right_x=cx + width_mm / 2,
        front_y=cy - length_mm / 2,
        back_y=cy + length_mm / 2,
        width=width_mm,
        view_pose=Pose(cx - ox, cy - oy, camera_height_mm, 0.0),
    )


def hub_pulley_scene(
    *,
    center_xy: tuple[float, float] = (0.0, 0.0),
    camera_height_mm: float = 1070.0,
    scale: float = 1.0,
    teeth: int = 40,
    table_albedo: float = 0.2,
    texture_rng: np.random.Generator | None = None,
) -> PulleyScene:
    """A toothed hub pulley (the seed's "gear in an auto part", seed 5.1) on a table.

    From the outside in (millimetres at ``scale = 1``, all parts concentric with
    `center_xy`, standing on the table at ``z = 0``):

    * `teeth` gear teeth, boxes 8 deep and 7 wide yawed to point radially,
      r 88..96, 45 high;
    * the rim, a tube r 76..88, 45 high, with two dark belt grooves on its top face
      (annuli r 80..82.5 and 84..86.5);
    * the web, an annulus r 24..76 at z = 20 with eight 7-mm lightening holes on
      the r 56 circle (the table shows through), a bright machined ring r 65..69
      and a dark ring r 42..45;
    * the boss, a tube r 24..38, 32 high, with a dark ring r 29..33 on top;
    * the hub, a tube r 10..24, 70 high, whose bore shows the table.

    Parameters
    ----------
    center_xy : tuple of float
        World ``(x, y)`` of the pulley's axis.
    camera_height_mm : float
        Height of the view pose above the table (1000 mm above the hub's top by
        default).
    scale : float
        Scale factor on every dimension of the part.
    teeth : int
        Number of gear teeth (0 for a plain rim).
    table_albedo : float
        Reflectance of the table.
    texture_rng : numpy.random.Generator or None
        If given, the table gets a :class:`NoiseTexture` drawn from it.

    Returns
    -------
    PulleyScene
        Label 0 is the table; the teeth are the last `teeth` primitives.

    Notes
    -----
    With the seed's camera at the default view pose the pulley spans about
    280 x 350 pixels and gives several hundred edge points along every 8th row
    at gradient threshold 8 (the seed found 818 and 815 on its part).

    References
    ----------
    Seed chapter 5.1 (figures 5-1, 5-2).

    Examples
    --------
    >>> s = hub_pulley_scene(center_xy=(300.0, 100.0))
    >>> s.top_z, s.outer_radius, len(s.primitives)
    (70.0, 96.0, 50)
    >>> s.view_pose
    Pose(x=300.0, y=100.0, z=1070.0, phi=0.0)
    """
    cx, cy = _pair("center_xy", center_xy)
    require_positive("scale", scale)
    require_positive("camera_height_mm", camera_height_mm)
    if isinstance(teeth, bool) or int(teeth) != teeth or teeth < 0:
        raise InputError(f"teeth must be a whole number >= 0, got {teeth}")
    k = float(scale)
    c = (cx, cy)
    top = 70 * k
    if top >= camera_height_mm:
        raise InputError(
            f"camera_height_mm must exceed the pulley top {top} mm, got {camera_height_mm}"
        )
    lift = 0.01 * k  # paint-thin rings sit this far above their face
    holes = tuple(
        (56 * k * math.cos(a), 56 * k * math.sin(a), 7 * k)
        for a in np.deg2rad(np.arange(8) * 45.0 + 22.5)
    )
    texture = None if texture_rng is None else NoiseTexture.from_rng(texture_rng)
    prims: list[Primitive] = [
        TablePlane(z=0.0, albedo=table_albedo, texture=texture),
        # rim with two belt grooves on its top face
        Cylinder(c, 0.0, 88 * k, 45 * k, inner_radius=76 * k, albedo=0.75),
        Disc(c, 45 * k + lift, 82.5 * k, inner_radius=80 * k, albedo=0.3),
        Disc(c, 45 * k + lift, 86.5 * k, inner_radius=84 * k, albedo=0.3),
        # web with lightening holes and two machined rings
        Disc(c, 20 * k, 76 * k, inner_radius=24 * k, holes=holes, albedo=0.5),
        Disc(c, 20 * k + lift, 69 * k, inner_radius=65 * k, albedo=0.9),
        Disc(c, 20 * k + lift, 45 * k, inner_radius=42 * k, albedo=0.2),
        # boss and hub
        Cylinder(c, 0.0, 38 * k, 32 * k, inner_radius=24 * k, albedo=0.7),
        Disc(c, 32 * k + lift, 33 * k, inner_radius=29 * k, albedo=0.25),
        Cylinder(c, 0.0, 24 * k, 70 * k, inner_radius=10 * k, albedo=0.85),
    ]
    for a in np.arange(int(teeth)) * (2 * math.pi / max(int(teeth), 1)):
        r = 91.75 * k  # r 87.5..96: the teeth overlap the rim by 0.5 mm
        prims.append(
            Box(
                (cx + r * math.cos(a), cy + r * math.sin(a)),
                0.0,
                (8.5 * k, 7 * k, 45 * k),
                yaw=float(a),
                albedo=0.75,
            )
        )
    return PulleyScene(
        primitives=tuple(prims),
        center=c,
        top_z=top,
        outer_radius=96 * k,
        view_pose=Pose(cx, cy, camera_height_mm, 0.0),
    )


# --------------------------------------------------------------------------- rendering


@dataclass(frozen=True)
class Rendering:
    """A rendered image with its ground truth.

    Attributes
    ----------
    image : ndarray of uint8, shape (H, W)
        Grey levels ``0 .. camera.grey_levels - 1``.
    depth : ndarray of float64, shape (H, W)
        Depth along the optical axis (mm) of the surface hit by the ray through each
        pixel centre; ``inf`` where the ray hits nothing.
    labels : ndarray of int32, shape (H, W)
        Index in ``scene.primitives`` of the primitive hit by the pixel-centre ray,
        -1 for none.
    intensity : ndarray of float64, shape (H, W)
        The noise-free, unquantised grey level (after supersampling and blur).
    """

    image: NDArray[np.uint8]
    depth: _Arr
    labels: NDArray[np.int32]
    intensity: _Arr


def sample_offsets(supersample: int) -> _Arr:
    """Sub-pixel offsets of the ``s x s`` rays cast per pixel, shape ``(s*s, 2)``.

    The rays form a rotated ("n-rooks") grid: their ``s*s`` x offsets are all
    distinct and evenly spaced, and so are their y offsets, so a vertical or a
    horizontal edge is located to ``1 / s**2`` of a pixel rather than ``1 / s``.
    For odd `s` one ray goes through the pixel centre.

    Examples
    --------
    >>> sample_offsets(2)
    array([[-0.375, -0.375],
           [-0.125,  0.125],
           [ 0.125, -0.125],
           [ 0.375,  0.375]])
    >>> sample_offsets(1)
    array([[0., 0.]])
    """
    s = int(supersample)
    a, b = np.meshgrid(np.arange(s), np.arange(s), indexing="ij")
    a, b = a.ravel(), b.ravel()
    n = s * s
    ox = (a * s + b + 0.5) / n - 0.5
    oy = (b * s + a + 0.5) / n - 0.5
    return np.column_stack([ox, oy])


def _window(prim: Primitive, camera: Camera, pose: Pose) -> tuple[slice, slice]:
    """Pixel rows and columns whose rays may hit `prim` (a conservative box)."""
    full = (slice(0, camera.height), slice(0, camera.width))
    bounds = prim._bounds()
    if bounds is None:
        return full
    (x0, y0, z0), (x1, y1, z1) = bounds
    corners = np.array(
        [[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)], dtype=float
    )
    uv, depth = camera.project(corners, pose)
    if np.any(depth <= 1e-6):
        return full
    c0 = max(math.floor(uv[:, 0].min() - 0.5) - 1, 0)
    c1 = min(math.ceil(uv[:, 0].max() + 0.5) + 2, camera.width)
    r0 = max(math.floor(uv[:, 1].min() - 0.5) - 1, 0)
    r1 = min(math.ceil(uv[:, 1].max() + 0.5) + 2, camera.height)
    if c1 <= c0 or r1 <= r0:
        return slice(0, 0), slice(0, 0)
    return slice(r0, r1), slice(c0, c1)


@functools.lru_cache(maxsize=4)
def _undistorted_grid(camera: Camera, offsets_bytes: bytes) -> _Arr:
    """Undistorted normalised coordinates of every ray, shape (S, H, W, 2) (cached)."""
    offsets = np.frombuffer(offsets_bytes, dtype=np.float64).reshape(-1, 2)
    w, h = camera.width, camera.height
    cx, cy = camera.principal_point
    x = np.arange(w)[None, None, :] + offsets[:, 0, None, None]
    y = np.arange(h)[None, :, None] + offsets[:, 1, None, None]
    shape = (len(offsets), h, w)
    d = np.stack([np.broadcast_to((x - cx) / camera.fx, shape),
                  np.broadcast_to((y - cy) / camera.fy, shape)], axis=-1)
    out = camera.undistort(d, iterations=10)  # contraction ~3 k1 r^2: ample
    out.setflags(write=False)
    return out


def _cast(
    scene: Scene, camera: Camera, pose: Pose, offsets: _Arr
) -> tuple[_Arr, NDArray[np.int32], _Arr]:
    """Cast one ray per pixel and offset: nearest t, label and radiance, shape (S, H, W)."""
    w, h = camera.width, camera.height
    k_inv = np.linalg.inv(camera.K)
    r = pose.rotation
    o = pose.position
    x = np.arange(w)[None, None, :] + offsets[:, 0, None, None]
    y = np.arange(h)[None, :, None] + offsets[:, 1, None, None]
    # camera-frame direction K^-1 (x, y, 1); K's last row is (0, 0, 1), so its z is 1
    u = k_inv[0, 0] * x + k_inv[0, 1] * y + k_inv[0, 2]
    v = k_inv[1, 0] * x + k_inv[1, 1] * y + k_inv[1, 2]
    shape = (len(offsets), h, w)
    if camera.distortion:  # the ray of a distorted pixel: undistort its normalised position
        n = _undistorted_grid(camera, offsets.tobytes())
        u, v = n[..., 0], n[..., 1]
    # world direction R @ (u, v, 1): its camera-z component is 1, so t is the depth
    dx = np.broadcast_to(r[0, 0] * u + r[0, 1] * v + r[0, 2], shape)
    dy = np.broadcast_to(r[1, 0] * u + r[1, 1] * v + r[1, 2], shape)
    dz = np.broadcast_to(r[2, 0] * u + r[2, 1] * v + r[2, 2], shape)
    t_best = np.full(shape, np.inf)
    labels = np.full(shape, -1, dtype=np.int32)
    radiance = np.full(shape, scene.background)
    light = np.asarray(scene.light_direction)
    for k, prim in enumerate(scene.primitives):
        rows, cols = _window(prim, camera, pose)
        if rows.stop - rows.start <= 0 or cols.stop - cols.start <= 0:
            continue
        wdx, wdy, wdz = dx[:, rows, cols], dy[:, rows, cols], dz[:, rows, cols]
        t, normal = prim._hit(o, wdx, wdy, wdz)
        tb = t_best[:, rows, cols]
        closer = t < tb
        if not closer.any():
            continue
        tc = t[closer]
        tb[closer] = tc
        labels[:, rows, cols][closer] = k
        sdx, sdy, sdz = wdx[closer], wdy[closer], wdz[closer]
        nx, ny, nz = (np.broadcast_to(np.asarray(n, dtype=float), t.shape)[closer] for n in normal)
        facing = np.where(nx * sdx + ny * sdy + nz * sdz > 0, -1.0, 1.0)
        cos = facing * (nx * light[0] + ny * light[1] + nz * light[2])
        albedo = prim._albedo_at(o[0] + tc * sdx, o[1] + tc * sdy)
        radiance[:, rows, cols][closer] = albedo * (
            scene.ambient + scene.light_intensity * np.maximum(cos, 0.0)
        )
    return t_best, labels, radiance


def render(
    scene: Scene,
    camera: Camera,
    pose: Pose,
    *,
    supersample: int = 3,
    blur_sigma_px: float = 0.6,
    noise_sigma: float = 0.0,
    rng: np.random.Generator | None = None,
    vignetting: float = 0.0,
) -> Rendering:
    """Render what `camera` at `pose` sees of `scene`, with depth and labels.

    Parameters
    ----------
    scene : Scene
    camera : Camera
        Pinhole camera; its ``grey_levels`` (at most 256) set the quantisation.
    pose : Pose
        Camera pose (optical centre and yaw).
    supersample : int
        ``s``: ``s x s`` rays per pixel on a rotated grid (:func:`sample_offsets`),
        averaged (a box pixel filter).
    blur_sigma_px : float
        Standard deviation of a Gaussian lens blur in pixels (0 for none).
    noise_sigma : float
        Standard deviation of additive Gaussian sensor noise, grey levels
        (0 for none; needs `rng`).
    rng : numpy.random.Generator or None
        Source of the sensor noise.
    vignetting : float
        Relative fall-off of the light towards the image corners, in ``[0, 1)``: the
        irradiance is multiplied by ``1 - vignetting * (r / r_corner)^2`` (0 for none).

    Other real-camera effects: lens distortion is the camera's
    (:attr:`robostereo.camera.Camera.distortion`), defocus is `blur_sigma_px`, surface
    texture a :class:`NoiseTexture` on the table or on a :class:`Box`.

    Returns
    -------
    Rendering
        ``image`` (H, W) uint8, ``depth`` (H, W) float64 (mm, ``inf`` for no hit),
        ``labels`` (H, W) int32 (-1 for no hit), ``intensity`` (H, W) float64.

    Notes
    -----
    1. Cast ``s*s`` rays per pixel from the optical centre; ray directions are
       ``R @ K^-1 (x, y, 1)`` so the ray parameter is the depth.  Each primitive is
       intersected only by the rays inside the image box its bounding box projects
       to; the nearest hit in front of the camera wins.
    2. Shade hits as Lambertian: ``albedo * (ambient + I * max(0, n . l))`` with the
       normal turned towards the camera (no shadows); misses get ``background``.
    3. Average the rays of each pixel, scale by ``grey_levels - 1``.
    4. Blur with a Gaussian of `blur_sigma_px` (borders reflected).
    5. Add ``N(0, noise_sigma^2)`` noise from `rng`, round, clip to the grey range.
    6. Depth and labels come from the single ray through each pixel centre (the
       centre ray of the grid when ``s`` is odd, an extra cast otherwise).

    References
    ----------
    Seed 4.1 (the camera and the 0..127 grey levels of the XGS system).

    Examples
    --------
    >>> from robostereo.camera import SEED_CAMERA
    >>> scene = Scene((TablePlane(z=0.0, albedo=0.5),), light_direction=(0, 0, 1))
    >>> r = render(scene, SEED_CAMERA, Pose(0.0, 0.0, 1000.0), supersample=1)
    >>> r.image.shape, int(r.image[0, 0]), float(r.depth[240, 254])
    ((481, 509), 60, 1000.0)
    """
    if not isinstance(scene, Scene):
        raise InputError(f"scene must be a Scene, got {type(scene).__name__}")
    if not isinstance(camera, Camera):
        raise InputError(f"camera must be a Camera, got {type(camera).__name__}")
    if not isinstance(pose, Pose | SE3):
        raise InputError(f"pose must be a Pose or an SE3, got {type(pose).__name__}")
    if isinstance(supersample, bool) or int(supersample) != supersample or supersample < 1:
        raise InputError(f"supersample must be an integer >= 1, got {supersample}")
    supersample = int(supersample)
    require_nonnegative("blur_sigma_px", blur_sigma_px)
    require_nonnegative("noise_sigma", noise_sigma)
    require_finite("vignetting", vignetting)
    if not 0.0 <= vignetting < 1.0:
        raise InputError(f"vignetting must be in [0, 1), got {vignetting}")
    if noise_sigma > 0 and not isinstance(rng, np.random.Generator):
        raise InputError("rng must be a numpy.random.Generator when noise_sigma > 0")
    levels = camera.grey_levels
    if not 2 <= levels <= 256:
        raise InputError(f"camera.grey_levels must be in [2, 256] for uint8, got {levels}")

    offsets = sample_offsets(supersample)
    t, labels, radiance = _cast(scene, camera, pose, offsets)
    if supersample % 2 == 1:
        centre = (supersample * supersample) // 2
        depth, label_map = t[centre], labels[centre]
    else:
        t0, l0, _ = _cast(scene, camera, pose, np.zeros((1, 2)))
        depth, label_map = t0[0], l0[0]
    intensity = np.clip(radiance, 0.0, 1.0).mean(axis=0) * (levels - 1)
    if vignetting > 0:
        cx, cy = camera.principal_point
        xs = (np.arange(camera.width) - cx)[None, :]
        ys = (np.arange(camera.height) - cy)[:, None]
        r2 = xs * xs + ys * ys
        intensity = intensity * (1.0 - vignetting * r2 / r2.max())
    if blur_sigma_px > 0:
        radius = max(1, math.ceil(4.0 * blur_sigma_px))
        intensity = cv2.GaussianBlur(
            intensity,
            (2 * radius + 1, 2 * radius + 1),
            sigmaX=blur_sigma_px,
            sigmaY=blur_sigma_px,
            borderType=cv2.BORDER_REFLECT_101,
        )
    noisy = intensity
    if noise_sigma > 0:
        assert rng is not None
        noisy = intensity + rng.normal(0.0, noise_sigma, intensity.shape)
    image = np.clip(np.rint(noisy), 0, levels - 1).astype(np.uint8)
    return Rendering(
        image=image,
        depth=np.ascontiguousarray(depth),
        labels=np.ascontiguousarray(label_map),
        intensity=intensity,
    )


def true_disparity(depth: ArrayLike, camera: Camera, baseline_mm: float) -> _Arr:
    """Ground-truth disparity ``d = fx * D / depth`` (pixels) of a rectified pair.

    For a left image rendered at the viewpoint ``-D/2`` along the camera's x axis
    (the baseline, ``phi = alpha``) and the right one at ``+D/2``, the point seen at
    left pixel ``(x, y)`` is at ``x - d`` in the right image, ``d = x_left - x_right``.
    ``inf`` depth (no surface) gives 0.

    Parameters
    ----------
    depth : array_like, shape (H, W)
        Depth map of the left view (:attr:`Rendering.depth`), millimetres.
    camera : Camera
    baseline_mm : float
        Baseline ``D``, millimetres.

    Returns
    -------
    ndarray, shape (H, W)

    References
    ----------
    Seed eq. (8) as corrected in the seed notes: ``z = D s / (x_l - x_r)``.

    Examples
    --------
    >>> from robostereo.camera import SEED_CAMERA
    >>> float(true_disparity([[1000.0]], SEED_CAMERA, 20.0)[0, 0].round(3))
    29.07
    """
    require_positive("baseline_mm", baseline_mm)
    z = np.asarray(depth, dtype=float)
    with np.errstate(divide="ignore"):
        return camera.fx * baseline_mm / z
