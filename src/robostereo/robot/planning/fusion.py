"""Fusing two captures: their located points merged into one set.

:func:`fuse_located` merges the points of two captures of one scene (e.g. with
orthogonal baselines) into one set (:class:`FusedPoints`), each point keeping its eq. 9
bound.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_positive

__all__ = [
    "FusedPoints",
    "fuse_located",
]


@dataclass(frozen=True, eq=False)
class FusedPoints:
    """Points of two captures merged (:func:`fuse_located`).

    Attributes
    ----------
    world : ndarray, shape (M, 3)
        World points, millimetres.
    z_bound : ndarray, shape (M,)
        Each point's eq. 9 bound (from its own capture).
    capture : ndarray of int, shape (M,)
        Which capture (0, 1) each point comes from.
    duplicates : int
        Points of the second capture dropped as within `merge_mm` of one of the first.
    """

    world: NDArray[np.float64]
    z_bound: NDArray[np.float64]
    capture: NDArray[np.int8]
    duplicates: int

    def __len__(self) -> int:
        return int(self.world.shape[0])

    def table(self) -> dict[str, NDArray[Any]]:
        """Columns ``X_w, Y_w, Z_w, z_bound, capture``."""
        return {"X_w": self.world[:, 0], "Y_w": self.world[:, 1], "Z_w": self.world[:, 2],
                "z_bound": self.z_bound, "capture": self.capture}


def fuse_located(first: Any, second: Any, *, merge_mm: float = 0.5) -> FusedPoints:
    """Merge the located points of two captures of one scene into one set.

    Parameters
    ----------
    first, second : Located
        :func:`robostereo.robot.capture.locate_pair.locate` results (world frame, same robot).
    merge_mm : float
        A point of `second` within this distance of a point of `first` is the same
        edge sample seen twice and is dropped (the first keeps its own bound).

    Returns
    -------
    FusedPoints

    Raises
    ------
    InputError
        An argument without ``world`` (N, 3) and ``z_bound`` (N,) arrays of finite
        numbers (a located point is never NaN: NaN would pass the merge unseen), or a
        bad `merge_mm`.

    Notes
    -----
    A k-d tree of `first`'s points (:class:`scipy.spatial.cKDTree`); each point of
    `second` is dropped when its nearest neighbour there is within `merge_mm`.
    """
    from scipy.spatial import cKDTree

    if isinstance(merge_mm, bool) or not isinstance(merge_mm, int | float) \
            or not math.isfinite(merge_mm):
        raise InputError(f"merge_mm must be a finite number > 0, got {merge_mm!r}")
    require_positive("merge_mm", merge_mm)
    a, za = _located_points("first", first)
    b, zb_b = _located_points("second", second)
    keep = np.ones(len(b), bool)
    if len(a) and len(b):
        d, _ = cKDTree(a).query(b, distance_upper_bound=merge_mm)
        keep = ~np.isfinite(d)
    world = np.vstack([a.reshape(-1, 3), b[keep].reshape(-1, 3)])
    zb = np.concatenate([za, zb_b[keep]])
    cap = np.concatenate([np.zeros(len(a), np.int8), np.ones(int(keep.sum()), np.int8)])
    return FusedPoints(world=world, z_bound=zb, capture=cap, duplicates=int((~keep).sum()))


def _located_points(name: str, located: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``world`` (N, 3) and ``z_bound`` (N,) of a Located, checked."""
    try:
        world = np.asarray(located.world, dtype=np.float64)
        bound = np.asarray(located.z_bound, dtype=np.float64)
    except AttributeError:
        raise InputError(f"{name} must be a Located (with world and z_bound), got "
                         f"{type(located).__name__}") from None
    except (TypeError, ValueError):
        raise InputError(f"{name}: world and z_bound must be arrays of numbers") from None
    if world.ndim != 2 or world.shape[1] != 3 or bound.shape != (world.shape[0],):
        raise InputError(f"{name}: world must be (N, 3) and z_bound (N,), got "
                         f"{world.shape} and {bound.shape}")
    if not (np.isfinite(world).all() and np.isfinite(bound).all()):
        raise InputError(f"{name}: world and z_bound must be finite (NaN or inf found)")
    if np.abs(world).max(initial=0.0) > 1e12:
        raise InputError(f"{name}: world points must be within +-1e12 mm")
    return world, bound
