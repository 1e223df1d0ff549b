"""Write every command's outputs into a folder, or compare two such folders byte for byte.

A refactoring that must not change results is checked by a snapshot before and after::

    python benchmarks/outputs_snapshot.py write /tmp/before     # on the old commit
    python benchmarks/outputs_snapshot.py write /tmp/after      # on the new one
    python benchmarks/outputs_snapshot.py compare /tmp/before /tmp/after

``write`` runs the command line as a user would (``python -m robostereo.cli``): ``match``
on every developer scene with each method (window with and without paths and narrowing,
relaxation, the thesis's settings) and the edge list, ``rig`` on the scene with a
calibration, ``evaluate --json`` (times removed), the SCARA and six-axis demos with their
figures, ``capture`` + ``locate`` on both arms and on N-view captures (a line, a cross
and a six-axis line), ``demo --views``, ``simulate-handeye`` + ``handeye`` and ``plan``
(two views and ``--views auto``).  Printed times are removed before comparing; every
other byte must be equal.
``compare`` exits 1 and names each file that differs.
"""

from __future__ import annotations

import argparse
import filecmp
import json
import os
import re
import subprocess
import sys
from pathlib import Path

#: searched ranges: each scene's own, and two over 64 disparities (the narrowing pass)
RANGES = {
    "tsukuba": (0, 16),
    "venus": (0, 24),
    "motorcycle": (0, 64),
    "cloth3": (16, 96),
    "reindeer": (0, 112),
    "wood2": (16, 112),
}
_TIMES = re.compile(r"\d+(\.\d+)?\s*(ms|s)\b|\"[a-z_]*(seconds|_ms|time)[a-z_]*\":\s*[-0-9.e]+")


def _run(out: Path, name: str, *args: str) -> None:
    # OpenCV's threaded calibrateCamera differs in the 12th digit from run to run
    env = dict(os.environ, ROBOSTEREO_THREADS=os.environ.get("ROBOSTEREO_THREADS", "2"),
               OPENCV_FOR_THREADS_NUM="1")
    proc = subprocess.run([sys.executable, "-m", "robostereo.cli", *args], capture_output=True,
                          text=True, env=env, check=False)
    text = f"exit {proc.returncode}\n{proc.stdout}\n--- stderr\n{proc.stderr}"
    text = _TIMES.sub("<time>", text.replace(str(out), "<out>"))
    (out / f"{name}.log").write_text(text)
    if proc.returncode != 0:
        print(f"{name}: exit {proc.returncode}: {proc.stderr.strip()[-300:]}", file=sys.stderr)


def _scene_files(data: Path, scene: str) -> tuple[str, str]:
    index = json.loads((data / "scenes.json").read_text())["scenes"][scene]
    return str(data / index["left"]), str(data / index["right"])


def write(out: Path, data: Path) -> None:
    out.mkdir(parents=True, exist_ok=False)
    for scene, (lo, hi) in RANGES.items():
        left, right = _scene_files(data, scene)
        rng = ["--min-disparity", str(lo), "--max-disparity", str(hi)]
        for tag, extra in [("window", []), ("nopaths", ["--no-paths"]),
                           ("nocoarse", ["--no-coarse"]), ("relax", ["--method", "relaxation"]),
                           ("thesis", ["--seed-mode"])]:
            if tag in ("relax", "thesis") and scene not in ("tsukuba", "venus"):
                continue
            csv = out / f"{scene}-{tag}.csv"
            more = ["--edges", str(out / f"{scene}-edges.csv")] if tag == "window" else []
            _run(out, f"{scene}-{tag}", "match", left, right, *rng, "-o", str(csv), *more, *extra)
    scenes = [str(data / s) for s in RANGES]
    _run(out, "evaluate", "evaluate", *scenes, "--no-sgbm", "--json")
    mc = data / "motorcycle"
    _run(out, "rig", "rig", str(mc / "im0.png"), str(mc / "im1.png"), "--calibration",
         str(mc / "calib.txt"), "--min-disparity", "0", "--max-disparity", "64",
         "-o", str(out / "rig.csv"), "--ply", str(out / "rig.ply"))
    _run(out, "demo", "demo", "--out", str(out / "demo"))
    _run(out, "demo-six", "demo", "--robot", "six-axis", "--json", "--out", str(out / "demo-six"))
    for robot in ("adeptone", "six-axis"):
        cap = out / f"capture-{robot}"
        _run(out, f"capture-{robot}", "capture", "--out", str(cap), "--robot", robot)
        _run(out, f"locate-{robot}", "locate", str(cap), "-o", str(out / f"located-{robot}.csv"),
             "--ply", str(out / f"located-{robot}.ply"))
    for name, extra in [("views3", ["--views", "3", "--span", "40"]),
                        ("cross5", ["--views", "5", "--pattern", "cross", "--scene", "pulley"]),
                        ("six3", ["--views", "3", "--robot", "six-axis"])]:
        cap = out / f"capture-{name}"
        _run(out, f"capture-{name}", "capture", "--out", str(cap), *extra)
        _run(out, f"locate-{name}", "locate", str(cap), "-o", str(out / f"located-{name}.csv"),
             "--ply", str(out / f"located-{name}.ply"))
    _run(out, "demo-views", "demo", "--views", "3", "--json")
    _run(out, "plan-views", "plan", "--depth", "1000", "--accuracy", "1", "--views", "auto",
         "--json")
    views = out / "handeye-views"
    _run(out, "simulate-handeye", "simulate-handeye", "--out", str(views), "--views", "10")
    _run(out, "handeye", "handeye", str(views), "-o", str(out / "handeye-camera.yaml"))
    _run(out, "plan", "plan", "--depth", "1000", "--accuracy", "1", "--json")


def compare(a: Path, b: Path) -> int:
    names_a = {p.relative_to(a) for p in a.rglob("*") if p.is_file()}
    names_b = {p.relative_to(b) for p in b.rglob("*") if p.is_file()}
    bad = sorted(str(n) for n in names_a ^ names_b)
    for name in sorted(names_a & names_b):
        if not filecmp.cmp(a / name, b / name, shallow=False):
            bad.append(str(name))
    for name in bad:
        print(f"differs: {name}")
    print(f"{len(names_a & names_b)} files compared, {len(bad)} differ")
    return 1 if bad else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="verb", required=True)
    w = sub.add_parser("write", help="run the commands, outputs into a new folder")
    w.add_argument("out", type=Path)
    w.add_argument("--data", type=Path, default=Path(__file__).resolve().parents[2]
                   / "shared" / "data" / "stereo")
    c = sub.add_parser("compare", help="compare two snapshot folders byte for byte")
    c.add_argument("a", type=Path)
    c.add_argument("b", type=Path)
    args = parser.parse_args()
    if args.verb == "write":
        write(args.out, args.data)
        return 0
    return compare(args.a, args.b)


if __name__ == "__main__":
    raise SystemExit(main())
