"""The seed's experiments on the simulated AdeptOne (seed chapters 4-5).

* :func:`simulate_capture`: the seed's set-up: the camera on the AdeptOne's forearm,
  moved by the acquisition program to ``-D/2`` and ``+D/2`` about a point above the
  object, one image grabbed (rendered) at each; returns a
  :class:`~robostereo.robot.capture.Capture` like the ones ``robostereo capture`` writes.
* :func:`run_block_experiment`: the accuracy test of 5.2 (table 5-1): the precision
  block at two heights 79.65 mm apart; per epipolar line the block's left and right
  edge points, the width, the mean depth per height, the measured lift and every
  point's depth error against its eq. (9) bound.
* :func:`run_pulley_experiment`: the effectiveness test of 5.1: the hub-pulley's edge
  points, and % matched and % false against the rendered ground truth after every
  relaxation iteration.
* :func:`run_demo`: both, as ``robostereo demo`` runs them; :func:`save_demo_figures`
  and :func:`print_demo_report` show them.

Set-up choices (the seed is silent; see :class:`RigSetup`): the camera's yaw offset on
the forearm is set so that at the mid-baseline point its x axis lies ``roll_deg`` from
the baseline direction (the seed's operator lines the camera up with the baseline);
the block is placed square to the baseline, as the seed's operator chose the baseline
across the block (figure 4-2); images are rendered with 5 x 5 rays per pixel, a
0.6-pixel lens blur and sensor noise of 0.5 grey level, quantised to 7 bits.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from robostereo.camera import SEED_CAMERA, Camera, EpipolarGeometry
from robostereo.errors import InputError, require_finite, require_nonnegative, require_positive
from robostereo.evaluation import MatchScore, score_matches
from robostereo.pipeline import MatchParameters
from robostereo.robot import AdeptOne, CameraMount, SimulatedCamera, acquire_stereo_pair
from robostereo.robot.capture import (
    Capture,
    Located,
    LocateParameters,
    capture_from_acquisition,
    locate,
)
from robostereo.simulation import (
    Box,
    Rendering,
    Scene,
    hub_pulley_scene,
    render,
    seed_block_scene,
)

__all__ = [
    "SEED_LIFT_MM",
    "BlockExperiment",
    "BlockHeight",
    "DemoResult",
    "PulleyExperiment",
    "RigSetup",
    "SimulatedCapture",
    "block_scene",
    "print_demo_report",
    "pulley_scene",
    "run_block_experiment",
    "run_demo",
    "run_pulley_experiment",
    "save_demo_figures",
    "simulate_capture",
]

SEED_LIFT_MM = 79.65
"""The seed's lift of the block between its two data sets (5.2)."""

SceneKind = Literal["block", "pulley"]
_BLOCK_OFFSET = (-43.3, -22.5)  # block centre from the view point, in the baseline frame


@dataclass(frozen=True)
class RigSetup:
    """The simulated robot, camera and viewing geometry of an experiment.

    Attributes
    ----------
    camera : Camera
        Default the seed's (509 x 481, 25 mm, 17.2 x 13.7 um, 7 bit).
    center_xy : tuple of float
        World ``(x, y)`` of the mid-baseline point, mm (inside the AdeptOne's reach).
    baseline_mm : float
        ``D`` (seed: 20 mm).
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


#: the experiments' matcher: the seed's, relaxation on connectivity (with robostereo's
#: sub-pixel edges), so that the figures follow the seed's iterations (fig. 4-4)
SEED_EXPERIMENT = LocateParameters(match=MatchParameters(method="relaxation"))


def _robot(setup: RigSetup) -> AdeptOne:
    """An AdeptOne whose forearm camera has yaw ``alpha + roll`` at the centre."""
    probe = AdeptOne(mount=CameraMount(z_mm=setup.camera_height_mm))
    arm = probe.forward(probe.inverse(*setup.center_xy)).phi
    offset = math.radians(setup.direction_deg + setup.roll_deg) - arm
    return AdeptOne(mount=CameraMount(z_mm=setup.camera_height_mm, yaw_offset=offset))


def block_scene(setup: RigSetup, *, lift_mm: float = 0.0) -> Scene:
    """The seed's precision block (23.6 x 80 x 50 mm) square to the baseline.

    Its centre is at ``(-43.3, -22.5)`` mm from the mid-baseline point in the baseline
    frame (the faces at X = -55.1 and -31.5 mm as in table 5-1); `lift_mm` raises
    its top (a taller block, :func:`robostereo.simulation.seed_block_scene`).  The
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
    The seed's acquisition (4.1, 4.2.1): :func:`robostereo.robot.scara.acquire_stereo_pair`
    moves the camera to ``centre -+ (D/2) u``, grabbing at each; the poses the robot
    reports go into the capture.
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


