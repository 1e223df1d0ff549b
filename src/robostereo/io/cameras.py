"""Camera and pose files: YAML for a camera, a pose, a stereo pair of poses, a stereo camera.

* a :class:`~robostereo.geometry.camera.Camera` (:func:`load_camera_yaml`,
  :func:`save_camera_yaml`; keys of :func:`~robostereo.geometry.camera.camera_from_dict`);
* a SCARA :class:`~robostereo.geometry.poses.Pose` (:func:`load_pose_yaml`,
  :func:`save_pose_yaml`) and the two viewpoints of a pair
  (:func:`load_stereo_poses_yaml`);
* the :class:`~robostereo.geometry.triangulation.StereoCamera` of a rectified pair
  (:func:`load_stereo_camera`, :func:`stereo_camera_from_dict`,
  :func:`stereo_camera_to_dict`).

Every reader raises :class:`~robostereo.errors.InputError` with one line naming the
file and the key.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from typing import Any

import yaml

from robostereo.errors import InputError, require_file, shown
from robostereo.geometry.camera import Camera, camera_from_dict, camera_to_dict
from robostereo.geometry.mapping_checks import check_keys
from robostereo.geometry.poses import Pose, pose_to_dict, scara_pose_from_dict
from robostereo.geometry.triangulation import StereoCamera
from robostereo.io.folder_yaml import folder_yaml_text
from robostereo.io.yaml_loading import load_yaml

__all__ = [
    "load_camera_yaml",
    "load_pose_yaml",
    "load_stereo_camera",
    "load_stereo_poses_yaml",
    "save_camera_yaml",
    "save_pose_yaml",
    "stereo_camera_from_dict",
    "stereo_camera_to_dict",
]

PathLike = str | os.PathLike[str]


def _read_yaml(path: str | os.PathLike[str], what: str) -> Any:
    name = os.fspath(path)
    try:
        with open(name, encoding="utf-8") as fh:
            text = fh.read()
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise InputError(f"{name}: cannot read {what} file ({reason})") from None
    try:
        return load_yaml(text, name)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{name}: not a valid YAML {what} file{where}") from None


def _write_yaml(data: Mapping[str, Any], path: str | os.PathLike[str], what: str) -> None:
    name = os.fspath(path)
    try:
        with open(name, "w", encoding="utf-8") as fh:
            fh.write(folder_yaml_text(data))
    except OSError as exc:
        raise InputError(f"{name}: cannot write {what} file ({exc.strerror})") from None


def load_camera_yaml(path: str | os.PathLike[str]) -> Camera:
    """Read a :class:`Camera` from a YAML file (keys as in :func:`camera_from_dict`).

    Raises
    ------
    InputError
        Unreadable file, invalid YAML, or a missing / bad key; the message names the
        file and the key.
    """
    return camera_from_dict(_read_yaml(path, "camera"), source=os.fspath(path))


def save_camera_yaml(camera: Camera, path: str | os.PathLike[str]) -> None:
    """Write a :class:`Camera` to a YAML file that :func:`load_camera_yaml` reads back."""
    _write_yaml(camera_to_dict(camera), path, "camera")


def load_pose_yaml(path: str | os.PathLike[str]) -> Pose:
    """Read a :class:`Pose` from a YAML file with keys ``x, y, z`` (mm), ``phi_deg``."""
    return scara_pose_from_dict(_read_yaml(path, "pose"), source=os.fspath(path))


def save_pose_yaml(pose: Pose, path: str | os.PathLike[str]) -> None:
    """Write a :class:`Pose` to a YAML file (``phi`` in degrees as ``phi_deg``)."""
    _write_yaml(pose_to_dict(pose), path, "pose")


def load_stereo_poses_yaml(path: str | os.PathLike[str]) -> tuple[Pose, Pose]:
    """Read the two viewpoints ``left:`` and ``right:`` (each a pose mapping) of a file."""
    name = os.fspath(path)
    data = _read_yaml(path, "poses")
    check_keys(data, ("left", "right"), name, "stereo pose file")
    out = []
    for side in ("left", "right"):
        if side not in data:
            raise InputError(f"{name}: missing key '{side}'")
        out.append(scara_pose_from_dict(data[side], source=f"{name}: {side}"))
    return out[0], out[1]


_PHYSICAL = {
    "focal_length_mm", "pixel_pitch_mm", "baseline_mm", "principal_point",
    "focal_length_uncertainty_mm", "baseline_uncertainty_mm", "disparity_uncertainty_px",
    "image_size", "grey_levels",
}
_PIXEL = {
    "fx", "fy", "cx", "cy", "doffs", "baseline_mm", "focal_uncertainty_px",
    "baseline_uncertainty_mm", "disparity_uncertainty_px",
}


def _number(source: str, key: str, v: Any) -> float:
    try:
        f = float(v)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{source}: {key} must be a finite number, got {shown(v)}") from None
    if not math.isfinite(f):
        raise InputError(f"{source}: {key} must be finite, got {shown(v)}")
    return f


def stereo_camera_from_dict(data: Mapping[str, Any], source: str = "camera") -> StereoCamera:
    """Build a :class:`StereoCamera` from a camera mapping (the camera YAML format).

    Two forms are accepted: physical (``focal_length_mm``, ``pixel_pitch_mm``,
    ``baseline_mm`` [, ``principal_point``, ``focal_length_uncertainty_mm``,
    ``baseline_uncertainty_mm``, ``disparity_uncertainty_px``]) and pixel
    (``fx``, ``fy``, ``baseline_mm`` [, ``cx``, ``cy``, ``doffs``,
    ``focal_uncertainty_px``, ``baseline_uncertainty_mm``, ``disparity_uncertainty_px``]).

    >>> stereo_camera_from_dict({"focal_length_mm": 25, "pixel_pitch_mm": [0.0172, 0.0137],
    ...                          "baseline_mm": 20}).baseline_mm
    20.0
    >>> stereo_camera_from_dict({"fx": 1000, "fy": 1000, "baseline_mm": -5})
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: camera: baseline_mm must be a finite number > 0, got -5.0
    """
    if not isinstance(data, Mapping):
        raise InputError(f"{source}: expected a mapping of camera parameters")
    try:
        if "fx" in data:
            unknown = set(data) - _PIXEL
            if unknown:
                raise InputError(f"{source}: unknown camera keys {sorted(unknown)}")
            kw = {k: _number(source, k, v) for k, v in data.items()}
            for k in ("fy", "baseline_mm"):
                if k not in kw:
                    raise InputError(f"{source}: missing camera key {k}")
            return StereoCamera(**kw)  # type: ignore[arg-type]
        unknown = set(data) - _PHYSICAL
        if unknown:
            raise InputError(f"{source}: unknown camera keys {sorted(unknown)}")
        for k in ("focal_length_mm", "pixel_pitch_mm", "baseline_mm"):
            if k not in data:
                raise InputError(f"{source}: missing camera key {k}")
        pitch = data["pixel_pitch_mm"]
        if not isinstance(pitch, list | tuple) or len(pitch) != 2:
            raise InputError(f"{source}: pixel_pitch_mm must be [horizontal, vertical]")
        pp = data.get("principal_point")

        def opt(key: str, default: float) -> float:
            return _number(source, key, data.get(key, default))

        if pp is not None and (not isinstance(pp, list | tuple) or len(pp) != 2):
            raise InputError(f"{source}: principal_point must be [cx, cy]")
        return StereoCamera.from_physical(
            _number(source, "focal_length_mm", data["focal_length_mm"]),
            (_number(source, "pixel_pitch_mm", pitch[0]),
             _number(source, "pixel_pitch_mm", pitch[1])),
            _number(source, "baseline_mm", data["baseline_mm"]),
            principal_point=None if pp is None else (
                _number(source, "principal_point", pp[0]),
                _number(source, "principal_point", pp[1])),
            focal_length_uncertainty_mm=opt("focal_length_uncertainty_mm", 0.01),
            baseline_uncertainty_mm=opt("baseline_uncertainty_mm", 0.01),
            disparity_uncertainty_px=opt("disparity_uncertainty_px", 1.0),
        )
    except InputError as e:
        msg = str(e)
        raise InputError(msg if msg.startswith(source) else f"{source}: {msg}") from None


def stereo_camera_to_dict(camera: StereoCamera) -> dict[str, float]:
    """The pixel form of the camera YAML format (round-trips through
    :func:`stereo_camera_from_dict`)."""
    out = {
        "fx": camera.fx, "fy": camera.fy, "baseline_mm": camera.baseline_mm,
        "doffs": camera.doffs, "focal_uncertainty_px": camera.focal_uncertainty_px,
        "baseline_uncertainty_mm": camera.baseline_uncertainty_mm,
        "disparity_uncertainty_px": camera.disparity_uncertainty_px,
    }
    if camera.cx is not None:
        out["cx"] = camera.cx
    if camera.cy is not None:
        out["cy"] = camera.cy
    return {k: float(v) for k, v in out.items()}


def load_stereo_camera(path: PathLike) -> StereoCamera:
    """Read a camera YAML file (see :func:`stereo_camera_from_dict`)."""
    p = require_file(path, "camera file")
    try:
        data = load_yaml(p.read_text(), str(p))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as e:
        raise InputError(f"{p}: cannot read camera YAML ({e.__class__.__name__})") from None
    return stereo_camera_from_dict(data, source=str(p))
