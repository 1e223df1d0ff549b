"""Ground-truth depth maps of capture folders: where they are, reading and writing them.

A capture folder (two views, :mod:`robostereo.robot.capture.capture_folder`, or N views,
:mod:`robostereo.robot.views.views_folder`) may hold a ground-truth depth map per view:
the z-depth along the view's optical axis at every pixel centre of its grabbed image, in
the capture's world unit (mm); 0, negative or non-finite values are unknown.  Formats, by
the file's suffix:

* ``.pfm``: 32-bit float (one channel, rows bottom to top as the format says), read and
  written by OpenCV;
* ``.npy``: a NumPy (H, W) float or integer array;
* ``.png``: 16-bit grey, ``depth_mm = value / depth_scale`` (``depth_scale`` in units
  per mm, :data:`DEFAULT_DEPTH_SCALE` = 1: millimetres, the depth cameras' convention;
  give 10 for 0.1 mm steps).

Where a view's map is (:func:`capture_depth_files`): the key ``depth_left`` /
``depth_right`` of a two-view ``capture.yaml``, or ``depth`` in a view's entry of
``views:``; without it ``depth/<stem of the view's image>.pfm`` (then ``.npy``, ``.png``)
when that file exists.  ``depth_scale`` is a top-level key.  The capture readers accept
these keys and ignore them; only ``robostereo evaluate`` reads the maps.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, shown

__all__ = [
    "DEFAULT_DEPTH_SCALE",
    "DEPTH_FOLDER",
    "DEPTH_SUFFIXES",
    "DepthFiles",
    "capture_depth_files",
    "depth_map_bytes",
    "depth_map_files",
    "read_depth_map",
    "write_depth_map",
]

DEPTH_SUFFIXES = (".pfm", ".npy", ".png")
"""Depth map formats, in the order the ``depth/`` fallback looks for them."""

DEPTH_FOLDER = "depth"
"""The folder of a capture where a view's depth map is looked for when no key names it."""

DEFAULT_DEPTH_SCALE = 1.0
"""``depth_scale`` of 16-bit PNG depth maps when the capture file gives none: units per
mm (1: the PNG holds millimetres)."""

_PNG_MAX = 65535


def _suffix(path: Path) -> str:
    s = path.suffix.lower()
    if s not in DEPTH_SUFFIXES:
        raise InputError(f"{path}: a depth map must be {', '.join(DEPTH_SUFFIXES)}, got "
                         f"{path.suffix or 'no suffix'}")
    return s


def read_depth_map(path: str | os.PathLike[str], *, image_size: tuple[int, int] | None = None,
                   scale: float = DEFAULT_DEPTH_SCALE) -> NDArray[np.float64]:
    """Read a ground-truth depth map.

    Parameters
    ----------
    path : path
        A ``.pfm``, ``.npy`` or 16-bit ``.png`` file.
    image_size : tuple of int, optional
        ``(W, H)`` the map must have (the camera's image size).
    scale : float
        Units per mm of a PNG (``depth_scale``); ignored for PFM and NPY.

    Returns
    -------
    ndarray, shape (H, W)
        Depth along the optical axis, mm; NaN where unknown (0, negative, not finite).

    Raises
    ------
    InputError
        One line naming the file: missing, of another format, unreadable, not one
        channel, an 8-bit PNG, or of another size than `image_size`.

    Examples
    --------
    >>> import tempfile
    >>> p = Path(tempfile.mkdtemp()) / "d.png"
    >>> _ = write_depth_map(p, np.array([[500.0, 0.0], [np.inf, 1234.4]]))
    >>> read_depth_map(p, image_size=(2, 2)).tolist()
    [[500.0, nan], [nan, 1234.0]]
    """
    p = Path(path)
    kind = _suffix(p)
    if not p.is_file():
        raise InputError(f"{p}: depth map not found")
    if not (np.isfinite(scale) and scale > 0):
        raise InputError(f"{p}: depth_scale must be a finite number > 0, got {shown(scale)}")
    if kind == ".npy":
        try:
            raw = np.load(p, allow_pickle=False)
        except (OSError, ValueError) as e:
            raise InputError(f"{p}: not a readable .npy depth map ({e})") from None
        if not (np.issubdtype(raw.dtype, np.floating) or np.issubdtype(raw.dtype, np.integer)):
            raise InputError(f"{p}: a depth map holds numbers, got dtype {raw.dtype}")
    else:
        import cv2

        raw = cv2.imread(str(p), cv2.IMREAD_UNCHANGED)
        if raw is None:
            raise InputError(f"{p}: not a readable {kind[1:].upper()} depth map")
        if kind == ".png" and raw.dtype != np.uint16:
            raise InputError(f"{p}: a PNG depth map must be 16-bit grey, got {raw.dtype}")
    if raw.ndim != 2:
        raise InputError(f"{p}: a depth map has one channel (H, W), got shape {raw.shape}")
    depth = raw.astype(np.float64)
    if kind == ".png":
        depth /= float(scale)
    if image_size is not None and depth.shape != (image_size[1], image_size[0]):
        raise InputError(f"{p}: the depth map is {depth.shape[1]} x {depth.shape[0]} pixels, "
                         f"the camera's image_size is {image_size[0]} x {image_size[1]}")
    with np.errstate(invalid="ignore"):
        depth[~(np.isfinite(depth) & (depth > 0))] = np.nan
    return depth


