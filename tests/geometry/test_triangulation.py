"""Tests for robostereo.geometry.triangulation: eq. 6-8 as corrected (the thesis, 3.6)
and the depth error bound (3.7, eq. 9)."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import Pose
from robostereo.geometry.triangulation import (
    StereoCamera,
    depth_error_bound,
    depth_from_disparity,
    triangulate,
)


def test_seed_worked_example_section_5_2():
    # D = 2.0 cm, s = 2.5 cm, x_r - x_l = 0.046 cm -> z about 108.7 cm, bound about 4.1 cm
    z = depth_from_disparity(2.0, 2.5, 0.046)
    assert z == pytest.approx(108.70, abs=0.01)
    bound = depth_error_bound(2.0, 2.5, 0.046, baseline_uncertainty=0.001,
                              focal_uncertainty=0.001, disparity_uncertainty=0.00172)
    # the seed's partial derivatives: dz/ds = 43.5 (printed 43.0), dz/dD = 54.3, and
    # D s / disp^2 = 2362.9
    assert 2.0 * 2.5 / 0.046**2 == pytest.approx(2362.9, abs=0.1)
    assert 2.5 / 0.046 == pytest.approx(54.3, abs=0.05)
    assert bound == pytest.approx(0.001 * 54.35 + 0.001 * 43.48 + 0.00172 * 2362.9, rel=1e-3)
    assert round(float(bound), 1) == 4.2 or round(float(bound), 1) == 4.1
    assert 4.0 < bound < 4.2


def test_generated_scene_triangulates_to_ground_truth(rng):
    # two views D apart along world X of a downward-looking camera, as on the robot
    cam = Camera()
    d = 20.0
    mid = np.array([300.0, 50.0, 1100.0])
    left = Pose(mid[0] - d / 2, mid[1], mid[2])
    right = Pose(mid[0] + d / 2, mid[1], mid[2])
    pts = np.column_stack([
        rng.uniform(250, 350, 200), rng.uniform(0, 100, 200), rng.uniform(0, 200, 200),
    ])
    uv_l, _ = cam.project(pts, left)
    uv_r, _ = cam.project(pts, right)
    assert np.allclose(uv_l[:, 1], uv_r[:, 1])          # rows are epipolar lines
    stereo = StereoCamera.from_physical(25.0, cam.pixel_pitch_mm, d)
    xyz, bound = triangulate(stereo, uv_l[:, 0], uv_r[:, 0], uv_l[:, 1], (cam.height, cam.width))
    # epipolar frame: origin mid-baseline, X = world X, Y = -world Y, Z = depth
    expected = np.column_stack([pts[:, 0] - mid[0], -(pts[:, 1] - mid[1]), mid[2] - pts[:, 2]])
    assert np.allclose(xyz, expected, atol=1e-8)
    assert np.all(bound > 0)
    # one pixel of disparity error moves z by less than the bound
    xyz2, _ = triangulate(stereo, uv_l[:, 0] + 1.0, uv_r[:, 0], uv_l[:, 1],
                          (cam.height, cam.width))
    assert np.all(np.abs(xyz2[:, 2] - xyz[:, 2]) <= bound)


def test_bound_terms_and_subpixel_uncertainty():
    stereo = StereoCamera.from_physical(disparity_uncertainty_px=0.2)
    d = stereo.fx * 20.0 / 1000.0
    _, b = triangulate(stereo, [254 + d / 2], [254 - d / 2], [240], (481, 509))
    # 0.01 * 25 / 0.5 + 0.01 * 20 / 0.5 + 0.2 * 0.0172 * 500 / 0.25
    assert b[0] == pytest.approx(0.5 + 0.4 + 0.2 * 0.0172 * 500 / 0.25, rel=1e-9)


def test_doffs_and_principal_point():
    stereo = StereoCamera(fx=1000.0, fy=1000.0, baseline_mm=100.0, cx=300.0, cy=200.0,
                          doffs=50.0)
    # a point at Z = 2000 mm straight ahead of the left camera (X = -D/2 from mid-baseline)
    xyz, _ = triangulate(stereo, [300.0], [300.0], [200.0], (400, 600))
    assert xyz[0].tolist() == pytest.approx([-50.0, 0.0, 2000.0])


def test_nonpositive_disparity_gives_nan():
    stereo = StereoCamera.from_physical()
    xyz, b = triangulate(stereo, [100.0, 100.0], [100.0, 105.0], [10, 10], (481, 509))
    assert np.isnan(xyz).all() and np.isnan(b).all()


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [
        ({"baseline_mm": 0.0}, "baseline_mm"),
        ({"baseline_mm": -20.0}, "baseline_mm"),
        ({"fx": float("nan")}, "fx"),
        ({"fy": -3.0}, "fy"),
        ({"disparity_uncertainty_px": -1.0}, "disparity_uncertainty_px"),
    ],
)
def test_bad_geometry_is_rejected(kwargs, word):
    base = {"fx": 1000.0, "fy": 1000.0, "baseline_mm": 20.0}
    base.update(kwargs)
    with pytest.raises(InputError, match=word):
        StereoCamera(**base)


def test_from_physical_rejects_nan_focal_length():
    with pytest.raises(InputError, match="focal_length_mm"):
        StereoCamera.from_physical(float("nan"))
