"""numba kernels of the N-view search (:mod:`robostereo.robot.views.prepared_views`,
:mod:`~robostereo.robot.views.ray_search`, :mod:`~robostereo.robot.views.point_refinement`).

* :func:`sweep_costs`: each reference edge point's window scored in every other view at
  every inverse depth of its ray (zero-mean normalised cross-correlation, bilinear
  sampling through the local affine map of the depth plane);
* :func:`central_gradient`: an image's gradient by central differences;
* :func:`normal_residuals`: the least-squares fit's residuals, each view's edge normal
  distance to the projection of a point on a reference ray;
* :func:`row_peaks` / :func:`edge_near`: sub-pixel edge points on the pixel grid, as
  the matcher's (thesis 3.1-3.2: the peak of the gradient magnitude along a row, a
  parabola through it and its neighbours), along rows for edges whose normal is nearer
  x and along columns for the others;
* :func:`ray_edge_peaks`: where a view's gradient across an edge peaks along each
  reference ray (the edge votes of :mod:`~robostereo.robot.views.edge_votes`).
"""

from __future__ import annotations

import numpy as np

from robostereo.matcher.jit import kernel

__all__ = ["central_gradient", "edge_near", "grid_edges", "normal_residuals", "ray_edge_peaks",
           "sweep_costs"]

#: cost of a view where the window falls outside the image (not a vote)
OUTSIDE = np.float32(np.nan)


@kernel(nogil=True)
def _bilinear(img, x, y):  # type: ignore[no-untyped-def]
    """Bilinear sample of ``img`` (H, W) at (x, y); the caller keeps it inside."""
    x0 = int(np.floor(x))
    y0 = int(np.floor(y))
    fx = x - x0
    fy = y - y0
    a = img[y0, x0] * (1.0 - fx) + img[y0, x0 + 1] * fx
    b = img[y0 + 1, x0] * (1.0 - fx) + img[y0 + 1, x0 + 1] * fx
    return a * (1.0 - fy) + b * fy


@kernel(nogil=True)
def _bilinear_inside(img, x, y):  # type: ignore[no-untyped-def]
    """:func:`_bilinear` where ``x, y >= 0`` (the truncation is the floor; unsigned
    indices spare numba's negative-index test); the same value."""
    x0 = np.uint64(x)
    y0 = np.uint64(y)
    fx = x - np.float64(x0)
    fy = y - np.float64(y0)
    x1 = x0 + np.uint64(1)
    y1 = y0 + np.uint64(1)
    a = img[y0, x0] * (1.0 - fx) + img[y0, x1] * fx
    b = img[y1, x0] * (1.0 - fx) + img[y1, x1] * fx
    return a * (1.0 - fy) + b * fy


