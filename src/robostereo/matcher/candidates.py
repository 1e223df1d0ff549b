"""Match candidates, similarity indices and initial probabilities (thesis 3.2-3.3, 3.5).

For every edge point of the left image, the candidates are the edge points of the
right image on the same epipolar line, with the same contrast sign, inside the
disparity search range (the thesis's matchable region, 3.5).  Each candidate gets the
similarity indices GI, PI and AI of section 3.2, their weighted sum ``w`` (3.3), and
an initial probability by eq. (1)-(3) as read in seed-notes (after Barnard and
Thompson, 1980).

Candidates are held in compressed-row form: the pairs are sorted by left edge, and
the pairs of left edge ``i`` are ``starts[i]:starts[i + 1]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_finite
from robostereo.matcher.edge_features import EdgeSet
from robostereo.matcher.jit import kernel

__all__ = [
    "Candidates",
    "SimilarityWeights",
    "assign_matches",
    "find_candidates",
    "group_argmax",
    "group_max",
    "group_sum",
    "initial_probabilities",
    "pair_similarity",
]


@dataclass(frozen=True)
class SimilarityWeights:
    """Weights ``lambda`` of the similarity indices in ``w`` (thesis 3.3).

    ``w = gradient * GI + pattern * PI + mean_grey * AI``; the thesis uses 1/3 each.
    Weights must be >= 0 with a positive sum; they are normalised to sum 1.

    Examples
    --------
    >>> SimilarityWeights().normalised()
    (0.333..., 0.333..., 0.333...)
    >>> SimilarityWeights(2.0, 1.0, 1.0).normalised()
    (0.5, 0.25, 0.25)
    """

    gradient: float = 1.0 / 3.0
    pattern: float = 1.0 / 3.0
    mean_grey: float = 1.0 / 3.0

    def __post_init__(self) -> None:
        vals = (self.gradient, self.pattern, self.mean_grey)
        require_finite("similarity weights", vals)
        if min(vals) < 0 or sum(vals) <= 0:
            raise InputError(f"similarity weights must be >= 0 with a positive sum, got {vals}")

    def normalised(self) -> tuple[float, float, float]:
        vals = (self.gradient, self.pattern, self.mean_grey)
        total = math.fsum(vals)
        g, p, a = (v / total for v in vals)
        return g, p, a


@dataclass(frozen=True)
class Candidates:
    """Candidate pairs (left edge, right edge) with their similarities.

    Arrays of shape ``(M,)`` are per pair, sorted by ``left``; ``starts`` has shape
    ``(N_left + 1,)``.

    Attributes
    ----------
    left, right : ndarray of int
        Edge indices in the left and right :class:`~robostereo.matcher.edge_features.EdgeSet`.
    disparity : ndarray of float
        ``x_left - x_right`` in pixels.
    gi, pi, ai : ndarray of float
        Similarity indices (thesis 3.2 (a)-(c)).
    profile : ndarray of float
        robostereo's edge-profile factor ``exp(-e / profile_scale)`` in ``(0, 1]``,
        ``e`` the mean absolute difference of the grey levels before and after the
        two edges (1 when ``profile_scale`` is None).
    w : ndarray of float
        Combined similarity (thesis 3.3) times the profile factor, in ``[0, 1]``.
    starts : ndarray of int
        Pairs of left edge ``i`` are ``starts[i]:starts[i + 1]``.
    """

    left: NDArray[np.intp]
    right: NDArray[np.intp]
    disparity: NDArray[np.float64]
    gi: NDArray[np.float64]
    pi: NDArray[np.float64]
    ai: NDArray[np.float64]
    profile: NDArray[np.float64]
    w: NDArray[np.float64]
    starts: NDArray[np.intp]

    def __len__(self) -> int:
        return int(self.left.shape[0])

    @property
    def counts(self) -> NDArray[np.intp]:
        """Number of candidates of each left edge, shape ``(N_left,)``."""
        return np.diff(self.starts)


def group_sum(values: NDArray[np.floating], starts: NDArray[np.intp]) -> NDArray[np.float64]:
    """Sum of ``values`` over each group ``starts[i]:starts[i + 1]`` (0 for empty groups).

    >>> group_sum(np.array([1.0, 2.0, 4.0]), np.array([0, 2, 2, 3])).tolist()
    [3.0, 0.0, 4.0]
    """
    c = np.concatenate([[0.0], np.cumsum(values, dtype=float)])
    return c[starts[1:]] - c[starts[:-1]]


def group_max(
    values: NDArray[np.floating], starts: NDArray[np.intp], empty: float = 0.0
) -> NDArray[np.float64]:
    """Maximum of ``values`` over each group (``empty`` for empty groups).

    >>> group_max(np.array([1.0, 2.0, 4.0]), np.array([0, 2, 2, 3])).tolist()
    [2.0, 0.0, 4.0]
    """
    n = starts.shape[0] - 1
    out = np.full(n, empty, dtype=float)
    nonempty = starts[1:] > starts[:-1]
    if values.shape[0]:
        red = np.maximum.reduceat(values, np.minimum(starts[:-1], values.shape[0] - 1))
        out[nonempty] = red[nonempty]
    return out


def group_argmax(values: NDArray[np.floating], starts: NDArray[np.intp]) -> NDArray[np.intp]:
    """Index of the (first) largest value of each group, -1 for empty groups.

    >>> group_argmax(np.array([1.0, 2.0, 2.0, 4.0]), np.array([0, 3, 3, 4])).tolist()
    [1, -1, 3]
    """
    n = starts.shape[0] - 1
    out = np.full(n, -1, dtype=np.intp)
    if values.shape[0] == 0:
        return out
    top = group_max(values, starts, empty=-np.inf)
    counts = np.diff(starts)
    group = np.repeat(np.arange(n), counts)
    idx = np.nonzero(values >= top[group])[0]
    g = group[idx]
    first = np.ones(idx.shape[0], bool)
    first[1:] = g[1:] != g[:-1]
    out[g[first]] = idx[first]
    return out


def find_candidates(
    left: EdgeSet,
    right: EdgeSet,
    disparity_range: tuple[float, float],
    *,
    weights: SimilarityWeights | None = None,
    profile_scale: float | None = 10.0,
) -> Candidates:
    """Candidate pairs and their similarity indices (thesis 3.2, 3.3, 3.5).

    Parameters
    ----------
    left, right : EdgeSet
        Edge points of the two images, found with the same row sampling.
    disparity_range : tuple of float
        ``(min, max)`` disparity ``x_left - x_right`` in pixels, whole-pixel bounds:
        candidates within half a pixel outside them are kept, as a pixel matcher would.
    weights : SimilarityWeights, optional
        Weights of the indices in ``w``; default the thesis's 1/3 each.
    profile_scale : float or None
        Scale (grey levels, 0..127 scale) of the edge-profile factor that multiplies
        ``w``; None leaves ``w`` as the thesis has it.

    Returns
    -------
    Candidates

    Notes
    -----
    1. Candidates of a left edge: right edges on the same line with the same contrast
       sign and ``min - 0.5 <= x_l - x_r <= max + 0.5`` (the matchable region, 3.5).
    2. ``GI = 1 / (1 + |G_l - G_r|)`` of the gradient magnitudes,
       ``PI = 1 / (1 + diff)`` with the pattern difference 0..6,
       ``AI = 1 / (1 + |A_l - A_r|)`` of the 5 x 5 mean grey levels (3.2).
    3. ``w = sum(lambda_k * index_k)`` with the normalised weights (3.3).
    4. Beyond the thesis: ``w`` is multiplied by ``exp(-e / profile_scale)``, with
       ``e = (|B_l - B_r| + |F_l - F_r|) / 2`` the difference of the smoothed grey
       levels four pixels before (B) and after (F) the two edges.  One 5 x 5 mean
       cannot tell a dark-to-bright edge from another with other grey levels on
       its two sides; on the Middlebury pairs this halves the false matches.
    """
    lo_d, hi_d = disparity_range
    require_finite("disparity_range", [lo_d, hi_d])
    if lo_d > hi_d:
        raise InputError(f"disparity_range must have min <= max, got ({lo_d}, {hi_d})")
    if left.row_step != right.row_step or left.row_offset != right.row_offset:
        raise InputError("left and right edges must be found on the same rows (row_step)")
    _check_profile_scale(profile_scale)
    span = float(max(np.max(left.x, initial=0.0), np.max(right.x, initial=0.0)))
    # no pair is more than `span` apart: a wider bound (-1e18) would only cost precision
    lo_d, hi_d = max(lo_d, -span - 1.0), min(hi_d, span + 1.0)
    big = span + abs(lo_d) + abs(hi_d) + 10.0
    key_r = right.line * big + right.x
    key_l = left.line * big + left.x
    lo = np.searchsorted(key_r, key_l - (hi_d + 0.5), side="left")
    hi = np.searchsorted(key_r, key_l - (lo_d - 0.5), side="right")
    counts = np.maximum(hi - lo, 0)
    total = int(counts.sum())
    li = np.repeat(np.arange(len(left)), counts)
    first = np.repeat(np.cumsum(counts) - counts, counts)
    ri = np.repeat(lo, counts) + (np.arange(total) - first)
    keep = left.sign[li] == right.sign[ri]
    li, ri = li[keep], ri[keep]
    starts = np.searchsorted(li, np.arange(len(left) + 1)).astype(np.intp)
    gi, pi, ai, profile, w = pair_similarity(left, right, li, ri, weights=weights,
                                             profile_scale=profile_scale)
    return Candidates(
        left=li.astype(np.intp), right=ri.astype(np.intp),
        disparity=left.x[li] - right.x[ri], gi=gi, pi=pi, ai=ai, profile=profile, w=w,
        starts=starts,
    )


def _check_profile_scale(profile_scale: float | None) -> None:
    if profile_scale is not None:
        require_finite("profile_scale", float(profile_scale))
        if profile_scale <= 0:
            raise InputError(f"profile_scale must be > 0 or None, got {profile_scale}")


def pair_similarity(
    left: EdgeSet,
    right: EdgeSet,
    li: NDArray[np.intp],
    ri: NDArray[np.intp],
    *,
    weights: SimilarityWeights | None = None,
    profile_scale: float | None = 10.0,
) -> tuple[NDArray[np.float64], ...]:
    """Similarity indices of edge pairs ``(li[k], ri[k])`` (thesis 3.2-3.3).

    Returns
    -------
    gi, pi, ai, profile, w : ndarray, shape (K,)
        The indices GI, PI, AI, the edge-profile factor and the combined ``w``
        (see :func:`find_candidates`, Notes 2-4).

    Examples
    --------
    An edge point compared with itself is similar in every respect:

    >>> from robostereo.matcher.edges import detect_edges
    >>> img = np.zeros((9, 20), np.uint8); img[:, 10:] = 200
    >>> e = detect_edges(img)
    >>> [round(float(v[0]), 3) for v in pair_similarity(e, e, np.array([4]), np.array([4]))]
    [1.0, 1.0, 1.0, 1.0, 1.0]
    """
    wg, wp, wa = (weights or SimilarityWeights()).normalised()
    _check_profile_scale(profile_scale)
    li = np.ascontiguousarray(li, np.int64)
    ri = np.ascontiguousarray(ri, np.int64)
    if li.shape != ri.shape or li.ndim != 1:
        raise InputError("li and ri must be 1-D arrays of one length")
    if li.size and (li.min() < 0 or li.max() >= len(left) or ri.min() < 0
                    or ri.max() >= len(right)):
        raise InputError("li and ri must index the left and right edge points")
    gi, pi, ai, side = _similarity(
        li, ri, *(np.ascontiguousarray(getattr(e, a)) for e in (left, right)
                  for a in ("magnitude", "up_offset", "down_offset", "up", "down",
                            "mean_grey", "grey_before", "grey_after")))
    profile = np.exp(-side / profile_scale) if profile_scale is not None else np.ones_like(side)
    w = (wg * gi + wp * pi + wa * ai) * profile
    return gi, pi, ai, profile, w


@kernel(nogil=True)
def _one_side(a, b, ha, hb):  # type: ignore[no-untyped-def]
    """Difference of one side's connection (see ``edges.pattern_difference``)."""
    if ha and hb:
        return abs(int(a) - int(b))
    return 0 if ha == hb else 3


