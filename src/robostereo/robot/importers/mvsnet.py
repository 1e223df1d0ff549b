"""MVSNet folders: ``cams/0000000K_cam.txt``, ``images/0000000K.jpg``, ``pair.txt``.

A camera file (MVSNet, Yao et al. 2018, and the DTU / BlendedMVS / Tanks and Temples
sets prepared for it) reads::

    extrinsic
    E00 E01 E02 E03        4 x 4, world to camera: x_cam = R x_world + t
    ...
    <blank>
    intrinsic
    K00 K01 K02            3 x 3, pixels
    ...
    <blank>
    DEPTH_MIN DEPTH_INTERVAL [DEPTH_NUM [DEPTH_MAX]]

:func:`read_mvsnet` inverts the extrinsic into ``T_world_camera`` and takes each view's
depth range from the last line (``DEPTH_MAX`` when given, else ``DEPTH_MIN +
DEPTH_INTERVAL * (DEPTH_NUM - 1)`` with ``DEPTH_NUM`` 192, MVSNet's default).  DTU's
world is in millimetres; ``unit_to_mm`` scales another.  ``intrinsics_scale``
multiplies ``fx, fy, cx, cy`` as MVSNet does (its DTU training cameras are for images
a quarter the size: 4).  ``pair.txt`` lists each view's best neighbours
(:func:`read_pairs`).

Ground-truth depth maps (DTU's ``Depths/scanN_train/depth_map_0000.pfm``, or an
MVSNet output's ``00000000.pfm``) are read by :func:`read_mvsnet_depths`: each
view's map, in the world's unit along its optical axis, often at a lower resolution
than the images (DTU's training maps: a quarter), is put on the capture's image grid
by nearest-neighbour sampling of pixel centres (:func:`depth_on_image_grid`; no
interpolation across depth steps), so that the capture keeps one camera.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.importers.imported_views import Imported, ImportedView

__all__ = [
    "MVSNET_DEPTH_NUM",
    "depth_on_image_grid",
    "mvsnet_depth_file",
    "read_mvsnet",
    "read_mvsnet_cam",
    "read_mvsnet_depths",
    "read_pairs",
]

MVSNET_DEPTH_NUM = 192
"""Depth planes when a camera file gives ``DEPTH_MIN DEPTH_INTERVAL`` alone (MVSNet's
``max_d``)."""

_IMAGE_SUFFIXES = (".jpg", ".jpeg", ".png")


def _numbers(path: Path, lines: list[str], what: str, rows: int, cols: int) -> np.ndarray:
    try:
        vals = [float(t) for line in lines[:rows] for t in line.split()]
    except ValueError:
        raise InputError(f"{path}: '{what}' must be {rows} x {cols} numbers") from None
    if len(vals) != rows * cols or not np.all(np.isfinite(vals)):
        raise InputError(f"{path}: '{what}' must be {rows} x {cols} finite numbers")
    return np.array(vals).reshape(rows, cols)


def read_mvsnet_cam(path: str | os.PathLike[str], *, intrinsics_scale: float = 1.0,
                    unit_to_mm: float = 1.0
                    ) -> tuple[np.ndarray, SE3, tuple[float, float] | None]:
    """``K``, ``T_world_camera`` and the depth range (mm, or None) of one camera file.

    >>> import tempfile
    >>> p = Path(tempfile.mkdtemp()) / "00000000_cam.txt"
    >>> _ = p.write_text("extrinsic\\n1 0 0 0\\n0 1 0 0\\n0 0 1 500\\n0 0 0 1\\n\\n"
    ...                  "intrinsic\\n400 0 80\\n0 400 64\\n0 0 1\\n\\n425 2.5\\n")
    >>> K, pose, depth = read_mvsnet_cam(p, intrinsics_scale=4)
    >>> K[0].tolist(), pose.translation.tolist(), depth
    ([1600.0, 0.0, 320.0], [0.0, 0.0, -500.0], (425.0, 902.5))
    """
    p = Path(path)
    try:
        lines = [ln.strip() for ln in p.read_text(encoding="utf-8").splitlines()]
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: cannot read the MVSNet camera file ({exc})") from None
    words = [ln for ln in lines if ln]
    try:
        e, k = words.index("extrinsic"), words.index("intrinsic")
    except ValueError:
        raise InputError(f"{p}: not an MVSNet camera file (no 'extrinsic' and "
                         "'intrinsic')") from None
    E = _numbers(p, words[e + 1:e + 5], "extrinsic", 4, 4)
    K = _numbers(p, words[k + 1:k + 4], "intrinsic", 3, 3)
    K[:2] *= intrinsics_scale
    T = SE3.from_matrix(E)
    pose = T.inv()
    pose = SE3(pose.rotation, pose.translation * unit_to_mm)
    depth = None
    rest = words[max(e + 5, k + 4):]
    if rest:
        try:
            d = [float(t) for t in rest[0].split()]
        except ValueError:
            raise InputError(f"{p}: the depth line must be DEPTH_MIN DEPTH_INTERVAL "
                             "[DEPTH_NUM [DEPTH_MAX]]") from None
        if len(d) >= 2:
            near = d[0]
            far = d[3] if len(d) >= 4 else d[0] + d[1] * ((d[2] if len(d) >= 3
                                                           else MVSNET_DEPTH_NUM) - 1)
            if not (np.isfinite([near, far]).all() and 0 < near < far):
                raise InputError(f"{p}: the depth range {near:g} .. {far:g} is not "
                                 "0 < min < max")
            depth = (near * unit_to_mm, far * unit_to_mm)
    return K, pose, depth


def read_pairs(path: str | os.PathLike[str]) -> dict[int, list[int]]:
    """``pair.txt``: each view's neighbours, best first.

    >>> import tempfile
    >>> p = Path(tempfile.mkdtemp()) / "pair.txt"
    >>> _ = p.write_text("2\\n0\\n1 1 300.5\\n1\\n1 0 300.5\\n")
    >>> read_pairs(p)
    {0: [1], 1: [0]}
    """
    p = Path(path)
    try:
        toks = p.read_text(encoding="utf-8").split()
        n = int(toks[0])
        out, i = {}, 1
        for _ in range(n):
            ref, m = int(toks[i]), int(toks[i + 1])
            out[ref] = [int(toks[i + 2 + 2 * j]) for j in range(m)]
            i += 2 + 2 * m
    except (OSError, UnicodeDecodeError, ValueError, IndexError):
        raise InputError(f"{p}: not an MVSNet pair.txt (N, then each view's id, its "
                         "neighbour count and id score pairs)") from None
    return out


def read_mvsnet(folder: str | os.PathLike[str], *, intrinsics_scale: float = 1.0,
                unit_to_mm: float = 1.0) -> Imported:
    """The views of an MVSNet folder (``cams/``, ``images/``).

    Parameters
    ----------
    folder : path
        The scan's folder.
    intrinsics_scale : float
        Factor on ``fx, fy, cx, cy`` (the camera files' image size to the images').
    unit_to_mm : float
        Millimetres per world unit (1 for DTU).

    Returns
    -------
    Imported
        Views keyed by the camera files' numbers (``00000003``), each view's depth
        range from its file.
    """
    d = Path(folder)
    cams = sorted((d / "cams").glob("*_cam.txt")) if (d / "cams").is_dir() else []
    if not cams:
        raise InputError(f"{d}: no cams/*_cam.txt (not an MVSNet folder)")
    if not (isinstance(intrinsics_scale, int | float) and intrinsics_scale > 0):
        raise InputError(f"--intrinsics-scale must be > 0, got {intrinsics_scale!r}")
    images = {p.stem: p for p in sorted((d / "images").iterdir())
              if p.suffix.lower() in _IMAGE_SUFFIXES} if (d / "images").is_dir() else {}
    views, depths = [], {}
    for c in cams:
        key = c.name[: -len("_cam.txt")]
        if key not in images:
            raise InputError(f"{c}: no image images/{key}.jpg (or .png)")
        K, pose, depth = read_mvsnet_cam(c, intrinsics_scale=intrinsics_scale,
                                         unit_to_mm=unit_to_mm)
        views.append(ImportedView(key, images[key], K, pose))
        if depth is not None:
            depths[key] = depth
    return Imported(tuple(views), None, depths, source=str(d))


def mvsnet_depth_file(folder: str | os.PathLike[str], key: str) -> Path:
    """View `key`'s depth map in `folder`: ``depth_map_NNNN.pfm`` (DTU's, ``NNNN`` the
    view number) or ``KEY.pfm`` (an MVSNet output's), the first that exists.

    Raises
    ------
    InputError
        Neither exists; the message names both.
    """
    d = Path(folder)
    names = ([f"depth_map_{int(key):04d}.pfm"] if key.isdigit() else []) + [f"{key}.pfm"]
    for n in names:
        if (d / n).is_file():
            return d / n
    raise InputError(f"{d}: no depth map for view {key} ({' or '.join(names)})")


def depth_on_image_grid(depth: NDArray[np.float64], image_size: tuple[int, int],
                        source: str = "depth map") -> NDArray[np.float64]:
    """A depth map resampled to an image's pixel grid (nearest pixel centre).

    Parameters
    ----------
    depth : ndarray, shape (h, w)
        Depth over the same field of view as the image, at any resolution.
    image_size : tuple of int
        ``(W, H)`` of the image.
    source : str
        The file, for messages.

    Returns
    -------
    ndarray, shape (H, W)
        ``depth[floor((y + 0.5) h / H), floor((x + 0.5) w / W)]`` at each image pixel
        ``(x, y)``: pixel centres mapped to pixel centres, no value made up between two
        (a depth step stays a step).

    Raises
    ------
    InputError
        A map whose aspect ratio is not the image's (within a pixel): it covers another
        field of view (a crop) and would be misplaced.

    Examples
    --------
    >>> depth_on_image_grid(np.array([[1.0, 2.0], [3.0, 4.0]]), (4, 2)).tolist()
    [[1.0, 1.0, 2.0, 2.0], [3.0, 3.0, 4.0, 4.0]]
    """
    h, w = depth.shape
    W, H = image_size
    if abs(w * H / W - h) > 1.0:
        raise InputError(f"{source}: the depth map is {w} x {h} pixels, not the image's "
                         f"{W} x {H} scaled (another aspect ratio: a crop?)")
    rows = np.minimum(((np.arange(H) + 0.5) * h / H).astype(np.intp), h - 1)
    cols = np.minimum(((np.arange(W) + 0.5) * w / W).astype(np.intp), w - 1)
    return depth[np.ix_(rows, cols)]


def read_mvsnet_depths(folder: str | os.PathLike[str], keys: list[str],
                       image_size: tuple[int, int], *, unit_to_mm: float = 1.0
                       ) -> dict[str, NDArray[np.float64]]:
    """The ground-truth depth maps of views `keys`, in mm on the image grid.

    Parameters
    ----------
    folder : path
        The folder of the maps (:func:`mvsnet_depth_file`).
    keys : list of str
        The views' keys (``00000003``).
    image_size : tuple of int
        ``(W, H)`` of the capture's images (after any ``--scale``).
    unit_to_mm : float
        Millimetres per world unit.

    Returns
    -------
    dict of str to ndarray, shape (H, W)
        Depth in mm, NaN unknown.

    Raises
    ------
    InputError
        A missing folder or map, an unreadable one, one of another aspect ratio.
    """
    from robostereo.evaluation.depth_maps import read_depth_map

    d = Path(folder)
    if not d.is_dir():
        raise InputError(f"{d}: depth map folder not found")
    out = {}
    for key in keys:
        p = mvsnet_depth_file(d, key)
        out[key] = depth_on_image_grid(read_depth_map(p), image_size, str(p)) * unit_to_mm
    return out
