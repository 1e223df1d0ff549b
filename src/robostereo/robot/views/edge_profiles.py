"""Sub-pixel edge positions beside an edge of opposite polarity: two blurred steps fitted.

The thesis places an edge at the peak of the gradient magnitude (3.1-3.2, a parabola
through it and its neighbours).  Where a second edge of opposite polarity runs within a
few pixels (a thin bright bar, a narrow dark gap, a ring seen just below an occluding
rim) the two gradients overlap through the camera's blur, and the peak of each is pushed
away from the other, by an amount that changes with the gap's width and so with the
viewpoint.  Across the edge, the grey profile of such a pair is two blurred steps:

    I(s) = a + b1 Phi((s - s1) / sigma) + b2 Phi((s - s2) / sigma)

with ``Phi`` the normal distribution function and ``sigma`` the camera's blur, estimated
once per image from its isolated edges (:func:`estimate_blur`).  :func:`two_step_edges`
fits it along each edge point's normal and returns the fitted position of the point's
own step where the fit is good.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.matcher.parallel import n_threads, run_all
from robostereo.robot.views.edge_profile_kernels import (
    fit_one_step_kernel,
    fit_two_steps_kernel,
    opposite_edges,
)
from robostereo.robot.views.views_kernels import grid_edges

__all__ = [
    "PROFILE_HALF_PX",
    "TwoStepFit",
    "estimate_blur",
    "fit_one_step",
    "fit_two_steps",
    "profiles",
    "two_step_edges",
    "view_blurs",
]

_F = NDArray[np.float64]

PROFILE_HALF_PX = 5
"""Pixels of a profile either side of the edge point, on each grid line."""


def profiles(grey: NDArray[np.float32], points: _F, normals: _F, *,
             half_px: int = PROFILE_HALF_PX, along: int = 2) -> tuple[_F, _F]:
    """Grey levels across edges: the pixels themselves, by their distance along the normal.

    Parameters
    ----------
    grey : ndarray, shape (H, W)
        The image (not smoothed).
    points, normals : ndarray, shape (M, 2)
        Edge points ``(x, y)`` and unit normals (dark to bright).
    half_px : int
        Pixels either side of the edge on each grid line (rows for normals nearer x,
        else columns).
    along : int
        Grid lines either side of the point's, along the edge.

    Returns
    -------
    s : ndarray, shape (M, S)
        Each sample's signed distance from the edge along the normal, pixels
        (``S = (2 along + 1) (2 half_px + 1)``; the central line's samples first).
    prof : ndarray, shape (M, S)
        The grey levels of those pixels (no interpolation: a pixel is a sample of the
        blurred image, which interpolation would blur again by an amount that depends
        on the sub-pixel phase).
    """
    h, w = grey.shape
    p = np.asarray(points, float)
    n = np.asarray(normals, float)
    rows = np.abs(n[:, 0]) >= np.abs(n[:, 1])
    # scan axis u (x for rows) and line axis v; the edge's u on line v0 + k
    u0 = np.where(rows, p[:, 0], p[:, 1])
    v0 = np.rint(np.where(rows, p[:, 1], p[:, 0]))
    nu = np.where(rows, n[:, 0], n[:, 1])
    nv = np.where(rows, n[:, 1], n[:, 0])
    dv0 = v0 - np.where(rows, p[:, 1], p[:, 0])
    ks = [0] + [k for j in range(1, along + 1) for k in (-j, j)]
    j = np.arange(-half_px, half_px + 1)
    s_parts, g_parts = [], []
    for k in ks:
        dv = dv0 + k
        uc = u0 - nv / nu * dv  # where the edge crosses this line
        uu = np.rint(uc)[:, None] + j[None, :]
        vv = np.broadcast_to((v0 + k)[:, None], uu.shape)
        s_parts.append((uu - u0[:, None]) * nu[:, None] + dv[:, None] * nv[:, None])
        xx = np.where(rows[:, None], uu, vv)
        yy = np.where(rows[:, None], vv, uu)
        xi = np.clip(xx, 0, w - 1).astype(np.intp)
        yi = np.clip(yy, 0, h - 1).astype(np.intp)
        g_parts.append(grey[yi, xi].astype(float))
    return np.concatenate(s_parts, axis=1), np.concatenate(g_parts, axis=1)


def fit_one_step(s: _F, prof: _F, iterations: int = 8) -> tuple[_F, _F, _F]:
    """One blurred step ``a + b Phi((s - s0) / sigma)`` fitted to each profile.

    Parameters
    ----------
    s : ndarray, shape (M, S)
        The samples' offsets along the normal (:func:`profiles`).
    prof : ndarray, shape (M, S)
        Their grey levels.
    iterations : int
        Damped Gauss-Newton steps.

    Returns
    -------
    s0, sigma, rms : ndarray, shape (M,)
        The step's position and blur, pixels, and the residuals' RMS, grey levels; NaN
        where the fit failed (``sigma`` at a bound of [0.2, 3] or no finite residual).
        Fitted one profile at a time
        (:func:`~robostereo.robot.views.edge_profile_kernels.fit_one_step_kernel`).
    """
    if not (isinstance(iterations, int) and iterations >= 0):
        raise InputError(f"iterations must be a non-negative integer, got {iterations!r}")
    s = np.ascontiguousarray(s, dtype=np.float64)
    prof = np.ascontiguousarray(prof, dtype=np.float64)
    if s.ndim != 2 or s.shape != prof.shape or s.shape[1] < 4:
        raise InputError(f"s and prof must be (M, S) arrays of one shape with S >= 4, got "
                         f"{s.shape} and {prof.shape}")
    if not len(s):
        return np.empty(0), np.empty(0), np.empty(0)
    return fit_one_step_kernel(s, prof, iterations)  # type: ignore[no-any-return]


@dataclass(frozen=True, eq=False)
class TwoStepFit:
    """Two blurred steps fitted across each edge (:func:`fit_two_steps`).

    Attributes
    ----------
    own, other : ndarray, shape (M,)
        Positions of the edge's own step and of the opposite one along the normal, px.
    own_height, other_height : ndarray, shape (M,)
        Their heights ``b2, b1`` (grey levels; the own one positive: dark to bright).
    rms : ndarray, shape (M,)
        RMS of the profile's residuals, grey levels.
    """

    own: _F
    other: _F
    own_height: _F
    other_height: _F
    rms: _F


MIN_PROFILES_PER_THREAD = 256
"""Fewest profiles :func:`fit_two_steps` gives a thread (about 6 ms of work): fewer
are fitted on the calling thread."""


def fit_two_steps(s: _F, prof: _F, sigma: float, own: _F, other: _F,
                  iterations: int = 12) -> TwoStepFit:
    """``a + b1 Phi((s - s1) / sigma) + b2 Phi((s - s2) / sigma)`` fitted to each profile.

    Parameters
    ----------
    s : ndarray, shape (M, S)
        The samples' offsets along the normal (:func:`profiles`).
    prof : ndarray, shape (M, S)
        Their grey levels.
    sigma : float
        The blur, pixels (:func:`estimate_blur`).
    own, other : ndarray, shape (M,)
        Starting positions of the two steps (the gradient's peaks).
    iterations : int
        Levenberg-Marquardt steps.

    Returns
    -------
    TwoStepFit
        The positions ``s2`` (own) and ``s1`` (other) by Levenberg-Marquardt, the
        heights and ``a`` solved by least squares at each
        (:func:`~robostereo.robot.views.edge_profile_kernels.fit_two_steps_kernel`).
    """
    s = np.ascontiguousarray(s, dtype=np.float64)
    prof = np.ascontiguousarray(prof, dtype=np.float64)
    own = np.ascontiguousarray(own, dtype=np.float64)
    other = np.ascontiguousarray(other, dtype=np.float64)
    # each profile's fit is its own: shares of them on the matcher's threads
    step = max(-(-len(s) // n_threads()), MIN_PROFILES_PER_THREAD)
    parts = run_all([lambda lo=lo: fit_two_steps_kernel(s[lo:lo + step], prof[lo:lo + step],
                                                        float(sigma), own[lo:lo + step],
                                                        other[lo:lo + step], int(iterations))
                     for lo in range(0, max(len(s), 1), step)])
    o2, o1, h2, h1, rms = (np.concatenate(x) for x in zip(*parts, strict=True))
    return TwoStepFit(own=o2, other=o1, own_height=h2, other_height=h1, rms=rms)


def _opposite_peak(s: _F, prof: _F, reach: float, least: float,
                   width: int = 2 * PROFILE_HALF_PX + 1) -> _F:
    """Offset along the normal of the steepest opposite-polarity slope within `reach` of
    the edge on each profile's central line (:func:`profiles`: its first `width`
    samples); NaN where none reaches `least` grey levels per pixel or it is the line's
    end sloping on."""
    sc, gc = s[:, :width], prof[:, :width]
    ds = np.diff(sc, axis=1)
    slope = np.diff(gc, axis=1) / np.where(ds != 0, ds, 1.0)
    mid = 0.5 * (sc[:, 1:] + sc[:, :-1])
    neg = np.where(np.abs(mid) <= reach, -slope, -np.inf)
    k = np.argmax(neg, axis=1)
    val = neg[np.arange(len(prof)), k]
    inside = (k > 0) & (k < neg.shape[1] - 1)
    return np.where((val >= least) & inside, mid[np.arange(len(prof)), k], np.nan)


def estimate_blur(grey: NDArray[np.float32], points: _F, normals: _F, *,
                  least_height: float = 20.0, max_points: int = 100) -> float:
    """The camera's blur (sigma, pixels) from its isolated straight edges.

    Parameters
    ----------
    grey : ndarray, shape (H, W)
        The image.
    points, normals : ndarray, shape (M, 2)
        Its edge points and unit normals (dark to bright).
    least_height : float
        Least step height (grey levels) of an edge that counts.
    max_points : int
        At most this many edge points, evenly spaced in the list, are fitted.

    Returns
    -------
    float
        The median of the single-step fits' sigma over the edges with no opposite slope
        within the profile and a good fit; NaN if fewer than 20 such edges.

    Notes
    -----
    The fitted sigma includes what the profile's sampling adds (the pixels' area,
    bilinear interpolation, an undistortion's resampling), as the two-step fit sees it.
    """
    if len(points) == 0:
        return math.nan
    take = np.unique(np.linspace(0, len(points) - 1, min(max_points, len(points))).astype(int))
    s, prof = profiles(grey, points[take], normals[take])
    w = 2 * PROFILE_HALF_PX + 1
    height = prof[:, w - 3:w].mean(axis=1) - prof[:, :3].mean(axis=1)
    lonely = np.isnan(_opposite_peak(s, prof, PROFILE_HALF_PX, 0.1 * np.maximum(height, 1)))
    keep = lonely & (height >= least_height)
    if keep.sum() < 20:
        return math.nan
    s0, sig, rms = fit_one_step(s[keep], prof[keep])
    good = np.isfinite(sig) & (np.abs(s0) <= 1.0) & (rms <= 0.1 * height[keep])
    if good.sum() < 20:
        return math.nan
    return float(np.median(sig[good]))


def two_step_edges(grey: NDArray[np.float32], points: _F, normals: _F,
                   sigma: float | Callable[[], float], *,
                   reach_px: float = 3.0, threshold: float = 8.0) -> tuple[_F, NDArray[np.bool_]]:
    """Edge points moved to their step in a fit of two blurred steps, where an edge of
    opposite polarity lies within `reach_px` along the normal.

    Parameters
    ----------
    grey : ndarray, shape (H, W)
        The image (not smoothed) on the thesis's 0..127 scale.
    points, normals : ndarray, shape (M, 2)
        Sub-pixel edge points ``(x, y)`` and unit normals (dark to bright).
    sigma : float or callable
        The image's blur (:func:`estimate_blur`), or a function giving it, called only
        if some point has an opposite edge; NaN: nothing is moved.
    reach_px : float
        Farthest opposite edge that counts, pixels.
    threshold : float
        Least gradient of the opposite edge (grey levels per pixel, half of it counts).

    Returns
    -------
    points : ndarray, shape (M, 2)
        Moved points (the others as given).
    moved : ndarray of bool, shape (M,)

    Notes
    -----
    A point is moved only if the fit is good: both steps keep their polarity, the own
    step stays within 1.5 px of the gradient's peak and the other within `reach_px`
    + 1 of it, at least 0.3 px apart, and the residual RMS is at most a twentieth of the
    smaller step height.
    """
    if not (isinstance(reach_px, int | float) and reach_px > 0):
        raise InputError(f"reach_px must be positive, got {reach_px!r}")
    p = np.asarray(points, float)
    out = p.copy()
    moved = np.zeros(len(p), bool)
    if not len(p):
        return out, moved
    n = np.asarray(normals, float)
    # the opposite edge on the central line first; the whole profile where there is one
    opp = opposite_edges(np.ascontiguousarray(grey, dtype=np.float32), np.ascontiguousarray(p),
                         np.ascontiguousarray(n), PROFILE_HALF_PX, float(reach_px),
                         threshold / 2.0)
    idx = np.nonzero(np.isfinite(opp))[0]
    if not len(idx):
        return out, moved
    sigma = sigma() if callable(sigma) else sigma
    if not np.isfinite(sigma):
        return out, moved
    s, prof = profiles(grey, p[idx], n[idx])
    fit = fit_two_steps(s, prof, float(sigma), np.zeros(len(idx)), opp[idx])
    small = np.minimum(fit.own_height, -fit.other_height)
    good = ((fit.own_height > 0) & (fit.other_height < 0) & (np.abs(fit.own) <= 1.5)
            & (np.abs(fit.other) <= reach_px + 1.0) & (np.abs(fit.other - fit.own) >= 0.3)
            & (fit.rms <= small / 20.0) & np.isfinite(fit.own))
    ii = idx[good]
    out[ii] = p[ii] + fit.own[good, None] * np.asarray(normals, float)[ii]
    moved[ii] = True
    return out, moved


def view_blurs(greys: NDArray[np.float32], gx: NDArray[np.float32], gy: NDArray[np.float32],
               threshold: float) -> _F:
    """Each view's blur from its edge points (:func:`estimate_blur`).

    Parameters
    ----------
    greys : ndarray, shape (N, H, W)
        The views' grey levels, not smoothed.
    gx, gy : ndarray, shape (N, H, W)
        The gradients whose peaks of magnitude at least `threshold` are the edge points
        (the thesis's smoothed images: an isolated edge's peak lies on it).
    threshold : float

    Returns
    -------
    ndarray, shape (N,)
        A view with too few isolated edges takes the median of the others (one camera);
        NaN if no view has enough.
    """
    out = np.full(len(greys), np.nan)
    for i in range(len(greys)):
        pts, nrm = [], []
        # every 6th row's peaks along it, and every 6th column's along it: enough edges
        for flip in (False, True):
            a, b = (gy[i].T, gx[i].T) if flip else (gx[i], gy[i])
            rows, _, sub, axes, ea, eb = grid_edges(np.ascontiguousarray(a[::6]),
                                                    np.ascontiguousarray(b[::6]),
                                                    float(threshold), 1, 0)
            k = axes == 0  # a peak along the line (the other axis is not sampled)
            q = np.column_stack([sub[k], 6.0 * rows[k]])
            g = np.column_stack([ea[k], eb[k]])
            pts.append(q[:, ::-1] if flip else q)
            nrm.append(g[:, ::-1] if flip else g)
        p, g = np.concatenate(pts), np.concatenate(nrm)
        inside = ((p[:, 0] >= 8) & (p[:, 1] >= 8) & (p[:, 0] <= greys.shape[2] - 9)
                  & (p[:, 1] <= greys.shape[1] - 9))
        g = g[inside] / np.maximum(np.hypot(g[inside, 0], g[inside, 1]), 1e-12)[:, None]
        out[i] = estimate_blur(greys[i], p[inside], g)
    if np.isfinite(out).any():
        out = np.where(np.isfinite(out), out, np.nanmedian(out))
    return out
