"""numba kernels of :mod:`robostereo.robot.views.edge_profiles`: blurred steps fitted to grey
profiles across edges, one edge point at a time (Levenberg-Marquardt)."""

from __future__ import annotations

import math

import numpy as np

from robostereo.matcher.jit import kernel

__all__ = ["fit_one_step_kernel", "fit_two_steps_kernel", "opposite_edges"]


@kernel(nogil=True)
def _solve_small(A, r, d, n):  # type: ignore[no-untyped-def]
    """``A d = r`` for one n x n system (n of 3 to 5) by Gaussian elimination with partial
    pivoting (`A`, `r` overwritten); False if a pivot vanishes.  In place: no allocation
    and no LAPACK call, which cost more than the elimination at this size."""
    for c in range(n):
        piv = c
        for i in range(c + 1, n):
            if abs(A[i, c]) > abs(A[piv, c]):
                piv = i
        if not abs(A[piv, c]) > 0.0:
            return False
        if piv != c:
            for j in range(n):
                A[c, j], A[piv, j] = A[piv, j], A[c, j]
            r[c], r[piv] = r[piv], r[c]
        for i in range(c + 1, n):
            f = A[i, c] / A[c, c]
            for j in range(c, n):
                A[i, j] -= f * A[c, j]
            r[i] -= f * r[c]
    for c in range(n - 1, -1, -1):
        x = r[c]
        for j in range(c + 1, n):
            x -= A[c, j] * d[j]
        d[c] = x / A[c, c]
    return True


@kernel(nogil=True)
def _cost(s, g, q, s1, s2, c, e1, e2, A, r):  # type: ignore[no-untyped-def]
    """Least squares of ``a + b1 Phi((s - s1)/sigma) + b2 Phi((s - s2)/sigma)`` for fixed
    ``s1, s2`` (``q = 1 / (sigma sqrt 2)``): the linear coefficients into `c` (3,), each
    step's ``Phi`` at the samples into `e1`, `e2` (S,); returns the sum of squared
    residuals.  `A` (3, 3) and `r` (3,) are work space."""
    k = s.shape[0]
    A[:, :] = 0.0
    r[:] = 0.0
    for i in range(k):
        a1 = 0.5 * math.erfc(-(s[i] - s1) * q)
        a2 = 0.5 * math.erfc(-(s[i] - s2) * q)
        e1[i] = a1
        e2[i] = a2
        r[0] += g[i]
        r[1] += a1 * g[i]
        r[2] += a2 * g[i]
        A[0, 0] += 1.0
        A[0, 1] += a1
        A[0, 2] += a2
        A[1, 1] += a1 * a1
        A[1, 2] += a1 * a2
        A[2, 2] += a2 * a2
    A[1, 0] = A[0, 1]
    A[2, 0] = A[0, 2]
    A[2, 1] = A[1, 2]
    for a in range(3):
        A[a, a] += 1e-9  # positive definite
    _solve_small(A, r, c, 3)
    ss = 0.0
    for i in range(k):
        ss += (g[i] - (c[0] + c[1] * e1[i] + c[2] * e2[i])) ** 2
    return ss