@kernel(nogil=True)
def sweep_costs(images, ref_patch, offs, views, a, b, aff, rho, margin, skip):  # type: ignore[no-untyped-def]
    """``1 - ZNCC`` of each point's reference window in each other view at each depth.

    Parameters
    ----------
    images : float32 (N, H, W)
        Smoothed, undistorted images of all views.
    ref_patch : float32 (M, P)
        Each point's reference window, zero mean and unit norm (norm 0: flat).
    offs : float64 (P, 2)
        Window sample offsets ``(dx, dy)`` in reference pixels.
    views : int64 (V,)
        The other views, indices into `images`.
    a, b : float64 (M, V, 3)
        The point at inverse depth ``rho`` projects to ``(a + rho b)[:2] / (a + rho b)[2]``.
    aff : float64 (M, V, 2, 2)
        Reference pixel offsets to the view's pixel offsets (the depth plane's local map).
    rho : float64 (M, K)
        Each point's inverse depths, 1/mm.
    margin : float
        Least distance of a window sample from the image border, pixels.
    skip : bool (M, V)
        Views not to score for a point (NaN at every depth): those that cannot vote.

    Returns
    -------
    float32 (M, V, K)
        ``1 - ZNCC`` (0 best, 2 worst); NaN where the window leaves the image, the
        point is behind the view or the view is skipped.
    """
    m, p = ref_patch.shape
    nv = views.shape[0]
    nk = rho.shape[1]
    h = images.shape[1]
    w = images.shape[2]
    out = np.empty((m, nv, nk), np.float32)
    buf = np.empty(p, np.float64)
    # the samples' offset terms, multiplied once per point and view (added as before)
    tx0 = np.empty(p)
    tx1 = np.empty(p)
    ty0 = np.empty(p)
    ty1 = np.empty(p)
    ox0 = ox1 = offs[0, 0]
    oy0 = oy1 = offs[0, 1]
    for q in range(p):
        ox0 = min(ox0, offs[q, 0])
        ox1 = max(ox1, offs[q, 0])
        oy0 = min(oy0, offs[q, 1])
        oy1 = max(oy1, offs[q, 1])
    for i in range(m):
        for v in range(nv):
            if skip[i, v]:
                for k in range(nk):
                    out[i, v, k] = OUTSIDE
                continue
            img = images[views[v]]
            a00 = aff[i, v, 0, 0]
            a01 = aff[i, v, 0, 1]
            a10 = aff[i, v, 1, 0]
            a11 = aff[i, v, 1, 1]
            for q in range(p):
                tx0[q] = a00 * offs[q, 0]
                tx1[q] = a01 * offs[q, 1]
                ty0[q] = a10 * offs[q, 0]
                ty1[q] = a11 * offs[q, 1]
            for k in range(nk):
                hx = a[i, v, 0] + rho[i, k] * b[i, v, 0]
                hy = a[i, v, 1] + rho[i, k] * b[i, v, 1]
                hz = a[i, v, 2] + rho[i, k] * b[i, v, 2]
                if hz <= 0.0:
                    out[i, v, k] = OUTSIDE
                    continue
                cx = hx / hz
                cy = hy / hz
                # the window's corners inside: every sample is (each is monotone in
                # either offset, rounding too), and none needs a test
                inside = True
                for c in range(4):
                    ox = ox0 if c < 2 else ox1
                    oy = oy0 if c % 2 == 0 else oy1
                    x = cx + a00 * ox + a01 * oy
                    y = cy + a10 * ox + a11 * oy
                    if x < margin or y < margin or x > w - 1 - margin or y > h - 1 - margin:
                        inside = False
                s = 0.0
                if inside and margin >= 0.0:
                    for q in range(p):
                        buf[q] = _bilinear_inside(img, cx + tx0[q] + tx1[q],
                                                  cy + ty0[q] + ty1[q])
                        s += buf[q]
                else:
                    inside = True
                    for q in range(p):
                        x = cx + tx0[q] + tx1[q]
                        y = cy + ty0[q] + ty1[q]
                        if (x < margin or y < margin or x > w - 1 - margin
                                or y > h - 1 - margin):
                            inside = False
                            break
                        buf[q] = (_bilinear_inside(img, x, y) if margin >= 0.0
                                  else _bilinear(img, x, y))
                        s += buf[q]
                if not inside:
                    out[i, v, k] = OUTSIDE
                    continue
                mean = s / p
                num = 0.0
                den = 0.0
                for q in range(p):
                    d = buf[q] - mean
                    num += d * ref_patch[i, q]
                    den += d * d
                if den <= 1e-12:
                    out[i, v, k] = np.float32(1.0)
                else:
                    out[i, v, k] = np.float32(1.0 - num / np.sqrt(den))
    return out


@kernel(nogil=True)
def _vertex(m0, m, m1):  # type: ignore[no-untyped-def]
    """Sub-pixel offset of a peak ``m`` between ``m0`` (at -1) and ``m1`` (at +1): the
    vertex of the parabola through the three (the matcher's, thesis 3.2)."""
    den = m0 - 2.0 * m + m1
    return 0.5 * (m0 - m1) / den if den < 0 else 0.0


@kernel(nogil=True)
def _along(gx, gy, px, py, nx, ny, along_x, lines, border):  # type: ignore[no-untyped-def]
    """The edge point ``(px, py)`` moved along the unit normal ``(nx, ny)`` by the mean
    normal offset of the edge's sub-pixel points on the `lines` grid lines either side
    (rows when `along_x`, else columns): the edge's position averaged along itself."""
    h, w = gx.shape
    total = 0.0
    count = 1
    for dl in range(-lines, lines + 1):
        if dl == 0:
            continue
        if along_x:
            y = int(np.rint(py)) + dl
            xc = px - ny / nx * dl
            x0 = int(np.rint(xc))
            if y < border or y > h - 1 - border:
                continue
        else:
            x = int(np.rint(px)) + dl
            yc = py - nx / ny * dl
            y0 = int(np.rint(yc))
            if x < border or x > w - 1 - border:
                continue
        best = -1.0
        pos = 0.0
        for s in range(-1, 2):
            if along_x:
                xx = x0 + s
                if xx < border or xx > w - 1 - border:
                    continue
                dm = gx[y, xx - 1] * nx + gy[y, xx - 1] * ny
                d0 = gx[y, xx] * nx + gy[y, xx] * ny
                dp = gx[y, xx + 1] * nx + gy[y, xx + 1] * ny
            else:
                yy = y0 + s
                if yy < border or yy > h - 1 - border:
                    continue
                dm = gx[yy - 1, x] * nx + gy[yy - 1, x] * ny
                d0 = gx[yy, x] * nx + gy[yy, x] * ny
                dp = gx[yy + 1, x] * nx + gy[yy + 1, x] * ny
            if d0 > dm and d0 >= dp and d0 > best:
                best = d0
                pos = (xx if along_x else yy) + _vertex(dm, d0, dp)
        if best <= 0.0:
            continue
        if along_x:
            total += nx * (pos - px) + ny * dl
        else:
            total += nx * dl + ny * (pos - py)
        count += 1
    off = total / count
    return px + off * nx, py + off * ny


