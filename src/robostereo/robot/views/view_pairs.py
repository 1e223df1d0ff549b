"""N views located as pairs through the two-view matcher, the pairs' matches combined.

The thesis [3]_ locates an object point from two views (2.2, 3.6) with the matcher of
chapter 3 and the eq. 9 bound.  :func:`locate_pairs` keeps that matcher for N views, so
that a pair of views gives exactly what the two-view path gives and more views can only
add pairs to it [1]_:

1. the *reference*: the view nearest the centre of the pattern (:func:`pair_reference`;
   of two views, the first);
2. the reference paired with each other view as a two-view
   :class:`~robostereo.robot.capture.capture_folder.Capture`
   (:meth:`~robostereo.robot.views.viewpoints.ViewsCapture.pair`) and located by
   :func:`~robostereo.robot.capture.locate_pair.locate`: rectified, matched along the
   epipolar lines with its left-right check and calibrated probability, eq. (6)-(9);
   N - 1 pair matches in all;
3. each pair's points kept only where its epipolar lines cross the edge at
   ``min_epipolar_angle_deg`` or more (a pair whose baseline runs along an edge does not
   vote on it: :func:`epipolar_sines`);
4. the pairs' points gathered in the reference image, widest baseline first
   (:func:`combine_pairs`): a point of a later pair joins the nearest earlier point
   within ``agree_px`` pixels whose depth agrees within the two bounds, at most one
   point of each pair to each;
5. each group's inverse depth the inverse-variance mean of its pairs' (eq. 9's bound
   as the spread: the least-squares depth along the reference's ray, in which the
   reference's own edge error cancels between pairs on opposite sides [2]_), its bound
   that mean's, widened by how far the first point lies from it;
6. reported: every point of the reference's widest pair, and the other pairs' points
   that ``min_pairs`` pairs agree on (one pair cannot check its own match, a second one
   can).

References
----------
.. [1] M. Okutomi and T. Kanade, "A multiple-baseline stereo", IEEE PAMI 15(4), 1993
   (inverse depth, the pairs' evidence summed).
.. [2] R. Hartley and A. Zisserman, *Multiple View Geometry*, 2nd ed., 2003, 12.2
   (least-squares triangulation over views).
.. [3] Kim (1989), the thesis, 2.2, chapter 3, 3.6-3.7 (eq. 6-9).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from robostereo.errors import InputError, PlausibilityWarning, warn_input
from robostereo.geometry.poses import as_se3
from robostereo.robot.capture.locate_pair import Located, locate
from robostereo.robot.views.frame_checks import grey_gradient
from robostereo.robot.views.located_points import LocatedViews
from robostereo.robot.views.view_agreement import (
    DOUBTFUL_CONFIDENCE,
    PairAgreement,
    pair_agreement,
)
from robostereo.robot.views.viewpoints import ViewsCapture

__all__ = [
    "combine_pairs",
    "epipolar_sines",
    "is_pairs",
    "locate_pairs",
    "pair_parts",
    "pair_reference",
    "views_agreement",
    "warn_disagreement",
]

_F = NDArray[np.float64]


def pair_reference(capture: ViewsCapture) -> int:
    """The reference view: nearest the centroid of the optical centres (the first of
    those equally near: view 0 of a pair).

    Its pairs are the pattern's shortest (easiest to match; on the real DTU views,
    turned 29 deg between neighbours, with every pair's point reported and before the
    rectified frames that hold both views, the reference at one end of three located 931
    points, 79.8 % of them on an edge of a held-out view, at the centre 1964 at 89.3 %).

    >>> from robostereo.geometry.camera import SEED_CAMERA
    >>> from robostereo.geometry.poses import se3_from_scara
    >>> w, h = SEED_CAMERA.image_size
    >>> images = tuple(np.zeros((h, w), np.uint8) for _ in range(3))
    >>> poses = tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20.0, 0.0, 20.0))
    >>> pair_reference(ViewsCapture(images, SEED_CAMERA, poses, depth_range_mm=(900, 1100)))
    1
    """
    c = capture.centres
    return int(np.argmin(np.linalg.norm(c - c.mean(axis=0), axis=1)))


def is_pairs(capture: ViewsCapture, params: Any) -> bool:
    """Whether ``locate_views(capture, params=params)`` locates by pairs (``matcher``
    ``'pairs'``, or ``'auto'`` with two views) rather than by the plane sweep."""
    return bool(params.matcher == "pairs" or (params.matcher == "auto" and len(capture) == 2))


def epipolar_sines(capture: ViewsCapture, ref: int, other: int, world: _F, pixel: _F,
                   gradient: tuple[_F, _F]) -> _F:
    """Sine of the angle between each point's edge and the pair's epipolar line through it.

    Parameters
    ----------
    capture : ViewsCapture
    ref, other : int
        The pair's views (`ref` the reference).
    world : ndarray, shape (M, 3)
        The pair's points, world mm.
    pixel : ndarray, shape (M, 2)
        ``(x, y)`` of each in the reference's grabbed image.
    gradient : tuple of ndarray, each shape (H, W)
        The reference's ``(gx, gy)``.

    Returns
    -------
    ndarray, shape (M,)
        ``|e . n|``: `e` the epipolar line's unit direction in the grabbed image (the
        image of the point moved along the baseline, lens distortion included), `n` the
        edge's unit normal (the gradient's direction); 1 for an edge across the line, 0
        for one along it, 0 where the gradient vanishes.
    """
    m = len(world)
    if not m:
        return np.zeros(0)
    cam = capture.camera
    pose = capture.poses[ref]
    c = capture.centres
    b = c[other] - c[ref]
    depth = (world - c[ref]) @ as_se3(pose).rotation[:, 2]
    step = (0.01 * np.abs(depth))[:, None] * (b / np.linalg.norm(b))
    uv0, _ = cam.project(world, pose)
    uv1, _ = cam.project(world + step, pose)
    e = uv1 - uv0
    h, w = gradient[0].shape
    col = np.clip(np.rint(pixel[:, 0]).astype(np.intp), 0, w - 1)
    row = np.clip(np.rint(pixel[:, 1]).astype(np.intp), 0, h - 1)
    n = np.column_stack([gradient[0][row, col], gradient[1][row, col]])
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.abs(np.einsum("ij,ij->i", e, n)) / (np.linalg.norm(e, axis=1)
                                                    * np.linalg.norm(n, axis=1))
    return np.nan_to_num(s, nan=0.0)


def combine_pairs(centre: _F, axis: _F, parts: list[dict[str, Any]], *,
                  agree_px: float) -> dict[str, Any]:
    """Gather the pairs' points in the reference image and combine their depths.

    Parameters
    ----------
    centre, axis : ndarray, shape (3,)
        The reference's optical centre (world mm) and optical axis (unit).
    parts : list of dict
        One per pair, widest baseline first: ``pixel`` (M, 2) in the reference's grabbed
        image, ``world`` (M, 3) mm, ``bound`` (M,) eq. 9 depth bound mm,
        ``probability`` (M,).
    agree_px : float
        Farthest a later pair's point may lie from a group's first point, pixels.

    Returns
    -------
    dict
        Per group (G of them): ``world`` (G, 3), ``depth`` (G,) along `axis`, ``bound``
        (G,), ``pixel`` (G, 2) of the first point, ``members`` (G, P) bool (which pairs
        agree), ``probability`` (G,) the largest of its points', ``spread_px`` (G,) RMS
        distance of its points from the first, pixels.

    Notes
    -----
    Inverse depth ``rho = 1 / Z`` has the variance ``(bound / Z**2)**2`` (eq. 9's bound
    as one standard deviation); a group's ``rho`` is the inverse-variance mean, its bound
    the least of its points' bounds (the reference's own edge error is shared by every
    pair, so the mean is not credited with more) plus the first point's distance from
    the mean (a group whose pairs disagree within their bounds says so).  A group of one point keeps
    that point and its bound exactly.
    """
    n_parts = len(parts)
    g: dict[str, Any] | None = None
    for q, p in enumerate(parts):
        depth = (p["world"] - centre) @ axis
        var = (p["bound"] / depth**2) ** 2
        m = len(depth)
        new = np.ones(m, bool)
        if g is not None and len(g["pixel"]) and m:
            dist, idx = cKDTree(g["pixel"]).query(p["pixel"], distance_upper_bound=agree_px)
            hit = np.isfinite(dist)
            ok = hit.copy()
            j = idx[hit]
            ok[hit] = np.abs(depth[hit] - g["depth"][j]) <= p["bound"][hit] + g["bound"][j]
            cand = np.nonzero(ok)[0]
            cand = cand[np.lexsort((dist[cand], idx[cand]))]
            first = np.ones(len(cand), bool)
            first[1:] = idx[cand][1:] != idx[cand][:-1]
            att, j = cand[first], idx[cand[first]]  # the nearest point of this pair
            g["wsum"][j] += 1.0 / var[att]
            g["rsum"][j] += (1.0 / depth[att]) / var[att]
            g["members"][j, q] = True
            g["bmin"][j] = np.minimum(g["bmin"][j], p["bound"][att])
            g["probability"][j] = np.maximum(g["probability"][j], p["probability"][att])
            g["sq_px"][j] += np.sum((p["pixel"][att] - g["pixel"][j]) ** 2, axis=1)
            new = ~ok  # agreeing points beyond a group's nearest are dropped
        k = np.nonzero(new)[0]
        add = {"pixel": p["pixel"][k], "world": p["world"][k], "depth": depth[k],
               "bound": p["bound"][k], "bmin": p["bound"][k].astype(np.float64),
               "wsum": 1.0 / var[k], "rsum": (1.0 / depth[k]) / var[k],
               "members": np.zeros((len(k), n_parts), bool),
               "probability": p["probability"][k].astype(np.float64),
               "sq_px": np.zeros(len(k))}
        add["members"][:, q] = True
        g = add if g is None else {f: np.concatenate([g[f], add[f]]) for f in g}
    if g is None:
        g = {"pixel": np.zeros((0, 2)), "world": np.zeros((0, 3)), "depth": np.zeros(0),
             "bound": np.zeros(0), "bmin": np.zeros(0), "wsum": np.zeros(0), "rsum": np.zeros(0),
             "members": np.zeros((0, 0), bool), "probability": np.zeros(0),
             "sq_px": np.zeros(0)}
    support = g["members"].sum(axis=1)
    single = support <= 1
    with np.errstate(divide="ignore", invalid="ignore"):
        depth = np.where(single, g["depth"], g["wsum"] / g["rsum"])
        bound = np.where(single, g["bound"], g["bmin"] + np.abs(g["depth"] - depth))
        scale = np.where(single, 1.0, depth / g["depth"])
        spread = np.sqrt(g["sq_px"] / np.maximum(support, 1))
    world = np.where(single[:, None], g["world"],
                     centre + (g["world"] - centre) * scale[:, None])
    return {"world": world, "depth": depth, "bound": bound, "pixel": g["pixel"],
            "members": g["members"], "probability": g["probability"],
            "spread_px": spread}


def _located_pair(capture: ViewsCapture, ref: int, other: int, source: str,
                  params: Any) -> Located | None:
    """Views `ref` and `other` located as a two-view capture; None (with a warning) when
    they share no scene and other pairs remain."""
    name = f"{source} (views {capture.view_name(ref)} and {capture.view_name(other)})"
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", PlausibilityWarning)
            located = locate(capture.pair(ref, other), params=params,
                             source=source if len(capture) == 2 else name)
    except InputError as e:
        if len(capture) == 2:
            raise
        warn_input(f"{e}: the pair is left out")
        return None
    for w in caught:  # each of the pair's warnings, naming the pair
        msg = str(w.message)
        if issubclass(w.category, PlausibilityWarning):
            warn_input(msg if msg.startswith(source) or len(capture) == 2 else f"{name}: {msg}")
        else:
            warnings.warn(w.message, w.category, stacklevel=2)
    return located


def pair_parts(capture: ViewsCapture, params: Any, source: str,
               progress: Callable[[int, int], None] | None = None
               ) -> tuple[int, list[int], list[dict[str, Any]]]:
    """Steps 1-3: the reference, each pair located, its points along an edge dropped.

    Returns
    -------
    ref : int
        The reference view.
    views : list of int
        The other view of each pair located, widest baseline first (a pair that shares
        no scene is left out with a warning).
    parts : list of dict
        One per pair: ``pixel`` (M, 2) in the reference's grabbed image, ``world``
        (M, 3) mm, ``bound`` (M,) eq. 9 bound mm, ``probability`` (M,).

    Raises
    ------
    InputError
        No pair located (two views that share no scene, or all pairs left out).
    """
    p = params
    n = len(capture)
    ref = pair_reference(capture)
    c = capture.centres
    others = [k for k in range(n) if k != ref]
    others.sort(key=lambda k: -float(np.linalg.norm(c[k] - c[ref])))
    sine_min = float(np.sin(np.radians(p.min_epipolar_angle_deg)))
    gradient = grey_gradient(capture, ref) if n > 2 else None
    parts: list[dict[str, Any]] = []
    views: list[int] = []
    for done, k in enumerate(others):
        loc = _located_pair(capture, ref, k, source, p.pair_match)
        if loc is not None:
            keep = np.ones(len(loc), bool)
            if gradient is not None:  # a pair along an edge does not vote on it
                keep = epipolar_sines(capture, ref, k, loc.world, loc.left_pixel,
                                      gradient) >= sine_min
            parts.append({"pixel": loc.left_pixel[keep], "world": loc.world[keep],
                          "bound": loc.z_bound[keep], "probability": loc.probability[keep]})
            views.append(k)
        if progress is not None:
            progress(done + 1, len(others))
    if not parts:
        raise InputError(f"{source}: no pair of views with view {capture.view_name(ref)} "
                         "shares a scene; check the poses and the depth range")
    return ref, views, parts


def warn_disagreement(capture: ViewsCapture, ref: int, views: list[int],
                      agreement: PairAgreement, q: int, source: str, *, carried_mm: float,
                      typical_mm: float) -> None:
    """Warn that pair `q` disagrees with another beyond the bounds and no view can be
    blamed: the views named, the bounds' gain and the confidence held."""
    name = capture.view_name
    d = agreement.disagreement
    r = int(np.nanargmax(np.abs(np.where(np.isfinite(d[q]), d[q], np.nan))))
    c = capture.centres
    pose_mm = abs(d[q, r]) * float(np.linalg.norm(c[views[q]] - c[ref]))
    warn_input(f"{source}: the pairs of view {name(ref)} with views {name(views[q])} and "
               f"{name(views[r])} disagree on depth by {100 * abs(d[q, r]):.2g} % (a pose "
               f"off along a baseline by up to {pose_mm:.2g} mm, where `uncertainty: "
               f"baseline_mm` says {capture.baseline_uncertainty_mm:g}): the bounds carry "
               f"it, {carried_mm:.2g} mm more than their median {typical_mm:.2g} mm, and "
               f"no point of theirs has a confidence over {DOUBTFUL_CONFIDENCE}")


