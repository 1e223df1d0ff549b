"""The stages of the N-view locate: views prepared, rays searched, points refined.

:func:`robostereo.robot.views.locate_views.locate_views` runs these for each reference view:

* :func:`prepare_views`: every view undistorted to the pinhole camera of its own
  intrinsics, on the thesis's 0..127 grey scale, smoothed (figure 3-1), with its
  gradient; the poses as rotations and optical centres;
* :func:`reference_edges`: the reference view's edge points on the pixel grid
  (:func:`~robostereo.robot.views.views_kernels.grid_edges`);
* :func:`search_rays`: each edge point's ray searched in inverse depth [1]_, every other
  view's window scored (:func:`~robostereo.robot.views.views_kernels.sweep_costs`) and
  the views combined robustly (the best half [2]_);
* :func:`refine_points`: each view's sub-pixel edge point near the best depth, the
  3-D point refined by least squares over the views that agree, its bound.

The checks by the views' edges (the views left out of a fit, and the edge points the
window search leaves) are in :mod:`~robostereo.robot.views.edge_votes`.

References
----------
.. [1] M. Okutomi and T. Kanade, "A multiple-baseline stereo", IEEE PAMI 15(4), 1993.
.. [2] S. B. Kang, R. Szeliski and J. Chai, "Handling occlusions in dense multi-view
   stereo", CVPR 2001.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from robostereo.geometry.poses import as_se3
from robostereo.matcher.grey_levels import smooth, to_grey
from robostereo.robot.views.edge_profiles import two_step_edges, view_blurs
from robostereo.robot.views.viewpoints import ViewsCapture
from robostereo.robot.views.views_kernels import (
    central_gradient,
    edge_near,
    grid_edges,
    normal_residuals,
    sweep_costs,
)

__all__ = [
    "PreparedViews",
    "RayMatches",
    "ReferenceEdges",
    "RefinedPoints",
    "bilinear",
    "carried_normals",
    "depth_plane_maps",
    "epipolar_sines",
    "prepare_views",
    "projection_terms",
    "ray_directions",
    "reference_edges",
    "refine_points",
    "search_rays",
]

_F = NDArray[np.float64]

SMOOTH_REACH = 2.0
"""Least distance (pixels) of a window sample from an image's border: the half-width of
the thesis's 5 x 5 smoothing filter, within which the smoothed grey levels are
reflections of the image's inside rather than its content.  A reference edge point
lies ``half_window + 2`` pixels inside, so its own window keeps this margin too."""

KEPT_FLOOR = 0.1
"""Window cost (``1 - ZNCC``) a view may always have to enter the fit: below it a
window fits well whatever the other views do."""


@dataclass(frozen=True, eq=False)
class PreparedViews:
    """Every view undistorted, smoothed and differentiated.

    Attributes
    ----------
    smoothed : float32 (N, H, W)
        Undistorted grey levels on the thesis's 0..127 scale, smoothed (figure 3-1).
    gx, gy : float32 (N, H, W)
        ``(S(x + 1) - S(x - 1)) / 2`` and the same along y.
    fine_gx, fine_gy : float32 (N, H, W)
        The same of the undistorted grey levels before the thesis's smoothing (blurred
        by a Gaussian of ``edge_blur_px`` if that is above 0), which place the sub-pixel
        edge points (:func:`reference_edges`, :func:`refine_points`); `gx`, `gy`
        themselves when ``edge_blur_px`` is None.
    K, K_inv : (3, 3)
        The pinhole intrinsics the undistorted images share.
    R : (N, 3, 3)
        Camera-to-world rotations.
    C : (N, 3)
        Optical centres, world mm.
    grey : float32 (N, H, W) or None
        Undistorted grey levels, not smoothed, for the two-step fit (None: no such fit;
        :func:`~robostereo.robot.views.edge_profiles.two_step_edges`).
    blur : (N,) or None
        Each view's blur, px (:meth:`blurs`; -1 until a first edge point needs it).
    opposite_px : float
        Farthest opposite edge of the two-step fit, px.
    """

    smoothed: NDArray[np.float32]
    gx: NDArray[np.float32]
    gy: NDArray[np.float32]
    fine_gx: NDArray[np.float32]
    fine_gy: NDArray[np.float32]
    K: _F
    K_inv: _F
    R: _F
    C: _F
    grey: NDArray[np.float32] | None = None
    blur: _F | None = None
    opposite_px: float = 3.0

    def blurs(self, threshold: float) -> _F:
        """:attr:`blur`, estimated at the first call (edges of `threshold`)."""
        assert self.blur is not None and self.grey is not None
        if self.blur[0] < 0:
            self.blur[:] = view_blurs(self.grey, self.gx, self.gy, threshold)
        return self.blur

    def project(self, world: _F, view: int) -> tuple[_F, _F]:
        """Pinhole pixels ``(M, 2)`` and depths ``(M,)`` of world points in `view`."""
        pc = (world - self.C[view]) @ self.R[view]
        z = pc[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            uv = pc[:, :2] / z[:, None]
        return uv * np.diag(self.K)[:2] + self.K[:2, 2], z


def prepare_views(capture: ViewsCapture, edge_blur_px: float | None = 0.7,
                  opposite_px: float | None = None) -> PreparedViews:
    """Undistort, convert, smooth and differentiate every view (see :class:`PreparedViews`).

    Parameters
    ----------
    capture : ViewsCapture
    edge_blur_px : float or None
        Gaussian sigma (pixels) of the images whose gradient places the sub-pixel edge
        points; 0: the undistorted grey levels as they are; None: the thesis's smoothed
        images, as the search uses.
    opposite_px : float or None
        :attr:`PreparedViews.opposite_px`; None: no two-step fit.

    Notes
    -----
    The thesis's 5 x 5 filter (figure 3-1) spreads an edge's gradient over about +-2 px;
    beside a second edge that close (a face seen nearly edge-on) the peak moves towards
    it; the search needs the smoothing, the sub-pixel position does not: on the simulated
    block the smoothed peak moved 0.119 px beside a 2.2 px strip, the unsmoothed 0.034 px
    (same spread).  A light blur (``ViewsParameters.edge_blur_px``) trades a little back.
    """
    cam = capture.camera
    w, h = cam.image_size
    K = cam.K
    undistort = bool(np.any(np.asarray(cam.dist_coeffs) != 0))
    if undistort:
        u, v = np.meshgrid(np.arange(w, dtype=float), np.arange(h, dtype=float))
        cx, cy = cam.principal_point
        n = np.column_stack([((u - cx) / cam.fx).ravel(), ((v - cy) / cam.fy).ravel()])
        d = cam.distort(n)
        map_x = (d[:, 0] * cam.fx + cx).reshape(h, w).astype(np.float32)
        map_y = (d[:, 1] * cam.fy + cy).reshape(h, w).astype(np.float32)
    n_views = len(capture.images)
    sm, gxs, gys = (np.empty((n_views, h, w), np.float32) for _ in range(3))
    fine = edge_blur_px is not None
    greys = np.empty((n_views, h, w), np.float32) if opposite_px is not None else None
    fxs, fys = (np.empty((n_views, h, w), np.float32) for _ in range(2)) if fine else (gxs, gys)
    for i, img in enumerate(capture.images):
        g = to_grey(img, bit_depth=int(capture.bit_depth))
        if undistort:
            g = cv2.remap(g, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        sm[i] = smooth(g)
        central_gradient(sm[i], gxs[i], gys[i])  # half the central differences
        g = np.asarray(g, np.float32)
        if greys is not None:
            greys[i] = g
        if fine:
            if edge_blur_px > 0:  # type: ignore[operator]
                g = cv2.GaussianBlur(g, (0, 0), float(edge_blur_px),  # type: ignore[arg-type]
                                     borderType=cv2.BORDER_REFLECT_101)
            central_gradient(np.ascontiguousarray(g, np.float32), fxs[i], fys[i])
    poses = [as_se3(p) for p in capture.poses]
    blur = np.full(n_views, -1.0) if opposite_px is not None else None
    return PreparedViews(
        smoothed=sm, gx=gxs, gy=gys, fine_gx=fxs, fine_gy=fys, K=K, K_inv=np.linalg.inv(K),
        R=np.stack([p.rotation for p in poses]),
        C=np.stack([p.translation for p in poses]),
        grey=greys if opposite_px is not None else None, blur=blur,
        opposite_px=float(opposite_px) if opposite_px is not None else 3.0)


@dataclass(frozen=True, eq=False)
class ReferenceEdges:
    """A reference view's edge points.

    Attributes
    ----------
    pixel : (M, 2)
        Sub-pixel ``(x, y)`` in the undistorted reference image.
    grid : int (M, 2)
        The pixel ``(x, y)`` each was found at.
    normal : (M, 2)
        Unit gradient direction (dark to bright).
    peak : (M, 2) or None
        The gradient's peaks, if a two-step fit moved `pixel` (for fits of two views).
    """

    pixel: _F
    grid: NDArray[np.intp]
    normal: _F
    peak: _F | None = None

    def __len__(self) -> int:
        return int(self.pixel.shape[0])

    def subset(self, keep: NDArray[np.bool_]) -> ReferenceEdges:
        return ReferenceEdges(self.pixel[keep], self.grid[keep], self.normal[keep],
                              None if self.peak is None else self.peak[keep])


def reference_edges(views: PreparedViews, ref: int, threshold: float,
                    border: int, lines: int = 2) -> ReferenceEdges:
    """Edge points of view `ref` on the pixel grid (``|grad| >= threshold`` in the
    smoothed image), each placed on the fine gradient's peak (within a pixel, along the
    same grid line; :attr:`PreparedViews.fine_gx`) and averaged along the edge over
    `lines` grid lines either side."""
    rows, cols, sub, axes, gx, gy = grid_edges(views.gx[ref], views.gy[ref],
                                              float(threshold), int(border),
                                              int(lines))
    x = np.where(axes == 0, sub, cols)
    y = np.where(axes == 0, rows, sub)
    mag = np.hypot(gx, gy)
    nx, ny = gx / mag, gy / mag
    if views.fine_gx is not views.gx:
        # the same scan axis as the grid's (the one nearer the normal), a pixel either side
        ex, ey, _, _, found = edge_near(views.fine_gx[ref], views.fine_gy[ref],
                                        x.astype(float), y.astype(float), nx, ny, 1,
                                        float(threshold) / 4.0, int(border), int(lines))
        x = np.where(found, ex, x)
        y = np.where(found, ey, y)
    pixel = peak = np.column_stack([x, y]).astype(float)
    if views.grey is not None and views.blur is not None:
        pixel = two_step_edges(views.grey[ref], pixel, np.column_stack([nx, ny]),
                               lambda: float(views.blurs(threshold)[ref]),
                               reach_px=views.opposite_px,
                               threshold=float(threshold))[0]
    return ReferenceEdges(pixel, np.column_stack([cols, rows]).astype(np.intp),
                          np.column_stack([nx, ny]), peak if pixel is not peak else None)


def ray_directions(views: PreparedViews, ref: int, pixel: _F) -> _F:
    """World directions ``d`` with ``C + d / rho`` at depth ``1 / rho`` along the
    reference's optical axis, shape (M, 3)."""
    hom = np.column_stack([pixel, np.ones(len(pixel))]) @ views.K_inv.T
    return hom @ views.R[ref].T


