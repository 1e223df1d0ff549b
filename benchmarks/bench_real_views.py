"""N-view locating on real robot-arm views: CPU time and peak memory against the pair.

Run:  python benchmarks/bench_real_views.py [--data ../shared/data/robot/dtu_scan24]
      [--counts 2,3,5,8] [--scale 0.5] [--repeat 3] [--matcher auto|pairs|sweep]
      python benchmarks/bench_real_views.py --held-out [--matcher ...] [--min-confidence C]
      python benchmarks/bench_real_views.py --pose-agreement [--scale 1]
      python benchmarks/bench_real_views.py --bound-agreement

The eight DTU views of scan 24 in ``--data`` (``cameras_sphere.npz`` and ``image/``),
read by :func:`robostereo.robot.importers.idr.read_idr` and scaled by ``--scale`` (0.5:
800 x 600) with the depth range 500-850 mm, located by
:func:`robostereo.robot.views.locating.locate_views` from the first N of
``0, 1, 2, 3, 4, 5, 6, 7`` for each N of ``--counts``, and the classic pair: views 1 and 2
(neighbours turned 29 degrees about their axes), the two-view path through the same
function.  Each row: the points, the median of ``--repeat`` runs' process CPU time
(after one warm-up run), the ratio against the pair's and against N - 1 (issue 34: at
most N - 1 times the pair's) and the peak resident memory of a fresh process that reads
the views and locates them once (``ru_maxrss``: numba's and OpenCV's allocations too,
and the interpreter's own, about 160 MB with the imports).  All rows come from one
process (the memory runs from its children).  The machine's load moves the times, not
the ratios much; quote medians.

``--held-out``: the confidence against what the views left out say, the real views' only
check without ground truth.  Views 0, 1 and 2 are located; each point that falls inside
views 3 and 4 counts as *consistent* if it lands within 1 px of a Canny edge in either
(as ``docs/guide/your-data.md``'s check; two views, because a right point hidden in one
is seldom hidden in both), and as the control the same point moved 5 mm along its
reference ray (a wrong point lands on an edge by chance that often).  Per confidence
bin: the points, their mean confidence, the share consistent and the control's.  A
right point is not always consistent (an edge Canny misses, or hidden in both views):
the rate of the pairs' points of the same views (all within 3 mm of the truth on a DTU
pair with ground truth), measured in the same run (about 94 %), stands for a right
point's, so a bin's share of right points is about ``(consistent - control) / (rate -
control)``, printed beside it, and the expected calibration error over the bins from
it (for ``--matcher pairs`` circular: the rate is their own), with its 5-95 % range
over 200 resamplings of the points (and of the pairs' points for the rate).  ``--min-confidence``
(default 0) reports the fits the default leaves out too.

``--pose-agreement``: whether DTU's own poses agree on depth, by a matcher that is not
ours.  With four or more of these views ``locate`` warns that the reference's pairs
disagree on depth by 0.13-0.25 %; this asks the same of SIFT features (Lowe's ratio
test at 0.75): view 2 is the reference, each other view's matches are triangulated with
the poses and kept where both reprojections lie within 1 px, and for each two pairs
the median of ``log(Z_q / Z_r)`` over the reference features both kept, with its
standard error (``1.25 * 1.4826 MAD / sqrt(n)``, as
:mod:`robostereo.robot.views.view_agreement` takes it).  ``--scale 1`` (full size) finds
about three times the matches of 0.5.

``--bound-agreement``: whether the sweep's bounds hold on real views, without ground
truth.  View 2 is the reference of two captures that share no other view (views 1, 2, 3
and views 0, 2, 4) and of all five; the points each locates from view 2 are paired by
their pixel there (within 0.3 px), and a pair agrees where its two depths differ by at
most ``sqrt(b1^2 + b2^2)`` (both bounds) and is far apart beyond three times that.  The
two captures' depth errors are independent but for view 2's own edge position, so the
share within is at most what the bounds promise.  Each row: with the capture's
``disparity_px`` alone (``bound_sigmas`` None) and with the fits' residual noise (the
default); the pose comparison is off (``lone_view_factor`` None) so that only the bounds
differ.
"""

from __future__ import annotations

import argparse
import itertools
import multiprocessing
import resource
import statistics
import sys
import time
import warnings
from pathlib import Path
from typing import Any

DEFAULT_DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "robot" / "dtu_scan24"
PAIR = (1, 2)


def _capture(data: Path, views: tuple[int, ...], scale: float) -> Any:
    from robostereo.robot.importers.idr import read_idr
    from robostereo.robot.importers.imported_views import views_capture_from_imported

    imported = read_idr(data / "cameras_sphere.npz", data / "image")
    return views_capture_from_imported(imported, select=list(views), scale=scale,
                                       depth_range_mm=(500.0, 850.0))


