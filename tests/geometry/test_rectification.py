"""Tests for robostereo.geometry.rectification: the interface the three rectifications share."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.geometry.calibrated_rectification import rectify_stereo
from robostereo.geometry.calibration import StereoCalibration
from robostereo.geometry.camera import Camera
from robostereo.geometry.pose_rectification import GeneralEpipolarGeometry
from robostereo.geometry.poses import SE3, Pose
from robostereo.geometry.rectification import Rectifier, maps_valid_mask
from robostereo.geometry.scara_rectification import EpipolarGeometry, rectified_valid_mask

CAM = Camera(image_size=(160, 120), pixel_pitch_mm=(0.02, 0.02))


def _scara() -> EpipolarGeometry:
    return EpipolarGeometry.from_poses(CAM, Pose(-15.0, 0.0, 900.0, 0.2),
                                       Pose(15.0, 5.0, 900.0, 0.1))


def _general() -> GeneralEpipolarGeometry:
    a = SE3.look_at([-15.0, -400.0, 900.0], [0.0, 0.0, 0.0])
    b = SE3.look_at([15.0, -390.0, 905.0], [0.0, 0.0, 0.0])
    return GeneralEpipolarGeometry.from_poses(CAM, a, b)


def _calibrated():
    K = CAM.K
    D = [-0.1, 0.02, 0.0, 0.0, 0.0]
    c = StereoCalibration(K, D, K, D, np.eye(3), [-40.0, 0.0, 0.0], CAM.image_size)
    return rectify_stereo(c)


RECTIFIERS = {"scara": _scara, "general": _general, "calibrated": _calibrated}


@pytest.mark.parametrize("kind", sorted(RECTIFIERS))
def test_each_rectification_is_a_rectifier(kind: str) -> None:
    assert isinstance(RECTIFIERS[kind](), Rectifier)


def test_a_camera_is_not_a_rectifier() -> None:
    assert not isinstance(CAM, Rectifier)


@pytest.mark.parametrize("kind", sorted(RECTIFIERS))
@pytest.mark.parametrize("side", ["left", "right"])
def test_points_round_trip_through_the_rectified_image(kind: str, side: str) -> None:
    r = RECTIFIERS[kind]()
    p = np.array([[40.0, 30.0], [80.0, 60.0], [120.0, 90.0]])
    q = r.to_rectified(p, side)
    assert q.shape == (3, 2)
    np.testing.assert_allclose(r.from_rectified(q, side), p, atol=1e-3)


@pytest.mark.parametrize("kind", sorted(RECTIFIERS))
def test_rectify_and_valid_mask_have_the_rectified_frames_shape(kind: str) -> None:
    """The image's shape, except for general poses, whose frame holds both views."""
    r = RECTIFIERS[kind]()
    w, h = CAM.image_size
    if isinstance(r, GeneralEpipolarGeometry):
        w, h = r.size_rect
    img = np.random.default_rng(0).uniform(0.0, 255.0, CAM.image_size[::-1])
    for side in ("left", "right"):
        mask = r.valid_mask(side)
        assert mask.shape == (h, w) and mask.dtype == np.bool_ and mask.any()
        assert r.rectify(img, side).shape == (h, w)


@pytest.mark.parametrize("kind", sorted(RECTIFIERS))
def test_side_is_checked(kind: str) -> None:
    from robostereo.errors import InputError

    with pytest.raises(InputError, match="side"):
        RECTIFIERS[kind]().valid_mask("middle")


def test_thin_methods_delegate_to_the_existing_functions() -> None:
    g = _scara()
    assert np.array_equal(g.valid_mask("right"), rectified_valid_mask(CAM, g.theta_r))
    r = _calibrated()
    mx, my = r.map_left
    assert np.array_equal(r.valid_mask("left"), maps_valid_mask(mx, my, CAM.image_size))
    img = np.arange(CAM.width * CAM.height, dtype=float).reshape(CAM.height, CAM.width)
    from robostereo.geometry.calibrated_rectification import rectify_images

    left, right = rectify_images(r, img, img, interpolation="cubic")
    assert np.array_equal(r.rectify(img, "left", interpolation="cubic"), left)
    assert np.array_equal(r.rectify(img, "right", interpolation="cubic"), right)
