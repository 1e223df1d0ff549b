"""Hand-eye accuracy before and after the joint refinement, on two kinds of views.

Run:  PYTHONPATH=src:tests python benchmarks/bench_handeye.py [--seeds 0 1 2]
                                      [--mode eye-in-hand|eye-to-hand] [--write-results PATH]
                                      [--tangential test|fit|zero] [--decentering P1,P2]

* ``renders``: the tests' own ray caster (``tests/board_renders.py``, not the project's
  simulator): 640 x 480, f 800 px, k1 = -0.1, an 8 x 5 chessboard with 20 mm squares,
  14 views from a six-axis-like wrist camera;
* ``simulated``: ``robostereo simulate-handeye`` (15 views of the 9 x 6 board) and
  ``robostereo handeye`` on the folder, compared with its ``truth.yaml``.

For each seed: the error of the closed form (Park-Martin on calibrateCamera's poses),
of the joint refinement, and of the refinement with the true intrinsics held
(``--intrinsics``); the AX = XB translation RMS and the RMS the corner noise explains;
what became of the decentering terms ``p1, p2`` (held at 0, kept or fitted, with the
test's chi-square; ``--tangential`` as ``handeye``'s).  ``--decentering P1,P2``: the
chessboard renders (either mode) through a lens with those terms too (the true
intrinsics held with them), and no simulated views.
``--write-results PATH`` also writes the errors as the results page's data file
(``docs/results/handeye.json``; eye-in-hand only).

``--mode eye-to-hand``: the same for a fixed camera and the board on the flange, the
error of ``T_base_camera`` (and of ``T_flange_board``): ``renders`` are
``board_renders.render_eye_to_hand_views`` (9 x 6 board of 30 mm squares, 14 views
650-750 mm away), ``simulated`` is ``simulate-handeye --mode eye-to-hand``.

``--board charuco [--hide patch|frame|none]``: ChArUco renders instead
(``board_renders.render_charuco_views`` / ``render_charuco_eye_to_hand_views``: OpenCV's
drawing of the board warped into the ray caster, a quarter of each board under a grey
patch or out of the frame): each seed's corner error against the truth (OpenCV's
corners, a further ``cornerSubPix``, robostereo's refinement) and the hand-eye error.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import io
import math
import sys
import tempfile
from pathlib import Path

import yaml
from board_renders import (
    BASE_CAMERA,
    FLANGE_BOARD,
    K1,
    X_TRUE,
    render_eye_to_hand_views,
    render_views,
)
from results_file import write_results

from robostereo.cli import main
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3, as_se3, pose_from_dict
from robostereo.robot.handeye import (
    TANGENTIAL_CHOICES,
    Chessboard,
    Tangential,
    calibrate_eye_in_hand,
    calibrate_eye_to_hand,
)

#: the two kinds of views, as the results page describes them
VIEWS = {
    "renders": "the tests' own ray caster (not the project's simulator): 640 x 480, f 800 px, "
               "k1 = -0.1, 8 x 5 board of 20 mm squares, 14 views",
    "simulated": "robostereo simulate-handeye (15 views of the 9 x 6 board), then robostereo "
                 "handeye",
}

RENDER_CAMERA = Camera(focal_length_mm=4.0, pixel_pitch_mm=(0.005, 0.005),
                       image_size=(640, 480), principal_point=(320.0, 240.0),
                       distortion=(-0.1, 0.0, 0.0, 0.0, 0.0))


def _err(truth: SE3, X: SE3) -> str:
    t, r = truth.distance_to(X)
    return f"{t:.3f} mm {math.degrees(r):.4f} deg"


def _errors(truth: SE3, X: SE3) -> list[float]:
    """The translation (mm) and rotation (deg) of ``X`` off ``truth``."""
    t, r = truth.distance_to(X)
    return [float(t), math.degrees(r)]


def _terms(tangential: dict[str, object] | None) -> str:
    """What became of ``p1, p2`` (the output's ``tangential`` mapping)."""
    if not tangential:
        return "p1, p2 -"
    chi2 = tangential.get("chi2")
    return f"p1, p2 {tangential['terms']}" + (f" (chi-square {chi2:.1f})" if chi2 else "")


def renders(seed: int, tangential: Tangential = "test",
            decentering: tuple[float, float] = (0.0, 0.0)) -> dict[str, object]:
    p1, p2 = decentering
    r = render_views(seed, lens=(K1, p1, p2)) if p1 or p2 else render_views(seed)
    board = Chessboard(r.inner_corners, r.square_mm)
    cal = calibrate_eye_in_hand(r.images, r.flange_poses, board, pixel_pitch_mm=0.005,
                                tangential=tangential)
    camera = dataclasses.replace(RENDER_CAMERA, distortion=(K1, 0.0, p1, p2, 0.0))
    known = calibrate_eye_in_hand(r.images, r.flange_poses, board, camera=camera)
    print(f"renders   seed {seed}: closed form {_err(X_TRUE, cal.closed_form)}; refined "
          f"{_err(X_TRUE, cal.hand_eye)}; true intrinsics held {_err(X_TRUE, known.hand_eye)}"
          f"; fx {cal.camera.fx:.2f} (true 800); pairs {cal.residuals.rms_translation_mm:.3f}"
          f" mm (noise explains {cal.predicted_translation_rms_mm:.3f}); reprojection "
          f"{cal.reprojection_rms_px:.3f} px; the views pin X to {cal.hand_eye_sigma_mm:.3f} mm"
          f" {cal.hand_eye_sigma_deg:.4f} deg; {_terms(cal.to_dict().get('tangential'))}")
    return {"views": "renders", "seed": seed, "closed_form": _errors(X_TRUE, cal.closed_form),
            "refined": _errors(X_TRUE, cal.hand_eye),
            "intrinsics_held": _errors(X_TRUE, known.hand_eye)}


def simulated(seed: int, tangential: Tangential = "test") -> dict[str, object]:
    with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()):
        d, out = Path(tmp) / "views", Path(tmp) / "camera.yaml"
        assert main(["simulate-handeye", "--out", str(d), "--seed", str(seed)]) == 0
        assert main(["handeye", str(d), "-o", str(out), "--tangential", tangential]) == 0
        known = Path(tmp) / "known.yaml"
        assert main(["handeye", str(d), "-o", str(known), "--intrinsics",
                     str(d / "truth.yaml")]) == 0
        truth = yaml.safe_load((d / "truth.yaml").read_text())
        data = yaml.safe_load(out.read_text())
        data_known = yaml.safe_load(known.read_text())
    X = as_se3(pose_from_dict(truth["hand_eye"]))
    print(f"simulated seed {seed}: closed form "
          f"{_err(X, as_se3(pose_from_dict(data['hand_eye_closed_form'])))}; refined "
          f"{_err(X, as_se3(pose_from_dict(data['hand_eye'])))}; true intrinsics held "
          f"{_err(X, as_se3(pose_from_dict(data_known['hand_eye'])))}; pairs "
          f"{data['handeye_residuals']['translation_mm_rms']:.3f} mm (noise explains "
          f"{data['handeye_residuals']['translation_mm_rms_predicted']:.3f}); "
          f"{_terms(data.get('tangential'))}", flush=True)
    return {"views": "simulated", "seed": seed,
            "closed_form": _errors(X, as_se3(pose_from_dict(data["hand_eye_closed_form"]))),
            "refined": _errors(X, as_se3(pose_from_dict(data["hand_eye"]))),
            "intrinsics_held": _errors(X, as_se3(pose_from_dict(data_known["hand_eye"])))}