def _params(matcher: str, **kw: Any) -> Any:
    from robostereo.robot.views.views_parameters import ViewsParameters

    return ViewsParameters(matcher=matcher, **kw)  # type: ignore[arg-type]


HELD_OUT = (3, 4)
BINS = (0.0, 0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.99, 1.0 + 1e-9)


def _held_out(data: Path, scale: float, matcher: str, min_confidence: float) -> None:
    """Print the confidence bins against held-out views 3 and 4 (``--held-out``)."""
    import cv2
    import numpy as np

    from robostereo.robot.views.locating import locate_views

    cap = _capture(data, (0, 1, 2, *HELD_OUT), scale)
    views = cap.subset(np.array([0, 1, 2]))
    held = range(3, 3 + len(HELD_OUT))
    to_edge = []
    for k in held:
        image = np.asarray(cap.images[k], np.uint8)
        edges = cv2.Canny(cv2.GaussianBlur(image, (5, 5), 1.0), 20, 60)
        to_edge.append(cv2.distanceTransform((edges == 0).astype(np.uint8), cv2.DIST_L2, 5))

    def consistent(world: Any) -> tuple[Any, Any]:
        """On an edge of some held-out view; inside every one of them."""
        hit = np.zeros(len(world), bool)
        inside = np.ones(len(world), bool)
        for k, dist in zip(held, to_edge, strict=True):
            pix, depth = cap.camera.project(world, cap.poses[k])
            ij = np.rint(pix).astype(int)
            within = (depth > 0) & np.all((ij >= 0) & (ij < dist.shape[::-1]), axis=1)
            on = np.zeros(len(world), bool)
            on[within] = dist[ij[within, 1], ij[within, 0]] <= 1.0
            hit |= on
            inside &= within
        return hit, inside

    def located(matcher: str, min_confidence: float) -> Any:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            kw = {"min_confidence": min_confidence} if matcher != "pairs" else {}
            return locate_views(views, params=_params(matcher, **kw))

    def scored(points: Any) -> tuple[Any, Any, Any]:
        hit, inside = consistent(points.world)
        ray = points.world - views.centres[points.reference]
        moved, inside_moved = consistent(points.world + 5.0 * ray / np.linalg.norm(
            ray, axis=1, keepdims=True))
        keep = inside & inside_moved
        return points.confidence[keep], hit[keep], moved[keep]

    # a right point's rate: the pairs' points (all within 3 mm on a DTU pair with truth)
    _, pairs_hit, _ = scored(located("pairs", 0.0))
    right_rate = float(pairs_hit.mean())
    conf, hit, moved = scored(located(matcher, min_confidence))
    print(f"views 0, 1, 2 ({matcher}): {len(conf)} points in views {HELD_OUT}: "
          f"{100 * hit.mean():.1f} % consistent, moved 5 mm {100 * moved.mean():.1f} %; "
          f"the pairs' points {100 * right_rate:.1f} %")
    print("confidence | points | mean confidence | consistent | control | right (est.)")
    print("--- | --- | --- | --- | --- | ---")
    ece, rows = _ece_estimate(conf, hit, moved, right_rate)
    for lo, hi, n, c, h, m, right in rows:
        print(f"{lo:.2f}-{min(hi, 1.0):.2f} | {n} | {c:.3f} | "
              f"{100 * h:.1f} % | {100 * m:.1f} % | {right:.2f}")
    # how far the figure moves with the points drawn: resampled with replacement (the
    # pairs' rate too), a fixed seed
    rng = np.random.default_rng(0)
    boot = []
    for _ in range(BOOTSTRAP_DRAWS):
        k = rng.integers(0, len(conf), len(conf))
        rate = float(pairs_hit[rng.integers(0, len(pairs_hit), len(pairs_hit))].mean())
        boot.append(_ece_estimate(conf[k], hit[k], moved[k], rate)[0])
    lo, hi = np.percentile(boot, [5, 95])
    print(f"calibration error against the estimate: {ece:.3f} "
          f"(resampled, 5-95 %: {lo:.3f}-{hi:.3f})")


BOOTSTRAP_DRAWS = 200


def _ece_estimate(conf: Any, hit: Any, moved: Any, right_rate: float
                  ) -> tuple[float, list[tuple[Any, ...]]]:
    """The calibration error against each bin's estimated share of right points
    ``(consistent - control) / (right_rate - control)``, and the bins' rows."""
    ece = 0.0
    rows = []
    for lo, hi in itertools.pairwise(BINS):
        k = (conf >= lo) & (conf < hi)
        if not k.any():
            continue
        right = (hit[k].mean() - moved[k].mean()) / (right_rate - moved[k].mean())
        right = min(max(right, 0.0), 1.0)
        ece += k.mean() * abs(right - conf[k].mean())
        rows.append((lo, hi, int(k.sum()), float(conf[k].mean()), float(hit[k].mean()),
                     float(moved[k].mean()), right))
    return ece, rows


