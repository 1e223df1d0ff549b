"""The analytic solid primitives of the simulated scenes: table, discs, cylinders, boxes.

Every primitive is a frozen dataclass that validates itself and answers three questions
of the renderer (:func:`robostereo.simulation.render.render`): ``bounds()``, a (2, 3)
array of world min/max corners (None when unbounded); ``hit(o, dx, dy, dz)``, the ray
parameter of the nearest intersection in front of the origin (inf where the ray misses)
and the surface normal; and ``albedo_at(x, y)``, the grey reflectance at world points.
:data:`Primitive` is any of them, these here or the flat printed targets of
:mod:`robostereo.simulation.targets`; the checks they share and the table's texture are
in :mod:`robostereo.simulation.surfaces`.

World coordinates are millimetres with Z up; the table top is at ``z = 0`` in the
scenes of :mod:`robostereo.simulation.scenes`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_finite, require_positive
from robostereo.simulation.surfaces import HIT_EPS, NoiseTexture, require_albedo, xy_pair
from robostereo.simulation.targets import Checkerboard, ImagePlane

__all__ = [
    "Box",
    "Cylinder",
    "Disc",
    "Primitive",
    "TablePlane",
]

_Arr = NDArray[np.float64]


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
        require_albedo(self.albedo)

    def bounds(self) -> _Arr | None:
        return None

    def hit(self, o: _Arr, dx: _Arr, dy: _Arr, dz: _Arr) -> tuple[_Arr, tuple]:
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (self.z - o[2]) / dz
        t = np.where(t > HIT_EPS, t, np.inf)
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
        require_albedo(self.albedo)

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
        ok = (t > HIT_EPS) & (r2 <= self.radius**2) & (r2 >= self.inner_radius**2)
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
        require_albedo(self.albedo)

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
                ok = (a > 1e-18) & (disc >= 0) & (t > HIT_EPS) & (z >= z0) & (z <= z1)
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
                ok = (t > HIT_EPS) & (r2 <= self.radius**2) & (r2 >= ri * ri)
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
        require_albedo(self.albedo)

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
        ok = (t_near <= t_far) & (t_near > HIT_EPS)
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


Primitive = TablePlane | Disc | Cylinder | Box | Checkerboard | ImagePlane