def projection_terms(views: PreparedViews, ref: int, others: NDArray[np.intp],
                     rays: _F) -> tuple[_F, _F]:
    """``a, b`` (M, V, 3): the ray's point at ``rho`` projects to ``(a + rho b)`` (homog.)."""
    KR = views.K @ np.transpose(views.R[others], (0, 2, 1))  # (V, 3, 3)
    a = np.einsum("vij,mj->mvi", KR, rays)
    b = np.einsum("vij,vj->vi", KR, views.C[ref] - views.C[others])
    return a, np.broadcast_to(b[None], a.shape).copy()


def depth_plane_maps(views: PreparedViews, ref: int, others: NDArray[np.intp],
                     pixel: _F, rho: float) -> _F:
    """The depth plane's local map of reference pixel offsets to each view's, (M, V, 2, 2)."""
    out = np.empty((len(pixel), len(others), 2, 2))
    base = None
    for c, step in enumerate(((1.0, 0.0), (0.0, 1.0), (0.0, 0.0))):
        p = pixel + np.array(step)
        world = views.C[ref] + ray_directions(views, ref, p) / rho
        uv = np.stack([views.project(world, int(j))[0] for j in others], axis=1)  # (M, V, 2)
        if c < 2:
            out[:, :, :, c] = uv
        else:
            base = uv
    assert base is not None
    return out - base[:, :, :, None]