AGREEMENT_REFERENCE = 2
MIN_SHARED_FEATURES = 10


def _pose_agreement(data: Path, scale: float) -> None:
    """Print how the reference's pairs agree on depth by SIFT (``--pose-agreement``)."""
    import cv2
    import numpy as np

    from robostereo.geometry.poses import as_se3

    cap = _capture(data, tuple(range(8)), scale)
    if cap.camera.distortion and any(cap.camera.distortion):
        raise SystemExit("--pose-agreement: the views' camera has distortion")
    sift = cv2.SIFT_create(nfeatures=40000, contrastThreshold=0.005)
    found = [sift.detectAndCompute(np.asarray(img, np.uint8), None) for img in cap.images]
    pixels = [np.array([k.pt for k in kps], dtype=np.float64) for kps, _ in found]
    world_to_camera = [as_se3(p).inv() for p in cap.poses]
    proj = [cap.camera.K @ np.hstack([t.rotation, t.translation[:, None]])
            for t in world_to_camera]
    ref = AGREEMENT_REFERENCE
    ref_pose = as_se3(cap.poses[ref])
    bf = cv2.BFMatcher(cv2.NORM_L2)
    depth: dict[int, dict[int, float]] = {}
    print(f"reference view {cap.view_name(ref)}: {len(pixels[ref])} features")
    print("pair | matches | within 1 px | baseline mm")
    print("--- | --- | --- | ---")
    for other in range(len(cap)):  # a loop over views, not over features
        if other == ref:
            continue
        knn = bf.knnMatch(found[ref][1], found[other][1], k=2)
        good = [m[0] for m in knn if len(m) == 2 and m[0].distance < 0.75 * m[1].distance]
        ia = np.array([g.queryIdx for g in good], dtype=np.intp)
        ib = np.array([g.trainIdx for g in good], dtype=np.intp)
        if len(ia) == 0:
            continue
        h = cv2.triangulatePoints(proj[ref], proj[other], pixels[ref][ia].T,
                                  pixels[other][ib].T)
        world = (h[:3] / h[3]).T
        ok = np.ones(len(ia), bool)
        for k, idx in ((ref, ia), (other, ib)):
            seen, z = cap.camera.project(world, cap.poses[k])
            ok &= (z > 0) & (np.linalg.norm(seen - pixels[k][idx], axis=1) <= 1.0)
        z = (world - ref_pose.translation) @ ref_pose.rotation[:, 2]
        depth[other] = dict(zip(ia[ok].tolist(), z[ok].tolist(), strict=True))
        base = float(np.linalg.norm(cap.centres[other] - cap.centres[ref]))
        print(f"{ref}-{cap.view_name(other)} | {len(ia)} | {int(ok.sum())} | {base:.0f}")
    print("pairs | shared features | median log(Z_q / Z_r) | standard error")
    print("--- | --- | --- | ---")
    for q, r in itertools.combinations(sorted(depth), 2):
        shared = sorted(set(depth[q]) & set(depth[r]))
        if len(shared) < MIN_SHARED_FEATURES:
            continue
        ratio = np.log(np.array([depth[q][f] / depth[r][f] for f in shared]))
        med = float(np.median(ratio))
        err = 1.25 * 1.4826 * float(np.median(np.abs(ratio - med))) / np.sqrt(len(ratio))
        print(f"{ref}-{q} / {ref}-{r} | {len(shared)} | {100 * med:+.3f} % | {100 * err:.3f} %")


BOUND_SETS = (((1, 2, 3), (0, 2, 4)), ((1, 2, 3), (0, 1, 2, 3, 4)))


