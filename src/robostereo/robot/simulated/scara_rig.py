"""The simulated AdeptOne rig: the thesis's set-up and its captures (the thesis, 4.1-4.2).

* :class:`RigSetup`: the simulated robot, camera and viewing geometry: the camera on
  the AdeptOne's forearm (:mod:`robostereo.robot.arms.scara`), the baseline and its
  direction, the rendering's blur and noise;
* :func:`block_scene` and :func:`pulley_scene`: the thesis's precision block and the
  hub-pulley (:mod:`robostereo.simulation.scenes`) placed for a set-up;
* :func:`simulate_capture`: the thesis's acquisition: the camera moved by the
  acquisition program to ``-D/2`` and ``+D/2`` about a point above the object, one
  image grabbed (rendered) at each; returns a :class:`SimulatedCapture`, whose
  :class:`~robostereo.robot.capture.locate_pair.Capture` is like the ones ``robostereo capture``
  writes, with the ground truth of its rendering.

Set-up choices (the thesis is silent; see :class:`RigSetup`): the camera's yaw offset on
the forearm is set so that at the mid-baseline point its x axis lies ``roll_deg`` from
the baseline direction (the thesis's operator lines the camera up with the baseline);
the block is placed square to the baseline, as the thesis's operator chose the baseline
across the block (figure 4-2); images are rendered with 5 x 5 rays per pixel, a
0.6-pixel lens blur and sensor noise of 0.5 grey level, quantised to 7 bits.

The experiments that use the rig are the application's (:mod:`robostereo.experiments`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_finite, require_nonnegative, require_positive
from robostereo.geometry.camera import SEED_CAMERA, Camera
from robostereo.robot.arms.acquisition import SimulatedCamera, acquire_stereo_pair
from robostereo.robot.arms.scara import AdeptOne, CameraMount
from robostereo.robot.capture.capture_folder import Capture, capture_from_acquisition
from robostereo.simulation.primitives import Box
from robostereo.simulation.render import Rendering, render
from robostereo.simulation.scenes import Scene, hub_pulley_scene, seed_block_scene

__all__ = [
    "SEED_LIFT_MM",
    "RigSetup",
    "SceneKind",
    "SimulatedCapture",
    "block_scene",
    "pulley_scene",
    "simulate_capture",
]

SEED_LIFT_MM = 79.65
"""The thesis's lift of the block between its two data sets (5.2)."""

SceneKind = Literal["block", "pulley"]
_BLOCK_OFFSET = (-43.3, -22.5)  # block centre from the view point, in the baseline frame


@dataclass(frozen=True)
class RigSetup:
    """The simulated robot, camera and viewing geometry of an experiment.

    Attributes
    ----------
    camera : Camera
        Default the thesis's (509 x 481, 25 mm, 17.2 x 13.7 um, 7 bit).
    center_xy : tuple of float
        World ``(x, y)`` of the mid-baseline point, mm (inside the AdeptOne's reach).
    baseline_mm : float
        ``D`` (the thesis: 20 mm).
    direction_deg : float
        Baseline direction ``alpha`` from world X, degrees.
    roll_deg : float
        Camera yaw minus ``alpha`` at the mid-baseline point, degrees (the forearm
        turns a little between the two viewpoints, so ``theta_l`` and ``theta_r``
        differ from it slightly).
    camera_height_mm : float
        Optical centre above the table (z = 0), mm; the forearm mount's height.
    supersample, blur_sigma_px, noise_sigma : float
        Rendering: rays per pixel side, lens blur (px), sensor noise (grey levels).
    table_depth_margin_mm, object_height_mm : float
        The capture's expected depth range is ``[camera_height - object_height,
        camera_height + margin]`` (anything from the table up to that height).
    """

    camera: Camera = SEED_CAMERA
    center_xy: tuple[float, float] = (400.0, 0.0)
    baseline_mm: float = 20.0
    direction_deg: float = 0.0
    roll_deg: float = 0.0
    camera_height_mm: float = 1050.0
    supersample: int = 5
    blur_sigma_px: float = 0.6
    noise_sigma: float = 0.5
    object_height_mm: float = 200.0
    table_depth_margin_mm: float = 20.0

    def __post_init__(self) -> None:
        if len(self.center_xy) != 2:
            raise InputError(f"center_xy must be (x, y), got {self.center_xy}")
        require_finite("center_xy", [float(v) for v in self.center_xy])
        require_positive("baseline_mm", self.baseline_mm)
        require_finite("direction_deg", self.direction_deg)
        require_finite("roll_deg", self.roll_deg)
        require_positive("camera_height_mm", self.camera_height_mm)
        require_positive("object_height_mm", self.object_height_mm)
        require_finite("table_depth_margin_mm", self.table_depth_margin_mm)
        require_nonnegative("noise_sigma", self.noise_sigma)
        if self.object_height_mm >= self.camera_height_mm:
            raise InputError("object_height_mm must be below camera_height_mm")

    @property
    def alpha(self) -> float:
        """Baseline direction, radians."""
        return math.radians(self.direction_deg)

    @property
    def depth_range_mm(self) -> tuple[float, float]:
        """Expected depth range of an object on the table."""
        return (self.camera_height_mm - self.object_height_mm,
                self.camera_height_mm + self.table_depth_margin_mm)



def _robot(setup: RigSetup) -> AdeptOne:
    """An AdeptOne whose forearm camera has yaw ``alpha + roll`` at the centre."""
    probe = AdeptOne(mount=CameraMount(z_mm=setup.camera_height_mm))
    arm = probe.forward(probe.inverse(*setup.center_xy)).phi
    offset = math.radians(setup.direction_deg + setup.roll_deg) - arm
    return AdeptOne(mount=CameraMount(z_mm=setup.camera_height_mm, yaw_offset=offset))


