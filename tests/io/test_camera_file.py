"""Tests for robostereo.io.camera_file: one camera's OpenCV or ROS calibration file."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.io.camera_file import camera_from_entry, read_camera_file

K = np.array([[612.5, 0.0, 320.25], [0.0, 610.0, 241.5], [0.0, 0.0, 1.0]])
DIST = np.array([-0.12, 0.03, 0.001, -0.0005, 0.0])


def test_an_opencv_filestorage_camera_file_gives_its_k_and_distortion(tmp_path):
    path = tmp_path / "camera.yml"
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    fs.write("image_width", 640)
    fs.write("image_height", 480)
    fs.write("camera_matrix", K)
    fs.write("distortion_coefficients", DIST.reshape(5, 1))
    fs.release()
    cam = read_camera_file(path)
    assert cam.in_pixels
    assert np.allclose(cam.K, K, atol=1e-9)
    assert np.allclose(cam.distortion, DIST)
    assert cam.image_size == (640, 480)


def test_a_ros_camera_info_file_gives_its_k(tmp_path):
    path = tmp_path / "ost.yaml"
    path.write_text(
        "image_width: 640\nimage_height: 480\ncamera_name: wrist\ncamera_matrix:\n"
        "  rows: 3\n  cols: 3\n  data: [612.5, 0, 320.25, 0, 610, 241.5, 0, 0, 1]\n"
        "distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n"
        "  data: [-0.12, 0.03, 0.001, -0.0005, 0]\nrectification_matrix:\n  rows: 3\n"
        "  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n")
    cam = read_camera_file(path)
    assert np.allclose(cam.K, K) and cam.image_size == (640, 480)


def test_a_camera_file_with_k4_and_beyond_is_refused_naming_the_file(tmp_path):
    path = tmp_path / "ost.yaml"
    path.write_text(
        "image_width: 640\nimage_height: 480\ncamera_matrix: {rows: 3, cols: 3, data: "
        "[612.5, 0, 320.25, 0, 610, 241.5, 0, 0, 1]}\ndistortion_model: rational_polynomial\n"
        "distortion_coefficients: {rows: 1, cols: 8, data: [0.1, 0, 0, 0, 0, 0.2, 0, 0]}\n")
    with pytest.raises(InputError, match=r"ost.yaml.*k4"):
        read_camera_file(path)


def test_a_camera_entry_naming_a_missing_file_is_refused(tmp_path):
    with pytest.raises(InputError, match=r"capture.yaml: camera: 'nope.yaml'"):
        camera_from_entry("nope.yaml", tmp_path, "capture.yaml")