def cell_renders(seed: int, tangential: Tangential = "test",
                 decentering: tuple[float, float] = (0.0, 0.0)) -> None:
    p1, p2 = decentering
    r = (render_eye_to_hand_views(seed, lens=(K1, p1, p2)) if p1 or p2
         else render_eye_to_hand_views(seed))
    board = Chessboard(r.inner_corners, r.square_mm)
    cal = calibrate_eye_to_hand(r.images, r.flange_poses, board, pixel_pitch_mm=0.005,
                                tangential=tangential)
    shah = calibrate_eye_to_hand(r.images, r.flange_poses, board, pixel_pitch_mm=0.005,
                                 method="shah", refine=False)
    camera = dataclasses.replace(RENDER_CAMERA, distortion=(K1, 0.0, p1, p2, 0.0))
    known = calibrate_eye_to_hand(r.images, r.flange_poses, board, camera=camera)
    print(f"renders   seed {seed}: T_base_camera closed form {_err(BASE_CAMERA, cal.closed_form)}"
          f" (OpenCV shah {_err(BASE_CAMERA, shah.base_camera)}); refined "
          f"{_err(BASE_CAMERA, cal.base_camera)}; true intrinsics held "
          f"{_err(BASE_CAMERA, known.base_camera)}; T_flange_board "
          f"{_err(FLANGE_BOARD, cal.flange_board)}; fx {cal.camera.fx:.2f} (true 800); "
          f"{_terms(cal.to_dict().get('tangential'))}", flush=True)


def cell_simulated(seed: int, tangential: Tangential = "test") -> None:
    with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()):
        d, out = Path(tmp) / "views", Path(tmp) / "cell.yaml"
        assert main(["simulate-handeye", "--mode", "eye-to-hand", "--out", str(d), "--seed",
                     str(seed)]) == 0
        assert main(["handeye", str(d), "-o", str(out), "--tangential", tangential]) == 0
        known = Path(tmp) / "known.yaml"
        assert main(["handeye", str(d), "-o", str(known), "--intrinsics",
                     str(d / "truth.yaml")]) == 0
        truth = yaml.safe_load((d / "truth.yaml").read_text())
        data = yaml.safe_load(out.read_text())
        data_known = yaml.safe_load(known.read_text())
    Z = as_se3(pose_from_dict(truth["base_camera"]))
    Y = as_se3(pose_from_dict(truth["flange_board"]))
    print(f"simulated seed {seed}: T_base_camera closed form "
          f"{_err(Z, as_se3(pose_from_dict(data['base_camera_closed_form'])))}; refined "
          f"{_err(Z, as_se3(pose_from_dict(data['base_camera'])))}; true intrinsics held "
          f"{_err(Z, as_se3(pose_from_dict(data_known['base_camera'])))}; T_flange_board "
          f"{_err(Y, as_se3(pose_from_dict(data['flange_board'])))}; "
          f"{_terms(data.get('tangential'))}", flush=True)


