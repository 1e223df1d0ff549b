"""Tests for robostereo.batch (its inputs: batch_inputs) and ``robostereo batch``: local pool vs
Dask, resume, failures."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest
from synthetic import synthetic_pair

from robostereo.batch import BatchOptions, run_batch
from robostereo.batch_inputs import find_inputs, process_input
from robostereo.cli import main
from robostereo.errors import InputError

N_PAIRS = 20
RANGE = (4.0, 16.0)


def _write_pair(d: Path, seed: int, *, camera: bool, range_file: bool) -> None:
    left, right, _ = synthetic_pair(np.random.default_rng(seed), height=60, width=200)
    d.mkdir(parents=True)
    cv2.imwrite(str(d / "left.png"), left)
    cv2.imwrite(str(d / "right.png"), right)
    if camera:
        (d / "camera.yaml").write_text("fx: 800\nfy: 800\nbaseline_mm: 60\n")
    if range_file:
        (d / "disparity.yaml").write_text("min_disparity: 4\nmax_disparity: 16\n")


@pytest.fixture(scope="module")
def inputs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """20 pair folders: half with camera.yaml (3-D), a third with disparity.yaml."""
    root = tmp_path_factory.mktemp("batch") / "pairs"
    for k in range(N_PAIRS):
        _write_pair(root / f"pair{k:02d}", k, camera=k % 2 == 0, range_file=k % 3 == 0)
    return root


@pytest.fixture(scope="module")
def cluster():
    """One small in-process Dask cluster on loopback TCP (threads, no worker processes)."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, protocol="tcp://",
        host="127.0.0.1", dashboard_address=None,
    ) as c:  # fmt: skip
        yield c


def _csvs(d: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(d.glob("*.csv"))}


def test_local_and_dask_give_identical_csvs(inputs: Path, tmp_path: Path, cluster) -> None:
    opts = BatchOptions(disparity_range=RANGE)
    local = run_batch(inputs, tmp_path / "local", options=opts, workers=2)
    dask = run_batch(inputs, tmp_path / "dask", options=opts, scheduler=cluster.scheduler_address)
    assert local.failed == () and dask.failed == ()
    assert len(local.processed) == len(dask.processed) == N_PAIRS
    a, b = _csvs(tmp_path / "local"), _csvs(tmp_path / "dask")
    assert len(a) == N_PAIRS + 1 and a == b  # 20 results + summary.csv, byte for byte
    rows = local.rows
    assert [r["input"] for r in rows] == [f"pair{k:02d}" for k in range(N_PAIRS)]
    assert all(r["matched_percent"] > 70 for r in rows)
    # camera.yaml gives 3-D points; disparity.yaml and the batch range both apply
    assert rows[0]["points_3d"] == rows[0]["matched"] > 0 and rows[1]["points_3d"] == 0
    head = (tmp_path / "local" / "pair00.csv").read_text().splitlines()[0]
    assert head.endswith("X,Y,Z,z_bound")
    assert all(r["min_disparity"] == 4.0 for r in rows)


