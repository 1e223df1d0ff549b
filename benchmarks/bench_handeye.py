"""Hand-eye accuracy before and after the joint refinement, on two kinds of views.

Run:  PYTHONPATH=src:tests python benchmarks/bench_handeye.py [--seeds 0 1 2]

* ``renders``: the tests' own ray caster (``tests/board_renders.py``, not the project's
  simulator): 640 x 480, f 800 px, k1 = -0.1, an 8 x 5 chessboard with 20 mm squares,
  14 views from a six-axis-like wrist camera;
* ``simulated``: ``robostereo simulate-handeye`` (15 views of the 9 x 6 board) and
  ``robostereo handeye`` on the folder, compared with its ``truth.yaml``.

For each seed: the error of the closed form (Park-Martin on calibrateCamera's poses),
of the joint refinement, and of the refinement with the true intrinsics held
(``--intrinsics``); the AX = XB translation RMS and the RMS the corner noise explains.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import tempfile
from pathlib import Path

import yaml
from board_renders import X_TRUE, render_views

from robostereo.cli import main
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3, as_se3, pose_from_dict
from robostereo.robot.handeye import Chessboard, calibrate_eye_in_hand

RENDER_CAMERA = Camera(focal_length_mm=4.0, pixel_pitch_mm=(0.005, 0.005),
                       image_size=(640, 480), principal_point=(320.0, 240.0),
                       distortion=(-0.1, 0.0, 0.0, 0.0, 0.0))


def _err(truth: SE3, X: SE3) -> str:
    t, r = truth.distance_to(X)
    return f"{t:.3f} mm {math.degrees(r):.4f} deg"


def renders(seed: int) -> None:
    r = render_views(seed)
    board = Chessboard(r.inner_corners, r.square_mm)
    cal = calibrate_eye_in_hand(r.images, r.flange_poses, board, pixel_pitch_mm=0.005)
    known = calibrate_eye_in_hand(r.images, r.flange_poses, board, camera=RENDER_CAMERA)
    print(f"renders   seed {seed}: closed form {_err(X_TRUE, cal.closed_form)}; refined "
          f"{_err(X_TRUE, cal.hand_eye)}; true intrinsics held {_err(X_TRUE, known.hand_eye)}"
          f"; fx {cal.camera.fx:.2f} (true 800); pairs {cal.residuals.rms_translation_mm:.3f}"
          f" mm (noise explains {cal.predicted_translation_rms_mm:.3f}); reprojection "
          f"{cal.reprojection_rms_px:.3f} px")


def simulated(seed: int) -> None:
    with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()):
        d, out = Path(tmp) / "views", Path(tmp) / "camera.yaml"
        assert main(["simulate-handeye", "--out", str(d), "--seed", str(seed)]) == 0
        assert main(["handeye", str(d), "-o", str(out)]) == 0
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
          f"{data['handeye_residuals']['translation_mm_rms_predicted']:.3f})", flush=True)


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    args = p.parse_args()
    for s in args.seeds:
        renders(s)
    for s in args.seeds:
        simulated(s)
