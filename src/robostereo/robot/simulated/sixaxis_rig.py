"""The simulated six-axis rig: the block on the table seen from tilted viewpoints.

The thesis's block experiment (5.2) redone with a UR5-like arm
(:class:`~robostereo.robot.arms.sixaxis.SixAxisArm`) carrying a distorting wrist camera:

* :func:`six_axis_block_scene`: the thesis's precision block on the table at
  :data:`BLOCK_CENTER_XY`;
* :func:`simulate_six_axis_capture` moves the camera to two viewpoints
  (:class:`SixAxisViewpoints`) that differ in all six coordinates, the camera tilted from
  vertical, and grabs the block (or the hub-pulley); the capture holds the reported
  flange poses and whatever hand-eye transform and camera the caller calibrated.

Rendering uses :data:`SIX_AXIS_RENDER` (:func:`render_six_axis`): moderate sensor noise
and defocus blur plus a little vignetting.  The hand-eye views are in
:mod:`~robostereo.robot.simulated.sixaxis_handeye`, the block experiments in
:mod:`~robostereo.robot.simulated.block_experiments`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_finite
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.arms.sixaxis import WRIST_CAMERA, WRIST_HAND_EYE, SixAxisArm
from robostereo.robot.capture import Capture
from robostereo.simulation import Box, Rendering, Scene, TablePlane, hub_pulley_scene, render

__all__ = [
    "BLOCK_CENTER_XY",
    "BLOCK_SIZE",
    "SIX_AXIS_RENDER",
    "SixAxisCapture",
    "SixAxisViewpoints",
    "render_six_axis",
    "simulate_six_axis_capture",
    "six_axis_block_scene",
]

SIX_AXIS_RENDER: Mapping[str, float] = {
    "supersample": 3, "blur_sigma_px": 0.9, "noise_sigma": 1.5, "vignetting": 0.15,
}
"""Renderer options of the six-axis simulations: defocus blur 0.9 px, sensor noise
1.5 grey levels (of 255), 15 % vignetting at the corners, 3 x 3 rays per pixel."""

BLOCK_CENTER_XY = (430.0, 120.0)
"""Where the block stands on the table (world mm; the arm's base at the origin)."""
BLOCK_SIZE = (23.6, 80.0, 50.0)
"""The thesis's precision block: 23.6 x 80 mm, 50 mm tall (x, y, z; mm)."""


def render_six_axis(scene: Scene, camera: Camera, pose: SE3,
                    rng: np.random.Generator) -> Rendering:
    """`scene` seen by `camera` at `pose` with the options :data:`SIX_AXIS_RENDER`."""
    return render(scene, camera, pose, rng=rng, **SIX_AXIS_RENDER)  # type: ignore[arg-type]


def six_axis_block_scene(*, lift_mm: float = 0.0) -> Scene:
    """The thesis's precision block (23.6 x 80 mm, 50 mm tall plus `lift_mm`) on the table
    at :data:`BLOCK_CENTER_XY`."""
    require_finite("lift_mm", lift_mm)
    sx, sy, sz = BLOCK_SIZE
    if sz + lift_mm <= 0:
        raise InputError(f"lift_mm must leave the block a height > 0, got {lift_mm}")
    box = Box(center=BLOCK_CENTER_XY, z_base=0.0, size=(sx, sy, sz + lift_mm), albedo=0.8)
    return Scene((TablePlane(z=0.0, albedo=0.3), box), light_direction=(0.3, -0.2, 1.0))


@dataclass(frozen=True)
class SixAxisViewpoints:
    """The two camera viewpoints of a six-axis capture.

    Attributes
    ----------
    target : tuple of float
        World point the mid-baseline camera looks at, mm.
    distance_mm : float
        Distance of the mid-baseline optical centre from `target`.
    tilt_deg : float
        Angle of the optical axis from vertical (>= 20 for the demo).
    azimuth_deg : float
        Direction (from world X) in which the camera stands off the target.
    baseline_mm : float
        Distance between the two optical centres.
    offset_mm : tuple of float
        Right minus left optical centre besides the baseline, in the mid camera's
        ``(y, z)`` axes (so the centres differ in all three coordinates).
    turn_rotvec : tuple of float
        Rotation vector (radians, camera frame) of the right camera against the left.
    """

    target: tuple[float, float, float] = (BLOCK_CENTER_XY[0], BLOCK_CENTER_XY[1], 60.0)
    distance_mm: float = 420.0
    tilt_deg: float = 25.0
    azimuth_deg: float = -100.0
    baseline_mm: float = 40.0
    offset_mm: tuple[float, float] = (3.0, -4.0)
    turn_rotvec: tuple[float, float, float] = (0.012, -0.018, 0.025)

    def camera_poses(self) -> tuple[SE3, SE3]:
        """``T_world_camera`` of the left and right viewpoints."""
        t = np.asarray(self.target, dtype=float)
        tilt, az = math.radians(self.tilt_deg), math.radians(self.azimuth_deg)
        eye = t + self.distance_mm * np.array([math.sin(tilt) * math.cos(az),
                                               math.sin(tilt) * math.sin(az), math.cos(tilt)])
        mid = SE3.look_at(eye, t, up=(0.0, 0.0, -1.0) if tilt == 0 else (0.0, 0.0, 1.0))
        R = mid.rotation
        b = 0.5 * self.baseline_mm * R[:, 0]
        o = 0.5 * (self.offset_mm[0] * R[:, 1] + self.offset_mm[1] * R[:, 2])
        half = SE3.from_rotvec([0, 0, 0], 0.5 * np.asarray(self.turn_rotvec))
        left = SE3(mid.rotation, mid.translation - b - o) @ half.inv()
        right = SE3(mid.rotation, mid.translation + b + o) @ half
        return left, right


@dataclass(frozen=True, eq=False)
class SixAxisCapture:
    """A six-axis capture with its truth.

    Attributes
    ----------
    capture : Capture
        Reported flange poses, the hand-eye transform and camera given (estimates).
    scene : Scene
    renderings : tuple of Rendering
    true_poses : tuple of SE3
        True ``T_world_camera`` of the two views.
    joints : tuple of ndarray
    """

    capture: Capture
    scene: Scene
    renderings: tuple[Rendering, Rendering]
    true_poses: tuple[SE3, SE3]
    joints: tuple[NDArray[np.float64], NDArray[np.float64]]


def simulate_six_axis_capture(
    kind: Literal["block", "pulley"] = "block",
    *,
    lift_mm: float = 0.0,
    seed: int = 0,
    viewpoints: SixAxisViewpoints | None = None,
    hand_eye: SE3 | None = None,
    camera: Camera | None = None,
    arm: SixAxisArm | None = None,
) -> SixAxisCapture:
    """Grab two views of the block (or the hub-pulley) with the six-axis arm.

    Parameters
    ----------
    kind : {'block', 'pulley'}
    lift_mm : float
        Block only: raise of its top.
    seed : int
        Sensor-noise seed.
    viewpoints : SixAxisViewpoints, optional
    hand_eye, camera : optional
        What the capture records as ``hand_eye`` and ``camera`` (default the truth;
        the demo passes its calibration).  The images are always rendered with the
        true camera at the true poses.
    arm : SixAxisArm, optional

    Raises
    ------
    UnreachablePoseError
        A viewpoint outside the arm's reach or joint limits.
    """
    if kind not in ("block", "pulley"):
        raise InputError(f"scene must be 'block' or 'pulley', got {kind!r}")
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise InputError(f"seed must be a whole number >= 0, got {seed}")
    a = arm or SixAxisArm()
    vp = viewpoints or SixAxisViewpoints()
    if kind == "block":
        scene = six_axis_block_scene(lift_mm=lift_mm)
    else:
        scene = hub_pulley_scene(center_xy=BLOCK_CENTER_XY)
    rng = np.random.default_rng([int(seed), 6, round(abs(lift_mm) * 100)])
    q = None
    flanges, joints, renders = [], [], []
    for pose in vp.camera_poses():
        q, flange = a.move_camera(pose, WRIST_HAND_EYE, q0=q)
        flanges.append(flange)
        joints.append(q)
        renders.append(render_six_axis(scene, WRIST_CAMERA, flange @ WRIST_HAND_EYE, rng))
    near = max(vp.distance_mm - 200.0, 50.0)
    cap = Capture.from_flange(
        flange_left=flanges[0], flange_right=flanges[1],
        hand_eye=hand_eye if hand_eye is not None else WRIST_HAND_EYE,
        left=renders[0].image, right=renders[1].image,
        camera=camera if camera is not None else WRIST_CAMERA, bit_depth=8,
        depth_range_mm=(near, vp.distance_mm + 120.0),
        notes={"robot": {"model": "UR5-like six-axis arm (simulated)",
                         "joints_left_deg": [round(float(v), 6) for v in np.degrees(joints[0])],
                         "joints_right_deg": [round(float(v), 6) for v in np.degrees(joints[1])]},
               "scene": {"kind": kind, "lift_mm": float(lift_mm), "seed": int(seed)}},
    )
    true = (flanges[0] @ WRIST_HAND_EYE, flanges[1] @ WRIST_HAND_EYE)
    return SixAxisCapture(capture=cap, scene=scene, renderings=(renders[0], renders[1]),
                          true_poses=true, joints=(joints[0], joints[1]))