def test_interrupted_batch_resumes_without_redoing(inputs: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    opts = BatchOptions(disparity_range=RANGE)

    def stop_after_7(done: int, total: int, row: dict) -> None:
        if done == 7:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_batch(inputs, out, options=opts, workers=1, progress=stop_after_7)
    finished = sorted(p.stem for p in out.glob("*.json"))
    assert finished == [f"pair{k:02d}" for k in range(7)]
    assert not (out / "summary.csv").exists()
    stamps = {p.name: p.stat().st_mtime_ns for p in out.glob("pair0[0-6].*")}
    # an interruption between the two writes: a CSV without its JSON is redone
    (out / "pair06.json").unlink()
    seen: list[str] = []
    rep = run_batch(inputs, out, options=opts, workers=1,
                    progress=lambda d, t, r: seen.append(r["input"]))
    assert rep.skipped == tuple(f"pair{k:02d}" for k in range(6))
    assert rep.processed == tuple(f"pair{k:02d}" for k in range(6, N_PAIRS))
    assert len(seen) == N_PAIRS and rep.failed == ()
    for name, t in stamps.items():
        if not name.startswith("pair06"):
            assert (out / name).stat().st_mtime_ns == t, name
    # a finished batch does nothing but rewrite the summary
    again = run_batch(inputs, out, options=opts, workers=1)
    assert again.processed == () and len(again.skipped) == N_PAIRS
    assert (out / "summary.csv").read_text() == (rep.summary).read_text()


def _bad_inputs(root: Path) -> None:
    _write_pair(root / "a_good", 1, camera=True, range_file=True)
    (root / "b_empty").mkdir()
    _write_pair(root / "c_unreadable", 2, camera=False, range_file=True)
    (root / "c_unreadable" / "right.png").write_bytes(b"not a png at all")
    _write_pair(root / "d_size", 3, camera=False, range_file=True)
    cv2.imwrite(str(root / "d_size" / "right.png"), np.zeros((60, 190), np.uint8))
    _write_pair(root / "e_camera", 4, camera=False, range_file=True)
    (root / "e_camera" / "camera.yaml").write_text("fx: .nan\nfy: 800\nbaseline_mm: 60\n")
    (root / "f_other").mkdir()
    (root / "f_other" / "notes.txt").write_text("hello")
    _write_pair(root / "g_norange", 5, camera=False, range_file=False)
    _write_pair(root / "h_good", 6, camera=False, range_file=True)


def test_failed_inputs_are_reported_and_the_rest_go_on(tmp_path: Path, capsys) -> None:
    root = tmp_path / "in"
    _bad_inputs(root)
    out = tmp_path / "out"
    rc = main(["batch", str(root), "--out", str(out), "--workers", "1"])
    cap = capsys.readouterr()
    assert rc == 2
    errs = [ln for ln in cap.err.splitlines() if ln.startswith("robostereo: error:")]
    assert len(errs) == 5  # b_empty, an empty folder, is no input: left out
    expect = {
        "c_unreadable": "right.png: cannot decode image",
        "d_size": "right.png: image is 190 x 60 (W x H), the left image 200 x 60",
        "e_camera": "camera.yaml: fx must be finite",
        "f_other": "f_other: neither a pair folder",
        "g_norange": "g_norange: no disparity.yaml and no batch-wide disparity range",
    }
    for name, text in expect.items():
        assert any(name in e and text in e for e in errs), (name, errs)
    assert "7 inputs: 2 processed, 0 already finished, 5 failed" in cap.out
    summary = (out / "summary.csv").read_text().splitlines()
    assert summary[0].startswith("input,status,kind")
    assert [ln.split(",")[1] for ln in summary[1:]] == ["ok"] + ["error"] * 5 + ["ok"]
    assert "b_empty" not in "".join(summary)
    assert sorted(p.name for p in out.glob("*.csv")) == ["a_good.csv", "h_good.csv",
                                                         "summary.csv"]
    # a rerun retries the failed inputs only
    rc = main(["batch", str(root), "--out", str(out), "--workers", "1",
               "--min-disparity", "4", "--max-disparity", "16"])
    assert rc == 2
    assert "7 inputs: 1 processed, 2 already finished, 4 failed" in capsys.readouterr().out


def test_failed_input_on_dask(tmp_path: Path, cluster) -> None:
    root = tmp_path / "in"
    _bad_inputs(root)
    rep = run_batch(root, tmp_path / "out", scheduler=cluster.scheduler_address)
    assert set(rep.failed) == {"c_unreadable", "d_size", "e_camera", "f_other", "g_norange"}
    assert "c_unreadable/right.png: cannot decode image" in rep.errors["c_unreadable"]


def test_rig_calibration_of_another_size(tmp_path: Path) -> None:
    from robostereo.geometry.calibration import StereoCalibration
    from robostereo.io.calibration_files import write_opencv_calibration

    root = tmp_path / "in"
    _write_pair(root / "p", 1, camera=False, range_file=True)
    K = np.array([[800.0, 0, 99.5], [0, 800.0, 29.5], [0, 0, 1]])
    good = write_opencv_calibration(
        StereoCalibration(K, None, K, None, np.eye(3), [-60, 0, 0], (200, 60)), tmp_path / "g.yml")
    bad = write_opencv_calibration(
        StereoCalibration(K, None, K, None, np.eye(3), [-60, 0, 0], (640, 480)), tmp_path / "b.yml")
    rep = run_batch(root, tmp_path / "o1", options=BatchOptions(calibration=str(good)),
                    workers=1)
    assert rep.failed == () and rep.rows[0]["kind"] == "rig" and rep.rows[0]["points_3d"] > 0
    rep = run_batch(root, tmp_path / "o2", options=BatchOptions(calibration=str(bad)),
                    workers=1)
    assert rep.failed == ("p",)
    assert "left.png: image is 200 x 60 (W x H), calibration 640 x 480" in rep.errors["p"]


def test_capture_folder(tmp_path: Path, monkeypatch) -> None:
    root = tmp_path / "in"
    cap_dir = root / "cap"
    from robostereo.geometry.camera import Camera
    from robostereo.geometry.poses import Pose
    from robostereo.robot.capture import Capture, write_capture

    left, right, _ = synthetic_pair(np.random.default_rng(3), height=120, width=320)
    c = Capture(left=left, right=right, camera=Camera(image_size=(320, 120)),
                pose_left=Pose(-10.0, 0.0, 900.0, 0.0), pose_right=Pose(10.0, 0.0, 900.0, 0.0),
                bit_depth=8, disparity_range=RANGE)
    root.mkdir()
    write_capture(cap_dir, c)
    rep = run_batch(root, tmp_path / "out", workers=1)
    assert rep.failed == (), rep.errors
    row = rep.rows[0]
    assert row["kind"] == "capture" and row["matched"] > 0 and row["points_3d"] == row["matched"]
    head = (tmp_path / "out" / "cap.csv").read_text().splitlines()[0]
    assert head.startswith("X_w,Y_w,Z_w")
    # without the capture module: a clear one-line error naming capture.yaml
    monkeypatch.setitem(sys.modules, "robostereo.robot.capture", None)
    row = process_input(cap_dir, tmp_path)
    assert row["status"] == "error" and "capture.yaml: capture folders need" in row["error"]


def test_find_inputs(tmp_path: Path, inputs: Path) -> None:
    assert find_inputs(inputs / "pair03") == [inputs / "pair03"]  # one input folder
    assert len(find_inputs(inputs)) == N_PAIRS
    with pytest.raises(InputError, match="no input folders"):
        find_inputs(tmp_path)
    with pytest.raises(InputError, match="input folder not found"):
        find_inputs(tmp_path / "missing")
    row = json.loads(json.dumps(process_input(tmp_path / "missing", tmp_path)))
    assert row["status"] == "error"


def test_summary_says_which_pairs_the_checks_corrected(tmp_path: Path) -> None:
    """A right view moved down 1.5 px, one 35 % brighter, and one as it was: the summary
    names the moved rows and the mapped grey levels of each, and only of those."""
    blurred = cv2.GaussianBlur(np.random.default_rng(3).random((160, 320)), (0, 0), 1.2)
    texture = cv2.normalize(blurred, None, 0, 255, cv2.NORM_MINMAX).astype(np.uint8)
    right = np.roll(texture, -11, axis=1)  # 11 px disparity
    moved = cv2.warpAffine(right, np.float32([[1, 0, 0], [0, 1, 1.5]]), (320, 160),
                           flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    bright = np.clip(np.rint(1.35 * right.astype(float) + 6), 0, 255).astype(np.uint8)
    for name, r in (("a_plain", right), ("b_rows", moved), ("c_bright", bright)):
        (tmp_path / "in" / name).mkdir(parents=True)
        cv2.imwrite(str(tmp_path / "in" / name / "left.png"), texture)
        cv2.imwrite(str(tmp_path / "in" / name / "right.png"), r)
    with pytest.warns(Warning, match="rows of the two views disagree"):
        rep = run_batch(tmp_path / "in", tmp_path / "out",
                        options=BatchOptions(disparity_range=(4.0, 16.0)), workers=1)
    rows = {r["input"]: r for r in rep.rows}
    assert [rows[n]["rows_moved"] for n in ("a_plain", "b_rows", "c_bright")] == [0, 1, 0]
    assert [rows[n]["grey_mapped"] for n in ("a_plain", "b_rows", "c_bright")] == [0, 0, 1]
    assert abs(float(rows["b_rows"]["row_offset_px"]) - 1.5) < 0.2
    assert abs(float(rows["a_plain"]["row_offset_px"])) < 0.2
    header = (tmp_path / "out" / "summary.csv").read_text().splitlines()[0].split(",")
    assert {"row_offset_px", "row_tilt_px", "row_stretch_px", "rows_moved",
            "grey_mapped"} <= set(header)


# -- N-view capture folders ------------------------------------------------------------


@pytest.fixture(scope="module")
def mixed(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A pair folder, a two-view capture folder and an N-view one (three views of the
    block over 40 mm: ``capture --views 3 --span 40``), side by side."""
    from robostereo.geometry.camera import Camera
    from robostereo.geometry.poses import Pose
    from robostereo.robot.capture import Capture, write_capture
    from robostereo.robot.simulated.grab_views import simulate_views
    from robostereo.robot.views.views_folder import write_views_capture

    root = tmp_path_factory.mktemp("mixed") / "in"
    _write_pair(root / "a_pair", 1, camera=True, range_file=True)
    left, right, _ = synthetic_pair(np.random.default_rng(3), height=120, width=320)
    write_capture(root / "b_two", Capture(
        left=left, right=right, camera=Camera(image_size=(320, 120)),
        pose_left=Pose(-10.0, 0.0, 900.0, 0.0), pose_right=Pose(10.0, 0.0, 900.0, 0.0),
        bit_depth=8, disparity_range=RANGE))
    write_views_capture(root / "c_views",
                        simulate_views("block", count=3, pattern="line", span_mm=40.0).capture)
    return root


def test_n_view_folders_are_located_as_locate_does_beside_pairs_and_two_views(
        mixed: Path, tmp_path: Path) -> None:
    """``batch`` refused every N-view folder ('unknown key views') that ``locate`` takes:
    now its CSV and PLY are ``locate``'s, byte for byte, its row kind ``views``."""
    out = tmp_path / "out"
    rep = run_batch(mixed, out, options=BatchOptions(ply=True), workers=1)
    assert rep.failed == (), rep.errors
    rows = {r["input"]: r for r in rep.rows}
    assert [rows[n]["kind"] for n in ("a_pair", "b_two", "c_views")] == [
        "pair", "capture", "views"]
    assert main(["locate", str(mixed / "c_views"), "-o", str(tmp_path / "l.csv"),
                 "--ply", str(tmp_path / "l.ply")]) == 0
    assert (out / "c_views.csv").read_bytes() == (tmp_path / "l.csv").read_bytes()
    assert (out / "c_views.ply").read_bytes() == (tmp_path / "l.ply").read_bytes()
    n = len((tmp_path / "l.csv").read_text().splitlines()) - 1
    views = rows["c_views"]
    assert n > 100 and views["matched"] == views["points_3d"] == n
    assert views["output"] == "c_views.csv" and views["status"] == "ok"
    # the two views' matcher's columns have no meaning here: blank, never a made-up 0
    blank = ("edges_left", "edges_right", "matched_percent", "min_disparity",
             "max_disparity", "row_offset_px", "rows_moved", "grey_mapped", "error")
    assert all(views[c] == "" for c in blank)
    line = next(ln for ln in (out / "summary.csv").read_text().splitlines()
                if ln.startswith("c_views,"))
    assert line == f"c_views,ok,views,,,{n},,{n},,,,,,,,c_views.csv,"


def test_a_finished_n_view_folder_is_skipped_and_redone_when_a_view_changes(
        mixed: Path, tmp_path: Path) -> None:
    import os
    import shutil

    import yaml

    root = tmp_path / "in"
    shutil.copytree(mixed, root)
    views = root / "c_views"
    # one view's image in a subfolder: its changes count too
    (views / "imgs").mkdir()
    (views / "view_02.png").rename(views / "imgs" / "view_02.png")
    data = yaml.safe_load((views / "capture.yaml").read_text())
    data["views"][2]["image"] = "imgs/view_02.png"
    (views / "capture.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    out = tmp_path / "out"
    first = run_batch(root, out, workers=1)
    assert first.failed == () and "c_views" in first.processed
    stamp = (out / "c_views.csv").stat().st_mtime_ns
    again = run_batch(root, out, workers=1)
    assert again.processed == () and "c_views" in again.skipped
    assert (out / "c_views.csv").stat().st_mtime_ns == stamp
    st = (views / "imgs" / "view_02.png").stat()
    os.utime(views / "imgs" / "view_02.png", ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))
    redo = run_batch(root, out, workers=1)
    assert redo.processed == redo.redone == ("c_views",)


def test_n_view_folders_on_dask_give_the_local_outputs(mixed: Path, tmp_path: Path,
                                                       cluster) -> None:
    local = run_batch(mixed, tmp_path / "local", workers=2)
    dask = run_batch(mixed, tmp_path / "dask", scheduler=cluster.scheduler_address)
    assert local.failed == dask.failed == ()
    assert [r["kind"] for r in dask.rows] == ["pair", "capture", "views"]
    assert _csvs(tmp_path / "local") == _csvs(tmp_path / "dask")
