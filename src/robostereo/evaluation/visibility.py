"""Which left pixels the right view sees, from the ground truth, and where outlines go missing.

A left pixel whose scene point the right view cannot see (it is *half-occluded*: a
nearer surface covers it there, or it falls outside the right image) has no right
match; a matcher that refuses it is right to.  The figures near depth steps are
therefore also given over the edge points *visible in both views*, and the near-step
points a matcher does not accept are sorted by why (:func:`missing_breakdown`).

Visibility is read off the ground truth (:func:`left_visibility`) in two ways:

*z-buffer* (:func:`zbuffer_occlusion`)
    every known left pixel is projected into the right view along its row and a pixel is
    hidden when a *nearer* left pixel's footprint covers its right position.  A pixel's
    footprint spans from its left border to its right border, each moved by the
    disparity there: the mean of the two pixels' disparities where they differ by at most
    ``continuity`` px (one surface, so a slanted surface's footprints tile the right
    row without gaps), the pixel's own otherwise (a depth step).  Sub-pixel disparities
    are handled by these intervals, never by equal integer positions.
*left-right cross-check* (:func:`cross_check_occlusion`)
    where the right view's ground truth exists: that ground truth at the pixels within
    1 px of ``x - d``; a nearer surface there (more than ``tolerance`` px larger
    disparity at all of them) hides the left pixel, the same disparity (within
    ``tolerance`` at one) shows it; anything else gives no verdict.

A pixel is *hidden* when the z-buffer hides it or the cross-check does, or when its
right position lies outside the right image; *visible* when it is known and not hidden;
*unknown* where the left ground truth is unknown (:data:`VISIBLE`, :data:`HIDDEN`,
:data:`UNKNOWN`).  An edge point is visible when a pixel of its row within 1.5 px of
its sub-pixel position is (an occluding contour is seen in both views even though the
background pixels beside it are not, and its intensity edge often lies 1-1.5 px from
where the ground truth's surface ends), hidden when all of them are
(:func:`edge_visibility`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_nonnegative
from robostereo.evaluation.rules import (
    MatchScore,
    coverage_curve,
    rule_errors,
    score_matches,
)

__all__ = [
    "BREAKDOWN",
    "HIDDEN",
    "UNKNOWN",
    "VISIBLE",
    "MissingBreakdown",
    "Visibility",
    "VisibilityFigures",
    "cross_check_occlusion",
    "edge_visibility",
    "format_visibility_figures",
    "left_visibility",
    "missing_breakdown",
    "visibility_figures",
    "zbuffer_occlusion",
]

#: visibility codes of :class:`Visibility` and :func:`edge_visibility`
VISIBLE, HIDDEN, UNKNOWN = 1, 0, -1

#: why an edge point is not accepted, in the order :func:`missing_breakdown` tests it
BREAKDOWN: tuple[str, ...] = ("hidden", "visibility_unknown", "no_candidate",
                              "best_right_refused", "best_wrong")


def _map(name: str, a: ArrayLike) -> NDArray[np.float64]:
    g = np.asarray(a, dtype=float)
    if g.ndim != 2 or g.size == 0:
        raise InputError(f"{name} must be a non-empty (H, W) map, got shape {g.shape}")
    return np.where(np.isfinite(g), g, np.nan)


def zbuffer_occlusion(
    gt_left: ArrayLike, *, continuity: float = 1.0,
) -> NDArray[np.bool_]:
    """Left pixels hidden from the right view by a nearer left pixel (z-buffer).

    Parameters
    ----------
    gt_left : array_like, shape (H, W)
        Left ground-truth disparity, NaN (or inf) where unknown; the left pixel
        ``(j, i)`` lies at ``j - d`` in the right view.
    continuity : float
        Neighbours whose disparities differ by at most this (1 px) are one surface:
        their shared border moves by the mean disparity.

    Returns
    -------
    ndarray of bool, shape (H, W)
        True where a known pixel's right position ``j - d`` lies inside the footprint
        ``[lo, hi)`` of a known pixel of the row with a larger disparity (half-open, so
        the footprints of one surface tile the right row: ground truth in half pixels
        often puts a right position exactly on a shared border).  Unknown
        pixels are False (neither hidden nor hiding).

    Notes
    -----
    1. Footprint of pixel ``k``: ``lo = k - 0.5 - d_l``, ``hi = k + 0.5 - d_r`` with
       ``d_l`` (``d_r``) the mean of ``d_k`` and its left (right) neighbour's disparity
       when they differ by at most ``continuity``, else ``d_k``.
    2. A nearer pixel ``k`` can only cover ``j`` from its right (``k - j`` is about
       ``d_k - d_j > 0``), so ``k = j + 1 .. j + ceil(max d - min d) + 1`` are tried,
       one whole-image comparison per offset.

    Examples
    --------
    A box at disparity 6 over a background at 2 hides the four background pixels left
    of it (6 - 2 = 4 px):

    >>> g = np.array([[2.0] * 8 + [6.0] * 4 + [2.0] * 4])
    >>> zbuffer_occlusion(g)[0].astype(int).tolist()
    [0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0]

    A sub-pixel gap of 2.6 px hides the pixels whose right position falls under the
    box's footprint, from ``8 - 0.5 - 4.6 = 2.9``: centres 5, 6, 7 land at 3, 4, 5
    (pixel 4 at 2, outside):

    >>> zbuffer_occlusion(np.array([[2.0] * 8 + [4.6] * 4]))[0].astype(int).tolist()
    [0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0, 0]
    """
    g = _map("gt_left", gt_left)
    require_nonnegative("continuity", continuity)
    h, w = g.shape
    cols = np.arange(w, dtype=float)[None, :]
    pad = np.pad(g, ((0, 0), (1, 1)), constant_values=np.nan)
    left_nb, right_nb = pad[:, :-2], pad[:, 2:]
    with np.errstate(invalid="ignore"):
        dl = np.where(np.abs(left_nb - g) <= continuity, 0.5 * (left_nb + g), g)
        dr = np.where(np.abs(right_nb - g) <= continuity, 0.5 * (right_nb + g), g)
    lo, hi = cols - 0.5 - dl, cols + 0.5 - dr
    xr = cols - g
    hidden = np.zeros((h, w), dtype=bool)
    known = np.isfinite(g)
    if not known.any():
        return hidden
    reach = math.ceil(float(np.nanmax(g) - np.nanmin(g))) + 1
    with np.errstate(invalid="ignore"):  # NaN compares False: unknown pixels do nothing
        for o in range(1, min(reach, w - 1) + 1):
            hidden[:, :-o] |= ((g[:, o:] > g[:, :-o]) & (lo[:, o:] <= xr[:, :-o])
                               & (xr[:, :-o] < hi[:, o:]))
    return hidden & known


def cross_check_occlusion(
    gt_left: ArrayLike, gt_right: ArrayLike, *, tolerance: float = 1.0,
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Left-right cross-check of the two ground truths.

    Parameters
    ----------
    gt_left, gt_right : array_like, shape (H, W)
        Left and right ground-truth disparities (right ``(x, y)`` matches left
        ``(x + d, y)``), NaN where unknown.
    tolerance : float
        Pixels (1).

    Returns
    -------
    hidden : ndarray of bool, shape (H, W)
        The right ground truth at the pixels within 1 px of ``x_r = j - d`` (one when
        ``x_r`` is whole, else two; those inside the image) is known and more than
        ``tolerance`` larger at all of them: a nearer
        surface covers the point in the right view.
    checked : ndarray of bool, shape (H, W)
        Pixels with a verdict: hidden, or the right ground truth at one of the two
        pixels is within ``tolerance`` of ``d`` (seen).  Pixels whose right position
        leaves the image, or lands on unknown or farther right ground truth, have none.

    Examples
    --------
    >>> gl = np.array([[2.0] * 8 + [6.0] * 4 + [2.0] * 4])
    >>> gr = np.array([[2.0] * 2 + [6.0] * 4 + [2.0] * 10])
    >>> hid, chk = cross_check_occlusion(gl, gr)
    >>> hid[0].astype(int).tolist()
    [0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0]
    >>> bool(chk[0, 2:].all()), bool(chk[0, :2].any())
    (True, False)
    """
    gl, gr = _map("gt_left", gt_left), _map("gt_right", gt_right)
    if gl.shape != gr.shape:
        raise InputError(f"gt_right must have the shape of gt_left {gl.shape}, got {gr.shape}")
    require_nonnegative("tolerance", tolerance)
    h, w = gl.shape
    xr = np.arange(w, dtype=float)[None, :] - gl
    rows = np.broadcast_to(np.arange(h)[:, None], (h, w))
    seen = np.zeros((h, w), dtype=bool)
    nearer = np.zeros((h, w), dtype=bool)
    farther_or_unknown = np.zeros((h, w), dtype=bool)
    inside_any = np.zeros((h, w), dtype=bool)
    with np.errstate(invalid="ignore"):
        base = np.floor(xr)
        for k in (0, 1):
            c = base + k
            inside = np.isfinite(c) & (c >= 0) & (c <= w - 1) & (np.abs(c - xr) < 1)
            v = np.full((h, w), np.nan)
            ci = np.where(inside, c, 0).astype(np.intp)
            v[inside] = gr[rows[inside], ci[inside]]
            known = inside & np.isfinite(v)
            inside_any |= known
            seen |= known & (np.abs(v - gl) <= tolerance)
            nearer |= known & (v > gl + tolerance)
            farther_or_unknown |= inside & ~(known & (v > gl + tolerance))
    hidden = nearer & ~farther_or_unknown & ~seen
    return hidden, (hidden | seen) & np.isfinite(gl)


