"""Tests for robostereo.datasets: scene layouts, the real developer set."""

from __future__ import annotations

import shutil
from pathlib import Path

import cv2
import numpy as np
import pytest

from robostereo.datasets import (
    available_scenes,
    disparity_consistency,
    find_data_dir,
    load_scene,
)
from robostereo.errors import InputError
from robostereo.io.images import write_pfm

REAL = Path(__file__).resolve().parents[2] / "shared" / "data" / "stereo"


needs_real = pytest.mark.skipif(
    not (REAL / "scenes.json").is_file(), reason="shared stereo data absent"
)


def _pair(rng: np.random.Generator, h: int = 40, w: int = 60, d: int = 4):
    """Random texture and the same texture seen with disparity d: left(x) = right(x - d)."""
    big = rng.integers(0, 256, (h, w + d, 3), dtype=np.uint8)
    big = cv2.GaussianBlur(big, (5, 5), 1.0)
    return big[:, :w], big[:, d:]  # left(x) = big(x) = right(x - d)


def test_middlebury_2014_layout(tmp_path: Path) -> None:
    rng = np.random.default_rng(2)
    left, right = _pair(rng, d=4)
    h, w = left.shape[:2]
    cv2.imwrite(str(tmp_path / "im0.png"), left[..., ::-1])
    cv2.imwrite(str(tmp_path / "im1.png"), right[..., ::-1])
    gt = np.full((h, w), 4.0, dtype=np.float32)
    gt[:, :4] = np.inf  # no match in the right image
    gt[10, 20] = 4.5
    write_pfm(tmp_path / "disp0.pfm", gt)
    (tmp_path / "calib.txt").write_text(
        f"cam0=[500 0 30; 0 500 20; 0 0 1]\ncam1=[500 0 32; 0 500 20; 0 0 1]\ndoffs=2\n"
        f"baseline=100\nwidth={w}\nheight={h}\nndisp=16\nvmin=4\nvmax=5\n"
    )
    s = load_scene(tmp_path)
    assert s.name == tmp_path.name and s.shape == (h, w) and s.bit_depth == 8
    assert np.array_equal(s.left, left) and np.array_equal(s.right, right)
    assert np.isnan(s.gt_disparity[:, :4]).all() and s.gt_disparity[10, 20] == 4.5
    assert s.disparity_range == (4.0, 4.5)
    assert s.unknown_fraction == pytest.approx(4 / w)
    assert s.calib is not None and s.calib.T.tolist() == [-100.0, 0.0, 0.0]
    assert s.calib.K2[0, 2] - s.calib.K1[0, 2] == 2.0
    mad, mad_shifted = disparity_consistency(s, rng=np.random.default_rng(0), n_points=200)
    assert mad < 1.0 < 5.0 < mad_shifted
    # MiddEval3 name, no calib.txt
    (tmp_path / "calib.txt").unlink()
    (tmp_path / "disp0.pfm").rename(tmp_path / "disp0GT.pfm")
    s2 = load_scene(tmp_path, name="mine")
    assert s2.name == "mine" and s2.calib is None and s2.disparity_range == (4.0, 4.5)


def test_middlebury_2014_size_mismatches(tmp_path: Path) -> None:
    rng = np.random.default_rng(3)
    left, right = _pair(rng)
    h, w = left.shape[:2]
    cv2.imwrite(str(tmp_path / "im0.png"), left)
    cv2.imwrite(str(tmp_path / "im1.png"), right)
    write_pfm(tmp_path / "disp0.pfm", np.ones((h, w - 1), dtype=np.float32))
    with pytest.raises(InputError, match=r"disp0\.pfm: ground truth is 59 x 40 \(W x H\)"):
        load_scene(tmp_path)
    write_pfm(tmp_path / "disp0.pfm", np.ones((h, w), dtype=np.float32))
    (tmp_path / "calib.txt").write_text(
        "cam0=[500 0 30; 0 500 20; 0 0 1]\ncam1=[500 0 30; 0 500 20; 0 0 1]\ndoffs=0\n"
        f"baseline=100\nwidth={2 * w}\nheight={2 * h}\nndisp=16\n"
    )
    with pytest.raises(InputError, match=r"im0\.png: image is 60 x 40 \(W x H\), calibration"):
        load_scene(tmp_path)
    (tmp_path / "calib.txt").unlink()
    cv2.imwrite(str(tmp_path / "im1.png"), right[:, :-2])
    with pytest.raises(InputError, match=r"im1\.png: right image has shape"):
        load_scene(tmp_path)


def _write_pgm(path: Path, a: np.ndarray) -> None:
    header = f"P5\n{a.shape[1]} {a.shape[0]}\n255\n".encode()
    path.write_bytes(header + a.astype(np.uint8).tobytes())


