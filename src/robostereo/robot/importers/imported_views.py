"""What an importer gives, and the N-view capture made of it.

An importer reads another tool's cameras into :class:`Imported`: one
:class:`ImportedView` per view (its image file, intrinsic matrix ``K`` in pixels with
pixel centres at whole coordinates, lens distortion and camera pose
``T_world_camera`` in millimetres) and, where the data has one, a depth range.
:func:`views_capture_from_imported` chooses views, scales images and intrinsics
together and makes the :class:`~robostereo.robot.views.viewpoints.ViewsCapture`
that :func:`~robostereo.robot.views.views_folder.write_views_capture` writes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, shown
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.views.viewpoints import ViewsCapture

__all__ = [
    "INTRINSICS_TOLERANCE_PX",
    "Imported",
    "ImportedView",
    "parse_view_selection",
    "scaled_intrinsics",
    "views_capture_from_imported",
]

INTRINSICS_TOLERANCE_PX = 0.05
"""Largest difference, pixels, between two chosen views' ``K`` entries for them to be
one camera (a capture has one); DTU's 49 views differ by under 0.01 px."""


@dataclass(frozen=True, eq=False)
class ImportedView:
    """One view read by an importer.

    Attributes
    ----------
    key : str
        The view's id in its source (``0``, ``00000003``, a COLMAP image name), which
        ``--views`` names.
    image : Path
        Its image file.
    K : ndarray, shape (3, 3)
        Intrinsics, pixels, pixel centres at whole coordinates.
    pose : SE3
        ``T_world_camera``, millimetres.
    distortion : tuple of float
        ``(k1, k2, p1, p2[, k3])`` or empty.
    """

    key: str
    image: Path
    K: NDArray[np.float64]
    pose: SE3
    distortion: tuple[float, ...] = ()


@dataclass(frozen=True, eq=False)
class Imported:
    """What an importer read: its views and, when the data has one, a depth range.

    Attributes
    ----------
    views : tuple of ImportedView
    depth_range_mm : tuple of float or None
        ``(near, far)`` along the optical axis, mm, over every view (per-view ranges in
        `view_depths` when the source gives them per view).
    view_depths : mapping of str to (float, float)
        Per view key, the source's own depth range (MVSNet's cameras, COLMAP's points).
    source : str
        What was read, for the capture's notes.
    """

    views: tuple[ImportedView, ...]
    depth_range_mm: tuple[float, float] | None = None
    view_depths: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    source: str = ""


def parse_view_selection(text: str | None, keys: Sequence[str]) -> list[int]:
    """Indices into `keys` of a ``--views`` value: comma-separated keys (``0,1,2``;
    numbers match keys numerically, so ``3`` names ``00000003``); None gives every view.

    >>> parse_view_selection("2,0", ["00000000", "00000001", "00000002"])
    [2, 0]
    >>> parse_view_selection("7", ["0", "1"])
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: --views: no view 7 (views: 0, 1)
    """
    if text is None:
        return list(range(len(keys)))
    out: list[int] = []
    for tok in (t.strip() for t in str(text).split(",")):
        if not tok:
            raise InputError(f"--views must be comma-separated view ids, got {text!r}")
        hit = [i for i, k in enumerate(keys) if k == tok
               or (tok.isdigit() and k.isdigit() and int(k) == int(tok))]
        if not hit:
            listed = ", ".join(keys[:12]) + (", ..." if len(keys) > 12 else "")
            raise InputError(f"--views: no view {tok} (views: {listed})")
        if hit[0] in out:
            raise InputError(f"--views: view {tok} given twice")
        out.append(hit[0])
    if len(out) < 2:
        raise InputError(f"--views: a capture needs at least two views, got {text!r}")
    return out


def scaled_intrinsics(K: NDArray[np.float64], sx: float, sy: float) -> NDArray[np.float64]:
    """``K`` of an image resized by ``(sx, sy)``, pixel centres at whole coordinates:
    ``f' = s f`` and ``c' = s (c + 0.5) - 0.5`` (the image's edges, not its first
    pixel's centre, stay put).

    >>> K = scaled_intrinsics(np.array([[100., 0, 49.5], [0, 100., 29.5], [0, 0, 1]]), .5, .5)
    >>> K[0].tolist(), K[1].tolist()
    ([50.0, 0.0, 24.5], [0.0, 50.0, 14.5])
    """
    out = np.array(K, dtype=float)
    out[0, 0] *= sx
    out[1, 1] *= sy
    out[0, 2] = sx * (out[0, 2] + 0.5) - 0.5
    out[1, 2] = sy * (out[1, 2] + 0.5) - 0.5
    return out


