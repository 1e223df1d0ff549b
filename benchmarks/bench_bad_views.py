"""One bad view among N (issue 36): what ``locate`` says, and whether any point it calls
sure lies far beyond its bound, on the simulator's captures and on renders of our own.

Run:  PYTHONPATH=tests python benchmarks/bench_bad_views.py [--renders]

For each capture (the simulator's hub-pulley from a line of 3 at 40 mm and from the
six-axis arm's line of 5, its block and pulley from a SCARA cross of 5; with
``--renders`` also ``tests/view_renders.py``'s printed ground from a cross of 5, a line
of 3 and 5 and a cross of 9), first as it is, then with one outer view made bad:

* its recorded pose moved 2 or 3 mm along the line from the views' centroid to it (its
  baseline), or 3 mm across it; turned 0.5 degrees about its optical axis;
* its image blurred by a Gaussian of sigma 2 or 4 px.

Each row: points located (default matcher), the median world z, how many points of
confidence 0.9 or more lie more than three times their bound from the truth (depth
against the rendered depth of the nearest of the 3 x 3 pixels about the point's
reference pixel), the largest such error, and the warnings (first 90 characters).
Worst first (by that count's share).
"""

from __future__ import annotations

import argparse
import dataclasses
import warnings
from typing import Any

import cv2
import numpy as np

from robostereo.errors import PlausibilityWarning
from robostereo.geometry.poses import SE3, as_se3
from robostereo.robot.simulated.grab_views import simulate_views
from robostereo.robot.simulated.views_truth import views_depth_errors
from robostereo.robot.views.locating import locate_views


def _bad_variants(cap: Any) -> list[tuple[str, Any]]:
    k = len(cap) - 1
    b = cap.centres[k] - cap.centres.mean(axis=0)
    b /= np.linalg.norm(b)
    pose = as_se3(cap.poses[k])
    across = np.cross(b, pose.rotation[:, 2])

    def moved(d: np.ndarray) -> Any:
        poses = list(cap.poses)
        poses[k] = SE3(pose.rotation, pose.translation + d)
        return dataclasses.replace(cap, poses=tuple(poses))

    def turned(deg: float) -> Any:
        poses = list(cap.poses)
        poses[k] = pose @ SE3.from_rotvec([0.0, 0.0, 0.0], [0.0, 0.0, np.radians(deg)])
        return dataclasses.replace(cap, poses=tuple(poses))

    def blurred(sigma: float) -> Any:
        images = list(cap.images)
        img = np.asarray(images[k])
        images[k] = cv2.GaussianBlur(img, (0, 0), sigma).astype(img.dtype)
        return dataclasses.replace(cap, images=tuple(images))

    return [("right", cap), (f"view {k} 2 mm along", moved(2 * b)),
            (f"view {k} 3 mm along", moved(3 * b)),
            (f"view {k} 3 mm across", moved(3 * across)),
            (f"view {k} turned 0.5 deg", turned(0.5)),
            (f"view {k} blur 2", blurred(2.0)), (f"view {k} blur 4", blurred(4.0))]


def _row(name: str, cap: Any, errors: Any) -> dict[str, Any]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PlausibilityWarning)
        loc = locate_views(cap)
    err = errors(cap, loc)
    sure = (loc.confidence >= 0.9) & (err > 3 * loc.bound_mm)
    said = [str(w.message)[:90] for w in caught
            if issubclass(w.category, PlausibilityWarning)]
    return {"case": name, "points": len(loc),
            "z": float(np.median(loc.world[:, 2])) if len(loc) else float("nan"),
            "sure_far": int(sure.sum()), "share": float(sure.mean()) if len(loc) else 0.0,
            "worst": float(err[sure].max()) if sure.any() else 0.0, "said": said}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--renders", action="store_true",
                    help="also tests/view_renders.py's printed ground (needs "
                         "PYTHONPATH=tests)")
    args = ap.parse_args()
    rows = []
    for kind, robot, pattern, count, span in (("pulley", "scara", "line", 3, 40.0),
                                              ("pulley", "six-axis", "line", 5, 80.0),
                                              ("block", "scara", "cross", 5, 80.0),
                                              ("pulley", "scara", "cross", 5, 80.0)):
        sim = simulate_views(kind, count=count, pattern=pattern, span_mm=span,  # type: ignore[arg-type]
                             robot=robot)  # type: ignore[arg-type]
        for case, cap in _bad_variants(sim.capture):
            rows.append(_row(f"sim {kind} {robot} {pattern} {count}: {case}", cap,
                             lambda c, loc, sim=sim: views_depth_errors(sim, loc)))
        print(f"done sim {kind} {robot} {pattern} {count}", flush=True)
    if args.renders:
        from view_renders import RenderSpec, render_views

        for pattern, count in (("cross", 5), ("line", 3), ("line", 5), ("cross", 9)):
            cap, truth = render_views(RenderSpec(texture="print", pattern=pattern,
                                                 count=count, seed=1))
            for case, bad in _bad_variants(cap):
                rows.append(_row(f"render print {pattern} {count}: {case}", bad,
                                 lambda c, loc, truth=truth: truth.depth_errors(c, loc)))
            print(f"done render {pattern} {count}", flush=True)
    rows.sort(key=lambda r: -r["share"])
    print("case | points | median z mm | conf >= 0.9 beyond 3 bounds | worst mm | said")
    print("--- | --- | --- | --- | --- | ---")
    for r in rows:
        print(f"{r['case']} | {r['points']} | {r['z']:.2f} | {r['sure_far']} "
              f"({100 * r['share']:.2f} %) | {r['worst']:.1f} | {' / '.join(r['said'])}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