def block_scene(setup: RigSetup, *, lift_mm: float = 0.0) -> Scene:
    """The thesis's precision block (23.6 x 80 x 50 mm) square to the baseline.

    Its centre is at ``(-43.3, -22.5)`` mm from the mid-baseline point in the baseline
    frame (the faces at X = -55.1 and -31.5 mm as in table 5-1); `lift_mm` raises
    its top (a taller block, :func:`robostereo.simulation.scenes.seed_block_scene`).  The
    block and the light turn with the baseline direction: the whole set-up is the same
    in the baseline frame, whatever ``alpha`` (the shading of the block's visible side
    face moves its right edge point by up to 0.2 px, so a world-fixed lamp would make
    the result depend on ``alpha`` through the lighting, not the geometry).
    """
    c, s = math.cos(setup.alpha), math.sin(setup.alpha)
    ox, oy = _BLOCK_OFFSET
    off = (c * ox - s * oy, s * ox + c * oy)
    cx, cy = setup.center_xy
    center = (cx + off[0], cy + off[1])
    base = seed_block_scene(lift_mm=lift_mm, camera_height_mm=setup.camera_height_mm,
                            center_xy=center, offset_xy=off)
    prims = tuple(replace(p, yaw=setup.alpha) if isinstance(p, Box) else p
                  for p in base.primitives)
    lx, ly, lz = base.light_direction
    light = (c * lx - s * ly, s * lx + c * ly, lz)
    return replace(base, primitives=prims, light_direction=light)


def pulley_scene(setup: RigSetup) -> Scene:
    """The hub-pulley (:func:`robostereo.simulation.hub_pulley_scene`) under the centre."""
    return hub_pulley_scene(center_xy=tuple(setup.center_xy),  # type: ignore[arg-type]
                            camera_height_mm=setup.camera_height_mm)


@dataclass(frozen=True)
class SimulatedCapture:
    """A capture of the simulated robot with the ground truth of its rendering.

    Attributes
    ----------
    capture : Capture
    scene : Scene
    renderings : tuple of Rendering
        Left and right renderings (depth and labels ground truth).
    setup : RigSetup
    """

    capture: Capture
    scene: Scene
    renderings: tuple[Rendering, Rendering]
    setup: RigSetup


def simulate_capture(
    kind: SceneKind,
    *,
    setup: RigSetup | None = None,
    lift_mm: float = 0.0,
    seed: int = 0,
    scene: Scene | None = None,
) -> SimulatedCapture:
    """Move the simulated AdeptOne to the two viewpoints and grab (render) both images.

    Parameters
    ----------
    kind : {'block', 'pulley'}
    setup : RigSetup, optional
    lift_mm : float
        Block only: raise of the block's top.
    seed : int
        Seed of the sensor noise (``numpy.random.default_rng([seed, scene])``).
    scene : Scene, optional
        Render this scene instead of `kind`'s (e.g. one block seen along two baselines).

    Returns
    -------
    SimulatedCapture

    Raises
    ------
    InputError
        Bad parameters; :class:`~robostereo.errors.UnreachablePoseError` if a
        viewpoint is outside the robot's reach.

    Notes
    -----
    The thesis's acquisition (4.1, 4.2.1):
    :func:`robostereo.robot.arms.acquisition.acquire_stereo_pair` moves the camera to
    ``centre -+ (D/2) u``, grabbing at each; the poses the robot reports go into the
    capture.
    """
    su = setup or RigSetup()
    if kind not in ("block", "pulley"):
        raise InputError(f"scene must be 'block' or 'pulley', got {kind!r}")
    require_finite("lift_mm", lift_mm)
    if scene is None:
        scene = block_scene(su, lift_mm=lift_mm) if kind == "block" else pulley_scene(su)
    robot = _robot(su)
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise InputError(f"seed must be a whole number >= 0, got {seed}")
    stream = [0] if kind == "pulley" else [1 + (lift_mm < 0), round(abs(lift_mm) * 100)]
    rng = np.random.default_rng([int(seed), *stream])
    device = SimulatedCamera(scene, su.camera, robot, rng, render, {
        "supersample": su.supersample, "blur_sigma_px": su.blur_sigma_px,
        "noise_sigma": su.noise_sigma,
    })
    grabs: list[Rendering] = []

    class _Recorder:
        def grab(self) -> NDArray[Any]:
            image = device.grab()
            grabs.append(device.last_rendering)
            return image

    acq = acquire_stereo_pair(robot, _Recorder(), su.camera, center_xy=su.center_xy,
                              baseline_mm=su.baseline_mm, direction_deg=su.direction_deg)
    notes = {
        "robot": {"model": "AdeptOne (simulated)", "mount": "forearm",
                  "joints_left_deg": [round(v, 9) for v in acq.joints[0].degrees()],
                  "joints_right_deg": [round(v, 9) for v in acq.joints[1].degrees()]},
        "scene": {"kind": kind, "lift_mm": float(lift_mm), "seed": int(seed),
                  "center_xy": [float(v) for v in su.center_xy],
                  "direction_deg": float(su.direction_deg), "roll_deg": float(su.roll_deg)},
    }
    cap = capture_from_acquisition(acq, bit_depth=int(math.log2(su.camera.grey_levels)),
                                   depth_range_mm=su.depth_range_mm, notes=notes)
    return SimulatedCapture(capture=cap, scene=scene, renderings=(grabs[0], grabs[1]),
                            setup=su)
