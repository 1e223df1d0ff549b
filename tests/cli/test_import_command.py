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


def _quarter_depths(folder, names) -> list[np.ndarray]:
    """DTU-style depth maps a quarter the images' size (80 x 60), each its own ramp."""
    from robostereo.evaluation import write_depth_map

    folder.mkdir()
    maps = []
    for k, name in enumerate(names):
        d = 600.0 + 10 * k + np.add.outer(np.arange(60.0), np.arange(80.0) / 100)
        d[0, 0] = 0.0  # unknown
        write_depth_map(folder / name, d)
        maps.append(d)
    return maps


def test_import_mvsnet_puts_quarter_size_depth_maps_on_the_image_grid(tmp_path, capsys):
    from robostereo.evaluation import capture_depth_files

    d = write_mvsnet(tmp_path)
    maps = _quarter_depths(d / "Depths", [f"depth_map_{k:04d}.pfm" for k in range(3)])
    out = tmp_path / "cap"
    assert main(["import", "mvsnet", str(d), "--intrinsics-scale", "4", "--views", "2,0",
                 "--depths", str(d / "Depths"), "--out", str(out)]) == 0
    assert "2 depth maps" in capsys.readouterr().out
    files = capture_depth_files(out)  # found where evaluate looks, by the image's stem
    assert [p.name for p in files.paths] == ["00000002.pfm", "00000000.pfm"]
    got = files.read(0, (320, 240))
    assert got.shape == (240, 320)
    # image pixel (x, y) takes the map's pixel (x // 4, y // 4): centres to centres
    assert got[9, 13] == np.float32(maps[2][2, 3]) and got[239, 319] == np.float32(
        maps[2][59, 79])
    assert np.isnan(got[:4, :4]).all() and np.isfinite(got[4:, 4:]).all()


def test_import_mvsnet_writes_its_depth_maps_with_the_folder_or_nothing(tmp_path, capsys,
                                                                         monkeypatch):
    # the depth maps go into the same all-or-nothing folder as the images: one that
    # cannot be encoded leaves no capture folder behind and nothing staged beside it
    import robostereo.evaluation.depth_maps as depth_maps
    from robostereo.errors import InputError

    d = write_mvsnet(tmp_path)
    _quarter_depths(d / "Depths", [f"depth_map_{k:04d}.pfm" for k in range(3)])
    before = set(tmp_path.iterdir())
    encode = depth_maps.depth_map_bytes
    done = []

    def second_fails(depth, suffix, **kw):
        done.append(suffix)
        if len(done) == 2:
            raise InputError(f"{kw.get('name')}: cannot be encoded")
        return encode(depth, suffix, **kw)

    monkeypatch.setattr(depth_maps, "depth_map_bytes", second_fails)
    out = tmp_path / "cap"
    assert main(["import", "mvsnet", str(d), "--intrinsics-scale", "4", "--views", "2,0",
                 "--depths", str(d / "Depths"), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot be encoded" in err[0], err
    assert done == [".pfm", ".pfm"]
    assert not out.exists() and set(tmp_path.iterdir()) == before


def test_import_mvsnet_refuses_a_missing_depth_map_and_writes_nothing(tmp_path, capsys):
    d = write_mvsnet(tmp_path)
    _quarter_depths(d / "out_depths", ["00000000.pfm"])
    out = tmp_path / "cap"
    assert main(["import", "mvsnet", str(d), "--intrinsics-scale", "4", "--views", "0,1",
                 "--depths", str(d / "out_depths"), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "out_depths: no depth map for view 00000001 " \
        "(depth_map_0001.pfm or 00000001.pfm)" in err[0]
    assert not out.exists()
