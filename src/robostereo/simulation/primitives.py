"""The analytic primitives of the simulated scenes: table, discs, cylinders, boxes, boards.

Every primitive is a frozen dataclass that validates itself and answers three questions
of the renderer (:func:`robostereo.simulation.render.render`): ``bounds()``, a (2, 3)
array of world min/max corners (None when unbounded); ``hit(o, dx, dy, dz)``, the ray
parameter of the nearest intersection in front of the origin (inf where the ray misses)
and the surface normal; and ``albedo_at(x, y)``, the grey reflectance at world points.

World coordinates are millimetres with Z up; the table top is at ``z = 0`` in the
scenes of :mod:`robostereo.simulation.scenes`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import gaussian_filter

from robostereo.errors import InputError, require_finite, require_positive
from robostereo.geometry.poses import SE3

__all__ = [
    "Box",
    "Checkerboard",
    "Cylinder",
    "Disc",
    "ImagePlane",
    "NoiseTexture",
    "Primitive",
    "TablePlane",
    "xy_pair",
]

_EPS = 1e-9
_Arr = NDArray[np.float64]


def _require_albedo(albedo: float) -> None:
    require_finite("albedo", albedo)
    if not 0.0 <= albedo <= 1.0:
        raise InputError(f"albedo must be in [0, 1], got {albedo}")


def xy_pair(name: str, value: Sequence[float]) -> tuple[float, float]:
    """`value` as a pair of finite floats ``(x, y)``; InputError (naming `name`) otherwise.

    Examples
    --------
    >>> xy_pair("center", [1, 2.5])
    (1.0, 2.5)
    """
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
# Every primitive has ``bounds()`` (a (2, 3) array of world min/max corners, or None
# when unbounded) and ``hit(o, dx, dy, dz)`` which returns the ray parameter t of the
# nearest intersection in front of the origin (inf where the ray misses) and the
# surface normal (three arrays or scalars, any orientation); ``albedo_at(x, y)`` gives
# the reflectance at world points.  Rays are ``o + t * d`` with d scaled so that t is
# the depth along the optical axis.  These three are what the renderer calls.


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

    def bounds(self) -> _Arr | None:
        return None

    def hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (self.z - o[2]) / dz
        t = np.where(t > _EPS, t, np.inf)
        return t, (0.0, 0.0, 1.0)

    def albedo_at(self, x: _Arr, y: _Arr) -> _Arr | float:
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
        object.__setattr__(self, "center", xy_pair("center", self.center))
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

    def bounds(self) -> _Arr | None:
        cx, cy = self.center
        r = self.radius
        return np.array([[cx - r, cy - r, self.z], [cx + r, cy + r, self.z]])

    def hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (self.z - o[2]) / dz
        px = o[0] + t * dx - self.center[0]
        py = o[1] + t * dy - self.center[1]
        r2 = px * px + py * py
        ok = (t > _EPS) & (r2 <= self.radius**2) & (r2 >= self.inner_radius**2)
        for hx, hy, hr in self.holes:
            ok &= (px - hx) ** 2 + (py - hy) ** 2 > hr * hr
        return np.where(ok, t, np.inf), (0.0, 0.0, 1.0)

    def albedo_at(self, x: _Arr, y: _Arr) -> float:
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
        object.__setattr__(self, "center", xy_pair("center", self.center))
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

    def bounds(self) -> _Arr | None:
        cx, cy = self.center
        r = self.radius
        return np.array([[cx - r, cy - r, self.z_base], [cx + r, cy + r, self.z_top]])

    def hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
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

    def albedo_at(self, x: _Arr, y: _Arr) -> float:
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
        object.__setattr__(self, "center", xy_pair("center", self.center))
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

    def bounds(self) -> _Arr | None:
        p = self.corners()
        return np.array([p.min(axis=0), p.max(axis=0)])

    def hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
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

    def albedo_at(self, x: _Arr, y: _Arr) -> _Arr | float:
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

    def bounds(self) -> _Arr | None:
        x0, x1, y0, y1 = self._extent()
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        pts = np.array([[bx, by] for bx in (x0, x1) for by in (y0, y1)])
        wx = self.origin[0] + c * pts[:, 0] + s * pts[:, 1]
        wy = self.origin[1] + s * pts[:, 0] - c * pts[:, 1]
        return np.array([[wx.min(), wy.min(), self.z], [wx.max(), wy.max(), self.z]])

    def hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
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
        object.__setattr__(self, "origin", xy_pair("origin", self.origin))
        require_finite("z", self.z)
        require_positive("square_mm", self.square_mm)
        require_finite("yaw", self.yaw)
        _require_albedo(self.dark)
        _require_albedo(self.light)

    def _extent(self) -> tuple[float, float, float, float]:
        q = self.square_mm
        c, r = self.inner_corners
        return -2 * q, c * q + q, -2 * q, r * q + q

    def albedo_at(self, x: _Arr, y: _Arr) -> _Arr:
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
        object.__setattr__(self, "origin", xy_pair("origin", self.origin))
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

    def albedo_at(self, x: _Arr, y: _Arr) -> _Arr:
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