def bilinear(img: NDArray[np.float32], x: _F, y: _F) -> _F:
    """`img` (H, W) at the points ``(x, y)`` (any shape), bilinear, clipped to the image."""
    h, w = img.shape
    x, y = np.clip(x, 0, w - 1.001), np.clip(y, 0, h - 1.001)
    x0, y0 = np.floor(x).astype(np.intp), np.floor(y).astype(np.intp)
    fx, fy = x - x0, y - y0
    a = img[y0, x0] * (1 - fx) + img[y0, x0 + 1] * fx
    b = img[y0 + 1, x0] * (1 - fx) + img[y0 + 1, x0 + 1] * fx
    return a * (1 - fy) + b * fy


@dataclass(frozen=True, eq=False)
class RayMatches:
    """The search along each reference ray.

    Attributes
    ----------
    others : int (V,)
        The other views.
    rho : (M,)
        Best inverse depth, 1/mm.
    costs : (M, V)
        Each other view's ``1 - ZNCC`` at `rho` (NaN: not visible).
    combined : (M,)
        The robust combined cost at `rho` (mean of the best half).
    kept : (M,)
        The largest cost among the views that voted at `rho`.
    distinct : (M,)
        Combined cost at the best depth over that of the best depth at least three
        steps away (1: ambiguous, small: distinct).
    affine : (M, V, 2, 2)
        The depth plane's local map of reference pixel offsets to each view's.
    """

    others: NDArray[np.intp]
    rho: _F
    costs: _F
    combined: _F
    kept: _F
    distinct: _F
    affine: _F


