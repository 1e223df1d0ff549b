"""The simulated block experiments: from the six-axis arm, and from two baselines fused.

The thesis's block experiment (5.2, table 5-1) redone in simulation:

* :func:`run_six_axis_block` calibrates the six-axis arm's hand-eye transform and camera
  from simulated views (:func:`~robostereo.robot.simulated.sixaxis_handeye.simulate_handeye_views`),
  captures the block at two heights 79.65 mm apart from tilted viewpoints
  (:func:`~robostereo.robot.simulated.sixaxis_rig.simulate_six_axis_capture`) and compares
  the located points with the truth;
* :func:`run_fused_block` captures the block on the simulated AdeptOne
  (:mod:`~robostereo.robot.simulated.scara_rig`) with the baseline along X and along Y,
  and fuses the two (:func:`~robostereo.robot.planning.fuse_located`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.matcher.parameters import MatchParameters
from robostereo.robot.arms.sixaxis import WRIST_CAMERA, WRIST_HAND_EYE
from robostereo.robot.capture import Located, LocateParameters, locate
from robostereo.robot.handeye import (
    DEFAULT_METHOD,
    EyeInHandCalibration,
    HandEyeMethod,
    calibrate_eye_in_hand,
)
from robostereo.robot.simulated.scara_rig import (
    SEED_LIFT_MM,
    RigSetup,
    block_scene,
    simulate_capture,
)
from robostereo.robot.simulated.sixaxis_handeye import simulate_handeye_views
from robostereo.robot.simulated.sixaxis_rig import (
    BLOCK_SIZE,
    SixAxisCapture,
    SixAxisViewpoints,
    simulate_six_axis_capture,
)
from robostereo.simulation import Box

__all__ = [
    "FusedBlockGain",
    "SixAxisBlock",
    "SixAxisHeight",
    "run_fused_block",
    "run_six_axis_block",
]


@dataclass(frozen=True, eq=False)
class SixAxisHeight:
    """One height of the six-axis block experiment.

    Attributes
    ----------
    lift_mm : float
    sim : SixAxisCapture
    located : Located
    on_top : ndarray of bool, shape (M,)
        Located points on the block's top face edges (by the truth).
    z_error : ndarray, shape (K,)
        Epipolar-frame depth error (measured - true) of the top points, mm.
    z_bound : ndarray, shape (K,)
        Their eq. 9 bounds, mm.
    mean_top_z : float
        Mean world Z of the top points, mm.
    true_top_z : float
    """

    lift_mm: float
    sim: SixAxisCapture
    located: Located
    on_top: NDArray[np.bool_]
    z_error: NDArray[np.float64]
    z_bound: NDArray[np.float64]
    mean_top_z: float
    true_top_z: float


@dataclass(frozen=True, eq=False)
class SixAxisBlock:
    """Result of :func:`run_six_axis_block`.

    Attributes
    ----------
    calibration : EyeInHandCalibration
        The hand-eye calibration from simulated views (used for the captures).
    heights : tuple of SixAxisHeight
    handeye_translation_error_mm, handeye_rotation_error_deg : float
        Estimated against true ``T_flange_camera``.
    tilt_deg : float
        Angle of the left camera's optical axis from vertical.
    pose_differences : dict
        Right minus left camera: ``dx, dy, dz`` (mm) and ``droll, dpitch, dyaw`` (deg).
    """

    calibration: EyeInHandCalibration
    heights: tuple[SixAxisHeight, ...]
    handeye_translation_error_mm: float
    handeye_rotation_error_deg: float
    tilt_deg: float
    pose_differences: dict[str, float] = field(default_factory=dict)

    @property
    def lift_mm(self) -> float:
        return self.heights[1].mean_top_z - self.heights[0].mean_top_z

    @property
    def lift_true_mm(self) -> float:
        return self.heights[1].true_top_z - self.heights[0].true_top_z

    @property
    def max_abs_error_mm(self) -> float:
        return max(float(np.max(np.abs(h.z_error))) for h in self.heights)

    @property
    def all_within_bound(self) -> bool:
        return all(bool(np.all(np.abs(h.z_error) <= h.z_bound)) for h in self.heights)

    def summary(self) -> dict[str, Any]:
        """The figures ``robostereo demo --robot six-axis --json`` prints."""
        worst = [(float(np.max(np.abs(h.z_error))),
                  float(h.z_bound[int(np.argmax(np.abs(h.z_error)))])) for h in self.heights]
        return {
            "lift_mm": round(self.lift_mm, 4),
            "lift_true_mm": round(self.lift_true_mm, 4),
            "max_abs_error_mm": round(self.max_abs_error_mm, 4),
            "bound_at_max_error_mm": round(max(worst)[1], 4),
            "all_within_bound": self.all_within_bound,
            "block_points": [len(h.z_error) for h in self.heights],
            "located_points": [len(h.located) for h in self.heights],
            "median_bound_mm": round(float(np.median(np.concatenate(
                [h.z_bound for h in self.heights]))), 4),
            "handeye_method": self.calibration.method,
            "handeye_translation_error_mm": round(self.handeye_translation_error_mm, 4),
            "handeye_rotation_error_deg": round(self.handeye_rotation_error_deg, 5),
            "reprojection_rms_px": round(self.calibration.reprojection_rms_px, 4),
            "camera_tilt_deg": round(self.tilt_deg, 3),
            "pose_difference": {k: round(v, 4) for k, v in self.pose_differences.items()},
        }


def _top_points(sim: SixAxisCapture, located: Located, top_z: float
                ) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """Located points whose true surface point is on the block's top-face boundary, and
    the epipolar-frame depth of that true point."""
    cam, pose = WRIST_CAMERA, sim.true_poses[0]
    pix = located.left_pixel
    if len(pix) == 0:
        return np.zeros(0, bool), np.zeros(0)
    ray = cam.backproject(pix, np.ones(len(pix)), pose) - pose.translation
    t = (top_z - pose.translation[2]) / ray[:, 2]
    P = pose.translation + t[:, None] * ray
    box = next(p for p in sim.scene.primitives if isinstance(p, Box))
    hx, hy = box.size[0] / 2, box.size[1] / 2
    lx, ly = P[:, 0] - box.center[0], P[:, 1] - box.center[1]
    inside = (np.abs(lx) <= hx + 1.0) & (np.abs(ly) <= hy + 1.0)
    edge = inside & ((np.abs(np.abs(lx) - hx) <= 1.0) | (np.abs(np.abs(ly) - hy) <= 1.0))
    near = np.abs(located.world[:, 2] - top_z) < 10.0
    z_true = located.geometry.from_world(P)[:, 2]
    return edge & near, z_true


def run_six_axis_block(
    *,
    seed: int = 0,
    views: int = 15,
    method: HandEyeMethod = DEFAULT_METHOD,
    viewpoints: SixAxisViewpoints | None = None,
    params: LocateParameters | None = None,
) -> SixAxisBlock:
    """The block experiment from the six-axis arm, with the hand-eye transform and the
    camera calibrated from simulated views (not the truth).

    Parameters
    ----------
    seed : int
        Seed of the hand-eye views and of the sensor noise.
    views : int
        Number of hand-eye views.
    method : {'park', 'tsai', 'daniilidis'}
    viewpoints : SixAxisViewpoints, optional
    params : LocateParameters, optional
        Default: the thesis's matcher (relaxation), as the SCARA block experiment
        (``robostereo.experiments.SEED_EXPERIMENT``).

    Notes
    -----
    1. :func:`simulate_handeye_views`,
       :func:`~robostereo.robot.handeye.calibrate.calibrate_eye_in_hand`.
    2. For lifts 0 and 79.65 mm: :func:`simulate_six_axis_capture` recording the
       calibrated camera and hand-eye transform,
       :func:`~robostereo.robot.capture.locate_pair.locate`.
    3. The located points whose true surface point (the left pixel's ray with the true
       camera, cut with the true top plane) lies on the top face's boundary are the
       block's; their depth error is taken in the capture's epipolar frame, where eq. 9
       bounds it; the lift is the difference of their mean world Z.

    References
    ----------
    Kim (1989), the thesis, 5.2 (the block at two heights, table 5-1), 3.7 (eq. 9).
    """
    hv, _truth = simulate_handeye_views(views=views, seed=seed)
    cal = calibrate_eye_in_hand(hv.images, hv.flange_poses, hv.board,
                                pixel_pitch_mm=hv.pixel_pitch_mm, grey_levels=hv.grey_levels,
                                method=method, names=hv.names)
    t_err, r_err = WRIST_HAND_EYE.distance_to(cal.hand_eye)
    heights = []
    for lift in (0.0, SEED_LIFT_MM):
        sim = simulate_six_axis_capture("block", lift_mm=lift, seed=seed,
                                        viewpoints=viewpoints, hand_eye=cal.hand_eye,
                                        camera=cal.camera)
        # the thesis's block experiment, with the thesis's matcher as robostereo demo uses it
        loc = locate(sim.capture, params=params or LocateParameters(
            match=MatchParameters(method="relaxation")))
        top = BLOCK_SIZE[2] + lift
        on_top, z_true = _top_points(sim, loc, top)
        z_err = loc.epipolar_xyz[on_top, 2] - z_true[on_top] if on_top.any() else np.zeros(0)
        if not on_top.any():
            raise InputError("six-axis block: no located point on the block's top edges")
        heights.append(SixAxisHeight(
            lift_mm=lift, sim=sim, located=loc, on_top=on_top, z_error=z_err,
            z_bound=loc.z_bound[on_top], mean_top_z=float(loc.world[on_top, 2].mean()),
            true_top_z=top))
    left, right = heights[0].sim.true_poses
    tilt = math.degrees(math.acos(float(np.clip(-left.rotation[2, 2], -1.0, 1.0))))
    from scipy.spatial.transform import Rotation

    e_l = Rotation.from_matrix(left.rotation).as_euler("xyz", degrees=True)
    e_r = Rotation.from_matrix(right.rotation).as_euler("xyz", degrees=True)
    d = right.translation - left.translation
    de = (e_r - e_l + 180.0) % 360.0 - 180.0
    diffs = {"dx_mm": float(d[0]), "dy_mm": float(d[1]), "dz_mm": float(d[2]),
             "droll_deg": float(de[0]), "dpitch_deg": float(de[1]), "dyaw_deg": float(de[2])}
    return SixAxisBlock(calibration=cal, heights=tuple(heights),
                        handeye_translation_error_mm=t_err,
                        handeye_rotation_error_deg=math.degrees(r_err), tilt_deg=tilt,
                        pose_differences=diffs)


# ------------------------------------------------------------- orthogonal baselines


@dataclass(frozen=True, eq=False)
class FusedBlockGain:
    """The block seen along two orthogonal baselines (:func:`run_fused_block`).

    Attributes
    ----------
    located : tuple of int
        Points located along the x and the y baseline.
    fused : int
        Points after :func:`~robostereo.robot.planning.fuse_located`.
    top_edge_points : tuple of int
        Points within 2 mm of the block's top outline: x baseline, y baseline, fused.
    outline_covered : tuple of float
        Share of the top outline (sampled every 0.26 mm) with a located point within
        1.5 mm: x baseline, y baseline, fused.
    """

    located: tuple[int, int]
    fused: int
    top_edge_points: tuple[int, int, int]
    outline_covered: tuple[float, float, float]


def run_fused_block(*, seed: int = 0) -> FusedBlockGain:
    """The thesis's block (on the simulated AdeptOne) captured with the baseline along
    world X (the thesis's) and along Y, located and fused.

    The thesis's baseline runs along the block's short top edges, which lie along the
    epipolar lines and are lost; the second baseline crosses them.
    """
    from scipy.spatial import cKDTree

    from robostereo.robot.planning import fuse_located

    scene = block_scene(RigSetup())
    box = next(p for p in scene.primitives if isinstance(p, Box))
    c = box.corners()
    top = c[c[:, 2] == c[:, 2].max()]
    ang = np.arctan2(top[:, 1] - top[:, 1].mean(), top[:, 0] - top[:, 0].mean())
    tc = top[np.argsort(ang)]
    outline = np.vstack([np.linspace(tc[i], tc[(i + 1) % 4], 200, endpoint=False)
                         for i in range(4)])
    loc = [locate(simulate_capture("block", setup=RigSetup(direction_deg=d), scene=scene,
                                   seed=seed).capture) for d in (0.0, 90.0)]
    fused = fuse_located(loc[0], loc[1])
    worlds = (loc[0].world, loc[1].world, fused.world)

    def on_top(w: NDArray[np.float64]) -> int:
        return int((cKDTree(outline).query(w)[0] < 2.0).sum()) if len(w) else 0

    def covered(w: NDArray[np.float64]) -> float:
        return float((cKDTree(w).query(outline)[0] < 1.5).mean()) if len(w) else 0.0

    return FusedBlockGain(
        located=(len(loc[0]), len(loc[1])), fused=len(fused),
        top_edge_points=tuple(on_top(w) for w in worlds),  # type: ignore[arg-type]
        outline_covered=tuple(covered(w) for w in worlds),  # type: ignore[arg-type]
    )