def _bound_agreement(data: Path, scale: float) -> None:
    """Print how often two captures' depths of one reference pixel agree within their
    bounds (``--bound-agreement``)."""
    import numpy as np
    from scipy.spatial import cKDTree

    from robostereo.robot.views.locating import locate_views

    cap = _capture(data, (0, 1, 2, 3, 4), scale)
    print("views | views | bounds | pixels paired | within both bounds | of those both "
          "at 0.9 | beyond 3x | median difference mm | median sqrt(b1^2 + b2^2) mm")
    print("--- | --- | --- | --- | --- | --- | --- | --- | ---")
    for sets in BOUND_SETS:
        for sigmas in (None, 3.0):
            got = []
            for views in sets:
                params = _params("sweep", bound_sigmas=sigmas, lone_view_factor=None)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    loc = locate_views(cap.subset(np.array(views)), params=params)
                k = loc.reference == views.index(2)
                got.append((loc.pixel[k], loc.depth_mm[k], loc.bound_mm[k],
                            loc.confidence[k]))
            (pa, da, ba, ca), (pb, db, bb, cb) = got
            d, j = cKDTree(pb).query(pa, distance_upper_bound=0.3)
            ok = np.isfinite(d)
            diff = np.abs(da[ok] - db[j[ok]])
            both = np.hypot(ba[ok], bb[j[ok]])
            sure = (ca[ok] >= 0.9) & (cb[j[ok]] >= 0.9)
            name = "capture's" if sigmas is None else f"{sigmas:g} sigmas of the residuals"
            print(f"{','.join(map(str, sets[0]))} | {','.join(map(str, sets[1]))} | {name} | "
                  f"{int(ok.sum())} | {100 * np.mean(diff <= both):.1f} % | "
                  f"{100 * np.mean(diff[sure] <= both[sure]):.1f} % | "
                  f"{100 * np.mean(diff > 3 * both):.2f} % | {np.median(diff):.2f} | "
                  f"{np.median(both):.2f}", flush=True)


def _peak_child(data: Path, views: tuple[int, ...], scale: float, matcher: str,
                out: Any) -> None:
    """Read and locate once in this (fresh) process; send its peak RSS in MB."""
    from robostereo.robot.views.locating import locate_views

    warnings.simplefilter("ignore")
    locate_views(_capture(data, views, scale), params=_params(matcher))
    out.send(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0)


def _peak_mb(data: Path, views: tuple[int, ...], scale: float, matcher: str) -> float:
    ctx = multiprocessing.get_context("spawn")
    recv, send = ctx.Pipe(duplex=False)
    p = ctx.Process(target=_peak_child, args=(data, views, scale, matcher, send))
    p.start()
    peak = recv.recv()
    p.join()
    return float(peak)


def _cpu(data: Path, views: tuple[int, ...], scale: float, matcher: str,
         repeat: int) -> tuple[int, float]:
    from robostereo.robot.views.locating import locate_views

    cap = _capture(data, views, scale)
    params = _params(matcher)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        located = locate_views(cap, params=params)  # compile and warm the caches
        times = []
        for _ in range(repeat):
            t = time.process_time()
            locate_views(cap, params=params)
            times.append(time.process_time() - t)
    return len(located.world), statistics.median(times)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA)
    ap.add_argument("--counts", default="2,3,5,8", help="comma-separated view counts")
    ap.add_argument("--scale", type=float, default=0.5)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--matcher", default="auto", choices=("auto", "pairs", "sweep"))
    ap.add_argument("--held-out", action="store_true",
                    help="the confidence against held-out views 3 and 4, not the times")
    ap.add_argument("--min-confidence", type=float, default=0.0,
                    help="--held-out: the sweep's min_confidence (default 0: every fit)")
    ap.add_argument("--pose-agreement", action="store_true",
                    help="how DTU's poses agree on depth by SIFT matches, not the times")
    ap.add_argument("--bound-agreement", action="store_true",
                    help="whether the sweep's bounds hold between captures sharing "
                         "view 2 only, not the times")
    args = ap.parse_args(argv)
    if not (args.data / "cameras_sphere.npz").is_file():
        print(f"no DTU views in {args.data}", file=sys.stderr)
        return 2
    if args.held_out:
        _held_out(args.data, args.scale, args.matcher, args.min_confidence)
        return 0
    if args.pose_agreement:
        _pose_agreement(args.data, args.scale)
        return 0
    if args.bound_agreement:
        _bound_agreement(args.data, args.scale)
        return 0
    counts = [int(c) for c in args.counts.split(",")]
    pair_points, pair_cpu = _cpu(args.data, PAIR, args.scale, "auto", args.repeat)
    pair_mb = _peak_mb(args.data, PAIR, args.scale, "auto")
    print("views | matcher | points | cpu s | x pair | x pair / (N - 1) | peak MB")
    print("--- | --- | --- | --- | --- | --- | ---")
    print(f"pair {PAIR[0]}-{PAIR[1]} | two-view | {pair_points} | {pair_cpu:.2f} | 1.0 | "
          f"1.0 | {pair_mb:.0f}", flush=True)
    for n in counts:
        views = tuple(range(n))
        points, cpu = _cpu(args.data, views, args.scale, args.matcher, args.repeat)
        mb = _peak_mb(args.data, views, args.scale, args.matcher)
        ratio = cpu / pair_cpu
        print(f"{n} | {args.matcher} | {points} | {cpu:.2f} | {ratio:.1f} | "
              f"{ratio / max(n - 1, 1):.1f} | {mb:.0f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
