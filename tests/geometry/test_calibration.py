"""Tests for robostereo.geometry.calibration: a calibrated rig from camera poses."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from robostereo.geometry.calibration import StereoCalibration
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import Pose


def test_from_poses_matches_camera_projection() -> None:
    cam = Camera()
    left, right = Pose(-25.0, 3.0, 900.0, 0.05), Pose(35.0, -2.0, 905.0, -0.04)
    c = StereoCalibration.from_poses(cam, left, right)
    P = np.array([[10.0, 20.0, 0.0], [-40.0, 15.0, 60.0]])
    uv_r, _ = cam.project(P, right)
    x_left = (P - left.position) @ left.rotation  # left camera frame
    proj, _ = cv2.projectPoints(x_left, cv2.Rodrigues(c.R)[0], c.T, c.K2, c.D2)
    np.testing.assert_allclose(proj.reshape(-1, 2), uv_r, atol=1e-9)
    assert c.baseline_mm == pytest.approx(np.linalg.norm(left.position - right.position))