def epipolar_sines(a: _F, b: _F, aff: _F, normal: _F, rho: float) -> _F:
    """``|sin|`` of the angle between each point's edge and its epipolar line in each
    view, shape (M, V): the edge normal carried over by the depth plane's map against
    the direction in which the point moves with its depth."""
    h = a + rho * b
    with np.errstate(all="ignore"):
        move = (b[:, :, :2] * h[:, :, 2:3] - h[:, :, :2] * b[:, :, 2:3]) / h[:, :, 2:3] ** 2
        move /= np.linalg.norm(move, axis=2, keepdims=True)
        inv_t = np.linalg.inv(aff + 1e-12 * np.eye(2)).transpose(0, 1, 3, 2)
        n = np.einsum("mvij,mj->mvi", inv_t, normal)
        n /= np.linalg.norm(n, axis=2, keepdims=True)
        out = np.abs(np.einsum("mvi,mvi->mv", n, move))
    return np.where(np.isfinite(out), out, 0.0)


def search_rays(views: PreparedViews, ref: int, edges: ReferenceEdges,
                depth_range: tuple[float, float], *, half_window: int,
                step_px: float, min_sine: float = 0.0, combine: str = "best-half",
                coarse_px: float = 2.0) -> RayMatches:
    """Search each edge point's ray in inverse depth and combine the views robustly.

    Notes
    -----
    1. Inverse depths from ``1 / far`` to ``1 / near`` in steps that move the point at
       most `coarse_px` in the view farthest from the reference; then, about each
       point's best one, steps of `step_px` over a coarse step either side.
    2. The reference window (``2 half_window + 1`` square) of each edge point, zero
       mean and unit norm; in each other view the window through the depth plane's
       local affine map at each depth, scored ``1 - ZNCC``
       (:func:`~robostereo.robot.views.views_kernels.sweep_costs`); a window with a
       sample within :data:`SMOOTH_REACH` pixels of a view's border is not scored
       there (the reference's own window keeps that margin: an edge point near the
       top of an image is measured by views beside it, not only by those below it).
    3. Views in which the edge runs within ``asin(min_sine)`` of the epipolar line
       (:func:`epipolar_sines`) do not vote: their window slides along the edge and
       fits at every depth.
    4. At each depth the views' costs are combined by the mean of the best half of the
       views that see the window (Kang, Szeliski & Chai 2001): a view in which the
       point is occluded scores badly and is among the worse half, so it does not
       vote; the best depth minimises the combination.
    """
    n = views.smoothed.shape[0]
    others = np.array([j for j in range(n) if j != ref], dtype=np.intp)
    m = len(edges)
    near, far = depth_range
    f = float(views.K[0, 0])
    reach = float(np.max(np.linalg.norm(views.C[others] - views.C[ref], axis=1)))
    drho = step_px / (f * reach)
    r = np.arange(-half_window, half_window + 1, dtype=float)
    ox, oy = np.meshgrid(r, r)
    offs = np.column_stack([ox.ravel(), oy.ravel()])
    px = edges.pixel
    patch = bilinear(views.smoothed[ref], px[:, 0:1] + offs[None, :, 0],
                      px[:, 1:2] + offs[None, :, 1])
    patch = patch - patch.mean(axis=1, keepdims=True)
    norm = np.linalg.norm(patch, axis=1, keepdims=True)
    patch = np.where(norm > 1e-9, patch / np.maximum(norm, 1e-9), 0.0).astype(np.float32)
    rays = ray_directions(views, ref, px)
    a, b = projection_terms(views, ref, others, rays)
    aff = depth_plane_maps(views, ref, others, px, 2.0 / (near + far))
    # -- a view along whose epipolar line the edge runs cannot tell depths apart: no vote
    mute = epipolar_sines(a, b, aff, edges.normal, 2.0 / (near + far)) < min_sine
    ratio = max(coarse_px / step_px, 1.0)
    grid = np.arange(1.0 / far, 1.0 / near + drho * ratio, drho * ratio)
    sweep = (views.smoothed, patch, offs, others.astype(np.int64), a, b, aff)
    costs, comb, srt, keep = _sweep(sweep, np.broadcast_to(grid, (m, len(grid))).copy(),
                                    mute, half_window, combine)
    k = np.argmin(comb, axis=1) if m else np.zeros(0, np.intp)
    best = comb[np.arange(m), k]
    far_k = np.abs(np.arange(len(grid))[None, :] - k[:, None]) >= 3
    second = np.where(far_k, comb, np.inf).min(axis=1)
    rho = grid[k]
    if ratio > 1.0 and m:
        # -- then the fine steps within a coarse step either side of the coarse best
        half = int(np.ceil(ratio))
        fine = rho[:, None] + drho * np.arange(-half, half + 1)[None, :]
        fine = np.clip(fine, 0.5 / far, None)
        costs, comb, srt, keep = _sweep(sweep, fine, mute, half_window, combine)
        k = np.argmin(comb, axis=1)
        best = comb[np.arange(m), k]
        rho = fine[np.arange(m), k]
    kept = srt[np.arange(m), keep[np.arange(m), k] - 1, k]  # the worst view that voted
    with np.errstate(divide="ignore", invalid="ignore"):
        distinct = np.where(np.isfinite(second) & (second > 0), best / second, 1.0)
    return RayMatches(others=others, rho=rho, costs=costs[np.arange(m), :, k],
                      combined=best, kept=kept, distinct=np.clip(distinct, 0.0, 1.0),
                      affine=aff)


