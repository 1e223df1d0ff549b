"""The checks on a first match: views of different exposure
(:mod:`robostereo.matcher.photometric`) and rows that are not epipolar lines
(:mod:`robostereo.matcher.alignment`): what each costs the matcher without its check, and
what the check gives back.

Run:  python benchmarks/bench_checks.py [--repeat N]

1. On every developer scene of ../shared/data/stereo (or $ROBOSTEREO_DATA) the right
   image is changed as a camera of another exposure would have taken it (a gain, a
   gain and an offset, a gamma; grey levels rounded and clipped to 0..255), and matched
   with robostereo's defaults with the check off (``MatchParameters(photometric=False)``)
   and on: % of the counted left edge points accepted and % of those false (silhouette
   rule), and ``*`` where the check found the views to differ and matched again.  Worst
   scene first (by coverage with the check off under the largest change).
2. The check's ratio on the scenes as they are (the pairs' median grey-level difference
   as they are over the one after a gain and offset; the views differ above
   :data:`~robostereo.matcher.photometric.RESIDUAL_RATIO`).
3. The right image's rows moved (linear interpolation): down by 0.5, 1 and 2 px, up by
   1 px, tilted by 0.2 and -0.4 degrees about the image's centre (a rotation between
   the views: rows at the side edges 1-2.6 px apart, none at the centre), and stretched
   1.5 px more at the bottom and as much less at the top (a focal length off): % accepted
   / % false with the rows check off and on (``*`` where it found the rows apart and
   matched again), and its estimate (offset / tilt / stretch) on the scenes as they are.
4. The time of both checks on the scenes as they are, per core (``ROBOSTEREO_THREADS=1``,
   thread CPU time): median of N interleaved rounds of the whole match with both checks
   on and both off, and the median of the rounds' ratios.
"""

from __future__ import annotations

import argparse
import os
import time
import warnings

import cv2
import numpy as np

from robostereo.datasets import available_scenes, find_data_dir, load_scene
from robostereo.errors import PlausibilityWarning
from robostereo.evaluation.rules import rule_errors
from robostereo.matcher.photometric import (
    RESIDUAL_RATIO,
    grey_difference,
    grey_pairs,
)
from robostereo.matcher.pipeline import MatchParameters, match_stereo

#: the changes of the right image: name -> (gain, offset in grey levels of 255, gamma)
CHANGES: dict[str, tuple[float, float, float]] = {
    "as is": (1.0, 0.0, 1.0),
    "gain 1.05": (1.05, 0.0, 1.0),
    "gain 1.1": (1.1, 0.0, 1.0),
    "gain 0.7 + 20": (0.7, 20.0, 1.0),
    "gamma 0.7": (1.0, 0.0, 0.7),
    "gain 1.3": (1.3, 0.0, 1.0),
}


def exposed(image: np.ndarray, gain: float, offset: float, gamma: float) -> np.ndarray:
    """``image`` (8-bit) with another exposure: ``gain * 255 (g / 255) ** gamma + offset``."""
    f = 255.0 * (image.astype(float) / 255.0) ** gamma
    return np.clip(np.rint(gain * f + offset), 0, 255).astype(np.uint8)


#: the right image's rows moved: name -> (rows down, tilt in degrees, stretch in px)
ROW_CHANGES: dict[str, tuple[float, float, float]] = {
    "+0.5 px": (0.5, 0.0, 0.0),
    "+1 px": (1.0, 0.0, 0.0),
    "+2 px": (2.0, 0.0, 0.0),
    "-1 px": (-1.0, 0.0, 0.0),
    "tilt 0.2 deg": (0.0, 0.2, 0.0),
    "tilt -0.4 deg": (0.0, -0.4, 0.0),
    "stretch 1.5 px": (0.0, 0.0, 1.5),
}


def rows_moved(image: np.ndarray, down: float, tilt_deg: float, stretch: float) -> np.ndarray:
    """``image`` whose row ``y`` at column ``x`` shows up at ``y + down + tan(tilt) (x - cx)
    + stretch (y - cy) / cy`` (linear interpolation, border repeated)."""
    h, w = image.shape[:2]
    cx, cy = 0.5 * (w - 1), 0.5 * (h - 1)
    t, k = np.tan(np.radians(tilt_deg)), stretch / cy
    m = np.float32([[1, 0, 0], [t, 1 + k, down - t * cx - k * cy]])
    return cv2.warpAffine(image, m, (w, h), flags=cv2.INTER_LINEAR,
                          borderMode=cv2.BORDER_REPLICATE)


