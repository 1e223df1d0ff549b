"""The truth of a simulated N-view capture: which located points are right, and how well.

Scoring for :func:`~robostereo.robot.views.locating.locate_views` on the captures of
:func:`~robostereo.robot.simulated.grab_views.simulate_views`, whose renderings hold the exact
depth of every pixel and whose scene holds the block's exact outline:

* :func:`views_correct`: each located point right or wrong (within one pixel of
  disparity over the pattern's longest baseline, the two-view rule's tolerance);
* :func:`views_block_truth`: the points on the block's top outline and their depth
  errors (the accuracy test of the thesis, 5.2, from N views);
* :func:`views_outline_coverage`: the share of the block's true outline located;
* :func:`views_pulley_score`: matched and false shares of the hub-pulley (5.1).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from robostereo.robot.simulated.grab_views import SimulatedViews
from robostereo.robot.views.located_points import LocatedViews
from robostereo.robot.views.prepared_views import prepare_views, reference_edges
from robostereo.simulation import Box

__all__ = [
    "views_block_truth",
    "views_correct",
    "views_depth_errors",
    "views_outline_coverage",
    "views_pulley_score",
]


def _top_box(sim: SimulatedViews) -> Box:
    return next(p for p in sim.scene.primitives if isinstance(p, Box))


def views_block_truth(sim: SimulatedViews, located: LocatedViews
                      ) -> tuple[NDArray[np.bool_], NDArray[np.float64], NDArray[np.int8]]:
    """The located points on the block's top outline and their depth errors, by the truth.

    Returns
    -------
    on_top : ndarray of bool, shape (M,)
        The point's reference pixel, cast with the true camera and pose onto the true top
        plane, lies within 1 mm of the top face's outline and at least 2 mm from its
        corners (the two-view demo keeps 3 rows inside the ends), and the point within
        10 mm of that plane.
    z_error : ndarray, shape (M,)
        Located minus true depth along the reference's optical axis, mm.
    edge : ndarray of int8, shape (M,)
        1 on the top face's long edges (80 mm, across the thesis's baseline), 2 on its
        short edges, 0 elsewhere.
    """
    box = _top_box(sim)
    top = box.z_base + box.size[2]
    m = len(located)
    on, err, edge = np.zeros(m, bool), np.full(m, np.nan), np.zeros(m, np.int8)
    cam = sim.camera or sim.capture.camera
    c, s = np.cos(box.yaw), np.sin(box.yaw)
    hx, hy = box.size[0] / 2, box.size[1] / 2
    for r in np.unique(located.reference):
        k = np.nonzero(located.reference == r)[0]
        pose = sim.true_poses[int(r)]
        ray = cam.backproject(located.pixel[k], np.ones(len(k)), pose) - pose.translation
        P = pose.translation + ((top - pose.translation[2]) / ray[:, 2])[:, None] * ray
        dx, dy = P[:, 0] - box.center[0], P[:, 1] - box.center[1]
        lx, ly = np.abs(c * dx + s * dy), np.abs(-s * dx + c * dy)
        inside = (lx <= hx + 1.0) & (ly <= hy + 1.0)
        # 2 mm clear of the corners (the two-view demo: 3 rows inside the ends)
        long_ = (np.abs(lx - hx) <= 1.0) & (ly <= hy - 2.0)
        short = (np.abs(ly - hy) <= 1.0) & (lx <= hx - 2.0)
        ok = inside & (long_ | short) & (np.abs(located.world[k, 2] - top) < 10.0)
        on[k] = ok
        edge[k] = np.where(ok & long_, 1, np.where(ok & short, 2, 0))
        err[k] = located.depth_mm[k] - (P - pose.translation) @ pose.rotation[:, 2]
    return on, err, edge


def views_outline_coverage(sim: SimulatedViews, located: LocatedViews, *,
                           within_mm: float = 1.0) -> float:
    """Share of the block's true top outline, sampled every mm, within `within_mm` (3-D)
    of a located point."""
    box = _top_box(sim)
    co = box.corners()
    top = co[co[:, 2] == co[:, 2].max()]
    ang = np.arctan2(top[:, 1] - top[:, 1].mean(), top[:, 0] - top[:, 0].mean())
    tc = top[np.argsort(ang)]
    pts = []
    for i in range(4):
        a, b = tc[i], tc[(i + 1) % 4]
        k = max(int(np.ceil(np.linalg.norm(b - a))), 1)
        pts.append(a + (b - a) * (np.arange(k) / k)[:, None])
    outline = np.vstack(pts)
    if not len(located):
        return 0.0
    return float((cKDTree(located.world).query(outline)[0] <= within_mm).mean())


def views_depth_errors(sim: SimulatedViews, located: LocatedViews) -> NDArray[np.float64]:
    """Each located point's depth error against the renderings' truth, mm, shape (M,):
    the least ``|Z_true - Z|`` over the 3 x 3 pixels about its reference pixel (an edge
    lies between pixels; ``inf`` where none has a depth)."""
    h, w = sim.renderings[0].depth.shape
    err = np.full(len(located), np.inf)
    for r in np.unique(located.reference):
        k = np.nonzero(located.reference == r)[0]
        d = sim.renderings[int(r)].depth
        x = np.clip(np.rint(located.pixel[k, 0]).astype(int), 1, w - 2)
        y = np.clip(np.rint(located.pixel[k, 1]).astype(int), 1, h - 2)
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                off = np.abs(d[y + dy, x + dx] - located.depth_mm[k])
                err[k] = np.fmin(err[k], off)
    return err


def views_correct(sim: SimulatedViews, located: LocatedViews) -> NDArray[np.bool_]:
    """Whether each located point is right, by the renderings' truth.

    Right: the true depth of some pixel of the 3 x 3 around the point's reference pixel
    lies within one pixel of disparity over the pattern's longest baseline of the
    located depth (``Z^2 / (f span)``; the two-view rule's tolerance).
    """
    cap = sim.capture
    tol = located.depth_mm**2 / (float(cap.camera.fx) * cap.span_mm)
    return views_depth_errors(sim, located) <= tol


def views_pulley_score(sim: SimulatedViews, located: LocatedViews, *,
                       threshold: float = 8.0, min_angle_deg: float = 15.0,
                       min_confidence: float = 0.0) -> tuple[float, float, float]:
    """``(matched, false, matched_all)`` fractions of a hub-pulley capture from N views.

    Matched: of the central reference view's edge points with a known depth that cross
    the epipolar line of some other view at `min_angle_deg` or more (the ones the views
    can measure: the thesis's matcher, too, counts only edge points found along its
    rows), those with a located point (from any reference) within 1 pixel in that view
    (both in its undistorted image);
    `matched_all` counts every edge point with a known depth.  False: located points
    that are not right by :func:`views_correct`.  Only the points with a confidence of
    at least `min_confidence` count.
    """
    located = located.subset(located.confidence >= min_confidence)
    cap = sim.capture
    views = prepare_views(cap)
    order = np.argsort(np.linalg.norm(cap.centres - cap.centres.mean(axis=0), axis=1),
                       kind="stable")
    ref = int(order[0])
    edges = reference_edges(views, ref, threshold, 5)
    # edge pixels are in the undistorted image, the renderings in the grabbed one
    cam = cap.camera
    c = np.array(cam.principal_point)
    grab = cam.distort((edges.pixel - c) / [cam.fx, cam.fy]) * [cam.fx, cam.fy] + c
    h, w = sim.renderings[ref].depth.shape
    gx = np.clip(np.rint(grab[:, 0]).astype(np.intp), 0, w - 1)
    gy = np.clip(np.rint(grab[:, 1]).astype(np.intp), 0, h - 1)
    known = np.isfinite(sim.renderings[ref].depth[gy, gx])
    # the edges the views can measure: across some baseline's image direction
    dirs = np.delete((views.C - views.C[ref]) @ views.R[ref], ref, axis=0)[:, :2]
    dirs /= np.maximum(np.linalg.norm(dirs, axis=1, keepdims=True), 1e-12)
    across = np.abs(edges.normal @ dirs.T).max(axis=1) >= np.sin(np.radians(min_angle_deg))
    near = np.zeros(len(edges), bool)
    false = int((~views_correct(sim, located)).sum())
    if len(located):
        uv, _ = views.project(located.world, ref)
        near = cKDTree(uv).query(edges.pixel)[0] <= 1.0
    counted = known & across
    matched = float((near & counted).sum() / max(int(counted.sum()), 1))
    matched_all = float((near & known).sum() / max(int(known.sum()), 1))
    return matched, false / max(len(located), 1), matched_all