def _sweep(sweep: tuple[Any, ...], rho: _F, mute: NDArray[np.bool_], half_window: int,
           combine: str) -> tuple[_F, _F, _F, NDArray[np.intp]]:
    """Costs (M, V, K) at each point's inverse depths `rho` (M, K), their combination
    (M, K), the views' sorted costs and how many voted."""
    costs = sweep_costs(*sweep, rho, SMOOTH_REACH, mute)
    c = np.where(np.isnan(costs), np.inf, costs.astype(np.float64))  # (M, V, K)
    srt = np.sort(c, axis=1)
    seen = np.isfinite(srt).sum(axis=1)  # (M, K)
    keep = np.maximum((seen + 1) // 2, 1) if combine == "best-half" else np.maximum(seen, 1)
    csum = np.cumsum(np.where(np.isfinite(srt), srt, 0.0), axis=1)
    comb = np.take_along_axis(csum, (keep - 1)[:, None, :], axis=1)[:, 0, :] / keep
    return costs, np.where(seen > 0, comb, np.inf), srt, keep


@dataclass(frozen=True, eq=False)
class RefinedPoints:
    """Points refined by least squares over the views that agree.

    Attributes
    ----------
    world : (M, 3)
    depth : (M,)
        Depth along the reference's optical axis, mm.
    used : bool (M, V)
        The other views whose edge point agreed and entered the fit.
    seen : bool (M, V)
        The other views whose edge point lies within ``reject_px`` of the fitted point
        (the used ones and those dropped for a bias the others do not share).
    used_reference : bool (M,)
        Whether the reference's own edge point stayed in the fit.
    edge : (M, V, 2)
        Each other view's sub-pixel edge point (undistorted pixels; NaN if none).
    residual_rms : (M,)
        RMS of the normal residuals over the reference and the used views, px.
    rho_std_unit : (M,)
        ``sqrt((J^T J)^-1)`` for the inverse depth, per pixel of residual (1/mm/px).
    epipolar_sine : (M,)
        Largest ``|sin|`` of the angle between the edge and the epipolar direction over
        the used views (0: the edge runs along every epipolar line).
    ok : bool (M,)
        At least one other view used and the fit determined.
    """

    world: _F
    depth: _F
    used: NDArray[np.bool_]
    seen: NDArray[np.bool_]
    used_reference: NDArray[np.bool_]
    edge: _F
    residual_rms: _F
    rho_std_unit: _F
    epipolar_sine: _F
    ok: NDArray[np.bool_]


def _residuals(views: PreparedViews, ref: int, others: NDArray[np.intp], e_ref: _F,
               n_ref: _F, edge: _F, normal: _F, t: _F, rho: _F) -> _F:
    """Normal residuals (M, V) of the other views for the point ``(t, rho)``
    (:func:`~robostereo.robot.views.views_kernels.normal_residuals`)."""
    def f(x: _F) -> _F:
        return np.ascontiguousarray(x, dtype=np.float64)

    return normal_residuals(  # type: ignore[no-any-return]
        f(e_ref), f(n_ref), f(t), f(rho), views.K_inv, views.R[ref], views.C[ref],
        views.R[others], views.C[others], views.K, f(edge), f(normal))


class _Fit:
    """Gauss-Newton in ``(t, rho)`` over the reference's residual ``t`` and the views'."""

    eps_t, eps_r = 1e-3, 1e-9

    def __init__(self, views: PreparedViews, ref: int, others: NDArray[np.intp], e_ref: _F,
                 n_ref: _F, edge: _F, normal: _F, t: _F, rho: _F) -> None:
        self.args = (views, ref, others, e_ref, n_ref, edge, normal)
        self.t, self.rho = t, rho
        self.J = np.zeros((*edge.shape[:2], 2))
        self.r = np.zeros(edge.shape[:2])

    def solve(self, used: NDArray[np.bool_], use_ref: NDArray[np.bool_],
              iterations: int) -> None:
        a, t, rho = self.args, self.t, self.rho
        w = used.astype(float)
        for _ in range(iterations):
            r = _residuals(*a, t, rho)
            self.J[:, :, 0] = (_residuals(*a, t + self.eps_t, rho) - r) / self.eps_t
            self.J[:, :, 1] = (_residuals(*a, t, rho + self.eps_r) - r) / self.eps_r
            J = self.J
            JtJ = np.einsum("mv,mvi,mvj->mij", w, J, J)
            JtJ[:, 0, 0] += use_ref  # the reference's residual t
            Jtr = np.einsum("mv,mvi,mv->mi", w, J, r)
            Jtr[:, 0] += use_ref * t
            det = JtJ[:, 0, 0] * JtJ[:, 1, 1] - JtJ[:, 0, 1] ** 2
            good = det > 1e-30
            safe = np.where(good, det, 1.0)
            dt = -(JtJ[:, 1, 1] * Jtr[:, 0] - JtJ[:, 0, 1] * Jtr[:, 1]) / safe
            dr = -(-JtJ[:, 0, 1] * Jtr[:, 0] + JtJ[:, 0, 0] * Jtr[:, 1]) / safe
            t = np.where(good, t + dt, t)
            rho = np.where(good & (rho + dr > 0), rho + dr, rho)
        self.t, self.rho = t, rho
        self.r = _residuals(*a, t, rho)


def refine_points(views: PreparedViews, ref: int, edges: ReferenceEdges, rays: RayMatches,
                  *, max_window_cost: float, threshold: float, reject_px: float,
                  border: int, lines: int = 2, drop_sigmas: float = 4.0,
                  iterations: int = 4
                  ) -> RefinedPoints:
    """Each view's edge point near the best depth, and the least-squares 3-D point.

    Notes
    -----
    1. Candidate views: those that see the window at the best depth with ``1 - ZNCC``
       at most twice the worst of the views that voted (or :data:`KEPT_FLOOR`) and at
       most `max_window_cost`: a view where the point is hidden fits worse.
    2. In each, the sub-pixel edge point nearest the predicted position, on the pixel
       grid, whose gradient points along the reference normal carried over by the depth
       plane's map (:func:`~robostereo.robot.views.views_kernels.edge_near`).
    3. Unknowns ``(t, rho)``: the point on the ray through ``e_ref + t n_ref`` at inverse
       depth ``rho``.  Residuals: ``t`` in the reference and ``n_j . (pi_j(P) - e_j)``
       in each view (its edge's normal distance, the only direction an edge point
       measures).  Gauss-Newton; then views with ``|residual| > reject_px`` are dropped
       and the fit repeated.
    """
    others = rays.others
    m, nv = len(edges), len(others)
    e_ref, n_ref = edges.pixel, edges.normal
    rho = rays.rho.copy()
    world = views.C[ref] + ray_directions(views, ref, e_ref) / rho[:, None]
    edge = np.full((m, nv, 2), np.nan)
    peak = edge.copy()  # the gradient's peaks, before any two-step fit
    normal = np.zeros((m, nv, 2))
    # views that fit about as well as the ones that voted (a hidden view fits worse)
    like = np.maximum(2.0 * rays.kept, KEPT_FLOOR)[:, None]
    cand = np.isfinite(rays.costs) & (rays.costs <= np.minimum(like, max_window_cost))
    carried = carried_normals(rays.affine, n_ref)  # (M, V, 2)
    for v, j in enumerate(others):
        uv, z = views.project(world, int(j))
        npred = carried[:, v]
        sel = cand[:, v] & (z > 0) & np.isfinite(npred).all(axis=1)
        idx = np.nonzero(sel)[0]
        ex, ey, gx, gy, found = edge_near(views.fine_gx[j], views.fine_gy[j], uv[idx, 0],
                                          uv[idx, 1],
                                          npred[idx, 0], npred[idx, 1], 2, threshold / 2.0,
                                          border, lines)
        g = np.column_stack([gx, gy])
        gn = g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-12)
        agree = found & (np.einsum("mi,mi->m", gn, npred[idx]) >= math.cos(math.radians(30)))
        ii = idx[agree]
        pts = peak[ii, v] = np.column_stack([ex, ey])[agree]
        if views.grey is not None and views.blur is not None and len(ii):
            pts = two_step_edges(views.grey[j], pts, gn[agree],
                                 lambda j=j: float(views.blurs(threshold)[j]),
                                 reach_px=views.opposite_px, threshold=threshold)[0]
        edge[ii, v] = pts
        normal[ii, v] = gn[agree]
    used = np.isfinite(edge[:, :, 0])
    use_ref = np.ones(m, bool)
    e = np.nan_to_num(edge)
    fit = _Fit(views, ref, others, e_ref, n_ref, e, normal, np.zeros(m), rho)
    fit.solve(used, use_ref, iterations)
    # gross outliers: an edge point of another surface
    used &= np.abs(fit.r) <= reject_px
    fit.solve(used, use_ref, 2)
    # then, one at a time, the view that disagrees most with the others, while its
    # residual stands out of the residuals' spread (an edge point moved by a
    # neighbouring edge, e.g. a side face seen edge-on) and three or more remain
    for _ in range(nv - 1):
        res = np.concatenate([fit.t[:, None], fit.r], axis=1)
        mask = np.concatenate([use_ref[:, None], used], axis=1)
        n_used = mask.sum(axis=1)
        pool = np.abs(res[mask & (n_used >= 3)[:, None]])
        if pool.size < 10:
            break
        sigma = 1.4826 * float(np.median(pool))
        worst = np.argmax(np.where(mask, np.abs(res), -1.0), axis=1)
        big = np.abs(res[np.arange(m), worst]) > drop_sigmas * sigma
        drop = big & (n_used >= 3)
        if not drop.any():
            break
        rows = np.nonzero(drop)[0]
        col = worst[rows]
        use_ref[rows[col == 0]] = False
        used[rows[col > 0], col[col > 0] - 1] = False
        fit.solve(used, use_ref, 2)
    # a fit of two views has no residual to reveal a wrong two-step model: the peaks
    ref_peak = edges.peak if edges.peak is not None else e_ref
    two = (used.sum(axis=1) + use_ref <= 2) & ((np.nansum(np.abs(peak - edge), axis=(1, 2)) > 0)
                                               | np.any(ref_peak != e_ref, axis=1))
    if two.any():
        e_ref = np.where(two[:, None], ref_peak, e_ref)
        sub = _Fit(views, ref, others, e_ref[two], n_ref[two], np.nan_to_num(peak[two]),
                   normal[two], fit.t[two], fit.rho[two])
        sub.solve(used[two], use_ref[two], iterations)
        fit.t[two], fit.rho[two], fit.r[two], fit.J[two] = sub.t, sub.rho, sub.r, sub.J
    t, rho, r, J = fit.t, fit.rho, fit.r, fit.J
    w = used.astype(float)
    JtJ = np.einsum("mv,mvi,mvj->mij", w, J, J)
    JtJ[:, 0, 0] += use_ref
    det = JtJ[:, 0, 0] * JtJ[:, 1, 1] - JtJ[:, 0, 1] ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        rho_std = np.sqrt(np.where(det > 1e-30, JtJ[:, 0, 0] / det, np.inf))
        k = used.sum(axis=1)
        rms = np.sqrt((np.sum(w * r**2, axis=1) + use_ref * t**2) / (k + use_ref))
    eps_r = fit.eps_r
    p = e_ref + t[:, None] * n_ref
    world = views.C[ref] + ray_directions(views, ref, p) / rho[:, None]
    world2 = views.C[ref] + ray_directions(views, ref, p) / (rho + eps_r)[:, None]
    sine = np.zeros(m)
    for v, j in enumerate(others):
        # the edge against the epipolar direction: d(residual)/d(rho) over the image speed
        speed = np.linalg.norm(views.project(world2, int(j))[0]
                               - views.project(world, int(j))[0], axis=1) / eps_r
        with np.errstate(divide="ignore", invalid="ignore"):
            sv = np.abs(J[:, v, 1]) / speed
        sine = np.maximum(sine, np.where(used[:, v] & np.isfinite(sv), sv, 0.0))
    ok = (k + use_ref >= 2) & np.isfinite(rho_std) & (rho > 0)
    seen = np.isfinite(edge[:, :, 0]) & (np.abs(r) <= reject_px)
    return RefinedPoints(world=world, depth=1.0 / rho, used=used, seen=seen,
                         used_reference=use_ref,
                         edge=edge,
                         residual_rms=rms, rho_std_unit=rho_std, epipolar_sine=sine, ok=ok)


def carried_normals(affine: _F, normal: _F) -> _F:
    """The reference's edge normals (M, 2) carried into each other view by the depth
    plane's map `affine` (M, V, 2, 2; gradients map with its inverse transpose), unit,
    shape (M, V, 2)."""
    with np.errstate(all="ignore"):
        inv_t = np.linalg.inv(affine + 1e-12 * np.eye(2)).transpose(0, 1, 3, 2)
        n = np.einsum("mvij,mj->mvi", inv_t, normal)
        return n / np.maximum(np.linalg.norm(n, axis=2, keepdims=True), 1e-12)