# ------------------------------------------------------------------------------- block


@dataclass(frozen=True)
class BlockHeight:
    """One data set of the block test (one half of table 5-1).

    Attributes
    ----------
    lift_mm : float
    located : Located
        Everything :func:`robostereo.robot.capture.locate` found.
    true_depth_mm : float
        Depth of the block's top below the mid-baseline point (the true Z).
    true_x_mm : tuple of float
        True epipolar X of the block's left and right top edges.
    true_rows : tuple of float
        Rectified rows of the block's near and far ends (top face).
    side : ndarray of int, shape (M,)
        For each located point: -1 on the left top edge, +1 on the right, 0 neither.
    z_error, x_error : ndarray, shape (M,)
        ``Z - true Z`` and ``X - true X`` (mm) of the block edge points (NaN elsewhere).
    lines : dict of ndarray
        Per epipolar line with both edges matched: ``row``, ``x, y, z`` (left edge),
        ``x2, y2, z2`` (right edge), ``width`` (mm), ``z_bound``, ``z2_bound``.
    """

    lift_mm: float
    located: Located
    true_depth_mm: float
    true_x_mm: tuple[float, float]
    true_rows: tuple[float, float]
    side: NDArray[np.int8]
    z_error: NDArray[np.float64]
    x_error: NDArray[np.float64]
    lines: dict[str, NDArray[Any]]

    @property
    def block_points(self) -> NDArray[np.bool_]:
        return self.side != 0

    @property
    def mean_z(self) -> float:
        """Mean Z of the block edge points, mm."""
        return float(np.mean(self.located.epipolar_xyz[self.block_points, 2]))

    @property
    def max_abs_z_error(self) -> float:
        return float(np.max(np.abs(self.z_error[self.block_points])))

    @property
    def within_bound(self) -> NDArray[np.bool_]:
        """``|z error| <= z_bound`` for each block edge point."""
        b = self.block_points
        return np.abs(self.z_error[b]) <= self.located.z_bound[b]

    @property
    def true_width_mm(self) -> float:
        return self.true_x_mm[1] - self.true_x_mm[0]


@dataclass(frozen=True)
class BlockExperiment:
    """The accuracy test of seed 5.2: the block at two heights.

    Attributes
    ----------
    heights : tuple of BlockHeight
        The block at ``lift = 0`` and at ``lift = 79.65`` mm.
    setup : RigSetup
    """

    heights: tuple[BlockHeight, BlockHeight]
    setup: RigSetup

    @property
    def true_lift_mm(self) -> float:
        return self.heights[1].lift_mm - self.heights[0].lift_mm

    @property
    def measured_lift_mm(self) -> float:
        """Mean Z at the first height minus mean Z at the second."""
        return self.heights[0].mean_z - self.heights[1].mean_z

    @property
    def max_abs_z_error(self) -> float:
        return max(h.max_abs_z_error for h in self.heights)

    @property
    def all_within_bound(self) -> bool:
        return all(bool(h.within_bound.all()) for h in self.heights)

    @property
    def max_width_error(self) -> float:
        return max(float(np.max(np.abs(h.lines["width"] - h.true_width_mm)))
                   for h in self.heights)