def views_agreement(capture: ViewsCapture, ref: int, views: list[int],
                    parts: list[dict[str, Any]], params: Any, source: str, *,
                    bounds: bool = True
                    ) -> tuple[int | None, PairAgreement, NDArray[np.bool_]]:
    """Whether the pairs agree on depth (:func:`~robostereo.robot.views.view_agreement.
    pair_agreement`), what they do not warned about naming the views.

    With `bounds` False only a lone view is warned about: the caller holds what remains
    against bounds of its own (:func:`warn_disagreement`).

    Returns
    -------
    lone : int or None
        The view (capture index) whose pose alone disagrees with the others along its
        baseline, to be left out; None.
    agreement : PairAgreement
    doubtful : ndarray, shape (P,), bool
        The pairs whose bounds the disagreement more than doubles (warned about): no
        view to blame, so none of their points is sure (their confidence is to be held
        to :data:`~robostereo.robot.views.view_agreement.DOUBTFUL_CONFIDENCE`).
    """
    c = capture.centres
    pose = as_se3(capture.poses[ref])
    agreement = pair_agreement(c[ref], pose.rotation[:, 2], parts,
                               np.linalg.norm(c[views] - c[ref], axis=1),
                               agree_px=params.agree_px,
                               baseline_uncertainty_mm=capture.baseline_uncertainty_mm,
                               lone_view_factor=params.lone_view_factor)
    name = capture.view_name
    d = agreement.disagreement
    if agreement.lone is not None:
        q = agreement.lone
        k = views[q]
        off = float(np.nanmedian(np.abs(np.delete(d[q], q))))
        warn_input(f"{source}: view {name(k)}'s depths are {100 * off:.2g} % off those of "
                   f"the other views' pairs with view {name(ref)} (its pose about "
                   f"{off * float(np.linalg.norm(c[k] - c[ref])):.2g} mm off along the "
                   "baseline): it is left out")
        return k, agreement, np.zeros(len(parts), bool)
    if not bounds:
        return None, agreement, np.zeros(len(parts), bool)
    # said when what the bounds gain outgrows them: the pairs' points lay far outside
    depth = [float(np.median((part["world"] - c[ref]) @ pose.rotation[:, 2]))
             if len(part["world"]) else 0.0 for part in parts]
    typical = np.array([float(np.median(part["bound"])) if len(part["bound"]) else np.inf
                        for part in parts])
    doubtful = agreement.extra * np.array(depth) > typical
    if doubtful.any():
        q = int(np.argmax(agreement.extra * np.array(depth) / typical))
        warn_disagreement(capture, ref, views, agreement, q, source,
                          carried_mm=float(agreement.extra[q] * depth[q]),
                          typical_mm=float(typical[q]))
    return None, agreement, doubtful


