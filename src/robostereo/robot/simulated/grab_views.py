"""Simulated captures of N views: the SCARA and the six-axis arm grab a viewpoint pattern.

The thesis grabs two views (4.2); :func:`simulate_views` moves the simulated robot to N
viewpoints in a pattern (:func:`robostereo.robot.views.viewpoints.view_offsets`: a line, a cross
or an arc) about the two-view demo's mid viewpoint and grabs (renders) an image at each:

* the AdeptOne (:mod:`robostereo.robot.simulated.scara_rig`): the camera on the forearm,
  looking straight down, every view at the mount's one height; the pattern's offsets
  are taken in the centre camera's x-y plane (an arc keeps only its horizontal
  positions: a SCARA cannot tilt the camera);
* the six-axis arm (:mod:`robostereo.robot.simulated.sixaxis_rig`): the tilted mid viewpoint of the
  six-axis demo, the offsets in that camera's frame (an arc turns each view towards the
  target); the capture holds the reported flange poses and the hand-eye transform and
  camera *estimated* from simulated board views, as the six-axis demo does.

The images are rendered at the true camera poses; the capture holds what the robot
reports, and :attr:`SimulatedViews.true_poses` the truth.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Literal

import numpy as np

from robostereo.errors import InputError, require_finite
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.arms.acquisition import SimulatedCamera
from robostereo.robot.arms.scara import AdeptOne, CameraMount
from robostereo.robot.arms.sixaxis import WRIST_CAMERA, WRIST_HAND_EYE, SixAxisArm
from robostereo.robot.handeye import EyeInHandCalibration, calibrate_eye_in_hand
from robostereo.robot.simulated.scara_rig import RigSetup, block_scene, pulley_scene
from robostereo.robot.simulated.sixaxis_handeye import simulate_handeye_views
from robostereo.robot.simulated.sixaxis_rig import (
    SIX_AXIS_RENDER,
    SixAxisViewpoints,
    six_axis_block_scene,
)
from robostereo.robot.views.viewpoints import PATTERNS, ViewsCapture, view_offsets
from robostereo.simulation import (
    Box,
    ImagePlane,
    Rendering,
    Scene,
    TablePlane,
    hub_pulley_scene,
    render,
)

__all__ = [
    "ROBOTS",
    "SimulatedViews",
    "estimated_hand_eye",
    "post_before_a_printed_plane",
    "simulate_views",
]

#: the simulated robots of :func:`simulate_views`
ROBOTS: tuple[str, ...] = ("scara", "six-axis")


@dataclass(frozen=True, eq=False)
class SimulatedViews:
    """N simulated views with their ground truth.

    Attributes
    ----------
    capture : ViewsCapture
        As the robot reports it (six-axis: flange poses and the estimated hand-eye
        transform and camera).
    scene : Scene
    renderings : tuple of Rendering
        One per view (depth and labels ground truth, in the true camera).
    true_poses : tuple of SE3
        True ``T_world_camera`` of each view.
    camera : Camera
        The true camera the images were rendered with.
    """

    capture: ViewsCapture
    scene: Scene
    renderings: tuple[Rendering, ...]
    true_poses: tuple[SE3, ...]
    camera: Camera | None = None


def _scara_robot(setup: RigSetup) -> AdeptOne:
    """An AdeptOne whose forearm camera's yaw is ``alpha + roll`` at the centre."""
    probe = AdeptOne(mount=CameraMount(z_mm=setup.camera_height_mm))
    arm = probe.forward(probe.inverse(*setup.center_xy)).phi
    offset = math.radians(setup.direction_deg + setup.roll_deg) - arm
    return AdeptOne(mount=CameraMount(z_mm=setup.camera_height_mm, yaw_offset=offset))


@lru_cache(maxsize=4)
def estimated_hand_eye(seed: int = 0) -> EyeInHandCalibration:
    """The six-axis demo's hand-eye calibration: 15 simulated board views, `seed`.

    Cached: every call with one seed returns the same calibration.
    """
    hv, _truth = simulate_handeye_views(views=15, seed=seed)
    return calibrate_eye_in_hand(hv.images, hv.flange_poses, hv.board,
                                 pixel_pitch_mm=hv.pixel_pitch_mm,
                                 grey_levels=hv.grey_levels, names=hv.names)


def _check(kind: str, count: int, pattern: str, span_mm: float, robot: str, lift_mm: float,
           seed: int) -> None:
    if kind not in ("block", "pulley"):
        raise InputError(f"scene must be 'block' or 'pulley', got {kind!r}")
    if robot not in ROBOTS:
        raise InputError(f"robot must be one of {', '.join(ROBOTS)}, got {robot!r}")
    if pattern not in PATTERNS:
        raise InputError(f"pattern must be one of {', '.join(PATTERNS)}, got {pattern!r}")
    require_finite("lift_mm", lift_mm)
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise InputError(f"seed must be a whole number >= 0, got {seed!r}")
    if kind == "pulley" and lift_mm != 0:
        raise InputError(f"lift_mm raises the block only, got {lift_mm:g} for the pulley")


