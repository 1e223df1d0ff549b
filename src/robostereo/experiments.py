"""The thesis's experiments on the simulated AdeptOne (the thesis, chapters 4-5).

The application layer over the simulated rig of :mod:`robostereo.robot.simulated.scara_rig`
(:class:`RigSetup`, :func:`simulate_capture`, re-exported here):

* :func:`run_block_experiment`: the accuracy test of 5.2 (table 5-1): the precision
  block at two heights 79.65 mm apart; per epipolar line the block's left and right
  edge points, the width, the mean depth per height, the measured lift and every
  point's depth error against its eq. (9) bound.
* :func:`run_pulley_experiment`: the effectiveness test of 5.1: the hub-pulley's edge
  points, and % matched and % false against the rendered ground truth after every
  relaxation iteration.
* :func:`run_demo`: both, as ``robostereo demo`` runs them; :func:`save_demo_figures`
  and :func:`print_demo_report` show them.
* :func:`run_views_demo`: the block (two heights) and the hub-pulley from N views in a
  pattern, SCARA or six-axis, as a summary.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.evaluation import MatchScore, score_matches
from robostereo.geometry.scara_rectification import EpipolarGeometry
from robostereo.matcher.parameters import MatchParameters
from robostereo.robot.capture import Located, LocateParameters, locate
from robostereo.robot.simulated.grab_views import simulate_views
from robostereo.robot.simulated.scara_rig import (
    SEED_LIFT_MM,
    RigSetup,
    SimulatedCapture,
    block_scene,
    pulley_scene,
    simulate_capture,
)
from robostereo.robot.simulated.views_truth import (
    views_block_truth,
    views_outline_coverage,
    views_pulley_score,
)
from robostereo.robot.views.locating import locate_views
from robostereo.robot.views.views_parameters import ViewsParameters
from robostereo.simulation import Box

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
    "run_views_demo",
    "save_demo_figures",
    "simulate_capture",
]

#: the experiments' matcher: the thesis's, relaxation on connectivity (with robostereo's
#: sub-pixel edges), so that the figures follow the thesis's iterations (fig. 4-4)
SEED_EXPERIMENT = LocateParameters(match=MatchParameters(method="relaxation"))


# ------------------------------------------------------------------------------- block


@dataclass(frozen=True)
class BlockHeight:
    """One data set of the block test (one half of table 5-1).

    Attributes
    ----------
    lift_mm : float
    located : Located
        Everything :func:`robostereo.robot.capture.locate_pair.locate` found.
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
    """The accuracy test of the thesis, 5.2: the block at two heights.

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
    """The thesis's accuracy test (5.2, table 5-1) on the simulated robot.

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
        Number of epipolar lines, evenly spread over the block, in the table (the thesis:
        13); the accuracy figures use every matched block edge point.

    Returns
    -------
    BlockExperiment

    Notes
    -----
    For each height: :func:`simulate_capture`,
    :func:`robostereo.robot.capture.locate_pair.locate`, then
    the block's left and right top edges are found among the located points by their
    rectified column (within 2 px of the projected true edge, 3 rows inside the ends),
    and compared with the true top-face geometry.

    References
    ----------
    Kim (1989), the thesis, 5.2, table 5-1, eq. (6)-(9).
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
    """The effectiveness test of the thesis, 5.1, on the hub-pulley.

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
        :func:`robostereo.evaluation.scorer.score_matches`).
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
    """The thesis's hub-pulley test (5.1): % matched and % false after every iteration.

    Notes
    -----
    1. :func:`simulate_capture` of the pulley and
       :func:`robostereo.robot.capture.locate_pair.locate`.
    2. Ground truth: the left rendering's depth rectified with the left view's theta
       (nearest neighbour; a rotation about the optical axis keeps depth), as
       disparity ``fx D / depth``.
    3. For ``k = 0 .. iterations``: the matches accepted after ``k`` iterations, scored
       with :func:`robostereo.evaluation.scorer.score_matches` over the left edge points (none
       near the rectification's fill: the matcher is told which pixels are filled).

    References
    ----------
    Kim (1989), the thesis, 5.1 (818 / 815 edges, 86% matched, 1.65% false after five iterations).
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
    s = Table(title="Block accuracy (thesis: lift 79.65 mm, largest |z error| 28 mm vs 41 mm)")
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
                    "(thesis: 818 / 815; 86% matched, 1.65% false)")
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
    con.print("  iterations 0..: the thesis's relaxation; window: robostereo's default matcher")
    tm = result.timings
    if tm:
        con.print(f"time: block {tm.get('block', 0):.1f} s, pulley {tm.get('pulley', 0):.1f} s, "
                  f"total {tm.get('total', 0):.1f} s")


