"""Relaxation of match probabilities by edge connectivity (thesis 3.4, eq. 4-5).

For a left edge point ``N`` on epipolar line ``i`` and a neighbouring left edge point
``M`` on line ``i - 1`` or ``i + 1``, with candidates ``Q_i`` (of ``N``) and ``R_j``
(of ``M``) in the right image, the coefficient ``r_ij = a_ij + b_ij`` (3.4.1) rewards
candidate pairs whose connectivity in the right image mirrors that of ``M`` and ``N``
in the left image.  The probabilities of ``N``'s candidates are then updated by eq. (5)
with the support ``sum_j P_j(M) r_ij`` and renormalised by eq. (4).

Choices where the thesis is silent (documented in docs/guide/algorithm.md):

* *Neighbours.*  On each of the two adjacent lines, ``N``'s neighbour ``M`` is the
  edge point it is connected to (case I), or else the nearest edge point of the same
  contrast sign within ``neighbour_radius`` pixels (case II); so ``N`` has at most two.
* *b in case I* when neither ``Q_i`` nor ``R_j`` is connected to another edge: 0.2,
  as when one of them is ("not connected to each other, at most one connected
  elsewhere").
* *The no-match label* takes part, as in Barnard and Thompson (1980): its support
  from every neighbour is the constant ``no_match_support``, and a neighbour's own
  no-match probability lends that same neutral support to each of ``N``'s labels.
  ``gamma`` (eq. 4) sums over the candidates *and* the no-match label, so each left
  edge's probabilities, no-match included, sum to 1 after every iteration.
* Supports from the (at most two) neighbours are averaged; an edge point with no
  neighbour keeps its probabilities.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_finite, require_int
from robostereo.matcher.candidates import Candidates, group_sum
from robostereo.matcher.edge_features import EdgeSet

__all__ = [
    "RelaxationParameters",
    "RelaxationResult",
    "connectivity_coefficient",
    "neighbours",
    "relax",
    "support_structure",
]


@dataclass(frozen=True)
class RelaxationParameters:
    """Tuning of the relaxation (thesis 3.4).

    Attributes
    ----------
    iterations : int
        Largest number of updates (the thesis: 5).
    tolerance : float
        Stop early once no probability changes by more than this.
    neighbour_radius : float
        Case II neighbours: the nearest same-sign edge within this many pixels.
    no_match_support : float
        Support of the no-match label from each neighbour (see module notes): 0 or
        1e-6 .. 1e6.
    b_connected, b_partial, b_none : float
        The values 1, 0.2 and 0 of ``b_ij`` (thesis 3.4.1), in 0 .. 1e6 (as are
        ``tolerance`` and ``neighbour_radius``).
    """

    iterations: int = 5
    tolerance: float = 1e-4
    neighbour_radius: float = 3.0
    no_match_support: float = 1.0
    b_connected: float = 1.0
    b_partial: float = 0.2
    b_none: float = 0.0

    def __post_init__(self) -> None:
        require_int("iterations", self.iterations, minimum=0)
        require_finite(
            "relaxation parameters",
            [self.tolerance, self.neighbour_radius, self.no_match_support,
             self.b_connected, self.b_partial, self.b_none],
        )
        # bounded so that the products of eq. (5) neither underflow nor overflow
        c = self.no_match_support
        if not (c == 0 or 1e-6 <= c <= 1e6):
            raise InputError(f"no_match_support must be 0 or in 1e-6 .. 1e6, got {c!r}")
        for name in ("tolerance", "neighbour_radius", "b_connected", "b_partial", "b_none"):
            v = getattr(self, name)
            if not 0 <= v <= 1e6:
                raise InputError(f"{name} must be in 0 .. 1e6, got {v!r}")


@dataclass(frozen=True)
class RelaxationResult:
    """Probabilities after each iteration.

    Attributes
    ----------
    history : list of ndarray
        ``history[k]`` has shape ``(M,)``: candidate probabilities after ``k``
        iterations (``history[0]`` the initial ones).
    none_history : list of ndarray
        ``none_history[k]`` has shape ``(N_left,)``: no-match probabilities.
    iterations : int
        Iterations run (fewer than asked when the probabilities settled).
    """

    history: list[NDArray[np.float64]]
    none_history: list[NDArray[np.float64]]
    iterations: int

    @property
    def probability(self) -> NDArray[np.float64]:
        """Final candidate probabilities, shape ``(M,)``."""
        return self.history[-1]

    @property
    def no_match(self) -> NDArray[np.float64]:
        """Final no-match probabilities, shape ``(N_left,)``."""
        return self.none_history[-1]


def neighbours(
    edges: EdgeSet, *, radius: float = 3.0
) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.bool_]]:
    """Neighbouring left edge points of each edge point on the adjacent lines.

    Returns
    -------
    n, m : ndarray of int, shape (K,)
        Pairs: ``m`` is a neighbour of ``n``.
    connected : ndarray of bool, shape (K,)
        True where ``m`` and ``n`` are connected (case I), False for case II.
    """
    out_n, out_m, out_c = [], [], []
    idx = np.arange(len(edges))
    for link in (edges.up, edges.down):
        has = link >= 0
        out_n.append(idx[has])
        out_m.append(link[has])
        out_c.append(np.ones(int(has.sum()), bool))
    # case II: nearest same-sign edge on the adjacent line, for edges not connected there
    big = float(np.max(edges.x, initial=0.0)) + 4.0 * radius + 10.0
    key = (edges.line * 2 + (edges.sign > 0)) * big + edges.x
    for dl, link in ((-1, edges.up), (1, edges.down)):
        need = idx[link < 0]
        if need.size == 0:
            continue
        q = ((edges.line[need] + dl) * 2 + (edges.sign[need] > 0)) * big + edges.x[need]
        pos = np.searchsorted(key, q)
        best = np.full(need.shape, -1, np.intp)
        bestd = np.full(need.shape, np.inf)
        for cand in (pos - 1, pos):
            ok = (cand >= 0) & (cand < len(edges))
            c = np.where(ok, cand, 0)
            d = np.abs(key[c] - q)
            ok &= (d <= radius) & (edges.line[c] == edges.line[need] + dl) & (d < bestd)
            best = np.where(ok, c, best)
            bestd = np.where(ok, d, bestd)
        has = best >= 0
        out_n.append(need[has])
        out_m.append(best[has])
        out_c.append(np.zeros(int(has.sum()), bool))
    return (np.concatenate(out_n).astype(np.intp), np.concatenate(out_m).astype(np.intp),
            np.concatenate(out_c))


def connectivity_coefficient(
    mn_connected: NDArray[np.bool_],
    qr_connected: NDArray[np.bool_],
    q_elsewhere: NDArray[np.bool_],
    r_elsewhere: NDArray[np.bool_],
    params: RelaxationParameters | None = None,
) -> NDArray[np.float64]:
    """The connectivity term ``b_ij`` of the relaxation coefficient (thesis 3.4.1).

    Parameters
    ----------
    mn_connected : ndarray of bool
        Whether the left edge points ``M`` and ``N`` are connected (case I) or not (II).
    qr_connected : ndarray of bool
        Whether the right candidates ``Q_i`` and ``R_j`` are connected to each other.
    q_elsewhere, r_elsewhere : ndarray of bool
        Whether ``Q_i`` (``R_j``) is connected, towards the other's line, to some other
        edge point.

    Returns
    -------
    ndarray of float

    Notes
    -----
    Case I (``M``, ``N`` connected): 1 if ``Q_i``, ``R_j`` are connected; 0 if they are
    not and both are connected to other edges; 0.2 otherwise.
    Case II (not connected): 0 if ``Q_i``, ``R_j`` are connected; 1 if both are
    connected to nothing; 0.2 otherwise.

    Examples
    --------
    >>> t, f = np.array([True]), np.array([False])
    >>> [connectivity_coefficient(t, t, f, f).item(), connectivity_coefficient(t, f, t, f).item(),
    ...  connectivity_coefficient(t, f, t, t).item(), connectivity_coefficient(f, f, f, f).item(),
    ...  connectivity_coefficient(f, f, t, f).item(), connectivity_coefficient(f, t, f, f).item()]
    [1.0, 0.2, 0.0, 1.0, 0.2, 0.0]
    """
    p = params or RelaxationParameters()
    case1 = np.where(
        qr_connected, p.b_connected, np.where(q_elsewhere & r_elsewhere, p.b_none, p.b_partial)
    )
    case2 = np.where(
        qr_connected, p.b_none, np.where(~q_elsewhere & ~r_elsewhere, p.b_connected, p.b_partial)
    )
    return np.where(mn_connected, case1, case2).astype(float)


def support_structure(
    left: EdgeSet, right: EdgeSet, cands: Candidates, params: RelaxationParameters
) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.float64], NDArray[np.intp],
           NDArray[np.intp], NDArray[np.intp]]:
    """Precompute the terms of eq. (5): which candidate supports which, and with what r.

    Returns
    -------
    t_i, t_j, t_r : ndarray, shape (T,)
        For every neighbour pair (N, M) and every candidate ``i`` of ``N`` and ``j`` of
        ``M`` (indices into ``cands``): ``r_ij = w_i + b_ij``.
    u_i, u_m : ndarray, shape (U,)
        For every neighbour pair and every candidate ``i`` of ``N``: ``i`` and ``M``.
    n_nbr : ndarray, shape (N_left,)
        Number of neighbours of each left edge point.
    """
    pn, pm, pconn = neighbours(left, radius=params.neighbour_radius)
    counts = cands.counts
    n_nbr = np.bincount(pn, minlength=len(left)).astype(np.intp)
    # (pair, i) list
    cn = counts[pn]
    u_pair = np.repeat(np.arange(pn.shape[0]), cn)
    u_i = np.repeat(cands.starts[pn], cn) + (
        np.arange(u_pair.shape[0]) - np.repeat(np.cumsum(cn) - cn, cn)
    )
    u_m = pm[u_pair]
    # (pair, i, j) list
    cm = counts[u_m]
    t_u = np.repeat(np.arange(u_i.shape[0]), cm)
    t_j = np.repeat(cands.starts[u_m], cm) + (
        np.arange(t_u.shape[0]) - np.repeat(np.cumsum(cm) - cm, cm)
    )
    t_i = u_i[t_u]
    t_pair = u_pair[t_u]
    q = cands.right[t_i]
    r = cands.right[t_j]
    above = left.line[pm[t_pair]] < left.line[pn[t_pair]]  # M above N
    q_link = np.where(above, right.up[q], right.down[q])
    r_link = np.where(above, right.down[r], right.up[r])
    qr = (q_link == r) | (r_link == q)
    q_else = (q_link >= 0) & (q_link != r)
    r_else = (r_link >= 0) & (r_link != q)
    b = connectivity_coefficient(pconn[t_pair], qr, q_else, r_else, params)
    t_r = cands.w[t_i] + b
    return t_i, t_j, t_r, u_i, u_m, n_nbr


def relax(
    left: EdgeSet,
    right: EdgeSet,
    cands: Candidates,
    p0: NDArray[np.float64],
    p0_none: NDArray[np.float64],
    *,
    params: RelaxationParameters | None = None,
) -> RelaxationResult:
    """Iterate the relaxation update of eq. (4)-(5) (thesis 3.4.2).

    Parameters
    ----------
    left, right : EdgeSet
        Edge points of the two images.
    cands : Candidates
        Candidate pairs with their combined similarities ``w``.
    p0 : ndarray, shape (M,)
        Initial candidate probabilities (eq. 1).
    p0_none : ndarray, shape (N_left,)
        Initial no-match probabilities (eq. 2).
    params : RelaxationParameters, optional

    Returns
    -------
    RelaxationResult

    Notes
    -----
    Each iteration ``k``:

    1. support of candidate ``i`` of ``N``:
       ``q_i = mean_M [ sum_j P_j(M) r_ij + P_none(M) * c ]``, with
       ``c = no_match_support``; the no-match label's support is ``c``;
    2. ``P_i <- P_i q_i / gamma`` and ``P_none <- P_none c / gamma`` with
       ``gamma = sum_i P_i q_i + P_none c`` (eq. 4-5 with the no-match label);
    3. stop when no probability changed by more than ``tolerance``.

    References
    ----------
    .. [1] T.-Q. Kim, NJIT thesis, 1989, section 3.4, eq. (4)-(5).
    .. [2] S. T. Barnard and W. B. Thompson, "Disparity analysis of images",
       IEEE Trans. PAMI 2(4), 333-340, 1980.
    """
    p = params or RelaxationParameters()
    t_i, t_j, t_r, u_i, u_m, n_nbr = support_structure(left, right, cands, p)
    c = p.no_match_support
    m = len(cands)
    # first renormalise so that each edge's labels sum to 1 (eq. 1-3 do not)
    total = group_sum(p0, cands.starts) + p0_none
    with np.errstate(divide="ignore", invalid="ignore"):
        prob = np.where(total[cands.left] > 0, p0 / total[cands.left], 0.0)
        pnone = np.where(total > 0, p0_none / total, 1.0)
    history, none_history = [prob], [pnone]
    nn = np.maximum(n_nbr, 1)[cands.left].astype(float)
    has_nbr = n_nbr[cands.left] > 0
    it = 0
    for it in range(1, p.iterations + 1):  # noqa: B007 - `it` is reported
        # float even when there are no terms (bincount of no weights gives int64)
        q = np.bincount(t_i, weights=prob[t_j] * t_r, minlength=m).astype(float)
        q += np.bincount(u_i, weights=pnone[u_m] * c, minlength=m)
        q = np.where(has_nbr, q / nn, c)
        num = prob * q
        gamma = group_sum(num, cands.starts) + pnone * c
        with np.errstate(divide="ignore", invalid="ignore"):
            new = np.where(gamma[cands.left] > 0, num / gamma[cands.left], prob)
            new_none = np.where(gamma > 0, pnone * c / gamma, pnone)
        change = max(
            float(np.max(np.abs(new - prob), initial=0.0)),
            float(np.max(np.abs(new_none - pnone), initial=0.0)),
        )
        prob, pnone = new, new_none
        history.append(prob)
        none_history.append(pnone)
        if change <= p.tolerance:
            break
    return RelaxationResult(history=history, none_history=none_history, iterations=it)
