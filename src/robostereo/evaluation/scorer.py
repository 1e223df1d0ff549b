"""Scoring sparse matches against ground-truth disparity: the project's evaluation rule.

The rules themselves (the project's and the silhouette rule), the near-step mask and
the calibration error live in :mod:`robostereo.evaluation.rules`, the figures near and
away from depth steps in :mod:`robostereo.evaluation.outlines`; their public names are
importable from here too.

The rule, the same everywhere in robostereo (tests, ``robostereo evaluate``, the demo):

* an edge point *counts* when the ground truth at its nearest pixel is known;
* a match is *false* when its disparity differs by more than ``tolerance`` (1 px) from
  every known ground-truth disparity at the edge's nearest pixel and at its left and
  right neighbours (an edge lies between two pixels);
* *% matched* is matched counted edges over counted edges; *% false* is false
  matches over matched counted edges; the disparity RMS is over correct matches,
  against the nearest of those ground-truth values.

The same scoring is applied to a dense disparity map (OpenCV's StereoSGBM) read at
the same pixels, so the two are compared point for point.

:func:`evaluate_scene` runs the core matcher (:func:`robostereo.matcher.pipeline.match_stereo`)
and OpenCV's StereoSGBM (:func:`sgbm_disparity`) on a
:class:`~robostereo.datasets.StereoScene` and scores both at the same pixels, the
matcher's left edge points, by the project's evaluation rule
(:func:`score_matches`): % matched, % false, disparity RMS of
the correct matches, and the time each took.  With a Middlebury ``calib.txt`` the
correct matches are also triangulated (:func:`robostereo.geometry.triangulation.triangulate`,
the project's one path) and compared in millimetres with the points that the
ground-truth disparity gives.  :func:`format_evaluation` prints the table that
``robostereo evaluate`` shows.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.datasets import StereoScene
from robostereo.errors import InputError
from robostereo.evaluation.outlines import (
    MethodPoints,
    OutlineFigures,
    format_outline_figures,
    outline_figures,
    settings_curve,
)
from robostereo.evaluation.rules import (
    RULES,
    CoverageCurve,
    MatchScore,
    coverage_curve,
    score_matches,
)
from robostereo.geometry.calibrated_rectification import rectify_stereo
from robostereo.geometry.triangulation import StereoCamera, triangulate
from robostereo.matcher.grey_levels import to_grey
from robostereo.matcher.parameters import MatchParameters
from robostereo.matcher.pipeline import match_stereo, searched_range

__all__ = [
    "CURVE_LEVELS",
    "SGBM_SWEEP",
    "MethodFigures",
    "SceneEvaluation",
    "errors_3d",
    "evaluate_scene",
    "format_evaluation",
    "nearest_ground_truth",
    "sample_dense",
    "sgbm_curve",
    "sgbm_disparity",
    "sgbm_input",
    "sgbm_sweep",
]


def sample_dense(dense: NDArray[np.floating], rows: ArrayLike, x: ArrayLike) -> NDArray[np.float64]:
    """Read a dense disparity map at the edge points' nearest pixels.

    Parameters
    ----------
    dense : ndarray, shape (H, W)
        Disparity map, NaN where the dense matcher gave none.
    rows, x : array_like, shape (N,)
        Rows and sub-pixel columns of the edge points.

    Returns
    -------
    ndarray, shape (N,)
    """
    d = np.asarray(dense, dtype=float)
    h, w = d.shape
    r = np.clip(np.asarray(rows, dtype=np.intp), 0, h - 1)
    c = np.clip(np.rint(np.asarray(x, dtype=float)).astype(np.intp), 0, w - 1)
    return d[r, c]


def sgbm_input(image: ArrayLike, *, bit_depth: int | None = None) -> NDArray[np.uint8]:
    """The grey image SGBM is given: robostereo's grey levels (0..127) times two, 8 bit."""
    return np.clip(np.rint(to_grey(image, bit_depth=bit_depth) * 2.0), 0, 255).astype(np.uint8)


