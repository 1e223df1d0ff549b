"""``robostereo evaluate``: the matcher and StereoSGBM scored on scenes with ground truth.

Parses, loads, calls the library (:func:`~robostereo.evaluation.evaluate_scene`; for a
capture folder with depth maps, recognised by its ``capture.yaml``, locating as
``robostereo locate`` does and :func:`~robostereo.evaluation.evaluate_capture_depth`) and
prints; a scene that fails is reported and skipped (exit code 2 at the end), any other
user error is an :class:`~robostereo.errors.InputError` (one line, exit code 2).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

from robostereo.cli._args import (
    add_matcher_args,
    disparity_range_args,
    finite,
    matcher_params,
)
from robostereo.cli._console import stage_reporter
from robostereo.errors import InputError

__all__ = ["add_evaluate_parser", "evaluate_capture_folder", "run_evaluate"]


def add_evaluate_parser(sub: Any) -> None:
    p = sub.add_parser(
        "evaluate", help="score the matcher and StereoSGBM on scenes with ground truth",
        description="For each scene folder (left/right/gt_disp_left as in the developer "
                    "set, or a Middlebury layout): edge points, % matched, % false by the "
                    "project's rule (or --rule silhouette), disparity RMS, and the same for "
                    "StereoSGBM at the same pixels, with times; 3-D errors in mm with a "
                    "Middlebury calib.txt.  Then "
                    "both rules (the project's and the silhouette rule) near depth steps and "
                    "away, the confidence's calibration error, 3-D distances to the ground-"
                    "truth surface (with calib.txt) and silhouette offsets.  A capture "
                    "folder (capture.yaml) with ground-truth depth maps is located as "
                    "robostereo locate does and scored against its reference view's depth "
                    "map: 3-D errors, the share within each point's bound, the coverage "
                    "of the edge pixels both views see, and the same for StereoSGBM on "
                    "the rectified pair.",
    )
    p.add_argument("scenes", type=Path, nargs="+", metavar="SCENE_DIR",
                   help="scene folders or capture folders with depth maps (other "
                        "arguments, e.g. README.md, are skipped)")
    p.add_argument("--json", action="store_true", help="print JSON instead of tables")
    p.add_argument("--min-disparity", type=finite("--min-disparity"),
                   help="search range (default: the ground truth's)")
    p.add_argument("--max-disparity", type=finite("--max-disparity"))
    p.add_argument("--scale", type=finite("--scale"),
                   help="ground-truth scale d = raw / scale (default: scenes.json or known)")
    p.add_argument("--no-sgbm", action="store_true", help="leave out StereoSGBM")
    p.add_argument("--no-curves", action="store_true",
                   help="only the default operating points (no SGBM settings sweep)")
    p.add_argument("--plot", type=Path, metavar="DIR",
                   help="write each scene's two curves as DIR/SCENE_curves.png (a "
                        "capture's error histogram and coverage image as "
                        "DIR/NAME_depth_errors.png and DIR/NAME_coverage.png)")
    p.add_argument("--rule", choices=("project", "silhouette"), default="project",
                   help="the rule of the figures over all points and of the curves: the "
                        "project's (default, kept for continuity) or the silhouette rule, "
                        "fair to occluding contours; the outline figures give both")
    p.add_argument("--threshold", type=finite("--threshold"), default=None,
                   help="the edge threshold, grey levels per pixel on the 0..127 scale "
                        "(default 8.0); of a capture folder also that of the scored edge "
                        "pixels")
    p.add_argument("--matcher", choices=("auto", "pairs", "sweep"), default=None,
                   help="N-view capture folders: as robostereo locate's --matcher")
    add_matcher_args(p)
    p.set_defaults(handler=run_evaluate)


def run_evaluate(args: argparse.Namespace) -> int:
    import json

    from robostereo.datasets import load_scene
    from robostereo.evaluation import (
        evaluate_scene,
        format_capture_evaluation,
        format_evaluation,
    )
    from robostereo.matcher.parameters import MatchParameters
    from robostereo.plots import save_capture_plots, save_curves

    drange = disparity_range_args(args)
    if args.plot is not None and not args.plot.is_dir():
        raise InputError(f"--plot {args.plot}: output folder does not exist")
    params = matcher_params(args, MatchParameters())
    if args.threshold is not None:
        params = replace(params, threshold=args.threshold)
    dirs = [s for s in args.scenes if s.is_dir()]
    for s in args.scenes:
        if not s.is_dir():
            print(f"robostereo: note: skipping {s} (not a scene folder)", file=sys.stderr)
    if not dirs:
        raise InputError(f"no scene folders among {', '.join(map(str, args.scenes))}")
    results, failed = [], 0
    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        for d in dirs:
            say(f"evaluating {d}")
            if (d / "capture.yaml").is_file():
                try:
                    cev, image = evaluate_capture_folder(d, args, params)
                except InputError as e:
                    print(f"robostereo: error: {e}", file=sys.stderr)
                    failed += 1
                    continue
                results.append(cev)
                if not args.json:
                    print(format_capture_evaluation(cev) + "\n", flush=True)
                if args.plot is not None:
                    save_capture_plots(cev, image, args.plot)
                continue
            try:
                scene = load_scene(d, scale=args.scale)
                ev = evaluate_scene(scene, disparity_range=drange, sgbm=not args.no_sgbm,
                                    curve=not args.no_curves, rule=args.rule,
                                    params=replace(params, bit_depth=scene.bit_depth))
            except InputError as e:
                print(f"robostereo: error: {e}", file=sys.stderr)
                failed += 1
                continue
            results.append(ev)
            if not args.json:
                print(format_evaluation(ev) + "\n", flush=True)
            if args.plot is not None:
                save_curves(ev, args.plot / f"{ev.name}_curves.png")
    if args.json:
        print(json.dumps([ev.as_dict() for ev in results], indent=2))
    return 2 if failed else 0


def evaluate_capture_folder(directory: Path, args: argparse.Namespace,
                            match: Any) -> tuple[Any, Any]:
    """A capture folder located as ``robostereo locate`` does and scored against its
    depth maps; the evaluation and the reference view's image.

    `match` is the matcher's parameters (the defaults, ``--threshold`` and the matcher
    options: ``robostereo locate``'s when none is given).  Two views: the left view is
    the reference, located by the two-view matcher.  N
    views: the reference is the view nearest the centroid of the optical centres (the
    first reference of the sweep, the pairs' reference), its points those found from
    it; the other view (edges both see, SGBM's right view) is the view nearest it.
    """
    import time

    import numpy as np

    from robostereo.evaluation import (
        CapturePoints,
        SgbmPair,
        capture_depth_files,
        evaluate_capture_depth,
    )
    from robostereo.robot.capture import LocateParameters, locate, read_capture
    from robostereo.robot.capture.locate_pair import rectify_pair
    from robostereo.robot.views.locating import locate_views
    from robostereo.robot.views.view_pairs import pair_reference
    from robostereo.robot.views.views_folder import is_views_folder, read_views_capture
    from robostereo.robot.views.views_parameters import ViewsParameters

    src = str(directory / "capture.yaml")
    threshold = float(match.threshold)  # --threshold's, else the default 8
    pair_params = LocateParameters(match=match)
    nview = is_views_folder(directory)
    if nview:
        views = read_views_capture(directory)
        ref = pair_reference(views)
        dist = np.linalg.norm(views.centres - views.centres[ref], axis=1)
        dist[ref] = np.inf
        other = int(np.argmin(dist))
        pair = views.pair(ref, other)
        names = (views.view_name(ref), views.view_name(other))
    else:
        if args.matcher is not None:
            raise InputError(f"{src}: --matcher chooses how an N-view folder (views:) is "
                             "matched; this folder has two views (left, right)")
        pair = read_capture(directory)
        ref, other, names = 0, 1, ("left.png", "right.png")
    camera = pair.camera
    files = capture_depth_files(directory)
    depth = files.read(ref, camera.image_size)  # a bad map is refused before locating
    if depth is None:
        key = "its depth" if nview else "depth_left"
        raise InputError(f"{src}: no depth map for the reference view {names[0]} (give "
                         f"{key} or depth/{Path(names[0]).stem}.pfm, .npy or .png)")
    other_depth = files.read(other, camera.image_size)
    t0 = time.perf_counter()
    if nview:
        params = ViewsParameters(matcher=args.matcher or "auto", pair_match=pair_params)
        if args.threshold is not None:  # the sweep's too, as robostereo locate's
            params = replace(params, threshold=threshold)
        located = locate_views(views, params=params, source=src)
        points = CapturePoints.from_located(located, ref)
        geometry = pair.geometry()
        rect = rectify_pair(pair.left, pair.right, geometry)
    else:
        two = locate(pair, params=pair_params, source=src)
        points = CapturePoints.from_located(two)
        geometry, rect = two.geometry, two.rectified
    seconds = time.perf_counter() - t0
    sgbm = None
    if not args.no_sgbm:
        sgbm = SgbmPair(rect.left, rect.right, geometry, pair.stereo_camera(geometry),
                        pair.resolved_disparity_range(geometry), int(pair.bit_depth))
    ev = evaluate_capture_depth(
        name=directory.resolve().name, directory=str(directory), camera=camera,
        poses=(pair.pose_left, pair.pose_right), image=pair.left, depth=depth,
        other_depth=other_depth, points=points, views=names, seconds=seconds, sgbm=sgbm,
        threshold=threshold, bit_depth=int(pair.bit_depth))
    return ev, pair.left