@dataclass(frozen=True)
class Visibility:
    """Per left pixel, whether the right view sees it (see the module docstring).

    Attributes
    ----------
    state : ndarray of int8, shape (H, W)
        :data:`VISIBLE` (1), :data:`HIDDEN` (0) or :data:`UNKNOWN` (-1).
    zbuffer_hidden : ndarray of bool, shape (H, W)
        :func:`zbuffer_occlusion`.
    out_of_view : ndarray of bool, shape (H, W)
        Known pixels whose right position ``j - d`` lies outside the right image.
    cross_hidden, cross_checked : ndarray of bool, shape (H, W), or None
        :func:`cross_check_occlusion`, with a right ground truth.
    """

    state: NDArray[np.int8]
    zbuffer_hidden: NDArray[np.bool_]
    out_of_view: NDArray[np.bool_]
    cross_hidden: NDArray[np.bool_] | None = None
    cross_checked: NDArray[np.bool_] | None = None

    def agreement(self) -> float:
        """Share of the cross-checked pixels where the z-buffer agrees (NaN without)."""
        if self.cross_checked is None or self.cross_hidden is None:
            return math.nan
        c = self.cross_checked & ~self.out_of_view
        if not c.any():
            return math.nan
        return float(np.mean(self.zbuffer_hidden[c] == self.cross_hidden[c]))