def test_middlebury_2001_2003_2005_layouts(tmp_path: Path) -> None:
    rng = np.random.default_rng(4)
    left, right = _pair(rng, d=3)
    raw = np.full(left.shape[:2], 24, dtype=np.uint8)  # 3 px at scale 8
    raw[0, :] = 0
    d01 = tmp_path / "sawtooth"
    d01.mkdir()
    cv2.imwrite(str(d01 / "im2.ppm"), left[..., ::-1])
    cv2.imwrite(str(d01 / "im6.ppm"), right[..., ::-1])
    _write_pgm(d01 / "disp2.pgm", raw)
    s = load_scene(d01)
    assert s.disparity_range == (3.0, 3.0) and np.isnan(s.gt_disparity[0]).all()
    assert s.gt_disparity_right is None
    assert load_scene(d01, scale=4).disparity_range == (6.0, 6.0)
    cones = tmp_path / "cones"
    shutil.copytree(d01, cones)
    assert load_scene(cones).disparity_range == (6.0, 6.0)  # 2003: scale 4 by name
    d05 = tmp_path / "art"
    d05.mkdir()
    cv2.imwrite(str(d05 / "view1.png"), left)
    cv2.imwrite(str(d05 / "view5.png"), right)
    cv2.imwrite(str(d05 / "disp1.png"), raw)
    with pytest.raises(InputError, match=r"disp1\.png: disparity scale .* pass scale="):
        load_scene(d05)
    assert load_scene(d05, scale=3).disparity_range == (8.0, 8.0)
    with pytest.raises(InputError, match=r"scale must be a finite number > 0"):
        load_scene(d05, scale=0)
    with pytest.raises(InputError, match=r"no known stereo layout"):
        load_scene(tmp_path)
    with pytest.raises(InputError, match=r"scene directory not found"):
        load_scene(tmp_path / "absent")


def test_find_data_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROBOSTEREO_DATA", str(tmp_path))
    assert find_data_dir() == tmp_path
    assert available_scenes() == []
    monkeypatch.setenv("ROBOSTEREO_DATA", str(tmp_path / "none"))
    with pytest.raises(InputError, match=r"ROBOSTEREO_DATA=.*none is not a directory"):
        find_data_dir()
    monkeypatch.delenv("ROBOSTEREO_DATA")
    if REAL.is_dir():
        assert find_data_dir() == REAL.resolve()


@needs_real
def test_tsukuba_matches_readme() -> None:
    s = load_scene(REAL / "tsukuba")
    assert s.left.shape == (288, 384, 3) and s.right.shape == (288, 384, 3)
    assert s.bit_depth == 8 and s.disparity_range == (5.0, 14.0)
    levels = np.unique(s.gt_disparity[s.known])
    assert len(levels) == 7 and np.array_equal(levels, np.round(levels))
    assert s.unknown_fraction == pytest.approx(0.207, abs=0.0005)
    assert np.isnan(s.gt_disparity[:18]).all() and np.isnan(s.gt_disparity[:, -18:]).all()
    assert s.gt_disparity_right is None and s.calib is None
    assert {"tsukuba", "venus"} <= set(available_scenes(REAL))
    assert load_scene("tsukuba").disparity_range == (5.0, 14.0)  # by name


@needs_real
def test_venus_matches_readme() -> None:
    s = load_scene(REAL / "venus")
    assert s.left.shape == (383, 434, 3) and s.disparity_range == (3.0, 19.75)
    assert s.unknown_fraction == 0.0
    assert np.array_equal(s.gt_disparity * 8, np.round(s.gt_disparity * 8))  # 1/8-px steps
    assert s.gt_disparity_right is not None and s.gt_disparity_right.shape == (383, 434)


@needs_real
@pytest.mark.parametrize(("scene", "readme_mad"), [("tsukuba", 9.5), ("venus", 7.1)])
def test_readme_verification(scene: str, readme_mad: float) -> None:
    s = load_scene(REAL / scene)
    mad, mad_plus = disparity_consistency(s, rng=np.random.default_rng(11), shift=1.0)
    _, mad_minus = disparity_consistency(s, rng=np.random.default_rng(11), shift=-1.0)
    assert mad == pytest.approx(readme_mad, abs=2.0)
    assert mad < 0.5 * mad_plus and mad < 0.5 * mad_minus


@needs_real
def test_scale_inferred_without_scenes_json(tmp_path: Path) -> None:
    ref = load_scene(REAL / "tsukuba")
    copy = shutil.copytree(REAL / "tsukuba", tmp_path / "tsukuba")
    s = load_scene(copy)  # no scenes.json beside it: scale 16 from the name
    np.testing.assert_array_equal(s.gt_disparity, ref.gt_disparity)
    other = shutil.copytree(REAL / "tsukuba", tmp_path / "head_and_lamp")
    with pytest.raises(InputError, match=r"gt_disp_left\.pgm: disparity scale unknown"):
        load_scene(other)
    wrong = load_scene(other, scale=8)  # a wrong scale fails the photometric check
    bad, _ = disparity_consistency(wrong, rng=np.random.default_rng(5))
    good, _ = disparity_consistency(load_scene(other, scale=16), rng=np.random.default_rng(5))
    assert bad > 2.0 * good
