"""Tests for robostereo.robot.capture.capture_keys: cameras in pixels, pose conventions,
the shared-scene check, in two-view and N-view folders."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import yaml

from robostereo.errors import InputError, PlausibilityWarning
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.capture.capture_folder import Capture, read_capture, write_capture
from robostereo.robot.views.viewpoints import ViewsCapture
from robostereo.robot.views.views_folder import read_views_capture, write_views_capture

W, H = 320, 240
K = [[400.0, 0.0, 159.5], [0.0, 400.0, 119.5], [0.0, 0.0, 1.0]]


def ring_poses(n: int = 3, radius: float = 600.0) -> list[SE3]:
    """Cameras on an arc 60 degrees wide looking at an object 600 mm from the world's
    origin, T_world_camera (read as world-to-camera, they look apart)."""
    centre = np.array([0.0, 0.0, -600.0])
    out = []
    for a in np.radians(np.linspace(-30.0, 30.0, n)):
        eye = centre + radius * np.array([np.sin(a), 0.3, -np.cos(a)])
        out.append(SE3.look_at(eye, centre, up=(0.0, -1.0, 0.0)))
    return out


def images(n: int) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(3)
    return tuple(rng.integers(0, 256, (H, W)).astype(np.uint8) for _ in range(n))


def views_yaml(tmp_path, camera, poses, **extra):
    cap = ViewsCapture(images(len(poses)), camera, tuple(poses), depth_range_mm=(450, 800),
                       bit_depth=8)
    d = write_views_capture(tmp_path / "cap", cap)
    data = yaml.safe_load((d / "capture.yaml").read_text())
    data.update(extra)
    return d, data


def rewrite(d, data):
    (d / "capture.yaml").write_text(yaml.safe_dump(data))


# ------------------------------------------------------------------ cameras in pixels

def test_a_camera_in_pixels_is_written_back_in_pixels_in_both_folders(tmp_path):
    cam = Camera.from_intrinsics(K, (W, H), grey_levels=256)
    d, data = views_yaml(tmp_path, cam, ring_poses())
    assert set(data["camera"]) == {"fx", "fy", "cx", "cy", "image_size", "grey_levels"}
    assert data["uncertainty"]["focal_px"] == 0.0
    back = read_views_capture(d)
    assert back.camera.in_pixels and np.allclose(back.camera.K, K)
    p = ring_poses(2)
    two = write_capture(tmp_path / "two", Capture(left=images(1)[0], right=images(1)[0],
                                                  camera=cam, pose_left=p[0], pose_right=p[1],
                                                  bit_depth=8, depth_range_mm=(450, 800)))
    assert "fx" in yaml.safe_load((two / "capture.yaml").read_text())["camera"]
    assert read_capture(two).camera.in_pixels


def test_a_camera_as_k_reads_as_the_same_camera_as_fx_fy_cx_cy(tmp_path):
    d, data = views_yaml(tmp_path, Camera.from_intrinsics(K, (W, H)), ring_poses())
    data["camera"] = {"K": K, "image_size": [W, H]}
    rewrite(d, data)
    assert np.allclose(read_views_capture(d).camera.K, K)


def test_a_camera_key_naming_an_opencv_file_is_read_in_a_views_folder(tmp_path):
    import cv2

    d, data = views_yaml(tmp_path, Camera.from_intrinsics(K, (W, H)), ring_poses())
    fs = cv2.FileStorage(str(d / "intrinsics.yml"), cv2.FILE_STORAGE_WRITE)
    fs.write("camera_matrix", np.array(K) * [[1.01], [1.01], [1]])
    fs.write("image_width", W)
    fs.write("image_height", H)
    fs.release()
    data["camera"] = "intrinsics.yml"
    rewrite(d, data)
    assert read_views_capture(d).camera.fx == pytest.approx(404.0)


def test_one_fx_in_pixels_gives_one_bound_whatever_mm_and_pitch_it_came_from(tmp_path):
    p = ring_poses(2)
    bounds = {}
    for f_mm, pitch in ((10.0, 0.025), (100.0, 0.25)):  # both 400 px
        phys = Camera(focal_length_mm=f_mm, pixel_pitch_mm=(pitch, pitch), image_size=(W, H))
        for form, cam in (("physical", phys), ("pixels", phys.in_pixel_form())):
            cap = Capture(left=images(1)[0], right=images(1)[0], camera=cam,
                          pose_left=p[0], pose_right=p[1], bit_depth=8,
                          depth_range_mm=(450, 800))
            d = write_capture(tmp_path / f"{form}{f_mm}", cap)
            sc = read_capture(d).stereo_camera()
            bounds[form, f_mm] = sc.focal_uncertainty_px
    # the physical form's default 0.01 mm is 0.4 px of a 10 mm lens, 0.04 px of 100 mm
    assert bounds["physical", 10.0] == pytest.approx(10 * bounds["physical", 100.0])
    assert bounds["pixels", 10.0] == bounds["pixels", 100.0] == 0.0


def test_a_focal_px_uncertainty_gives_the_bound_its_pixels(tmp_path):
    d, data = views_yaml(tmp_path, Camera.from_intrinsics(K, (W, H)), ring_poses(2))
    data["uncertainty"]["focal_px"] = 2.0
    rewrite(d, data)
    cap = read_views_capture(d)
    assert cap.pair(0, 1).stereo_camera().focal_uncertainty_px == pytest.approx(
        2.0 * cap.pair(0, 1).stereo_camera().fx / 400.0)
    assert yaml.safe_load(
        write_views_capture(tmp_path / "again", cap).joinpath("capture.yaml").read_text()
    )["uncertainty"]["focal_px"] == pytest.approx(2.0)


def test_a_focal_length_mm_uncertainty_is_refused_for_a_camera_in_pixels(tmp_path):
    d, data = views_yaml(tmp_path, Camera.from_intrinsics(K, (W, H)), ring_poses(2))
    data["uncertainty"] = {"focal_length_mm": 0.01}
    rewrite(d, data)
    with pytest.raises(InputError, match=r"capture.yaml: key 'uncertainty'.*focal_px"):
        read_views_capture(d)


# ------------------------------------------------------------------ pose conventions

def test_world_to_camera_extrinsics_read_as_the_camera_poses(tmp_path):
    poses = ring_poses()
    d, data = views_yaml(tmp_path, Camera.from_intrinsics(K, (W, H)), poses,
                         pose_convention="world_to_camera")
    for v, p in zip(data["views"], poses, strict=True):
        v["pose"] = {"matrix": p.inv().matrix.tolist()}
    data["views"][1]["pose"] = {"matrix": poses[1].matrix.tolist()}
    data["views"][1]["pose_convention"] = "camera_to_world"  # one view its own
    rewrite(d, data)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        back = read_views_capture(d)
    for a, b in zip(back.poses, poses, strict=True):
        assert np.allclose(a.matrix, b.matrix, atol=1e-9)


def test_world_to_camera_pasted_as_poses_warns_naming_the_view_and_the_key(tmp_path):
    poses = ring_poses()
    d, data = views_yaml(tmp_path, Camera.from_intrinsics(K, (W, H)), poses)
    for v, p in zip(data["views"], poses, strict=True):
        v["pose"] = {"matrix": p.inv().matrix.tolist()}
    rewrite(d, data)
    with pytest.warns(PlausibilityWarning, match="pose_convention: world_to_camera"):
        read_views_capture(d)


def test_a_two_view_folder_takes_pose_convention_too(tmp_path):
    p = ring_poses(2)
    cam = Camera.from_intrinsics(K, (W, H))
    d = write_capture(tmp_path / "two", Capture(left=images(1)[0], right=images(1)[0],
                                                camera=cam, pose_left=p[0], pose_right=p[1],
                                                bit_depth=8, depth_range_mm=(450, 800)))
    data = yaml.safe_load((d / "capture.yaml").read_text())
    data["pose_left"] = {"matrix": p[0].inv().matrix.tolist()}
    data["pose_right"] = {"matrix": p[1].inv().matrix.tolist()}
    rewrite(d, data)
    with pytest.warns(PlausibilityWarning, match="no view sees what another sees"):
        read_capture(d)
    data["pose_convention"] = "world_to_camera"
    rewrite(d, data)
    assert np.allclose(read_capture(d).pose_right.matrix, p[1].matrix, atol=1e-9)


def test_a_rotation_printed_with_six_decimals_is_taken_with_a_warning(tmp_path):
    poses = ring_poses()
    d, data = views_yaml(tmp_path, Camera.from_intrinsics(K, (W, H)), poses)
    printed = np.round(poses[2].matrix, 6)
    printed[:3, :3] += np.array([[4e-7, -4e-7, 0], [0, 4e-7, 0], [0, 0, -4e-7]])
    assert np.abs(printed[:3, :3].T @ printed[:3, :3] - np.eye(3)).max() > 1e-6
    data["views"][2]["pose"] = {"matrix": printed.tolist()}
    rewrite(d, data)
    with pytest.warns(PlausibilityWarning, match=r"views\[2\].*orthonormal"):
        back = read_views_capture(d)
    assert np.allclose(back.poses[2].rotation, poses[2].rotation, atol=5e-6)


def test_a_rotation_further_off_than_rounding_is_refused(tmp_path):
    d, data = views_yaml(tmp_path, Camera.from_intrinsics(K, (W, H)), ring_poses())
    m = np.array(data["views"][0]["pose"].get("matrix") or ring_poses()[0].matrix)
    m[0, 0] += 1e-4
    data["views"][0]["pose"] = {"matrix": m.tolist()}
    rewrite(d, data)
    with pytest.raises(InputError, match=r"views\[0\].*orthonormal"):
        read_views_capture(d)


def test_a_camera_file_the_folder_names_is_one_of_its_inputs(tmp_path):
    from robostereo.robot.views.views_folder import views_folder_files

    d, data = views_yaml(tmp_path, Camera.from_intrinsics(K, (W, H)), ring_poses())
    data["camera"] = "intrinsics.yml"
    rewrite(d, data)
    assert d / "intrinsics.yml" in views_folder_files(d)
