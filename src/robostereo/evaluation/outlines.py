"""Object outlines measured fairly: figures near and away from depth steps.

The figures that :func:`robostereo.evaluation.scorer.evaluate_scene` adds to a scene's
evaluation (:class:`OutlineFigures`), by both scoring rules of
:mod:`robostereo.evaluation.rules` (the project's and the silhouette rule), each split
between edge points *near a depth step* (within 4 px, a 9 x 9 neighbourhood, of a
ground-truth disparity jump of more than 2 px between known 4-neighbours) and *away*:

* % matched and % false of each method at its default point, and the coverage its
  curve reaches at <= 1.65, 2 and 3 % false (:data:`OUTLINE_LEVELS`);
* the expected calibration error of robostereo's confidence (ten equal-width bins;
  :func:`~robostereo.evaluation.rules.expected_calibration_error`) over its best match
  of every counted edge point;
* with a calibration, the 3-D distance from each located point to the ground-truth
  surface (:func:`surface_distances`), median and 95th percentile in mm;
* the silhouette offsets (:func:`silhouette_offsets`): how far the edges matched with
  the nearer surface's disparity lie from the ground truth's boundary
  (:func:`boundary_offsets`: how far every edge point near a boundary lies from it,
  the edge localisation alone);
* near steps, the same over the edge points visible in both views and why the points
  not accepted are missing (:mod:`robostereo.evaluation.visibility`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_nonnegative
from robostereo.evaluation.rules import (
    RULES,
    CoverageCurve,
    MatchScore,
    coverage_curve,
    depth_step_mask,
    expected_calibration_error,
    near_steps,
    rule_errors,
    score_matches,
)
from robostereo.evaluation.visibility import (
    VisibilityFigures,
    format_visibility_figures,
    left_visibility,
    visibility_figures,
)
from robostereo.geometry.triangulation import StereoCamera, triangulate

__all__ = [
    "OUTLINE_LEVELS",
    "MethodPoints",
    "OffsetSummary",
    "OutlineFigures",
    "RowBoundaries",
    "SplitFigures",
    "boundary_offsets",
    "format_outline_figures",
    "outline_figures",
    "row_boundaries",
    "settings_curve",
    "silhouette_offsets",
    "surface_distances",
]

#: the false rates at which the near/away curves are compared
OUTLINE_LEVELS: tuple[float, ...] = (0.0165, 0.02, 0.03)


@dataclass(frozen=True)
class RowBoundaries:
    """Where the ground truth's surfaces end along rows (silhouette boundaries).

    Attributes
    ----------
    rows : ndarray of int, shape (M,)
    x : ndarray of float, shape (M,)
        Sub-pixel column of each boundary.
    near_side : ndarray of int, shape (M,)
        +1 when the nearer surface (larger disparity) is to the boundary's right,
        -1 when to its left.
    near_disparity : ndarray of float, shape (M,)
        The nearer surface's disparity at the boundary.
    """

    rows: NDArray[np.intp]
    x: NDArray[np.float64]
    near_side: NDArray[np.intp]
    near_disparity: NDArray[np.float64]

    def __post_init__(self) -> None:
        shapes = {np.shape(v) for v in (self.rows, self.x, self.near_side, self.near_disparity)}
        if len(shapes) != 1 or np.ndim(self.x) != 1:
            raise InputError(f"RowBoundaries arrays must be 1-D of one length, got {shapes}")


def row_boundaries(gt_disparity: ArrayLike, *, step: float = 2.0) -> RowBoundaries:
    """The boundaries of a ground-truth map: between horizontal neighbours whose known
    disparities differ by more than ``step`` px, at ``x = j + 0.5``.

    >>> b = row_boundaries(np.array([[4.0, 4.0, 9.0, 9.0, np.nan, 3.0]]))
    >>> b.x.tolist(), b.near_side.tolist(), b.near_disparity.tolist()
    ([1.5], [1], [9.0])
    """
    g = np.asarray(gt_disparity, dtype=float)
    if g.ndim != 2:
        raise InputError(f"gt_disparity must be an (H, W) map, got shape {g.shape}")
    require_nonnegative("step", step)
    g = np.where(np.isfinite(g), g, np.nan)
    a, b = g[:, :-1], g[:, 1:]
    with np.errstate(invalid="ignore"):
        r, j = np.nonzero(np.abs(b - a) > step)
    right_nearer = b[r, j] > a[r, j]
    return RowBoundaries(rows=r.astype(np.intp), x=j + 0.5,
                         near_side=np.where(right_nearer, 1, -1).astype(np.intp),
                         near_disparity=np.where(right_nearer, b[r, j], a[r, j]))


def boundary_offsets(
    rows: ArrayLike, x: ArrayLike, boundaries: RowBoundaries, *, reach: float = 1.5,
) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.intp]]:
    """Signed offsets of edge points from the nearest boundary of their row, whatever
    their match: how well the edge localisation finds outlines.

    Parameters
    ----------
    rows, x : array_like, shape (N,)
        Edge points (image row, sub-pixel column).
    boundaries : RowBoundaries
        Exact (a synthetic scene's) or from the ground truth (:func:`row_boundaries`).
    reach : float
        Pixels: only points this close to a boundary of their row count (1.5: the
        boundary's own edge, not the texture beside it).

    Returns
    -------
    index : ndarray of int, shape (M,)
        The points among the N within ``reach`` of a boundary of their row.
    offset : ndarray, shape (M,)
        ``x`` minus the nearest boundary's ``x``, signed so that positive is towards
        the farther surface (the edge lies outside the object), pixels.
    boundary : ndarray of int, shape (M,)
        Index of that boundary in ``boundaries``.

    Examples
    --------
    >>> b = RowBoundaries(np.array([0, 0]), np.array([10.0, 20.0]), np.array([1, -1]),
    ...                   np.array([9.0, 9.0]))
    >>> i, off, k = boundary_offsets([0, 0, 0, 1], [9.6, 20.3, 15.0, 10.0], b)
    >>> i.tolist(), off.round(2).tolist(), k.tolist()
    ([0, 1], [0.4, 0.3], [0, 1])
    """
    r = np.asarray(rows, dtype=np.intp)
    xs = np.asarray(x, dtype=float)
    if not r.shape == xs.shape or r.ndim != 1:
        raise InputError(f"rows and x must be 1-D of one length, got {r.shape}, {xs.shape}")
    require_nonnegative("reach", reach)
    empty = (np.zeros(0, dtype=np.intp), np.zeros(0), np.zeros(0, dtype=np.intp))
    if boundaries.x.size == 0 or r.size == 0:
        return empty
    span = float(max(np.max(np.abs(boundaries.x)), np.max(np.abs(xs)))) * 2 + 4 * reach + 10
    key_b = boundaries.rows * span + boundaries.x
    order = np.argsort(key_b, kind="stable")
    key_b = key_b[order]
    key_p = r * span + xs
    i = np.searchsorted(key_b, key_p)
    cand = np.stack([np.clip(i - 1, 0, key_b.size - 1), np.clip(i, 0, key_b.size - 1)], 1)
    dist = np.abs(key_b[cand] - key_p[:, None])
    nearest = order[cand[np.arange(r.size), np.argmin(dist, axis=1)]]
    dx = xs - boundaries.x[nearest]
    idx = np.nonzero((boundaries.rows[nearest] == r) & (np.abs(dx) <= reach))[0]
    return idx, -dx[idx] * boundaries.near_side[nearest[idx]], nearest[idx]


def silhouette_offsets(
    rows: ArrayLike, x: ArrayLike, disparity: ArrayLike, boundaries: RowBoundaries, *,
    reach: float = 4.0, tolerance: float = 1.0,
) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """Signed offsets of silhouette edges from the true boundary.

    An edge point is on a silhouette when a boundary of its row lies within ``reach``
    px (4: the near-step distance) and its disparity is within ``tolerance`` of that
    boundary's nearer surface (it was matched as the occluding contour).

    Parameters
    ----------
    rows, x, disparity : array_like, shape (N,)
        Edge points and their disparities (NaN where unmatched).
    boundaries : RowBoundaries
        Exact (a synthetic scene's) or from the ground truth (:func:`row_boundaries`).
    reach, tolerance : float
        Pixels.

    Returns
    -------
    index : ndarray of int, shape (M,)
        The silhouette points among the N.
    offset : ndarray, shape (M,)
        ``x`` minus the nearest boundary's ``x``, signed so that positive is towards
        the farther surface (the edge lies outside the object), pixels.

    Notes
    -----
    The offsets of the *accepted* silhouette matches mix two things: where the edge
    localisation puts outlines (:func:`boundary_offsets`, every edge point) and which
    of those edges the matcher accepts with the nearer surface's disparity.

    Examples
    --------
    >>> b = RowBoundaries(np.array([0]), np.array([10.0]), np.array([1]), np.array([9.0]))
    >>> silhouette_offsets([0, 0, 0], [9.6, 11.0, 10.2], [9.3, 4.0, np.nan], b)
    (array([0]), array([0.4]))
    """
    r = np.asarray(rows, dtype=np.intp)
    xs = np.asarray(x, dtype=float)
    d = np.asarray(disparity, dtype=float)
    if not r.shape == xs.shape == d.shape or r.ndim != 1:
        raise InputError(f"rows, x and disparity must be 1-D of one length, got {r.shape}, "
                         f"{xs.shape}, {d.shape}")
    require_nonnegative("tolerance", tolerance)
    idx, off, nearest = boundary_offsets(r, xs, boundaries, reach=reach)
    with np.errstate(invalid="ignore"):
        on = np.abs(d[idx] - boundaries.near_disparity[nearest]) <= tolerance
    return idx[on], off[on]


@dataclass(frozen=True)
class OffsetSummary:
    """Silhouette offsets in brief: count, median ``|offset|`` (px), fraction over 1 px."""

    count: int
    median_abs_px: float
    over_1px: float

    def __post_init__(self) -> None:
        if self.count < 0 or not (math.isnan(self.over_1px) or 0 <= self.over_1px <= 1):
            raise InputError(f"OffsetSummary needs count >= 0 and over_1px in 0..1, got "
                             f"{self.count}, {self.over_1px}")

    @classmethod
    def of(cls, offsets: ArrayLike) -> OffsetSummary:
        """>>> OffsetSummary.of([0.2, -0.5, 1.5, 0.1])
        OffsetSummary(count=4, median_abs_px=0.35, over_1px=0.25)
        """
        o = np.abs(np.asarray(offsets, dtype=float))
        if o.size == 0:
            return cls(0, math.nan, math.nan)
        return cls(int(o.size), float(np.median(o)), float(np.mean(o > 1.0)))


def surface_distances(
    camera: StereoCamera, rows: ArrayLike, x: ArrayLike, disparity: ArrayLike,
    gt_disparity: ArrayLike,
) -> NDArray[np.float64]:
    """Distance (mm) from each located point to the ground-truth surface.

    Parameters
    ----------
    camera : StereoCamera
        The rectified pair's camera (e.g. of a Middlebury ``calib.txt``).
    rows, x, disparity : array_like, shape (N,)
        Edge points and their disparities (NaN where unmatched).
    gt_disparity : array_like, shape (H, W)
        Ground truth, NaN where unknown.

    Returns
    -------
    ndarray, shape (N,)
        NaN where unmatched.

    Notes
    -----
    1. Every known pixel ``(j, i)`` of the ground truth is triangulated with
       ``x_right = j - gt`` (:func:`~robostereo.geometry.triangulation.triangulate`,
       the thesis's eq. 9 path): the ground-truth surface as a point cloud.
    2. Each located point is triangulated the same way from ``(x, row, d)`` and its
       distance to the nearest cloud point is found with a k-d tree
       (:class:`scipy.spatial.cKDTree`).

    Examples
    --------
    A plane 10 m away (f = 1000 px, B = 100 mm, d = 10); a point found at d = 9 lies
    1111 mm behind it:

    >>> cam = StereoCamera(1000.0, 1000.0, 100.0, cx=5.0, cy=5.0)
    >>> surface_distances(cam, [5, 5], [5.0, 5.0], [10.0, 9.0], np.full((11, 11), 10.0)
    ...                   ).round(0).tolist()
    [0.0, 1111.0]
    """
    from scipy.spatial import cKDTree

    g = np.asarray(gt_disparity, dtype=float)
    i, j = np.nonzero(np.isfinite(g))
    ref, _ = triangulate(camera, j.astype(float), j - g[i, j], i.astype(float), g.shape)
    ref = ref[np.isfinite(ref).all(axis=1)]
    xs = np.asarray(x, dtype=float)
    d = np.asarray(disparity, dtype=float)
    out = np.full(xs.shape, np.nan)
    if ref.size == 0:
        return out
    p, _ = triangulate(camera, xs, xs - d, np.asarray(rows, dtype=float), g.shape)
    ok = np.isfinite(p).all(axis=1)
    out[ok] = cKDTree(ref).query(p[ok])[0]
    return out


def settings_curve(
    samples: Sequence[ArrayLike], labels: Sequence[float], rows: ArrayLike, x: ArrayLike,
    gt_disparity: ArrayLike, *, tolerance: float = 1.0, rule: str = "project",
    subset: ArrayLike | None = None,
) -> CoverageCurve:
    """The curve of a matcher run at several settings: one point per setting.

    ``samples[k]`` holds the disparities (NaN where none) the ``k``-th setting gave the
    edge points; ``labels[k]`` goes to ``threshold``.  Points are sorted by coverage.

    >>> gt = np.full((1, 4), 5.0)
    >>> c = settings_curve([[5.0, 9.0, np.nan], [5.0, np.nan, np.nan]], [0, 10],
    ...                    [0, 0, 0], [1.0, 2.0, 3.0], gt)
    >>> c.coverage.round(2).tolist(), c.false_rate.tolist(), c.threshold.tolist()
    ([0.33, 0.67], [0.0, 0.5], [10.0, 0.0])
    """
    pts = []
    for d, label in zip(samples, labels, strict=True):
        s = score_matches(rows, x, d, gt_disparity, tolerance=tolerance, rule=rule,
                          subset=subset)
        pts.append((s.matched_fraction, s.false_fraction, float(label)))
    pts.sort()
    a = np.array(pts, dtype=float).reshape(-1, 3)
    return CoverageCurve(coverage=a[:, 0], false_rate=a[:, 1], threshold=a[:, 2])


@dataclass(frozen=True)
class SplitFigures:
    """One method's figures by one rule, near depth steps and away from them.

    Attributes
    ----------
    method, rule : str
    near, away : MatchScore
        The default operating point's score.
    ece_near, ece_away : float or None
        Expected calibration error of the confidence (None for a method without one).
    coverage_near, coverage_away : tuple of float
        Coverage of the curve at each false rate of :data:`OUTLINE_LEVELS` (empty
        without a curve).
    """

    method: str
    rule: str
    near: MatchScore
    away: MatchScore
    ece_near: float | None = None
    ece_away: float | None = None
    coverage_near: tuple[float, ...] = ()
    coverage_away: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        if self.rule not in RULES:
            raise InputError(f"rule must be one of {', '.join(RULES)}, got {self.rule!r}")

    def as_dict(self) -> dict[str, Any]:
        def side(s: MatchScore, ece: float | None, cov: tuple[float, ...]) -> dict[str, Any]:
            out: dict[str, Any] = {
                "counted": s.counted, "matched": s.matched, "false": s.false,
                "matched_percent": _clean(100 * s.matched_fraction),
                "false_percent": _clean(100 * s.false_fraction), "ece": _clean(ece)}
            if cov:
                out["coverage_at_false"] = {f"{100 * f:g}%": c
                                            for f, c in zip(OUTLINE_LEVELS, cov, strict=True)}
            return out

        return {"near": side(self.near, self.ece_near, self.coverage_near),
                "away": side(self.away, self.ece_away, self.coverage_away)}


def _clean(v: float | None) -> float | None:
    return None if v is None or not math.isfinite(v) else float(v)


@dataclass(frozen=True)
class OutlineFigures:
    """A scene's figures near and away from depth steps (see the module docstring).

    Attributes
    ----------
    near_points, away_points : int
        Counted edge points (known ground truth at the nearest pixel) near / away.
    split : tuple of SplitFigures
        Per method and rule.
    distances_mm : dict
        ``method -> {"near": (median, p95), "away": (median, p95)}`` of
        :func:`surface_distances` over the located points; empty without a calibration.
    offsets : dict of str to OffsetSummary
        Method name to its silhouette offsets against :func:`row_boundaries` (sparse
        matchers only: a dense one is read at their edge points).
    step_px, radius_px, connectivity : float, int, int
        The near-step definition used (2, 4, 4).
    visibility : VisibilityFigures or None
        Near steps over all edge points and over those visible in both views, and why
        points are not accepted (:mod:`robostereo.evaluation.visibility`).
    """

    near_points: int
    away_points: int
    split: tuple[SplitFigures, ...]
    distances_mm: dict[str, dict[str, tuple[float, float]]] = field(default_factory=dict)
    offsets: dict[str, OffsetSummary] = field(default_factory=dict)
    step_px: float = 2.0
    radius_px: int = 4
    connectivity: int = 4
    visibility: VisibilityFigures | None = None

    def figures(self, method: str, rule: str) -> SplitFigures:
        """The :class:`SplitFigures` of ``method`` by ``rule``."""
        for s in self.split:
            if s.method == method and s.rule == rule:
                return s
        raise InputError(f"no figures of method {method!r} by rule {rule!r}")

    def as_dict(self) -> dict[str, Any]:
        return {
            "definition": {"step_px": self.step_px, "radius_px": self.radius_px,
                           "connectivity": self.connectivity},
            "near_points": self.near_points, "away_points": self.away_points,
            "rules": {rule: {s.method: s.as_dict() for s in self.split if s.rule == rule}
                      for rule in RULES},
            "distance_3d_mm": {m: {k: {"median": _clean(v[0]), "p95": _clean(v[1])}
                                   for k, v in sides.items()}
                               for m, sides in self.distances_mm.items()},
            "silhouette_offsets": {m: {"count": o.count,
                                       "median_abs_px": _clean(o.median_abs_px),
                                       "over_1px": _clean(o.over_1px)}
                                   for m, o in self.offsets.items()},
            **({"visibility": self.visibility.as_dict()} if self.visibility is not None
               else {}),
        }  # fmt: skip


@dataclass(frozen=True)
class MethodPoints:
    """What :func:`outline_figures` needs of one method at the edge points.

    ``disparity`` is the default point's (NaN where refused); a sparse matcher adds its
    best match of every point and its confidence (``best``, ``confidence``), a dense one
    the disparities of its settings sweep (``sweep``, ``sweep_labels``).
    """

    method: str
    disparity: NDArray[np.float64]
    best: NDArray[np.float64] | None = None
    confidence: NDArray[np.float64] | None = None
    sweep: tuple[NDArray[np.float64], ...] = ()
    sweep_labels: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        n = np.shape(self.disparity)
        arrays = [a for a in (self.best, self.confidence, *self.sweep) if a is not None]
        if len(n) != 1 or any(np.shape(a) != n for a in arrays):
            raise InputError(f"MethodPoints {self.method!r}: disparity, best, confidence and "
                             f"sweep must be 1-D arrays of one length")
        if len(self.sweep) != len(self.sweep_labels):
            raise InputError(f"MethodPoints {self.method!r}: {len(self.sweep)} sweep runs but "
                             f"{len(self.sweep_labels)} labels")


def _percentiles(v: NDArray[np.float64]) -> tuple[float, float]:
    v = v[np.isfinite(v)]
    return (float(np.median(v)), float(np.percentile(v, 95))) if v.size else (math.nan,
                                                                            math.nan)


def outline_figures(
    rows: ArrayLike, x: ArrayLike, gt_disparity: ArrayLike, methods: Sequence[MethodPoints], *,
    camera: StereoCamera | None = None, tolerance: float = 1.0, step: float = 2.0,
    radius: int = 4, connectivity: int = 4, gt_right: ArrayLike | None = None,
    visibility: bool = True,
) -> OutlineFigures:
    """Every near/away figure of :class:`OutlineFigures` for methods at the same points.

    Parameters
    ----------
    rows, x : array_like, shape (N,)
        The edge points (the matcher's left edges).
    gt_disparity : array_like, shape (H, W)
    methods : sequence of MethodPoints
    camera : StereoCamera, optional
        With it, the 3-D distances to the ground-truth surface.
    tolerance, step, radius, connectivity
        The rules' tolerance and the near-step definition
        (:func:`~robostereo.evaluation.rules.depth_step_mask`).
    gt_right : array_like, shape (H, W), optional
        The right view's ground truth: the visibility's left-right cross-check.
    visibility : bool
        Also the figures over the edge points visible in both views
        (:func:`~robostereo.evaluation.visibility.visibility_figures`).

    Returns
    -------
    OutlineFigures
    """
    g = np.asarray(gt_disparity, dtype=float)
    r = np.asarray(rows, dtype=np.intp)
    xs = np.asarray(x, dtype=float)
    near = near_steps(r, xs, depth_step_mask(g, step=step, radius=radius,
                                             connectivity=connectivity))
    away = ~near
    split = []
    for m in methods:
        for rule in RULES:
            sn = score_matches(r, xs, m.disparity, g, tolerance=tolerance, rule=rule,
                               subset=near)
            sa = score_matches(r, xs, m.disparity, g, tolerance=tolerance, rule=rule,
                               subset=away)
            ece: list[float | None] = [None, None]
            cov: list[tuple[float, ...]] = [(), ()]
            for k, sub in enumerate((near, away)):
                if m.best is not None and m.confidence is not None:
                    known, err = rule_errors(r, xs, m.best, g, rule=rule)
                    t = known & np.isfinite(err) & np.isfinite(m.confidence) & sub
                    ece[k] = expected_calibration_error(m.confidence[t], err[t] <= tolerance)
                    c = coverage_curve(r, xs, m.best, m.confidence, g, tolerance=tolerance,
                                       rule=rule, subset=sub)
                elif m.sweep:
                    c = settings_curve(m.sweep, m.sweep_labels, r, xs, g, tolerance=tolerance,
                                       rule=rule, subset=sub)
                else:
                    continue
                cov[k] = tuple(c.coverage_at(f) for f in OUTLINE_LEVELS)
            split.append(SplitFigures(m.method, rule, sn, sa, ece[0], ece[1], cov[0], cov[1]))
    distances = {}
    if camera is not None:
        for m in methods:
            dist = surface_distances(camera, r, xs, m.disparity, g)
            distances[m.method] = {"near": _percentiles(dist[near]),
                                   "away": _percentiles(dist[away])}
    bounds = row_boundaries(g, step=step)
    offsets = {m.method: OffsetSummary.of(silhouette_offsets(
        r, xs, m.disparity, bounds, reach=float(radius), tolerance=tolerance)[1])
        for m in methods if m.best is not None}
    vf = None
    if visibility:
        vf = visibility_figures(r, xs, g, near, left_visibility(g, gt_right), methods,
                                levels=OUTLINE_LEVELS, tolerance=tolerance)
    s0 = split[0] if split else None
    return OutlineFigures(
        near_points=s0.near.counted if s0 else int(near.sum()),
        away_points=s0.away.counted if s0 else int(away.sum()), split=tuple(split),
        distances_mm=distances, offsets=offsets, step_px=step, radius_px=radius,
        connectivity=connectivity, visibility=vf)


def _f(v: float | None, fmt: str) -> str:
    return "-" if v is None or not math.isfinite(v) else format(v, fmt)


def _label(method: str) -> str:
    return "SGBM" if method == "sgbm" else method


def format_outline_figures(of: OutlineFigures) -> list[str]:
    """The near/away lines that ``robostereo evaluate`` adds to a scene's table."""
    lines = [
        f"  near depth steps (a known jump > {of.step_px:g} px to a {of.connectivity}-neighbour"
        f" within {of.radius_px} px): {of.near_points} points; away: {of.away_points}",
        "  rule        method        near: matched   false    ECE   away: matched   false"
        "    ECE",
    ]
    for s in of.split:
        sides = [f"{_f(100 * sc.matched_fraction, '13.1f')} % "
                 f"{_f(100 * sc.false_fraction, '5.2f')} % {_f(ece, '6.3f'):>6}"
                 for sc, ece in ((s.near, s.ece_near), (s.away, s.ece_away))]
        lines.append(f"  {s.rule:<11} {_label(s.method):<10}  {sides[0]}  {sides[1]}")
    levels = "".join(f"{'<=' + format(100 * f, 'g') + '%':>8s}" for f in OUTLINE_LEVELS)
    lines.append(f"  silhouette rule, coverage at  near{levels}    away{levels}")
    for s in of.split:
        if s.rule == "silhouette" and s.coverage_near:
            lines.append(f"  {_label(s.method):<34}" + "".join(
                f"{100 * c:7.1f}%" for c in s.coverage_near) + "        " + "".join(
                f"{100 * c:7.1f}%" for c in s.coverage_away))
    if of.distances_mm:
        lines.append("  3-D distance to the ground-truth surface, mm: near median / p95, "
                     "away median / p95")
        for m, sides in of.distances_mm.items():
            (nm, n95), (am, a95) = sides["near"], sides["away"]
            lines.append(f"  {_label(m):<10} {_f(nm, '10.2f')} / {_f(n95, '8.2f')}   "
                         f"{_f(am, '10.2f')} / {_f(a95, '8.2f')}")
    for m, o in of.offsets.items():
        lines.append(f"  silhouette offsets, {_label(m)}: {o.count} edges matched with the "
                     f"nearer surface, median |offset| {_f(o.median_abs_px, '.2f')} px, "
                     f"{_f(100 * o.over_1px, '.1f')} % > 1 px")
    if of.visibility is not None:
        lines += format_visibility_figures(of.visibility)
    return lines