def simulate_views(
    kind: Literal["block", "pulley"] = "block",
    *,
    count: int = 5,
    pattern: Literal["line", "cross", "arc"] = "line",
    span_mm: float = 80.0,
    robot: Literal["scara", "six-axis"] = "scara",
    lift_mm: float = 0.0,
    seed: int = 0,
    setup: RigSetup | None = None,
    viewpoints: SixAxisViewpoints | None = None,
    scene: Scene | None = None,
) -> SimulatedViews:
    """Move the simulated robot to `count` viewpoints in a pattern and grab each.

    Parameters
    ----------
    kind : {'block', 'pulley'}
        The thesis's precision block or the hub-pulley.
    count : int
        Number of views, 2..100.
    pattern : {'line', 'cross', 'arc'}
        :func:`~robostereo.robot.views.viewpoints.view_offsets` about the two-view demo's mid
        viewpoint; the line runs along the demo's baseline direction.
    span_mm : float
        Distance between the outermost viewpoints, mm.
    robot : {'scara', 'six-axis'}
    lift_mm : float
        Block only: raise of its top.
    seed : int
        Seed of the sensor noise (and, six-axis, of the hand-eye views).
    setup : RigSetup, optional
        SCARA: the rig (default the thesis's: camera 1050 mm above the table).
    viewpoints : SixAxisViewpoints, optional
        Six-axis: the mid viewpoint (its ``target``, ``distance_mm``, ``tilt_deg``,
        ``azimuth_deg``; the two-view baseline and offsets are not used).
    scene : Scene, optional
        Render this scene instead of `kind`'s.

    Returns
    -------
    SimulatedViews

    Raises
    ------
    InputError
        Bad parameters; :class:`~robostereo.errors.UnreachablePoseError` for a
        viewpoint outside the robot's reach.

    Notes
    -----
    SCARA: 1. the camera moved above the centre (``setup.center_xy``) gives the centre
    pose; 2. each offset ``o`` of the pattern becomes the world move ``R o`` (x and y
    only); 3. the robot moves there, reports its pose, the camera grabs.

    Six-axis: 1. the mid pose looks at ``viewpoints.target`` from ``distance_mm``;
    2. view ``k`` is the mid pose moved by ``R o_k`` (and, on an arc, turned about its y
    axis towards the target); 3. the arm's inverse kinematics gives the flange pose
    (``flange = camera @ hand_eye^-1`` with the true hand-eye); the capture records the
    flanges with the hand-eye and camera calibrated by :func:`estimated_hand_eye`.

    Examples
    --------
    >>> sim = simulate_views("pulley", count=2, span_mm=40.0)
    >>> len(sim.capture), round(sim.capture.span_mm), len(sim.renderings)
    (2, 40, 2)
    """
    _check(kind, count, pattern, span_mm, robot, lift_mm, seed)
    if robot == "scara":
        return _simulate_scara(kind, count, pattern, span_mm, lift_mm, int(seed),
                               setup or RigSetup(), scene)
    return _simulate_six_axis(kind, count, pattern, span_mm, lift_mm, int(seed),
                              viewpoints or SixAxisViewpoints(), scene)


def _simulate_scara(kind: str, count: int, pattern: str, span_mm: float, lift_mm: float,
                    seed: int, su: RigSetup, scene: Scene | None) -> SimulatedViews:
    depth = su.camera_height_mm - 50.0 - lift_mm  # the block's top: the arc's centre
    offsets = view_offsets(pattern, count, span_mm,  # type: ignore[arg-type]
                           depth_mm=depth if pattern == "arc" else None)
    if scene is None:
        scene = block_scene(su, lift_mm=lift_mm) if kind == "block" else pulley_scene(su)
    arm = _scara_robot(su)
    stream = [0] if kind == "pulley" else [1 + (lift_mm < 0), round(abs(lift_mm) * 100)]
    rng = np.random.default_rng([seed, 19, count, *stream])
    device = SimulatedCamera(scene, su.camera, arm, rng, render, {
        "supersample": su.supersample, "blur_sigma_px": su.blur_sigma_px,
        "noise_sigma": su.noise_sigma})
    centre = arm.move_camera(*su.center_xy)
    R = centre.rotation
    images, poses, true_poses, renders, joints = [], [], [], [], []
    for o in offsets:
        d = R @ np.array([o[0], o[1], 0.0])
        pose = arm.move_camera(su.center_xy[0] + float(d[0]), su.center_xy[1] + float(d[1]))
        img = np.array(device.grab(), copy=True)
        img.setflags(write=False)
        images.append(img)
        poses.append(pose)
        true_poses.append(arm.actual_pose())
        renders.append(device.last_rendering)
        joints.append([round(v, 9) for v in arm.joints.degrees()])
    notes = {
        "robot": {"model": "AdeptOne (simulated)", "mount": "forearm", "joints_deg": joints},
        "scene": {"kind": kind, "lift_mm": float(lift_mm), "seed": seed,
                  "pattern": pattern, "span_mm": float(span_mm),
                  "center_xy": [float(v) for v in su.center_xy],
                  "direction_deg": float(su.direction_deg), "roll_deg": float(su.roll_deg)},
    }
    cap = ViewsCapture(tuple(images), su.camera, tuple(poses),
                       depth_range_mm=su.depth_range_mm,
                       bit_depth=int(math.log2(su.camera.grey_levels)),
                       names=tuple(f"view_{k:02d}.png" for k in range(count)), notes=notes)
    return SimulatedViews(capture=cap, scene=scene, renderings=tuple(renders),
                          true_poses=tuple(true_poses), camera=su.camera)


