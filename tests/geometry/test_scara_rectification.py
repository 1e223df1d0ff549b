"""Tests for robostereo.geometry.scara_rectification: epipolar frames, rectification by theta."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.geometry.camera import SEED_CAMERA, Camera
from robostereo.geometry.poses import SE3, Pose
from robostereo.geometry.scara_rectification import (
    EpipolarGeometry,
    epipolar_to_image,
    image_to_epipolar,
    rectification_matrix,
    rectified_valid_mask,
    rectify_image,
)

CAM = SEED_CAMERA


def _world_points(rng: np.random.Generator, n: int, centre=(0.0, 0.0)) -> np.ndarray:
    """Points on and above the table (z in [0, 60] mm) near `centre`, in view from 1000 mm."""
    xy = rng.uniform(-120.0, 120.0, size=(n, 2)) + np.asarray(centre)
    z = rng.uniform(0.0, 60.0, size=(n, 1))
    return np.hstack([xy, z])


def test_alpha_theta_with_roll_known_values():
    left = Pose(100.0, 200.0, 1000.0, math.radians(60.0))
    right = Pose(110.0, 210.0, 1000.0, math.radians(50.0))
    g = EpipolarGeometry.from_poses(CAM, left, right)
    assert g.alpha == pytest.approx(math.radians(45.0))
    assert g.theta_l == pytest.approx(math.radians(15.0))
    assert g.theta_r == pytest.approx(math.radians(5.0))
    assert g.baseline_mm == pytest.approx(math.sqrt(200.0))
    assert g.origin == pytest.approx((105.0, 205.0, 1000.0))
    # theta wraps across +-180 degrees
    g2 = EpipolarGeometry.from_poses(
        CAM, Pose(0.0, 0.0, 1000.0, math.radians(179.0)),
        Pose(-20.0, -1e-12, 1000.0, math.radians(-179.0)),
    )
    assert g2.theta_l == pytest.approx(math.radians(-1.0), abs=1e-9)
    assert g2.theta_r == pytest.approx(math.radians(1.0), abs=1e-9)


def test_zero_baseline_rejected():
    with pytest.raises(InputError, match="baseline"):
        EpipolarGeometry.from_poses(CAM, Pose(5.0, 5.0, 1000.0), Pose(5.0, 5.0, 900.0, 0.3))


def test_epipolar_axes_and_round_trip():
    g = EpipolarGeometry.from_poses(
        CAM, Pose(0.0, 0.0, 1000.0, 0.2), Pose(0.0, 20.0, 1000.0, 0.25)
    )
    # baseline along world +Y: X = (0, 1, 0), Z = (0, 0, -1), Y = Z x X = (1, 0, 0)
    assert g.rotation == pytest.approx(np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1.0]]).T)
    assert g.origin == pytest.approx((0.0, 10.0, 1000.0))
    assert g.to_world([[10.0, 0.0, 0.0]]) == pytest.approx(np.array([[0.0, 20.0, 1000.0]]))
    assert g.to_world([[0.0, 3.0, 1000.0]]) == pytest.approx(np.array([[3.0, 10.0, 0.0]]))
    rng = np.random.default_rng(1)
    P = _world_points(rng, 50)
    assert g.to_world(g.from_world(P)) == pytest.approx(P, abs=1e-9)
    with pytest.raises(InputError, match=r"\(N, 3\)"):
        g.to_world(np.zeros((4, 2)))


@pytest.mark.parametrize("phi_deg, alpha_deg", [(0.0, 0.0), (30.0, 5.0), (-70.0, 20.0),
                                                 (170.0, -165.0), (90.0, 0.0)])
def test_point_map_equals_virtual_camera(phi_deg, alpha_deg):
    """A real view (yaw phi) mapped by image_to_epipolar is the view of yaw alpha."""
    rng = np.random.default_rng(7)
    P = _world_points(rng, 200, centre=(30.0, -20.0))
    real = Pose(35.0, -15.0, 1000.0, math.radians(phi_deg))
    virtual = Pose(35.0, -15.0, 1000.0, math.radians(alpha_deg))
    theta = math.radians(phi_deg - alpha_deg)
    uv_real, _ = CAM.project(P, real)
    uv_virtual, _ = CAM.project(P, virtual)
    assert np.abs(image_to_epipolar(uv_real, CAM, theta) - uv_virtual).max() < 1e-9
    assert np.abs(epipolar_to_image(uv_virtual, CAM, theta) - uv_real).max() < 1e-9
    back = epipolar_to_image(image_to_epipolar(uv_real, CAM, theta), CAM, theta)
    assert np.abs(back - uv_real).max() < 0.01
    if abs(theta) > 1e-3:
        # the opposite sign is wrong (the test can fail), and so is a plain pixel rotation
        assert np.abs(image_to_epipolar(uv_real, CAM, -theta) - uv_virtual).max() > 1.0
        c, s = math.cos(theta), math.sin(theta)
        pp = np.asarray(CAM.principal_point)
        naive = (uv_real - pp) @ np.array([[c, s], [-s, c]]).T + pp
        assert np.abs(naive - uv_virtual).max() > 1.0


def test_rectified_rows_agree_for_different_rolls():
    """Same world point: equal rectified row in left and right, disparity fx D / Z."""
    rng = np.random.default_rng(3)
    D, a = 20.0, math.radians(35.0)
    centre = np.array([400.0, 150.0])
    u = np.array([math.cos(a), math.sin(a)])
    cl, cr = centre - D / 2 * u, centre + D / 2 * u
    left = Pose(cl[0], cl[1], 1000.0, math.radians(61.0))
    right = Pose(cr[0], cr[1], 1000.0, math.radians(58.5))
    g = EpipolarGeometry.from_poses(CAM, left, right)
    P = _world_points(rng, 300, centre=centre)
    ul = g.to_rectified(CAM.project(P, left)[0], "left")
    ur = g.to_rectified(CAM.project(P, right)[0], "right")
    assert np.abs(ul[:, 1] - ur[:, 1]).max() < 1e-9
    depth = 1000.0 - P[:, 2]
    assert ul[:, 0] - ur[:, 0] == pytest.approx(CAM.fx * D / depth, abs=1e-9)
    # without rectification the rows disagree by many pixels
    raw_l, raw_r = CAM.project(P, left)[0], CAM.project(P, right)[0]
    assert np.abs(raw_l[:, 1] - raw_r[:, 1]).max() > 5.0
    # lift: triangulate in the epipolar frame (eq. 6-8 in pixels) and go back to the world
    disp = ul[:, 0] - ur[:, 0]
    Z = CAM.fx * D / disp
    X = (ul[:, 0] - CAM.principal_point[0]) * Z / CAM.fx - D / 2
    Y = (ul[:, 1] - CAM.principal_point[1]) * Z / CAM.fy
    assert g.to_world(np.column_stack([X, Y, Z])) == pytest.approx(P, abs=1e-8)


def test_point_map_shape_checked():
    with pytest.raises(InputError, match=r"\(N, 2\)"):
        image_to_epipolar(np.zeros((3, 3)), CAM, 0.1)
    assert rectification_matrix(CAM, 0.3)[2] == pytest.approx([0.0, 0.0, 1.0])


def _render_plane(camera: Camera, pose: Pose, texture) -> np.ndarray:
    """Image of the textured plane z = 0 (analytic, no interpolation)."""
    w, h = camera.image_size
    xs, ys = np.meshgrid(np.arange(w, dtype=float), np.arange(h, dtype=float))
    uv = np.column_stack([xs.ravel(), ys.ravel()])
    P = camera.backproject(uv, np.full(len(uv), pose.z), pose)
    return texture(P[:, 0], P[:, 1]).reshape(h, w)


def test_rectified_image_is_virtual_camera_image():
    def texture(X, Y):
        return 60.0 + 25.0 * np.sin(X / 3.0) * np.cos(Y / 4.0) + 15.0 * np.sin((X + Y) / 5.0)

    phi, alpha = math.radians(40.0), math.radians(12.0)
    real = Pose(10.0, 5.0, 1000.0, phi)
    virtual = Pose(10.0, 5.0, 1000.0, alpha)
    img = _render_plane(CAM, real, texture)
    expect = _render_plane(CAM, virtual, texture)
    rect = rectify_image(img, CAM, phi - alpha)
    valid = rectified_valid_mask(CAM, phi - alpha)
    assert np.isnan(rect[~valid]).all() and np.isfinite(rect[valid]).all()
    assert 0.6 < valid.mean() < 0.95  # a 28-degree turn cuts the corners
    err = np.abs(rect - expect)[valid]
    assert err.mean() < 0.2 and np.percentile(err, 99) < 1.0
    # the wrong sign is far off
    wrong = rectify_image(img, CAM, alpha - phi)
    ok = valid & rectified_valid_mask(CAM, alpha - phi)
    assert np.abs(wrong - expect)[ok].mean() > 5.0


@pytest.mark.parametrize("interpolation", ["cubic", "linear"])
def test_warped_dot_moves_as_point_map_says(interpolation):
    theta = math.radians(-23.0)
    h, w = CAM.height, CAM.width
    # a single bright pixel
    dot = np.zeros((h, w), dtype=np.uint8)
    dot[100, 380] = 127
    rect = rectify_image(dot, CAM, theta, interpolation=interpolation, fill_value=0.0)
    expect = image_to_epipolar([[380.0, 100.0]], CAM, theta)[0]
    i, j = np.unravel_index(np.argmax(rect), rect.shape)
    assert abs(j - expect[0]) <= 0.75 and abs(i - expect[1]) <= 0.75
    # a Gaussian blob at a sub-pixel position: its centroid maps exactly (affine map)
    x0, y0 = 141.3, 352.8
    xs, ys = np.meshgrid(np.arange(w, dtype=float), np.arange(h, dtype=float))
    blob = 100.0 * np.exp(-((xs - x0) ** 2 + (ys - y0) ** 2) / (2 * 2.5**2))
    rect = rectify_image(blob, CAM, theta, interpolation=interpolation, fill_value=0.0)
    centroid = np.array([(rect * xs).sum(), (rect * ys).sum()]) / rect.sum()
    expect = image_to_epipolar([[x0, y0]], CAM, theta)[0]
    assert np.abs(centroid - expect).max() < 0.03


def test_rectify_image_checks_input():
    with pytest.raises(InputError, match="shape"):
        rectify_image(np.zeros((10, 10)), CAM, 0.1)
    with pytest.raises(InputError, match="interpolation"):
        rectify_image(np.zeros((CAM.height, CAM.width)), CAM, 0.1, interpolation="area")
    img = np.full((CAM.height, CAM.width), 7.0)
    out = rectify_image(img, CAM, math.pi / 2)
    assert np.isnan(out[0, 0]) and out[240, 254] == pytest.approx(7.0)
    assert out.dtype == np.float64


def test_epipolar_frame_of_plain_se3_poses_looking_down() -> None:
    left, right = Pose(-12.0, 3.0, 950.0, 0.25), Pose(9.0, -4.0, 950.0, 0.2)
    g = EpipolarGeometry.from_poses(CAM, left, right)
    assert EpipolarGeometry.from_poses(CAM, left, right).pose_left is left  # Poses kept as given
    plain = EpipolarGeometry.from_poses(CAM, SE3(left.rotation, left.position),
                                        SE3(right.rotation, right.position))
    assert plain.alpha == pytest.approx(g.alpha, abs=1e-12)
    assert plain.theta_l == pytest.approx(g.theta_l, abs=1e-9)
    assert plain.theta_r == pytest.approx(g.theta_r, abs=1e-9)
    assert plain.baseline_mm == pytest.approx(g.baseline_mm, abs=1e-9)
    tilted = SE3.look_at([0.0, -400.0, 900.0], [0.0, 0.0, 0.0])
    with pytest.raises(InputError, match="straight down"):
        EpipolarGeometry.from_poses(CAM, tilted, right)
