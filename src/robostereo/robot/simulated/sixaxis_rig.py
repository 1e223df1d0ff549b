"""Simulated six-axis experiments: hand-eye views and the block from tilted viewpoints.

The thesis's block experiment (5.2) redone with a UR5-like arm
(:class:`~robostereo.robot.arms.sixaxis.SixAxisArm`) carrying a distorting wrist camera:

* :func:`simulate_handeye_views` renders a chessboard on the table from tilted views
  and records the flange pose of each (a hand-eye views folder, with the truth);
* :func:`simulate_six_axis_capture` moves the camera to two viewpoints that differ in
  all six coordinates, the camera tilted from vertical, and grabs the block (or the
  hub-pulley); the capture holds the reported flange poses and whatever hand-eye
  transform and camera the caller calibrated;
* :func:`run_six_axis_block` calibrates from simulated views, captures the block at
  two heights 79.65 mm apart and compares the located points with the truth.

Rendering uses :data:`SIX_AXIS_RENDER`: moderate sensor noise and defocus blur plus a
little vignetting.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, UnreachablePoseError, require_finite
from robostereo.geometry.camera import Camera, camera_to_dict
from robostereo.geometry.poses import SE3, pose_to_dict
from robostereo.matcher.parameters import MatchParameters
from robostereo.robot.arms.sixaxis import WRIST_CAMERA, WRIST_HAND_EYE, SixAxisArm
from robostereo.robot.capture import Capture, Located, LocateParameters, locate
from robostereo.robot.handeye import (
    DEFAULT_METHOD,
    Board,
    Chessboard,
    EyeInHandCalibration,
    HandEyeMethod,
    HandEyeViews,
    calibrate_eye_in_hand,
)
from robostereo.robot.simulated.scara_rig import (
    SEED_LIFT_MM,
    RigSetup,
    block_scene,
    simulate_capture,
)
from robostereo.simulation import (
    Box,
    Checkerboard,
    ImagePlane,
    Rendering,
    Scene,
    TablePlane,
    hub_pulley_scene,
    render,
)

__all__ = [
    "BLOCK_CENTER_XY",
    "BOARD",
    "SIX_AXIS_RENDER",
    "FusedBlockGain",
    "SixAxisBlock",
    "SixAxisCapture",
    "SixAxisHeight",
    "SixAxisViewpoints",
    "board_scene",
    "run_fused_block",
    "run_six_axis_block",
    "simulate_handeye_views",
    "simulate_six_axis_capture",
    "six_axis_block_scene",
]

SIX_AXIS_RENDER: Mapping[str, float] = {
    "supersample": 3, "blur_sigma_px": 0.9, "noise_sigma": 1.5, "vignetting": 0.15,
}
"""Renderer options of the six-axis simulations: defocus blur 0.9 px, sensor noise
1.5 grey levels (of 255), 15 % vignetting at the corners, 3 x 3 rays per pixel."""

BOARD = Chessboard(inner_corners=(9, 6), square_mm=12.0)
"""The simulated calibration board: 9 x 6 inner corners, 12 mm squares."""
BOARD_ORIGIN_XY = (300.0, 150.0)
BLOCK_CENTER_XY = (430.0, 120.0)
"""Where the block stands on the table (world mm; the arm's base at the origin)."""
_BLOCK_SIZE = (23.6, 80.0, 50.0)


def board_scene(
    *, board: Board = BOARD, origin_xy: tuple[float, float] = BOARD_ORIGIN_XY, yaw: float = 0.0
) -> tuple[Scene, Checkerboard | ImagePlane]:
    """A calibration board (2 mm thick) lying on the table, and the board primitive.

    A :class:`Chessboard` is drawn analytically (:class:`Checkerboard`), a
    :class:`Charuco` as its OpenCV image printed at 10 px/mm (:class:`ImagePlane`).
    """
    cb: Checkerboard | ImagePlane
    if isinstance(board, Chessboard):
        cb = Checkerboard(origin=origin_xy, z=2.0, inner_corners=board.inner_corners,
                          square_mm=board.square_mm, yaw=yaw)
    else:
        img = board.image(25.0).astype(np.float64) / 255.0
        cb = ImagePlane(origin=origin_xy, image=0.08 + 0.77 * img, mm_per_px=0.04, z=2.0,
                        yaw=yaw)
    return Scene((TablePlane(z=0.0, albedo=0.3), cb), light_direction=(0.2, -0.1, 1.0)), cb


def _board_frame(board: Board) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Board-frame centre (3,) and outline corners (4, 3) that must be in view."""
    q = board.square_mm
    if isinstance(board, Chessboard):
        c, r = board.inner_corners
        x0, x1, y0, y1 = -q, c * q, -q, r * q
    else:
        c, r = board.squares
        x0, x1, y0, y1 = 0.0, c * q, 0.0, r * q
    centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2, 0.0])
    outline = np.array([[x0, y0, 0.0], [x1, y0, 0.0], [x0, y1, 0.0], [x1, y1, 0.0]])
    return centre, outline


def _render(scene: Scene, camera: Camera, pose: SE3, rng: np.random.Generator) -> Rendering:
    return render(scene, camera, pose, rng=rng, **SIX_AXIS_RENDER)  # type: ignore[arg-type]


def simulate_handeye_views(
    *,
    views: int = 15,
    seed: int = 0,
    arm: SixAxisArm | None = None,
    camera: Camera = WRIST_CAMERA,
    hand_eye: SE3 = WRIST_HAND_EYE,
    board: Board = BOARD,
) -> tuple[HandEyeViews, dict[str, Any]]:
    """Views of a chessboard on the table from the six-axis arm's wrist camera.

    Parameters
    ----------
    views : int
        Number of views (>= 3).
    seed : int
        Seed of the viewpoints and the sensor noise.
    arm, camera, hand_eye, board
        The simulated arm (default a UR5), wrist camera, true ``T_flange_camera``
        and board (a :class:`Chessboard` or a :class:`Charuco`).

    Returns
    -------
    views : HandEyeViews
        Images and the flange poses the arm reports.
    truth : dict
        ``camera`` (mapping), ``hand_eye`` and ``base_board`` (pose mappings), in the
        file forms of :mod:`robostereo.geometry.poses`.

    Notes
    -----
    The camera looks at points within 40 mm of the board centre from 330-430 mm away,
    tilted 12-38 degrees from vertical at azimuths spread round the board, turned up to
    30 degrees about its axis (the board whole in the view, anywhere in the image), so
    that the flange rotates about many axes.  Each camera pose is reached by
    inverse kinematics (``flange = camera @ hand_eye^-1``).
    """
    if isinstance(views, bool) or int(views) != views or views < 3:
        raise InputError(f"views must be an integer >= 3, got {views}")
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise InputError(f"seed must be a whole number >= 0, got {seed}")
    a = arm or SixAxisArm()
    rng = np.random.default_rng([int(seed), 9])
    scene, cb = board_scene(board=board)
    centre_b, outline_b = _board_frame(board)
    centre = cb.pose.apply(centre_b)
    outline = cb.pose.apply(outline_b)
    images, poses, names = [], [], []
    q = None
    attempts = 0
    while len(images) < views:
        attempts += 1
        if attempts > 4 * views:
            raise InputError(f"could not place {views} hand-eye views within the arm's reach")
        i = len(images)
        az = 2 * math.pi * i / views + rng.uniform(-0.3, 0.3)
        tilt = math.radians(rng.uniform(12.0, 38.0))
        dist = rng.uniform(330.0, 430.0)
        target = centre + np.array([rng.uniform(-40, 40), rng.uniform(-28, 28), 0.0])
        eye = target + dist * np.array([math.sin(tilt) * math.cos(az),
                                        math.sin(tilt) * math.sin(az), math.cos(tilt)])
        cam_pose = SE3.look_at(eye, target)
        roll = SE3.from_rotvec([0, 0, 0], [0, 0, math.radians(rng.uniform(-30, 30))])
        cam_pose = cam_pose @ roll
        uv, _ = camera.project(outline, cam_pose)
        w, h = camera.image_size
        if not ((uv[:, 0] > 8) & (uv[:, 0] < w - 9) & (uv[:, 1] > 8) & (uv[:, 1] < h - 9)).all():
            continue  # the board (with its margin) must be whole in the view
        try:
            q, flange = a.move_camera(cam_pose, hand_eye, q0=q)
        except UnreachablePoseError:
            continue  # draw another viewpoint
        images.append(_render(scene, camera, flange @ hand_eye, rng).image)
        poses.append(flange)
        names.append(f"view_{i:02d}.png")
    truth = {
        "camera": camera_to_dict(camera),
        "hand_eye": pose_to_dict(hand_eye),
        "base_board": pose_to_dict(cb.pose),
        "units": "mm",
    }
    v = HandEyeViews(images=tuple(images), flange_poses=tuple(poses), names=tuple(names),
                     board=board, pixel_pitch_mm=camera.pixel_pitch_mm[0],
                     grey_levels=camera.grey_levels)
    return v, truth


# --------------------------------------------------------------------- block captures


def six_axis_block_scene(*, lift_mm: float = 0.0) -> Scene:
    """The thesis's precision block (23.6 x 80 mm, 50 mm tall plus `lift_mm`) on the table
    at :data:`BLOCK_CENTER_XY`."""
    require_finite("lift_mm", lift_mm)
    sx, sy, sz = _BLOCK_SIZE
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
        renders.append(_render(scene, WRIST_CAMERA, flange @ WRIST_HAND_EYE, rng))
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


# ------------------------------------------------------------------------- the block


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
        top = _BLOCK_SIZE[2] + lift
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
