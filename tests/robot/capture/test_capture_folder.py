"""Capture folders: written, read back (the points located from them unchanged), refused."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.geometry.camera import SEED_CAMERA
from robostereo.robot.capture import locate, locate_capture
from robostereo.robot.capture.capture_folder import (
    disparity_range_from_depth,
    read_capture,
    write_capture,
)
from robostereo.robot.simulated.scara_rig import SimulatedCapture, simulate_capture


@pytest.fixture(scope="module")
def block_sim() -> SimulatedCapture:
    return simulate_capture("block", seed=0)


@pytest.fixture(scope="module")
def capture_dir(block_sim, tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("cap") / "block"
    write_capture(d, block_sim.capture)
    return d


def test_disparity_range_from_depth():
    lo, hi = disparity_range_from_depth(SEED_CAMERA, 20.0, (1000.0, 1000.0))
    assert (lo, hi) == (29.0, 30.0)  # fx * 20 / 1000 = 29.07
    with pytest.raises(InputError, match="depth_range_mm"):
        disparity_range_from_depth(SEED_CAMERA, 20.0, (1000.0, 900.0))


def test_capture_round_trip(block_sim, capture_dir):
    cap = read_capture(capture_dir)
    orig = block_sim.capture
    assert sorted(p.name for p in capture_dir.iterdir()) == ["capture.yaml", "left.png",
                                                             "right.png"]
    assert np.array_equal(cap.left, orig.left) and np.array_equal(cap.right, orig.right)
    assert cap.left.dtype == np.uint8 and int(cap.left.max()) <= 127
    assert cap.camera == orig.camera and cap.bit_depth == 7
    for a, b in ((cap.pose_left, orig.pose_left), (cap.pose_right, orig.pose_right)):
        assert a.position == pytest.approx(b.position, abs=1e-12)
        assert a.phi == pytest.approx(b.phi, abs=1e-12)
    assert cap.depth_range_mm == orig.depth_range_mm
    assert cap.resolved_disparity_range() == orig.resolved_disparity_range() == (27.0, 35.0)
    data = yaml.safe_load((capture_dir / "capture.yaml").read_text())
    assert set(data["pose_left"]) == {"x", "y", "z", "phi_deg"}
    assert data["pose_right"]["x"] - data["pose_left"]["x"] == pytest.approx(20.0)


def test_locate_capture_equals_the_demo_run(block_sim, capture_dir):
    """The folder read back gives the points of the in-memory run, to 1e-6 mm."""
    a = locate(block_sim.capture)
    b = locate_capture(capture_dir)
    assert len(a) == len(b) > 250
    ta, tb = a.table(), b.table()
    assert list(tb) == ["X_w", "Y_w", "Z_w", "X", "Y", "Z", "z_bound", "row", "x_left",
                        "x_right", "u_left", "v_left", "disparity", "confidence"]
    for k in ta:
        assert np.allclose(ta[k], tb[k], atol=1e-6, rtol=0), k


def _edit_yaml(d: Path, **changes) -> None:
    p = d / "capture.yaml"
    data = yaml.safe_load(p.read_text())
    for k, v in changes.items():
        if v is None:
            data.pop(k, None)
        else:
            data[k] = v
    p.write_text(yaml.safe_dump(data))


def _copy(src: Path, dst: Path) -> Path:
    dst.mkdir()
    for name in ("left.png", "right.png", "capture.yaml"):
        (dst / name).write_bytes((src / name).read_bytes())
    return dst


@pytest.mark.parametrize(("change", "message"), [
    ({"pose_right": {"x": 390.0, "y": 0.0, "z": 1050.0, "phi_deg": 0.0}}, "coincide"),
    ({"pose_left": {"x": float("nan"), "y": 0.0, "z": 1050.0, "phi_deg": 0.0}}, "pose_left"),
    ({"pose_right": {"x": 410.0, "y": 0.0, "z": 1000.0, "phi_deg": 0.0}}, "same height"),
    ({"disparity_range": [30, 20]}, "disparity_range"),
    ({"depth_range_mm": None}, "disparity_range \\[min, max\\] or depth_range_mm"),
    ({"camera": None}, "missing key 'camera'"),
    ({"color": 3}, "unknown key 'color'"),
    ({"bit_depth": 6}, "grey level"),
    ({"uncertainty": {"disparity_px": -1}}, "disparity_px"),
    ({"uncertainty": {"rotation_deg": -0.1}}, "rotation_deg"),
    ({"uncertainty": {"rotation_deg": 30}}, "rotation_deg' must be a finite number >= 0 and "
                                            "below 10"),
    ({"uncertainty": {"hand_eye_deg": float("inf")}}, "hand_eye_deg"),
])
def test_bad_capture_folders(capture_dir, tmp_path, change, message):
    d = _copy(capture_dir, tmp_path / "bad")
    _edit_yaml(d, **change)
    with pytest.raises(InputError, match=message):
        read_capture(d)
    # the CLI: one line, exit 2, no output file
    out = tmp_path / "out.csv"
    assert main(["locate", str(d), "-o", str(out)]) == 2
    assert not out.exists() and not (d / "located.csv").exists()


def test_missing_files(capture_dir, tmp_path, capsys):
    d = _copy(capture_dir, tmp_path / "c")
    (d / "capture.yaml").unlink()
    with pytest.raises(InputError, match="missing capture file"):
        read_capture(d)
    d2 = _copy(capture_dir, tmp_path / "c2")
    (d2 / "right.png").unlink()
    with pytest.raises(InputError, match=r"right\.png"):
        read_capture(d2)
    assert main(["locate", str(tmp_path / "nowhere")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("robostereo: error: ") and "not found" in err[0]


def test_capture_errors(block_sim, tmp_path, capsys):
    # write_capture refuses a non-empty folder and leaves nothing on failure
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "x").write_text("x")
    with pytest.raises(InputError, match="not an empty folder"):
        write_capture(tmp_path / "full", block_sim.capture)
    with pytest.raises(InputError, match=r"zero|coincide"):
        replace(block_sim.capture, pose_right=block_sim.capture.pose_left)
    # CLI: unreachable pose, zero baseline, NaN -> one line, exit 2, no folder
    for args in (["--center", "900", "0"], ["--baseline", "0"], ["--lift", "nan"],
                 ["--center", "30", "0"]):
        d = tmp_path / "c"
        with pytest.raises(SystemExit) if args[1] == "nan" else _no_raise():
            code = main(["capture", "--out", str(d), *args])
            assert code == 2
        assert not d.exists()
        assert not list(tmp_path.glob(".c.*"))
    err = capsys.readouterr().err
    assert "cannot reach" in err and "baseline_mm" in err


class _no_raise:
    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: object) -> bool:
        return False


@pytest.fixture(scope="module")
def six_axis_folder(tmp_path_factory):
    from robostereo.robot.capture import write_capture
    from robostereo.robot.simulated.sixaxis_rig import simulate_six_axis_capture

    d = tmp_path_factory.mktemp("six") / "cap"
    write_capture(d, simulate_six_axis_capture("block").capture)
    return d


def _copy_with(src, dst, edit):
    import shutil

    import yaml

    shutil.copytree(src, dst)
    data = yaml.safe_load((dst / "capture.yaml").read_text())
    edit(data)
    (dst / "capture.yaml").write_text(yaml.safe_dump(data))
    return dst


def test_translations_in_metres_without_a_unit_warn_naming_the_key(six_axis_folder, tmp_path):
    import warnings

    from robostereo.errors import PlausibilityWarning
    from robostereo.robot.capture.capture_folder import read_capture

    def metres(data, unit):
        for k in ("flange_left", "flange_right", "hand_eye"):
            data[k]["position"] = [v / 1000.0 for v in data[k]["position"]]
            if unit:
                data[k]["unit"] = "m"

    d = _copy_with(six_axis_folder, tmp_path / "m", lambda data: metres(data, False))
    with pytest.warns(PlausibilityWarning) as rec:
        read_capture(d)
    msgs = [str(w.message) for w in rec]
    assert any("flange_left and flange_right" in m and "unit: m" in m for m in msgs)
    assert any(": hand_eye: every translation" in m for m in msgs)
    assert all(m.startswith(str(d / "capture.yaml")) for m in msgs)
    d = _copy_with(six_axis_folder, tmp_path / "ok", lambda data: metres(data, True))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_capture(d)
        read_capture(six_axis_folder)


def test_identity_hand_eye_warns_and_the_cli_prints_warnings_as_lines(
        six_axis_folder, tmp_path, capsys):
    from robostereo.cli import main

    def identity(data):
        data["hand_eye"] = {"position": [0, 0, 0], "quaternion": [0, 0, 0, 1]}

    d = _copy_with(six_axis_folder, tmp_path / "id", identity)
    main(["locate", str(d), "-o", str(tmp_path / "o.csv")])
    err = capsys.readouterr().err.splitlines()
    assert (f"robostereo: warning: {d / 'capture.yaml'}: hand_eye is the identity (camera "
            "frame = flange frame): a placeholder, not a calibration? (robostereo handeye "
            "estimates it)") in err
    assert all(line.startswith("robostereo: ") for line in err)


def test_a_baseline_within_its_uncertainty_is_reported_as_such(tmp_path, capsys):
    assert main(["capture", "--baseline", "1e-6", "--out", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == ["robostereo: error: baseline D = 1e-06 mm is not longer than its "
                   "uncertainty 0.01 mm (eq. 9's dD): the two views are one viewpoint; "
                   "move the camera further between them"]
    assert not (tmp_path / "c").exists()


def test_a_pose_near_the_float_range_gives_no_numpy_warning(block_sim):
    # found by the long property profile: the baseline's norm overflowed while squaring
    import warnings

    from robostereo.geometry.poses import Pose

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:  # refused as beyond any robot's reach (MAX_TRANSLATION_MM)
            far = Pose(1.3407807929942597e154, 0.0, block_sim.capture.pose_left.z, 0.0)
            replace(block_sim.capture, pose_left=far)
        except InputError:
            pass


def test_a_hand_eye_turned_about_the_optical_axis_is_warned_about(tmp_path, capsys):
    """A hand-eye 2 degrees off about the camera's optical axis puts the rectified rows
    of the six-axis pulley about 2.6 px apart: the first match's places are mostly wrong,
    so the rows check must search whole rows to see it. `locate` warns (exit 0) and the
    second match's points lie where the right hand-eye's do."""
    from scipy.spatial.transform import Rotation

    from robostereo.robot.capture import write_capture
    from robostereo.robot.simulated.sixaxis_rig import simulate_six_axis_capture

    good = tmp_path / "good"
    write_capture(good, simulate_six_axis_capture("pulley").capture)

    def turned(data):
        q = Rotation.from_quat(data["hand_eye"]["quaternion"])  # ROS order x, y, z, w
        turn = q * Rotation.from_euler("z", 2.0, degrees=True)
        data["hand_eye"]["quaternion"] = [float(v) for v in turn.as_quat()]

    bad = _copy_with(good, tmp_path / "bad", turned)
    assert main(["locate", str(good), "-o", str(tmp_path / "good.csv")]) == 0
    assert "disagree" not in capsys.readouterr().err
    assert main(["locate", str(bad), "-o", str(tmp_path / "bad.csv")]) == 0
    assert "the rows of the two views disagree" in capsys.readouterr().err
    z_good = np.genfromtxt(tmp_path / "good.csv", delimiter=",", names=True)["Z_w"]
    z_bad = np.genfromtxt(tmp_path / "bad.csv", delimiter=",", names=True)["Z_w"]
    assert z_bad.size > 0.8 * z_good.size
    assert abs(np.median(z_bad) - np.median(z_good)) < 3.0
    assert np.percentile(z_bad, 95) < np.percentile(z_good, 95) + 5.0


def test_a_rotation_uncertainty_widens_each_bound_by_the_disparity_it_allows(capture_dir,
                                                                           tmp_path):
    """``uncertainty: rotation_deg``: each view turned up to that much across the baseline
    moves the disparity by up to ``2 f tan`` of it, and eq. 9's bound grows by
    ``Z^2 / (f D)`` times that; files without the key read and write as before."""
    plain = read_capture(capture_dir)
    assert plain.rotation_uncertainty_deg == 0.0
    d = _copy(capture_dir, tmp_path / "turned")
    data = yaml.safe_load((d / "capture.yaml").read_text())
    data["uncertainty"]["rotation_deg"] = 0.02
    (d / "capture.yaml").write_text(yaml.safe_dump(data))
    turned = read_capture(d)
    assert turned.rotation_uncertainty_deg == 0.02
    a, b = locate_capture(capture_dir), locate_capture(d)
    np.testing.assert_array_equal(a.world, b.world)  # the points are the same
    cam = plain.stereo_camera()
    gain = 2 * cam.fx * np.tan(np.radians(0.02))  # px of disparity
    # the added bound is eq. 9's disparity term for `gain` more pixels
    np.testing.assert_allclose(b.z_bound - a.z_bound,
                               gain * cam.baseline_mm * cam.fx / a.disparity**2, rtol=0.02)
    assert np.median(b.z_bound - a.z_bound) > 0.5  # 0.02 deg at 1 m: mm, not microns
    # written back with the key; a capture without it writes none
    write_capture(tmp_path / "again", turned)
    again = yaml.safe_load((tmp_path / "again" / "capture.yaml").read_text())
    assert again["uncertainty"]["rotation_deg"] == 0.02
    write_capture(tmp_path / "plain", plain)
    assert "rotation_deg" not in yaml.safe_load(
        (tmp_path / "plain" / "capture.yaml").read_text())["uncertainty"]


def test_a_hand_eye_uncertainty_widens_each_bound_by_how_far_it_moves_the_point(
        capture_dir, tmp_path):
    """``uncertainty: hand_eye_deg``: the world tilts with the hand-eye, moving a point at
    depth ``Z`` by ``Z tan`` of it, which no image shows; each bound gains that."""
    d = _copy(capture_dir, tmp_path / "hand_eye")
    data = yaml.safe_load((d / "capture.yaml").read_text())
    data["uncertainty"]["hand_eye_deg"] = 0.4
    (d / "capture.yaml").write_text(yaml.safe_dump(data))
    assert read_capture(d).hand_eye_uncertainty_deg == 0.4
    a, b = locate_capture(capture_dir), locate_capture(d)
    np.testing.assert_array_equal(a.world, b.world)
    np.testing.assert_allclose(b.z_bound - a.z_bound,
                               a.epipolar_xyz[:, 2] * np.tan(np.radians(0.4)), rtol=1e-9)
    assert np.median(b.z_bound - a.z_bound) > 5.0  # 0.4 deg at about 1 m: 7 mm
    write_capture(tmp_path / "again", read_capture(d))
    assert yaml.safe_load((tmp_path / "again" / "capture.yaml").read_text())[
        "uncertainty"]["hand_eye_deg"] == 0.4
