"""One camera's calibration file: an OpenCV camera YAML/XML/JSON or a ROS ``camera_info``.

:func:`read_camera_file` gives the :class:`~robostereo.geometry.camera.Camera` (in
pixels) of

* a file that ``cv2.FileStorage`` writes after :func:`cv2.calibrateCamera`, as
  OpenCV's calibration sample does: ``camera_matrix`` (or ``K``, ``cameraMatrix``),
  ``distortion_coefficients`` (or ``D``, ``dist_coeffs``, ``distCoeffs``) and the
  image size (``image_width``/``image_height``, ``width``/``height`` or
  ``image_size``);
* a ROS ``camera_info`` YAML (``camera_calibration``'s ``ost.yaml``): ``image_width``,
  ``image_height``, ``camera_matrix`` and ``distortion_coefficients`` as
  ``{rows, cols, data}``, ``distortion_model`` ``plumb_bob``.

Both put the centre of the top-left pixel at ``(0, 0)``, as robostereo does.  A capture
folder's ``camera:`` may name such a file (:func:`camera_from_entry`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.errors import InputError, shown
from robostereo.geometry.camera import Camera, camera_from_dict
from robostereo.io.calibration_files import calibration_matrix, read_calibration_mapping

__all__ = ["camera_from_entry", "read_camera_file"]

_K_KEYS = ("camera_matrix", "K", "cameraMatrix")
_D_KEYS = ("distortion_coefficients", "D", "dist_coeffs", "distCoeffs")


def _first(data: Mapping[str, Any], keys: tuple[str, ...]) -> tuple[str, Any] | None:
    for k in keys:
        if data.get(k) is not None:
            return k, data[k]
    return None


def _image_size(path: Path, data: Mapping[str, Any]) -> tuple[int, int]:
    for wk, hk in (("image_width", "image_height"), ("width", "height")):
        if wk in data and hk in data:
            size = [data[wk], data[hk]]
            break
    else:
        found = _first(data, ("image_size", "imageSize"))
        if found is None:
            raise InputError(f"{path}: missing key image_width and image_height (or "
                             "image_size)")
        size = calibration_matrix(path, found[0], found[1]).ravel().tolist()
    ok = len(size) == 2 and all(
        isinstance(v, int | float) and not isinstance(v, bool) and float(v).is_integer()
        and v > 0 for v in size)
    if not ok:
        raise InputError(f"{path}: the image size must be two whole numbers > 0, got "
                         f"{shown(size)}")
    return int(size[0]), int(size[1])


def read_camera_file(path: str | os.PathLike[str], *, grey_levels: int = 256) -> Camera:
    """The camera of an OpenCV or ROS ``camera_info`` calibration file, in pixels.

    Parameters
    ----------
    path : path
        The file (see the module docstring).
    grey_levels : int
        Grey levels of the images (the files do not say; 256 for 8-bit images).

    Returns
    -------
    Camera
        ``in_pixels``, its ``K`` and distortion ``(k1, k2, p1, p2[, k3])`` as the file
        gives them.

    Raises
    ------
    InputError
        One line naming the file: unreadable, a key missing, ``K`` not a camera matrix,
        a distortion model other than ``plumb_bob`` (coefficients past ``k3`` that are
        not zero).

    Examples
    --------
    >>> import tempfile
    >>> p = Path(tempfile.mkdtemp()) / "ost.yaml"
    >>> _ = p.write_text("image_width: 640\\nimage_height: 480\\ncamera_matrix:\\n"
    ...     "  rows: 3\\n  cols: 3\\n  data: [600, 0, 319.5, 0, 600, 239.5, 0, 0, 1]\\n"
    ...     "distortion_model: plumb_bob\\ndistortion_coefficients:\\n  rows: 1\\n"
    ...     "  cols: 5\\n  data: [-0.1, 0.01, 0, 0, 0]\\n")
    >>> cam = read_camera_file(p)
    >>> cam.fx, cam.principal_point, cam.distortion, cam.image_size
    (600.0, (319.5, 239.5), (-0.1, 0.01, 0.0, 0.0, 0.0), (640, 480))
    """
    p, data = read_calibration_mapping(path)
    model = str(data.get("distortion_model") or "plumb_bob").strip().lower()
    if model not in ("plumb_bob", "rational_polynomial"):
        raise InputError(f"{p}: distortion_model must be plumb_bob, got {model!r}")
    k = _first(data, _K_KEYS)
    if k is None:
        raise InputError(f"{p}: missing key camera_matrix (or K)")
    K = calibration_matrix(p, k[0], k[1])
    if K.size != 9:
        raise InputError(f"{p}: {k[0]} must be a 3 x 3 matrix, got {K.size} values")
    d = _first(data, _D_KEYS)
    dist = np.zeros(0) if d is None else calibration_matrix(p, d[0], d[1]).ravel()
    if dist.size > 5:
        if np.any(dist[5:] != 0):
            raise InputError(f"{p}: {d[0] if d else ''} has {dist.size} coefficients with "
                             "k4.. not zero: only (k1, k2, p1, p2, k3) is modelled")
        dist = dist[:5]
    if dist.size not in (0, 4, 5) or not np.all(np.isfinite(dist)):
        raise InputError(f"{p}: distortion coefficients must be 4 or 5 finite numbers, got "
                         f"{shown(dist.tolist())}")
    try:
        return Camera.from_intrinsics(K.reshape(3, 3), _image_size(p, data),
                                      distortion=tuple(float(v) for v in dist),
                                      grey_levels=grey_levels)
    except InputError as exc:
        raise InputError(f"{p}: {exc}") from None


def camera_from_entry(value: Any, folder: str | os.PathLike[str], source: str) -> Camera:
    """The camera a capture file's ``camera:`` key gives: a mapping (either form of
    :func:`~robostereo.geometry.camera.camera_from_dict`) or the path, relative to
    `folder`, of a camera file (:func:`read_camera_file`).

    Parameters
    ----------
    value : mapping or str
        The key's value.
    folder : path
        The capture folder, which a relative path starts from.
    source : str
        The capture file, for messages.
    """
    if isinstance(value, str):
        file = Path(folder) / value
        if not file.is_file():
            raise InputError(f"{source}: camera: {value!r} is not a camera file (a path "
                             "relative to the capture folder)")
        return read_camera_file(file)
    if not isinstance(value, Mapping):
        raise InputError(f"{source}: camera must be a mapping or the path of a camera "
                         f"file, got {shown(value)}")
    return camera_from_dict(value, source=f"{source}: camera")