def _block_height(sim: SimulatedCapture, located: Located, lift_mm: float,
                  table_lines: int) -> BlockHeight:
    g: EpipolarGeometry = located.geometry
    box = next(p for p in sim.scene.primitives if isinstance(p, Box))
    corners = box.corners()
    top = corners[corners[:, 2] == corners[:, 2].max()]
    epi = g.from_world(top)  # (4, 3) top-face corners in the epipolar frame
    true_z = float(np.mean(epi[:, 2]))
    xs = np.sort(epi[:, 0])
    x_true = (float(xs[:2].mean()), float(xs[2:].mean()))
    cam = g.camera
    cx, cy = cam.principal_point
    rows_end = np.sort(cy + cam.fy * epi[:, 1] / epi[:, 2])
    r0, r1 = float(rows_end[:2].mean()), float(rows_end[2:].mean())
    col_true = [cx + cam.fx * (x + g.baseline_mm / 2) / true_z for x in x_true]
    m = len(located)
    side = np.zeros(m, np.int8)
    inside = (located.row >= r0 + 3) & (located.row <= r1 - 3)
    for s, c in zip((-1, 1), col_true, strict=True):
        side[inside & (np.abs(located.x_left - c) < 2.0)] = s
    xyz = located.epipolar_xyz
    z_err = np.where(side != 0, xyz[:, 2] - true_z, np.nan)
    x_ref = np.where(side < 0, x_true[0], x_true[1])
    x_err = np.where(side != 0, xyz[:, 0] - x_ref, np.nan)
    # per line: rows with exactly one left and one right block edge point
    rows_l = located.row[side < 0]
    rows_r = located.row[side > 0]
    both = np.intersect1d(rows_l, rows_r)
    if table_lines > 0 and both.size > table_lines:
        pick = np.rint(np.linspace(0, both.size - 1, table_lines)).astype(int)
        both = both[pick]
    il = np.array([np.nonzero((side < 0) & (located.row == r))[0][0] for r in both], int)
    ir = np.array([np.nonzero((side > 0) & (located.row == r))[0][0] for r in both], int)
    il = il.reshape(-1)
    ir = ir.reshape(-1)
    lines = {
        "row": both.astype(np.intp),
        "x": xyz[il, 0], "y": xyz[il, 1], "z": xyz[il, 2],
        "x2": xyz[ir, 0], "y2": xyz[ir, 1], "z2": xyz[ir, 2],
        "width": xyz[ir, 0] - xyz[il, 0],
        "z_bound": located.z_bound[il], "z2_bound": located.z_bound[ir],
    }
    return BlockHeight(lift_mm=float(lift_mm), located=located, true_depth_mm=true_z,
                       true_x_mm=x_true, true_rows=(r0, r1), side=side, z_error=z_err,
                       x_error=x_err, lines=lines)


def run_block_experiment(
    *,
    setup: RigSetup | None = None,
    lifts_mm: Sequence[float] = (0.0, SEED_LIFT_MM),
    params: LocateParameters | None = None,
    seed: int = 0,
    table_lines: int = 13,
) -> BlockExperiment:
    """The seed's accuracy test (5.2, table 5-1) on the simulated robot.

    Parameters
    ----------
    setup : RigSetup, optional
    lifts_mm : pair of float
        Heights of the two data sets (the block's top raised by each).
    params : LocateParameters, optional
        Default: robostereo's matcher on every row, sub-pixel edges.
    seed : int
        Sensor-noise seed.
    table_lines : int
        Number of epipolar lines, evenly spread over the block, in the table (the seed:
        13); the accuracy figures use every matched block edge point.

    Returns
    -------
    BlockExperiment

    Notes
    -----
    For each height: :func:`simulate_capture`, :func:`robostereo.robot.capture.locate`, then
    the block's left and right top edges are found among the located points by their
    rectified column (within 2 px of the projected true edge, 3 rows inside the ends),
    and compared with the true top-face geometry.

    References
    ----------
    Seed 5.2, table 5-1, eq. (6)-(9).
    """
    lifts = tuple(float(v) for v in lifts_mm)
    if len(lifts) != 2:
        raise InputError(f"lifts_mm must be two heights, got {lifts_mm}")
    out = []
    for lift in lifts:
        sim = simulate_capture("block", setup=setup, lift_mm=lift, seed=seed)
        out.append(_block_height(sim, locate(sim.capture, params=params or SEED_EXPERIMENT),
                                 lift, table_lines))
    return BlockExperiment(heights=(out[0], out[1]), setup=sim.setup)


# ------------------------------------------------------------------------------ pulley


@dataclass(frozen=True)
class PulleyExperiment:
    """The effectiveness test of seed 5.1 on the hub-pulley.

    Attributes
    ----------
    located : Located
    gt_disparity : ndarray, shape (H, W)
        Ground-truth disparity of the rectified left image, ``fx D / depth``, NaN where
        unknown (no surface, or outside the grabbed image).
    n_left_edges, n_right_edges : int
        Edge points (away from the fill) in the rectified images.
    scores : tuple of MatchScore
        Against the ground truth after 0, 1, ... iterations (evaluation rule of
        :func:`robostereo.evaluation.score_matches`).
    default_score : MatchScore or None
        robostereo's default matcher (the window method) on the same capture.
    """

    located: Located
    gt_disparity: NDArray[np.float64]
    n_left_edges: int
    n_right_edges: int
    scores: tuple[MatchScore, ...]
    setup: RigSetup
    default_score: MatchScore | None = None

    @property
    def final(self) -> MatchScore:
        return self.scores[-1]