def sgbm_disparity(
    left: ArrayLike,
    right: ArrayLike,
    disparity_range: tuple[float, float],
    *,
    block_size: int = 5,
    uniqueness_ratio: int = 10,
    left_right_check: bool = False,
    bit_depth: int | None = None,
) -> NDArray[np.float64]:
    """OpenCV StereoSGBM on the same pair and range: the project's dense reference.

    Parameters
    ----------
    left, right : array_like, shape (H, W) or (H, W, 3|4)
    disparity_range : tuple of float
        ``(min, max)`` disparity; SGBM searches ``numDisparities`` rounded up to a
        multiple of 16 from ``floor(min)``, and values above ``max + 0.5`` are dropped.
        ``numDisparities`` is cut to what the image width allows SGBM (all NaN when
        not even 16 fit).
    block_size, uniqueness_ratio : int
        SGBM's ``blockSize`` (5) and ``uniquenessRatio`` (10); ``P1 = 8 * block_size**2``
        and ``P2 = 32 * block_size**2`` as OpenCV's documentation recommends for grey input.
    left_right_check : bool
        SGBM's own left-right check, ``disp12MaxDiff = 1`` (off: -1).

    Returns
    -------
    ndarray, shape (H, W)
        Disparity in pixels, NaN where SGBM gives none.
    """
    import cv2

    lo, hi = disparity_range
    g = [sgbm_input(im, bit_depth=bit_depth) for im in (left, right)]
    n = int(np.ceil((np.floor(hi) - np.floor(lo) + 1) / 16.0) * 16)
    # SGBM needs width - (minDisparity + numDisparities) > blockSize // 2
    room = g[0].shape[1] - int(np.floor(lo)) - block_size // 2 - 1
    n = min(n, room // 16 * 16)
    if n < 16:  # the range leaves SGBM no room in this image: no disparity at all
        return np.full(g[0].shape, np.nan)
    sgbm = cv2.StereoSGBM_create(
        minDisparity=int(np.floor(lo)), numDisparities=n, blockSize=block_size,
        uniquenessRatio=uniqueness_ratio, P1=8 * block_size**2, P2=32 * block_size**2,
        disp12MaxDiff=1 if left_right_check else -1,
    )
    d = sgbm.compute(g[0], g[1]).astype(float) / 16.0
    d[(d < np.floor(lo)) | (d > hi + 0.5)] = np.nan
    return d


#: SGBM's settings swept for its curve: uniquenessRatio 0, 5, ..., 60, each with its
#: left-right check off and on
SGBM_SWEEP: tuple[tuple[int, bool], ...] = tuple(
    (u, lr) for lr in (False, True) for u in range(0, 61, 5))

#: the false rates at which curves are compared
CURVE_LEVELS: tuple[float, ...] = (0.02, 0.03, 0.05)


def sgbm_sweep(
    left: ArrayLike, right: ArrayLike, disparity_range: tuple[float, float], rows: ArrayLike,
    x: ArrayLike, *, bit_depth: int | None = None,
) -> tuple[tuple[NDArray[np.float64], ...], tuple[float, ...]]:
    """StereoSGBM at every setting of :data:`SGBM_SWEEP`, read at the given pixels.

    Returns
    -------
    samples : tuple of ndarray, shape (N,) each
        The disparity each setting gives the points (NaN where none).
    labels : tuple of float
        ``uniquenessRatio`` of each setting, negative where the left-right check was on.
    """
    samples = tuple(
        sample_dense(sgbm_disparity(left, right, disparity_range, uniqueness_ratio=u,
                                    left_right_check=lr, bit_depth=bit_depth), rows, x)
        for u, lr in SGBM_SWEEP)
    return samples, tuple(float(-u if lr else u) for u, lr in SGBM_SWEEP)


def sgbm_curve(
    left: ArrayLike, right: ArrayLike, disparity_range: tuple[float, float], rows: ArrayLike,
    x: ArrayLike, gt_disparity: NDArray[np.floating], *, bit_depth: int | None = None,
    tolerance: float = 1.0, rule: str = "project",
) -> CoverageCurve:
    """StereoSGBM's coverage against false rate at the given pixels, over its settings.

    Each setting of :data:`SGBM_SWEEP` gives one point (coverage, false rate by
    ``rule``); the points are sorted by coverage.  ``threshold`` holds
    ``uniquenessRatio`` (negative where the left-right check was on).
    """
    samples, labels = sgbm_sweep(left, right, disparity_range, rows, x, bit_depth=bit_depth)
    return settings_curve(samples, labels, rows, x, gt_disparity, tolerance=tolerance,
                          rule=rule)


@dataclass(frozen=True)
class MethodFigures:
    """One method's figures on one scene, at the matcher's left edge points.

    Attributes
    ----------
    method : str
        ``"robostereo"`` or ``"sgbm"``.
    counted, matched, false : int
        Edge points with known ground truth; those matched; those matched falsely
        (the project's evaluation rule).
    rms_px : float
        Disparity RMS error of the correct matches, pixels (NaN if none).
    seconds : float
        Wall time of the method on the whole pair.
    rms_3d_mm, median_3d_mm : float or None
        RMS and median distance between the triangulated correct matches and the
        points of the ground-truth disparity, millimetres; None without a calibration.
    """

    method: str
    counted: int
    matched: int
    false: int
    rms_px: float
    seconds: float
    rms_3d_mm: float | None = None
    median_3d_mm: float | None = None

    @property
    def matched_percent(self) -> float:
        return 100.0 * self.matched / self.counted if self.counted else math.nan

    @property
    def false_percent(self) -> float:
        return 100.0 * self.false / self.matched if self.matched else 0.0

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["matched_percent"] = self.matched_percent
        d["false_percent"] = self.false_percent
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
                for k, v in d.items()}


