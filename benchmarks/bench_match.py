"""Time robostereo's whole matcher against OpenCV's StereoSGBM on the same pairs.

Run:  python benchmarks/bench_match.py [--repeat N]

For every pair (the real scenes of ../shared/data/stereo and synthetic pairs of a few
sizes) both run in this one process on the same grey images and disparity range:
robostereo's ``match_stereo`` (edges, candidates, relaxation, acceptance) and
``cv2.StereoSGBM`` (blockSize 5, uniquenessRatio 10).  It prints the median time of
each, their ratio (SGBM time / robostereo time: above 1 means robostereo is faster)
and the peak traced memory of each (tracemalloc; OpenCV's internal buffers are not
traced: SGBM keeps about ``W * H * numDisparities * 2`` bytes of path costs besides).
Speed goals live here, never in the tests.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from robostereo.datasets import find_data_dir, load_scene
from robostereo.evaluation import sgbm_disparity
from robostereo.pipeline import match_stereo


def pairs() -> list[tuple[str, np.ndarray, np.ndarray, tuple[float, float]]]:
    from synthetic import synthetic_pair

    out = []
    d = find_data_dir()
    if d is not None:
        for name in ("tsukuba", "venus"):
            s = load_scene(d / name)
            out.append((name, s.left, s.right, s.disparity_range))
    rng = np.random.default_rng(0)
    for h, w in ((480, 640), (960, 1280)):
        left, right, _ = synthetic_pair(rng, height=h, width=w, disparities=(7.3, 11.65, 9.05))
        out.append((f"synthetic {w}x{h}", left, right, (4.0, 16.0)))
    return out


def _time(fn, repeat: int) -> float:
    fn()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def peak_mib(fn) -> float:
    """Peak of the memory traced while ``fn()`` runs once, MiB (tracemalloc: every
    NumPy array and Python object; OpenCV's internal C++ buffers are not traced, so
    SGBM's figure counts its input copies and output only)."""
    import tracemalloc

    tracemalloc.start()
    fn()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak / 2**20


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=15)
    args = ap.parse_args()
    import cv2

    print(f"OpenCV {cv2.__version__}, {cv2.getNumThreads()} threads; median of {args.repeat}")
    head = (f"{'pair':<20} {'robostereo ms':>14} {'SGBM ms':>9} {'ratio':>7} "
            f"{'robostereo MiB':>15} {'SGBM MiB':>9}")
    print(head)
    print("-" * len(head))
    for name, left, right, rng in pairs():
        t_ours = _time(lambda left=left, right=right, rng=rng: match_stereo(left, right, rng),
                       args.repeat)
        t_sgbm = _time(lambda left=left, right=right, rng=rng: sgbm_disparity(left, right, rng),
                       args.repeat)
        m_ours = peak_mib(lambda left=left, right=right, rng=rng: match_stereo(left, right, rng))
        m_sgbm = peak_mib(lambda left=left, right=right, rng=rng: sgbm_disparity(left, right, rng))
        print(f"{name:<20} {1000 * t_ours:>14.2f} {1000 * t_sgbm:>9.2f} "
              f"{t_sgbm / t_ours:>6.2f}x {m_ours:>15.1f} {m_sgbm:>9.1f}")


if __name__ == "__main__":
    main()