def save_demo_figures(result: DemoResult, out_dir: str | Path) -> list[Path]:
    """Write the demo's figures (PNG) into `out_dir`; returns their paths.

    * ``block_iterations.png`` and ``pulley_iterations.png``: matched points over the
      rectified left image after 0, 1, 3 and 5 iterations (the thesis's figures 4-4, 5-2),
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


# --------------------------------------------------------------------------- N views


def run_views_demo(*, count: int = 5, pattern: str = "line", span_mm: float = 80.0,
                   robot: str = "scara", seed: int = 0,
                   params: ViewsParameters | None = None) -> dict[str, Any]:
    """The block (two heights) and the hub-pulley located from N views, as a summary.

    Parameters
    ----------
    count, pattern, span_mm, robot, seed
        :func:`~robostereo.robot.simulated.grab_views.simulate_views`'s.
    params : ViewsParameters, optional
        :func:`~robostereo.robot.views.locating.locate_views`'s.

    Returns
    -------
    dict
        ``views``, ``pattern``, ``span_mm``, ``robot``; ``lift_mm`` (mean located height of
        the block's top outline points, second height minus first), ``lift_true_mm``;
        ``max_abs_error_mm`` (largest depth error of the top outline points over both
        heights, against the truth), ``max_abs_error_long_edges_mm`` (the long edges
        only, as the two-view demo measures), ``bound_at_max_error_mm``,
        ``all_within_bound``, ``median_bound_mm``, ``block_points``; ``outline_coverage``
        (:func:`views_outline_coverage`, first height); ``pulley_matched``,
        ``pulley_false``, ``pulley_matched_all_edges`` (:func:`views_pulley_score`, of
        the points `locate_views` reports: those whose confidence reaches
        ``params.min_confidence``), ``pulley_points``;
        ``locate_seconds`` (the three locates) and ``seconds`` (everything).

    Notes
    -----
    1. For lifts 0 and 79.65 mm: :func:`simulate_views` of the block,
       :func:`~robostereo.robot.views.locating.locate_views`, :func:`views_block_truth`.
    2. The hub-pulley the same way, :func:`views_pulley_score`.

    References
    ----------
    Kim (1989), the thesis, 5.1, 5.2 (table 5-1), 3.7 (eq. 9).
    """
    t0 = time.perf_counter()
    t_loc = 0.0
    tops, errs, bounds, longs, cover = [], [], [], [], 0.0
    for lift in (0.0, SEED_LIFT_MM):
        sim = simulate_views("block", count=count, pattern=pattern,  # type: ignore[arg-type]
                             span_mm=span_mm, robot=robot, lift_mm=lift,  # type: ignore[arg-type]
                             seed=seed)
        t = time.perf_counter()
        loc = locate_views(sim.capture, params=params)
        t_loc += time.perf_counter() - t
        on, err, edge = views_block_truth(sim, loc)
        if not on.any():
            raise InputError(f"views demo: no located point on the block's top at lift {lift}")
        tops.append(float(loc.world[on, 2].mean()))
        errs.append(err[on])
        bounds.append(loc.bound_mm[on])
        longs.append(err[on & (edge == 1)])
        if lift == 0.0:
            cover = views_outline_coverage(sim, loc)
    pul = simulate_views("pulley", count=count, pattern=pattern,  # type: ignore[arg-type]
                         span_mm=span_mm, robot=robot, seed=seed)  # type: ignore[arg-type]
    t = time.perf_counter()
    ploc = locate_views(pul.capture, params=params)
    t_loc += time.perf_counter() - t
    matched, false, matched_all = views_pulley_score(pul, ploc)
    e, b = np.concatenate(errs), np.concatenate(bounds)
    worst = int(np.argmax(np.abs(e)))
    el = np.concatenate(longs)
    return {
        "views": int(count), "pattern": pattern, "span_mm": float(span_mm), "robot": robot,
        "lift_mm": round(tops[1] - tops[0], 4), "lift_true_mm": SEED_LIFT_MM,
        "max_abs_error_mm": round(float(np.abs(e).max()), 4),
        "max_abs_error_long_edges_mm": round(float(np.abs(el).max()), 4) if len(el) else None,
        "bound_at_max_error_mm": round(float(b[worst]), 4),
        "all_within_bound": bool(np.all(np.abs(e) <= b)),
        "median_bound_mm": round(float(np.median(b)), 4),
        "block_points": [len(x) for x in errs],
        "outline_coverage": round(cover, 4),
        "pulley_matched": round(matched, 4), "pulley_false": round(false, 4),
        "pulley_matched_all_edges": round(matched_all, 4),
        "pulley_points": len(ploc),
        "locate_seconds": round(t_loc, 3),
        "seconds": round(time.perf_counter() - t0, 3),
    }