def scored(scene, right: np.ndarray, **checks: bool) -> tuple[float, float, bool]:
    """% accepted, % of them false (silhouette rule), and whether a check matched again."""
    res = match_stereo(scene.left, right, scene.disparity_range,
                       params=MatchParameters(**checks))
    e = res.left_edges
    known, err = rule_errors(e.row, e.x, res.edge_disparity, scene.gt_disparity,
                             rule="silhouette")
    acc = res.accepted & known
    again = res.grey_map is not None or (res.row_offset is not None
                                         and res.row_offset.misaligned)
    return (100.0 * acc.sum() / max(known.sum(), 1),
            100.0 * (acc & (err > 1.0)).sum() / max(acc.sum(), 1), again)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--repeat", type=int, default=9, help="rounds of the time table")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore", PlausibilityWarning)  # the rows check's, expected here
    data = find_data_dir()
    if data is None:
        print("no real scenes (../shared/data/stereo or $ROBOSTEREO_DATA)")
        return 0
    scenes = {n: load_scene(data / n) for n in available_scenes(data)}

    # -- 1. coverage / false % with the check off and on, per change of the right view
    rows = {}
    for name, s in scenes.items():
        rows[name] = {c: (scored(s, exposed(s.right, *v), photometric=False),
                          scored(s, exposed(s.right, *v))) for c, v in CHANGES.items()}
    last = list(CHANGES)[-1]
    order = sorted(rows, key=lambda n: rows[n][last][0][0])
    print("% accepted / % false (silhouette rule): check off -> on (* matched again)")
    for c in CHANGES:
        print(f"\n{c}")
        for n in order:
            (a0, f0, _), (a1, f1, again) = rows[n][c]
            print(f"  {n:11s} {a0:5.1f} / {f0:4.2f}  ->  {a1:5.1f} / {f1:4.2f} "
                  f"{'*' if again else ''}")

    # -- 2. the check's ratio on the pairs as they are
    print(f"\nthe check on the pairs as they are (views differ above {RESIDUAL_RATIO:g}):")
    for n, s in scenes.items():
        res = match_stereo(s.left, s.right, s.disparity_range,
                           params=MatchParameters(photometric=False))
        acc = res.accepted
        as_is, fitted = grey_difference(*grey_pairs(
            s.left, s.right, res.left_edges.row[acc], res.left_edges.x[acc],
            res.edge_disparity[acc]))
        print(f"  {n:11s} {as_is:5.2f} / {fitted:5.2f} grey levels = {as_is / fitted:4.2f}")

    # -- 3. rows moved: the rows check off and on
    print("\n% accepted / % false (silhouette rule) with the right image's rows moved: rows "
          "check off -> on (* matched again)")
    for change, move in ROW_CHANGES.items():
        print(f"\n{change}")
        for n in order:
            s = scenes[n]
            a0, f0, _ = scored(s, rows_moved(s.right, *move), rows_check=False)
            a1, f1, again = scored(s, rows_moved(s.right, *move))
            print(f"  {n:11s} {a0:5.1f} / {f0:5.2f}  ->  {a1:5.1f} / {f1:4.2f} "
                  f"{'*' if again else ''}")
    print("\nthe rows check on the pairs as they are: offset +- its standard error, tilt, "
          "stretch (px)")
    for n in order:
        s = scenes[n]
        ro = match_stereo(s.left, s.right, s.disparity_range).row_offset
        print(f"  {n:11s} " + (f"{ro.offset_px:+.2f} +- {ro.standard_error_px:.2f}, "
                               f"{ro.tilt_px:+.2f}, {ro.stretch_px:+.2f}"
                               if ro is not None else "no estimate"))

    # -- 4. the checks' time, per core, on the pairs as they are
    os.environ["ROBOSTEREO_THREADS"] = "1"
    cv2.setNumThreads(1)
    print(f"\ntime per core (thread CPU ms, median of {args.repeat} rounds): both checks on, "
          "both off, ratio")
    for n, s in scenes.items():
        t: dict[bool, list[float]] = {True: [], False: []}
        for _ in range(args.repeat):
            for on in (True, False):
                p = MatchParameters(photometric=on, rows_check=on)
                match_stereo(s.left, s.right, s.disparity_range, params=p)
                t0 = time.thread_time()
                match_stereo(s.left, s.right, s.disparity_range, params=p)
                t[on].append(time.thread_time() - t0)
        ratio = float(np.median(np.array(t[True]) / np.array(t[False])))
        print(f"  {n:11s} {1000 * np.median(t[True]):7.2f} {1000 * np.median(t[False]):7.2f}"
              f"  {ratio:5.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
