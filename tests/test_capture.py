"""Capture folders, rectification with fill, locate, and the demo/capture/locate commands."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml

from robostereo.camera import SEED_CAMERA, Camera, EpipolarGeometry, Pose
from robostereo.cli import main
from robostereo.edges import detect_edges
from robostereo.errors import InputError
from robostereo.experiments import (
    RigSetup,
    SimulatedCapture,
    run_block_experiment,
    simulate_capture,
)
from robostereo.robot.capture import (
    disparity_range_from_depth,
    fill_invalid_rows,
    locate,
    locate_capture,
    read_capture,
    rectify_pair,
    write_capture,
)


@pytest.fixture(scope="module")
def block_sim() -> SimulatedCapture:
    return simulate_capture("block", seed=0)


@pytest.fixture(scope="module")
def capture_dir(block_sim, tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("cap") / "block"
    write_capture(d, block_sim.capture)
    return d


def test_fill_invalid_rows_known_answer():
    img = np.array([[np.nan, np.nan, 4.0, 6.0, np.nan], [1.0, 2.0, 3.0, 4.0, 5.0]])
    out = fill_invalid_rows(img, np.isfinite(img))
    assert out.tolist() == [[4.0, 4.0, 4.0, 6.0, 6.0], [1.0, 2.0, 3.0, 4.0, 5.0]]


def test_rectified_fill_makes_no_edges():
    """A rolled view of a vertical step: after rectification and fill, edge points only at
    the step, none at the boundary of the filled region (the fill is flat along rows)."""
    cam = Camera(image_size=(200, 160))
    left, right = Pose(-10.0, 0.0, 1000.0, 0.25), Pose(10.0, 0.0, 1000.0, 0.2)
    g = EpipolarGeometry.from_poses(cam, left, right)
    # a world step edge at X = 0 on the table, seen by the left camera: build its image
    xs, ys = np.meshgrid(np.arange(200.0), np.arange(160.0))
    pts = cam.backproject(np.column_stack([xs.ravel(), ys.ravel()]), np.full(xs.size, 1000.0),
                          left)
    img = np.where(pts[:, 0] < 0.0, 20.0, 100.0).reshape(xs.shape)
    pair = rectify_pair(img, img, g)
    assert not pair.valid_left.all() and np.isfinite(pair.left).all()
    e = detect_edges(pair.left, threshold=8.0, bit_depth=7)
    # the step is at rectified column where X = 0 projects for the left (virtual) camera
    col = cam.project([[0.0, 0.0, 0.0]], g.virtual_pose("left"))[0][0, 0]
    assert len(e) > 100
    assert np.abs(e.x - col).max() < 1.5


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


def test_locate_points_are_the_block(block_sim):
    """Known answer: the block's top at z = 50 mm, its faces at x = 357.4 -+ 11.8 mm."""
    loc = locate(block_sim.capture)
    w = loc.world
    on_top = np.abs(w[:, 2] - 50.0) <= loc.z_bound
    assert on_top.mean() > 0.95
    centre_x = 400.0 - 43.3
    near_face = np.minimum(np.abs(w[:, 0] - (centre_x - 11.8)), np.abs(w[:, 0] - (centre_x + 11.8)))
    assert np.median(near_face) < 0.2
    # the left pixel in the grabbed image: the projection of the located world point
    uv, _ = SEED_CAMERA.project(w, block_sim.capture.pose_left)
    assert np.abs(uv - loc.left_pixel).max() < 0.05
    # eq. 9 bound: dD and ds terms plus d(disp) = 0.2 px at 1000 mm -> 7.8 mm
    assert np.median(loc.z_bound) == pytest.approx(0.5 + 0.4 + 0.2 * 1000 / 29.07, abs=0.1)


def test_cli_capture_then_locate_gives_the_demo_points(tmp_path, capsys):
    """`robostereo capture` + `robostereo locate` = the demo's block run (lift 0, seed 0)."""
    d = tmp_path / "cap"
    assert main(["capture", "--out", str(d), "--scene", "block", "--seed", "0"]) == 0
    assert main(["locate", str(d), "-o", str(tmp_path / "pts.csv"), "--ply",
                 str(tmp_path / "pts.ply")]) == 0
    out = capsys.readouterr().out
    assert "located" in out
    rows = np.genfromtxt(tmp_path / "pts.csv", delimiter=",", names=True)
    demo = run_block_experiment(setup=RigSetup(), seed=0, lifts_mm=(0.0, 79.65))
    ref = demo.heights[0].located
    assert rows.shape[0] == len(ref)
    assert np.allclose(np.column_stack([rows["X_w"], rows["Y_w"], rows["Z_w"]]), ref.world,
                       atol=1e-3)
    assert np.allclose(rows["z_bound"], ref.z_bound, atol=1e-3)
    assert (tmp_path / "pts.ply").read_bytes().startswith(b"ply")
    # default output: DIR/located.csv
    assert main(["locate", str(d)]) == 0
    assert (d / "located.csv").is_file()


def test_cli_pulley_capture_options(tmp_path):
    d = tmp_path / "pulley"
    assert main(["capture", "--out", str(d), "--scene", "pulley", "--direction", "30",
                 "--roll", "10", "--baseline", "25", "--center", "350", "100"]) == 0
    cap = read_capture(d)
    g = cap.epipolar
    assert g.baseline_mm == pytest.approx(25.0) and math.degrees(g.alpha) == pytest.approx(30.0)
    assert math.degrees(g.theta_l) == pytest.approx(10.0, abs=2.5)
    assert (g.origin[0], g.origin[1]) == pytest.approx((350.0, 100.0))


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


def test_demo_command(tmp_path, capsys):
    out = tmp_path / "figs"
    assert main(["demo", "--out", str(out), "--seed", "1"]) == 0
    text = capsys.readouterr().out
    assert "Table 5-1(a)" in text and "Hub-pulley" in text and "measured lift" in text
    assert sorted(p.name for p in out.iterdir()) == ["block_iterations.png", "points_3d.png",
                                                     "pulley_iterations.png"]
    assert main(["demo", "--seed", "-1", "--out", str(tmp_path / "x")]) == 2
    assert not (tmp_path / "x").exists()
