"""Ground-truth depth maps: PFM, NPY and 16-bit PNG, their keys in capture folders."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from robostereo.errors import InputError
from robostereo.evaluation import capture_depth_files, read_depth_map, write_depth_map
from robostereo.geometry.camera import SEED_CAMERA
from robostereo.geometry.poses import se3_from_scara
from robostereo.robot.capture import read_capture, write_capture
from robostereo.robot.capture.capture_folder import Capture
from robostereo.robot.views.viewpoints import ViewsCapture
from robostereo.robot.views.views_folder import read_views_capture, write_views_capture


def _depth(rng: np.random.Generator) -> np.ndarray:
    d = rng.uniform(300.0, 1500.0, (30, 40))
    d[0, 0], d[1, 2], d[2, 3], d[3, 4] = 0.0, -5.0, np.nan, np.inf  # unknown, four ways
    return d


@pytest.mark.parametrize("suffix", [".pfm", ".npy"])
def test_float_depth_maps_round_trip_with_unknowns_as_nan(tmp_path: Path, suffix: str) -> None:
    d = _depth(np.random.default_rng(0))
    back = read_depth_map(write_depth_map(tmp_path / f"d{suffix}", d), image_size=(40, 30))
    known = np.isfinite(d) & (d > 0)
    assert np.isnan(back[~known]).all() and (~known).sum() == 4
    np.testing.assert_allclose(back[known], d[known], rtol=1e-6)  # float32 on disk


def test_pfm_rows_are_read_top_row_first(tmp_path: Path) -> None:
    # the format stores rows bottom to top: a file written by hand that way
    d = np.arange(1.0, 7.0, dtype="<f4").reshape(2, 3)
    (tmp_path / "d.pfm").write_bytes(b"Pf\n3 2\n-1.0\n" + np.flipud(d).tobytes())
    np.testing.assert_array_equal(read_depth_map(tmp_path / "d.pfm"), d)


def test_png_depth_maps_hold_depth_times_the_scale(tmp_path: Path) -> None:
    d = _depth(np.random.default_rng(1))
    p = write_depth_map(tmp_path / "d.png", d, scale=10.0)
    raw = cv2.imread(str(p), cv2.IMREAD_UNCHANGED)
    assert raw.dtype == np.uint16 and raw[5, 5] == round(10 * d[5, 5])
    back = read_depth_map(p, scale=10.0)
    known = np.isfinite(d) & (d > 0)
    assert np.abs(back[known] - d[known]).max() <= 0.05 + 1e-9  # 0.1 mm steps
    assert np.isnan(back[~known]).all()
    # the default scale, 1 unit per mm, reads the same file ten times deeper
    np.testing.assert_allclose(read_depth_map(p)[known], 10 * back[known])


def test_depth_maps_that_do_not_fit_are_refused_naming_the_file(tmp_path: Path) -> None:
    p = write_depth_map(tmp_path / "d.npy", np.ones((30, 40)))
    with pytest.raises(InputError, match=r"d\.npy: the depth map is 40 x 30 pixels, the "
                                         r"camera's image_size is 64 x 48"):
        read_depth_map(p, image_size=(64, 48))
    cv2.imwrite(str(tmp_path / "eight.png"), np.ones((30, 40), np.uint8))
    with pytest.raises(InputError, match=r"eight\.png: a PNG depth map must be 16-bit"):
        read_depth_map(tmp_path / "eight.png")
    (tmp_path / "bad.pfm").write_bytes(b"not a pfm")
    with pytest.raises(InputError, match=r"bad\.pfm: not a readable PFM"):
        read_depth_map(tmp_path / "bad.pfm")
    with pytest.raises(InputError, match=r"gone\.pfm: depth map not found"):
        read_depth_map(tmp_path / "gone.pfm")
    with pytest.raises(InputError, match=r"d\.tif: a depth map must be"):
        read_depth_map(tmp_path / "d.tif")
    with pytest.raises(InputError, match="exceeds a 16-bit PNG"):
        write_depth_map(tmp_path / "far.png", np.full((2, 2), 7000.0), scale=10.0)


def _two_view(tmp_path: Path) -> Path:
    w, h = SEED_CAMERA.image_size
    img = np.random.default_rng(0).integers(0, 128, (h, w)).astype(np.uint8)
    cap = Capture(left=img, right=img, camera=SEED_CAMERA,
                  pose_left=se3_from_scara(-10, 0, 1000), pose_right=se3_from_scara(10, 0, 1000),
                  depth_range_mm=(900.0, 1100.0))
    return write_capture(tmp_path / "cap", cap)


def _edit(d: Path, **keys) -> None:
    data = yaml.safe_load((d / "capture.yaml").read_text())
    data.update(keys)
    (d / "capture.yaml").write_text(yaml.safe_dump(data, sort_keys=False))


def test_two_view_readers_accept_the_depth_keys_and_nothing_else_changes(
        tmp_path: Path) -> None:
    d = _two_view(tmp_path)
    before = read_capture(d)
    _edit(d, depth_left="depth/l.npy", depth_right="depth/r.png", depth_scale=10)
    after = read_capture(d)
    assert after.pose_right == before.pose_right and after.depth_range_mm == (900.0, 1100.0)
    assert read_views_capture(d).names == ("left.png", "right.png")
    _edit(d, depth_middle="x.npy")
    with pytest.raises(InputError, match="unknown key 'depth_middle'"):
        read_capture(d)


def test_two_view_depth_maps_are_found_by_key_or_in_the_depth_folder(tmp_path: Path) -> None:
    d = _two_view(tmp_path)
    assert capture_depth_files(d).paths == (None, None)
    (d / "depth").mkdir()
    write_depth_map(d / "depth" / "left.png", np.ones((2, 2)))
    write_depth_map(d / "depth" / "right.npy", np.ones((2, 2)))
    write_depth_map(d / "depth" / "right.png", np.ones((2, 2)))
    files = capture_depth_files(d)  # the fallback: .pfm, then .npy, then .png
    assert files.paths == (d / "depth" / "left.png", d / "depth" / "right.npy")
    assert files.scale == 1.0
    _edit(d, depth_left="depth/right.png", depth_scale=4)
    files = capture_depth_files(d)
    assert files.paths[0] == d / "depth" / "right.png" and files.scale == 4.0
    _edit(d, depth_right="depth/missing.pfm")
    with pytest.raises(InputError, match=r"missing\.pfm: depth map not found \(.*depth_right"):
        capture_depth_files(d)
    _edit(d, depth_right="../outside.pfm")
    with pytest.raises(InputError, match=r"depth_right: the depth map '\.\./outside\.pfm' must be"):
        capture_depth_files(d)
    _edit(d, depth_right="depth/right.png", depth_scale=0)
    with pytest.raises(InputError, match="key 'depth_scale' must be a finite number > 0"):
        capture_depth_files(d)


def test_views_readers_accept_a_depth_key_per_view(tmp_path: Path) -> None:
    w, h = SEED_CAMERA.image_size
    rng = np.random.default_rng(3)
    cap = ViewsCapture(tuple(rng.integers(0, 128, (h, w)).astype(np.uint8) for _ in range(3)),
                       SEED_CAMERA, tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20, 0, 20)),
                       depth_range_mm=(900.0, 1100.0))
    d = write_views_capture(tmp_path / "views", cap)
    data = yaml.safe_load((d / "capture.yaml").read_text())
    data["views"][1]["depth"] = "gt/one.npy"
    data["depth_scale"] = 10
    (d / "capture.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    (d / "gt").mkdir()
    write_depth_map(d / "gt" / "one.npy", np.ones((h, w)))
    (d / "depth").mkdir()
    write_depth_map(d / "depth" / "view_02.pfm", np.ones((h, w)))
    assert len(read_views_capture(d)) == 3
    files = capture_depth_files(d)
    assert files.paths == (None, d / "gt" / "one.npy", d / "depth" / "view_02.pfm")
    assert files.read(1, (w, h)).shape == (h, w) and files.read(0, (w, h)) is None
    data["views"][0]["depth_map"] = "x.npy"
    (d / "capture.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    with pytest.raises(InputError, match=r"views\[0\]: unknown key 'depth_map'"):
        read_views_capture(d)
