"""N-view locating beside the classic pair: on the simulated robots and on renders of our own.

Run:  python benchmarks/bench_views.py [--robot scara|six-axis|both] [--counts 2,3,5,9]
      [--patterns line,cross,arc] [--span 80] [--repeat 3] [--seeds 0] [--cpu-time]
      PYTHONPATH=src:tests python benchmarks/bench_views.py --renders [--families base,turn]
      [--patterns line,cross] [--counts 2,5,9] [--spans 80,160] [--seeds 0] [--repeat 1]
      [--views-pair]

Simulated robots (the default): for each robot, pattern and view count it runs
:func:`robostereo.experiments.run_views_demo` (the block at two heights and the
hub-pulley, SCARA or six-axis with its estimated hand-eye) for each seed of the
sensor noise (and, six-axis, of the hand-eye views) and prints one row: the
lift, the largest depth error of the block's top outline (all of it, and its long
edges), whether every point lies within its bound, the median bound, the outline
coverage, the pulley's matched and false shares (of the points reported: those whose
confidence reaches ``ViewsParameters.min_confidence``).  Times: the median over `--repeat`
runs of :func:`~robostereo.robot.views.locating.locate_views` on the block (lift 0) and of
the two-view :func:`~robostereo.robot.capture.locate_pair.locate` on the pair of the two outermost
views of the same capture, in one process, interleaved; wall-clock time, or with
``--cpu-time`` the process's CPU time (steadier on a shared machine).  Rows with the
worst largest error first.  Quality does not depend on the machine; the times do.

Renders (``--renders``; issue 34's test bed): captures the simulator did not make,
rendered by ``tests/view_renders.py`` (a textured box on a textured ground, a lens with
``k1``, the viewpoints off the ideal pattern, turns about the optical axis; see its
docstring).  Each family of ``--families`` (:data:`FAMILIES`) is rendered for each
pattern, count, span and seed, and three rows are printed one beside the other:

* ``views``: :func:`~robostereo.robot.views.locating.locate_views` on all N views;
* ``pair``: the classic :func:`~robostereo.robot.capture.locate_pair.locate` on
  ``capture.pair(i, j)`` of the outer views (a line's ends; a cross's x-arm ends, the
  arm along the camera's x axis: both arms are `span` long);
* ``views2`` (with ``--views-pair``, N > 2): the same two outer views written as a
  ``views:`` capture folder of N = 2, read back and located by ``locate_views``.

Columns: the points reported; the 3-D error of each (its distance to the nearest true
surface, box faces or ground) over the points within 10 mm of the box: median, p95 and
max; the share of all points more than 2 mm off; the share within its own bound: the
point's depth error along its reference camera's optical axis at its pixel (the located
depth minus the true depth of the ray from the recorded centre through the point, cast
into the true scene, or of one of the eight rays 1 px round it, whichever is nearest: an
edge point lies between pixels, and at a silhouette its one ray's depth is either
side's; ``robostereo evaluate`` takes a depth map's 3 x 3 neighbourhood alike) at most
``bound_mm`` (N views; ``LocatedViews.bound_mm``, a depth bound along the reference's
axis) or ``z_bound`` (the pair, eq. (9), along the epipolar frame's axis, within a
degree or so of the left camera's: taken as the same), and beyond three times it, and
the share within it on the exact ray alone (``in bound, ray``); the p95 of the 3-D error
of the box points that every view sees (``p95 every``); the outline coverage (the box's
top outline, sampled every mm, with a located point within 2 mm); the expected
calibration error of the confidence (ten bins) against being within the own bound
(``ECE``) and against the rule the confidences were fitted on (``ECE 1px``: the depth
error at the pixel, as above, within one pixel of disparity over the span,
``depth^2 / (f span)``, as ``fit_views_confidence.py`` takes it); the process's CPU
time (median of `--repeat`), the same over the pair's (``x pair``) and the peak memory
traced by :mod:`tracemalloc` in a separate run (NumPy's
allocations; numba's own are not traced).  ``--sweep`` adds the plane sweep's row,
``--matcher`` chooses the ``views`` row's matcher, ``--bound-sigmas`` the N-view rows'
``ViewsParameters.bound_sigmas`` (``none``: bounds of the capture's figures alone).
Groups with the worst N-view share beyond 2 mm first.  A second table pools each
family's rows of one method (every pattern, count and seed): its points, both
calibration errors, and the floor, the median calibration error over 200 draws of a
calibrated confidence on the same points (each right with the probability it says):
ten bins of a hundred points show a few hundredths by chance alone.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
import tempfile
import time
import tracemalloc
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.errors import InputError
from robostereo.experiments import run_views_demo
from robostereo.robot.capture import locate
from robostereo.robot.simulated.grab_views import simulate_views
from robostereo.robot.views.locating import locate_views
from robostereo.robot.views.viewpoints import ViewsCapture, view_offsets
from robostereo.robot.views.views_folder import read_views_capture, write_views_capture
from robostereo.robot.views.views_parameters import ViewsParameters

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from view_renders import RenderSpec, ViewsTruth, render_views

FAMILIES: dict[str, dict[str, Any]] = {
    "base": {},
    "coarse": {"texture": "coarse"},
    "stripes": {"texture": "stripes"},
    "print": {"texture": "print"},
    "d300": {"distance_mm": 300.0},
    "d700": {"distance_mm": 700.0},
    "d1000": {"distance_mm": 1000.0},
    "k0": {"k1": 0.0},
    "k05": {"k1": -0.05},
    "still": {"jitter_deg": 0.0, "jitter_mm": 0.0},
    "error": {"jitter_deg": 0.0, "jitter_mm": 0.0, "error_deg": 0.1, "error_mm": 0.2},
    "turn": {"turn_deg": 30.0},
    "tilt": {"tilt_deg": 30.0, "aim": True},
    "dtu": {"texture": "print", "distance_mm": 700.0, "turn_deg": 30.0, "tilt_deg": 20.0,
            "aim": True},
}
"""The render families of ``--renders``: changes to :class:`RenderSpec`'s defaults (fine
noise, 400 mm, ``k1 = -0.1``, each viewpoint off the pattern by 1 deg and 2 mm as the arm
went and reported, no turns).  ``error``: the true poses off the reported ones by 0.1 deg
and 0.2 mm (not recorded); ``dtu``: a printed ground at 700 mm seen obliquely (20 deg)
by converging views turned up to 30 deg apart about their axes."""


def _times(count: int, pattern: str, span: float, robot: str, repeat: int, seed: int,
           clock: Any = time.perf_counter) -> tuple[float, float]:
    sim = simulate_views("block", count=count, pattern=pattern,  # type: ignore[arg-type]
                         span_mm=span, robot=robot, seed=seed)  # type: ignore[arg-type]
    pair = sim.capture.pair(0, count - 1) if pattern != "cross" else sim.capture.pair(1, 2)
    locate_views(sim.capture)
    locate(pair)
    tv, t2 = [], []
    for _ in range(repeat):
        t = clock()
        locate_views(sim.capture)
        tv.append(clock() - t)
        t = clock()
        locate(pair)
        t2.append(clock() - t)
    return statistics.median(tv), statistics.median(t2)


def _outer_pair(spec: RenderSpec) -> tuple[int, int]:
    """The outer views: a line's ends, a cross's x-arm ends."""
    o = view_offsets(spec.pattern, spec.count, spec.span_mm)  # type: ignore[arg-type]
    on_x = np.nonzero(np.abs(o[:, 1]) < 1e-9)[0]
    return int(on_x[np.argmin(o[on_x, 0])]), int(on_x[np.argmax(o[on_x, 0])])


def _ece(confidence: np.ndarray, right: np.ndarray, bins: int = 10) -> float:
    """Expected calibration error: the mean over ten equal confidence bins of
    ``|mean confidence - share right|``, weighted by the bins' points."""
    if not len(confidence):
        return float("nan")
    k = np.minimum((np.asarray(confidence) * bins).astype(int), bins - 1)
    n = np.bincount(k, minlength=bins)
    c = np.bincount(k, weights=confidence, minlength=bins)
    r = np.bincount(k, weights=right.astype(float), minlength=bins)
    used = n > 0
    return float(np.sum(np.abs(c[used] - r[used])) / len(confidence))


