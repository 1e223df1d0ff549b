"""The robot commands: ``demo``, ``capture``, ``locate``, ``handeye``,
``simulate-handeye`` and ``plan``.

``demo`` and ``capture`` run the thesis's SCARA (the AdeptOne) or, with ``--robot
six-axis``, the six-axis arm; ``locate --fuse`` merges two capture folders.  With
``--views N`` (and ``locate`` on a folder of N views) ``demo``, ``capture``, ``locate``
and ``plan`` hand over to :mod:`robostereo.cli.views`.  Each
handler parses, loads, calls the library and writes; every user error is an
:class:`~robostereo.errors.InputError` (one line, exit code 2, no partial output).
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import sys
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.cli._args import (
    finite,
    require_at_least,
    require_empty_folder,
    require_output_folder,
    require_positive,
    require_seed,
)
from robostereo.cli._console import stage_reporter
from robostereo.cli.views import (
    add_views_options,
    run_demo_views,
    run_locate_views,
    run_plan_views,
    views_capture,
)
from robostereo.errors import InputError, require_file

__all__ = [
    "add_capture_parser",
    "add_demo_parser",
    "add_handeye_parser",
    "add_locate_parser",
    "add_parsers",
    "add_plan_parser",
    "add_simulate_handeye_parser",
    "run_capture_command",
    "run_demo_command",
    "run_handeye",
    "run_locate_command",
    "run_plan",
    "run_simulate_handeye",
]


def add_parsers(sub: Any) -> None:
    """Add ``demo``, ``capture``, ``locate``, ``handeye``, ``simulate-handeye`` and
    ``plan`` to the subcommands `sub`."""
    add_demo_parser(sub)
    add_capture_parser(sub)
    add_locate_parser(sub)
    add_handeye_parser(sub)
    add_simulate_handeye_parser(sub)
    add_plan_parser(sub)


# -- demo ------------------------------------------------------------------------------


def add_demo_parser(sub: Any) -> None:
    p = sub.add_parser(
        "demo", help="run the thesis's experiments on the simulated AdeptOne (no files needed)",
        description="Render the precision block at two heights 79.65 mm apart and the "
                    "hub-pulley as the simulated AdeptOne's forearm camera sees them from "
                    "two viewpoints 20 mm apart, locate the edge points, and print table 5-1 "
                    "and the hub-pulley's % matched and % false per iteration; write the "
                    "figures to the output folder.  With --views N: locate the block (at two "
                    "heights) and the pulley from N views in a pattern and print the "
                    "figures (nothing written).",
    )
    p.add_argument("--out", type=Path,
                   help="folder for the figures (created; default ./robostereo-out)")
    p.add_argument("--seed", type=int, default=0, help="sensor-noise seed (0)")
    p.add_argument("--robot", choices=("adeptone", "six-axis"), default="adeptone",
                   help="the thesis's SCARA (adeptone, default) or the six-axis arm's block "
                        "experiment with an estimated hand-eye transform")
    p.add_argument("--json", action="store_true",
                   help="six-axis or --views: print one JSON object")
    add_views_options(p)
    p.set_defaults(handler=run_demo_command)


def run_demo_command(args: argparse.Namespace) -> int:
    from rich.console import Console

    if args.views is not None or args.pattern is not None or args.span is not None:
        return run_demo_views(args)
    if args.out is None:
        args.out = Path("robostereo-out")
    if args.robot != "six-axis" and args.json:
        raise InputError("--json needs --robot six-axis or --views")
    require_seed(args.seed)
    if args.out.exists() and not args.out.is_dir():
        raise InputError(f"{args.out}: exists and is not a folder")
    if args.robot == "six-axis":
        return _run_demo_six_axis(args)

    from robostereo.experiments import print_demo_report, run_demo, save_demo_figures

    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        say("rendering and matching the block and the hub-pulley")
        result = run_demo(seed=args.seed)
    print_demo_report(result, Console())
    args.out.mkdir(parents=True, exist_ok=True)
    paths = save_demo_figures(result, args.out)
    print(f"figures: {', '.join(str(p) for p in paths)}")
    return 0


def _run_demo_six_axis(args: argparse.Namespace) -> int:
    from robostereo.io import check_outputs
    from robostereo.robot.handeye import save_handeye_yaml
    from robostereo.robot.simulated.sixaxis_rig import run_six_axis_block

    for name in ("capture-low", "capture-high"):
        d = args.out / name
        if d.exists() and not (d / "capture.yaml").is_file():
            raise InputError(f"{d}: exists and is not a capture folder")
    _require_writable(args.out, args.out)  # before the simulation's 10-15 s of work
    if args.out.is_dir():
        check_outputs({"--out": args.out / "handeye.yaml"})
    res = run_six_axis_block(seed=args.seed)
    args.out.mkdir(parents=True, exist_ok=True)
    # the two capture folders and handeye.yaml: all written, or none
    _replace_captures({args.out / "capture-low": res.heights[0].sim.capture,
                       args.out / "capture-high": res.heights[1].sim.capture},
                      then=lambda: save_handeye_yaml(args.out / "handeye.yaml",
                                                     res.calibration))
    s = res.summary()
    if args.json:
        print(json.dumps(s))
        return 0
    d = s["pose_difference"]
    print("six-axis arm (UR5-like, simulated), wrist camera 640 x 480 with lens distortion")
    print(f"  camera tilted {s['camera_tilt_deg']:.1f} deg from vertical; right minus left "
          f"view: {d['dx_mm']:.1f}, {d['dy_mm']:.1f}, {d['dz_mm']:.1f} mm, "
          f"{d['droll_deg']:.2f}, {d['dpitch_deg']:.2f}, {d['dyaw_deg']:.2f} deg")
    print(f"  hand-eye ({s['handeye_method']}, estimated from simulated views): error "
          f"{s['handeye_translation_error_mm']:.3f} mm, "
          f"{s['handeye_rotation_error_deg']:.4f} deg; board reprojection RMS "
          f"{s['reprojection_rms_px']:.3f} px")
    print(f"  block top edge points: {s['block_points'][0]} (low), {s['block_points'][1]} "
          "(high)")
    print(f"  lift: measured {s['lift_mm']:.2f} mm, true {s['lift_true_mm']:.2f} mm "
          f"(error {s['lift_mm'] - s['lift_true_mm']:+.2f} mm)")
    print(f"  largest |z error| {s['max_abs_error_mm']:.2f} mm, its eq. 9 bound "
          f"{s['bound_at_max_error_mm']:.2f} mm; every point within its bound: "
          f"{'yes' if s['all_within_bound'] else 'NO'}")
    print(f"captures: {args.out / 'capture-low'}, {args.out / 'capture-high'}; "
          f"calibration: {args.out / 'handeye.yaml'}")
    return 0


def _replace_captures(captures: dict[Path, Any], then: Any = None) -> None:
    """Write every capture folder beside its target first (and run `then`, the last
    output, inside an atomic block), then rename them all into place: all or none."""
    from robostereo.robot.capture import write_capture

    temps = {t: t.with_name(f".{t.name}.new") for t in captures}
    try:
        for target, capture in captures.items():
            tmp = temps[target]
            if tmp.exists():
                shutil.rmtree(tmp)
            write_capture(tmp, capture)
            if target.exists() and not (target / "capture.yaml").is_file():
                raise InputError(f"{target}: exists and is not a capture folder")
        if then is not None:
            then()
    except BaseException:
        for tmp in temps.values():
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    for target, tmp in temps.items():
        if target.exists():
            shutil.rmtree(target)
        tmp.rename(target)


# -- capture ---------------------------------------------------------------------------


def add_capture_parser(sub: Any) -> None:
    p = sub.add_parser(
        "capture", help="grab two (or N) views with the (simulated) robot into a capture "
                        "folder",
        description="Move the AdeptOne's forearm camera to -D/2 and +D/2 about the centre "
                    "along the baseline direction, grab an image at each (rendered by the "
                    "simulator) and write DIR/left.png, DIR/right.png and DIR/capture.yaml.  "
                    "With --views N: grab N views in a pattern spanning --span mm about the "
                    "centre and write DIR/view_00.png, ... and DIR/capture.yaml (views:).",
    )
    p.add_argument("--out", type=Path, required=True, metavar="DIR",
                   help="capture folder to create (must not exist, or be empty)")
    p.add_argument("--scene", choices=("block", "pulley"), default="block",
                   help="simulated object (block)")
    p.add_argument("--lift", type=finite("--lift", 1e6), default=0.0,
                   help="block: raise of its top, mm (0; the thesis's second set: 79.65)")
    p.add_argument("--baseline", type=finite("--baseline", 1e6), default=20.0,
                   help="baseline D, mm (20)")
    p.add_argument("--direction", type=finite("--direction", 1e6), default=0.0,
                   help="baseline direction from world X, degrees (0)")
    p.add_argument("--roll", type=finite("--roll", 1e6), default=0.0,
                   help="camera yaw against the baseline at the centre, degrees (0)")
    p.add_argument("--center", type=finite("--center", 1e6), nargs=2, default=(400.0, 0.0),
                   metavar=("X", "Y"), help="mid-baseline point, world mm (400 0)")
    p.add_argument("--seed", type=int, default=0, help="sensor-noise seed (0)")
    p.add_argument("--robot", choices=("adeptone", "six-axis"), default="adeptone",
                   help="simulated robot (adeptone: the thesis's SCARA)")
    p.add_argument("--tilt", type=finite("--tilt"), default=25.0,
                   help="six-axis: camera tilt from vertical, degrees (25)")
    p.add_argument("--handeye", type=Path,
                   help="six-axis: record this camera file's camera and hand_eye "
                        "(robostereo handeye's output) instead of the truth")
    add_views_options(p)
    p.set_defaults(handler=run_capture_command)


def run_capture_command(args: argparse.Namespace) -> int:
    from robostereo.experiments import RigSetup, simulate_capture
    from robostereo.robot.capture import write_capture

    if args.views is not None or args.pattern is not None or args.span is not None:
        return views_capture(args)
    baseline = args.baseline
    if args.robot == "six-axis":
        if args.direction != 0.0 or args.roll != 0.0 or tuple(args.center) != (400.0, 0.0):
            raise InputError("--direction, --roll and --center are for --robot adeptone; "
                             "the six-axis arm takes --baseline, --tilt and --handeye")
        if baseline == 20.0:  # the SCARA default; the six-axis views stand 40 mm apart
            baseline = 40.0
    require_seed(args.seed)
    require_empty_folder(args.out)
    if args.robot == "six-axis":
        return _run_capture_six_axis(args, baseline)

    setup = RigSetup(center_xy=(args.center[0], args.center[1]), baseline_mm=baseline,
                     direction_deg=args.direction, roll_deg=args.roll)
    sim = simulate_capture(args.scene, setup=setup, lift_mm=args.lift, seed=args.seed)
    write_capture(args.out, sim.capture)
    g = sim.capture.epipolar
    print(f"{args.out}: {args.scene}, D = {g.baseline_mm:.3f} mm, alpha = "
          f"{math.degrees(g.alpha):.3f} deg, theta_l = {math.degrees(g.theta_l):.3f} deg, "
          f"theta_r = {math.degrees(g.theta_r):.3f} deg")
    return 0


def _run_capture_six_axis(args: argparse.Namespace, baseline: float) -> int:
    from robostereo.robot.capture import write_capture
    from robostereo.robot.handeye import load_handeye_yaml
    from robostereo.robot.simulated.sixaxis_rig import SixAxisViewpoints, simulate_six_axis_capture

    camera = hand_eye = None
    if args.handeye is not None:
        camera, hand_eye = load_handeye_yaml(args.handeye)
    require_positive("--baseline", baseline)
    if not 0 <= args.tilt < 80:
        raise InputError(f"--tilt must be in [0, 80) degrees, got {args.tilt}")
    vp = SixAxisViewpoints(baseline_mm=baseline, tilt_deg=args.tilt)
    sim = simulate_six_axis_capture(args.scene, lift_mm=args.lift, seed=args.seed,
                                    viewpoints=vp, hand_eye=hand_eye, camera=camera)
    write_capture(args.out, sim.capture)
    g = sim.capture.epipolar
    print(f"{args.out}: {args.scene} from the six-axis arm, D = {g.baseline_mm:.3f} mm, "
          f"camera tilted {args.tilt:g} deg, hand-eye "
          f"{'from ' + str(args.handeye) if args.handeye else 'true (simulated)'}")
    return 0


# -- locate ----------------------------------------------------------------------------


def add_locate_parser(sub: Any) -> None:
    p = sub.add_parser(
        "locate", help="3-D world coordinates of the edge points of a capture folder",
        description="Rectify a capture folder's two views by their poses, match the edge "
                    "points, and write world and epipolar-frame coordinates with the eq. 9 "
                    "depth bound of every point (CSV; optionally PLY).  A folder of N views "
                    "(capture.yaml with views:): search each edge point's ray in the other "
                    "views, every view as reference, and write each point once with its "
                    "bound, confidence and view count.",
    )
    p.add_argument("capture", type=Path, metavar="DIR", help="capture folder")
    p.add_argument("-o", "--output", type=Path,
                   help="points CSV (default DIR/located.csv)")
    p.add_argument("--ply", type=Path, help="write the world points as PLY")
    p.add_argument("--fuse", type=Path, metavar="DIR2",
                   help="a second capture of the scene (e.g. an orthogonal baseline): write "
                        "the two point sets merged, each point with its own bound")
    p.set_defaults(handler=run_locate_command)


def run_locate_command(args: argparse.Namespace) -> int:
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.robot.capture import locate_capture

    for d in (args.capture, args.fuse):
        if d is not None and not d.is_dir():
            raise InputError(f"{d}: capture folder not found")
    from robostereo.robot.views.views_folder import is_views_folder

    if any(d is not None and is_views_folder(d) for d in (args.capture, args.fuse)):
        return run_locate_views(args)
    if args.fuse is not None:
        return _run_locate_fused(args)

    output = args.output if args.output is not None else args.capture / "located.csv"
    outs = check_outputs({"-o": output, "--ply": args.ply}, inputs=_capture_files(args))
    located = locate_capture(args.capture)
    with atomic_outputs(outs) as tmp:  # all outputs or none
        write_csv(tmp["-o"], located.table())
        if "--ply" in tmp:
            write_ply(tmp["--ply"], located.world)
    n_left, n = len(located.result.left_edges), len(located)
    lo, hi = located.disparity_range
    zb = located.z_bound
    bound = f", depth bound {np.median(zb):.1f} mm (median)" if n else ""
    print(f"{args.capture}: disparity {lo:g} .. {hi:g} px, {n_left} edge points, {n} located"
          f"{bound} -> {output}")
    return 0


def _capture_files(args: argparse.Namespace) -> list[Path]:
    """The files of the capture folders a ``locate`` reads (none may be an output)."""
    from robostereo.robot.capture import CAPTURE_YAML

    return [d / n for d in (args.capture, args.fuse) if d is not None
            for n in (CAPTURE_YAML, "left.png", "right.png")]


def _run_locate_fused(args: argparse.Namespace) -> int:
    from robostereo.io import atomic_outputs, check_outputs, write_csv, write_ply
    from robostereo.robot.capture import locate_capture
    from robostereo.robot.planning import fuse_located

    output = args.output if args.output is not None else args.capture / "located-fused.csv"
    outs = check_outputs({"-o": output, "--ply": args.ply}, inputs=_capture_files(args))
    a, b = locate_capture(args.capture), locate_capture(args.fuse)
    fused = fuse_located(a, b)
    with atomic_outputs(outs) as tmp:  # all outputs or none
        write_csv(tmp["-o"], fused.table())
        if "--ply" in tmp:
            write_ply(tmp["--ply"], fused.world)
    print(f"{args.capture}: {len(a)} located; {args.fuse}: {len(b)} located; fused "
          f"{len(fused)} points ({fused.duplicates} seen twice) -> {output}")
    return 0


# -- handeye, simulate-handeye ---------------------------------------------------------


def add_handeye_parser(sub: Any) -> None:
    from robostereo.robot.handeye import DEFAULT_METHOD, METHODS

    p = sub.add_parser(
        "handeye", help="eye-in-hand calibration from views of a chessboard",
        description="From a views folder (views.yaml: the board, and per view an image "
                    "and the flange pose the robot reported) estimate the camera's "
                    "intrinsics and distortion (OpenCV calibrateCamera) and the "
                    "flange-to-camera transform (AX = XB), refine both jointly on the "
                    "board corners, print the per-view and per-pair residuals, refuse an "
                    "implausible result (exit 2), and write camera.yaml.",
    )
    p.add_argument("views", type=Path, metavar="VIEWS_DIR", help="hand-eye views folder")
    p.add_argument("-o", "--output", type=Path, required=True,
                   help="camera file to write (camera and hand_eye)")
    p.add_argument("--method", choices=METHODS, default=DEFAULT_METHOD,
                   help=f"AX = XB closed form that starts the refinement ({DEFAULT_METHOD})")
    p.add_argument("--intrinsics", type=Path, metavar="CAMERA_YAML",
                   help="known intrinsics and distortion (a camera YAML or a handeye "
                        "output), held fixed: only the hand-eye transform and the board "
                        "pose are refined")
    p.add_argument("--reject-outliers", action="store_true",
                   help="drop the views whose residuals stand out (robust z-score > 3.5 "
                        "of the reprojection RMS or of the AX = XB residuals of their "
                        "pairs) and solve again once")
    p.set_defaults(handler=run_handeye)


_PAIRS_SHOWN = 10


def run_handeye(args: argparse.Namespace) -> int:
    from robostereo.io import check_outputs
    from robostereo.robot.handeye import (
        VIEWS_YAML,
        calibrate_eye_in_hand,
        describe_board,
        read_views,
        save_handeye_yaml,
    )

    require_output_folder(args.output)
    camera = None
    if args.intrinsics is not None:
        camera, extra = _load_any_camera(args.intrinsics)
        if extra:  # the stereo camera YAML of match --camera
            raise InputError(f"--intrinsics {args.intrinsics}: a stereo camera YAML has no "
                             "distortion or image size; give a camera YAML or the file "
                             "robostereo handeye wrote")
    v = read_views(args.views)
    # refuse an input as the output (views.yaml, an image, the intrinsics file)
    check_outputs({"-o": args.output},
                  inputs=[args.views / VIEWS_YAML, *v.names, args.intrinsics])
    cal = calibrate_eye_in_hand(v.images, v.flange_poses, v.board,
                                pixel_pitch_mm=v.pixel_pitch_mm, grey_levels=v.grey_levels,
                                method=args.method, names=v.names, camera=camera,
                                reject_outliers=args.reject_outliers,
                                source=str(args.views / VIEWS_YAML))
    save_handeye_yaml(args.output, cal)  # written whole, or not at all
    _print_handeye(args, v, cal, describe_board(v.board))
    return 0


def _print_handeye(args: argparse.Namespace, v: Any, cal: Any, board: str) -> None:
    cam = cal.camera
    names = [Path(n).name for n in cal.names]
    n = len(names)
    print(f"{len(v.images)} views, {board}, {v.board.square_mm:g} mm squares"
          + (f"; rejected as outliers: {', '.join(Path(r).name for r in cal.rejected)}"
             if cal.rejected else ""))
    pairs = cal.pairs
    tr, rot = cal.residuals.translation_mm, cal.residuals.rotation_deg
    ii = np.array([p[0] for p in pairs] + [p[1] for p in pairs], dtype=int)
    cnt = np.maximum(np.bincount(ii, minlength=n), 1)
    view_tr = np.sqrt(np.bincount(ii, np.concatenate([tr, tr]) ** 2, minlength=n) / cnt)
    view_rot = np.sqrt(np.bincount(ii, np.concatenate([rot, rot]) ** 2, minlength=n) / cnt)
    out = {Path(o).name for o in cal.outliers}
    width = max(len(x) for x in names)
    print(f"  {'view':<{width}}  reprojection RMS px  pairs' AX = XB RMS: mm    deg")
    for k, name in enumerate(names):
        print(f"  {name:<{width}}  {cal.per_view_rms_px[k]:19.3f}  {view_tr[k]:24.3f}  "
              f"{view_rot[k]:.4f}{'  stands out' if name in out else ''}")
    head = f"pair (worst {min(_PAIRS_SHOWN, len(pairs))} of {len(pairs)}; all in the output)"
    print(f"  {head:<{2 * width + 3}}  AX vs XB: mm      deg")
    for k in np.argsort(tr)[::-1][:_PAIRS_SHOWN]:
        i, j = pairs[k]
        print(f"  {names[i] + ' - ' + names[j]:<{2 * width + 3}}  {tr[k]:12.3f}  {rot[k]:.4f}")
    print(f"camera{' (held fixed)' if args.intrinsics else ''}: fx {cam.fx:.2f} px, fy "
          f"{cam.fy:.2f} px, principal point ({cam.principal_point[0]:.2f}, "
          f"{cam.principal_point[1]:.2f}), distortion "
          f"[{', '.join(f'{d:.5f}' for d in cam.distortion)}], "
          f"RMS {cal.reprojection_rms_px:.3f} px (corner noise {cal.corner_noise_px:.3f} px)")
    t, rv = cal.hand_eye.translation, cal.hand_eye.rotvec
    moved = cal.closed_form.distance_to(cal.hand_eye) if cal.closed_form else (0.0, 0.0)
    print(f"hand-eye ({args.method}, jointly refined: moved {moved[0]:.3f} mm, "
          f"{math.degrees(moved[1]):.4f} deg): translation [{t[0]:.3f}, {t[1]:.3f}, "
          f"{t[2]:.3f}] mm, rotation vector [{rv[0]:.5f}, {rv[1]:.5f}, {rv[2]:.5f}] rad")
    r = cal.residuals
    print(f"AX = XB residuals over {len(r.rotation_deg)} view pairs: rotation RMS "
          f"{r.rms_rotation_deg:.4f} deg (max {r.rotation_deg.max():.4f}), translation RMS "
          f"{r.rms_translation_mm:.3f} mm (max {r.translation_mm.max():.3f}; corner noise "
          f"explains {cal.predicted_translation_rms_mm:.3f}) -> {args.output}")
    if cal.outliers and not cal.rejected:
        print(f"views that stand out: {', '.join(Path(o).name for o in cal.outliers)} "
              "(--reject-outliers drops them)")


MAX_SIMULATED_VIEWS = 200
"""Most views ``simulate-handeye`` renders: each takes about half a second and the
view pairs grow as n^2 (19 900 at 200), while 15-40 views already settle the result."""


def _require_writable(folder: Path, what: Path) -> None:
    """Refuse before any work a `folder` (or its nearest existing ancestor) in which no
    file can be made: a probe folder is created and removed at once."""
    import tempfile

    probe = folder
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    try:
        Path(tempfile.mkdtemp(prefix=".robostereo-probe-", dir=probe)).rmdir()
    except OSError as e:
        raise InputError(f"{what}: folder {probe} is not writable ({e.strerror})") from None


def add_simulate_handeye_parser(sub: Any) -> None:
    p = sub.add_parser(
        "simulate-handeye", help="write a simulated hand-eye views folder (six-axis arm)",
        description="Render a chessboard from tilted views of the simulated six-axis arm's "
                    "wrist camera and write a hand-eye views folder: views.yaml, the images, "
                    "and the truth (camera, hand_eye, base_board) in truth.yaml.",
    )
    p.add_argument("--out", type=Path, required=True, metavar="DIR",
                   help="views folder to create (must not exist, or be empty)")
    p.add_argument("--views", type=int, default=15,
                   help=f"number of views, 3 to {MAX_SIMULATED_VIEWS} (15)")
    p.add_argument("--seed", type=int, default=0, help="viewpoint and noise seed (0)")
    p.add_argument("--board", choices=("chessboard", "charuco"), default="chessboard",
                   help="calibration target: a 9 x 6 chessboard or an 8 x 6 ChArUco board")
    p.set_defaults(handler=run_simulate_handeye)


def run_simulate_handeye(args: argparse.Namespace) -> int:
    from robostereo.robot.handeye import Charuco, write_views
    from robostereo.robot.simulated.sixaxis_rig import BOARD, simulate_handeye_views

    require_at_least("--views", args.views, 3)
    if args.views > MAX_SIMULATED_VIEWS:
        raise InputError(f"--views must be <= {MAX_SIMULATED_VIEWS} (each view is rendered "
                         f"and the pairs grow as n^2), got {args.views}")
    require_seed(args.seed)
    require_empty_folder(args.out)
    _require_writable(args.out.parent if str(args.out.parent) else Path("."), args.out)
    board = Charuco() if args.board == "charuco" else BOARD
    views, truth = simulate_handeye_views(views=args.views, seed=args.seed, board=board)
    write_views(args.out, views, extra={"truth.yaml": truth})
    print(f"{args.out}: {args.views} views of a {args.board}; truth in "
          f"{args.out / 'truth.yaml'}")
    return 0


# -- plan ------------------------------------------------------------------------------


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


def _load_any_camera(path: Path) -> tuple[Any, dict[str, float]]:
    """The camera of a camera YAML, of ``robostereo handeye``'s camera file or of
    ``match``'s stereo camera YAML; with the eq. 9 uncertainties that file gives.

    A stereo camera YAML (keys ``fx``/``fy`` or ``baseline_mm``) gives a camera of its
    focal length in pixels (a nominal 1 mm lens over pixels of ``1/fx`` mm, so the
    focal-length uncertainty keeps its ratio) and, without ``image_size``, no image
    width to bound the disparities by."""
    import yaml

    from robostereo.geometry.camera import Camera, camera_from_dict
    from robostereo.io.cameras import load_camera_yaml, stereo_camera_from_dict

    require_file(path, "camera file")
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError):
        data = None
    if isinstance(data, dict) and "camera" in data:
        return camera_from_dict(data["camera"], source=f"{path}: camera"), {}
    if isinstance(data, dict) and ("fx" in data or "baseline_mm" in data):
        sc = stereo_camera_from_dict(data, source=str(path))
        size = data.get("image_size")
        known = isinstance(size, list | tuple) and len(size) == 2
        cam = Camera(focal_length_mm=1.0, pixel_pitch_mm=(1.0 / sc.fx, 1.0 / sc.fy),
                     image_size=(int(size[0]), int(size[1])) if known else (5, 5))
        extra: dict[str, float] = {
            "baseline_uncertainty_mm": sc.baseline_uncertainty_mm,
            "focal_length_uncertainty_mm": sc.focal_uncertainty_px / sc.fx}
        if not known:
            extra["max_disparity_px"] = math.inf
        return cam, extra
    return load_camera_yaml(path), {}


def run_plan(args: argparse.Namespace) -> int:
    from robostereo.geometry.camera import SEED_CAMERA
    from robostereo.robot.planning import best_baseline_direction, plan_baseline

    for name in ("depth", "accuracy", "near", "far"):
        v = getattr(args, name)
        if v is not None and not v > 0:
            raise InputError(f"--{name} must be > 0 mm, got {v:g}")
    camera, extra = (_load_any_camera(args.camera) if args.camera is not None
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
