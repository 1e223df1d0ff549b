"""Batches: reruns with other options redo, workers die with the main process."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import pytest
from synthetic import synthetic_pair

from robostereo.batch import BatchOptions, run_batch
from robostereo.cli import main

RANGE = (4.0, 16.0)


def _pair(d: Path, seed: int, *, camera: bool = True, tile: int = 1) -> None:
    left, right, _ = synthetic_pair(np.random.default_rng(seed), height=60, width=200)
    d.mkdir(parents=True)
    cv2.imwrite(str(d / "left.png"), np.tile(left, (tile, tile)))
    cv2.imwrite(str(d / "right.png"), np.tile(right, (tile, tile)))
    if camera:
        (d / "camera.yaml").write_text("fx: 800\nfy: 800\nbaseline_mm: 60\n")


def test_rerun_with_other_options_redoes(tmp_path: Path) -> None:
    root, out = tmp_path / "in", tmp_path / "out"
    _pair(root / "a", 1)
    _pair(root / "b", 2, camera=False)
    first = run_batch(root, out, options=BatchOptions(disparity_range=RANGE), workers=1)
    assert first.processed == ("a", "b") and first.redone == ()
    again = run_batch(root, out, options=BatchOptions(disparity_range=RANGE), workers=1)
    assert again.skipped == ("a", "b") and again.processed == ()
    # --ply added: redone, and a has its PLY (b has no camera: no 3-D, no PLY)
    ply = run_batch(root, out, options=BatchOptions(disparity_range=RANGE, ply=True), workers=1)
    assert ply.redone == ("a", "b") and ply.failed == ()
    assert (out / "a.ply").is_file() and not (out / "b.ply").exists()
    # another range: redone, the CSV follows it
    narrow = BatchOptions(disparity_range=(4.0, 5.0), ply=True)
    rep = run_batch(root, out, options=narrow, workers=1)
    assert rep.redone == ("a", "b") and rep.rows[0]["max_disparity"] == 5.0
    # --ply dropped: the old PLY is removed with the redo
    rep = run_batch(root, out, options=BatchOptions(disparity_range=(4.0, 5.0)), workers=1)
    assert rep.redone == ("a", "b") and not (out / "a.ply").exists()
    # a marker edited by hand (or from an older robostereo): redone, not a crash
    (out / "b.json").write_text('{"status": "ok", "output": "b.csv", "signature": "x"}')
    rep = run_batch(root, out, options=BatchOptions(disparity_range=(4.0, 5.0)), workers=1)
    assert rep.redone == ("b",) and rep.skipped == ("a",)
    # an input file changed: that input is redone, the other skipped
    (root / "a" / "camera.yaml").write_text("fx: 900\nfy: 900\nbaseline_mm: 60\n")
    rep = run_batch(root, out, options=BatchOptions(disparity_range=(4.0, 5.0)), workers=1)
    assert rep.redone == ("a",) and rep.skipped == ("b",)


def test_output_folder_that_is_an_input(tmp_path: Path) -> None:
    from robostereo.errors import InputError

    _pair(tmp_path / "in" / "a", 1)
    with pytest.raises(InputError, match="the output folder is an input folder"):
        run_batch(tmp_path / "in" / "a", tmp_path / "in" / "a", workers=1)
    assert sorted(p.name for p in (tmp_path / "in" / "a").iterdir()) == [
        "camera.yaml", "left.png", "right.png"]


def test_unwritable_output_folder(tmp_path: Path, monkeypatch) -> None:
    from robostereo.errors import InputError

    _pair(tmp_path / "in" / "a", 1)
    (tmp_path / "out").mkdir()
    real = os.access
    monkeypatch.setattr(os, "access", lambda p, mode: False if Path(p) == tmp_path / "out"
                        else real(p, mode))  # as if read-only (root may write anyway)
    with pytest.raises(InputError, match="output folder is not writable"):
        run_batch(tmp_path / "in", tmp_path / "out", workers=1)


def test_batch_ply_with_no_3d_points_is_finished(tmp_path: Path) -> None:
    root, out = tmp_path / "in", tmp_path / "out"
    d = root / "flat"
    d.mkdir(parents=True)
    cv2.imwrite(str(d / "left.png"), np.full((40, 60), 90, np.uint8))
    cv2.imwrite(str(d / "right.png"), np.full((40, 60), 90, np.uint8))
    (d / "camera.yaml").write_text("fx: 800\nfy: 800\nbaseline_mm: 60\n")
    opts = BatchOptions(disparity_range=RANGE, ply=True)
    rep = run_batch(root, out, options=opts, workers=1)
    assert rep.failed == () and rep.rows[0]["points_3d"] == 0
    assert b"element vertex 0" in (out / "flat.ply").read_bytes()
    assert run_batch(root, out, options=opts, workers=1).skipped == ("flat",)


def test_other_calibration_contents_redo(tmp_path: Path, capsys) -> None:
    from robostereo.geometry.calibration import StereoCalibration
    from robostereo.io.calibration_files import write_opencv_calibration

    root, out = tmp_path / "in", tmp_path / "out"
    _pair(root / "p", 1, camera=False)
    K = np.array([[800.0, 0, 99.5], [0, 800.0, 29.5], [0, 0, 1]])
    cal = tmp_path / "rig.yml"
    write_opencv_calibration(StereoCalibration(K, None, K, None, np.eye(3), [-60, 0, 0],
                                               (200, 60)), cal)
    args = ["batch", str(root), "--out", str(out), "--workers", "1", "--calibration", str(cal),
            "--min-disparity", "4", "--max-disparity", "16"]
    assert main(args) == 0
    assert main(args) == 0
    assert "1 inputs: 0 processed, 1 already finished" in capsys.readouterr().out
    z1 = (out / "p.csv").read_text()
    write_opencv_calibration(StereoCalibration(K, None, K, None, np.eye(3), [-120, 0, 0],
                                               (200, 60)), cal)  # same path, other baseline
    assert main(args) == 0
    cap = capsys.readouterr()
    assert "1 inputs: 1 processed, 0 already finished" in cap.out
    assert "1 finished input was made with other options or input files: redone" in cap.err
    assert (out / "p.csv").read_text() != z1


# -- the main process killed: no worker stays behind -----------------------------------


def _children(pid: int) -> list[int]:
    kids = []
    for p in Path("/proc").iterdir():
        if not p.name.isdigit():
            continue
        try:
            fields = (p / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            kids.append(int(p.name))
    return kids


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"  # a zombie has ended; only its parent's reaping is left


def _outputs(out: Path) -> set[str]:
    return {p.name for p in out.glob("*") if not p.name.startswith(".")}


@pytest.fixture(scope="module")
def slow_inputs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Four large pairs: each takes a worker a second or more."""
    root = tmp_path_factory.mktemp("slow") / "in"
    _pair(root / "p0", 0, camera=False, tile=20)
    for k in range(1, 4):
        shutil.copytree(root / "p0", root / f"p{k}")
    return root


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGKILL],
                         ids=["SIGINT", "SIGTERM", "SIGKILL"])