def locate_pairs(capture: ViewsCapture, *, params: Any = None,
                 progress: Callable[[int, int], None] | None = None,
                 source: str = "capture") -> LocatedViews:
    """Locate the edge points of N views as N - 1 two-view pairs, combined.

    Parameters
    ----------
    capture : ViewsCapture
    params : ViewsParameters, optional
        Its ``min_epipolar_angle_deg``, ``agree_px``, ``min_pairs`` and ``pair_match``
        (the pairs' :class:`~robostereo.robot.capture.locate_pair.LocateParameters`).
    progress : callable, optional
        ``progress(done, total)`` after each pair.
    source : str
        The capture's name in warnings and errors.

    Returns
    -------
    LocatedViews
        ``window_cost`` and ``distinct`` are NaN (the pairs' matcher scores its own
        windows); ``residual_px`` is the RMS distance between the pairs' points of a
        group in the reference image; ``views_checked`` counts the other views the
        point falls inside, ``views_against`` those of them whose pair did not agree.

    Raises
    ------
    InputError
        Two views that share no scene (with more views, such a pair is left out with a
        warning; all of them left out is an error).

    Notes
    -----
    The module's steps 1-6.  A capture of two views gives the two-view path's points,
    bounds and probabilities exactly (one pair, every point its own group).

    References
    ----------
    Kim (1989), the thesis, 2.2, chapter 3, 3.6-3.7; Okutomi & Kanade 1993.
    """
    from robostereo.robot.views.views_parameters import ViewsParameters

    p = params if params is not None else ViewsParameters()
    n = len(capture)
    # -- each pair through the two-view matcher (rectify, match, eq. 6-9)
    ref, views, parts = pair_parts(capture, p, source, progress)
    c = capture.centres
    pose = as_se3(capture.poses[ref])
    centre, axis = c[ref], pose.rotation[:, 2]
    # -- pairs that disagree on depth: a lone view left out, the rest carried by bounds
    if len(parts) >= 2 and p.lone_view_factor is not None:
        lone, agreement, doubtful = views_agreement(capture, ref, views, parts, p, source)
        if lone is not None:
            keep = np.array([k for k in range(n) if k != lone])
            rest = locate_pairs(capture.subset(keep), params=p, source=source)
            return rest.in_views(keep, n)
        for q, part in enumerate(parts):
            part["bound"] = part["bound"] + agreement.extra[q] * ((part["world"] - centre)
                                                                  @ axis)
            if doubtful[q]:
                part["probability"] = np.minimum(part["probability"], DOUBTFUL_CONFIDENCE)
    # -- gathered in the reference image, widest pair first; agreeing pairs combined
    g = combine_pairs(centre, axis, parts, agree_px=p.agree_px)
    support = g["members"].sum(axis=1)
    keep = (support >= min(p.min_pairs, len(parts))) | g["members"][:, 0]
    members = g["members"][keep]
    m = int(keep.sum())
    seen = np.zeros((m, n), bool)
    seen[:, ref] = True
    seen[:, views] = members
    world = g["world"][keep]
    checked = np.zeros(m, np.intp)
    against = np.zeros(m, np.intp)
    w, h = capture.camera.image_size
    for q, k in enumerate(views):
        with np.errstate(all="ignore"):
            uv, z = capture.camera.project(world, capture.poses[k])
        inside = (z > 0) & (uv[:, 0] >= 0) & (uv[:, 0] <= w - 1) & (uv[:, 1] >= 0) \
            & (uv[:, 1] <= h - 1)
        checked += inside
        against += inside & ~members[:, q]
    nan = np.full(m, np.nan)
    return LocatedViews(world=world, bound_mm=g["bound"][keep],
                        confidence=g["probability"][keep],
                        view_count=seen.sum(axis=1).astype(np.intp),
                        reference=np.full(m, ref, np.intp), pixel=g["pixel"][keep],
                        depth_mm=g["depth"][keep], views=seen,
                        residual_px=g["spread_px"][keep], window_cost=nan, distinct=nan.copy(),
                        views_seen=np.full(m, len(views), np.intp), views_checked=checked,
                        views_against=against)