def _ece_floor(confidence: np.ndarray, draws: int = 200) -> float:
    """The median ECE of a calibrated confidence over the same points: each point right
    with the probability its confidence says (`draws` draws, a fixed seed).  Ten bins of
    a few hundred points show an ECE of a few hundredths by chance alone."""
    if not len(confidence):
        return float("nan")
    rng = np.random.default_rng(0)
    c = np.asarray(confidence, dtype=float)
    return float(np.median([_ece(c, rng.random(len(c)) < c) for _ in range(draws)]))


def _score(truth: ViewsTruth, world: np.ndarray, bound: np.ndarray, origins: np.ndarray,
           rotations: np.ndarray, focal_px: float, span_mm: float,
           confidence: np.ndarray | None = None) -> dict[str, Any]:
    """The quality columns of one method's points (see the module's docstring)."""
    m = len(world)
    err = truth.surface_distance(world) if m else np.zeros(0)
    box = truth.near_box(world) if m else np.zeros(0, bool)
    within = np.zeros(m, bool)
    within3 = np.zeros(m, bool)
    within_ray = np.zeros(m, bool)
    right_px = np.zeros(m, bool)
    for o in np.unique(origins, axis=0):
        k = np.nonzero((origins == o).all(axis=1))[0]
        R = rotations[k[0]]
        depth = (world[k] - o) @ R[:, 2]
        on_ray = np.abs(depth - truth.ray_depth(o, R[:, 2], world[k]))
        off = truth.pixel_depth_error(o, R, focal_px, world[k])
        within[k] = off <= bound[k]
        within3[k] = off <= 3 * bound[k]
        within_ray[k] = on_ray <= bound[k]
        # the confidences' own rule: within one pixel of disparity over the span
        right_px[k] = off <= depth**2 / (focal_px * span_mm)
    outline = truth.outline()
    cover = 0.0
    if m:
        from scipy.spatial import cKDTree
        cover = float((cKDTree(world).query(outline)[0] <= 2.0).mean())
    eb = err[box]
    every = box & truth.seen_by(world).all(axis=1) if m else box
    ea = err[every]
    return {"points": m, "box": int(box.sum()),
            "p95_every": float(np.percentile(ea, 95)) if len(ea) else float("nan"),
            "median": float(np.median(eb)) if len(eb) else float("nan"),
            "p95": float(np.percentile(eb, 95)) if len(eb) else float("nan"),
            "max": float(eb.max()) if len(eb) else float("nan"),
            "beyond2": float((err > 2.0).mean()) if m else float("nan"),
            "within": float(within.mean()) if m else float("nan"),
            "within_ray": float(within_ray.mean()) if m else float("nan"),
            "beyond3b": float((~within3).mean()) if m else float("nan"), "outline": cover,
            "ece": _ece(confidence, within) if confidence is not None else float("nan"),
            "ece_px": _ece(confidence, right_px) if confidence is not None else float("nan"),
            "confidence": confidence if confidence is not None else np.zeros(0),
            "right_px": right_px, "within_bound": within}