def depth_map_bytes(depth: ArrayLike, suffix: str, *, scale: float = DEFAULT_DEPTH_SCALE,
                    name: str = "depth map") -> bytes:
    """A depth map (mm; NaN, inf or <= 0: unknown, written as 0) encoded as the file
    `suffix` (``.pfm``, ``.npy`` or ``.png``) holds; `name` is the file for messages.

    Raises
    ------
    InputError
        Not (H, W); a PNG whose largest scaled depth exceeds 65535.

    >>> len(depth_map_bytes(np.ones((2, 3)), ".npy")) > 6 * 4
    True
    """
    import io

    import cv2

    d = np.asarray(depth, dtype=np.float64)
    if d.ndim != 2:
        raise InputError(f"{name}: a depth map is (H, W), got shape {d.shape}")
    with np.errstate(invalid="ignore"):
        known = np.isfinite(d) & (d > 0)
    if suffix == ".png":
        v = np.where(known, np.rint(np.where(known, d, 0.0) * scale), 0.0)
        if v.max(initial=0.0) > _PNG_MAX:
            raise InputError(f"{name}: depth {d[known].max():g} mm times depth_scale "
                             f"{scale:g} exceeds a 16-bit PNG's {_PNG_MAX}: lower "
                             "depth_scale")
        ok, buf = cv2.imencode(".png", v.astype(np.uint16))
    else:
        out = np.where(known, d, 0.0).astype(np.float32)
        if suffix == ".npy":
            b = io.BytesIO()
            np.save(b, out, allow_pickle=False)
            return b.getvalue()
        ok, buf = cv2.imencode(".pfm", out)
    if not ok:  # pragma: no cover - OpenCV encodes these always
        raise InputError(f"{name}: could not encode the depth map")
    return buf.tobytes()


def write_depth_map(path: str | os.PathLike[str], depth: ArrayLike, *,
                    scale: float = DEFAULT_DEPTH_SCALE) -> Path:
    """Write a depth map (mm; NaN, inf or <= 0: unknown) as PFM, NPY or 16-bit PNG
    (:func:`depth_map_bytes`).

    Parameters
    ----------
    path : path
        Its suffix chooses the format.
    depth : array_like, shape (H, W)
    scale : float
        Units per mm of a PNG: ``value = round(depth * scale)``, unknown 0.

    Returns
    -------
    Path

    Raises
    ------
    InputError
        Not (H, W); a PNG whose largest scaled depth exceeds 65535; a file that cannot
        be written.
    """
    p = Path(path)
    data = depth_map_bytes(depth, _suffix(p), scale=scale, name=str(p))
    try:
        p.write_bytes(data)
    except OSError as e:
        raise InputError(f"{p}: could not write the depth map ({e.strerror})") from None
    return p