@kernel(nogil=True)
def fit_two_steps_kernel(s, prof, sigma, own, other, iterations):  # type: ignore[no-untyped-def]
    """Two blurred steps fitted to each profile (see
    :func:`robostereo.robot.views.edge_profiles.fit_two_steps`).

    `s`, `prof` (M, S); `own`, `other` (M,) starting positions.  Returns the fitted
    positions of the own and other steps, their heights and the residual RMS (M,) each.
    The steps' ``Phi`` at the current positions are the last accepted cost's (each
    computed once), and the work arrays are allocated once for all profiles."""
    m, k = s.shape
    o_own = np.empty(m)
    o_oth = np.empty(m)
    h_own = np.empty(m)
    h_oth = np.empty(m)
    rms = np.empty(m)
    norm = 1.0 / (sigma * math.sqrt(2.0 * math.pi))
    q = 1.0 / (sigma * math.sqrt(2.0))
    c = np.zeros(3)
    cn = np.zeros(3)
    e1 = np.empty(k)  # each step's Phi at the current positions
    e2 = np.empty(k)
    f1 = np.empty(k)  # and at the trial ones
    f2 = np.empty(k)
    A = np.empty((3, 3))
    r3 = np.empty(3)
    H = np.empty((5, 5))
    gvec = np.empty(5)
    d = np.zeros(5)
    J = np.empty(5)
    for p in range(m):
        si = s[p]
        gi = prof[p]
        lo = si.min()
        hi = si.max()
        s1 = other[p]
        s2 = own[p]
        cost = _cost(si, gi, q, s1, s2, c, e1, e2, A, r3)
        lam = 1e-2
        # Levenberg-Marquardt on (a, b1, b2, s1, s2); the heights then solved again at
        # the new positions (variable projection)
        for _ in range(iterations):
            H[:, :] = 0.0
            gvec[:] = 0.0
            for i in range(k):
                z1 = (si[i] - s1) / sigma
                z2 = (si[i] - s2) / sigma
                r = gi[i] - (c[0] + c[1] * e1[i] + c[2] * e2[i])
                J[0] = 1.0
                J[1] = e1[i]
                J[2] = e2[i]
                J[3] = -c[1] * norm * math.exp(-0.5 * z1 * z1)
                J[4] = -c[2] * norm * math.exp(-0.5 * z2 * z2)
                for a in range(5):
                    gvec[a] += J[a] * r
                    for b in range(a, 5):
                        H[a, b] += J[a] * J[b]
            for a in range(5):
                for b in range(a):
                    H[a, b] = H[b, a]
                H[a, a] += lam * H[a, a] + 1e-9
            if not _solve_small(H, gvec, d, 5):
                break
            n1 = min(max(s1 + d[3], lo), hi)
            n2 = min(max(s2 + d[4], lo), hi)
            new = _cost(si, gi, q, n1, n2, cn, f1, f2, A, r3)
            if new < cost:
                step = max(abs(n1 - s1), abs(n2 - s2))
                s1 = n1
                s2 = n2
                cost = new
                c[:] = cn
                e1[:] = f1
                e2[:] = f2
                lam *= 0.3
                if step < 1e-4:
                    break
            else:
                lam *= 10.0
        o_own[p] = s2
        o_oth[p] = s1
        h_own[p] = c[2]
        h_oth[p] = c[1]
        rms[p] = math.sqrt(cost / k)
    return o_own, o_oth, h_own, h_oth, rms