def _run(fn: Callable[[], Any], repeat: int) -> tuple[Any, float, float]:
    """`fn`'s result, its median CPU time over `repeat` runs and its traced peak, MB."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fn()  # compile and warm the caches
        times = []
        for _ in range(repeat):
            t = time.process_time()
            out = fn()
            times.append(time.process_time() - t)
        tracemalloc.start()
        fn()
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return out, statistics.median(times), peak / 2**20


def _views_pair(cap: ViewsCapture, i: int, j: int) -> ViewsCapture:
    """Views `i` and `j` written as a ``views:`` folder of two and read back."""
    two = dataclasses.replace(cap, images=(cap.images[i], cap.images[j]),
                              poses=(cap.poses[i], cap.poses[j]),
                              names=("view_00.png", "view_01.png"))
    with tempfile.TemporaryDirectory() as tmp:
        write_views_capture(Path(tmp) / "two", two)
        return read_views_capture(Path(tmp) / "two")


def _render_rows(family: str, spec: RenderSpec, repeat: int,
                 views_pair: bool, sweep: bool = False,
                 matcher: str = "auto", bound_sigmas: float | None = 3.0
                 ) -> list[dict[str, Any]]:
    cap, truth = render_views(spec)
    i, j = _outer_pair(spec)
    poses = cap.poses
    vp = ViewsParameters(matcher=matcher, bound_sigmas=bound_sigmas)  # type: ignore[arg-type]
    lv, tv, mv = _run(lambda: locate_views(cap, params=vp), repeat)
    ref = lv.reference
    f = float(cap.camera.K[0, 0])
    rows = [{"method": f"views ({matcher})", "t": tv, "mem": mv, **_score(
        truth, lv.world, lv.bound_mm, np.array([poses[r].translation for r in ref]),
        np.array([poses[r].rotation for r in ref]), f, spec.span_mm, lv.confidence)}]
    if sweep:
        sp = ViewsParameters(matcher="sweep", bound_sigmas=bound_sigmas)
        ls, ts, ms = _run(lambda: locate_views(cap, params=sp), repeat)
        rows.append({"method": "sweep", "t": ts, "mem": ms, **_score(
            truth, ls.world, ls.bound_mm,
            np.array([poses[r].translation for r in ls.reference]).reshape(-1, 3),
            np.array([poses[r].rotation for r in ls.reference]).reshape(-1, 3, 3), f,
            spec.span_mm, ls.confidence)})
    pair = cap.pair(i, j)
    lp, tp, mp = _run(lambda: locate(pair), repeat)
    m = len(lp.world)
    rows.append({"method": f"pair {i}-{j}", "t": tp, "mem": mp, **_score(
        truth, lp.world, lp.z_bound, np.tile(poses[i].translation, (m, 1)),
        np.tile(poses[i].rotation, (m, 1, 1)), f, spec.span_mm, lp.probability)})
    if views_pair and spec.count > 2:
        two = _views_pair(cap, i, j)
        l2, t2, m2 = _run(lambda: locate_views(two), repeat)
        rows.append({"method": f"views2 {i}-{j}", "t": t2, "mem": m2, **_score(
            truth, l2.world, l2.bound_mm,
            np.array([two.poses[r].translation for r in l2.reference]).reshape(-1, 3),
            np.array([two.poses[r].rotation for r in l2.reference]).reshape(-1, 3, 3), f,
            spec.span_mm, l2.confidence)})
    for r in rows:
        r.update(family=family, pattern=spec.pattern, N=spec.count, span=spec.span_mm,
                 seed=spec.seed)
    return rows


def _percent(v: float, digits: int = 1) -> str:
    return "nan" if v != v else f"{100 * v:.{digits}f}%"


def renders_main(args: argparse.Namespace) -> int:
    """The ``--renders`` mode: the table of the module's docstring."""
    groups: list[list[dict[str, Any]]] = []
    for family in args.families.split(","):
        if family not in FAMILIES:
            raise SystemExit(f"unknown family {family!r}: one of {', '.join(FAMILIES)}")
        for pattern in (args.patterns or "line").split(","):
            for count in (int(c) for c in (args.counts or "2,5").split(",")):
                if pattern == "cross" and count < 5:
                    continue
                for span in (float(s) for s in args.spans.split(",")):
                    for seed in (int(s) for s in args.seeds.split(",")):
                        spec = dataclasses.replace(
                            RenderSpec(), pattern=pattern, count=count, span_mm=span,
                            seed=seed, **FAMILIES[family])
                        groups.append(_render_rows(family, spec, args.repeat,
                                                   args.views_pair, args.sweep,
                                                   args.matcher, args.bound_sigmas))
                        print(f"done {family} {pattern} {count} {span:g} seed {seed}",
                              flush=True)
    head = ("family", "pattern", "N", "span", "seed", "method", "points", "box pts",
            "median", "p95", "max", "p95 every", ">2mm", "in bound", "in bound, ray",
            ">3 bounds", "outline",
            "ECE", "ECE 1px", "cpu s", "x pair", "peak MB")
    print(" | ".join(head))
    print(" | ".join("---" for _ in head))
    groups.sort(key=lambda g: -np.nan_to_num(g[0]["beyond2"], nan=1.0))
    for g in groups:
        t_pair = next(r["t"] for r in g if r["method"].startswith("pair"))
        for r in g:
            print(" | ".join(str(v) for v in (
                r["family"], r["pattern"], r["N"], f"{r['span']:g}", r["seed"], r["method"],
                r["points"], r["box"], f"{r['median']:.2f}", f"{r['p95']:.2f}",
                f"{r['max']:.2f}", f"{r['p95_every']:.2f}", _percent(r["beyond2"], 2),
                _percent(r["within"]), _percent(r["within_ray"]), _percent(r["beyond3b"], 2),
                _percent(r["outline"]),
                f"{r['ece']:.3f}", f"{r['ece_px']:.3f}", f"{r['t']:.2f}",
                f"{r['t'] / t_pair:.1f}", f"{r['mem']:.0f}")))
    _pooled_calibration([r for g in groups for r in g])
    return 0