@kernel(nogil=True)
def _similarity(li, ri, mag_l, uo_l, do_l, up_l, dn_l, mean_l, bef_l, aft_l,
                mag_r, uo_r, do_r, up_r, dn_r, mean_r, bef_r, aft_r
                ):  # type: ignore[no-untyped-def]
    """GI, PI, AI and the profile difference ``e`` of each pair, in one pass over
    the pairs (:func:`pair_similarity`)."""
    n = li.shape[0]
    gi = np.empty(n)
    pi = np.empty(n)
    ai = np.empty(n)
    side = np.empty(n)
    for k in range(n):
        i, j = li[k], ri[k]
        # np.float64, not float(): numba's float() keeps a float32 a float32, and the
        # differences are taken in float64 whatever the edge sets' dtypes
        gi[k] = 1.0 / (1.0 + abs(np.float64(mag_l[i]) - np.float64(mag_r[j])))
        diff = (_one_side(uo_l[i], uo_r[j], up_l[i] >= 0, up_r[j] >= 0)
                + _one_side(do_l[i], do_r[j], dn_l[i] >= 0, dn_r[j] >= 0))
        pi[k] = 1.0 / (1.0 + float(diff))
        ai[k] = 1.0 / (1.0 + abs(np.float64(mean_l[i]) - np.float64(mean_r[j])))
        side[k] = 0.5 * (abs(np.float64(bef_l[i]) - np.float64(bef_r[j]))
                         + abs(np.float64(aft_l[i]) - np.float64(aft_r[j])))
    return gi, pi, ai, side


