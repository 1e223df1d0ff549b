"""``robostereo capture``: two (or N) views grabbed by the (simulated) robot into a capture
folder.

Two views from the AdeptOne (the thesis's SCARA) or, with ``--robot six-axis``, the
six-axis arm; with ``--views N``, N views in a pattern.  Every check runs before any
work and raises :class:`~robostereo.errors.InputError` (one line, exit code 2, nothing
written); an option given where it does not apply is refused, even at its default
value, never ignored: ``--baseline`` and ``--handeye`` with ``--views`` (``--span``
sets the views' extent), ``--direction``, ``--roll`` and ``--center`` with the six-axis
arm, ``--tilt`` and ``--handeye`` with the AdeptOne.  With ``--views`` on the AdeptOne,
``--direction`` turns the whole set-up (the block, the light, the camera and the
views' line) about the centre, and ``--roll`` turns the camera and its pattern
together against the scene (the pattern lies in the camera's frame).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

from robostereo.cli._args import (
    finite,
    require_empty_folder,
    require_positive,
    require_seed,
)
from robostereo.cli._console import stage_reporter
from robostereo.cli._views_args import (
    ROBOTS,
    add_views_options,
    check_views_options,
    on_pattern,
)
from robostereo.errors import InputError

__all__ = ["add_capture_parser", "run_capture_command", "views_capture"]


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
    # the defaults are None, so that an option given where it does not apply is refused
    p.add_argument("--baseline", type=finite("--baseline", 1e6),
                   help="two views: baseline D, mm (20; six-axis 40)")
    p.add_argument("--direction", type=finite("--direction", 1e6),
                   help="adeptone: baseline direction from world X, degrees (0); with "
                        "--views the whole set-up turns with it")
    p.add_argument("--roll", type=finite("--roll", 1e6),
                   help="adeptone: camera yaw against the baseline at the centre, degrees "
                        "(0); with --views the pattern turns with the camera")
    p.add_argument("--center", type=finite("--center", 1e6), nargs=2,
                   metavar=("X", "Y"), help="adeptone: mid-baseline point, world mm (400 0)")
    p.add_argument("--seed", type=int, default=0, help="sensor-noise seed (0)")
    p.add_argument("--robot", choices=("adeptone", "six-axis"), default="adeptone",
                   help="simulated robot (adeptone: the thesis's SCARA)")
    p.add_argument("--tilt", type=finite("--tilt"),
                   help="six-axis: camera tilt from vertical, degrees (25)")
    p.add_argument("--handeye", type=Path,
                   help="six-axis: record this camera file's camera and hand_eye "
                        "(robostereo handeye's output) instead of the truth, and three "
                        "times its hand_eye_sigma rotation as uncertainty: hand_eye_deg")
    p.add_argument("--depth-maps", action="store_true",
                   help="also write each view's true depth (the renderer's, mm along its "
                        "optical axis) as DIR/depth/<image>.npy, for robostereo evaluate")
    add_views_options(p)
    p.set_defaults(handler=run_capture_command)


def run_capture_command(args: argparse.Namespace) -> int:
    from robostereo.experiments import RigSetup, simulate_capture
    from robostereo.robot.capture import write_capture

    if args.views is not None or args.pattern is not None or args.span is not None:
        return views_capture(args)
    _refuse_other_robots_options(args, "--baseline, --tilt and --handeye")
    require_seed(args.seed)
    require_empty_folder(args.out)
    if args.robot == "six-axis":  # its views stand 40 mm apart
        return _run_capture_six_axis(args, _given(args.baseline, 40.0))

    center = (400.0, 0.0) if args.center is None else tuple(args.center)
    setup = RigSetup(center_xy=center, baseline_mm=_given(args.baseline, 20.0),
                     direction_deg=_given(args.direction, 0.0), roll_deg=_given(args.roll, 0.0))
    sim = simulate_capture(args.scene, setup=setup, lift_mm=args.lift, seed=args.seed)
    write_capture(args.out, sim.capture, depth_maps=_depths(args, sim))
    g = sim.capture.epipolar
    print(f"{args.out}: {args.scene}, D = {g.baseline_mm:.3f} mm, alpha = "
          f"{math.degrees(g.alpha):.3f} deg, theta_l = {math.degrees(g.theta_l):.3f} deg, "
          f"theta_r = {math.degrees(g.theta_r):.3f} deg")
    return 0


def _refuse_other_robots_options(args: argparse.Namespace, six_axis_takes: str) -> None:
    """Refuse, given at any value, an option of the robot that ``--robot`` does not
    name (`six_axis_takes`: what the six-axis arm takes instead, for the message)."""
    if args.robot == "six-axis":
        if any(v is not None for v in (args.direction, args.roll, args.center)):
            raise InputError("--direction, --roll and --center are for --robot adeptone; "
                             f"the six-axis arm takes {six_axis_takes}")
    elif args.tilt is not None or args.handeye is not None:
        raise InputError("--tilt and --handeye are for --robot six-axis; the AdeptOne takes "
                         "--direction, --roll and --center")


HAND_EYE_SIGMAS = 3.0
"""``capture --handeye``: the calibration's ``hand_eye_sigma`` rotation times this is
written as ``uncertainty: hand_eye_deg`` (the bounds are worst cases, not one standard
deviation)."""


def _run_capture_six_axis(args: argparse.Namespace, baseline: float) -> int:
    from dataclasses import replace

    from robostereo.robot.capture import write_capture
    from robostereo.robot.handeye import load_handeye_with_sigma
    from robostereo.robot.simulated.sixaxis_rig import SixAxisViewpoints, simulate_six_axis_capture

    camera = hand_eye = sigma = None
    if args.handeye is not None:
        camera, hand_eye, sigma = load_handeye_with_sigma(args.handeye)
    require_positive("--baseline", baseline)
    tilt = _six_axis_tilt(args)
    vp = SixAxisViewpoints(baseline_mm=baseline, tilt_deg=tilt)
    sim = simulate_six_axis_capture(args.scene, lift_mm=args.lift, seed=args.seed,
                                    viewpoints=vp, hand_eye=hand_eye, camera=camera)
    capture = sim.capture
    if sigma is not None:  # what the calibration says its rotation may be off by, carried
        capture = replace(capture, hand_eye_uncertainty_deg=HAND_EYE_SIGMAS * sigma[1])
    write_capture(args.out, capture, depth_maps=_depths(args, sim))
    g = capture.epipolar
    print(f"{args.out}: {args.scene} from the six-axis arm, D = {g.baseline_mm:.3f} mm, "
          f"camera tilted {tilt:g} deg, hand-eye "
          f"{'from ' + str(args.handeye) if args.handeye else 'true (simulated)'}"
          + ("" if sigma is None else
             f"; its rotation may be off by {HAND_EYE_SIGMAS:g} x {sigma[1]:.4f} deg "
             "(uncertainty: hand_eye_deg, in every bound)"))
    return 0


def _depths(args: argparse.Namespace, sim: Any) -> list[Any] | None:
    """``--depth-maps``: the simulator's rendered depth of each view, else None."""
    return [r.depth for r in sim.renderings] if args.depth_maps else None


