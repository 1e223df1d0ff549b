"""Tests for robostereo.cli.import_command: robostereo import idr / mvsnet / colmap."""

from __future__ import annotations

import numpy as np
import yaml
from import_sources import K, poses, write_colmap, write_idr, write_mvsnet

from robostereo.cli import main
from robostereo.robot.views.views_folder import read_views_capture


def test_import_mvsnet_writes_a_views_folder_that_reads_back(tmp_path, capsys):
    d = write_mvsnet(tmp_path)
    out = tmp_path / "cap"
    assert main(["import", "mvsnet", str(d), "--intrinsics-scale", "4", "--views", "0,1",
                 "--out", str(out)]) == 0
    cap = read_views_capture(out)
    assert len(cap) == 2 and np.allclose(cap.camera.K, K, atol=1e-5)
    assert cap.depth_range_mm == (425.0, 425.0 + 2.5 * 191)
    assert np.allclose(cap.poses[1].translation, poses()[1].translation, atol=1e-3)
    assert "2 views of mvsnet" in capsys.readouterr().out


def test_import_idr_scales_and_writes_pixels(tmp_path):
    npz = write_idr(tmp_path)
    out = tmp_path / "cap"
    assert main(["import", "idr", str(npz), "--images", str(tmp_path / "image"),
                 "--scale", "0.5", "--out", str(out)]) == 0
    data = yaml.safe_load((out / "capture.yaml").read_text())
    assert data["camera"]["image_size"] == [160, 120]
    assert abs(data["camera"]["fx"] - 250.0) < 1e-4  # 500 px halved (float32 file)


def test_import_colmap_in_metres_multiplies_the_world_by_1000(tmp_path):
    m = write_colmap(tmp_path, "1 PINHOLE 320 240 500 505 160 120")
    mm, m_out = tmp_path / "mm", tmp_path / "m"
    assert main(["import", "colmap", str(m), "--images", str(tmp_path / "images"),
                 "--out", str(mm)]) == 0
    assert main(["import", "colmap", str(m), "--images", str(tmp_path / "images"),
                 "--unit", "m", "--out", str(m_out)]) == 0
    a, b = read_views_capture(mm), read_views_capture(m_out)
    assert np.allclose(b.poses[2].translation, 1000 * a.poses[2].translation)
    assert np.allclose(b.depth_range_mm, np.multiply(1000, a.depth_range_mm))


def test_import_without_a_depth_range_fails_with_exit_2_and_writes_nothing(tmp_path, capsys):
    d = write_mvsnet(tmp_path, depth_line="")
    out = tmp_path / "cap"
    assert main(["import", "mvsnet", str(d), "--intrinsics-scale", "4",
                 "--out", str(out)]) == 2
    assert "--depth-range" in capsys.readouterr().err
    assert not out.exists()
    assert main(["import", "mvsnet", str(d), "--intrinsics-scale", "4",
                 "--depth-range", "500", "800", "--out", str(out)]) == 0


def test_import_refuses_a_folder_that_is_not_empty(tmp_path, capsys):
    d = write_mvsnet(tmp_path)
    assert main(["import", "mvsnet", str(d), "--out", str(d)]) == 2
    assert "not an empty folder" in capsys.readouterr().err


def test_import_mvsnet_pair_of_keeps_a_view_and_its_best_neighbours(tmp_path):
    d = write_mvsnet(tmp_path)  # pair.txt: view 2's best are 1, then 0
    out = tmp_path / "cap"
    assert main(["import", "mvsnet", str(d), "--intrinsics-scale", "4", "--pair-of", "2",
                 "--neighbours", "1", "--out", str(out)]) == 0
    assert read_views_capture(out).names == ("00000002.png", "00000001.png")
