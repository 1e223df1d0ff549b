"""Tests for robostereo.robot.importers: IDR, MVSNet and COLMAP cameras to N-view
capture folders (small files written here, and DTU scan 24 where it is at hand)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from import_sources import (
    H,
    K,
    W,
    poses,
    projected,
    sphere_points,
    write_colmap,
    write_colmap_binary,
    write_idr,
    write_mvsnet,
)

from robostereo.errors import InputError
from robostereo.robot.importers import (
    parse_view_selection,
    read_colmap,
    read_idr,
    read_mvsnet,
    views_capture_from_imported,
)
from robostereo.robot.importers.imported_views import scaled_intrinsics
from robostereo.robot.views.views_folder import read_views_capture, write_views_capture

DTU = Path(os.environ.get("ROBOSTEREO_DTU", Path(__file__).parents[4] / "shared" / "data"
                          / "robot" / "dtu_scan24"))
# -------------------------------------------------------------------------- IDR

def test_idr_poses_reproject_as_the_projection_matrices(tmp_path):
    npz = write_idr(tmp_path)
    imported = read_idr(npz, tmp_path / "image")
    cap = views_capture_from_imported(imported)
    P = sphere_points()
    mats = np.load(npz)
    for k, pose in enumerate(cap.poses):
        px, z = cap.camera.project(P, pose)
        assert np.all(z > 0)
        assert np.abs(px - projected(P, mats[f"world_mat_{k}"][:3].astype(float))).max() < 0.1
    near, far = cap.depth_range_mm  # the 120 mm sphere 612 mm away
    assert 485 < near < 500 and 725 < far < 740


def test_idr_scale_halves_images_and_intrinsics_together(tmp_path):
    npz = write_idr(tmp_path)
    cap = views_capture_from_imported(read_idr(npz, tmp_path / "image"), scale=0.5,
                                      select=[2, 0])
    assert cap.camera.image_size == (W // 2, H // 2) and cap.images[0].shape == (H // 2, W // 2)
    P = sphere_points()
    full = projected(P, np.load(npz)["world_mat_2"][:3].astype(float))
    px, _ = cap.camera.project(P, cap.poses[0])
    assert np.abs(px - ((full + 0.5) * 0.5 - 0.5)).max() < 0.1
    assert cap.names == ("000002.png", "000000.png")


@pytest.mark.skipif(not (DTU / "cameras_sphere.npz").is_file(), reason="DTU scan 24 absent")
def test_dtu_scan24_imported_poses_reproject_within_a_tenth_of_a_pixel(tmp_path):
    imported = read_idr(DTU / "cameras_sphere.npz", DTU / "image")
    assert [v.key for v in imported.views] == ["0", "1", "2", "3", "4", "10", "21", "30"]
    cap = views_capture_from_imported(imported, scale=0.5)
    back = read_views_capture(write_views_capture(tmp_path / "cap", cap))
    mats = np.load(DTU / "cameras_sphere.npz")
    S = mats["scale_mat_0"].astype(float)
    P = S[:3, 3] + S[0, 0] * 0.8 * (np.random.default_rng(2).uniform(-1, 1, (2000, 3)) / 3**0.5)
    for k, view in enumerate(imported.views):
        full = projected(P, mats[f"world_mat_{view.key}"][:3].astype(float))
        px, z = back.camera.project(P, back.poses[k])
        assert np.all(z > 0)
        assert np.abs(px - ((full + 0.5) * 0.5 - 0.5)).max() < 0.1


# -------------------------------------------------------------------------- MVSNet

def test_mvsnet_extrinsics_are_inverted_and_intrinsics_scaled(tmp_path):
    d = write_mvsnet(tmp_path)
    imported = read_mvsnet(d, intrinsics_scale=4.0)
    assert [v.key for v in imported.views] == ["00000000", "00000001", "00000002"]
    assert imported.view_depths["00000001"] == (425.0, 425.0 + 2.5 * 191)
    cap = views_capture_from_imported(imported, select=parse_view_selection(
        "0,2", [v.key for v in imported.views]))
    assert np.allclose(cap.camera.K, K, atol=1e-5)
    for got, want in zip(cap.poses, (poses()[0], poses()[2]), strict=True):
        assert np.allclose(got.translation, want.translation, atol=1e-3)
        assert np.allclose(got.rotation, want.rotation, atol=1e-5)


def test_mvsnet_depth_max_is_taken_when_given(tmp_path):
    d = write_mvsnet(tmp_path, depth_line="425.0 2.5 128 800.0")
    assert read_mvsnet(d).view_depths["00000002"] == (425.0, 800.0)


def test_mvsnet_folder_without_cams_is_refused(tmp_path):
    with pytest.raises(InputError, match="no cams"):
        read_mvsnet(tmp_path)


# -------------------------------------------------------------------------- COLMAP

def test_colmap_principal_point_moves_half_a_pixel_to_ours(tmp_path):
    # COLMAP's (160, 120) is the centre of a 320 x 240 image: ours (159.5, 119.5)
    m = write_colmap(tmp_path, f"1 PINHOLE {W} {H} 500 505 160 120")
    cap = views_capture_from_imported(read_colmap(m, tmp_path / "images"))
    assert np.allclose(cap.camera.K, K)
    P = sphere_points()
    for got, want in zip(cap.poses, poses(), strict=True):
        assert np.allclose(got.matrix, want.matrix, atol=1e-6)
    near, far = cap.depth_range_mm  # points within 100 mm of a centre 600 mm away
    assert 470 < near < 560 and 640 < far < 730
    px, _ = cap.camera.project(P, cap.poses[1])
    want, _ = cap.camera.project(P, poses()[1])
    assert np.abs(px - want).max() < 1e-3


@pytest.mark.parametrize(("line", "dist"), [
    (f"1 SIMPLE_PINHOLE {W} {H} 500 160 120", ()),
    (f"1 RADIAL {W} {H} 500 160 120 -0.05 0.01", (-0.05, 0.01, 0.0, 0.0)),
    (f"1 OPENCV {W} {H} 500 500 160 120 -0.05 0.01 0.001 -0.001",
     (-0.05, 0.01, 0.001, -0.001)),
])
def test_colmap_camera_models_give_their_distortion(tmp_path, line, dist):
    cap = views_capture_from_imported(read_colmap(write_colmap(tmp_path, line),
                                                  tmp_path / "images"))
    assert cap.camera.distortion == tuple(dist)
    assert cap.camera.principal_point == (159.5, 119.5)


def test_a_binary_colmap_model_reads_as_its_text_model(tmp_path):
    m = write_colmap(tmp_path, f"1 OPENCV {W} {H} 500 505 160 120 -0.05 0.01 0.001 -0.001")
    text = read_colmap(m, tmp_path / "images")
    binary = read_colmap(write_colmap_binary(m), tmp_path / "images")
    assert [v.key for v in binary.views] == [v.key for v in text.views]
    for a, b in zip(binary.views, text.views, strict=True):
        assert np.array_equal(a.K, b.K) and a.distortion == b.distortion
        assert np.allclose(a.pose.matrix, b.pose.matrix, atol=1e-9)
    assert binary.view_depths.keys() == text.view_depths.keys()
    for k, rng in text.view_depths.items():
        assert binary.view_depths[k] == pytest.approx(rng)


def test_a_truncated_binary_colmap_file_is_refused_naming_it(tmp_path):
    b = write_colmap_binary(write_colmap(tmp_path, f"1 PINHOLE {W} {H} 500 505 160 120"))
    (b / "images.bin").write_bytes((b / "images.bin").read_bytes()[:-10])
    with pytest.raises(InputError, match=r"images.bin: ends inside a record"):
        read_colmap(b, tmp_path / "images")


def test_colmap_unknown_model_is_refused_naming_the_line(tmp_path):
    m = write_colmap(tmp_path, f"1 FISHEYE {W} {H} 500 160 120 0.1")
    with pytest.raises(InputError, match=r"cameras.txt: line 2: .*FISHEYE"):
        read_colmap(m, tmp_path / "images")


def test_views_that_are_not_one_camera_are_refused(tmp_path):
    d = write_mvsnet(tmp_path)
    text = (d / "cams" / "00000001_cam.txt").read_text().replace("125.0", "130.0", 1)
    (d / "cams" / "00000001_cam.txt").write_text(text)
    with pytest.raises(InputError, match="intrinsics differ"):
        views_capture_from_imported(read_mvsnet(d, intrinsics_scale=4.0))


def test_a_depth_range_is_required_where_the_data_has_none(tmp_path):
    d = write_mvsnet(tmp_path, depth_line="")
    with pytest.raises(InputError, match="--depth-range"):
        views_capture_from_imported(read_mvsnet(d, intrinsics_scale=4.0))
    cap = views_capture_from_imported(read_mvsnet(d, intrinsics_scale=4.0),
                                      depth_range_mm=(500.0, 800.0))
    assert cap.depth_range_mm == (500.0, 800.0)


def test_scaled_intrinsics_keep_the_image_edges():
    Ks = scaled_intrinsics(K, 0.5, 0.5)
    # the image's left edge, x = -0.5, stays at -0.5
    assert (-0.5 - K[0, 2]) / K[0, 0] == pytest.approx((-0.5 - Ks[0, 2]) / Ks[0, 0])


def test_depth_maps_of_another_aspect_ratio_are_refused() -> None:
    from robostereo.robot.importers.mvsnet import depth_on_image_grid

    full = depth_on_image_grid(np.arange(12.0).reshape(3, 4), (8, 6))
    assert full.shape == (6, 8) and full[5, 7] == 11.0 and full[1, 1] == 0.0
    with pytest.raises(InputError, match="the depth map is 4 x 5 pixels, not the image's "
                                         "8 x 6 scaled"):
        depth_on_image_grid(np.zeros((5, 4)), (8, 6))