@dataclass(frozen=True)
class SceneEvaluation:
    """The evaluation of one scene (see :func:`evaluate_scene`).

    Attributes
    ----------
    name, path : str
        Scene name and directory.
    image_size : tuple of int
        ``(width, height)``.
    disparity_range : tuple of float
        The search range used by both methods.
    edges_left, edges_right : int
        Edge points found in each image.
    methods : tuple of MethodFigures
        ``robostereo`` first, then ``sgbm`` (unless left out): the default operating
        points (SGBM: uniquenessRatio 10, no left-right check).
    curves : dict of str to CoverageCurve
        ``robostereo`` (its confidence swept) and ``sgbm`` (:data:`SGBM_SWEEP`).
    outlines : OutlineFigures or None
        Both scoring rules near and away from depth steps, calibration, 3-D distances
        to the ground-truth surface and silhouette offsets
        (:mod:`robostereo.evaluation.outlines`).
    rule : str
        The rule of ``methods`` and ``curves`` (:data:`RULES`): ``"project"`` or
        ``"silhouette"``.
    """

    name: str
    path: str
    image_size: tuple[int, int]
    disparity_range: tuple[float, float]
    edges_left: int
    edges_right: int
    methods: tuple[MethodFigures, ...]
    curves: dict[str, CoverageCurve] = field(default_factory=dict)
    outlines: OutlineFigures | None = None
    rule: str = "project"

    def __post_init__(self) -> None:
        if self.rule not in RULES:
            raise InputError(f"rule must be one of {', '.join(RULES)}, got {self.rule!r}")

    def coverage_at(self, method: str, max_false: float) -> float:
        """Coverage of ``method``'s curve at at most ``max_false`` false."""
        return self.curves[method].coverage_at(max_false)

    def as_dict(self) -> dict[str, Any]:
        return {
            "scene": self.name, "path": self.path, "width": self.image_size[0],
            "height": self.image_size[1], "min_disparity": self.disparity_range[0],
            "max_disparity": self.disparity_range[1], "edges_left": self.edges_left,
            "edges_right": self.edges_right,
            "methods": {m.method: m.as_dict() for m in self.methods},
            "coverage_at_false": {
                name: {f"{100 * f:g}%": c.coverage_at(f) for f in CURVE_LEVELS}
                for name, c in self.curves.items()},
            **({"outlines": self.outlines.as_dict()} if self.outlines is not None else {}),
            "rule": self.rule,
        }  # fmt: skip


