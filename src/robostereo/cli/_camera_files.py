"""The camera files the commands read: a camera YAML, ``robostereo handeye``'s camera file,
or ``match``'s stereo camera YAML (``handeye --intrinsics``, ``plan --camera``)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from robostereo.errors import require_file

__all__ = ["load_any_camera"]


def load_any_camera(path: Path) -> tuple[Any, dict[str, float]]:
    """The camera of a camera YAML, of ``robostereo handeye``'s camera file or of
    ``match``'s stereo camera YAML; with the eq. 9 uncertainties that file gives.

    A stereo camera YAML (keys ``fx``/``fy`` or ``baseline_mm``) gives a camera of its
    focal length in pixels (a nominal 1 mm lens over pixels of ``1/fx`` mm, so the
    focal-length uncertainty keeps its ratio) and, without ``image_size``, no image
    width to bound the disparities by."""
    import yaml

    from robostereo.geometry.camera import Camera, camera_from_dict
    from robostereo.io.cameras import load_camera_yaml, stereo_camera_from_dict
    from robostereo.io.yaml_loading import load_yaml

    require_file(path, "camera file")
    try:
        data = load_yaml(path.read_text(encoding="utf-8"), str(path))
    except (OSError, UnicodeDecodeError, yaml.YAMLError):
        data = None
    if isinstance(data, dict) and "camera" in data:
        return camera_from_dict(data["camera"], source=f"{path}: camera"), {}
    if isinstance(data, dict) and ("fx" in data or "baseline_mm" in data):
        sc = stereo_camera_from_dict(data, source=str(path))
        size = data.get("image_size")
        known = isinstance(size, list | tuple) and len(size) == 2
        cam = Camera(focal_length_mm=1.0, pixel_pitch_mm=(1.0 / sc.fx, 1.0 / sc.fy),
                     image_size=(int(size[0]), int(size[1])) if known else (5, 5))
        extra: dict[str, float] = {
            "baseline_uncertainty_mm": sc.baseline_uncertainty_mm,
            "focal_length_uncertainty_mm": sc.focal_uncertainty_px / sc.fx}
        if not known:
            extra["max_disparity_px"] = math.inf
        return cam, extra
    return load_camera_yaml(path), {}