def run_pulley_experiment(
    *, setup: RigSetup | None = None, params: LocateParameters | None = None, seed: int = 0
) -> PulleyExperiment:
    """The seed's hub-pulley test (5.1): % matched and % false after every iteration.

    Notes
    -----
    1. :func:`simulate_capture` of the pulley and :func:`robostereo.robot.capture.locate`.
    2. Ground truth: the left rendering's depth rectified with the left view's theta
       (nearest neighbour; a rotation about the optical axis keeps depth), as
       disparity ``fx D / depth``.
    3. For ``k = 0 .. iterations``: the matches accepted after ``k`` iterations, scored
       with :func:`robostereo.evaluation.score_matches` over the left edge points (none
       near the rectification's fill: the matcher is told which pixels are filled).

    References
    ----------
    Seed 5.1 (818 / 815 edges, 86% matched, 1.65% false after five iterations).
    """
    sim = simulate_capture("pulley", setup=setup, seed=seed)
    loc = locate(sim.capture, params=params or SEED_EXPERIMENT)
    g = loc.geometry
    depth = sim.renderings[0].depth.copy()
    depth[~np.isfinite(depth)] = 0.0
    rd = g.rectify(depth, "left", interpolation="nearest", fill_value=0.0)
    with np.errstate(divide="ignore"):
        gt = np.where(rd > 0, g.camera.fx * g.baseline_mm / rd, np.nan)
    res = loc.result
    el = res.left_edges
    if res.relaxation is not None:
        scores = [score_matches(el.row, el.x, res.disparity_of(loc.matches_after(k)), gt)
                  for k in range(len(res.relaxation.history))]
    else:  # the window matcher has no iterations: its accepted matches
        scores = [score_matches(el.row, el.x, res.accepted_disparity(), gt)]
    default = locate(sim.capture, params=replace(params or SEED_EXPERIMENT,
                                                 match=MatchParameters()))
    dr = default.result
    default_score = score_matches(dr.left_edges.row, dr.left_edges.x, dr.accepted_disparity(),
                                  gt)
    return PulleyExperiment(located=loc, gt_disparity=gt, n_left_edges=len(el),
                            n_right_edges=len(res.right_edges), scores=tuple(scores),
                            setup=sim.setup, default_score=default_score)


# -------------------------------------------------------------------------------- demo


@dataclass(frozen=True)
class DemoResult:
    """Both experiments and how long they took (seconds)."""

    block: BlockExperiment
    pulley: PulleyExperiment
    timings: dict[str, float] = field(default_factory=dict)


def run_demo(*, setup: RigSetup | None = None, seed: int = 0) -> DemoResult:
    """Run the block and the hub-pulley experiments as ``robostereo demo`` does."""
    t0 = time.perf_counter()
    block = run_block_experiment(setup=setup, seed=seed)
    t1 = time.perf_counter()
    pulley = run_pulley_experiment(setup=setup, seed=seed)
    t2 = time.perf_counter()
    return DemoResult(block=block, pulley=pulley,
                      timings={"block": t1 - t0, "pulley": t2 - t1, "total": t2 - t0})


