"""Time robostereo's whole matcher against OpenCV's dense matchers, per core and all cores.

Run:  python benchmarks/bench_match.py [--repeat N] [--threads per-core|all|both]
                                      [--no-memory] [--no-paths] [--no-coarse] [--contour]
                                      [--profile] [--write-results PATH] [--write-memory PATH]

For every pair (the six real scenes of ../shared/data/stereo, motorcycle again with
wider disparity ranges, and synthetic pairs of two sizes) all run in this one process on
the same grey images and disparity range: robostereo's ``match_stereo`` (edges, window
costs, confidence, acceptance: the default window method) and OpenCV's
``StereoSGBM`` in ``MODE_SGBM`` and in ``MODE_SGBM_3WAY`` (its fastest: blockSize 5,
uniquenessRatio 10, P1 = 8*25, P2 = 32*25) and ``StereoBM`` (blockSize 9, OpenCV's
defaults otherwise), each searching ``numDisparities`` = the range rounded up to 16.

Two tables: *per core* (robostereo with ``ROBOSTEREO_THREADS=1``, OpenCV with
``cv2.setNumThreads(1)``) and *all cores* (each with the threads it takes by default).
Each gives the median time of each method (in rounds: each method twice, the second run
timed, the steady state of a frame loop while a slow spell of the machine hits all
alike) and the median of the rounds' ratios (peer time / robostereo time: above 1
means robostereo is faster).  With memory, the peak memory robostereo and MODE_SGBM
add to a process: a fresh child process per method and pair, the growth of its peak
resident set over what it held after a warm-up on a small random pair (Linux: free
heap memory is given back with ``malloc_trim`` and the peak is reset through
``/proc/self/clear_refs``, so imports and numba's compiled code are not counted (robostereo's
warm-up pair is textured enough for every stage to run, the rows check included, and is
also matched over a wide range, so that the half-size narrowing's OpenCV code, some
0.4 MiB of pages, is not counted on the wide-range pairs), every
page either method touches is, OpenCV's own buffers too).
With ``--cpu-time`` the per-core table counts the CPU time of the calling thread
(``time.thread_time``; with one thread every method runs there) instead of the time
that passed: on a machine shared with other work, the time the others take is left
out.  With ``--profile`` it prints instead where robostereo's time goes, on one thread: the
whole ``match_stereo``, its edge stage (both images), its window stage
(``window_match``) and within that the half-size narrowing of a wide range, the
window-cost pass (``window_costs``), the part of it the paths along the rows take (the
pass without them subtracted) and the rest (evidence, right edge points, confidence),
the window-cost pass over one disparity (census, Sobel, rows and the per-point reading
that do not grow with the range) and a third of ``MODE_SGBM_3WAY``'s time (the whole
match's budget for 3x it), each timed alone in rounds as CPU time of the thread
(``time.thread_time``: a loaded machine slows it little).  ``--write-results PATH`` and
``--write-memory PATH`` also write the time tables and the memory table as the results
page's data files (``docs/results/speed.json``, ``docs/results/memory.json``).
Speed goals live here, never in the tests.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from results_file import write_results

from robostereo.datasets import find_data_dir, load_scene
from robostereo.evaluation import sgbm_input
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


def _time_rounds(fns: dict[str, object], repeat: int, clock=time.perf_counter
                 ) -> dict[str, tuple[float, float]]:
    """Median time of each call and the median of the per-round ratios ``time /
    time of the first call``.  Each round runs every call twice and times the second
    run: the steady state of a matcher run frame after frame (its buffers and code
    warm, as in a user's loop), while a slow spell of the machine hits all alike."""
    times: dict[str, list[float]] = {k: [] for k in fns}
    for _ in range(repeat):
        for key, fn in fns.items():
            fn()  # type: ignore[operator]
            t = clock()
            fn()  # type: ignore[operator]
            times[key].append(clock() - t)
    first = next(iter(fns))
    return {k: (statistics.median(v), statistics.median(
        [b / a for a, b in zip(times[first], v, strict=True)])) for k, v in times.items()}


def opencv_peer(kind: str, left: np.ndarray, right: np.ndarray,
                disparity_range: tuple[float, float]):
    """A call that runs OpenCV's matcher ``kind`` (``sgbm``, ``sgbm-3way``, ``bm``) on
    the grey pair over the range (``numDisparities`` rounded up to 16)."""
    import cv2

    a, b = sgbm_input(left), sgbm_input(right)
    lo = int(np.floor(disparity_range[0]))
    n = int(np.ceil((np.floor(disparity_range[1]) - lo + 1) / 16.0) * 16)
    if kind == "bm":
        m = cv2.StereoBM_create(numDisparities=n, blockSize=9)
        m.setMinDisparity(lo)
    else:
        mode = cv2.STEREO_SGBM_MODE_SGBM_3WAY if kind == "sgbm-3way" else \
            cv2.STEREO_SGBM_MODE_SGBM
        m = cv2.StereoSGBM_create(minDisparity=lo, numDisparities=n, blockSize=5,
                                  uniquenessRatio=10, P1=8 * 25, P2=32 * 25,
                                  disp12MaxDiff=-1, mode=mode)
    return lambda: m.compute(a, b)


PEERS = ("sgbm", "sgbm-3way", "bm")


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
# a warm-up that loads the method's code: for robostereo a pair on which every stage
# runs (the rows check's kernel needs some tens of well-structured matches), so that
# loading compiled code is not counted as memory; OpenCV's is loaded by any call
import cv2
warm = np.random.default_rng(0).integers(0, 255, (40, 200)).astype(np.uint8)
if {method!r} == "robostereo":
    noise = np.random.default_rng(0).random((160, 320))
    warm = cv2.normalize(cv2.GaussianBlur(noise, (0, 0), 1.2), None, 0, 255,
                         cv2.NORM_MINMAX).astype(np.uint8)
    fn(warm, np.roll(warm, -3, axis=1), (0.0, 16.0))
    fn(warm, np.roll(warm, -3, axis=1), (0.0, 100.0))  # a wide range: the half-size pass
    warm = np.dstack([warm] * 3)  # and colour: the developer scenes are
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


def _stage_times(name: str, repeat: int, params: MatchParameters) -> dict[str, float]:
    """Median ms of each stage of robostereo on pair ``name`` (see :func:`profile`)."""
    from robostereo.matcher.edges import detect_edges
    from robostereo.matcher.grey_levels import to_grey
    from robostereo.matcher.window_costs import PATH_PENALTIES, coarse_range, window_costs
    from robostereo.matcher.window_match import COARSE_MIN_DISPARITIES, window_match

    left, right, rng = pair(name)
    p = params
    res = match_stereo(left, right, rng, params=p)
    ga, gb = to_grey(left), to_grey(right)
    el, er = res.left_edges, res.right_edges
    e, wc = el, res.window.costs
    searched = (wc.d_min, wc.d_min + wc.n_disparities - 1)
    whole = (int(np.floor(rng[0])), int(np.ceil(rng[1])))
    wide = p.coarse and whole[1] - whole[0] + 1 > COARSE_MIN_DISPARITIES
    paths = PATH_PENALTIES if p.paths else None
    calls = {
        "match": lambda: match_stereo(left, right, rng, params=p),
        "edges": lambda: [detect_edges(im, threshold=t, row_step=p.row_step,
                                       subpixel=p.subpixel, grey=to_grey(im),
                                       edge_blur_px=p.edge_blur_px)
                          for im, t in ((left, p.threshold),
                                        (right, p.threshold * p.right_threshold_ratio))],
        "window": lambda: window_match(el, er, ga, gb, res.disparity_range,
                                       gradient_truncation=p.gradient_truncation,
                                       weights=p.weights, profile_scale=p.profile_scale,
                                       path_penalties=paths, coarse=p.coarse),
        "narrow": (lambda: coarse_range(ga, gb, e.row, e.column, whole)) if wide
        else (lambda: None),
        "costs": lambda: window_costs(ga, gb, e.row, e.column, searched, path_penalties=paths),
        "no paths": lambda: window_costs(ga, gb, e.row, e.column, searched,
                                         path_penalties=None),
        "one disparity": lambda: window_costs(ga, gb, e.row, e.column,
                                              (searched[0], searched[0]), path_penalties=paths),
        "3way": opencv_peer("sgbm-3way", left, right, rng),
    }
    times: dict[str, list[float]] = {k: [] for k in calls}
    for _ in range(repeat):
        for key, fn in calls.items():
            fn()
            t = time.thread_time()  # CPU time of this thread: all runs here, one thread
            fn()
            times[key].append(time.thread_time() - t)
    med = {k: 1000 * statistics.median(v) for k, v in times.items()}
    med["paths"] = med["costs"] - med["no paths"]
    med["rest"] = med["window"] - med["narrow"] - med["costs"]
    med["3way/3"] = med["3way"] / 3
    return med


def profile(pairs: list[str], repeat: int, params: MatchParameters) -> None:
    """Print where robostereo's time goes on each pair, one thread (module notes)."""
    os.environ["ROBOSTEREO_THREADS"] = "1"
    import cv2

    cv2.setNumThreads(1)
    keys = ("match", "edges", "window", "narrow", "costs", "paths", "rest", "one disparity",
            "3way/3")
    print(f"\nprofile, one thread: CPU ms (median of {repeat} rounds); edges: both images; "
          "window: narrow + costs (the window-cost pass, of which paths) + rest (evidence, "
          "right edge points, confidence); one disparity: the window-cost pass over the "
          "first disparity alone (the part that does not grow with the range); 3way/3: a "
          "third of MODE_SGBM_3WAY's time, what the whole match may take for 3x it")
    label = {"match": "total", "one disparity": "1 disp"}
    head = f"{'pair':<20} " + " ".join(f"{label.get(k, k):>7}" for k in keys)
    print(head)
    print("-" * len(head))
    for name in pairs:
        med = _stage_times(name, repeat, params)
        print(f"{name:<20} " + " ".join(f"{med[k]:>7.2f}" for k in keys), flush=True)


def _threads(per_core: bool, opencv_default: int) -> None:
    import cv2

    if per_core:
        os.environ["ROBOSTEREO_THREADS"] = "1"
        cv2.setNumThreads(1)
    else:
        os.environ.pop("ROBOSTEREO_THREADS", None)
        cv2.setNumThreads(opencv_default)


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--threads", choices=("per-core", "all", "both"), default="both")
    ap.add_argument("--no-memory", action="store_true", help="skip the memory children")
    ap.add_argument("--no-paths", action="store_true", help="robostereo without its paths")
    ap.add_argument("--no-coarse", action="store_true",
                    help="robostereo searching wide ranges whole")
    ap.add_argument("--contour", action="store_true",
                    help="robostereo accepting with its contours' support (opt-in)")
    ap.add_argument("--pairs", nargs="*", help="only these pairs (names as printed)")
    ap.add_argument("--cpu-time", action="store_true",
                    help="per core: time the calling thread's CPU time (a shared machine)")
    ap.add_argument("--profile", action="store_true",
                    help="where robostereo's time goes, per core, instead of the tables")
    ap.add_argument("--write-results", type=Path, metavar="PATH",
                    help="also write the time tables as JSON (docs/results/speed.json)")
    ap.add_argument("--write-memory", type=Path, metavar="PATH",
                    help="also write the memory table as JSON (docs/results/memory.json)")
    args = ap.parse_args()
    outputs = ("--write-results", "--write-memory")
    options = {"paths": not args.no_paths, "coarse": not args.no_coarse,
               "contour": args.contour}
    params = MatchParameters(**options)
    if args.profile:
        profile([n for n in names() if not args.pairs or n in args.pairs], args.repeat,
                params)
        return
    import cv2

    opencv_default = cv2.getNumThreads()
    pairs = [n for n in names() if not args.pairs or n in args.pairs]
    print(f"OpenCV {cv2.__version__} ({opencv_default} threads by default), "
          f"{os.cpu_count()} cores; median of {args.repeat} rounds; robostereo paths "
          f"{'on' if params.paths else 'off'}, coarse {'on' if params.coarse else 'off'}, "
          f"contour {'on' if params.contour else 'off'}")
    modes = {"per-core": [True], "all": [False], "both": [True, False]}[args.threads]
    tables: dict[str, list[dict[str, object]]] = {}
    for per_core in modes:
        _threads(per_core, opencv_default)
        clock = "CPU ms" if per_core and args.cpu_time else "ms"
        print(f"\n{'per core (one thread each)' if per_core else 'all cores'}: "
              f"{clock}, and peer time / robostereo time")
        head = (f"{'pair':<20} {'edges':>6} {'robostereo':>10} "
                + " ".join(f"{p:>17}" for p in PEERS))
        print(head)
        print("-" * len(head))
        for name in pairs:
            left, right, rng = pair(name)
            n = len(match_stereo(left, right, rng, params=params).left_edges)
            fns = {"robostereo": lambda left=left, right=right, rng=rng: match_stereo(
                left, right, rng, params=params)}
            fns.update({p: opencv_peer(p, left, right, rng) for p in PEERS})
            res = _time_rounds(fns, args.repeat, time.thread_time if per_core and args.cpu_time
                               else time.perf_counter)
            cells = " ".join(f"{1000 * res[p][0]:>8.2f} {res[p][1]:>6.2f}x "
                             for p in PEERS)
            print(f"{name:<20} {n:>6} {1000 * res['robostereo'][0]:>10.2f} {cells}",
                  flush=True)
            tables.setdefault("per_core" if per_core else "all_cores", []).append(
                {"pair": name, "edges": n, "robostereo_ms": 1000 * res["robostereo"][0],
                 "ms": {p: 1000 * res[p][0] for p in PEERS},
                 "ratio": {p: res[p][1] for p in PEERS}})
    if args.write_results:
        write_results(args.write_results, sys.argv[1:], outputs=outputs,
                      opencv=cv2.__version__, cores=os.cpu_count(), repeat=args.repeat,
                      cpu_time=args.cpu_time, **tables)
    if args.no_memory:
        return
    _threads(False, opencv_default)
    print("\npeak memory added (MiB): robostereo, SGBM (MODE_SGBM), ratio")
    memory = []
    for name in pairs:
        m_ours = peak_mib("robostereo", name, options)
        m_sgbm = peak_mib("sgbm", name, options)
        print(f"{name:<20} {m_ours:>8.1f} {m_sgbm:>8.1f} {m_ours / max(m_sgbm, 0.1):>6.2f}x",
              flush=True)
        memory.append({"pair": name, "robostereo_mib": m_ours, "sgbm_mib": m_sgbm,
                       "ratio": m_ours / max(m_sgbm, 0.1)})
    if args.write_memory:
        write_results(args.write_memory, sys.argv[1:], outputs=outputs, pairs=memory)


if __name__ == "__main__":
    main()
