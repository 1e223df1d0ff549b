"""COLMAP models: ``cameras``, ``images``, ``points3D``, as text (``.txt``) or binary.

``cameras.txt`` has one line per camera, ``CAMERA_ID MODEL WIDTH HEIGHT PARAMS...``;
the models read are ``SIMPLE_PINHOLE`` (f cx cy), ``PINHOLE`` (fx fy cx cy),
``SIMPLE_RADIAL`` (f cx cy k), ``RADIAL`` (f cx cy k1 k2) and ``OPENCV`` (fx fy cx cy
k1 k2 p1 p2).  ``images.txt`` has two lines per image: ``IMAGE_ID QW QX QY QZ TX TY TZ
CAMERA_ID NAME`` (world to camera, quaternion scalar first) and its 2-D points.
``points3D.txt`` has ``POINT3D_ID X Y Z R G B ERROR TRACK[]`` with the track's
``IMAGE_ID POINT2D_IDX`` pairs.  The binary files hold the same
(:mod:`~robostereo.robot.importers.colmap_binary`).

COLMAP puts the centre of the top-left pixel at ``(0.5, 0.5)``; robostereo (as OpenCV)
at ``(0, 0)``: ``cx = cx_colmap - 0.5``, ``cy = cy_colmap - 0.5``.  Each view's depth
range is that of the points it sees (the 1st to 99th percentile of their depths,
widened by a tenth).  A reconstruction's unit is its own (arbitrary, unless it was
scaled to the world): ``unit_to_mm`` says how many mm one is.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.importers.imported_views import Imported, ImportedView

__all__ = ["COLMAP_MODELS", "PIXEL_CENTRE_OFFSET", "colmap_intrinsics", "read_colmap"]

PIXEL_CENTRE_OFFSET = 0.5
"""COLMAP's principal point minus robostereo's, pixels (COLMAP's top-left pixel centre
is at ``(0.5, 0.5)``)."""

#: model name -> number of parameters
COLMAP_MODELS = {"SIMPLE_PINHOLE": 3, "PINHOLE": 4, "SIMPLE_RADIAL": 4, "RADIAL": 5,
                 "OPENCV": 8}


def colmap_intrinsics(model: str, params: list[float]
                      ) -> tuple[np.ndarray, tuple[float, ...]]:
    """``K`` (robostereo's pixel centres) and distortion ``(k1, k2, p1, p2)`` of a
    COLMAP camera.

    >>> K, d = colmap_intrinsics("RADIAL", [1000.0, 320.0, 240.0, -0.1, 0.01])
    >>> K[0].tolist(), K[1].tolist(), d
    ([1000.0, 0.0, 319.5], [0.0, 1000.0, 239.5], (-0.1, 0.01, 0.0, 0.0))
    """
    if model not in COLMAP_MODELS:
        raise InputError(f"COLMAP camera model {model} is not read (models: "
                         f"{', '.join(COLMAP_MODELS)})")
    if len(params) != COLMAP_MODELS[model]:
        raise InputError(f"COLMAP camera model {model} takes {COLMAP_MODELS[model]} "
                         f"parameters, got {len(params)}")
    if model in ("PINHOLE", "OPENCV"):
        fx, fy, cx, cy = params[:4]
    else:
        fx = fy = params[0]
        cx, cy = params[1:3]
    dist: tuple[float, ...] = ()
    if model == "SIMPLE_RADIAL":
        dist = (params[3], 0.0, 0.0, 0.0)
    elif model == "RADIAL":
        dist = (params[3], params[4], 0.0, 0.0)
    elif model == "OPENCV":
        dist = tuple(params[4:8])
    K = np.array([[fx, 0.0, cx - PIXEL_CENTRE_OFFSET], [0.0, fy, cy - PIXEL_CENTRE_OFFSET],
                  [0.0, 0.0, 1.0]])
    return K, tuple(float(v) for v in dist)


def _lines(path: Path, *, keep_comments: bool = False) -> list[str]:
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the COLMAP model file ({exc})") from None
    return [ln for ln in text.splitlines() if keep_comments or not ln.startswith("#")]


def read_colmap(model: str | os.PathLike[str], images: str | os.PathLike[str], *,
                unit_to_mm: float = 1.0) -> Imported:
    """The views of a COLMAP text model and its image folder.

    Parameters
    ----------
    model : path
        The folder with ``cameras``, ``images`` and (for the depth range)
        ``points3D``, ``.txt`` (read first) or ``.bin``.
    images : path
        The image folder the model's ``NAME`` s are relative to.
    unit_to_mm : float
        Millimetres per model unit.

    Returns
    -------
    Imported
        Views keyed by image name, in ``IMAGE_ID`` order; per view depth ranges from
        the points it sees.

    Raises
    ------
    InputError
        A missing file, a line or record that does not parse (named by file and
        line), a camera model not read.
    """
    m, imgdir = Path(model), Path(images)
    if (m / "cameras.txt").is_file():
        cams = _text_cameras(m / "cameras.txt")
        images_ = _text_images(m / "images.txt")
        points = _text_points(m / "points3D.txt") if (m / "points3D.txt").is_file() \
            else None
    elif (m / "cameras.bin").is_file():
        from robostereo.robot.importers.colmap_binary import (
            read_cameras_bin,
            read_images_bin,
            read_points3d_bin,
        )

        cams = read_cameras_bin(m / "cameras.bin")
        images_ = read_images_bin(m / "images.bin")
        points = read_points3d_bin(m / "points3D.bin") if (m / "points3D.bin").is_file() \
            else None
    else:
        raise InputError(f"{m}: no cameras.txt or cameras.bin (not a COLMAP model)")
    intrinsics = {}
    for cid, (name, params) in cams.items():
        try:
            intrinsics[cid] = colmap_intrinsics(name, params)
        except InputError as exc:
            raise InputError(f"{m}: camera {cid}: {exc}") from None
    views: list[tuple[int, ImportedView]] = []
    for iid, q, tr, cid, name in images_:
        if cid not in intrinsics:
            raise InputError(f"{m}: image {name} has camera {cid}, which the cameras lack")
        world_to_cam = SE3.from_quaternion(tr, [*q[1:], q[0]], source=f"{m}: {name}")
        pose = world_to_cam.inv()
        pose = SE3(pose.rotation, pose.translation * unit_to_mm)
        K, dist = intrinsics[cid]
        views.append((iid, ImportedView(name, imgdir / name, K, pose, dist)))
    views.sort(key=lambda v: v[0])
    depths = {} if points is None else _view_depths(points, views, unit_to_mm)
    return Imported(tuple(v for _, v in views), None, depths, source=str(m))


#: what the text and binary readers give: cameras {id: (model, params)}, images
#: [(id, (qw, qx, qy, qz), (tx, ty, tz), camera id, name)], points ((N, 3), [image ids])
Cameras = dict[int, tuple[str, list[float]]]
Images = list[tuple[int, list[float], list[float], int, str]]
Points = tuple[np.ndarray, list[set[int]]]


def _text_cameras(path: Path) -> Cameras:
    cams: Cameras = {}
    for n, line in enumerate(_lines(path, keep_comments=True), 1):
        t = line.split()
        if not t or line.startswith("#"):
            continue
        try:
            cams[int(t[0])] = (t[1], [float(v) for v in t[4:]])
            colmap_intrinsics(t[1], cams[int(t[0])][1])
        except InputError as exc:
            raise InputError(f"{path}: line {n}: {exc}") from None
        except (ValueError, IndexError):
            raise InputError(f"{path}: line {n} is not CAMERA_ID MODEL WIDTH HEIGHT "
                             "PARAMS") from None
    return cams


def _text_images(path: Path) -> Images:
    rows = _lines(path)
    out: Images = []
    for n in range(0, len(rows), 2):
        t = rows[n].split()
        if not t:
            continue
        try:
            out.append((int(t[0]), [float(v) for v in t[1:5]], [float(v) for v in t[5:8]],
                        int(t[8]), " ".join(t[9:])))
        except (ValueError, IndexError):
            raise InputError(f"{path}: an image line does not read as IMAGE_ID QW QX QY QZ "
                             "TX TY TZ CAMERA_ID NAME") from None
    return out


def _text_points(path: Path) -> Points:
    xyz, seen = [], []
    for line in _lines(path):
        t = line.split()
        if len(t) < 8:
            continue
        try:
            xyz.append([float(v) for v in t[1:4]])
            seen.append({int(v) for v in t[8::2]})
        except ValueError:
            raise InputError(f"{path}: a line does not read as POINT3D_ID X Y Z R G B "
                             "ERROR TRACK") from None
    return np.array(xyz, dtype=float).reshape(-1, 3), seen


def _view_depths(points: Points, views: list[tuple[int, ImportedView]],
                 unit_to_mm: float) -> dict[str, tuple[float, float]]:
    """Each view's depth range from the points whose track has it."""
    xyz, seen = points
    pts = xyz * unit_to_mm
    out = {}
    for iid, v in views:
        mask = np.array([iid in s for s in seen], bool)
        if mask.sum() < 2:
            continue
        z = (pts[mask] - v.pose.translation) @ v.pose.rotation[:, 2]
        z = z[z > 0]
        if z.size < 2:
            continue
        lo, hi = np.percentile(z, [1.0, 99.0])
        pad = 0.1 * (hi - lo)
        out[v.key] = (float(max(lo - pad, lo / 2)), float(hi + pad))
    return out
