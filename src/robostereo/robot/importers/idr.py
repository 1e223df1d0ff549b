"""IDR / NeuS camera files (``cameras.npz``), as DTU MVS is distributed for them.

The file holds, per view ``K``, ``world_mat_K`` (4 x 4: its top three rows are the
projection ``P = K [R | t]``, world to image, DTU's world frame in millimetres) and
``scale_mat_K`` (the similarity that maps the unit sphere onto the object's bounding
sphere).  The images are ``image/NNNNNN.png`` (or any files sorted in view order).

:func:`read_idr` decomposes ``world_mat @ scale_mat`` as IDR does
(:func:`cv2.decomposeProjectionMatrix`: ``K``, the rotation world to camera, the
optical centre in the sphere's frame), takes the centre back to millimetres through
``scale_mat`` and gives the depth range the bounding sphere covers in front of the
chosen views.  DTU's world is in millimetres already; ``unit_to_mm`` scales another.
"""

from __future__ import annotations

import os
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.importers.imported_views import Imported, ImportedView

__all__ = ["decompose_projection", "read_idr", "sphere_depth_range"]

_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp")


def decompose_projection(P: NDArray[np.float64]) -> tuple[NDArray[np.float64], SE3]:
    """``K`` (3, 3) and ``T_world_camera`` of a projection ``P = K [R | t]`` (3, 4).

    Notes
    -----
    :func:`cv2.decomposeProjectionMatrix` (an RQ decomposition) gives ``K``, ``R``
    (world to camera) and the optical centre ``C`` (homogeneous); the pose is rotation
    ``R^T``, translation ``C``.  ``K`` is divided by ``K[2, 2]``.

    >>> K = np.array([[800.0, 0, 320], [0, 800, 240], [0, 0, 1]])
    >>> P = K @ np.hstack([np.eye(3), [[0.0], [0.0], [500.0]]])
    >>> k, pose = decompose_projection(P)
    >>> np.allclose(k, K), (pose.translation.round(9) + 0.0).tolist()
    (True, [0.0, 0.0, -500.0])
    """
    K, R, c, *_ = cv2.decomposeProjectionMatrix(np.asarray(P, dtype=np.float64))
    K = K / K[2, 2]
    centre = (c[:3] / c[3]).ravel()
    return K, SE3(R.T, centre)


def sphere_depth_range(poses: list[SE3], centre: NDArray[np.float64],
                       radius: float) -> tuple[float, float]:
    """``(near, far)`` along the optical axes, mm, that a sphere covers in front of the
    views: the centre's depth minus and plus the radius, over all views, ``near`` at
    least a hundredth of ``far``."""
    depths = [float((centre - p.translation) @ p.rotation[:, 2]) for p in poses]
    far = max(depths) + radius
    if far <= 0:
        raise InputError("the bounding sphere (scale_mat) lies behind every view")
    return max(min(depths) - radius, far / 100.0), far


def read_idr(cameras: str | os.PathLike[str], images: str | os.PathLike[str], *,
             unit_to_mm: float = 1.0) -> Imported:
    """The views of an IDR / NeuS ``cameras.npz`` and its image folder.

    Parameters
    ----------
    cameras : path
        The ``.npz`` with ``world_mat_K`` and (optionally) ``scale_mat_K`` per view.
    images : path
        The image folder: files named by view number (``000024.png`` is view 24, as
        IDR's DTU), else its image files sorted by name are views 0, 1, ...; cameras
        without an image are left out.
    unit_to_mm : float
        Millimetres per unit of the world frame (1 for DTU).

    Returns
    -------
    Imported
        Views keyed ``0``, ``1``, ... (the ``K`` of ``world_mat_K``); the depth range
        of the bounding sphere of ``scale_mat`` when there is one.

    Raises
    ------
    InputError
        Unreadable file, no ``world_mat_K``, fewer images than cameras, a projection
        that does not decompose into a camera.
    """
    path = Path(cameras)
    try:
        npz = np.load(path, allow_pickle=False)
        keys = set(npz.files)
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: cannot read the IDR cameras file ({exc})") from None
    ids = sorted(int(k.split("_")[-1]) for k in keys
                 if k.startswith("world_mat_") and k.split("_")[-1].isdigit()
                 and not k.startswith("world_mat_inv"))
    if not ids:
        raise InputError(f"{path}: no world_mat_K (not an IDR / NeuS cameras file)")
    folder = Path(images)
    if not folder.is_dir():
        raise InputError(f"{folder}: not an image folder")
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in _IMAGE_SUFFIXES)
    if files and all(p.stem.isdigit() for p in files):  # 000024.png is view 24
        by_id = {int(p.stem): p for p in files}
    else:
        by_id = dict(enumerate(files))
    ids = [i for i in ids if i in by_id]
    if not ids:
        raise InputError(f"{folder}: no image of a camera of {path.name} (files named by "
                         "view number, NNNNNN.png, or in view order)")
    views, spheres = [], []
    for i in ids:
        P = np.asarray(npz[f"world_mat_{i}"], dtype=np.float64)
        S = np.asarray(npz[f"scale_mat_{i}"], dtype=np.float64) \
            if f"scale_mat_{i}" in keys else np.eye(4)
        if P.shape != (4, 4) or S.shape != (4, 4) or not np.all(np.isfinite(P @ S)):
            raise InputError(f"{path}: world_mat_{i} and scale_mat_{i} must be finite 4 x 4")
        scale = float(np.cbrt(np.linalg.det(S[:3, :3])))
        if not scale > 0:
            raise InputError(f"{path}: scale_mat_{i} is not a scale and a shift")
        K, sphere_pose = decompose_projection((P @ S)[:3])  # IDR's decomposition
        centre = S[:3, :3] @ sphere_pose.translation + S[:3, 3]  # back to the world
        pose = SE3(sphere_pose.rotation, centre * unit_to_mm)
        if not np.isfinite(K).all() or K[0, 0] <= 0 or K[1, 1] <= 0:
            raise InputError(f"{path}: world_mat_{i} is not a camera's projection")
        views.append(ImportedView(str(i), by_id[i], K, pose))
        if f"scale_mat_{i}" in keys:
            spheres.append((S[:3, 3] * unit_to_mm, scale * unit_to_mm))
    depth = None
    if spheres:
        c = np.mean([s[0] for s in spheres], axis=0)
        r = max(s[1] for s in spheres)
        depth = sphere_depth_range([v.pose for v in views], c, r)
    view_depths = {}
    if spheres:
        for v in views:
            view_depths[v.key] = sphere_depth_range([v.pose], spheres[0][0], spheres[0][1])
    return Imported(tuple(views), depth, view_depths, source=str(path))