def depth_map_files(stems: Sequence[str], depths: Sequence[ArrayLike] | None, *,
                    suffix: str = ".npy") -> dict[str, bytes]:
    """Ground-truth depth maps as the files of a capture folder that
    :func:`capture_depth_files` finds without a key: ``depth/<stem><suffix>`` (``.npy``
    or ``.pfm``), one per view (none when `depths` is None); for the capture writers'
    all-or-nothing folder."""
    return {f"{DEPTH_FOLDER}/{stem}{suffix}": depth_map_bytes(d, suffix, name=f"{stem} depth")
            for stem, d in zip(stems, depths or (), strict=False)}


@dataclass(frozen=True)
class DepthFiles:
    """The depth maps a capture folder names or holds.

    Attributes
    ----------
    names : tuple of str
        Each view's image file (``left.png``, ``right.png`` for a two-view folder).
    paths : tuple of Path or None
        Each view's depth map; None where it has none.
    scale : float
        ``depth_scale`` (units per mm of PNG maps).
    source : str
        The ``capture.yaml``, for messages.
    """

    names: tuple[str, ...]
    paths: tuple[Path | None, ...]
    scale: float
    source: str

    def __post_init__(self) -> None:
        if len(self.names) != len(self.paths):
            raise InputError("DepthFiles: one path (or None) per view name")
        if not (isinstance(self.scale, float) and np.isfinite(self.scale) and self.scale > 0):
            raise InputError(f"{self.source}: key 'depth_scale' must be a finite number > 0 "
                             f"(units per mm), got {shown(self.scale)}")

    def read(self, view: int, image_size: tuple[int, int]) -> NDArray[np.float64] | None:
        """View `view`'s depth map (:func:`read_depth_map`), None when it has none."""
        p = self.paths[view]
        if p is None:
            return None
        return read_depth_map(p, image_size=image_size, scale=self.scale)


def _entry(d: Path, value: Any, where: str) -> Path:
    if not isinstance(value, str) or not value.strip():
        raise InputError(f"{where}: a depth map is a file name inside the capture folder, "
                         f"got {shown(value)}")
    p = PurePosixPath(value)
    if p.is_absolute() or ".." in p.parts:
        raise InputError(f"{where}: the depth map {value!r} must be a file inside the "
                         "capture folder")
    path = d / value
    _suffix(path)
    if not path.is_file():
        raise InputError(f"{path}: depth map not found ({where})")
    return path


def _fallback(d: Path, image: str) -> Path | None:
    stem = PurePosixPath(image).stem
    for s in DEPTH_SUFFIXES:
        p = d / DEPTH_FOLDER / f"{stem}{s}"
        if p.is_file():
            return p
    return None


def capture_depth_files(directory: str | os.PathLike[str]) -> DepthFiles:
    """Where a capture folder's depth maps are (the keys, else ``depth/<stem>.*``).

    Parameters
    ----------
    directory : path
        A two-view or N-view capture folder.

    Returns
    -------
    DepthFiles

    Raises
    ------
    InputError
        ``capture.yaml`` missing or unreadable, a depth key that is not a file name
        inside the folder or names a missing file, a bad ``depth_scale``.
    """
    from robostereo.io import read_folder_yaml

    data, ypath = read_folder_yaml(directory, "capture.yaml", folder="capture")
    d, src = ypath.parent, str(ypath)
    if not isinstance(data, Mapping):
        raise InputError(f"{src}: expected a mapping")
    scale = data.get("depth_scale", DEFAULT_DEPTH_SCALE)
    if isinstance(scale, bool) or not isinstance(scale, int | float):
        raise InputError(f"{src}: key 'depth_scale' must be a number (units per mm), got "
                         f"{shown(scale)}")
    if "views" in data and isinstance(data["views"], list):
        names, paths = [], []
        for k, v in enumerate(data["views"]):
            image = v.get("image") if isinstance(v, Mapping) else None
            if not isinstance(image, str):
                raise InputError(f"{src}: views[{k}]: missing key 'image'")
            names.append(image)
            paths.append(_entry(d, v["depth"], f"{src}: views[{k}] depth") if "depth" in v
                         else _fallback(d, image))
    else:
        names = ["left.png", "right.png"]
        paths = [_entry(d, data[f"depth_{s}"], f"{src}: depth_{s}") if f"depth_{s}" in data
                 else _fallback(d, f"{s}.png") for s in ("left", "right")]
    return DepthFiles(tuple(names), tuple(paths), float(scale), src)