def nearest_ground_truth(
    rows: ArrayLike, x: ArrayLike, disparity: ArrayLike, gt_disparity: NDArray[np.floating]
) -> NDArray[np.float64]:
    """Per point, the known ground truth nearest to its disparity among the edge's
    nearest pixel and its left and right neighbours (the evaluation rule's reference).

    Parameters
    ----------
    rows, x, disparity : array_like, shape (N,)
    gt_disparity : ndarray, shape (H, W)

    Returns
    -------
    ndarray, shape (N,)
        NaN where the nearest pixel's ground truth is unknown or the point unmatched.

    Examples
    --------
    >>> g = np.array([[4.0, 5.0, 6.0, np.nan]])
    >>> nearest_ground_truth([0, 0, 0], [1.2, 2.6, 1.0], [5.9, 6.0, np.nan], g).tolist()
    [6.0, nan, nan]
    """
    g = np.asarray(gt_disparity, dtype=float)
    h, w = g.shape
    r = np.clip(np.asarray(rows, dtype=np.intp), 0, h - 1)
    c = np.clip(np.rint(np.asarray(x, dtype=float)).astype(np.intp), 0, w - 1)
    d = np.asarray(disparity, dtype=float)
    nb = np.stack([g[r, np.clip(c + o, 0, w - 1)] for o in (-1, 0, 1)], axis=1)
    err = np.where(np.isfinite(nb), np.abs(nb - d[:, None]), np.inf)
    k = np.argmin(err, axis=1)
    best = nb[np.arange(len(d)), k]
    ok = np.isfinite(g[r, c]) & np.isfinite(d) & np.isfinite(err[np.arange(len(d)), k])
    return np.where(ok, best, np.nan)


def errors_3d(
    camera: StereoCamera,
    rows: ArrayLike,
    x: ArrayLike,
    disparity: ArrayLike,
    gt_disparity: ArrayLike,
    image_shape: tuple[int, int],
) -> NDArray[np.float64]:
    """Distance (mm) between the points of the found and of the true disparity.

    Both are triangulated by :func:`robostereo.geometry.triangulation.triangulate` from the same
    left position ``(x, row)``, with ``x_right = x - d``.

    Examples
    --------
    At the principal point, f = 1000 px, B = 100 mm: d = 10 gives Z = 10 m and
    d = 9 gives 11.111 m, 1111.1 mm apart:

    >>> cam = StereoCamera(1000.0, 1000.0, 100.0, cx=50.0, cy=20.0)
    >>> errors_3d(cam, [20], [50.0], [10.0], [9.0], (40, 100)).round(1).tolist()
    [1111.1]
    """
    r = np.asarray(rows, dtype=float)
    xs = np.asarray(x, dtype=float)
    p, _ = triangulate(camera, xs, xs - np.asarray(disparity, float), r, image_shape)
    q, _ = triangulate(camera, xs, xs - np.asarray(gt_disparity, float), r, image_shape)
    return np.linalg.norm(p - q, axis=1)


def _figures(
    method: str, rows: NDArray[Any], x: NDArray[Any], d: NDArray[Any], scene: StereoScene,
    seconds: float, camera: StereoCamera | None, tolerance: float, rule: str = "project",
) -> MethodFigures:
    s: MatchScore = score_matches(rows, x, d, scene.gt_disparity, tolerance=tolerance,
                                  rule=rule)
    rms3 = med3 = None
    if camera is not None:
        gt = nearest_ground_truth(rows, x, d, scene.gt_disparity)
        good = np.isfinite(gt) & (np.abs(d - gt) <= tolerance)
        e = errors_3d(camera, rows[good], x[good], d[good], gt[good], scene.shape)
        e = e[np.isfinite(e)]
        if e.size:
            rms3, med3 = float(np.sqrt(np.mean(e**2))), float(np.median(e))
    return MethodFigures(method, s.counted, s.matched, s.false, s.rms, seconds, rms3, med3)


