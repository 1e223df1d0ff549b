"""Tests for robostereo.io.calibration_files: OpenCV, ROS, Middlebury readers, their errors."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml
from calibrated_rig import D1, D2, K1, K2, H, R, T, W, synthetic_calibration

from robostereo.errors import InputError
from robostereo.geometry.calibrated_rectification import rectify_stereo
from robostereo.geometry.calibration import StereoCalibration
from robostereo.io.calibration_files import (
    read_calibration,
    read_middlebury_calib,
    read_opencv_calibration,
    read_ros_calibration,
    write_opencv_calibration,
)


@pytest.fixture(scope="module")
def calib() -> StereoCalibration:
    return synthetic_calibration()


def _write_fs(path: Path, entries: dict, size_key: str | None = "image_size") -> Path:
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    for k, v in entries.items():
        fs.write(k, v)
    if size_key is not None:
        fs.startWriteStruct(size_key, cv2.FileNode_SEQ)
        fs.write("", W)
        fs.write("", H)
        fs.endWriteStruct()
    fs.release()
    return path


def _assert_same(a: StereoCalibration, b: StereoCalibration) -> None:
    for name in ("K1", "D1", "K2", "D2", "R", "T"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=1e-12, atol=1e-12)
    assert a.image_size == b.image_size


@pytest.mark.parametrize("ext", ["yml", "yaml", "json", "xml"])
def test_filestorage_round_trip(tmp_path: Path, calib: StereoCalibration, ext: str) -> None:
    p = _write_fs(tmp_path / f"stereo.{ext}", {"K1": K1, "D1": D1, "K2": K2, "D2": D2, "R": R,
                                               "T": T.reshape(3, 1)})  # fmt: skip
    got = read_opencv_calibration(p)
    _assert_same(got, calib)
    assert got.source == str(p)
    _assert_same(read_calibration(p), calib)


def test_opencv_sample_aliases_and_two_files(tmp_path: Path, calib: StereoCalibration) -> None:
    # OpenCV's stereo_calib sample: intrinsics.yml (M1 D1 M2 D2), extrinsics.yml (R T ...)
    intr = _write_fs(tmp_path / "intrinsics.yml", {"M1": K1, "D1": D1, "M2": K2, "D2": D2},
                     size_key="imageSize")  # fmt: skip
    extr = _write_fs(tmp_path / "extrinsics.yml", {"R": R, "T": T / 1000.0}, size_key=None)
    got = read_opencv_calibration(intr, extrinsics_path=extr, unit_to_mm=1000.0)
    np.testing.assert_allclose(got.T, T, rtol=1e-12)
    _assert_same(got, calib)
    assert got.baseline_mm == pytest.approx(np.sqrt(60.0**2 + 0.25 + 1.0))


def test_width_height_keys_and_size_argument(tmp_path: Path, calib: StereoCalibration) -> None:
    p = _write_fs(tmp_path / "wh.yml", {"K1": K1, "D1": D1, "K2": K2, "D2": D2, "R": R, "T": T,
                                        "width": W, "height": H}, size_key=None)  # fmt: skip
    _assert_same(read_opencv_calibration(p), calib)
    q = _write_fs(tmp_path / "nosize.yml", {"K1": K1, "D1": D1, "K2": K2, "D2": D2, "R": R,
                                            "T": T}, size_key=None)  # fmt: skip
    with pytest.raises(InputError, match=r"nosize\.yml: missing key image_size"):
        read_opencv_calibration(q)
    _assert_same(read_opencv_calibration(q, image_size=(W, H)), calib)


def test_plain_json_and_yaml_fallback(tmp_path: Path, calib: StereoCalibration) -> None:
    body = {"K1": K1.tolist(), "D1": D1.tolist(), "K2": K2.ravel().tolist(),
            "D2": {"rows": 1, "cols": 5, "data": D2.tolist()}, "R": R.tolist(),
            "T": T.tolist(), "imageSize": [W, H]}  # fmt: skip
    pj = tmp_path / "plain.json"
    pj.write_text(json.dumps(body))
    _assert_same(read_opencv_calibration(pj), calib)
    py = tmp_path / "plain.yaml"
    py.write_text(yaml.safe_dump(body))
    _assert_same(read_opencv_calibration(py), calib)


def test_writer_round_trip_in_metres(tmp_path: Path, calib: StereoCalibration) -> None:
    p = write_opencv_calibration(calib, tmp_path / "out.json", unit_to_mm=1000.0)
    raw = json.loads(p.read_text())
    assert raw["T"]["data"] == pytest.approx((T / 1000.0).tolist())
    _assert_same(read_opencv_calibration(p, unit_to_mm=1000.0), calib)


def _ros_pair(tmp_path: Path, t_metres: np.ndarray) -> tuple[Path, Path, tuple]:
    R1, R2, P1, P2, *_ = cv2.stereoRectify(K1, D1, K2, D2, (W, H), R, t_metres.reshape(3, 1),
                                           flags=cv2.CALIB_ZERO_DISPARITY, alpha=0.0)  # fmt: skip
    paths = []
    for name, K, D, Rr, P in (("left", K1, D1, R1, P1), ("right", K2, D2, R2, P2)):
        info = {
            "image_width": W, "image_height": H, "camera_name": name,
            "camera_matrix": {"rows": 3, "cols": 3, "data": K.ravel().tolist()},
            "distortion_model": "plumb_bob",
            "distortion_coefficients": {"rows": 1, "cols": 5, "data": D.tolist()},
            "rectification_matrix": {"rows": 3, "cols": 3, "data": Rr.ravel().tolist()},
            "projection_matrix": {"rows": 3, "cols": 4, "data": P.ravel().tolist()},
        }  # fmt: skip
        p = tmp_path / f"{name}.yaml"
        p.write_text(yaml.safe_dump(info, sort_keys=False))
        paths.append(p)
    return paths[0], paths[1], (R1, R2, P1, P2)


def test_ros_pair(tmp_path: Path, calib: StereoCalibration) -> None:
    left, right, (_, _, _, P2) = _ros_pair(tmp_path, T / 1000.0)
    # ROS convention: P2[0, 3] = -fx' * B with B in metres
    assert -P2[0, 3] / P2[0, 0] == pytest.approx(np.linalg.norm(T) / 1000.0)
    got = read_ros_calibration(left, right)
    np.testing.assert_allclose(got.R, R, atol=1e-12)
    np.testing.assert_allclose(got.T, T, atol=1e-9)
    np.testing.assert_allclose(got.K1, K1)
    np.testing.assert_allclose(got.D2, D2)
    assert got.image_size == (W, H)
    np.testing.assert_allclose(read_calibration(left, right).T, T, atol=1e-9)


def test_ros_size_mismatch(tmp_path: Path) -> None:
    left, right, _ = _ros_pair(tmp_path, T / 1000.0)
    d = yaml.safe_load(right.read_text())
    d["image_width"] = 320
    right.write_text(yaml.safe_dump(d))
    with pytest.raises(InputError, match=r"right\.yaml: image size"):
        read_ros_calibration(left, right)
    d["image_width"] = W
    d["distortion_coefficients"]["data"] = [0.1, float("nan"), 0, 0, 0]
    right.write_text(yaml.safe_dump(d))
    with pytest.raises(InputError, match=r"right\.yaml: distortion_coefficients must be finite"):
        read_ros_calibration(left, right)
    del d["distortion_coefficients"]  # absent: no distortion
    right.write_text(yaml.safe_dump(d))
    assert read_ros_calibration(left, right).D2.tolist() == [0.0] * 5


MB_TEXT = """cam0=[4161.221 0 1445.577; 0 4161.221 984.686; 0 0 1]
cam1=[4161.221 0 1654.636; 0 4161.221 984.686; 0 0 1]
doffs=209.059
baseline=176.252
width=2880
height=1988
ndisp=290
isint=0
vmin=33
vmax=218
dyavg=0
dymax=0
"""


def test_middlebury_calib(tmp_path: Path) -> None:
    p = tmp_path / "calib.txt"
    p.write_text(MB_TEXT)
    mb = read_middlebury_calib(p)
    assert (mb.width, mb.height, mb.ndisp, mb.vmin, mb.vmax) == (2880, 1988, 290, 33.0, 218.0)
    assert mb.doffs == pytest.approx(209.059)
    c = mb.calibration
    np.testing.assert_array_equal(c.T, [-176.252, 0.0, 0.0])
    np.testing.assert_array_equal(c.R, np.eye(3))
    assert c.K2[0, 2] == 1654.636 and c.image_size == (2880, 1988)
    assert read_calibration(p).K1[0, 0] == 4161.221
    # an already rectified pair: rectification keeps the geometry; doffs as in the file
    r = rectify_stereo(c, zero_disparity=False)
    assert r.doffs == pytest.approx(209.059, abs=1e-6)
    assert r.fx == pytest.approx(4161.221, rel=1e-9)
    assert r.baseline_mm == pytest.approx(176.252)
    # Middlebury's depth formula Z = baseline * f / (d + doffs)
    assert r.depth_from_disparity(100.0) == pytest.approx(176.252 * 4161.221 / 309.059)
    np.testing.assert_array_equal(r.map_right[0][5, :4], [0, 1, 2, 3])
    # with zero_disparity OpenCV moves both principal points to their mean
    r0 = rectify_stereo(c, zero_disparity=True)
    assert r0.cx_left == r0.cx_right == pytest.approx((1445.577 + 1654.636) / 2, abs=1e-3)


@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        (MB_TEXT.replace("doffs=209.059", "doffs=10"), "doffs must equal cx1 - cx0"),
        (MB_TEXT.replace("baseline=176.252\n", ""), "missing key baseline"),
        (MB_TEXT.replace("baseline=176.252", "baseline=abc"), "baseline must be a number"),
        (MB_TEXT.replace("cam0=[4161.221 0", "cam0=[nan 0"), "cam0 must be"),
        (MB_TEXT.replace("width=2880", "width=0"), "width/height must be"),
    ],
)
def test_middlebury_invalid(tmp_path: Path, text: str, pattern: str) -> None:
    p = tmp_path / "calib.txt"
    p.write_text(text)
    with pytest.raises(InputError, match=rf"calib\.txt: {pattern}"):
        read_middlebury_calib(p)


SINGULAR = np.array([[800.0, 0, 320], [1600.0, 0, 640], [0, 0, 1]])


NAN_K = K1.copy()


NAN_K[0, 2] = np.nan


@pytest.mark.parametrize(
    ("entries", "field"),
    [
        ({"K1": NAN_K}, "K1 must be finite"),
        ({"K2": SINGULAR}, "K2 must"),
        ({"K1": np.eye(2)}, "K1 must be a 3x3"),
        ({"D1": np.zeros(6)}, "D1 must have 4, 5, 8, 12 or 14"),
        ({"D2": np.array([0.1, np.nan, 0, 0, 0])}, "D2 must be finite"),
        ({"R": R * 1.01}, "R must be a rotation"),
        ({"R": np.diag([1.0, 1.0, -1.0])}, "R must be a rotation"),
        ({"T": np.zeros(3)}, "T must be non-zero"),
        ({"T": np.array([-60.0, np.inf, 0])}, "T must be finite"),
        ({"T": np.array([-60.0, 0])}, "T must be a 3-vector"),
    ],
)
def test_invalid_values_name_file_and_field(tmp_path: Path, entries: dict, field: str) -> None:
    base = {"K1": K1, "D1": D1, "K2": K2, "D2": D2, "R": R, "T": T}
    base.update(entries)
    p = _write_fs(tmp_path / "bad.yml", base)
    with pytest.raises(InputError, match=rf"bad\.yml: {field}") as info:
        read_opencv_calibration(p)
    assert "\n" not in str(info.value)


def test_missing_key_and_unreadable_files(tmp_path: Path) -> None:
    p = _write_fs(tmp_path / "nok.json", {"K1": K1, "D1": D1, "K2": K2, "D2": D2, "R": R})
    with pytest.raises(InputError, match=r"nok\.json: missing key T"):
        read_opencv_calibration(p)
    q = _write_fs(tmp_path / "m.yml", {"D1": D1, "K2": K2, "D2": D2, "R": R, "T": T})
    with pytest.raises(InputError, match=r"m\.yml: missing key K1 or M1"):
        read_opencv_calibration(q)
    z = _write_fs(tmp_path / "size.xml", {"K1": K1, "D1": D1, "K2": K2, "D2": D2, "R": R, "T": T,
                                          "width": 0, "height": H}, size_key=None)  # fmt: skip
    with pytest.raises(InputError, match=r"size\.xml: image_size must be \(width, height\)"):
        read_opencv_calibration(z)
    with pytest.raises(InputError, match=r"absent\.yml: calibration file not found"):
        read_opencv_calibration(tmp_path / "absent.yml")
    empty = tmp_path / "empty.yml"
    empty.write_text("")
    with pytest.raises(InputError, match=r"empty\.yml: calibration file is empty"):
        read_opencv_calibration(empty)
    broken = tmp_path / "broken.yml"
    broken.write_text("%YAML:1.0\nK1: [1, 2,\n")
    with pytest.raises(InputError, match=r"broken\.yml: cannot parse"):
        read_opencv_calibration(broken)
    binary = tmp_path / "garbage.json"
    binary.write_bytes(bytes(range(256)))
    with pytest.raises(InputError, match=r"garbage\.json: cannot"):
        read_opencv_calibration(binary)
    with pytest.raises(InputError, match=r"garbage\.json: cannot"):
        read_calibration(binary)