def _grey(path: Path) -> NDArray[np.uint8]:
    img = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if img is None:
        raise InputError(f"{path}: cannot read the image (missing, or not an image file)")
    return img


def views_capture_from_imported(
    imported: Imported,
    *,
    select: Sequence[int] | None = None,
    scale: float = 1.0,
    depth_range_mm: tuple[float, float] | None = None,
    notes: Mapping[str, Any] | None = None,
) -> ViewsCapture:
    """The N-view capture of some of an importer's views.

    Parameters
    ----------
    imported : Imported
    select : sequence of int, optional
        Indices of the views to keep, in order (:func:`parse_view_selection`); default
        all.
    scale : float
        Image scale in ``(0, 1]``: images resized with pixel-area averaging and ``K``
        with them (:func:`scaled_intrinsics`).
    depth_range_mm : tuple of float, optional
        ``(near, far)`` along the optical axis, mm; default the data's (the chosen
        views' own ranges joined, else the import's); one of them is required.
    notes : mapping, optional
        The capture's ``robot`` / ``scene`` notes.

    Returns
    -------
    ViewsCapture
        8-bit grey images named after their source files (``.png``), one camera in
        pixels, the views' poses.

    Raises
    ------
    InputError
        No depth range, a scale outside ``(0, 1]``, images of different sizes, views
        whose intrinsics differ (a capture has one camera), an unreadable image.
    """
    chosen = [imported.views[i] for i in (range(len(imported.views)) if select is None
                                          else select)]
    if len(chosen) < 2:
        raise InputError(f"a capture needs at least two views, got {len(chosen)}")
    if not (isinstance(scale, int | float) and 0 < scale <= 1 and math.isfinite(scale)):
        raise InputError(f"--scale must be in (0, 1], got {shown(scale)}")
    if depth_range_mm is None:
        ranges = [imported.view_depths[v.key] for v in chosen if v.key in imported.view_depths]
        if ranges:
            depth_range_mm = (min(r[0] for r in ranges), max(r[1] for r in ranges))
        else:
            depth_range_mm = imported.depth_range_mm
    if depth_range_mm is None:
        raise InputError(f"{imported.source}: the data has no depth range: give "
                         "--depth-range NEAR FAR (mm along the optical axis)")
    images, names, sizes = [], [], []
    for v in chosen:
        img = _grey(v.image)
        sizes.append(img.shape)
        if scale != 1.0:
            h, w = img.shape
            img = cv2.resize(img, (max(5, round(w * scale)), max(5, round(h * scale))),
                             interpolation=cv2.INTER_AREA)
        images.append(img)
        names.append(Path(v.image).stem + ".png")
    if len(set(sizes)) > 1:
        raise InputError(f"{imported.source}: the chosen views' images differ in size "
                         "(a capture has one camera)")
    h0, w0 = images[0].shape
    sx, sy = w0 / sizes[0][1], h0 / sizes[0][0]
    Ks = [scaled_intrinsics(v.K, sx, sy) for v in chosen]
    K = np.mean(Ks, axis=0)
    spread = max(float(np.abs(k - K).max()) for k in Ks)
    if spread > INTRINSICS_TOLERANCE_PX:
        raise InputError(f"{imported.source}: the chosen views' intrinsics differ by "
                         f"{spread:.3g} px: a capture has one camera; choose views of one "
                         "camera with --views")
    dists = {v.distortion for v in chosen}
    if len(dists) > 1:
        raise InputError(f"{imported.source}: the chosen views' lens distortions differ: a "
                         "capture has one camera")
    K[0, 1] = 0.0
    camera = Camera.from_intrinsics(K, (w0, h0), distortion=dists.pop(), grey_levels=256)
    if len(set(names)) != len(names):
        names = [f"view_{k:03d}_{n}" for k, n in enumerate(names)]
    return ViewsCapture(tuple(images), camera, tuple(v.pose for v in chosen),
                        depth_range_mm=depth_range_mm, bit_depth=8, names=tuple(names),
                        notes=dict(notes or {}))