def _pooled_calibration(rows: list[dict[str, Any]]) -> None:
    """Each family's calibration error over all its rows of a method, beside the floor a
    calibrated confidence would show on the same points (:func:`_ece_floor`)."""
    print()
    head = ("family", "method", "points", "ECE 1px", "ECE bound", "floor")
    print(" | ".join(head))
    print(" | ".join("---" for _ in head))
    kinds: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in rows:
        kinds.setdefault((r["family"], r["method"].split(" ")[0]), []).append(r)
    for (family, method), rs in kinds.items():
        c = np.concatenate([r["confidence"] for r in rs])
        if not len(c):
            continue
        right = np.concatenate([r["right_px"] for r in rs])
        within = np.concatenate([r["within_bound"] for r in rs])
        print(" | ".join((family, method, str(len(c)), f"{_ece(c, right):.3f}",
                          f"{_ece(c, within):.3f}", f"{_ece_floor(c):.3f}")))


def main() -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--robot", default="both", choices=("scara", "six-axis", "both"))
    ap.add_argument("--counts", default=None,
                    help="comma-separated view counts (default 2,3,5,9; renders 2,5)")
    ap.add_argument("--patterns", default=None,
                    help="comma-separated patterns (default line,cross,arc; renders line)")
    ap.add_argument("--span", type=float, default=80.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--seeds", default="0", help="comma-separated noise seeds")
    ap.add_argument("--cpu-time", action="store_true",
                    help="time the locates by the process's CPU time, not the wall clock")
    ap.add_argument("--renders", action="store_true",
                    help="score on tests/view_renders.py's captures (issue 34's test bed)")
    ap.add_argument("--families", default="base,stripes,turn,d1000",
                    help=f"renders: comma-separated of {','.join(FAMILIES)}")
    ap.add_argument("--spans", default="80", help="renders: comma-separated spans, mm")
    ap.add_argument("--matcher", default="auto", choices=("auto", "pairs", "sweep"),
                    help="renders: ViewsParameters.matcher of the views row")
    ap.add_argument("--sweep", action="store_true",
                    help="renders: also the plane sweep (ViewsParameters(matcher='sweep'))")
    ap.add_argument("--views-pair", action="store_true",
                    help="renders: also the outer views as a views: capture of two")
    ap.add_argument("--bound-sigmas", default="3",
                    type=lambda v: None if v.lower() == "none" else float(v),
                    help="renders: ViewsParameters.bound_sigmas of the N-view rows ('none': "
                         "the capture's figures alone)")
    args = ap.parse_args()
    if args.renders:
        return renders_main(args)
    args.counts = args.counts or "2,3,5,9"
    args.patterns = args.patterns or "line,cross,arc"
    robots = ("scara", "six-axis") if args.robot == "both" else (args.robot,)
    rows: list[dict[str, Any]] = []
    for robot in robots:
        for pattern in args.patterns.split(","):
            for count in (int(c) for c in args.counts.split(",")):
                for seed in (int(s) for s in args.seeds.split(",")):
                    try:
                        r = run_views_demo(count=count, pattern=pattern, span_mm=args.span,
                                           robot=robot, seed=seed)
                    except InputError as e:  # e.g. a cross of two views
                        print(f"{robot} {pattern} {count}: {e}", flush=True)
                        break
                    tv, t2 = _times(count, pattern, args.span, robot, args.repeat, seed,
                                    time.process_time if args.cpu_time else time.perf_counter)
                    r.update(t_views=tv, t_two=t2, seed=seed)
                    rows.append(r)
                    print(f"done {robot} {pattern} {count} seed {seed}", flush=True)
    head = ("robot", "pattern", "N", "seed", "lift", "max|err|", "long", "bound@max", "within",
            "med bound", "outline", "pul.match", "pul.false", "t views",
            "t two", "ratio", "(N-1)")
    print(" | ".join(head))
    for r in sorted(rows, key=lambda r: -r["max_abs_error_mm"]):
        print(" | ".join(str(v) for v in (
            r["robot"], r["pattern"], r["views"], r["seed"], f"{r['lift_mm']:.2f}",
            f"{r['max_abs_error_mm']:.2f}", f"{r['max_abs_error_long_edges_mm']:.2f}",
            f"{r['bound_at_max_error_mm']:.2f}", r["all_within_bound"],
            f"{r['median_bound_mm']:.2f}", f"{100 * r['outline_coverage']:.1f}%",
            f"{100 * r['pulley_matched']:.1f}%", f"{100 * r['pulley_false']:.2f}%",
            f"{r['t_views']:.3f}", f"{r['t_two']:.3f}", f"{r['t_views'] / r['t_two']:.1f}",
            r["views"] - 1)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