def charuco_renders(seed: int, mode: str, hide: str | None,
                    tangential: Tangential = "test") -> None:
    import cv2
    import numpy as np
    from board_renders import (
        charuco_corners_in_image,
        render_charuco_eye_to_hand_views,
        render_charuco_views,
    )

    from robostereo.robot.handeye import Charuco, detect_charuco

    eth = mode == "eye-to-hand"
    r = (render_charuco_eye_to_hand_views if eth else render_charuco_views)(seed, hide=hide)
    board = Charuco(r.squares, r.square_mm, r.marker_mm, r.dictionary)
    err: dict[str, list[np.ndarray]] = {"opencv": [], "cornerSubPix": [], "refined": []}
    for img, T in zip(r.images, r.camera_board, strict=True):
        truth = charuco_corners_in_image(T.inv(), r.squares, r.square_mm)
        raw, fine = detect_charuco(img, board, refine=False), detect_charuco(img, board)
        sub = cv2.cornerSubPix(img, raw.pixels.astype(np.float32).reshape(-1, 1, 2), (3, 3),
                               (-1, -1), (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER,
                                          100, 1e-4)).reshape(-1, 2)
        for key, px, ids in (("opencv", raw.pixels, raw.ids), ("cornerSubPix", sub, raw.ids),
                             ("refined", fine.pixels, fine.ids)):
            err[key].append(px - truth[ids])
    rms = {k: float(np.sqrt(np.mean(np.sum(np.concatenate(v) ** 2, axis=1))))
           for k, v in err.items()}
    solve = calibrate_eye_to_hand if eth else calibrate_eye_in_hand
    cal = solve(r.images, r.flange_poses, board, pixel_pitch_mm=0.005,
                tangential=tangential)
    truth_pose = BASE_CAMERA if eth else X_TRUE
    k = cal.corners_per_view
    print(f"charuco renders seed {seed} ({mode}, hide {hide}): corners {k.min()}-{k.max()} of "
          f"{len(board.object_points)} a view, off the truth {rms['opencv']:.3f} px RMS "
          f"(OpenCV), {rms['cornerSubPix']:.3f} (+ cornerSubPix 7 x 7), {rms['refined']:.3f} "
          f"(refined); {'T_base_camera' if eth else 'T_flange_camera'} closed form "
          f"{_err(truth_pose, cal.closed_form)}, refined {_err(truth_pose, cal.hand_eye)}; "
          f"{_terms(cal.to_dict().get('tangential'))}", flush=True)


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    p.add_argument("--write-results", type=Path, metavar="PATH",
                   help="also write the errors as JSON (docs/results/handeye.json)")
    p.add_argument("--mode", choices=("eye-in-hand", "eye-to-hand"), default="eye-in-hand")
    p.add_argument("--board", choices=("chessboard", "charuco"), default="chessboard")
    p.add_argument("--hide", choices=("patch", "frame", "none"), default="patch",
                   help="ChArUco renders: a quarter of each board under a grey patch, out "
                        "of the frame, or none hidden")
    p.add_argument("--tangential", choices=TANGENTIAL_CHOICES, default="test",
                   help="the calibrations' decentering terms p1, p2 (handeye --tangential)")
    p.add_argument("--decentering", metavar="P1,P2",
                   type=lambda v: tuple(float(x) for x in v.split(",")),
                   help="chessboard renders only: a lens with these decentering terms too")
    args = p.parse_args()
    tg = args.tangential
    if args.decentering and len(args.decentering) != 2:
        p.error("--decentering takes two numbers, P1,P2")
    if args.decentering and (args.board != "chessboard" or args.write_results):
        p.error("--decentering renders the chessboard views only (no --write-results)")
    if args.board == "charuco":
        if args.write_results:
            p.error("--write-results writes the chessboard results page's data only")
        for s in args.seeds:
            charuco_renders(s, args.mode, None if args.hide == "none" else args.hide, tg)
        sys.exit(0)
    if args.mode == "eye-to-hand":
        if args.write_results:
            p.error("--write-results writes the eye-in-hand results page's data only")
        for s in args.seeds:
            cell_renders(s, tg, args.decentering or (0.0, 0.0))
        if not args.decentering:
            for s in args.seeds:
                cell_simulated(s, tg)
        sys.exit(0)
    if args.decentering:
        for s in args.seeds:
            renders(s, tg, tuple(args.decentering))
        sys.exit(0)
    rows = [renders(s, tg) for s in args.seeds] + [simulated(s, tg) for s in args.seeds]
    if args.write_results:
        # worst refined rotation first, as the results page shows them
        rows.sort(key=lambda r: -r["refined"][1])  # type: ignore[index]
        write_results(args.write_results, sys.argv[1:], env="PYTHONPATH=src:tests",
                      views=VIEWS, rows=rows)