def evaluate_scene(
    scene: StereoScene,
    *,
    disparity_range: tuple[float, float] | None = None,
    params: MatchParameters | None = None,
    sgbm: bool = True,
    curve: bool = True,
    tolerance: float = 1.0,
    outlines: bool = True,
    rule: str = "project",
) -> SceneEvaluation:
    """Score the matcher and StereoSGBM on one scene with ground truth.

    Parameters
    ----------
    scene : StereoScene
        From :func:`robostereo.datasets.load_scene`.
    disparity_range : tuple of float, optional
        Search range of both methods; default ``scene.disparity_range``, the known
        ground truth's least and largest value (as the core matcher's tests use).
    params : MatchParameters, optional
        Matcher tuning; default ``MatchParameters()`` with the scene's bit depth.
    sgbm : bool
        Also run StereoSGBM (blockSize 5, uniquenessRatio 10, same range).
    curve : bool
        Also sweep SGBM's settings for its curve (:func:`sgbm_curve`; 26 runs).
    tolerance : float
        Largest disparity error of a correct match (both rules' 1 px).
    outlines : bool
        Also the figures near and away from depth steps by both rules
        (:func:`~robostereo.evaluation.outlines.outline_figures`).
    rule : {"project", "silhouette"}
        The rule of the methods' figures (% false, RMS) and of the curves; the 3-D
        errors of correct matches keep the project's reference pixels.

    Returns
    -------
    SceneEvaluation

    Notes
    -----
    1. :func:`~robostereo.matcher.pipeline.match_stereo` on the pair, timed.
    2. :func:`~robostereo.evaluation.scorer.sgbm_disparity`, timed, read at the matcher's left
       edge points (:func:`~robostereo.evaluation.scorer.sample_dense`).
    3. Both scored by :func:`~robostereo.evaluation.scorer.score_matches`.
    4. Curves: robostereo's best match of every edge point by decreasing confidence
       (:func:`coverage_curve`), SGBM over its settings (:func:`sgbm_curve`).
    5. With ``scene.calib``: its rectification's
       :class:`~robostereo.geometry.triangulation.StereoCamera` triangulates each correct match
       and its ground truth (:func:`errors_3d`).
    6. With ``outlines``: both rules near and away from depth steps, ECE of the
       confidence, the located points' 3-D distances to the ground-truth surface (with
       ``scene.calib``) and the silhouette offsets, for both methods at the same points;
       near steps also over the edge points visible in both views (the ground truth
       z-buffered, cross-checked with ``scene.gt_disparity_right``) and why the rest
       are not accepted.
    """
    lo, hi = searched_range(scene.disparity_range if disparity_range is None
                            else disparity_range, scene.shape[1])  # both methods search it
    p = params if params is not None else MatchParameters(bit_depth=scene.bit_depth)
    if params is not None and params.bit_depth is None:
        p = replace(params, bit_depth=scene.bit_depth)
    camera = None
    if scene.calib is not None:
        camera = rectify_stereo(scene.calib, zero_disparity=False).stereo_camera()
    from robostereo.matcher.pipeline import warm_up

    warm_up()  # the kernels' first load is not the scene's time
    t0 = time.perf_counter()
    res = match_stereo(scene.left, scene.right, (lo, hi), params=p)
    t_match = time.perf_counter() - t0
    e = res.left_edges
    d = res.accepted_disparity()
    methods = [_figures("robostereo", e.row, e.x, d, scene, t_match, camera, tolerance, rule)]
    curves = {"robostereo": coverage_curve(e.row, e.x, res.edge_disparity, res.edge_confidence,
                                           scene.gt_disparity, tolerance=tolerance, rule=rule)}
    points = [MethodPoints("robostereo", d, res.edge_disparity, res.edge_confidence)]
    if sgbm:
        t0 = time.perf_counter()
        dense = sgbm_disparity(scene.left, scene.right, (lo, hi), bit_depth=p.bit_depth)
        t_sgbm = time.perf_counter() - t0
        ds = sample_dense(dense, e.row, e.x)
        methods.append(_figures("sgbm", e.row, e.x, ds, scene, t_sgbm, camera, tolerance, rule))
        sweep: tuple[tuple[NDArray[np.float64], ...], tuple[float, ...]] = ((), ())
        if curve:
            sweep = sgbm_sweep(scene.left, scene.right, (lo, hi), e.row, e.x,
                               bit_depth=p.bit_depth)
            curves["sgbm"] = settings_curve(*sweep, e.row, e.x, scene.gt_disparity,
                                            tolerance=tolerance, rule=rule)
        points.append(MethodPoints("sgbm", ds, sweep=sweep[0], sweep_labels=sweep[1]))
    of = (outline_figures(e.row, e.x, scene.gt_disparity, points, camera=camera,
                          tolerance=tolerance, gt_right=scene.gt_disparity_right)
          if outlines else None)
    h, w = scene.shape
    return SceneEvaluation(
        name=scene.name, path=str(scene.path) if scene.path is not None else "",
        image_size=(w, h), disparity_range=(float(lo), float(hi)),
        edges_left=len(e), edges_right=len(res.right_edges), methods=tuple(methods),
        curves=curves, outlines=of, rule=rule,
    )  # fmt: skip