def initial_probabilities(
    cands: Candidates,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Initial match probabilities, eq. (1)-(3) as read in seed-notes.

    Parameters
    ----------
    cands : Candidates

    Returns
    -------
    p : ndarray, shape (M,)
        ``P0(l_i) = P(l_i | match) * (1 - P(no match))`` per candidate pair.
    p_none : ndarray, shape (N_left,)
        ``P(no match) = 1 - max_i w_i`` per left edge (1 where there is no candidate).

    Notes
    -----
    ``P(l_i | match) = w_i / sum_j w_j`` (eq. 3) and ``P(no match) = 1 - max_i w_i``
    (eq. 2, the thesis's ``P_m``).  The probabilities of each left edge and its
    no-match label sum to 1 only when it has a single candidate; they are
    renormalised in the first relaxation step.

    Examples
    --------
    Two candidates with ``w = 0.8`` and ``0.2``:

    >>> c = Candidates(*(np.array(v) for v in ([0, 0], [0, 1], [1.0, 2.0],
    ...     [1, 1], [1, 1], [1, 1], [1, 1], [0.8, 0.2], [0, 2])))
    >>> p, p_none = initial_probabilities(c)
    >>> p.round(3).tolist(), p_none.round(3).tolist()
    ([0.64, 0.16], [0.2])
    """
    wsum = group_sum(cands.w, cands.starts)
    wmax = group_max(cands.w, cands.starts)
    ws = wsum[cands.left]
    cond = np.divide(cands.w, ws, out=np.zeros_like(cands.w, dtype=float), where=ws > 0)
    p = cond * wmax[cands.left]
    return p, 1.0 - wmax


def assign_matches(
    cands: Candidates,
    probability: NDArray[np.float64],
    no_match: NDArray[np.float64],
    n_left: int,
    *,
    min_probability: float = 0.5,
) -> NDArray[np.intp]:
    """Accept at most one match per left edge and per right edge (thesis 3.4, 3.5).

    Parameters
    ----------
    cands : Candidates
    probability : ndarray, shape (M,)
        Candidate probabilities (after relaxation).
    no_match : ndarray, shape (N_left,)
        No-match probabilities.
    n_left : int
        Number of left edge points.
    min_probability : float
        Least probability of an accepted match.

    Returns
    -------
    ndarray of int, shape (N_left,)
        Index into ``cands`` of each left edge's match, -1 where it has none.

    Notes
    -----
    1. Each left edge's most probable candidate is its choice, if its probability is
       at least ``min_probability`` and above the no-match probability.
    2. A right edge chosen by several left edges goes to the most probable pair;
       the others stay unmatched.

    Examples
    --------
    Left edges 0 and 1 both want right edge 5; edge 1's pair is more probable.

    >>> c = Candidates(*(np.array(v) for v in ([0, 1, 1], [5, 5, 6], [1.0, 2.0, 3.0],
    ...     [1] * 3, [1] * 3, [1] * 3, [1] * 3, [1] * 3, [0, 1, 3])))
    >>> assign_matches(c, np.array([0.6, 0.7, 0.3]), np.array([0.4, 0.0]), 2).tolist()
    [-1, 1]
    """
    best = group_max(probability, cands.starts, empty=-1.0)
    ok = (
        (probability >= best[cands.left])
        & (probability >= min_probability)
        & (probability > no_match[cands.left])
    )
    idx = np.nonzero(ok)[0]
    # one per left edge (ties: the first); pairs are sorted by left edge
    li = cands.left[idx]
    keep = np.ones(idx.shape[0], bool)
    keep[1:] = li[1:] != li[:-1]
    idx = idx[keep]
    # one per right edge: the most probable pair (ties: the first left edge)
    ri = cands.right[idx]
    n_right = int(ri.max()) + 1 if ri.size else 0
    best_right = np.full(n_right, -1.0)
    np.maximum.at(best_right, ri, probability[idx])
    top = idx[probability[idx] >= best_right[ri]]
    first = np.full(n_right, np.iinfo(np.intp).max, dtype=np.intp)
    np.minimum.at(first, cands.right[top], top)
    chosen = top[first[cands.right[top]] == top]
    out = np.full(n_left, -1, dtype=np.intp)
    out[cands.left[chosen]] = chosen
    return out
