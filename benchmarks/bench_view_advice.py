"""Where to put more views: the hand-eye advice's predictions against calibrations that
take the advised views.

Run:  PYTHONPATH=src:tests python benchmarks/bench_view_advice.py [--seeds 0 1 2 3 4]
                                          [--tilts 0-3 3-10 12-38]

For each tilt range and seed: 14 renders of ``tests/board_renders.py`` (the tests' own
ray caster, not the project's simulator) tilted that far from the board's normal, the
eye-in-hand calibration, its advice (:func:`robostereo.robot.handeye.advise_views`),
then the calibration again with the four advised views rendered through the true
hand-eye transform.  Printed: the rotation and translation errors before and after,
the spread the calibration reported, the spread the advice predicted for its tilt and
for four more views like the first, and the spread the second calibration reported.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
from board_renders import BASE_BOARD, X_TRUE, render_board, render_views

from robostereo.robot.handeye import Chessboard, calibrate_eye_in_hand


def _errors(X) -> str:
    t, r = X_TRUE.distance_to(X)
    return f"{t:.3f} mm {math.degrees(r):.4f} deg"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    ap.add_argument("--tilts", nargs="+", default=["0-3", "3-10", "12-38"],
                    help="tilt ranges of the views, deg, as LO-HI")
    args = ap.parse_args()
    for spec in args.tilts:
        lo, hi = (float(v) for v in spec.split("-"))
        for seed in args.seeds:
            r = render_views(seed, tilt_deg=(lo, hi))
            board = Chessboard(r.inner_corners, r.square_mm)
            cal = calibrate_eye_in_hand(r.images, r.flange_poses, board)
            a = cal.advice
            k = a.best
            line = (f"tilts {spec:>6} seed {seed}: off {_errors(cal.hand_eye)}, sigma "
                    f"{a.current_mm:.3f} mm {a.current_deg:.4f} deg")
            if k is None:
                print(line + "; no tilt fits the image")
                continue
            rng = np.random.default_rng([seed, 5])
            images, flanges = list(r.images), list(r.flange_poses)
            for f in a.flange_poses[k]:
                images.append(render_board(BASE_BOARD.inv() @ f @ X_TRUE, r.inner_corners,
                                           r.square_mm, rng=rng))
                flanges.append(f)
            after = calibrate_eye_in_hand(images, flanges, board)
            print(f"{line} | advised {a.tilts_deg[k]:g} deg: predicted {a.sigma_mm[k]:.3f} mm "
                  f"{a.sigma_deg[k]:.4f} deg (like yours {a.like_views_mm:.3f} mm "
                  f"{a.like_views_deg:.4f} deg) | after: off {_errors(after.hand_eye)}, sigma "
                  f"{after.hand_eye_sigma_mm:.3f} mm {after.hand_eye_sigma_deg:.4f} deg",
                  flush=True)


if __name__ == "__main__":
    main()
