"""Numba kernels of figural continuity: support of a match from its edge contour.

The thesis's relaxation (3.4, eq. 4-5 [1]_) lets the matches of edge points that are
connected along an edge contour support each other when their disparities agree: an
edge contour is one surface boundary, and its points move together between the views.
These kernels measure that evidence for the window matcher's best disparities, one pass
over the edge points, walking each point's contour up to ``reach`` lines up and down
through the edge stage's connectivity (:attr:`robostereo.matcher.edge_features.EdgeSet.up` /
``down``):

* :func:`contour_support`: the neighbours whose best disparity lies within
  ``tolerance`` of the point's own add their ``weight``;
* :func:`linked_support`: the neighbours matched to the right contour's neighbours (the
  same right edge point) add theirs;
* :func:`chain_support`: how far the disparity runs smoothly along the contour, and
  whether it reaches a strong match.

``benchmarks/bench_contour.py`` measures what they add to the confidence: little near
depth steps, where the wrong matches run along contours as smoothly as the right ones.
The matcher calls :func:`contour_support` only for its opt-in second acceptance
(:func:`robostereo.matcher.window_match.contour_accepted`).  Only numba functions.

References
----------
.. [1] T.-Q. Kim, "A robot vision system for determining 3-D coordinates of
   object points", M.S. thesis, NJIT, 1989, section 3.4.
"""

from __future__ import annotations

import numpy as np

from robostereo.matcher.jit import kernel

__all__ = ["chain_support", "contour_support", "linked_support"]


@kernel(nogil=True)
def contour_support(up, down, disparity, weight, reach, tolerance):  # type: ignore[no-untyped-def]
    """Support of each point's best disparity from its contour neighbours.

    Parameters
    ----------
    up, down : ndarray of int64, shape (N,)
        Index of the connected edge point on the line above / below, -1 if none.
    disparity : ndarray of float64, shape (N,)
        Best disparity of each point, NaN where none.
    weight : ndarray of float64, shape (N,)
        What each neighbour adds when it agrees (e.g. 1, or whether its own evidence
        is strong).
    reach : int
        Lines walked up and down the contour (at most ``2 * reach`` neighbours).
    tolerance : float
        A neighbour agrees when its disparity is within this of the point's (pixels).

    Returns
    -------
    support : ndarray of float64, shape (N,)
        Sum of ``weight`` over the agreeing neighbours; 0 where the point has no
        disparity.
    reached : ndarray of int64, shape (N,)
        Neighbours met along the contour (with or without a disparity).
    """
    n = up.shape[0]
    support = np.zeros(n, np.float64)
    reached = np.zeros(n, np.int64)
    for i in range(n):
        d = disparity[i]
        s = 0.0
        m = 0
        for direction in range(2):
            j = i
            for _ in range(reach):
                j = up[j] if direction == 0 else down[j]
                if j < 0:
                    break
                m += 1
                dj = disparity[j]
                if abs(dj - d) <= tolerance:  # False for NaN
                    s += weight[j]
        support[i] = s
        reached[i] = m
    return support, reached


@kernel(nogil=True)
def linked_support(up, down, right_edge, right_up, right_down, weight, reach):  # type: ignore[no-untyped-def]
    """Support of each match from contour neighbours matched to the right contour's.

    Walking ``reach`` lines up (down) the left contour from point ``i`` and, in step, up
    (down) the right contour from its right edge point, a neighbour adds its ``weight``
    where its own right edge point is the one met on the right contour: the two
    contours are matched point to point (the thesis's figural continuity, 3.4).

    Parameters
    ----------
    up, down : ndarray of int64, shape (N,)
        Left contour: connected edge point above / below, -1 if none.
    right_edge : ndarray of int64, shape (N,)
        Index of each left point's right edge point, -1 if none.
    right_up, right_down : ndarray of int64, shape (M,)
        Right contour: connected edge point above / below, -1 if none.
    weight : ndarray of float64, shape (N,)
    reach : int

    Returns
    -------
    ndarray of float64, shape (N,)
        Sum of ``weight`` over the linked neighbours; 0 without a right edge point.
    """
    n = up.shape[0]
    support = np.zeros(n, np.float64)
    for i in range(n):
        if right_edge[i] < 0:
            continue
        s = 0.0
        for direction in range(2):
            j = i
            q = right_edge[i]
            for _ in range(reach):
                if direction == 0:
                    j = up[j]
                    q = right_up[q] if j >= 0 else -1
                else:
                    j = down[j]
                    q = right_down[q] if j >= 0 else -1
                if j < 0 or q < 0:
                    break
                if right_edge[j] == q:
                    s += weight[j]
        support[i] = s
    return support


@kernel(nogil=True)
def chain_support(up, down, disparity, strong, reach, tolerance):  # type: ignore[no-untyped-def]
    """How far each point's disparity runs smoothly along its contour, and whether it
    reaches a strong match.

    From point ``i`` the contour is walked up (down) while each step's disparity lies
    within ``tolerance`` of the previous one, at most ``reach`` lines.

    Parameters
    ----------
    up, down : ndarray of int64, shape (N,)
    disparity : ndarray of float64, shape (N,)
        NaN where none (a chain stops there).
    strong : ndarray of bool, shape (N,)
        The anchors: matches confident on their own evidence.
    reach : int
    tolerance : float
        Largest change of disparity from one line to the next (pixels).

    Returns
    -------
    length : ndarray of int64, shape (N,)
        Lines walked smoothly, both ways together (0 .. 2 reach).
    anchors : ndarray of int64, shape (N,)
        Directions (0, 1 or 2) in which the smooth walk meets a strong match.
    """
    n = up.shape[0]
    length = np.zeros(n, np.int64)
    anchors = np.zeros(n, np.int64)
    for i in range(n):
        if not disparity[i] == disparity[i]:  # NaN
            continue
        for direction in range(2):
            j = i
            prev = disparity[i]
            for _ in range(reach):
                j = up[j] if direction == 0 else down[j]
                if j < 0:
                    break
                dj = disparity[j]
                if not abs(dj - prev) <= tolerance:
                    break
                prev = dj
                length[i] += 1
                if strong[j]:
                    anchors[i] += 1
                    break
    return length, anchors