def _given(value: float | None, default: float) -> float:
    """An option's value, or its default when it was not given."""
    return default if value is None else value


def _six_axis_tilt(args: argparse.Namespace) -> float:
    """``--tilt``, checked; 25 degrees when not given."""
    tilt = _given(args.tilt, 25.0)
    if not 0 <= tilt < 80:
        raise InputError(f"--tilt must be in [0, 80) degrees, got {tilt}")
    return float(tilt)


# -- capture --views N -----------------------------------------------------------------


def views_capture(args: argparse.Namespace) -> int:
    """``capture --views N``: the simulated robot grabs N views into a views folder."""
    from robostereo.robot.simulated.grab_views import simulate_views
    from robostereo.robot.views.views_folder import write_views_capture

    count, pattern, span = check_views_options(args)
    if args.baseline is not None:  # given at any value, 20 too: never silently ignored
        raise InputError("--baseline is for two views; with --views give --span")
    if args.handeye is not None:
        raise InputError("--handeye is for two views; with --views the six-axis arm records "
                         "the hand-eye transform it estimates from simulated board views")
    _refuse_other_robots_options(args, "--tilt")
    kw: dict[str, Any] = {}
    if args.robot == "six-axis":
        from robostereo.robot.simulated.sixaxis_rig import SixAxisViewpoints

        kw["viewpoints"] = SixAxisViewpoints(tilt_deg=_six_axis_tilt(args))
    else:
        from robostereo.robot.simulated.scara_rig import RigSetup

        center = (400.0, 0.0) if args.center is None else tuple(args.center)
        kw["setup"] = RigSetup(center_xy=center, direction_deg=_given(args.direction, 0.0),
                               roll_deg=_given(args.roll, 0.0))
    require_seed(args.seed)
    require_empty_folder(args.out)
    status, say = stage_reporter(sys.stderr.isatty())
    with status:
        say(f"grabbing {count} views ({pattern}, {span:g} mm)")
        sim = simulate_views(args.scene, count=count, pattern=pattern, span_mm=span,
                             robot=ROBOTS[args.robot], lift_mm=args.lift, seed=args.seed,
                             **kw)
        say("writing the capture folder")
        write_views_capture(args.out, sim.capture, depth_maps=_depths(args, sim))
    cap = sim.capture
    near, far = cap.depth_range_mm
    print(f"{args.out}: {args.scene}, {len(cap)} views {on_pattern(pattern)} spanning {span:g} mm "
          f"(optical centres at most {cap.span_mm:.3f} mm apart), depths {near:g} .. "
          f"{far:g} mm"
          + (", hand-eye estimated from simulated board views"
             if args.robot == "six-axis" else ""))
    return 0
