"""Time robostereo's whole matcher against OpenCV's StereoSGBM on the same pairs.

Run:  python benchmarks/bench_match.py [--repeat N] [--no-memory] [--no-paths] [--no-coarse]

For every pair (the six real scenes of ../shared/data/stereo, motorcycle again with
wider disparity ranges, and synthetic pairs of two sizes) both run in this one process
on the same images and disparity range: robostereo's ``match_stereo`` (edges, window
costs, confidence, acceptance: the default window method) and ``cv2.StereoSGBM``
(blockSize 5, uniquenessRatio 10, P1 = 8*25, P2 = 32*25).  It prints the median time
of each (in rounds: each method twice, the second run timed), the median of the rounds' ratios
(SGBM time / robostereo time: above 1 means robostereo is faster) and the peak
memory each adds to a process: a fresh child process per method and pair, the
growth of its peak resident set over what it held after a warm-up on a small random
pair (Linux: free heap memory is given back with ``malloc_trim`` and the peak is reset
through ``/proc/self/clear_refs``, so imports and numba's compiled code are not
counted, every page either method touches is, OpenCV's own buffers too).
Speed goals live here, never in the tests.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from robostereo.datasets import find_data_dir, load_scene
from robostereo.evaluation import sgbm_disparity
from robostereo.matcher.pipeline import MatchParameters, match_stereo

SCENES = ("tsukuba", "venus", "motorcycle", "cloth3", "reindeer", "wood2")


def names() -> list[str]:
    """The pairs benchmarked, in order."""
    d = find_data_dir()
    out = [n for n in SCENES if d is not None and (d / n).is_dir()]
    if "motorcycle" in out:
        out += [f"motorcycle 0..{hi}" for hi in (64, 128, 256)]
    return [*out, "synthetic 640x480", "synthetic 1280x960"]


def pair(name: str) -> tuple[np.ndarray, np.ndarray, tuple[float, float]]:
    """Left, right and disparity range of the pair ``name`` (see :func:`names`)."""
    from synthetic import synthetic_pair

    if name.startswith("synthetic"):
        w, h = (int(v) for v in name.split()[1].split("x"))
        left, right, _ = synthetic_pair(np.random.default_rng(0), height=h, width=w,
                                        disparities=(7.3, 11.65, 9.05))
        return left, right, (4.0, 16.0)
    scene = name.split()[0]
    s = load_scene(find_data_dir() / scene)
    if " 0.." in name:
        return s.left, s.right, (0.0, float(name.split("..")[1]))
    return s.left, s.right, s.disparity_range


def _time_pair(ours, theirs, repeat: int) -> tuple[float, float, float]:
    """Median times of two calls and the median of the per-round ratios ``theirs /
    ours``.  Each round runs one call twice, then the other twice, and times the second
    run of each: the steady state of a matcher run frame after frame (its buffers and
    code warm, as in a user's loop), while a slow spell of the machine hits both alike."""
    t_ours, t_theirs = [], []
    for _ in range(repeat):
        for fn, out in ((ours, t_ours), (theirs, t_theirs)):
            fn()
            t = time.perf_counter()
            fn()
            out.append(time.perf_counter() - t)
    ratios = [b / a for a, b in zip(t_ours, t_theirs, strict=True)]
    return statistics.median(t_ours), statistics.median(t_theirs), statistics.median(ratios)


_CHILD = """
import sys, json
sys.path.insert(0, {tests!r})
import numpy as np
from bench_match import pair
from robostereo.evaluation import sgbm_disparity
from robostereo.matcher.pipeline import MatchParameters, match_stereo
params = MatchParameters(**{options!r})
fn = ((lambda a, b, r: match_stereo(a, b, r, params=params)) if {method!r} == "robostereo"
      else sgbm_disparity)
left, right, rng = pair({name!r})
warm = np.random.default_rng(0).integers(0, 255, (40, 200)).astype(np.uint8)
fn(warm, np.roll(warm, -3, axis=1), (0.0, 16.0))
def status(key):
    for line in open("/proc/self/status"):
        if line.startswith(key):
            return int(line.split()[1])
import ctypes, gc
gc.collect()
ctypes.CDLL("libc.so.6").malloc_trim(0)  # free heap back to the system: new pages count
open("/proc/self/clear_refs", "w").write("5")  # peak resident set := current
base = status("VmRSS:")
fn(left, right, rng)
print(json.dumps((status("VmHWM:") - base) / 1024.0))
"""


def peak_mib(method: str, name: str, options: dict[str, bool]) -> float:
    """Peak resident memory (MiB) that one run of ``method`` on pair ``name`` adds
    (robostereo with ``MatchParameters(**options)``)."""
    here = Path(__file__).resolve().parent
    code = _CHILD.format(tests=str(here.parent / "tests"), method=method, name=name,
                         options=options)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=here, check=True)
    return float(json.loads(out.stdout.strip().splitlines()[-1]))


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--no-memory", action="store_true", help="skip the memory children")
    ap.add_argument("--no-paths", action="store_true", help="robostereo without its paths")
    ap.add_argument("--no-coarse", action="store_true",
                    help="robostereo searching wide ranges whole")
    args = ap.parse_args()
    options = {"paths": not args.no_paths, "coarse": not args.no_coarse}
    params = MatchParameters(**options)
    import cv2

    print(f"OpenCV {cv2.__version__}, {cv2.getNumThreads()} threads; median of {args.repeat}; "
          f"robostereo paths {'on' if params.paths else 'off'}, "
          f"coarse {'on' if params.coarse else 'off'}")
    head = (f"{'pair':<20} {'edges':>6} {'robostereo ms':>14} {'SGBM ms':>9} {'ratio':>7} "
            f"{'robostereo MiB':>15} {'SGBM MiB':>9} {'mem ratio':>9}")
    print(head)
    print("-" * len(head))
    for name in names():
        left, right, rng = pair(name)
        n = len(match_stereo(left, right, rng, params=params).left_edges)
        t_ours, t_sgbm, ratio = _time_pair(
            lambda left=left, right=right, rng=rng: match_stereo(left, right, rng,
                                                                 params=params),
            lambda left=left, right=right, rng=rng: sgbm_disparity(left, right, rng),
            args.repeat)
        mem = ""
        if not args.no_memory:
            m_ours = peak_mib("robostereo", name, options)
            m_sgbm = peak_mib("sgbm", name, options)
            mem = f"{m_ours:>15.1f} {m_sgbm:>9.1f} {m_ours / max(m_sgbm, 0.1):>8.2f}x"
        print(f"{name:<20} {n:>6} {1000 * t_ours:>14.2f} {1000 * t_sgbm:>9.2f} "
              f"{ratio:>6.2f}x {mem}", flush=True)


if __name__ == "__main__":
    main()