@kernel(nogil=True)
def fit_one_step_kernel(s, prof, iterations):  # type: ignore[no-untyped-def]
    """One blurred step fitted to each profile (see
    :func:`robostereo.robot.views.edge_profiles.fit_one_step`).

    `s`, `prof` (M, S).  Damped Gauss-Newton on ``(a, b, s0, sigma)`` from ``s0 = 0``,
    ``sigma = 1`` and the mean grey levels within 1.5 px of either end (damping 1e-3 of
    the diagonal; ``s0`` clipped to the samples' span, ``sigma`` to [0.2, 3]).  Returns
    ``s0, sigma`` and the residual RMS (M,) each, NaN where the fit failed."""
    m, k = s.shape
    o_s0 = np.empty(m)
    o_sig = np.empty(m)
    o_rms = np.empty(m)
    q = 1.0 / math.sqrt(2.0)
    norm = 1.0 / math.sqrt(2.0 * math.pi)
    H = np.zeros((4, 4))
    g = np.zeros(4)
    d = np.zeros(4)
    J = np.zeros(4)
    for p in range(m):
        si = s[p]
        gi = prof[p]
        lo_s = si.min()
        hi_s = si.max()
        lo = 0.0
        hi = 0.0
        n_lo = 0
        n_hi = 0
        for i in range(k):
            if si[i] <= lo_s + 1.5:
                lo += gi[i]
                n_lo += 1
            if si[i] >= hi_s - 1.5:
                hi += gi[i]
                n_hi += 1
        lo /= n_lo
        hi /= n_hi
        a = lo
        b = hi - lo
        s0 = 0.0
        sig = 1.0
        for _ in range(iterations):
            H[:, :] = 0.0
            g[:] = 0.0
            for i in range(k):
                z = (si[i] - s0) / sig
                ph = 0.5 * math.erfc(-z * q)
                pd = norm * math.exp(-0.5 * z * z)
                r = gi[i] - (a + b * ph)
                J[0] = 1.0
                J[1] = ph
                J[2] = -b * pd / sig
                J[3] = -b * pd * z / sig
                for u in range(4):
                    g[u] += J[u] * r
                    for v in range(4):
                        H[u, v] += J[u] * J[v]
            for u in range(4):
                H[u, u] += 1e-3 * H[u, u] + 1e-12
            if not _solve_small(H, g, d, 4):
                break
            a += d[0]
            b += d[1]
            s0 = min(max(s0 + d[2], lo_s), hi_s)
            sig = min(max(sig + d[3], 0.2), 3.0)
        ss = 0.0
        for i in range(k):
            ph = 0.5 * math.erfc(-(si[i] - s0) / sig * q)
            ss += (gi[i] - (a + b * ph)) ** 2
        rms = math.sqrt(ss / k)
        if not math.isfinite(rms) or sig <= 0.2 or sig >= 3.0:
            o_s0[p] = o_sig[p] = o_rms[p] = np.nan
        else:
            o_s0[p] = s0
            o_sig[p] = sig
            o_rms[p] = rms
    return o_s0, o_sig, o_rms


@kernel(nogil=True)
def opposite_edges(grey, points, normals, half_px, reach, least):  # type: ignore[no-untyped-def]
    """Offset along the normal of the steepest opposite slope on each edge point's own
    grid line (see :func:`robostereo.robot.views.edge_profiles.profiles`, ``along=0``, and
    ``_opposite_peak`` there, which this computes the same way, one point at a time).

    `grey` float32 (H, W); `points`, `normals` (M, 2).  Returns (M,): the slope's
    midpoint offset, pixels, NaN where none within `reach` of the edge reaches `least`
    grey levels per pixel downhill or the steepest is at the line's end."""
    h, w = grey.shape
    m = points.shape[0]
    nj = 2 * half_px + 1
    out = np.empty(m)
    s = np.empty(nj)
    g = np.empty(nj)
    for i in range(m):
        rows = abs(normals[i, 0]) >= abs(normals[i, 1])
        if rows:
            u0 = points[i, 0]
            pv = points[i, 1]
            nu = normals[i, 0]
            nv = normals[i, 1]
        else:
            u0 = points[i, 1]
            pv = points[i, 0]
            nu = normals[i, 1]
            nv = normals[i, 0]
        v0 = np.rint(pv)
        dv = (v0 - pv) + 0
        uc = u0 - nv / nu * dv
        ru = np.rint(uc)
        vi = int(min(max(v0, 0.0), (h - 1) if rows else (w - 1)))
        for j in range(nj):
            uu = ru + (j - half_px)
            s[j] = (uu - u0) * nu + dv * nv
            if rows:
                g[j] = grey[vi, int(min(max(uu, 0.0), w - 1))]
            else:
                g[j] = grey[int(min(max(uu, 0.0), h - 1)), vi]
        best = -np.inf
        kb = 0
        mid_b = 0.0
        for k in range(nj - 1):
            ds = s[k + 1] - s[k]
            slope = (g[k + 1] - g[k]) / (ds if ds != 0 else 1.0)
            mid = 0.5 * (s[k + 1] + s[k])
            neg = -slope if abs(mid) <= reach else -np.inf
            if neg > best:
                best = neg
                kb = k
                mid_b = mid
        if best >= least and kb > 0 and kb < nj - 2:
            out[i] = mid_b
        else:
            out[i] = np.nan
    return out