def left_visibility(
    gt_left: ArrayLike, gt_right: ArrayLike | None = None, *, continuity: float = 1.0,
    tolerance: float = 1.0,
) -> Visibility:
    """Which left pixels the right view sees, from the ground truth.

    Parameters
    ----------
    gt_left : array_like, shape (H, W)
        NaN where unknown.
    gt_right : array_like, shape (H, W), optional
        The right view's ground truth; with it, the cross-check too.
    continuity, tolerance : float
        Of :func:`zbuffer_occlusion` and :func:`cross_check_occlusion`.

    Returns
    -------
    Visibility
        Hidden where the z-buffer or the cross-check hides a pixel, or its right
        position leaves the image (``j - d < -0.5``).

    Examples
    --------
    Pixels 0 and 1 land left of the right image, 4-7 behind the box:

    >>> v = left_visibility(np.array([[2.0] * 8 + [6.0] * 4 + [np.nan] * 4]))
    >>> v.state[0].tolist()
    [0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 1, 1, -1, -1, -1, -1]
    """
    g = _map("gt_left", gt_left)
    z = zbuffer_occlusion(g, continuity=continuity)
    known = np.isfinite(g)
    with np.errstate(invalid="ignore"):
        out = known & (np.arange(g.shape[1])[None, :] - g < -0.5)
    hidden = z | out
    ch = cc = None
    if gt_right is not None:
        ch, cc = cross_check_occlusion(g, gt_right, tolerance=tolerance)
        hidden |= ch
    state = np.where(known, np.where(hidden, HIDDEN, VISIBLE), UNKNOWN).astype(np.int8)
    return Visibility(state=state, zbuffer_hidden=z, out_of_view=out, cross_hidden=ch,
                      cross_checked=cc)


