"""``robostereo plan``: the baseline and disparity range for a depth accuracy (eq. 9
inverted), and the baseline direction; with ``--views``, the span of N views.

Parses, loads, calls the library (:mod:`robostereo.robot.planning`) and prints; every
user error is an :class:`~robostereo.errors.InputError` (one line, exit code 2).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.cli._args import finite
from robostereo.cli._camera_files import load_any_camera
from robostereo.cli._views_args import MAX_VIEWS, add_views_options, on_pattern
from robostereo.errors import InputError

__all__ = ["add_plan_parser", "run_plan", "run_plan_views"]


def add_plan_parser(sub: Any) -> None:
    p = sub.add_parser(
        "plan", help="baseline and disparity range for a depth accuracy; baseline direction",
        description="Invert eq. 9: the baseline D that bounds the depth error at the target "
                    "depth by the wanted accuracy, and the disparity range to search; with "
                    "--image, the baseline direction that makes most of the scene's edges "
                    "cross the epipolar lines.  With --views N (or auto): the span of N views "
                    "in a pattern that bounds the error alike (least squares over the views: "
                    "equal, independent edge errors in every view), and the disparity range "
                    "between neighbouring views.",
    )
    p.add_argument("--depth", type=finite("--depth"), required=True, help="target depth, mm")
    p.add_argument("--accuracy", type=finite("--accuracy"), required=True,
                   help="wanted eq. 9 bound, mm")
    p.add_argument("--camera", type=Path,
                   help="camera YAML (a capture's camera, or match's stereo camera YAML), "
                        "or robostereo handeye's camera file (default: the thesis's camera)")
    p.add_argument("--near", type=finite("--near"),
                   help="nearest depth to search, mm (0.8 x depth)")
    p.add_argument("--far", type=finite("--far"),
                   help="farthest depth to search, mm (1.2 x depth)")
    p.add_argument("--disparity-uncertainty", type=finite("--disparity-uncertainty"),
                   default=0.2, help="d(disp) of eq. 9, px (0.2)")
    p.add_argument("--image", type=Path, help="an image of the scene from the camera")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_views_options(p, plan=True)
    p.set_defaults(handler=run_plan)


def run_plan(args: argparse.Namespace) -> int:
    from robostereo.geometry.camera import SEED_CAMERA
    from robostereo.robot.planning import best_baseline_direction, plan_baseline

    for name in ("depth", "accuracy", "near", "far"):
        v = getattr(args, name)
        if v is not None and not v > 0:
            raise InputError(f"--{name} must be > 0 mm, got {v:g}")
    camera, extra = (load_any_camera(args.camera) if args.camera is not None
                     else (SEED_CAMERA, {}))
    near = args.near if args.near is not None else 0.8 * args.depth
    far = args.far if args.far is not None else 1.2 * args.depth
    if args.views is not None:
        return run_plan_views(args, camera, extra, near, far)
    if args.pattern is not None:
        raise InputError("--pattern needs --views N (or auto)")
    plan = plan_baseline(camera, args.depth, args.accuracy, depth_range_mm=(near, far),
                         disparity_uncertainty_px=args.disparity_uncertainty, **extra)
    out: dict[str, Any] = {
        # significant digits, not decimals: a 1e-5 mm baseline is not 0
        "baseline_mm": float(f"{plan.baseline_mm:.10g}"),
        "disparity_px": float(f"{plan.disparity_px:.10g}"),
        "disparity_range": list(plan.disparity_range),
        "bound_terms_mm": [float(f"{v:.10g}") for v in plan.bound_terms_mm],
    }
    if args.image is not None:
        from robostereo.io.images import load_image
        from robostereo.matcher.grey_levels import to_grey

        img, bits = load_image(args.image)
        grey = to_grey(np.asarray(img, dtype=np.float64), bit_depth=bits)
        bd = best_baseline_direction(grey)
        out.update({"direction_deg": bd.direction_deg,
                    "matchable_fraction": round(bd.matchable_fraction, 4),
                    "matchable_fraction_x": round(bd.matchable_fraction_x, 4)})
    if args.json:
        print(json.dumps(out))
        return 0
    t = plan.bound_terms_mm
    print(f"baseline D = {plan.baseline_mm:.4g} mm for a {args.accuracy:g} mm bound at "
          f"{args.depth:g} mm (eq. 9 terms: baseline {t[0]:.3f}, focal length {t[1]:.3f}, "
          f"disparity {t[2]:.3f} mm)")
    print(f"disparity {plan.disparity_px:.1f} px at the target; search "
          f"{plan.disparity_range[0]:g} .. {plan.disparity_range[1]:g} px for depths "
          f"{near:g} .. {far:g} mm")
    if args.image is not None:
        print(f"baseline direction: {out['direction_deg']:g} deg from the image's x axis "
              f"towards y (down): {100 * out['matchable_fraction']:.1f} % of the edge "
              f"strength crosses the epipolar lines at >= 30 deg "
              f"(along x: {100 * out['matchable_fraction_x']:.1f} %)")
    return 0


# -- plan --views N|auto ---------------------------------------------------------------


def run_plan_views(args: argparse.Namespace, camera: Any, extra: dict[str, float],
                   near: float, far: float) -> int:
    """``plan --views N|auto``: the span (and count) of N views in a pattern."""
    from robostereo.robot.planning import plan_views
    from robostereo.robot.views.viewpoints import PATTERNS

    text = str(args.views).strip().lower()
    views: int | None = None
    if text != "auto":
        try:
            views = int(text)
        except ValueError:
            raise InputError(f"--views must be a whole number in 2..{MAX_VIEWS} or 'auto', "
                             f"got {args.views!r}") from None
        if not 2 <= views <= MAX_VIEWS:
            raise InputError(f"--views must be in 2..{MAX_VIEWS}, got {views}")
    pattern = args.pattern if args.pattern is not None else "line"
    if pattern not in PATTERNS:
        raise InputError(f"--pattern must be one of {', '.join(PATTERNS)}, got {pattern!r}")
    if pattern == "cross" and views is not None and views < 3:
        raise InputError(f"--pattern cross needs --views >= 3, got {views}")
    if args.image is not None:
        raise InputError("--image chooses a two-view baseline direction; with --views a "
                         "cross sees every edge direction")
    plan = plan_views(camera, args.depth, args.accuracy, views=views, pattern=pattern,
                      depth_range_mm=(near, far),
                      disparity_uncertainty_px=args.disparity_uncertainty, **extra)
    out = {
        "views": plan.views,
        "pattern": plan.pattern,
        "span_mm": float(f"{plan.span_mm:.10g}"),
        "step_mm": float(f"{plan.step_mm:.10g}"),
        "effective_baseline_mm": float(f"{plan.effective_baseline_mm:.10g}"),
        "step_disparity_px": float(f"{plan.step_disparity_px:.10g}"),
        "disparity_range": list(plan.disparity_range),
        "bound_terms_mm": [float(f"{v:.10g}") for v in plan.bound_terms_mm],
    }
    if args.json:
        print(json.dumps(out))
        return 0
    t = plan.bound_terms_mm
    print(f"{plan.views} views {on_pattern(plan.pattern)} spanning {plan.span_mm:.4g} mm "
          f"(neighbours {plan.step_mm:.4g} mm apart) for a {args.accuracy:g} mm bound at "
          f"{args.depth:g} mm: as precise as two views {plan.effective_baseline_mm:.4g} mm "
          f"apart (eq. 9 terms: baseline {t[0]:.3f}, focal length {t[1]:.3f}, disparity "
          f"{t[2]:.3f} mm)")
    print(f"neighbouring views: disparity {plan.step_disparity_px:.1f} px at the target; "
          f"search {plan.disparity_range[0]:g} .. {plan.disparity_range[1]:g} px for depths "
          f"{near:g} .. {far:g} mm")
    return 0