def test_killing_the_main_process_leaves_no_worker(slow_inputs: Path, tmp_path: Path,
                                                   sig: signal.Signals) -> None:
    proc = subprocess.Popen(
        [sys.executable, "-m", "robostereo.cli", "batch", str(slow_inputs), "--out",
         str(tmp_path / "out"), "--min-disparity", "4", "--max-disparity", "16",
         "--workers", "2"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        # a shell's background job ignores SIGINT and its children inherit that: give the
        # batch the default, as a user's terminal does
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        deadline = time.monotonic() + 60
        kids: list[int] = []
        while time.monotonic() < deadline and proc.poll() is None:
            kids = _children(proc.pid)
            if len(kids) >= 2:  # the two workers (and the resource tracker)
                break
            time.sleep(0.02)
        assert len(kids) >= 2, "the batch started no worker processes"
        time.sleep(0.2)  # let them take up their first inputs
        assert proc.poll() is None, "the batch ended before it could be killed"
        proc.send_signal(sig)
        written = _outputs(tmp_path / "out")
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate(timeout=30)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and any(_alive(k) for k in kids):
        time.sleep(0.1)
    assert [k for k in kids if _alive(k)] == []
    # a worker left running would finish its input and write it: nothing new may appear
    # (files written before the signal are the batch's; it did not get to the summary)
    assert _outputs(tmp_path / "out") == written
    assert not (tmp_path / "out" / "summary.csv").exists()
    if sig == signal.SIGINT:
        assert proc.returncode == 130
        assert err.strip() == "robostereo: interrupted"
    elif sig == signal.SIGTERM:
        assert proc.returncode == 143
        assert err.strip() == "robostereo: terminated"
    else:
        assert proc.returncode == -signal.SIGKILL
    for k in kids:  # nothing to clean up, but never leave a process behind
        if _alive(k):
            os.kill(k, signal.SIGKILL)


def test_local_workers_share_the_cores(monkeypatch):
    """A local worker gets its share of the cores for the matcher's threads, unless
    ROBOSTEREO_THREADS says otherwise."""
    from robostereo import batch_workers

    monkeypatch.setattr(batch_workers, "die_with_parent", lambda parent: None)
    monkeypatch.delenv("ROBOSTEREO_THREADS", raising=False)
    batch_workers.start_worker(os.getpid(), 3)
    assert os.environ["ROBOSTEREO_THREADS"] == "3"
    monkeypatch.setenv("ROBOSTEREO_THREADS", "5")
    batch_workers.start_worker(os.getpid(), 1)
    assert os.environ["ROBOSTEREO_THREADS"] == "5"
