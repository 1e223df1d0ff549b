"""Tests for robostereo.io: the package keeps every name of the old io module."""

from __future__ import annotations

import robostereo.io as io
from robostereo.io.calibration_files import read_calibration
from robostereo.io.images import load_image


def test_io_package_keeps_the_names_of_the_old_module() -> None:
    old = {"atomic_outputs", "atomic_path", "check_outputs", "load_image", "load_stereo_camera",
           "read_folder_yaml", "stereo_camera_from_dict", "stereo_camera_to_dict", "write_csv",
           "write_image_folder", "write_ply"}
    assert old <= set(io.__all__)
    assert all(callable(getattr(io, name)) for name in io.__all__)
    assert io.load_image is load_image
    assert io.read_calibration is read_calibration
