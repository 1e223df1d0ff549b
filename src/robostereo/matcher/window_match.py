"""The window matcher's answer per left edge point: disparity, evidence, confidence.

:func:`window_match` reads the summary of the window costs
(:func:`~robostereo.matcher.window_costs.window_costs`, a wide range first narrowed by
:func:`~robostereo.matcher.window_costs.coarse_range`) as evidence about each left edge
point's best disparity: how unique it is, whether the right pixel and the paths along
the row agree, whether a right edge point of the same sign lies there and how similar
it is by the thesis's indices (3.2-3.3).  The disparity is made sub-pixel from that right
edge point or from the parabola of the costs, and the evidence becomes a calibrated
confidence (:mod:`robostereo.matcher.confidence`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.matcher.candidates import SimilarityWeights, pair_similarity
from robostereo.matcher.confidence import DEFAULT_MODEL, FEATURES, ConfidenceModel
from robostereo.matcher.contour_kernels import contour_support
from robostereo.matcher.edge_features import EdgeSet
from robostereo.matcher.window_costs import (
    PATH_PENALTIES,
    WindowCosts,
    coarse_range,
    window_costs,
)
from robostereo.matcher.window_kernels import (
    StreamSummary,
    evidence,
    right_partners,
)

__all__ = [
    "COARSE_MIN_DISPARITIES",
    "CONTOUR_MIN_CONFIDENCE",
    "CONTOUR_REACH",
    "CONTOUR_SHARE",
    "CONTOUR_TOLERANCE",
    "SIMILARITY_CHUNK",
    "SWAP_UNIQUENESS",
    "WindowMatch",
    "contour_accepted",
    "search_costs",
    "window_match",
]

#: the feature columns that :func:`~robostereo.matcher.window_kernels.evidence` fills,
#: in the order it computes them, and the two that the right edge point gives
_EVIDENCE_COLUMNS = np.array([FEATURES.index(name) for name in (
    "uniqueness", "uniqueness_row", "row_agree", "left_right", "out_of_view",
    "path_uniqueness", "path_agree", "path_swapped")], np.int64)
_RIGHT_EDGE, _SIMILARITY = FEATURES.index("right_edge"), FEATURES.index("similarity")

#: where the paths' best disparity is more than a pixel from the windows', it is taken
#: instead when its uniqueness exceeds this (leave-one-scene-out, as the penalties)
SWAP_UNIQUENESS = 0.1

#: a search range of more whole disparities than this is first narrowed by a pass at
#: half resolution (:func:`coarse_range`); narrower ones are searched whole
COARSE_MIN_DISPARITIES = 64

#: figural continuity (:func:`contour_accepted`): a match of at least this confidence is
#: accepted when at least :data:`CONTOUR_SHARE` of the :data:`CONTOUR_REACH` edge points
#: up and down its contour have its disparity (within :data:`CONTOUR_TOLERANCE`) and are
#: accepted on their own; the three chosen leave one scene out on the developer scenes
#: (``benchmarks/bench_contour.py --lift``: each at most 1 % false, 0.5 % away from depth
#: steps, near steps at most 2 % or as today; the most coverage near steps)
CONTOUR_MIN_CONFIDENCE = 0.80
CONTOUR_REACH = 8
CONTOUR_SHARE = 0.5
#: largest disparity difference (pixels) of contour neighbours that support each other
CONTOUR_TOLERANCE = 1.0

#: the evidence, the thesis's similarity of the right edge points found and the
#: confidence are computed this many points at a time, so that their float64
#: temporaries stay small whatever the number of edge points (a chunk's features in
#: float64 are 320 KiB; at 16 384 points, 1.3 MiB, they and the similarity's
#: temporaries were what put the synthetic 640 x 480 pair's peak over twice SGBM's)
SIMILARITY_CHUNK = 1 << 12


@dataclass(frozen=True)
class WindowMatch:
    """Best disparity of every left edge point, its evidence and its confidence.

    Attributes
    ----------
    disparity : ndarray of float, shape (N,)
        Sub-pixel disparity ``x_left - x_right`` of the best window cost: from the
        right edge point it lands on where there is one (edge positions are precise
        to a twentieth of a pixel), else the vertex of the parabola through the costs
        at the best disparity and its two neighbours.  NaN where the whole search
        range is out of view.
    right_edge : ndarray of int, shape (N,)
        Index of that right edge point, -1 where there is none.
    features : ndarray of float32, shape (N, F)
        The evidence, columns named by :data:`robostereo.matcher.confidence.FEATURES`,
        kept in float32 (uniquenesses and similarities in 0..1, flags 0 or 1: seven
        digits are more than they hold).
    confidence : ndarray of float, shape (N,)
        Calibrated ``P(correct)`` of the best disparity; NaN where there is none.  It is
        scored from the evidence in float64 before the features are stored, so the
        model applied to ``features`` again may differ from it by about 1e-7.
    costs : WindowCosts
        The window costs the match was read from.
    """

    disparity: NDArray[np.float64]
    right_edge: NDArray[np.intp]
    features: NDArray[np.float32]
    confidence: NDArray[np.float64]
    costs: WindowCosts


def search_costs(
    left: EdgeSet,
    grey_left: NDArray[np.floating],
    grey_right: NDArray[np.floating],
    disparity_range: tuple[float, float],
    *,
    gradient_truncation: int = 64,
    valid_left: NDArray[np.bool_] | None = None,
    valid_right: NDArray[np.bool_] | None = None,
    vertical: bool = True,
    path_penalties: tuple[float, float] | None = PATH_PENALTIES,
    coarse: bool = True,
) -> WindowCosts:
    """The window costs that :func:`window_match` reads: its step 1 alone.

    Parameters are those of :func:`window_match`.  A caller that no longer needs the
    grey images once the costs are made can let them go before the rest of the match
    (``window_match(..., costs=search_costs(...))``): at the match's peak memory they
    are then not held.

    Returns
    -------
    WindowCosts
        Over every whole disparity of `disparity_range`, or over the part a pass at
        half size narrows it to (`coarse` and more than :data:`COARSE_MIN_DISPARITIES`
        disparities, :func:`coarse_range`).

    Examples
    --------
    >>> from robostereo.matcher.edges import detect_edges
    >>> from robostereo.matcher.grey_levels import to_grey
    >>> rng = np.random.default_rng(0)
    >>> row = np.repeat(rng.integers(0, 2, 40) * 200, 6)[:200].astype(np.uint8)
    >>> left = np.tile(row, (20, 1)); right = np.roll(left, -7, axis=1)
    >>> wc = search_costs(detect_edges(left), to_grey(left), to_grey(right), (0, 12))
    >>> wc.d_min, wc.n_disparities
    (0, 13)
    """
    d_lo, d_hi = int(np.floor(disparity_range[0])), int(np.ceil(disparity_range[1]))
    if coarse and d_hi - d_lo + 1 > COARSE_MIN_DISPARITIES:
        d_lo, d_hi = coarse_range(grey_left, grey_right, left.row, left.column, (d_lo, d_hi),
                                  gradient_truncation=gradient_truncation,
                                  valid_left=valid_left, valid_right=valid_right)
    return window_costs(grey_left, grey_right, left.row, left.column, (d_lo, d_hi),
                        gradient_truncation=gradient_truncation, valid_left=valid_left,
                        valid_right=valid_right, vertical=vertical,
                        path_penalties=path_penalties)


def window_match(
    left: EdgeSet,
    right: EdgeSet,
    grey_left: NDArray[np.floating] | None,
    grey_right: NDArray[np.floating] | None,
    disparity_range: tuple[float, float],
    *,
    gradient_truncation: int = 64,
    weights: SimilarityWeights | None = None,
    profile_scale: float | None = 10.0,
    model: ConfidenceModel | None = None,
    valid_left: NDArray[np.bool_] | None = None,
    valid_right: NDArray[np.bool_] | None = None,
    vertical: bool = True,
    path_penalties: tuple[float, float] | None = PATH_PENALTIES,
    coarse: bool = True,
    costs: WindowCosts | None = None,
) -> WindowMatch:
    """Best disparity and calibrated confidence of every left edge point.

    Parameters
    ----------
    left, right : EdgeSet
        Edge points of the two images (:func:`robostereo.matcher.edges.detect_edges`).
    grey_left, grey_right : ndarray, shape (H, W), or None
        The grey images they were found in (0..127 scale); None with `costs`.
    disparity_range : tuple of float
        ``(min, max)`` disparity; every whole pixel from ``floor(min)`` to ``ceil(max)``
        is scored, and results more than half a pixel outside are dropped.
    gradient_truncation : int
        See :func:`window_costs`.
    weights, profile_scale
        The thesis's similarity weights and robostereo's edge-profile factor, for the
        ``similarity`` feature (:func:`robostereo.matcher.candidates.pair_similarity`).
    model : ConfidenceModel, optional
        Default :data:`robostereo.matcher.confidence.DEFAULT_MODEL`.
    valid_left, valid_right : ndarray of bool, shape (H, W), optional
        Pixels that hold image data (see :func:`window_costs`).
    vertical : bool
        Windows above and below too (see :func:`window_costs`).
    path_penalties : tuple of float or None
        Paths along the rows (see :func:`window_costs`); None: none.
    coarse : bool
        Narrow a range of more than :data:`COARSE_MIN_DISPARITIES` whole disparities
        to the part the scene holds by a pass at half size first
        (:func:`coarse_range`); False: search it all.
    costs : WindowCosts, optional
        The costs of step 1 already made by :func:`search_costs` with the same
        arguments; the grey images, masks, `vertical`, `path_penalties` and `coarse`
        are then not read.

    Returns
    -------
    WindowMatch

    Notes
    -----
    1. Window costs over the range (:func:`window_costs`), a wide range first
       narrowed at half size (:func:`coarse_range`).
    2. Best disparity ``d1`` (cost ``c1``); ``c2`` the best cost more than one pixel
       away; uniqueness ``(c2 - c1) / c2`` (0 when no such disparity is in view).
    3. Left-right check: the right pixel ``x - d1`` scored against every left pixel;
       its best disparity should be ``d1`` (or one pixel off).
    4. Sub-pixel disparity from the right edge point within half a pixel of
       ``x - d`` (same contrast sign), else from the parabola of the costs.
    5. Paths along the row (:func:`window_costs`, Notes 6): where their best
       disparity is more than a pixel from the windows' and their uniqueness is above
       :data:`SWAP_UNIQUENESS`, theirs is taken (parabola of the path costs, then the
       right edge point there as in 4); their agreement and uniqueness are evidence.
    6. Confidence from the evidence by the calibrated model
       (:mod:`robostereo.matcher.confidence`).
    """
    lo, hi = float(disparity_range[0]), float(disparity_range[1])
    if costs is None:
        if grey_left is None or grey_right is None:
            raise InputError("window_match needs the grey images or the costs")
        costs = search_costs(left, grey_left, grey_right, (lo, hi),
                             gradient_truncation=gradient_truncation, valid_left=valid_left,
                             valid_right=valid_right, vertical=vertical,
                             path_penalties=path_penalties, coarse=coarse)
    wc = costs
    d_lo = wc.d_min
    n, nd = len(left), wc.n_disparities
    summary = StreamSummary(*(getattr(wc, name) for name in StreamSummary._fields))
    score = model or DEFAULT_MODEL
    n_lines = _n_lines(left, right)
    # the right points of line l: line_start[l] .. line_start[l + 1] - 1
    # (the lines sought in the right points' own dtype: no int64 copy of them)
    lines = np.asarray(right.line)
    line_start = np.searchsorted(lines, np.arange(n_lines + 1).astype(lines.dtype)).astype(
        np.int64)
    # the evidence, a chunk of points at a time: each chunk's features in float64 while
    # its confidence is computed, then kept in float32 (the whole table in float64 was
    # the largest array of a match with many edge points)
    feats = np.empty((n, len(FEATURES)), np.float32)
    disparity = np.empty(n)
    right_edge = np.empty(n, np.intp)
    conf = np.empty(n)
    for k0 in range(0, n, SIMILARITY_CHUNK):
        k1 = min(n, k0 + SIMILARITY_CHUNK)
        f = np.zeros((k1 - k0, len(FEATURES)))
        conf[k0:k1] = _chunk(left, right, StreamSummary(*(a[k0:k1] for a in summary)), k0, f,
                             d_lo, nd, lo, hi, line_start, weights, profile_scale, score,
                             disparity[k0:k1], right_edge[k0:k1])
        feats[k0:k1] = f
    return WindowMatch(disparity=disparity, right_edge=right_edge, features=feats,
                       confidence=conf, costs=wc)


def _n_lines(left: EdgeSet, right: EdgeSet) -> int:
    """Lines that the edge points of either image lie on (0 without any)."""
    if len(left) == 0 or len(right) == 0:
        return 0
    return int(max(int(left.line.max()), int(right.line.max())) + 1)


def _chunk(left: EdgeSet, right: EdgeSet, summary: StreamSummary, k0: int,
           feats: NDArray[np.float64], d_lo: int, nd: int, lo: float, hi: float,
           line_start: NDArray[np.int64], weights: SimilarityWeights | None,
           profile_scale: float | None, score: ConfidenceModel,
           disparity: NDArray[np.float64], right_edge: NDArray[np.intp]
           ) -> NDArray[np.float64]:
    """Steps 2-6 of :func:`window_match` for the left edge points ``k0 .. k0 + K - 1``
    (``summary`` their window costs): their features into ``feats`` ``(K, F)``, their
    disparities and right edge points into ``disparity`` and ``right_edge`` ``(K,)``;
    returns their confidences ``(K,)``.  ``line_start`` ``(L + 1,)``: the right edge
    points of line ``l`` are ``line_start[l] .. line_start[l + 1] - 1``."""
    d_par, seen = evidence(summary, d_lo, nd, SWAP_UNIQUENESS, feats, _EVIDENCE_COLUMNS)
    k1 = k0 + d_par.shape[0]
    # the right edge point within half a pixel of the disparity (a partner), the
    # sub-pixel disparity from it where there is one, else the parabola's; NaN outside
    # the range
    partner = np.empty(k1 - k0, np.int64)
    right_partners(np.ascontiguousarray(left.x[k0:k1], np.float64),
                   np.ascontiguousarray(left.line[k0:k1], np.int32),
                   np.ascontiguousarray(left.sign[k0:k1], np.int8), d_par, seen, float(lo),
                   float(hi), line_start, np.ascontiguousarray(right.x, np.float64),
                   np.ascontiguousarray(right.sign, np.int8), disparity, right_edge, partner,
                   feats, _RIGHT_EDGE)
    sel = np.flatnonzero(partner >= 0)
    feats[sel, _SIMILARITY] = pair_similarity(left, right, sel + k0, partner[sel],
                                              weights=weights, profile_scale=profile_scale)[4]
    conf = score(feats)
    conf[~np.isfinite(disparity)] = np.nan
    return conf


def contour_accepted(
    left: EdgeSet,
    disparity: NDArray[np.float64],
    confidence: NDArray[np.float64],
    acceptance: float,
    *,
    min_confidence: float = CONTOUR_MIN_CONFIDENCE,
    reach: int = CONTOUR_REACH,
    share: float = CONTOUR_SHARE,
) -> NDArray[np.bool_]:
    """The matches accepted with the support of their edge contour (thesis 3.4).

    An edge contour is one surface boundary, so its points' disparities agree (the
    thesis's figural continuity, relaxation eq. 4-5).  A match is accepted when its
    confidence reaches `acceptance`, or when it reaches `min_confidence` and at least
    `share` of the ``2 * reach`` places up and down its contour (the edge stage's
    connectivity, :attr:`~robostereo.matcher.edge_features.EdgeSet.up` / ``down``) hold a match
    within :data:`CONTOUR_TOLERANCE` of its disparity that reaches `acceptance` itself
    (:func:`~robostereo.matcher.contour_kernels.contour_support`).

    Parameters
    ----------
    left : EdgeSet
        The left edge points, ``N`` of them.
    disparity, confidence : ndarray of float, shape (N,)
        Best disparity and its confidence per point (:class:`WindowMatch`), NaN where
        none.
    acceptance : float
        Least confidence of a match accepted on its own evidence.
    min_confidence : float
        Least confidence of a match accepted with its contour's support.
    reach : int
        Lines walked up and down the contour.
    share : float
        Least share of the ``2 * reach`` places that must support the match.

    Returns
    -------
    ndarray of bool, shape (N,)

    Examples
    --------
    One contour down nine lines, all at 12 px; the middle point is less sure of itself:

    >>> from robostereo.matcher.edges import detect_edges
    >>> img = np.zeros((13, 40), np.uint8); img[:, 20:] = 200
    >>> e = detect_edges(img)
    >>> d = np.full(len(e), 12.0); c = np.full(len(e), 0.99); c[len(e) // 2] = 0.85
    >>> acc = contour_accepted(e, d, c, 20 / 21, reach=2)
    >>> bool(acc[len(e) // 2]), int(acc.sum()) == len(e)
    (True, True)
    """
    conf = np.nan_to_num(np.asarray(confidence, dtype=np.float64), nan=-1.0)
    own = conf >= acceptance
    support, _ = contour_support(np.ascontiguousarray(left.up, np.int32),
                                 np.ascontiguousarray(left.down, np.int32),
                                 np.ascontiguousarray(disparity, np.float64),
                                 own.astype(np.float64), int(reach), CONTOUR_TOLERANCE)
    return own | ((conf >= min_confidence) & (support >= share * 2 * reach))
