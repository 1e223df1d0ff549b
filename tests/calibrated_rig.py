"""A synthetic calibrated stereo rig, shared by the calibration tests of geometry and io."""

from __future__ import annotations

import cv2
import numpy as np

from robostereo.geometry.calibration import StereoCalibration

W, H = 640, 480
K1 = np.array([[820.0, 0.0, 330.0], [0.0, 815.0, 245.0], [0.0, 0.0, 1.0]])
K2 = np.array([[810.0, 0.0, 315.0], [0.0, 812.0, 238.0], [0.0, 0.0, 1.0]])
D1 = np.array([-0.12, 0.05, 0.001, -0.0005, 0.0])
D2 = np.array([-0.10, 0.03, -0.0008, 0.0004, 0.0])
R = cv2.Rodrigues(np.deg2rad([1.5, -3.0, 2.0]).reshape(3, 1))[0]
T = np.array([-60.0, 0.5, 1.0])  # mm


def synthetic_calibration() -> StereoCalibration:
    """The rig above: distorted cameras, a small rotation, a 60 mm baseline."""
    return StereoCalibration(K1, D1, K2, D2, R, T, (W, H), source="synthetic")
