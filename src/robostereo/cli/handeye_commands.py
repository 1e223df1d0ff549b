"""``robostereo handeye`` and ``robostereo simulate-handeye``: eye-in-hand calibration
from views of a calibration board, and a simulated views folder to calibrate from.

``handeye`` reads a views folder, calls
:func:`~robostereo.robot.handeye.calibrate_eye_in_hand`, prints the per-view and
per-pair residuals and writes the camera file; ``simulate-handeye`` writes such a
folder from the simulated six-axis arm.  Every user error is an
:class:`~robostereo.errors.InputError` (one line, exit code 2, no partial output).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.cli._args import (
    require_at_least,
    require_empty_folder,
    require_output_folder,
    require_seed,
    require_writable,
)
from robostereo.cli._camera_files import load_any_camera
from robostereo.errors import InputError

__all__ = [
    "MAX_SIMULATED_VIEWS",
    "add_handeye_parser",
    "add_simulate_handeye_parser",
    "run_handeye",
    "run_simulate_handeye",
]


def add_handeye_parser(sub: Any) -> None:
    from robostereo.robot.handeye import (
        ALL_METHODS,
        DEFAULT_METHOD,
        TANGENTIAL_CHOICES,
        VIEW_MODES,
    )

    p = sub.add_parser(
        "handeye", help="hand-eye calibration (eye-in-hand or eye-to-hand) from board views",
        description="From a views folder (views.yaml: the board, and per view an image "
                    "and the flange pose the robot reported) estimate the camera's "
                    "intrinsics and distortion (OpenCV calibrateCamera) and the "
                    "flange-to-camera transform (AX = XB; eye-to-hand: the camera in the "
                    "base frame and the board on the flange, AX = ZB), refine them jointly "
                    "on the board corners, print the per-view and per-pair residuals, "
                    "refuse an implausible result (exit 2), and write the camera file.",
    )
    p.add_argument("views", type=Path, metavar="VIEWS_DIR", help="hand-eye views folder")
    p.add_argument("-o", "--output", type=Path, required=True,
                   help="camera file to write (camera and hand_eye; eye-to-hand: camera, "
                        "base_camera and flange_board)")
    p.add_argument("--mode", choices=VIEW_MODES,
                   help="eye-in-hand (the camera on the flange) or eye-to-hand (a fixed "
                        "camera, the board on the flange); default: views.yaml's mode, "
                        "else eye-in-hand")
    p.add_argument("--method", choices=ALL_METHODS, default=DEFAULT_METHOD,
                   help=f"closed form that starts the refinement ({DEFAULT_METHOD}; shah and "
                        "li are OpenCV's AX = ZB)")
    p.add_argument("--intrinsics", type=Path, metavar="CAMERA_YAML",
                   help="known intrinsics and distortion (a camera YAML or a handeye "
                        "output), held fixed: only the hand-eye transform and the board "
                        "pose are refined")
    p.add_argument("--tangential", choices=TANGENTIAL_CHOICES, default="test",
                   help="the lens's decentering terms p1, p2: held at 0 unless the views "
                        "show them (test, Wald's test at 1 %%), always fitted (fit), or "
                        "held at 0 (zero); unknown ones trade with the principal point and "
                        "so with the hand-eye rotation")
    p.add_argument("--reject-outliers", action="store_true",
                   help="drop the views whose residuals stand out (robust z-score > 3.5 "
                        "of the reprojection RMS or of the AX = XB residuals of their "
                        "pairs) and solve again once")
    p.add_argument("--advise", type=Path, metavar="ADVICE_YAML",
                   help="also write the flange poses of four more views, tilted from the "
                        "board's normal, that would pin the hand-eye transform best, with "
                        "the spread they would leave at each tilt tried")
    p.set_defaults(handler=run_handeye)


_PAIRS_SHOWN = 10


def run_handeye(args: argparse.Namespace) -> int:
    from robostereo.io import atomic_outputs, check_outputs
    from robostereo.robot.handeye import (
        VIEWS_YAML,
        calibrate_eye_in_hand,
        calibrate_eye_to_hand,
        describe_board,
        handeye_yaml_text,
        read_views,
        view_advice_text,
    )

    require_output_folder(args.output)
    if args.advise is not None:
        require_output_folder(args.advise)
    camera = None
    if args.intrinsics is not None:
        camera, extra = load_any_camera(args.intrinsics)
        if extra:  # the stereo camera YAML of match --camera
            raise InputError(f"--intrinsics {args.intrinsics}: a stereo camera YAML has no "
                             "distortion or image size; give a camera YAML or the file "
                             "robostereo handeye wrote")
    v = read_views(args.views)
    # refuse an input as the output (views.yaml, an image, the intrinsics file)
    outputs = check_outputs({"-o": args.output, "--advise": args.advise},
                            inputs=[args.views / VIEWS_YAML, *v.names, args.intrinsics])
    mode = args.mode or v.mode
    solve = calibrate_eye_to_hand if mode == "eye-to-hand" else calibrate_eye_in_hand
    cal = solve(v.images, v.flange_poses, v.board, pixel_pitch_mm=v.pixel_pitch_mm,
                grey_levels=v.grey_levels, method=args.method, names=v.names, camera=camera,
                reject_outliers=args.reject_outliers, source=str(args.views / VIEWS_YAML),
                tangential=args.tangential)
    texts = {"-o": handeye_yaml_text(cal)}
    if args.advise is not None:
        texts["--advise"] = view_advice_text(cal.advice)
    with atomic_outputs(outputs) as tmp:  # written whole, or not at all
        for key, text in texts.items():
            tmp[key].write_text(text, encoding="utf-8")
    _print_handeye(args, v, cal, describe_board(v.board), mode)
    return 0


def _print_handeye(args: argparse.Namespace, v: Any, cal: Any, board: str, mode: str) -> None:
    cam = cal.camera
    names = [Path(n).name for n in cal.names]
    n = len(names)
    # ChArUco views with too few corners left out (outliers rejected are named below)
    used = f" ({len(v.images) - len(cal.left_out)} used)" if cal.left_out else ""
    print(f"{len(v.images)} views{used}, {board}, {v.board.square_mm:g} mm squares"
          + (f"; rejected as outliers: {', '.join(Path(r).name for r in cal.rejected)}"
             if cal.rejected else ""))
    if cal.corners_per_view is not None:  # ChArUco
        k = cal.corners_per_view
        left = (f"; left out (too few corners): {', '.join(Path(x).name for x in cal.left_out)}"
                if cal.left_out else "")
        seen = (f"{k.min()} of {len(v.board.object_points)} corners in every view"
                if k.min() == k.max() else f"{k.min()}-{k.max()} of "
                f"{len(v.board.object_points)} corners a view (median {int(np.median(k))})")
        print(f"ChArUco: {seen}; the markers' ids fix the corner order, so any board size "
              f"and part-views serve{left}")
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
    if cal.tangential in ("held", "kept") and math.isfinite(cal.tangential_chi2):
        print(f"  decentering p1, p2 {'held at 0' if cal.tangential == 'held' else 'kept'}: "
              f"the views show them at chi-square {cal.tangential_chi2:.2f} (2 dof; "
              f"{'under' if cal.tangential == 'held' else 'over'} 9.21, the 1 % level)")
    eth = mode == "eye-to-hand"
    T = cal.base_camera if eth else cal.hand_eye
    t, rv = T.translation, T.rotvec
    moved = cal.closed_form.distance_to(T) if cal.closed_form else (0.0, 0.0)
    print(f"{'camera in the base frame' if eth else 'hand-eye'} ({args.method}, jointly "
          f"refined: moved {moved[0]:.3f} mm, {math.degrees(moved[1]):.4f} deg): translation "
          f"[{t[0]:.3f}, {t[1]:.3f}, {t[2]:.3f}] mm, rotation vector [{rv[0]:.5f}, "
          f"{rv[1]:.5f}, {rv[2]:.5f}] rad")
    if math.isfinite(cal.hand_eye_sigma_mm):
        print(f"  the views pin it to {cal.hand_eye_sigma_mm:.3f} mm and "
              f"{cal.hand_eye_sigma_deg:.4f} deg (one standard deviation, largest axis; "
              "views turned further apart pin the rotation against the principal point)")
    if cal.advice is not None and cal.advice.best is not None:
        a, k = cal.advice, cal.advice.best
        tilts = a.view_tilts_deg
        print(f"  4 more views tilted {a.tilts_deg[k]:g} deg from the board's normal (yours: "
              f"{tilts.min():.0f}-{tilts.max():.0f}) would pin it to {a.sigma_mm[k]:.3f} mm "
              f"and {a.sigma_deg[k]:.4f} deg; 4 more like yours to {a.like_views_mm:.3f} mm "
              f"and {a.like_views_deg:.4f} deg"
              + ("" if args.advise is None else f" (their flange poses -> {args.advise})"))
    if eth:
        t, rv = cal.flange_board.translation, cal.flange_board.rotvec
        print(f"board on the flange: translation [{t[0]:.3f}, {t[1]:.3f}, {t[2]:.3f}] mm, "
              f"rotation vector [{rv[0]:.5f}, {rv[1]:.5f}, {rv[2]:.5f}] rad")
    r = cal.residuals
    print(f"{'AX = ZB' if eth else 'AX = XB'} residuals over {len(r.rotation_deg)} view "
          "pairs: rotation RMS "
          f"{r.rms_rotation_deg:.4f} deg (max {r.rotation_deg.max():.4f}), translation RMS "
          f"{r.rms_translation_mm:.3f} mm (max {r.translation_mm.max():.3f}; corner noise "
          f"explains {cal.predicted_translation_rms_mm:.3f}) -> {args.output}")
    if cal.outliers and not cal.rejected:
        print(f"views that stand out: {', '.join(Path(o).name for o in cal.outliers)} "
              "(--reject-outliers drops them)")


# -- simulate-handeye ------------------------------------------------------------------


MAX_SIMULATED_VIEWS = 200
"""Most views ``simulate-handeye`` renders: each takes about half a second and the
view pairs grow as n^2 (19 900 at 200), while 15-40 views already settle the result."""


def add_simulate_handeye_parser(sub: Any) -> None:
    p = sub.add_parser(
        "simulate-handeye", help="write a simulated hand-eye views folder (six-axis arm)",
        description="Render a board (chessboard or ChArUco) from tilted views of the "
                    "simulated six-axis arm's wrist camera (or, --mode eye-to-hand, a board "
                    "on its flange from a camera fixed in the cell) and write a hand-eye "
                    "views folder: "
                    "views.yaml, the images, and the truth (camera, hand_eye, base_board; "
                    "or camera, base_camera, flange_board) in truth.yaml.",
    )
    p.add_argument("--out", type=Path, required=True, metavar="DIR",
                   help="views folder to create (must not exist, or be empty)")
    p.add_argument("--views", type=int,
                   help=f"number of views, 3 to {MAX_SIMULATED_VIEWS} (15; eye-to-hand 14)")
    p.add_argument("--seed", type=int, default=0, help="viewpoint and noise seed (0)")
    p.add_argument("--board", choices=("chessboard", "charuco"), default="chessboard",
                   help="calibration target: a chessboard of 9 x 6 inner corners, or a "
                        "ChArUco board (DICT_5X5_100) of 8 x 6 squares (eye-to-hand: 10 x 7 "
                        "squares of 30 mm, 22 mm markers)")
    p.add_argument("--mode", choices=("eye-in-hand", "eye-to-hand"), default="eye-in-hand",
                   help="eye-in-hand (the wrist camera, a board on the table; default) or "
                        "eye-to-hand (a 640 x 480 camera fixed in the cell, k1 = -0.1, a "
                        "9 x 6 board with 30 mm squares on the flange 650-750 mm from it; "
                        "truth: base_camera and flange_board)")
    p.set_defaults(handler=run_simulate_handeye)


def run_simulate_handeye(args: argparse.Namespace) -> int:
    from robostereo.robot.handeye import Charuco, write_views
    from robostereo.robot.simulated.cell_handeye import (
        CELL_BOARD,
        CELL_CHARUCO,
        simulate_eye_to_hand_views,
    )
    from robostereo.robot.simulated.sixaxis_handeye import BOARD, simulate_handeye_views

    eth = args.mode == "eye-to-hand"
    if args.views is None:
        args.views = 14 if eth else 15
    require_at_least("--views", args.views, 3)
    if args.views > MAX_SIMULATED_VIEWS:
        raise InputError(f"--views must be <= {MAX_SIMULATED_VIEWS} (each view is rendered "
                         f"and the pairs grow as n^2), got {args.views}")
    require_seed(args.seed)
    require_empty_folder(args.out)
    require_writable(args.out.parent if str(args.out.parent) else Path("."), args.out)
    if eth:
        views, truth = simulate_eye_to_hand_views(
            views=args.views, seed=args.seed,
            board=CELL_CHARUCO if args.board == "charuco" else CELL_BOARD)
    else:
        board = Charuco() if args.board == "charuco" else BOARD
        views, truth = simulate_handeye_views(views=args.views, seed=args.seed, board=board)
    write_views(args.out, views, extra={"truth.yaml": truth})
    print(f"{args.out}: {args.views} {'eye-to-hand ' if eth else ''}views of a {args.board}; "
          f"truth in {args.out / 'truth.yaml'}")
    return 0
