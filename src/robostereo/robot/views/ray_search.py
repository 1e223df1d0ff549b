"""The N-view search: each reference edge point's ray searched in inverse depth.

:func:`robostereo.robot.views.locating.locate_views` runs :func:`search_rays` for each
reference view, between preparing the views
(:mod:`~robostereo.robot.views.prepared_views`) and refining the points
(:mod:`~robostereo.robot.views.point_refinement`): each edge point's ray searched in
inverse depth [1]_, every other view's window scored
(:func:`~robostereo.robot.views.views_kernels.sweep_costs`) and the views combined
robustly (the best half [2]_).  With it, the geometry of a reference ray in the other
views: its directions (:func:`ray_directions`), its projections (:func:`projection_terms`),
the depth plane's local maps (:func:`depth_plane_maps`) and the edge normals they carry
(:func:`carried_normals`, :func:`epipolar_sines`).

The checks by the views' edges (the views left out of a fit, and the edge points the
window search leaves) are in :mod:`~robostereo.robot.views.edge_votes`.

References
----------
.. [1] M. Okutomi and T. Kanade, "A multiple-baseline stereo", IEEE PAMI 15(4), 1993.
.. [2] S. B. Kang, R. Szeliski and J. Chai, "Handling occlusions in dense multi-view
   stereo", CVPR 2001.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.matcher.parallel import n_threads, run_all
from robostereo.robot.views.prepared_views import PreparedViews, ReferenceEdges
from robostereo.robot.views.views_kernels import sweep_costs

__all__ = [
    "RayMatches",
    "bilinear",
    "carried_normals",
    "depth_plane_maps",
    "epipolar_sines",
    "projection_terms",
    "ray_directions",
    "search_rays",
]

_F = NDArray[np.float64]

SMOOTH_REACH = 2.0
"""Least distance (pixels) of a window sample from an image's border: the half-width of
the thesis's 5 x 5 smoothing filter, within which the smoothed grey levels are
reflections of the image's inside rather than its content.  A reference edge point
lies ``half_window + 2`` pixels inside, so its own window keeps this margin too."""


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
    rho_second : (M,)
        That next best inverse depth, 1/mm (NaN: none searched).
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
    rho_second: _F


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
    comb, costs, kept = _sweep(sweep, np.broadcast_to(grid, (m, len(grid))), mute,
                               combine)
    k = np.argmin(comb, axis=1) if m else np.zeros(0, np.intp)
    best = comb[np.arange(m), k]
    # the best depth three or more steps away
    rows = np.arange(m)
    for d in range(-2, 3):
        near_k = k + d
        inside = (near_k >= 0) & (near_k < len(grid))
        comb[rows[inside], near_k[inside]] = np.inf
    second = comb.min(axis=1)  # the grid holds 1 / far at least
    rho_second = grid[np.argmin(comb, axis=1)] if m else np.zeros(0)
    rho = grid[k]
    if ratio > 1.0 and m:
        # -- then the fine steps within a coarse step either side of the coarse best
        half = int(np.ceil(ratio))
        fine = rho[:, None] + drho * np.arange(-half, half + 1)[None, :]
        fine = np.clip(fine, 0.5 / far, None)
        comb, costs, kept = _sweep(sweep, fine, mute, combine)
        k = np.argmin(comb, axis=1)
        best = comb[np.arange(m), k]
        rho = fine[np.arange(m), k]
    with np.errstate(divide="ignore", invalid="ignore"):
        distinct = np.where(np.isfinite(second) & (second > 0), best / second, 1.0)
    return RayMatches(others=others, rho=rho, costs=costs, combined=best, kept=kept,
                      distinct=np.clip(distinct, 0.0, 1.0), affine=aff,
                      rho_second=rho_second)


SWEEP_CHUNK_COSTS = 1 << 21
"""Most window costs (points x views x depths) :func:`_sweep` holds at once, over all
its threads: its working arrays then stay near 100 MB however many edge points a
reference has and however many cores score them (on eight real DTU views at 800 x 600,
a coarse sweep of every point at once took 2.8 GB)."""


def _sweep(sweep: tuple[Any, ...], rho: _F, mute: NDArray[np.bool_], combine: str
           ) -> tuple[_F, NDArray[np.float32], _F]:
    """The views' costs at each point's inverse depths `rho` (M, K) combined (M, K); at
    each point's best depth, every view's cost (M, V; NaN where not scored) and the
    worst cost that voted (M,).  Points are scored in chunks of at most
    :data:`SWEEP_CHUNK_COSTS` costs shared among the matcher's threads
    (:func:`~robostereo.matcher.parallel.run_all`; each point's result is its own)."""
    images, patch, offs, others, a, b, aff = sweep
    m, n_k = rho.shape
    n_v = len(others)
    comb = np.empty((m, n_k))
    at_best = np.empty((m, n_v), np.float32)
    kept = np.empty(m)

    def chunk(s: slice) -> None:
        costs = sweep_costs(images, patch[s], offs, others, a[s], b[s], aff[s],
                            np.ascontiguousarray(rho[s]), SMOOTH_REACH, mute[s])
        c = np.where(np.isnan(costs), np.inf, costs.astype(np.float64))  # (m, V, K)
        srt = np.sort(c, axis=1)
        seen = np.isfinite(srt).sum(axis=1)  # (m, K)
        keep = (np.maximum((seen + 1) // 2, 1) if combine == "best-half"
                else np.maximum(seen, 1))
        csum = np.cumsum(np.where(np.isfinite(srt), srt, 0.0), axis=1)
        part = np.take_along_axis(csum, (keep - 1)[:, None, :], axis=1)[:, 0, :] / keep
        part = np.where(seen > 0, part, np.inf)
        comb[s] = part
        i = np.arange(len(part))
        k = np.argmin(part, axis=1)
        at_best[s] = costs[i, :, k]
        kept[s] = srt[i, keep[i, k] - 1, k]  # the worst view that voted

    threads = n_threads()
    step = max(min(SWEEP_CHUNK_COSTS // max(threads * n_v * n_k, 1), -(-m // threads)), 1)
    run_all([lambda s=slice(lo, lo + step): chunk(s) for lo in range(0, m, step)])
    return comb, at_best, kept


def carried_normals(affine: _F, normal: _F) -> _F:
    """The reference's edge normals (M, 2) carried into each other view by the depth
    plane's map `affine` (M, V, 2, 2; gradients map with its inverse transpose), unit,
    shape (M, V, 2)."""
    with np.errstate(all="ignore"):
        inv_t = np.linalg.inv(affine + 1e-12 * np.eye(2)).transpose(0, 1, 3, 2)
        n = np.einsum("mvij,mj->mvi", inv_t, normal)
        return n / np.maximum(np.linalg.norm(n, axis=2, keepdims=True), 1e-12)
