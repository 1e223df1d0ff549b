"""Whether the reference's pairs agree on depth: a view whose pose is off along a baseline.

A pose off *across* a baseline moves the epipolar lines and the pose check sees it
(:mod:`~robostereo.robot.views.pose_check`); a pose off *along* a baseline only changes
the baseline's length, and with it every depth of that pair by the same factor (eq. 9
[2]_: ``Z = f D / d``, so ``dZ / Z = dD / D``).  One pair cannot see that; two pairs sharing
the reference's edge points can, since their depths at the same pixel must agree.  The
test that follows [1]_:

1. for each two of the reference's pairs, the median of ``log(Z_q / Z_r)`` over the
   reference pixels both located (within ``agree_px``): their *disagreement* ``D[q, r]``,
   with its standard error from the median absolute deviation;
2. with three or more pairs, a pair whose disagreement with every other is several times
   (``lone_view_factor``) the largest among the others, and beyond what the stated
   ``uncertainty: baseline_mm`` allows, names its other view: that view alone explains
   the disagreement (leave-one-out; the bounds, worst cases, would hide much of it);
3. what disagreement remains among the pairs kept is carried by their bounds: a pair that
   disagrees with another by ``|D|`` (beyond three standard errors) more than the two
   pairs' bounds allow (the median of ``(bound_q + bound_r) / Z`` over the shared pixels,
   eq. 9 with its baseline and disparity terms) may be off by that excess, so its bound
   gains ``excess * Z``; the pose error this implies along the pair's baseline,
   ``excess * D_q``, is reported.

Three views make two pairs, and then which view is off cannot be told: moving either
other view (or the reference) along its baseline, with the scene scaled, explains the
same disagreement.  The views are then named together and the bounds carry it; where
that more than doubles them, no point of those pairs is called sure
(:data:`DOUBTFUL_CONFIDENCE`).

References
----------
.. [1] R. Hartley and A. Zisserman, *Multiple View Geometry*, 2nd ed., 2003, 15.3 and
   18.1: the trifocal constraint and the scale each pair's reconstruction carries.
.. [2] Kim (1989), the thesis, 3.7 (eq. 9: the baseline's share of the depth bound).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

__all__ = ["DOUBTFUL_CONFIDENCE", "PairAgreement", "pair_agreement"]

_F = NDArray[np.float64]

DOUBTFUL_CONFIDENCE = 0.5
"""Highest confidence of a point from pairs whose disagreement more than doubles their
bounds and that no view can be blamed for: as likely wrong as right (a pair far off
locates few points, near the end of the depth range, so its disagreement is measured
short: a simulated pulley view 3 mm off along a 20 mm baseline scaled its pair's depths
by 15 %, the pairs' medians said 6 %)."""

MIN_SHARED = 20
"""Least number of reference pixels two pairs must both locate to be compared."""


@dataclass(frozen=True)
class PairAgreement:
    """How the reference's pairs agree on depth (:func:`pair_agreement`).

    Attributes
    ----------
    disagreement : ndarray, shape (P, P)
        ``D[q, r]``: median ``log(Z_q / Z_r)`` over the pixels both pairs located (NaN
        where they share fewer than :data:`MIN_SHARED`); ``D[r, q] = -D[q, r]``.
    standard_error : ndarray, shape (P, P)
        Of each ``D[q, r]`` (``1.25 * 1.4826 MAD / sqrt(n)``).
    allowed : ndarray, shape (P, P)
        What the two pairs' bounds allow between them: the median of
        ``(bound_q + bound_r) / Z`` over the shared pixels.
    shared : ndarray, shape (P, P), int
        Pixels both pairs located.
    lone : int or None
        The pair (index into the pairs) whose other view alone disagrees with the rest,
        or None.
    beyond_noise : ndarray, shape (P,)
        Each kept pair's largest ``|D|`` less three standard errors (0 for none): what a
        locate whose bounds are not the pairs' (the sweep's) must hold against its own.
    extra : ndarray, shape (P,)
        Relative depth each pair's bound gains (``extra * Z`` mm): its largest
        disagreement with the other pairs kept beyond three standard errors and what
        their bounds allow; 0 for a pair that agrees (and for the lone one).
    pose_error_mm : ndarray, shape (P,)
        ``extra * D_q``: how far along its baseline the pair's other view would be off if
        the disagreement were its alone, mm.
    """

    disagreement: _F
    standard_error: _F
    allowed: _F
    shared: NDArray[np.intp]
    lone: int | None
    beyond_noise: _F
    extra: _F
    pose_error_mm: _F


def _disagreements(centre: _F, axis: _F, parts: list[dict[str, Any]],
                   agree_px: float) -> tuple[_F, _F, _F, NDArray[np.intp]]:
    """Step 1: each two pairs' median log depth ratio, its standard error, what their
    bounds allow (relative) and how many pixels they share."""
    n = len(parts)
    d = np.full((n, n), np.nan)
    se = np.full((n, n), np.nan)
    allowed = np.zeros((n, n))
    shared = np.zeros((n, n), np.intp)
    depth = [(p["world"] - centre) @ axis for p in parts]
    trees = [cKDTree(p["pixel"]) if len(p["pixel"]) else None for p in parts]
    for q in range(n):  # a loop over pairs (a handful), not over points
        for r in range(q + 1, n):
            tree = trees[r]
            if not len(parts[q]["pixel"]) or tree is None:
                continue
            dist, idx = tree.query(parts[q]["pixel"], distance_upper_bound=agree_px)
            hit = np.isfinite(dist)
            zq, zr = depth[q][hit], depth[r][idx[hit]]
            ok = (zq > 0) & (zr > 0)
            ratio = np.log(zq[ok] / zr[ok])
            bq = parts[q].get("bound", np.zeros(len(depth[q])))[hit][ok]
            br = parts[r].get("bound", np.zeros(len(depth[r])))[idx[hit]][ok]
            shared[q, r] = shared[r, q] = len(ratio)
            if len(ratio) < MIN_SHARED:
                continue
            med = float(np.median(ratio))
            err = 1.25 * 1.4826 * float(np.median(np.abs(ratio - med))) / np.sqrt(len(ratio))
            d[q, r], d[r, q] = med, -med
            se[q, r] = se[r, q] = err
            allowed[q, r] = allowed[r, q] = float(np.median((bq + br) / zq[ok]))
    return d, se, allowed, shared


def pair_agreement(centre: _F, axis: _F, parts: list[dict[str, Any]], baselines_mm: _F, *,
                   agree_px: float, baseline_uncertainty_mm: float,
                   lone_view_factor: float) -> PairAgreement:
    """Compare the depths the reference's pairs give at the same pixels (the module's steps).

    Parameters
    ----------
    centre, axis : ndarray, shape (3,)
        The reference's optical centre (world mm) and optical axis (unit).
    parts : list of dict
        One per pair: ``pixel`` (M, 2) in the reference's image, ``world`` (M, 3) mm,
        ``bound`` (M,) mm (eq. 9; taken as 0 when absent).
    baselines_mm : ndarray, shape (P,)
        Each pair's baseline length.
    agree_px : float
        Two pairs' points within this many pixels are at the same reference pixel.
    baseline_uncertainty_mm : float
        The capture's ``uncertainty: baseline_mm`` (eq. 9's ``dD``).
    lone_view_factor : float
        Step 2: how many times the largest disagreement among the other pairs a pair's
        must be for its view alone to be named.

    Returns
    -------
    PairAgreement

    Examples
    --------
    Three pairs seeing one scene at 1000 mm, the third's depths 5 % long (its view 1 mm
    off along a 20 mm baseline):

    >>> rng = np.random.default_rng(0)
    >>> px = rng.uniform(0, 500, (200, 2))
    >>> z = np.full(200, 1000.0) + rng.normal(0, 1, 200)
    >>> parts = [{"pixel": px, "world": np.column_stack([px, z * s])}
    ...          for s in (1.0, 1.0, 1.05)]
    >>> a = pair_agreement(np.zeros(3), np.array([0, 0, 1.0]), parts, np.full(3, 20.0),
    ...                    agree_px=1.0, baseline_uncertainty_mm=0.01, lone_view_factor=4)
    >>> a.lone
    2
    >>> float(a.extra.max())
    0.0
    """
    n = len(parts)
    d, se, by_bounds, shared = _disagreements(centre, axis, parts, agree_px)
    b = np.asarray(baselines_mm, dtype=float)
    stated = baseline_uncertainty_mm / b  # eq. 9's relative baseline term, per pair
    # what the stated uncertainty and the medians' noise allow between pairs q and r
    allowed = stated[:, None] + stated[None, :] + 3.0 * np.nan_to_num(se, nan=0.0)
    # -- step 2: leave one pair out; the rest agree, it alone does not
    lone: int | None = None
    if n >= 3:
        best = 0.0
        for q in range(n):
            rest = np.delete(np.arange(n), q)
            with_q = d[q, rest]
            valid = np.isfinite(with_q)
            among = d[np.ix_(rest, rest)]
            # each pair q is compared with must be held by another of the rest
            held = np.isfinite(among).any(axis=1)
            if not valid.any() or not np.all(held[valid]):
                continue
            if not (np.all(np.abs(with_q[valid]) > allowed[q, rest][valid])
                    and (np.all(with_q[valid] > 0) or np.all(with_q[valid] < 0))):
                continue
            worst_rest = max(float(np.nanmax(np.abs(among))),
                             float(np.nanmax(allowed[np.ix_(rest, rest)])))
            ratio = float(np.min(np.abs(with_q[valid]))) / worst_rest
            if ratio > lone_view_factor and ratio > best:
                lone, best = q, ratio
    # -- step 3: what remains among the pairs kept, carried by their bounds
    kept = np.ones(n, bool)
    if lone is not None:
        kept[lone] = False
    def worst(excess: _F) -> _F:  # each kept pair's largest, 0 for none
        excess = np.where(kept[:, None] & kept[None, :] & np.isfinite(excess), excess,
                          -np.inf)
        return np.where(kept, np.clip(excess.max(axis=1), 0.0, None), 0.0)

    beyond_noise = worst(np.abs(d) - 3.0 * se)
    extra = worst(np.abs(d) - 3.0 * se - by_bounds)
    return PairAgreement(disagreement=d, standard_error=se, allowed=by_bounds,
                         shared=shared, lone=lone, beyond_noise=beyond_noise,
                         extra=extra, pose_error_mm=extra * b)