@kernel(nogil=True)
def _grid_peak(gx, gy, y, x, threshold):  # type: ignore[no-untyped-def]
    """(axis, sub-pixel offset) of a grid edge point at (y, x), axis -1 for none."""
    mag = np.sqrt(gx[y, x] ** 2 + gy[y, x] ** 2)
    if mag < threshold:
        return -1, 0.0
    if abs(gx[y, x]) >= abs(gy[y, x]):
        m0 = np.sqrt(gx[y, x - 1] ** 2 + gy[y, x - 1] ** 2)
        m1 = np.sqrt(gx[y, x + 1] ** 2 + gy[y, x + 1] ** 2)
        axis = 0
    else:
        m0 = np.sqrt(gx[y - 1, x] ** 2 + gy[y - 1, x] ** 2)
        m1 = np.sqrt(gx[y + 1, x] ** 2 + gy[y + 1, x] ** 2)
        axis = 1
    if not (mag > m0 and mag >= m1):
        return -1, 0.0
    return axis, _vertex(m0, mag, m1)


@kernel(nogil=True)
def grid_edges(gx, gy, threshold, border, lines):  # type: ignore[no-untyped-def]
    """Edge points on the pixel grid: peaks of ``|grad|`` along rows (normal nearer x) or
    along columns (normal nearer y), ``|grad| >= threshold``, `border` px inside.

    Returns rows, columns, the sub-pixel position along the scan axis (x for row peaks,
    y for column peaks), the axis (0 rows, 1 columns), and the gradient at the pixel."""
    h, w = gx.shape
    n = 0
    # one test of every pixel: its axis (-1: no edge point) and offset, kept for the fill
    axis_at = np.full((h, w), -1, np.int8)
    off_at = np.zeros((h, w), np.float64)
    # below this squared magnitude a pixel is surely under `threshold` (sqrt spared)
    low = (threshold * (1.0 - 1e-5)) ** 2 if threshold > 0.0 else -1.0
    for y in range(border, h - border):
        for x in range(border, w - border):
            if gx[y, x] * gx[y, x] + gy[y, x] * gy[y, x] < low:
                continue
            axis, off = _grid_peak(gx, gy, y, x, threshold)
            if axis >= 0:
                axis_at[y, x] = axis
                off_at[y, x] = off
                n += 1
    rows = np.empty(n, np.int64)
    cols = np.empty(n, np.int64)
    sub = np.empty(n, np.float64)
    axes = np.empty(n, np.int64)
    gxs = np.empty(n, np.float64)
    gys = np.empty(n, np.float64)
    n = 0
    for y in range(border, h - border):
        for x in range(border, w - border):
            axis = axis_at[y, x]
            if axis < 0:
                continue
            off = off_at[y, x]
            rows[n] = y
            cols[n] = x
            sub[n] = (x if axis == 0 else y) + off
            if lines > 0:
                g = np.sqrt(gx[y, x] ** 2 + gy[y, x] ** 2)
                nx = gx[y, x] / g
                ny = gy[y, x] / g
                qx, qy = _along(gx, gy, x + off if axis == 0 else float(x),
                                float(y) if axis == 0 else y + off, nx, ny, axis == 0, lines,
                                border)
                sub[n] = qx if axis == 0 else qy
                # the point moved along its normal: keep it on its grid line
                if axis == 0:
                    sub[n] = qx + (qy - y) * ny / nx
                else:
                    sub[n] = qy + (qx - x) * nx / ny
            axes[n] = axis
            gxs[n] = gx[y, x]
            gys[n] = gy[y, x]
            n += 1
    return rows, cols, sub, axes, gxs, gys