def _six_axis_poses(vp: SixAxisViewpoints, pattern: str, count: int,
                    span_mm: float) -> list[SE3]:
    t = np.asarray(vp.target, dtype=float)
    tilt, az = math.radians(vp.tilt_deg), math.radians(vp.azimuth_deg)
    eye = t + vp.distance_mm * np.array([math.sin(tilt) * math.cos(az),
                                         math.sin(tilt) * math.sin(az), math.cos(tilt)])
    mid = SE3.look_at(eye, t, up=(0.0, 0.0, -1.0) if tilt == 0 else (0.0, 0.0, 1.0))
    offsets = view_offsets(pattern, count, span_mm,  # type: ignore[arg-type]
                           depth_mm=vp.distance_mm if pattern == "arc" else None)
    out = []
    for o in offsets:
        turn = SE3.identity()
        if pattern == "arc":
            turn = SE3.from_rotvec([0.0, 0.0, 0.0],
                                   [0.0, math.atan2(-o[0], vp.distance_mm - o[2]), 0.0])
        moved = SE3(mid.rotation, mid.translation + mid.rotation @ o)
        out.append(moved @ turn)
    return out


def _simulate_six_axis(kind: str, count: int, pattern: str, span_mm: float, lift_mm: float,
                       seed: int, vp: SixAxisViewpoints, scene: Scene | None) -> SimulatedViews:
    poses = _six_axis_poses(vp, pattern, count, span_mm)
    if scene is None:
        scene = (six_axis_block_scene(lift_mm=lift_mm) if kind == "block"
                 else hub_pulley_scene(center_xy=(vp.target[0], vp.target[1])))
    cal = estimated_hand_eye(seed)
    arm = SixAxisArm()
    rng = np.random.default_rng([seed, 19, 6, count, round(abs(lift_mm) * 100)])
    q = None
    flanges, renders, true_poses, joints = [], [], [], []
    for pose in poses:
        q, flange = arm.move_camera(pose, WRIST_HAND_EYE, q0=q)
        true = flange @ WRIST_HAND_EYE
        flanges.append(flange)
        true_poses.append(true)
        joints.append([round(float(v), 6) for v in np.degrees(q)])
        renders.append(render(scene, WRIST_CAMERA, true, rng=rng,
                              **SIX_AXIS_RENDER))  # type: ignore[arg-type]
    near = max(vp.distance_mm - 200.0, 50.0)
    images = []
    for r in renders:
        img = np.array(r.image, copy=True)
        img.setflags(write=False)
        images.append(img)
    notes = {"robot": {"model": "UR5-like six-axis arm (simulated)", "joints_deg": joints},
             "scene": {"kind": kind, "lift_mm": float(lift_mm), "seed": seed,
                       "pattern": pattern, "span_mm": float(span_mm)}}
    cap = ViewsCapture.from_flange(
        images, cal.camera, flanges=flanges, hand_eye=cal.hand_eye,
        depth_range_mm=(near, vp.distance_mm + 120.0), bit_depth=8,
        names=tuple(f"view_{k:02d}.png" for k in range(count)), notes=notes)
    return SimulatedViews(capture=cap, scene=scene, renderings=tuple(renders),
                          true_poses=tuple(true_poses), camera=WRIST_CAMERA)


def post_before_a_printed_plane() -> Scene:
    """An occluder seen from both sides: a post before a plane printed with random blobs.

    The post (12 x 40 mm, 150 mm tall, at world ``(400, 0)``) stands under the SCARA's
    mid viewpoint (:class:`~robostereo.robot.simulated.scara_rig.RigSetup`) before a plane
    0.5 mm above the table printed with smoothed random blobs, so the plane's edge points
    beside the post are hidden from the views on one side and seen from the others.
    Pass it as ``simulate_views("block", scene=...)``.

    Returns
    -------
    Scene
    """
    from scipy.ndimage import gaussian_filter

    rng = np.random.default_rng(5)
    blobs = gaussian_filter(rng.standard_normal((200, 320)), 8.0) > 0
    plane = ImagePlane(origin=(320.0, 50.0), image=0.15 + 0.65 * blobs, mm_per_px=0.5,
                       z=0.5, margin_mm=5.0, margin_albedo=0.5)
    post = Box(center=(400.0, 0.0), z_base=0.0, size=(12.0, 40.0, 150.0), albedo=0.5)
    return Scene((TablePlane(z=0.0, albedo=0.5), plane, post),
                 light_direction=(0.2, -0.1, 1.0))
