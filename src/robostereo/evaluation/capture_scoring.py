"""Located points of a robot capture scored against ground-truth depth maps.

A capture folder with depth maps (:mod:`robostereo.evaluation.depth_maps`) is located as
``robostereo locate`` would; :func:`evaluate_capture_depth` scores what one reference
view's points say against its depth map, and StereoSGBM on the same rectified pair at
the same pixels:

* each point's 3-D error (:func:`depth_errors`): its pixel in the reference view
  back-projected at the true depth, against its located world point; the error along
  the ray; whether its depth error lies within its own bound (eq. 9);
* the coverage of the edge pixels both views see (:func:`shared_edge_pixels`): Canny
  edges of the reference view at the project's gradient threshold where the true depth
  is known and the pixel's 3-D point falls inside the other view, unoccluded when that
  view has a depth map; covered where a point lies within ``cover_px`` (2 px);
* StereoSGBM (:func:`sgbm_points`, the settings of
  :func:`~robostereo.evaluation.scorer.sgbm_disparity`) on the project's rectified pair,
  its disparity at those edge pixels turned into 3-D points by the same rectification.

The library does the scoring only: reading the capture and locating it (robot layer)
is the caller's (``robostereo evaluate``), which passes the points as
:class:`CapturePoints` and SGBM's pair as :class:`SgbmPair`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError
from robostereo.evaluation.scorer import sample_dense, sgbm_disparity
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3, as_se3
from robostereo.geometry.triangulation import StereoCamera, triangulate

__all__ = [
    "COVER_PX",
    "CaptureEvaluation",
    "CapturePoints",
    "DepthFigures",
    "SgbmPair",
    "depth_errors",
    "depth_figures",
    "evaluate_capture_depth",
    "format_capture_evaluation",
    "occlusion_tolerance_mm",
    "sgbm_points",
    "shared_edge_pixels",
]

_F = NDArray[np.float64]

COVER_PX = 2.0
"""An edge pixel is covered when a located point lies within this many pixels."""

_SCALE = 16.0  # the gradient's fixed-point scale for OpenCV's Canny (int16 input)


def occlusion_tolerance_mm(depth_mm: ArrayLike) -> _F:
    """How far two depths of one point may differ and still be one surface: 2 mm plus
    1 % of the depth (a pixel's footprint at a slant, the maps' own error)."""
    return 2.0 + 0.01 * np.asarray(depth_mm, dtype=float)


@dataclass(frozen=True)
class CapturePoints:
    """A method's points in a reference view.

    Attributes
    ----------
    pixel : ndarray, shape (M, 2)
        ``(x, y)`` in the reference's grabbed image.
    world : ndarray, shape (M, 3)
        The located points, world mm.
    bound_mm : ndarray, shape (M,), or None
        Each point's depth bound along the reference's optical axis (eq. 9), mm.
    """

    pixel: _F
    world: _F
    bound_mm: _F | None = None

    def __post_init__(self) -> None:
        p, w = np.asarray(self.pixel, float), np.asarray(self.world, float)
        if p.ndim != 2 or p.shape[1] != 2 or w.shape != (len(p), 3):
            raise InputError(f"CapturePoints: pixel (M, 2) and world (M, 3), got {p.shape} "
                             f"and {w.shape}")
        object.__setattr__(self, "pixel", p)
        object.__setattr__(self, "world", w)
        if self.bound_mm is not None:
            b = np.asarray(self.bound_mm, float)
            if b.shape != (len(p),):
                raise InputError(f"CapturePoints: bound_mm (M,), got {b.shape}")
            object.__setattr__(self, "bound_mm", b)

    def __len__(self) -> int:
        return len(self.pixel)

    @classmethod
    def from_located(cls, located: Any, reference: int | None = None) -> CapturePoints:
        """The points of a two-view ``Located`` (its left view) or of an N-view
        ``LocatedViews`` found from view `reference` (all of them when None)."""
        if hasattr(located, "left_pixel"):
            return cls(located.left_pixel, located.world, located.z_bound)
        keep = (np.ones(len(located), bool) if reference is None
                else np.asarray(located.reference) == reference)
        return cls(located.pixel[keep], located.world[keep], located.bound_mm[keep])


@dataclass(frozen=True, eq=False)
class SgbmPair:
    """The rectified pair StereoSGBM is run on (the reference is its left view).

    Attributes
    ----------
    left, right : ndarray, shape (H', W')
        The rectified images (the project's, e.g. ``Located.rectified``).
    geometry : EpipolarGeometry or GeneralEpipolarGeometry
        Their rectification (``to_rectified``, ``to_world``).
    camera : StereoCamera
        The rectified pair's intrinsics and baseline (eq. 6-8).
    disparity_range : tuple of float
    bit_depth : int
    """

    left: _F
    right: _F
    geometry: Any
    camera: StereoCamera
    disparity_range: tuple[float, float]
    bit_depth: int


def _neighbours(pixel: _F, shape: tuple[int, int]) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Rows and columns ``(M, 9)`` of each pixel's nearest pixel and its 8 neighbours."""
    h, w = shape
    off = np.array([-1, 0, 1])
    dr, dc = (a.ravel() for a in np.meshgrid(off, off, indexing="ij"))
    r = np.rint(pixel[:, 1]).astype(np.intp)[:, None] + dr
    c = np.rint(pixel[:, 0]).astype(np.intp)[:, None] + dc
    inside = (r >= 0) & (r < h) & (c >= 0) & (c < w)
    return np.where(inside, r, -1), np.where(inside, c, -1)


def _sample9(depth: _F, pixel: _F) -> _F:
    """The depth map at each pixel's 3 x 3 neighbourhood, ``(M, 9)``, NaN outside."""
    r, c = _neighbours(pixel, depth.shape)
    out = depth[np.clip(r, 0, None), np.clip(c, 0, None)]
    return np.where(r >= 0, out, np.nan)


def depth_errors(pixel: ArrayLike, world: ArrayLike, camera: Camera, pose: SE3,
                 depth: NDArray[np.floating]) -> dict[str, _F]:
    """Each point against the true surface seen at its pixel.

    Parameters
    ----------
    pixel : array_like, shape (M, 2)
        ``(x, y)`` in the view's grabbed image.
    world : array_like, shape (M, 3)
        The located points, world mm.
    camera : Camera
    pose : SE3
        The view's ``T_world_camera``.
    depth : ndarray, shape (H, W)
        The view's true depth, mm (NaN unknown).

    Returns
    -------
    dict of ndarray, shape (M,) each
        ``error_mm``: 3-D distance to the true point; ``ray_mm``: its part along the
        ray; ``depth_error_mm``: located minus true depth along the optical axis.  NaN
        where the true depth is unknown at the whole neighbourhood.

    Notes
    -----
    1. The true depths at the point's nearest pixel and its 8 neighbours (an edge lies
       between pixels, so the surface either side counts, as in the project's rule).
    2. The pixel back-projected at each of them (:meth:`Camera.backproject`, distortion
       included); the nearest of those true points to the located one is its truth.
    """
    pix = np.atleast_2d(np.asarray(pixel, float))
    X = np.atleast_2d(np.asarray(world, float))
    m = len(pix)
    nan = np.full(m, np.nan)
    if not m:
        return {"error_mm": nan, "ray_mm": nan, "depth_error_mm": nan}
    pose = as_se3(pose)
    z9 = _sample9(np.asarray(depth, float), pix)
    known = np.isfinite(z9)
    G = camera.backproject(np.repeat(pix, 9, axis=0), np.where(known, z9, 1.0).ravel(), pose)
    G = G.reshape(m, 9, 3)
    d = np.linalg.norm(G - X[:, None, :], axis=2)
    d[~known] = np.inf
    best = np.argmin(d, axis=1)
    ok = known.any(axis=1)
    g = G[np.arange(m), best]
    ray = g - pose.translation
    ray /= np.linalg.norm(ray, axis=1, keepdims=True)
    err = np.where(ok, d[np.arange(m), best], np.nan)
    along = np.where(ok, np.abs(np.einsum("ij,ij->i", X - g, ray)), np.nan)
    z_pt = (X - pose.translation) @ pose.rotation[:, 2]
    dz = np.where(ok, z_pt - z9[np.arange(m), best], np.nan)
    return {"error_mm": err, "ray_mm": along, "depth_error_mm": dz}


def shared_edge_pixels(image: ArrayLike, depth: NDArray[np.floating], camera: Camera,
                       pose: SE3, other_pose: SE3,
                       other_depth: NDArray[np.floating] | None = None, *,
                       threshold: float = 8.0, bit_depth: int | None = None) -> _F:
    """The reference view's edge pixels that both views see, with known true depth.

    Parameters
    ----------
    image : array_like, shape (H, W)
        The reference's grabbed image.
    depth : ndarray, shape (H, W)
        Its true depth, mm (NaN unknown).
    camera : Camera
    pose, other_pose : SE3
        ``T_world_camera`` of the reference and the other view.
    other_depth : ndarray, shape (H, W), optional
        The other view's true depth: with it, pixels hidden there are left out.
    threshold : float
        The project's edge threshold (grey levels per pixel, 0..127 scale;
        :class:`~robostereo.matcher.parameters.MatchParameters`'s 8).
    bit_depth : int, optional
        The image's significant bits.

    Returns
    -------
    ndarray, shape (K, 2)
        ``(x, y)`` of the edge pixels, whole pixels.

    Notes
    -----
    1. The image on the thesis's 0..127 scale smoothed by its 5 x 5 filter (figure
       3-1), the project's central gradient ``(S(x + 1) - S(x - 1)) / 2`` along x and y.
    2. Canny on that gradient (L2 magnitude, non-maximum suppression across the edge)
       with both hysteresis thresholds at `threshold`: the pixels whose gradient peaks
       at or above what the matcher needs of an edge point.
    3. Kept where the true depth is known; each back-projected at it and projected into
       the other view: kept when in front of it and inside its image and, with
       `other_depth`, when a true depth of the 3 x 3 pixels there lies within
       :func:`occlusion_tolerance_mm` of the point's depth in that view.
    """
    import cv2

    from robostereo.matcher.grey_levels import smooth, to_grey

    s = smooth(to_grey(image, bit_depth=bit_depth)).astype(np.float64)
    gx, gy = np.zeros_like(s), np.zeros_like(s)
    gx[:, 1:-1] = (s[:, 2:] - s[:, :-2]) / 2.0
    gy[1:-1, :] = (s[2:, :] - s[:-2, :]) / 2.0
    dx, dy = (np.clip(np.rint(g * _SCALE), -32767, 32767).astype(np.int16) for g in (gx, gy))
    t = float(threshold) * _SCALE
    edges = cv2.Canny(dx, dy, t, t, L2gradient=True) > 0
    z = np.asarray(depth, float)
    rows, cols = np.nonzero(edges & np.isfinite(z))
    pix = np.column_stack([cols, rows]).astype(np.float64)
    if not len(pix):
        return pix
    world = camera.backproject(pix, z[rows, cols], as_se3(pose))
    with np.errstate(all="ignore"):
        uv, zo = camera.project(world, as_se3(other_pose))
    w, h = camera.image_size
    keep = (zo > 0) & (uv[:, 0] >= -0.5) & (uv[:, 0] <= w - 0.5) \
        & (uv[:, 1] >= -0.5) & (uv[:, 1] <= h - 0.5)
    if other_depth is not None:
        od = _sample9(np.asarray(other_depth, float), np.where(keep[:, None], uv, 0.0))
        with np.errstate(invalid="ignore"):
            near = np.abs(od - zo[:, None]) <= occlusion_tolerance_mm(zo)[:, None]
        keep &= near.any(axis=1)
    return pix[keep]


def sgbm_points(pair: SgbmPair, edge_pixels: ArrayLike) -> CapturePoints:
    """StereoSGBM's 3-D points at the reference's edge pixels.

    Notes
    -----
    1. :func:`~robostereo.evaluation.scorer.sgbm_disparity` on the rectified pair (its
       default settings, as in ``robostereo evaluate`` on scenes).
    2. Each edge pixel mapped into the rectified left image
       (``geometry.to_rectified``), the disparity read at its nearest pixel.
    3. ``x_right = x - d`` triangulated (eq. 6-8,
       :func:`~robostereo.geometry.triangulation.triangulate`) at the pixel's own
       sub-pixel rectified position and taken to the world (``geometry.to_world``):
       the point lies on the edge pixel's ray.
    """
    pix = np.atleast_2d(np.asarray(edge_pixels, float)).reshape(-1, 2)
    disp = sgbm_disparity(pair.left, pair.right, pair.disparity_range,
                          bit_depth=pair.bit_depth)
    h, w = disp.shape
    if not len(pix):
        return CapturePoints(np.zeros((0, 2)), np.zeros((0, 3)))
    r = pair.geometry.to_rectified(pix, "left")
    inside = np.isfinite(r).all(axis=1) & (r[:, 0] >= -0.5) & (r[:, 0] <= w - 0.5) \
        & (r[:, 1] >= -0.5) & (r[:, 1] <= h - 0.5)
    d = np.full(len(pix), np.nan)
    d[inside] = sample_dense(disp, np.rint(r[inside, 1]), r[inside, 0])
    ok = np.isfinite(d) & (d > 0)
    xyz, _ = triangulate(pair.camera, r[ok, 0], r[ok, 0] - d[ok], r[ok, 1], disp.shape)
    world = pair.geometry.to_world(xyz) if ok.any() else np.zeros((0, 3))
    return CapturePoints(pix[ok], world)


@dataclass(frozen=True)
class DepthFigures:
    """One method's figures against the depth map (``None``: nothing to measure).

    Attributes
    ----------
    method : str
    points : int
        Points in the reference view.
    with_truth : int
        Of them, those with a known true depth near their pixel.
    median_mm, p95_mm, max_mm : float or None
        3-D error (:func:`depth_errors`).
    median_ray_mm : float or None
        Its part along the ray.
    within_1mm, beyond_5mm : float or None
        Shares of the points with truth within 1 mm, beyond 5 mm.
    within_bound : float or None
        Share whose depth error lies within their own bound (None: no bounds).
    edges, covered, covered_5mm : int
        Edge pixels both views see; those with a point within ``cover_px``; those with
        a point within 5 mm of the truth within ``cover_px``.
    seconds : float
    """

    method: str
    points: int
    with_truth: int
    median_mm: float | None
    p95_mm: float | None
    max_mm: float | None
    median_ray_mm: float | None
    within_1mm: float | None
    beyond_5mm: float | None
    within_bound: float | None
    edges: int
    covered: int
    covered_5mm: int
    seconds: float

    @property
    def coverage(self) -> float | None:
        return self.covered / self.edges if self.edges else None

    @property
    def coverage_5mm(self) -> float | None:
        return self.covered_5mm / self.edges if self.edges else None

    def as_dict(self) -> dict[str, Any]:
        out = {k: getattr(self, k) for k in self.__dataclass_fields__}
        out["coverage"], out["coverage_5mm"] = self.coverage, self.coverage_5mm
        return out


def _covered(edges: _F, pixel: _F, cover_px: float) -> NDArray[np.bool_]:
    if not len(edges) or not len(pixel):
        return np.zeros(len(edges), bool)
    from scipy.spatial import cKDTree

    d, _ = cKDTree(pixel).query(edges, k=1, distance_upper_bound=cover_px)
    return np.isfinite(d)


def depth_figures(method: str, points: CapturePoints, errors: dict[str, _F], edges: _F, *,
                  seconds: float = 0.0, cover_px: float = COVER_PX
                  ) -> tuple[DepthFigures, NDArray[np.bool_]]:
    """A method's :class:`DepthFigures` and which edge pixels it covers, ``(K,)``."""
    e = errors["error_mm"]
    has = np.isfinite(e)
    ev = e[has]

    def stat(f: Any) -> float | None:
        return float(f(ev)) if ev.size else None

    within = None
    if points.bound_mm is not None and ev.size:
        within = float(np.mean(np.abs(errors["depth_error_mm"][has])
                               <= points.bound_mm[has]))
    cov = _covered(edges, points.pixel, cover_px)
    good = has & (e <= 5.0)
    cov5 = _covered(edges, points.pixel[good], cover_px)
    fig = DepthFigures(
        method=method, points=len(points), with_truth=int(has.sum()),
        median_mm=stat(np.median), p95_mm=stat(lambda v: np.percentile(v, 95)),
        max_mm=stat(np.max), median_ray_mm=float(np.median(errors["ray_mm"][has]))
        if ev.size else None, within_1mm=stat(lambda v: np.mean(v <= 1.0)),
        beyond_5mm=stat(lambda v: np.mean(v > 5.0)), within_bound=within,
        edges=len(edges), covered=int(cov.sum()), covered_5mm=int(cov5.sum()),
        seconds=float(seconds))
    return fig, cov


@dataclass(frozen=True, eq=False)
class CaptureEvaluation:
    """A capture scored against its depth maps (:func:`evaluate_capture_depth`).

    Attributes
    ----------
    name, directory : str
    reference, other : str
        The scored view and the view paired with it (edges both see; SGBM's right view).
    image_size : tuple of int
    methods : tuple of DepthFigures
        ``robostereo`` first, then ``sgbm`` when run.
    edge_pixels : ndarray, shape (K, 2)
        The edge pixels both views see (for plots).
    covered : dict of str to ndarray of bool, shape (K,)
    errors : dict of str to ndarray, shape (M,)
        Each method's 3-D errors, mm (NaN: no truth).
    """

    name: str
    directory: str
    reference: str
    other: str
    image_size: tuple[int, int]
    methods: tuple[DepthFigures, ...]
    edge_pixels: _F = field(repr=False)
    covered: dict[str, NDArray[np.bool_]] = field(repr=False)
    errors: dict[str, _F] = field(repr=False)

    def as_dict(self) -> dict[str, Any]:
        return {"name": self.name, "directory": self.directory, "kind": "capture",
                "reference": self.reference, "other": self.other,
                "image_size": list(self.image_size),
                "methods": [m.as_dict() for m in self.methods]}


def evaluate_capture_depth(
    *, name: str, directory: str, camera: Camera, poses: tuple[SE3, SE3],
    image: ArrayLike, depth: NDArray[np.floating],
    other_depth: NDArray[np.floating] | None, points: CapturePoints,
    views: tuple[str, str] = ("left", "right"), seconds: float = 0.0,
    sgbm: SgbmPair | None = None, threshold: float = 8.0, bit_depth: int | None = None,
    cover_px: float = COVER_PX,
) -> CaptureEvaluation:
    """Score a capture's located points, and StereoSGBM's, against a depth map.

    Parameters
    ----------
    name, directory : str
        For the report.
    camera : Camera
    poses : tuple of SE3
        ``T_world_camera`` of the reference view and the other view.
    image : array_like, shape (H, W)
        The reference's grabbed image.
    depth, other_depth : ndarray, shape (H, W)
        True depths of the two views, mm (`other_depth` None when unknown).
    points : CapturePoints
        The project's points in the reference view.
    views : tuple of str
        The two views' names.
    seconds : float
        The project's locating time.
    sgbm : SgbmPair, optional
        The rectified pair to run StereoSGBM on (left = the reference); None: no SGBM.
    threshold, bit_depth
        Of the edge pixels (:func:`shared_edge_pixels`).
    cover_px : float

    Returns
    -------
    CaptureEvaluation

    Notes
    -----
    1. The edge pixels both views see (:func:`shared_edge_pixels`).
    2. The project's errors (:func:`depth_errors`) and figures (:func:`depth_figures`).
    3. SGBM's points at those edge pixels (:func:`sgbm_points`), their errors and
       figures, timed.
    """
    w, h = camera.image_size
    if np.shape(depth) != (h, w):
        raise InputError(f"{directory}: the depth map is not {w} x {h} pixels")
    edges = shared_edge_pixels(image, depth, camera, poses[0], poses[1], other_depth,
                               threshold=threshold, bit_depth=bit_depth)
    methods, covered, errors = [], {}, {}
    runs: list[tuple[str, CapturePoints, float]] = [("robostereo", points, seconds)]
    if sgbm is not None:
        t0 = time.perf_counter()
        sp = sgbm_points(sgbm, edges)
        runs.append(("sgbm", sp, time.perf_counter() - t0))
    for method, pts, secs in runs:
        err = depth_errors(pts.pixel, pts.world, camera, poses[0], depth)
        fig, cov = depth_figures(method, pts, err, edges, seconds=secs, cover_px=cover_px)
        methods.append(fig)
        covered[method], errors[method] = cov, err["error_mm"]
    return CaptureEvaluation(name, directory, views[0], views[1], (w, h), tuple(methods),
                             edges, covered, errors)


def _pct(v: float | None, width: int) -> str:
    return f"{'-':>{width}}" if v is None else f"{100 * v:{width}.1f}"


def _mm(v: float | None, width: int) -> str:
    return f"{'-':>{width}}" if v is None or not math.isfinite(v) else f"{v:{width}.2f}"


def format_capture_evaluation(ev: CaptureEvaluation) -> str:
    """The table ``robostereo evaluate`` prints for a capture.

    >>> f = DepthFigures("robostereo", 900, 880, 0.41, 1.9, 12.0, 0.3, 0.8, 0.02, 0.7,
    ...                  1000, 850, 840, 2.5)
    >>> ev = CaptureEvaluation("c", "/d/c", "left.png", "right.png", (640, 480), (f,),
    ...                        np.zeros((0, 2)), {}, {})
    >>> print(format_capture_evaluation(ev))  # doctest: +NORMALIZE_WHITESPACE
    c: 640 x 480 px, reference left.png (paired with right.png), 1000 edge pixels both
    views see
      method      points  truth  median mm  p95 mm  max mm  ray mm  <=1mm %  >5mm %
        in bound %  coverage %  cov <=5mm %  time s
      robostereo     900    880       0.41    1.90   12.00    0.30     80.0     2.0
              70.0        85.0         84.0     2.5
    """
    lines = [f"{ev.name}: {ev.image_size[0]} x {ev.image_size[1]} px, reference "
             f"{ev.reference} (paired with {ev.other}), "
             f"{ev.methods[0].edges if ev.methods else 0} edge pixels both views see",
             "  method      points  truth  median mm  p95 mm  max mm  ray mm  <=1mm %  "
             ">5mm %  in bound %  coverage %  cov <=5mm %  time s"]
    for m in ev.methods:
        label = "SGBM" if m.method == "sgbm" else m.method
        lines.append(
            f"  {label:<10} {m.points:7d} {m.with_truth:6d} {_mm(m.median_mm, 10)} "
            f"{_mm(m.p95_mm, 7)} {_mm(m.max_mm, 7)} {_mm(m.median_ray_mm, 7)} "
            f"{_pct(m.within_1mm, 8)} {_pct(m.beyond_5mm, 7)} {_pct(m.within_bound, 11)} "
            f"{_pct(m.coverage, 11)} {_pct(m.coverage_5mm, 12)} {m.seconds:7.1f}")
    return "\n".join(lines)