@kernel(nogil=True)
def edge_near(gx, gy, ux, uy, nx, ny, reach, threshold, border, lines):  # type: ignore[no-untyped-def]
    """The sub-pixel edge point nearest each predicted position, on the pixel grid.

    For each point: the scan axis is the one nearer the predicted normal ``(nx, ny)``;
    on the grid line through the rounded prediction, the pixels within `reach` whose
    gradient agrees with the normal (``grad . n >= threshold``) and is a peak of
    ``grad . n`` along the axis; the nearest such peak, refined by a parabola.

    Returns ``(ex, ey, gxe, gye, found)``: the edge point (x, y), the gradient at its
    pixel, and whether one was found."""
    h, w = gx.shape
    m = ux.shape[0]
    ex = np.full(m, np.nan)
    ey = np.full(m, np.nan)
    gxe = np.zeros(m)
    gye = np.zeros(m)
    found = np.zeros(m, np.bool_)
    for i in range(m):
        if not (np.isfinite(ux[i]) and np.isfinite(uy[i])):
            continue
        xr = int(np.rint(ux[i]))
        yr = int(np.rint(uy[i]))
        if xr < border or yr < border or xr > w - 1 - border or yr > h - 1 - border:
            continue
        along_x = abs(nx[i]) >= abs(ny[i])
        best = 1e9
        for s in range(-reach, reach + 1):
            x = xr + s if along_x else xr
            y = yr if along_x else yr + s
            if x < border or y < border or x > w - 1 - border or y > h - 1 - border:
                continue
            d0 = gx[y, x] * nx[i] + gy[y, x] * ny[i]
            if d0 < threshold:
                continue
            if along_x:
                dm = gx[y, x - 1] * nx[i] + gy[y, x - 1] * ny[i]
                dp = gx[y, x + 1] * nx[i] + gy[y, x + 1] * ny[i]
            else:
                dm = gx[y - 1, x] * nx[i] + gy[y - 1, x] * ny[i]
                dp = gx[y + 1, x] * nx[i] + gy[y + 1, x] * ny[i]
            if not (d0 > dm and d0 >= dp):
                continue
            off = _vertex(dm, d0, dp)
            if along_x:
                px = x + off
                py = float(y)
                dist = abs(px - ux[i])
            else:
                px = float(x)
                py = y + off
                dist = abs(py - uy[i])
            if dist < best:
                best = dist
                ex[i] = px
                ey[i] = py
                gxe[i] = gx[y, x]
                gye[i] = gy[y, x]
                found[i] = True
    if lines > 0:
        for i in range(m):
            if not found[i]:
                continue
            g = np.sqrt(gxe[i] ** 2 + gye[i] ** 2)
            nxi = gxe[i] / g
            nyi = gye[i] / g
            ex[i], ey[i] = _along(gx, gy, ex[i], ey[i], nxi, nyi, abs(nxi) >= abs(nyi), lines,
                                  border)
    return ex, ey, gxe, gye, found


@kernel(nogil=True, error_model="numpy")
def normal_residuals(e_ref, n_ref, t, rho, k_inv, r_ref, c_ref, rs, cs, kk,  # type: ignore[no-untyped-def]
                     edge, normal):
    """Normal distances of each view's edge point to the projection of a point on a
    reference ray (the residuals of :class:`robostereo.robot.views.point_refinement._Fit`).

    Parameters
    ----------
    e_ref, n_ref : float64 (M, 2)
        Reference edge points and unit normals; the ray is through ``e_ref + t n_ref``.
    t, rho : float64 (M,)
        Offsets along the normals, pixels, and inverse depths along the reference's
        optical axis, 1/mm.
    k_inv : float64 (3, 3)
        The inverse of the camera matrix.
    r_ref, c_ref : float64 (3, 3), (3,)
        The reference's rotation (camera to world) and centre, mm.
    rs, cs : float64 (V, 3, 3), (V, 3)
        The same of the other views.
    kk : float64 (3, 3)
        The camera matrix (pinhole, undistorted).
    edge, normal : float64 (M, V, 2)
        Each view's edge point ``(x, y)`` and unit normal (zeros where none).

    Returns
    -------
    float64 (M, V)
        ``normal . (pi_v(P) - edge)``, pixels (inf or NaN behind a view's centre).
    """
    m = e_ref.shape[0]
    nv = cs.shape[0]
    out = np.empty((m, nv))
    hom = np.empty(3)
    d = np.empty(3)
    wp = np.empty(3)
    for i in range(m):
        px = e_ref[i, 0] + t[i] * n_ref[i, 0]
        py = e_ref[i, 1] + t[i] * n_ref[i, 1]
        for a in range(3):
            hom[a] = px * k_inv[a, 0] + py * k_inv[a, 1] + k_inv[a, 2]
        for a in range(3):
            d[a] = hom[0] * r_ref[a, 0] + hom[1] * r_ref[a, 1] + hom[2] * r_ref[a, 2]
            wp[a] = c_ref[a] + d[a] / rho[i]
        for v in range(nv):
            x0 = wp[0] - cs[v, 0]
            x1 = wp[1] - cs[v, 1]
            x2 = wp[2] - cs[v, 2]
            pc0 = x0 * rs[v, 0, 0] + x1 * rs[v, 1, 0] + x2 * rs[v, 2, 0]
            pc1 = x0 * rs[v, 0, 1] + x1 * rs[v, 1, 1] + x2 * rs[v, 2, 1]
            pc2 = x0 * rs[v, 0, 2] + x1 * rs[v, 1, 2] + x2 * rs[v, 2, 2]
            u = pc0 / pc2 * kk[0, 0] + kk[0, 2]
            w = pc1 / pc2 * kk[1, 1] + kk[1, 2]
            out[i, v] = (normal[i, v, 0] * (u - edge[i, v, 0])
                         + normal[i, v, 1] * (w - edge[i, v, 1]))
    return out


