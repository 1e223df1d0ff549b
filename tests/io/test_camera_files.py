"""Tests for robostereo.io.cameras: camera and pose YAML files."""

from __future__ import annotations

import math

import pytest

from robostereo.errors import InputError
from robostereo.geometry.camera import SEED_CAMERA, Camera, camera_from_dict, camera_to_dict
from robostereo.geometry.poses import Pose, pose_from_dict
from robostereo.io.cameras import (
    load_camera_yaml,
    load_pose_yaml,
    load_stereo_poses_yaml,
    save_camera_yaml,
    save_pose_yaml,
)


def test_camera_yaml_round_trip(tmp_path):
    cam = Camera(
        focal_length_mm=16.0,
        pixel_pitch_mm=(0.0099, 0.0083),
        image_size=(640, 480),
        principal_point=(321.25, 236.5),
        grey_levels=256,
    )
    path = tmp_path / "cam.yaml"
    save_camera_yaml(cam, path)
    text = path.read_text()
    for key in ("focal_length_mm", "pixel_pitch_mm", "image_size", "principal_point",
                "grey_levels"):
        assert key in text
    assert load_camera_yaml(path) == cam
    assert camera_from_dict(camera_to_dict(SEED_CAMERA)) == SEED_CAMERA


def test_camera_yaml_handwritten_defaults(tmp_path):
    path = tmp_path / "cam.yaml"
    path.write_text(
        "focal_length_mm: 25\npixel_pitch_mm: [0.0172, 0.0137]\nimage_size: [509, 481]\n"
    )
    cam = load_camera_yaml(path)
    assert cam == SEED_CAMERA  # principal point defaults to the centre, 128 grey levels


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ("pixel_pitch_mm: [0.0172, 0.0137]\nimage_size: [509, 481]\n", "focal_length_mm"),
        ("focal_length_mm: .nan\npixel_pitch_mm: [0.0172, 0.0137]\nimage_size: [509, 481]\n",
         "focal_length_mm"),
        ("focal_length_mm: 25\npixel_pitch_mm: [-0.0172, 0.0137]\nimage_size: [509, 481]\n",
         "pixel_pitch_mm"),
        ("focal_length_mm: 25\npixel_pitch_mm: [0.0172]\nimage_size: [509, 481]\n",
         "pixel_pitch_mm"),
        ("focal_length_mm: 25\npixel_pitch_mm: [0.0172, 0.0137]\nimage_size: [509.5, 481]\n",
         "image_size"),
        ("focal_length_mm: 25\npixel_pitch_mm: [0.0172, 0.0137]\nimage_size: [509, 481]\n"
         "principal_point: [.nan, 3]\n", "principal_point"),
        ("focal_length_mm: 25\npixel_pitch_mm: [0.0172, 0.0137]\nimage_size: [509, 481]\n"
         "grey_levels: -3\n", "grey_levels"),
        ("focal_length_mm: '25'\npixel_pitch_mm: [0.0172, 0.0137]\nimage_size: [509, 481]\n",
         "focal_length_mm"),
        ("focal_length_mm: 25\npixel_pitch_mm: [0.0172, 0.0137]\nimage_size: [509, 481]\n"
         "focal_lenght_mm: 3\n", "focal_lenght_mm"),
    ],
)
def test_camera_yaml_errors_name_file_and_key(tmp_path, text, key):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(InputError) as info:
        load_camera_yaml(path)
    msg = str(info.value)
    assert str(path) in msg and key in msg and "\n" not in msg


def test_camera_yaml_unreadable_and_invalid(tmp_path):
    missing = tmp_path / "nope.yaml"
    with pytest.raises(InputError, match=r"nope\.yaml: cannot read camera file"):
        load_camera_yaml(missing)
    bad = tmp_path / "broken.yaml"
    bad.write_text("focal_length_mm: [25\n")
    with pytest.raises(InputError, match=r"broken\.yaml: not a valid YAML"):
        load_camera_yaml(bad)
    notmap = tmp_path / "list.yaml"
    notmap.write_text("- 1\n- 2\n")
    with pytest.raises(InputError, match=r"list\.yaml: a camera must be a mapping"):
        load_camera_yaml(notmap)


def test_pose_yaml_round_trip_degrees_in_file(tmp_path):
    pose = Pose(12.5, -40.0, 1000.0, math.radians(30.0))
    path = tmp_path / "pose.yaml"
    save_pose_yaml(pose, path)
    assert path.read_text() == "x: 12.5\ny: -40.0\nz: 1000.0\nphi_deg: 30.0\n"
    back = load_pose_yaml(path)
    assert back.position == pytest.approx(pose.position)
    assert back.phi == pytest.approx(pose.phi, abs=1e-15)


def test_pose_yaml_errors(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text("x: 1\ny: 2\nz: .nan\nphi_deg: 3\n")
    with pytest.raises(InputError, match=r"p.yaml: key 'z' must be a finite number"):
        load_pose_yaml(path)
    path.write_text("x: 1\ny: 2\nphi: 3\n")
    with pytest.raises(InputError, match=r"p.yaml: unknown key 'phi'"):
        load_pose_yaml(path)
    assert pose_from_dict({"x": 1, "y": 2, "z": 3}).phi == 0.0


def test_stereo_poses_yaml(tmp_path):
    path = tmp_path / "poses.yaml"
    path.write_text(
        "left: {x: -10, y: 0, z: 1000, phi_deg: 5}\nright: {x: 10, y: 0, z: 1000, phi_deg: 7}\n"
    )
    left, right = load_stereo_poses_yaml(path)
    assert (left.x, right.x) == (-10.0, 10.0)
    assert right.phi == pytest.approx(math.radians(7.0))
    path.write_text("left: {x: -10, y: 0, z: 1000}\n")
    with pytest.raises(InputError, match="missing key 'right'"):
        load_stereo_poses_yaml(path)
