"""Tests for robostereo.geometry.camera: the pinhole camera and its mapping form."""

from __future__ import annotations

import math

import pytest

from robostereo.errors import InputError
from robostereo.geometry.camera import (
    SEED_CAMERA,
    Camera,
    wrap_angle,
)
from robostereo.geometry.poses import Pose

CAM = SEED_CAMERA


def test_seed_camera_intrinsics_known_values():
    assert CAM.fx == pytest.approx(25.0 / 0.0172)
    assert CAM.fy == pytest.approx(25.0 / 0.0137)
    assert CAM.principal_point == (254.0, 240.0)
    # a point 10 mm right of the axis, 1000 mm down: x = cx + fx * 10 / 1000
    uv, z = CAM.project([[10.0, 0.0, 0.0]], Pose(0.0, 0.0, 1000.0, 0.0))
    assert uv[0] == pytest.approx([254.0 + CAM.fx * 0.01, 240.0])
    assert z[0] == pytest.approx(1000.0)


def test_grey_levels_validated():
    with pytest.raises(InputError, match="grey_levels"):
        Camera(grey_levels=1)
    with pytest.raises(InputError, match="grey_levels"):
        Camera(grey_levels=True)


def test_wrap_angle():
    assert wrap_angle(math.radians(358.0)) == pytest.approx(math.radians(-2.0))
    assert wrap_angle(-math.pi) == pytest.approx(math.pi)
    assert wrap_angle(0.25) == 0.25


def test_distortion_that_folds_the_image_or_cannot_be_inverted_is_refused(tmp_path):
    import pytest

    from robostereo.errors import InputError
    from robostereo.io.cameras import load_camera_yaml

    base = ("focal_length_mm: 25\npixel_pitch_mm: [0.0172, 0.0137]\n"
            "image_size: [509, 481]\n")
    for k, why in (([-10.0, 0, 0, 0, 0], "folds the image over"),
                   ([50.0, 0, 0, 0, 0], "cannot be inverted over the image")):
        f = tmp_path / "cam.yaml"
        f.write_text(base + f"distortion: {k}\n")
        with pytest.raises(InputError, match=rf"^{f}: .*{why}"):
            load_camera_yaml(f)
    # lens-like values, strong barrel included, are accepted
    for k in ([-0.3, 0.1, 0.001, -0.002, 0.0], [-3.0, 0, 0, 0, 0], [0.3, 0, 0, 0, 0]):
        f.write_text(base + f"distortion: {k}\n")
        assert load_camera_yaml(f).distortion