def print_demo_report(result: DemoResult, console: Any = None) -> None:
    """Print table 5-1 and the hub-pulley figures as rich tables."""
    from rich.console import Console
    from rich.table import Table

    con = console or Console()
    b = result.block
    for h, tag in zip(b.heights, "ab", strict=True):
        t = Table(title=f"Table 5-1({tag}): block, lift {h.lift_mm:g} mm "
                        f"(true depth {h.true_depth_mm:.2f} mm, width {h.true_width_mm:.2f} mm)")
        for c in ("k", "row", "x", "y", "z", "x'", "y'", "z'", "width", "bound z"):
            t.add_column(c, justify="right")
        ln = h.lines
        for i in range(ln["row"].shape[0]):
            t.add_row(str(i + 1), str(int(ln["row"][i])),
                      *(f"{ln[c][i]:.1f}" for c in ("x", "y", "z", "x2", "y2", "z2")),
                      f"{ln['width'][i]:.2f}", f"{ln['z_bound'][i]:.1f}")
        con.print(t)
        con.print(f"  mean z {h.mean_z:.2f} mm over {int(h.block_points.sum())} block edge "
                  f"points; largest |z error| {h.max_abs_z_error:.2f} mm; all within the "
                  f"eq. 9 bound: {bool(h.within_bound.all())}")
    s = Table(title="Block accuracy (seed: lift 79.65 mm, largest |z error| 28 mm vs 41 mm)")
    for c in ("quantity", "measured", "target"):
        s.add_column(c)
    bounds = np.concatenate([h.located.z_bound[h.block_points] for h in b.heights])
    s.add_row("measured lift", f"{b.measured_lift_mm:.2f} mm",
              f"{b.true_lift_mm:.2f} mm +- 1 mm")
    s.add_row("largest |z error|", f"{b.max_abs_z_error:.2f} mm",
              f"<= 5 mm and <= its eq. 9 bound ({bounds.min():.1f}..{bounds.max():.1f} mm)")
    s.add_row("points within bound", str(b.all_within_bound), "all")
    s.add_row("largest |width error|", f"{b.max_width_error:.2f} mm", "<= 0.5 mm")
    con.print(s)
    p = result.pulley
    t = Table(title=f"Hub-pulley: {p.n_left_edges} edges left, {p.n_right_edges} right "
                    "(seed: 818 / 815; 86% matched, 1.65% false)")
    for c in ("iteration", "counted", "matched", "% matched", "false", "% false"):
        t.add_column(c, justify="right")
    for k, sc in enumerate(p.scores):
        t.add_row(str(k), str(sc.counted), str(sc.matched), f"{100 * sc.matched_fraction:.1f}",
                  str(sc.false), f"{100 * sc.false_fraction:.2f}")
    if p.default_score is not None:
        sc = p.default_score
        t.add_row("window", str(sc.counted), str(sc.matched), f"{100 * sc.matched_fraction:.1f}",
                  str(sc.false), f"{100 * sc.false_fraction:.2f}")
    con.print(t)
    con.print("  iterations 0..: the seed's relaxation; window: robostereo's default matcher")
    tm = result.timings
    if tm:
        con.print(f"time: block {tm.get('block', 0):.1f} s, pulley {tm.get('pulley', 0):.1f} s, "
                  f"total {tm.get('total', 0):.1f} s")


def save_demo_figures(result: DemoResult, out_dir: str | Path) -> list[Path]:
    """Write the demo's figures (PNG) into `out_dir`; returns their paths.

    * ``block_iterations.png`` and ``pulley_iterations.png``: matched points over the
      rectified left image after 0, 1, 3 and 5 iterations (seed figure 4-4, 5-2),
      coloured by disparity;
    * ``points_3d.png``: the located points in the world frame (block at both heights,
      hub-pulley).

    All figures are drawn first and written together: all three files or none.
    """
    from matplotlib.figure import Figure

    from robostereo.io import atomic_outputs
    from robostereo.plots import plot_matches, plot_points_3d

    out = Path(out_dir)
    if not out.is_dir():
        raise InputError(f"{out}: output folder does not exist")
    figures: dict[str, Any] = {}
    panels = (("block", result.block.heights[0].located), ("pulley", result.pulley.located))
    for name, loc in panels:
        fig = Figure(figsize=(13, 3.6))
        res = loc.result
        its = [k for k in (0, 1, 3, 5) if k < len(res.relaxation.history)]
        lo, hi = loc.disparity_range
        for i, k in enumerate(its):
            ax = fig.add_subplot(1, len(its), i + 1)
            m = loc.matches_after(k)
            ok = m >= 0
            d = res.disparity_of(m)[ok]
            plot_matches(ax, loc.rectified.left, res.left_edges.x[ok], res.left_edges.row[ok],
                         d, vmin=lo, vmax=hi, size=2.0, colorbar=False)
            ax.set_title(f"{name}, {k} iter.: {int(ok.sum())} matched", fontsize=9)
        if fig.axes and fig.axes[-1].collections:
            fig.colorbar(fig.axes[-1].collections[-1], ax=fig.axes, shrink=0.8,
                         label="disparity (px)")
        figures[f"{name}_iterations.png"] = fig
    fig = Figure(figsize=(11, 5))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    pts = np.concatenate([h.located.world[h.block_points] for h in result.block.heights])
    plot_points_3d(ax, pts)
    ax.set_title("block edge points, two heights (world mm)", fontsize=9)
    ax = fig.add_subplot(1, 2, 2, projection="3d")
    plot_points_3d(ax, result.pulley.located.world)
    ax.set_title("hub-pulley points (world mm)", fontsize=9)
    figures["points_3d.png"] = fig
    paths = {name: out / name for name in figures}
    with atomic_outputs(paths) as tmp:
        for name, f in figures.items():
            f.savefig(tmp[name], format="png", dpi=110, bbox_inches="tight")
    return list(paths.values())