@kernel(nogil=True)
def central_gradient(s, gx, gy):  # type: ignore[no-untyped-def]
    """``gx, gy`` (H, W) of `s` (H, W), float32 all: half the central differences along x
    and y, zero on the border they cannot reach; in place, one pass."""
    h, w = s.shape
    for y in range(h):
        for x in range(w):
            if x == 0 or x == w - 1:
                gx[y, x] = 0.0
            else:
                gx[y, x] = (s[y, x + 1] - s[y, x - 1]) * np.float32(0.5)
            if y == 0 or y == h - 1:
                gy[y, x] = 0.0
            else:
                gy[y, x] = (s[y + 1, x] - s[y - 1, x]) * np.float32(0.5)


@kernel(nogil=True)
def ray_edge_peaks(gx, gy, a, b, normals, grid, threshold, border):  # type: ignore[no-untyped-def]
    """The inverse depths along each ray where one view's gradient across the edge peaks
    (:func:`robostereo.robot.views.edge_votes.edge_votes`, step 1), one point at a time.

    Parameters
    ----------
    gx, gy : float32 (H, W)
        The view's gradient.
    a, b : float64 (K, 3)
        Each point at inverse depth ``rho`` projects to ``(a + rho b)`` (homogeneous).
    normals : float64 (K, 2)
        The edge's unit normal carried into the view.
    grid : float64 (G,)
        The inverse depths.
    threshold : float
        Least gradient across the edge at a peak.
    border : int
        Least distance of a sample from the image's border, pixels.

    Returns
    -------
    point : int64 (C,)
        Each peak's point, in order of point and then depth.
    k : int64 (C,)
        Its index in `grid`.
    frac : float64 (C,)
        The parabola's vertex through it and its neighbours, in grid steps (0 where the
        parabola opens upward or a neighbour falls outside the image).
    """
    h, w = gx.shape
    m = a.shape[0]
    n_g = grid.shape[0]
    cap = 16
    point = np.empty(cap, np.int64)
    kk = np.empty(cap, np.int64)
    frac = np.empty(cap)
    c = 0
    d = np.empty(n_g)
    for i in range(m):
        nx = normals[i, 0]
        ny = normals[i, 1]
        for g in range(n_g):
            hz = a[i, 2] + grid[g] * b[i, 2]
            d[g] = -np.inf
            if not hz > 0.0:
                continue
            x = (a[i, 0] + grid[g] * b[i, 0]) / hz
            y = (a[i, 1] + grid[g] * b[i, 1]) / hz
            if not (x >= border and y >= border and x <= w - 1 - border
                    and y <= h - 1 - border):
                continue
            x = min(max(x, 0.0), w - 1.001)
            y = min(max(y, 0.0), h - 1.001)
            d[g] = _bilinear(gx, x, y) * nx + _bilinear(gy, x, y) * ny
        for g in range(1, n_g - 1):
            y1 = d[g]
            if not (y1 >= threshold and y1 > d[g - 1] and y1 >= d[g + 1]):
                continue
            if c == cap:  # grow the outputs
                cap *= 2
                point2 = np.empty(cap, np.int64)
                kk2 = np.empty(cap, np.int64)
                frac2 = np.empty(cap)
                point2[:c] = point[:c]
                kk2[:c] = kk[:c]
                frac2[:c] = frac[:c]
                point, kk, frac = point2, kk2, frac2
            y0 = d[g - 1]
            y2 = d[g + 1]
            den = y0 - 2.0 * y1 + y2
            point[c] = i
            kk[c] = g
            frac[c] = 0.5 * (y0 - y2) / den if (np.isfinite(den) and den < 0) else 0.0
            c += 1
    return point[:c], kk[:c], frac[:c]
