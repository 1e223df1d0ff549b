"""The last stage of the N-view search: each 3-D point refined over the views that agree.

:func:`refine_points` takes the best depth of each reference edge point
(:func:`~robostereo.robot.views.ray_search.search_rays`), finds each view's sub-pixel
edge point near it and fits the 3-D point by least squares over the views whose edge
points agree (Gauss-Newton in the reference's normal offset and the inverse depth),
dropping the views that disagree; the fit's spread gives the point's bound
(:func:`~robostereo.robot.views.located_points.views_bound`, eq. 9 generalised).

References
----------
Kim (1989), the thesis, 3.6-3.7; M. Okutomi and T. Kanade, "A multiple-baseline
stereo", IEEE PAMI 15(4), 1993.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.robot.views.edge_profiles import two_step_edges
from robostereo.robot.views.prepared_views import PreparedViews, ReferenceEdges
from robostereo.robot.views.ray_search import RayMatches, carried_normals, ray_directions
from robostereo.robot.views.views_kernels import edge_near, normal_residuals

__all__ = [
    "RefinedPoints",
    "refine_points",
]

_F = NDArray[np.float64]

KEPT_FLOOR = 0.1
"""Window cost (``1 - ZNCC``) a view may always have to enter the fit: below it a
window fits well whatever the other views do."""


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