def edge_visibility(rows: ArrayLike, x: ArrayLike, state: ArrayLike, *,
                    reach: float = 1.5) -> NDArray[np.int8]:
    """Per edge point: visible when a pixel of its row within ``reach`` of it is.

    Parameters
    ----------
    rows, x : array_like, shape (N,)
        Edge points (row, sub-pixel column).
    state : array_like of int, shape (H, W)
        :attr:`Visibility.state`.
    reach : float
        Pixels ``j`` of the row with ``|j - x| <= reach`` (1.5: the two pixels round
        ``x`` and the nearer of their neighbours; an outline's intensity edge often lies
        1-1.5 px from where the ground truth's surface ends).

    Returns
    -------
    ndarray of int8, shape (N,)
        :data:`VISIBLE` when one of those pixels is visible, :data:`HIDDEN` when all of
        them (inside the image) are hidden, :data:`UNKNOWN` otherwise.

    Examples
    --------
    >>> s = np.array([[1, 1, 0, 0, 0, 0, -1, 1]], dtype=np.int8)
    >>> edge_visibility([0, 0, 0, 0], [1.5, 3.5, 4.6, 6.5], s).tolist()
    [1, 0, -1, 1]
    >>> edge_visibility([0], [2.6], s, reach=2.0).tolist()  # pixel 1 is 1.6 px away
    [1]
    """
    s = np.asarray(state)
    if s.ndim != 2:
        raise InputError(f"state must be an (H, W) map, got shape {s.shape}")
    require_nonnegative("reach", reach)
    h, w = s.shape
    r = np.clip(np.asarray(rows, dtype=np.intp), 0, h - 1)
    xs = np.asarray(x, dtype=float)
    k = int(np.ceil(reach)) + 1
    cols = np.floor(xs).astype(np.intp)[:, None] + np.arange(-k + 1, k + 1)
    use = (np.abs(cols - xs[:, None]) <= reach + 1e-9) & (cols >= 0) & (cols <= w - 1)
    v = np.where(use, s[r[:, None], np.clip(cols, 0, w - 1)], HIDDEN)
    return np.where((v == VISIBLE).any(axis=1), VISIBLE,
                    np.where((v == HIDDEN).all(axis=1), HIDDEN, UNKNOWN)).astype(np.int8)


@dataclass(frozen=True)
class MissingBreakdown:
    """The counted edge points of a subset that a method does not accept, by why.

    Attributes
    ----------
    counted, accepted : int
        Counted points (known ground truth at the nearest pixel); those accepted.
    counts : dict of str to int
        :data:`BREAKDOWN` -> points: hidden in the other view, visibility unknown,
        no candidate (no best disparity at all), best disparity right but refused
        (confidence below the acceptance), best disparity wrong (by the rule used).
    """

    counted: int
    accepted: int
    counts: dict[str, int]

    def __post_init__(self) -> None:
        if set(self.counts) != set(BREAKDOWN) or sum(self.counts.values()) != (
                self.counted - self.accepted):
            raise InputError(f"MissingBreakdown needs the counts {BREAKDOWN} summing to "
                             f"counted - accepted, got {self.counts}")

    def as_dict(self) -> dict[str, Any]:
        return {"counted": self.counted, "accepted": self.accepted, **self.counts}


