"""Tests for robostereo.geometry.calibrated_rectification: OpenCV rectification, point maps."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from calibrated_rig import D1, D2, K1, K2, H, R, T, W, synthetic_calibration

from robostereo.errors import InputError
from robostereo.geometry.calibrated_rectification import (
    check_image_size,
    original_to_rectified,
    points_in_left_camera,
    rectified_to_original,
    rectify_images,
    rectify_stereo,
    triangulate_rectified,
)
from robostereo.geometry.calibration import StereoCalibration


@pytest.fixture(scope="module")
def calib() -> StereoCalibration:
    return synthetic_calibration()


@pytest.fixture(scope="module")
def rect(calib: StereoCalibration):
    return rectify_stereo(calib)


def test_check_image_size(calib: StereoCalibration) -> None:
    check_image_size(calib, (H, W), "a.png")
    check_image_size(calib, (H, W, 3), "a.png")
    with pytest.raises(InputError, match=r"^b\.png: image is 480 x 640 \(W x H\)"):
        check_image_size(calib, (W, H), "b.png")


def _scene_points(rng: np.random.Generator, n: int = 200) -> np.ndarray:
    z = rng.uniform(400.0, 3000.0, n)
    x = rng.uniform(-0.3, 0.3, n) * z
    y = rng.uniform(-0.22, 0.22, n) * z
    return np.column_stack([x, y, z])


def _project(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    pl, _ = cv2.projectPoints(points, np.zeros(3), np.zeros(3), K1, D1)
    pr, _ = cv2.projectPoints(points, cv2.Rodrigues(R)[0], T, K2, D2)
    return pl.reshape(-1, 2), pr.reshape(-1, 2)


@pytest.mark.parametrize("zero_disparity", [True, False])
def test_rectified_rows_and_depth(calib: StereoCalibration, zero_disparity: bool) -> None:
    rect = rectify_stereo(calib, zero_disparity=zero_disparity)
    rng = np.random.default_rng(7)
    X = _scene_points(rng)
    pl, pr = _project(X)
    inside = (pl[:, 0] > 0) & (pl[:, 0] < W - 1) & (pl[:, 1] > 0) & (pl[:, 1] < H - 1)
    inside &= (pr[:, 0] > 0) & (pr[:, 0] < W - 1) & (pr[:, 1] > 0) & (pr[:, 1] < H - 1)
    assert inside.sum() > 100
    X, pl, pr = X[inside], pl[inside], pr[inside]
    ql, qr = original_to_rectified(pl, rect, "left"), original_to_rectified(pr, rect, "right")
    assert np.abs(ql[:, 1] - qr[:, 1]).max() < 0.01  # same rows
    d = ql[:, 0] - qr[:, 0]
    assert np.all(d > 0)
    z_rect = (X @ rect.R1.T)[:, 2]
    if zero_disparity:
        assert rect.cx_left == rect.cx_right
        np.testing.assert_allclose(rect.fx * rect.baseline_mm / d, z_rect, rtol=1e-4)
    np.testing.assert_allclose(rect.depth_from_disparity(d), z_rect, rtol=1e-4)
    assert rect.baseline_mm == pytest.approx(calib.baseline_mm, rel=1e-9)
    # full triangulation back to the original left camera frame
    X_back = points_in_left_camera(triangulate_rectified(ql, d, rect), rect)
    np.testing.assert_allclose(X_back, X, rtol=1e-4, atol=0.05)


def test_point_maps_round_trip(rect) -> None:
    xs, ys = np.meshgrid(np.linspace(0, W - 1, 17), np.linspace(0, H - 1, 13))
    pts = np.column_stack([xs.ravel(), ys.ravel()])
    for which in ("left", "right"):
        back = rectified_to_original(original_to_rectified(pts, rect, which), rect, which)
        assert np.abs(back - pts).max() < 0.01
        # and the other way, starting in the rectified image
        fwd = original_to_rectified(rectified_to_original(pts, rect, which), rect, which)
        assert np.abs(fwd - pts).max() < 0.01


def test_point_maps_agree_with_remap_tables(rect) -> None:
    ij = np.array([[0, 0], [100, 37], [479, 639], [240, 320], [13, 600]])
    pts = ij[:, ::-1].astype(float)  # (x, y) = (j, i)
    for which, (mx, my) in (("left", rect.map_left), ("right", rect.map_right)):
        orig = rectified_to_original(pts, rect, which)
        table = np.column_stack([mx[ij[:, 0], ij[:, 1]], my[ij[:, 0], ij[:, 1]]])
        np.testing.assert_allclose(orig, table, atol=2e-3)


def test_rectify_images_samples_the_right_place(rect) -> None:
    yy, xx = np.mgrid[0:H, 0:W].astype(np.float64)
    left = 0.25 * xx + 0.5 * yy  # a linear ramp: bilinear interpolation is exact on it
    right = 0.5 * xx - 0.25 * yy + 200.0
    lr, rr = rectify_images(rect, left, right)
    assert lr.dtype == np.float64 and lr.shape == (H, W)
    x, y = rect.roi_left[0] + 50, rect.roi_left[1] + 40
    ox, oy = rectified_to_original([[x, y]], rect, "left")[0]
    assert lr[y, x] == pytest.approx(0.25 * ox + 0.5 * oy, abs=0.01)
    x, y = rect.roi_right[0] + 200, rect.roi_right[1] + 120
    ox, oy = rectified_to_original([[x, y]], rect, "right")[0]
    assert rr[y, x] == pytest.approx(0.5 * ox - 0.25 * oy + 200.0, abs=0.01)


def test_rectify_images_dtypes(rect) -> None:
    rng = np.random.default_rng(3)
    u8 = rng.integers(0, 256, (H, W, 3), dtype=np.uint8)
    a, b = rectify_images(rect, u8, u8, interpolation="cubic")
    assert a.dtype == np.uint8 and a.shape == (H, W, 3) and b.dtype == np.uint8
    u16 = rng.integers(0, 65536, (H, W), dtype=np.uint16)
    a, _ = rectify_images(rect, u16, u16)
    assert a.dtype == np.uint16
    f = rng.uniform(0.0, 1.0, (H, W))
    a, _ = rectify_images(rect, f, f, interpolation="cubic")
    assert a.dtype == np.float64 and a.min() >= 0.0 and a.max() <= f.max()
    i32 = rng.integers(-(2**31), 2**31 - 1, (H, W), dtype=np.int32)
    a, _ = rectify_images(rect, i32, i32, interpolation="cubic")
    assert a.dtype == np.int32
    with pytest.raises(InputError, match=r"^left: image is 320 x 480"):
        rectify_images(rect, u8[:, :320], u8)
    with pytest.raises(InputError, match="interpolation must be"):
        rectify_images(rect, u8, u8, interpolation="lanczos")  # type: ignore[arg-type]


def test_identity_rig_rectification() -> None:
    K = np.array([[800.0, 0, 319.5], [0, 800.0, 239.5], [0, 0, 1]])
    c = StereoCalibration(K, None, K, None, np.eye(3), [-60.0, 0, 0], (W, H))
    r = rectify_stereo(c)
    np.testing.assert_allclose(r.R1, np.eye(3), atol=1e-12)
    yy, xx = np.mgrid[0:H, 0:W]
    np.testing.assert_allclose(r.map_left[0], xx, atol=1e-3)
    np.testing.assert_allclose(r.map_left[1], yy, atol=1e-3)
    # a point 1200 mm away at x = 100 mm: d = f B / Z = 40 px
    ql = original_to_rectified([[319.5 + 800 * 100 / 1200, 239.5]], r, "left")
    qr = original_to_rectified([[319.5 + 800 * 40 / 1200, 239.5]], r, "right")
    assert ql[0, 0] - qr[0, 0] == pytest.approx(40.0, abs=1e-6)