#: how the printed table names each rule
_RULE_WORDS = {"project": "project's rule", "silhouette": "silhouette rule"}


def _num(v: float | None, fmt: str) -> str:
    return "-" if v is None or not math.isfinite(v) else format(v, fmt)


def format_evaluation(ev: SceneEvaluation) -> str:
    """The per-scene table printed by ``robostereo evaluate``.

    >>> m = MethodFigures("robostereo", 100, 85, 1, 0.25, 0.0123)
    >>> ev = SceneEvaluation("s", "/d/s", (40, 30), (5.0, 14.0), 120, 118, (m,))
    >>> print(format_evaluation(ev))  # doctest: +NORMALIZE_WHITESPACE
    s: 40 x 30 px, disparity 5 .. 14 px, 120 left edge points (100 with ground truth),
    false by the project's rule
      method      matched   false  RMS px  time ms
      robostereo   85.0 %  1.18 %   0.250     12.3
    """
    three_d = any(m.rms_3d_mm is not None for m in ev.methods)
    counted = ev.methods[0].counted if ev.methods else 0
    lines = [
        f"{ev.name}: {ev.image_size[0]} x {ev.image_size[1]} px, disparity "
        f"{ev.disparity_range[0]:g} .. {ev.disparity_range[1]:g} px, {ev.edges_left} left edge "
        f"points ({counted} with ground truth), false by the {_RULE_WORDS[ev.rule]}",
        "  method      matched   false  RMS px  time ms"
        + ("  3-D RMS mm  3-D median mm" if three_d else ""),
    ]
    for m in ev.methods:
        name = "SGBM" if m.method == "sgbm" else m.method
        line = (f"  {name:<10} {_num(m.matched_percent, '6.1f')} % "
                f"{_num(m.false_percent, '5.2f')} %  {_num(m.rms_px, '6.3f')}  "
                f"{_num(1000 * m.seconds, '7.1f')}")
        if three_d:
            line += f"  {_num(m.rms_3d_mm, '10.2f')}  {_num(m.median_3d_mm, '13.2f')}"
        lines.append(line)
    if ev.curves:
        lines.append("  coverage at" + "".join(f"{'<=' + format(100 * f, 'g') + '% false':>14s}"
                                               for f in CURVE_LEVELS))
        notes = {"robostereo": "confidence swept",
                 "sgbm": "uniquenessRatio 0..60, left-right check off/on"}
        for name, c in ev.curves.items():
            label = "SGBM" if name == "sgbm" else name
            lines.append(f"  {label:<10} " + "".join(
                f"{100 * c.coverage_at(f):12.1f} %" for f in CURVE_LEVELS)
                + f"   ({notes.get(name, '')})")
    if ev.outlines is not None:
        lines += format_outline_figures(ev.outlines)
    return "\n".join(lines)