def missing_breakdown(
    rows: ArrayLike, x: ArrayLike, accepted: ArrayLike, best: ArrayLike,
    gt_disparity: ArrayLike, visibility: ArrayLike, *, subset: ArrayLike | None = None,
    tolerance: float = 1.0, rule: str = "silhouette",
) -> MissingBreakdown:
    """Why the counted points of ``subset`` are not accepted.

    Parameters
    ----------
    rows, x : array_like, shape (N,)
    accepted, best : array_like, shape (N,)
        The default point's disparities (NaN where refused) and the best match of every
        point (NaN where there is none).
    gt_disparity : array_like, shape (H, W)
    visibility : array_like of int, shape (N,)
        :func:`edge_visibility`.
    subset : array_like of bool, shape (N,), optional
    tolerance, rule
        Of :func:`~robostereo.evaluation.rules.rule_errors`.

    Returns
    -------
    MissingBreakdown

    Examples
    --------
    >>> gt = np.full((1, 8), 5.0)
    >>> b = missing_breakdown([0] * 5, [1.0, 2.0, 3.0, 4.0, 5.0],
    ...                       [5.0, np.nan, np.nan, np.nan, np.nan],
    ...                       [5.0, 5.2, 9.0, np.nan, 5.0], gt, [1, 1, 1, 1, 0])
    >>> [b.counts[k] for k in BREAKDOWN]  # hidden, unknown, none, right refused, wrong
    [1, 0, 1, 1, 1]
    """
    g = np.asarray(gt_disparity, dtype=float)
    a = np.asarray(accepted, dtype=float)
    known, err = rule_errors(rows, x, best, g, rule=rule)
    vis = np.asarray(visibility)
    if vis.shape != known.shape:
        raise InputError(f"visibility must have shape {known.shape}, got {vis.shape}")
    if subset is not None:
        known = known & np.asarray(subset, dtype=bool)
    acc = known & np.isfinite(a)
    miss = known & ~acc
    hid = miss & (vis == HIDDEN)
    unk = miss & (vis == UNKNOWN)
    rest = miss & (vis == VISIBLE)
    none = rest & ~np.isfinite(np.asarray(best, dtype=float))
    scored = rest & ~none
    with np.errstate(invalid="ignore"):
        right = scored & (err <= tolerance)
    wrong = scored & ~right
    counts = {k: int(v.sum()) for k, v in zip(BREAKDOWN, (hid, unk, none, right, wrong),
                                              strict=True)}
    return MissingBreakdown(int(known.sum()), int(acc.sum()), counts)


@dataclass(frozen=True)
class VisibilityFigures:
    """A scene's near-step figures over all edge points and over the visible ones.

    Attributes
    ----------
    near_points : dict of str to int
        Counted near-step edge points: ``"all"``, ``"visible"``, ``"hidden"``,
        ``"unknown"`` (by :func:`edge_visibility`).
    scores : dict
        ``method -> {"all" | "visible" | "hidden": MatchScore}``, near steps, by the
        silhouette rule, the default point.
    coverage : dict
        ``method -> {"all" | "visible": tuple}``: coverage of the method's confidence
        curve at each false rate of ``levels`` near steps (sparse methods only).
    missing : dict
        ``method -> {"near" | "away": MissingBreakdown}`` (sparse methods only).
    agreement : float
        Share of cross-checked pixels where z-buffer and cross-check agree (NaN without
        a right ground truth).
    levels : tuple of float
    """

    near_points: dict[str, int]
    scores: dict[str, dict[str, MatchScore]]
    coverage: dict[str, dict[str, tuple[float, ...]]] = field(default_factory=dict)
    missing: dict[str, dict[str, MissingBreakdown]] = field(default_factory=dict)
    agreement: float = math.nan
    levels: tuple[float, ...] = ()

    def as_dict(self) -> dict[str, Any]:
        def score(s: MatchScore) -> dict[str, Any]:
            return {"counted": s.counted, "matched": s.matched, "false": s.false,
                    "matched_percent": _clean(100 * s.matched_fraction),
                    "false_percent": _clean(100 * s.false_fraction)}

        return {
            "near_points": dict(self.near_points),
            "agreement_zbuffer_cross_check": _clean(self.agreement),
            "near_silhouette_rule": {
                m: {k: score(s) for k, s in sides.items()} for m, sides in self.scores.items()},
            "near_coverage_at_false": {
                m: {k: {f"{100 * f:g}%": c for f, c in zip(self.levels, cov, strict=True)}
                    for k, cov in sides.items()} for m, sides in self.coverage.items()},
            "not_accepted": {m: {k: b.as_dict() for k, b in sides.items()}
                             for m, sides in self.missing.items()},
        }  # fmt: skip


def _clean(v: float | None) -> float | None:
    return None if v is None or not math.isfinite(v) else float(v)


