"""The camera and hand-eye file of ``robostereo handeye`` (``camera.yaml``, ``cell.yaml``).

:func:`save_handeye_yaml` writes an
:class:`~robostereo.robot.handeye.calibrate.EyeInHandCalibration` (its
:meth:`~robostereo.robot.handeye.calibrate.EyeInHandCalibration.to_dict` mapping: the
camera, ``T_flange_camera``, the residuals per view and per pair of views) or an
:class:`~robostereo.robot.handeye.eye_to_hand.EyeToHandCalibration` (``mode:
eye-to-hand``, the camera, ``base_camera`` = ``T_base_camera``, ``flange_board``, the
residuals); :func:`load_handeye_yaml` reads back the camera and ``T_flange_camera`` (as
``robostereo capture --handeye`` does), :func:`load_base_camera_yaml` the camera and
``T_base_camera`` (as ``robostereo rig --base-camera`` does).  :func:`view_advice_text`
is the file of ``robostereo handeye --advise``: the flange poses of four more views
that would pin the transform better (:mod:`~robostereo.robot.handeye.view_advice`).
"""

from __future__ import annotations

from typing import Any

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye.calibrate import EyeInHandCalibration
from robostereo.robot.handeye.eye_to_hand import EyeToHandCalibration
from robostereo.robot.handeye.view_advice import ViewAdvice

__all__ = [
    "handeye_yaml_text",
    "load_base_camera_yaml",
    "load_handeye_with_sigma",
    "load_handeye_yaml",
    "save_handeye_yaml",
    "view_advice_text",
]


def save_handeye_yaml(path: Any,
                      calibration: EyeInHandCalibration | EyeToHandCalibration) -> None:
    """Write ``camera.yaml``
    (:meth:`~robostereo.robot.handeye.calibrate.EyeInHandCalibration.to_dict`) atomically."""
    from robostereo.io import atomic_path

    text = handeye_yaml_text(calibration)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def handeye_yaml_text(calibration: EyeInHandCalibration | EyeToHandCalibration) -> str:
    """The text :func:`save_handeye_yaml` writes."""
    import yaml

    return yaml.safe_dump(calibration.to_dict(), sort_keys=False, default_flow_style=None)


def view_advice_text(advice: ViewAdvice) -> str:
    """The advice file: a comment, then :meth:`ViewAdvice.to_dict
    <robostereo.robot.handeye.view_advice.ViewAdvice.to_dict>` (``flange_poses`` in the
    pose form of ``views.yaml``, ready to send to the arm and to list beside the new
    views' images).

    Examples
    --------
    >>> import numpy as np
    >>> a = ViewAdvice(np.array([30.0]), np.array([0.05]), np.array([0.02]),
    ...                ((SE3.identity(),) * 4,), 0.08, 0.04, np.array([10.0, 12.0]))
    >>> print(view_advice_text(a).splitlines()[2])
    mode: eye-in-hand
    """
    import yaml

    head = ("# robostereo handeye --advise: four more views, tilted from the board's normal,\n"
            "# that would pin the hand-eye transform best (sigma: one standard deviation)\n")
    return head + yaml.safe_dump(advice.to_dict(), sort_keys=False, default_flow_style=None)


def _mapping(path: Any, what: str) -> tuple[Any, Any]:
    """The file's path and its parsed YAML (one line naming the file if unreadable)."""
    from pathlib import Path

    import yaml

    from robostereo.errors import require_file
    from robostereo.io.yaml_loading import load_yaml

    p = require_file(path, what)
    try:
        return p, load_yaml(Path(p).read_text(encoding="utf-8"), str(p))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise InputError(f"{p}: not a readable YAML file ({exc.__class__.__name__})") from None


def _calibration(p: Any, data: Any, key: str, other: str) -> tuple[Camera, SE3]:
    """The camera and the pose under `key` of a parsed ``robostereo handeye`` file."""
    from robostereo.geometry.camera import camera_from_dict
    from robostereo.geometry.poses import as_se3, pose_from_dict

    if isinstance(data, dict) and "camera" in data and other in data and key not in data:
        mode = "eye-to-hand" if other == "base_camera" else "eye-in-hand"
        raise InputError(f"{p}: an {mode} calibration ({other}), not the {key} this needs")
    if not isinstance(data, dict) or "camera" not in data or key not in data:
        raise InputError(f"{p}: expected the keys camera and {key} (robostereo handeye's "
                         "output)")
    camera = camera_from_dict(data["camera"], source=f"{p}: camera")
    return camera, as_se3(pose_from_dict(data[key], source=f"{p}: {key}"))


def load_handeye_yaml(path: Any) -> tuple[Camera, SE3]:
    """Read the camera and ``T_flange_camera`` of a ``robostereo handeye`` file."""
    p, data = _mapping(path, "hand-eye camera file")
    return _calibration(p, data, "hand_eye", "base_camera")


def load_handeye_with_sigma(path: Any) -> tuple[Camera, SE3, tuple[float, float] | None]:
    """:func:`load_handeye_yaml`'s camera and ``T_flange_camera``, and the file's
    ``hand_eye_sigma``: ``(translation_mm, rotation_deg)``, one standard deviation of
    the transform along its worst axes, or None when the file has none (unrefined, or
    written before it was reported).

    Raises
    ------
    InputError
        As :func:`load_handeye_yaml`, and ``hand_eye_sigma`` not two non-negative finite
        numbers.
    """
    import math

    p, data = _mapping(path, "hand-eye camera file")
    camera, hand_eye = _calibration(p, data, "hand_eye", "base_camera")
    sigma = data.get("hand_eye_sigma")
    if sigma is None:
        return camera, hand_eye, None
    try:
        mm, deg = float(sigma["translation_mm"]), float(sigma["rotation_deg"])
    except (TypeError, KeyError, ValueError):
        raise InputError(f"{p}: hand_eye_sigma must hold translation_mm and "
                         "rotation_deg") from None
    if not all(math.isfinite(v) and v >= 0 for v in (mm, deg)):
        raise InputError(f"{p}: hand_eye_sigma must be non-negative finite numbers, got "
                         f"{mm!r} mm and {deg!r} deg")
    return camera, hand_eye, (mm, deg)


def load_base_camera_yaml(path: Any) -> tuple[Camera, SE3]:
    """Read the camera and ``T_base_camera`` of a ``robostereo handeye --mode
    eye-to-hand`` file (``cell.yaml``)."""
    p, data = _mapping(path, "eye-to-hand camera file")
    return _calibration(p, data, "base_camera", "hand_eye")
