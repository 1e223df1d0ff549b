"""Numba kernel of the rows check: Lucas-Kanade at a few places, on the images as given.

:func:`~robostereo.matcher.alignment.row_offset` tracks about a hundred places from the
left view into the right.  OpenCV's ``calcOpticalFlowPyrLK`` wants 8-bit grey images
and makes the gradients of the whole image first, which cost more than the tracking;
here each place reads only its own window, of any grey-level type: Lucas-Kanade [1]_
with the template's gradients kept fixed (the inverse additive form of [2]_).  Only
numba functions.

References
----------
.. [1] B. D. Lucas and T. Kanade, "An iterative image registration technique with an
   application to stereo vision", IJCAI 1981.
.. [2] S. Baker and I. Matthews, "Lucas-Kanade 20 years on: a unifying framework",
   IJCV 56(3), 2004.
"""

from __future__ import annotations

import math

import numpy as np

from robostereo.matcher.jit import kernel

__all__ = ["track_kernel"]


@kernel(nogil=True)
def _structure(left, x, y, half, gx, gy):  # type: ignore[no-untyped-def]
    """Central-difference gradients of the window at ``(x, y)`` into ``gx, gy`` and the
    structure tensor's entries ``sxx, syy, sxy``."""
    n = 2 * half + 1
    sxx = 0.0
    syy = 0.0
    sxy = 0.0
    for j in range(n):
        for i in range(n):
            yy = y - half + j
            xx = x - half + i
            a = 0.5 * (float(left[yy, xx + 1]) - float(left[yy, xx - 1]))
            b = 0.5 * (float(left[yy + 1, xx]) - float(left[yy - 1, xx]))
            gx[j, i] = a
            gy[j, i] = b
            sxx += a * a
            syy += b * b
            sxy += a * b
    return sxx, syy, sxy


@kernel(nogil=True)
def _row_search(left, right, x, y, u, half, search):  # type: ignore[no-untyped-def]
    """The whole row offset ``v`` in ``-search .. search`` (0 first, then nearest first)
    whose right window at ``(x + u, y + v)`` (``x + u`` rounded) has the least sum of
    squared differences from the left window at ``(x, y)``; 0 where none fits in the
    image."""
    h, w = right.shape
    n = 2 * half + 1
    xr = math.floor(x + u + 0.5)
    if xr - half < 0 or xr + half >= w:
        return 0
    best = 0
    best_e = np.inf
    for step in range(2 * search + 1):
        v = (step + 1) // 2 * (1 if step % 2 else -1)  # 0, 1, -1, 2, -2, ...
        if y + v - half < 0 or y + v + half >= h:
            continue
        e = 0.0
        for j in range(n):
            for i in range(n):
                d = float(right[y + v - half + j, xr - half + i]) - float(
                    left[y - half + j, x - half + i])
                e += d * d
        if e < best_e:
            best_e = e
            best = v
    return best


@kernel(nogil=True)
def track_kernel(left, right, px, py, disparity, half, iterations,
                 search):  # type: ignore[no-untyped-def]
    """Track the better-structured half of the left places ``(px, py)`` (M,) int64 into
    ``right``, from ``(px - disparity, py + v0)``, over ``(2 half + 1)^2`` windows (images
    ``(H, W)``, any real type); ``v0`` is the whole row offset in ``-search .. search``
    whose window differs least from the left one (sum of squared differences), so rows
    several pixels apart are tracked too (Lucas-Kanade alone reaches about a pixel or
    two).

    Returns ``strength, dx, dy, ok`` (M,) each: the smaller eigenvalue of the window's
    structure tensor (central differences; 0 for places too near the border), the
    motion found (right minus left, ``dx`` beside ``-disparity``), and whether the
    place was tracked (strength at least the median of the places in the image), stayed
    in the image and converged (a step under 0.02 px within ``iterations``)."""
    m = px.shape[0]
    h, w = left.shape
    strength = np.zeros(m)
    dxs = np.zeros(m)
    dys = np.zeros(m)
    ok = np.zeros(m, np.bool_)
    n = 2 * half + 1
    gx = np.empty((n, n))
    gy = np.empty((n, n))
    usable = np.zeros(m, np.bool_)
    x0s = np.empty(n, np.int64)  # a step's bilinear sources and weights per column, row
    y0s = np.empty(n, np.int64)
    fxs = np.empty(n)
    fys = np.empty(n)
    for k in range(m):
        x = px[k]
        y = py[k]
        if x - half - 1 < 0 or x + half + 1 >= w or y - half - 1 < 0 or y + half + 1 >= h:
            continue
        sxx, syy, sxy = _structure(left, x, y, half, gx, gy)
        strength[k] = 0.5 * (sxx + syy) - math.sqrt(0.25 * (sxx - syy) ** 2 + sxy * sxy)
        usable[k] = True
    if not usable.any():
        return strength, dxs, dys, ok
    level = np.median(strength[usable])
    for k in range(m):
        if not usable[k] or strength[k] < level:
            continue
        x = px[k]
        y = py[k]
        sxx, syy, sxy = _structure(left, x, y, half, gx, gy)
        det = sxx * syy - sxy * sxy
        if det <= 1e-12 * max(sxx * syy, 1.0):
            continue
        u = -disparity[k]
        v = float(_row_search(left, right, x, y, u, half, search))
        converged = False
        inside = True
        for _ in range(iterations):
            if (x + u - half < 0 or x + u + half + 1 >= w or y + v - half < 0
                    or y + v + half + 1 >= h):
                inside = False
                break
            # bilinear samples of the right view at the window moved by (u, v): a
            # column's source and weight are the same on every row, and a row's on
            # every column, so they are made once a step
            for i in range(n):
                at = x - half + i + u
                x0s[i] = math.floor(at)
                fxs[i] = at - x0s[i]
                at = y - half + i + v
                y0s[i] = math.floor(at)
                fys[i] = at - y0s[i]
            bx = 0.0
            by = 0.0
            for j in range(n):
                y0 = y0s[j]
                fy = fys[j]
                for i in range(n):
                    x0 = x0s[i]
                    fx = fxs[i]
                    top = (1.0 - fx) * right[y0, x0] + fx * right[y0, x0 + 1]
                    bottom = (1.0 - fx) * right[y0 + 1, x0] + fx * right[y0 + 1, x0 + 1]
                    e = (1.0 - fy) * top + fy * bottom - float(left[y - half + j, x - half + i])
                    bx += e * gx[j, i]
                    by += e * gy[j, i]
            du = -(syy * bx - sxy * by) / det
            dv = -(sxx * by - sxy * bx) / det
            u += du
            v += dv
            if abs(du) < 0.02 and abs(dv) < 0.02:
                converged = True
                break
        if inside and converged:
            dxs[k] = u
            dys[k] = v
            ok[k] = True
    return strength, dxs, dys, ok