def visibility_figures(
    rows: ArrayLike, x: ArrayLike, gt_disparity: ArrayLike, near: ArrayLike,
    visibility: Visibility, methods: Sequence[Any], *, levels: tuple[float, ...],
    tolerance: float = 1.0,
) -> VisibilityFigures:
    """The figures of :class:`VisibilityFigures` for methods at the same edge points.

    ``methods`` are :class:`~robostereo.evaluation.outlines.MethodPoints` (``method``,
    ``disparity``, optionally ``best`` and ``confidence``); ``near`` is the near-step
    flag of each point (:func:`~robostereo.evaluation.rules.near_steps`).
    """
    g = np.asarray(gt_disparity, dtype=float)
    r = np.asarray(rows, dtype=np.intp)
    xs = np.asarray(x, dtype=float)
    nr = np.asarray(near, dtype=bool)
    vis = edge_visibility(r, xs, visibility.state)
    known = np.isfinite(g[np.clip(r, 0, g.shape[0] - 1),
                          np.clip(np.rint(xs).astype(np.intp), 0, g.shape[1] - 1)])
    base = known & nr
    subsets = {"all": nr, "visible": nr & (vis == VISIBLE), "hidden": nr & (vis == HIDDEN)}
    points = {"all": int(base.sum()), "visible": int((base & (vis == VISIBLE)).sum()),
              "hidden": int((base & (vis == HIDDEN)).sum()),
              "unknown": int((base & (vis == UNKNOWN)).sum())}
    scores, coverage, missing = {}, {}, {}
    for m in methods:
        scores[m.method] = {k: score_matches(r, xs, m.disparity, g, tolerance=tolerance,
                                             rule="silhouette", subset=s)
                            for k, s in subsets.items()}
        if m.best is None or m.confidence is None:
            continue
        coverage[m.method] = {
            k: tuple(coverage_curve(r, xs, m.best, m.confidence, g, tolerance=tolerance,
                                    rule="silhouette", subset=subsets[k]).coverage_at(f)
                     for f in levels) for k in ("all", "visible")}
        missing[m.method] = {k: missing_breakdown(r, xs, m.disparity, m.best, g, vis,
                                                  subset=s, tolerance=tolerance)
                             for k, s in (("near", nr), ("away", ~nr))}
    return VisibilityFigures(points, scores, coverage, missing, visibility.agreement(),
                             tuple(levels))


def _pct(n: int, d: int) -> str:
    return f"{100 * n / d:.1f} %" if d else "-"


def format_visibility_figures(vf: VisibilityFigures) -> list[str]:
    """The lines that ``robostereo evaluate`` adds about visibility near depth steps."""
    p = vf.near_points
    agree = ("" if not math.isfinite(vf.agreement) else
             f"; z-buffer and right cross-check agree on {100 * vf.agreement:.1f} %")
    lv = "".join(f"{'<=' + format(100 * f, 'g') + '%':>8s}" for f in vf.levels)
    lines = [f"  near steps, visible in both views (ground truth): {p['visible']} of "
             f"{p['all']} points, hidden {p['hidden']}, unknown {p['unknown']}{agree}",
             f"  near, silhouette rule   all: matched   false{lv}   visible: matched   false"
             f"{lv}   hidden: matched   false"]
    for m, sides in vf.scores.items():
        cov = vf.coverage.get(m, {})
        parts = []
        for k in ("all", "visible"):
            s = sides[k]
            c = "".join(f"{100 * v:7.1f}%" for v in cov[k]) if k in cov else " " * 8 * len(
                vf.levels)
            parts.append(f"{100 * s.matched_fraction:14.1f} % {100 * s.false_fraction:6.2f} %"
                         f"{c}")
        h = sides["hidden"]
        parts.append(f"{_pct(h.matched, h.counted):>18} {100 * h.false_fraction:6.2f} %")
        lines.append(f"  {'SGBM' if m == 'sgbm' else m:<12}" + "".join(parts))
    for m, sides in vf.missing.items():
        b = sides["near"]
        miss = b.counted - b.accepted
        c = b.counts
        lines.append(
            f"  near steps not accepted by {m}: {miss} of {b.counted} ({_pct(miss, b.counted)}):"
            f" hidden {c['hidden']}, visibility unknown {c['visibility_unknown']}, no "
            f"candidate {c['no_candidate']}, best right but refused {c['best_right_refused']}"
            f", best wrong {c['best_wrong']}")
    return lines
