"""Flat printed targets lying on a horizontal plane of the simulated scenes.

:class:`Checkerboard` is a chessboard calibration target drawn analytically,
:class:`ImagePlane` a printed grey image (e.g. a ChArUco board); each knows its
``pose``, the frame of OpenCV's board object points, for the simulated hand-eye
calibration.  Like the other primitives (:mod:`robostereo.simulation.primitives`) they
answer the renderer's ``bounds()``, ``hit(o, dx, dy, dz)`` and ``albedo_at(x, y)``;
the two share their flat rectangle turned by a yaw about its origin.

World coordinates are millimetres with Z up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_finite, require_positive
from robostereo.geometry.poses import SE3
from robostereo.simulation.surfaces import HIT_EPS, require_albedo, xy_pair

__all__ = [
    "Checkerboard",
    "ImagePlane",
]

_Arr = NDArray[np.float64]


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
        ok = (t > HIT_EPS) & (bx >= x0) & (bx <= x1) & (by >= y0) & (by <= y1)
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
        require_albedo(self.dark)
        require_albedo(self.light)

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
        require_albedo(self.margin_albedo)

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
