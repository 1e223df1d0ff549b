"""Every command that writes refuses an input as output, two outputs on one path and a
folder as an output file, before any work; writes all or nothing; and leaves no
``.part`` behind, removing those of killed earlier runs."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import pytest
from synthetic import synthetic_pair

from robostereo.cli import main
from robostereo.io import remove_stale_parts
from robostereo.robot.capture import write_capture
from robostereo.robot.simulated.scara_rig import RigSetup, block_scene, simulate_capture

SRC = Path(__file__).resolve().parents[2] / "src"


@pytest.fixture(scope="module")
def captures(tmp_path_factory) -> tuple[Path, Path]:
    d = tmp_path_factory.mktemp("captures")
    scene = block_scene(RigSetup())
    for name, a in (("x", 0.0), ("y", 90.0)):
        sim = simulate_capture("block", setup=RigSetup(direction_deg=a), scene=scene)
        write_capture(d / name, sim.capture)
    return d / "x", d / "y"


def _snapshot(*folders: Path) -> dict[str, bytes]:
    return {str(p): p.read_bytes() for f in folders for p in sorted(f.iterdir()) if p.is_file()}


@pytest.mark.parametrize("case", ["yaml-of-second", "image", "same-two", "ply-folder"])
def test_fused_locate_refuses_bad_outputs_before_any_work(captures, tmp_path, capsys, case):
    x, y = captures
    before = _snapshot(x, y)
    (tmp_path / "plyd").mkdir()
    argv = {
        "yaml-of-second": ["-o", str(y / "capture.yaml")],
        "image": ["-o", str(x / "left.png")],
        "same-two": ["-o", str(tmp_path / "a.csv"), "--ply", str(tmp_path / "a.csv")],
        "ply-folder": ["--ply", str(tmp_path / "plyd")],
    }[case]
    assert main(["locate", str(x), "--fuse", str(y), *argv]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("robostereo: error: ")
    assert _snapshot(x, y) == before  # nothing overwritten, no located-fused.csv
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plyd"]


def test_locate_refuses_two_outputs_on_one_path(captures, tmp_path, capsys):
    x, _ = captures
    out = tmp_path / "x.csv"
    assert main(["locate", str(x), "-o", str(out), "--ply", str(out)]) == 2
    assert "same file" in capsys.readouterr().err
    assert not out.exists()


def _pair_files(d: Path) -> tuple[Path, Path]:
    left, right, _ = synthetic_pair(np.random.default_rng(3))
    paths = d / "left.png", d / "right.png"
    for p, img in zip(paths, (left, right), strict=True):
        cv2.imwrite(str(p), img)
    return paths


def test_stale_parts_of_killed_runs_are_removed_and_live_ones_kept(tmp_path, capsys):
    left, right = _pair_files(tmp_path)
    dead = tmp_path / ".out.csv.999999999-abcdefgh.part"  # no such process
    live = tmp_path / f".out.csv.{os.getppid()}-abcdefgh.part"  # a running process's
    other = tmp_path / ".notes.txt.999999999-abcdefgh.part"  # another target's
    for p in (dead, live, other):
        p.write_text("half")
    assert main(["match", str(left), str(right), "--min-disparity", "0",
                 "--max-disparity", "16", "-o", str(tmp_path / "out.csv")]) == 0
    assert not dead.exists() and live.exists() and other.exists()
    assert remove_stale_parts(tmp_path) == [other]
    old = tmp_path / ".out.csv.abcdefgh.part"  # the former naming, without a process id
    old.write_text("half")
    assert remove_stale_parts(tmp_path) == []  # young: could be a running old version
    os.utime(old, (time.time() - 7200, time.time() - 7200))
    assert remove_stale_parts(tmp_path) == [old]


def test_a_killed_runs_nested_part_is_removed_by_the_next_run(tmp_path, capsys):
    # write_csv writes atomically into the command's own temporary file: a run killed
    # between the two leaves the outer part and the inner one (named after the outer)
    left, right = _pair_files(tmp_path)
    outer = tmp_path / ".out.csv.999999999-abcdefgh.part"
    nested = tmp_path / "..out.csv.999999999-abcdefgh.part.999999999-ijklmnop.part"
    live = tmp_path / f"..out.csv.{os.getppid()}-abcdefgh.part.{os.getppid()}-x.part"
    other = tmp_path / "..notes.txt.999999999-abcdefgh.part.999999999-ijklmnop.part"
    for p in (outer, nested, live, other):
        p.write_text("half")
    assert main(["match", str(left), str(right), "--min-disparity", "0",
                 "--max-disparity", "16", "-o", str(tmp_path / "out.csv")]) == 0
    assert not outer.exists() and not nested.exists()
    assert live.exists() and other.exists()


def test_batch_removes_stale_parts_of_its_folder(tmp_path, capsys):
    inp = tmp_path / "in" / "p1"
    inp.mkdir(parents=True)
    _pair_files(inp)
    out = tmp_path / "out"
    out.mkdir()
    stale = out / ".p0.csv.999999999-abcdefgh.part"
    stale.write_text("half")
    assert main(["batch", str(tmp_path / "in"), "--out", str(out), "--min-disparity", "0",
                 "--max-disparity", "16", "--workers", "1"]) == 0
    assert not stale.exists()
    assert not [p for p in out.iterdir() if p.name.endswith(".part")]


def test_sigkill_leaves_at_most_parts_that_the_next_run_removes(tmp_path):
    """SIGKILL cannot be caught: whatever it leaves, the next run of the command removes
    (the kill lands at many moments over the runs, writing included)."""
    left, right = _pair_files(tmp_path)
    out = tmp_path / "out.csv"
    cmd = [sys.executable, "-m", "robostereo.cli", "match", str(left), str(right),
           "--min-disparity", "0", "--max-disparity", "16", "-o", str(out),
           "--edges", str(tmp_path / "edges.csv")]
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    p = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    while p.poll() is None and not any(q.name.endswith(".part") for q in tmp_path.iterdir()):
        time.sleep(0.001)
    p.send_signal(signal.SIGKILL)
    p.wait()
    r = subprocess.run(cmd, env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert not [q.name for q in tmp_path.iterdir() if q.name.endswith(".part")]
