"""The matching stages behind :func:`~robostereo.matcher.pipeline.match_stereo`, once.

:func:`match_once` runs the thesis's chapter 3 on a pair as given: edge points in both
images (3.1-3.2), then the window method's costs, disparity and confidence, or the
thesis's candidates and relaxation (3.3-3.5).  ``match_stereo`` calls it once, and again
where a check on the first match (:mod:`~robostereo.matcher.alignment`,
:mod:`~robostereo.matcher.photometric`) finds the views' rows or grey levels apart.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.matcher.candidates import (
    assign_matches,
    find_candidates,
    group_argmax,
    initial_probabilities,
)
from robostereo.matcher.edge_features import EdgeSet
from robostereo.matcher.edges import detect_edges
from robostereo.matcher.grey_levels import to_grey
from robostereo.matcher.parallel import run_all
from robostereo.matcher.parameters import MatchParameters
from robostereo.matcher.photometric import GreyMap
from robostereo.matcher.relaxation import relax
from robostereo.matcher.window_costs import PATH_PENALTIES
from robostereo.matcher.window_match import search_costs, window_match

__all__ = ["match_once"]


def match_once(a: np.ndarray, b: np.ndarray, lo: float, hi: float, p: MatchParameters,
               valid_left: ArrayLike | None, valid_right: ArrayLike | None,
               say: Callable[[str], None], t: dict[str, float], grey_map: GreyMap | None,
               accept: Callable[[EdgeSet, NDArray[np.float64], NDArray[np.float64]],
                                NDArray[np.bool_]]) -> tuple[dict, EdgeSet, EdgeSet]:
    """One match of the pair ``a, b`` (``(H, W)`` or ``(H, W, 3|4)``) over the disparities
    ``lo .. hi`` by ``p``'s method (:func:`~robostereo.matcher.pipeline.match_stereo`'s
    steps 1-3; ``p`` is its :class:`~robostereo.matcher.parameters.MatchParameters`, not
    imported here: that would be a cycle), the right view's grey levels through
    ``grey_map`` where given, the window method's acceptance by
    ``accept(left_edges, disparity, confidence)``.

    Returns the fields of :class:`~robostereo.matcher.pipeline.MatchResult` that are
    per edge point (a dict) and the two edge sets; stage times go into ``t``."""
    t0 = time.perf_counter()
    say("edges")
    # grey levels on this thread: the memory they take, freed after the window costs,
    # is then this thread's to reuse (a worker thread's allocator keeps its own memory)
    ga = to_grey(a, bit_depth=p.bit_depth, name="left image")
    gb = to_grey(b, bit_depth=p.bit_depth, name="right image")
    if grey_map is not None:
        gb = grey_map(gb)

    # the two images' edge points side by side, on two threads where there are two cores
    el, er = run_all([
        lambda: detect_edges(a, threshold=p.threshold, row_step=p.row_step,
                             subpixel=p.subpixel, grey=ga, valid=valid_left,
                             edge_blur_px=p.edge_blur_px),
        lambda: detect_edges(b, threshold=p.threshold * p.right_threshold_ratio,
                             row_step=p.row_step, subpixel=p.subpixel, grey=gb,
                             valid=valid_right, edge_blur_px=p.edge_blur_px),
    ])
    t1 = time.perf_counter()
    t["edges"] = t1 - t0
    n = len(el)
    if p.method == "window":
        say("window costs")
        costs = search_costs(
            el, ga, gb, (float(lo), float(hi)), gradient_truncation=p.gradient_truncation,
            valid_left=None if valid_left is None else np.asarray(valid_left, bool),
            valid_right=None if valid_right is None else np.asarray(valid_right, bool),
            path_penalties=PATH_PENALTIES if p.paths else None, coarse=p.coarse)
        del ga, gb  # the grey images are done with: not held at the peak of what follows
        wm = window_match(el, er, None, None, (float(lo), float(hi)),
                          gradient_truncation=p.gradient_truncation, weights=p.weights,
                          profile_scale=p.profile_scale, costs=costs)
        conf = wm.confidence
        accepted = accept(el, wm.disparity, conf)
        fields = dict(edge_disparity=wm.disparity, edge_confidence=conf,
                      edge_right=wm.right_edge, accepted=accepted, window=wm,
                      candidates=None, relaxation=None, match=None)
        t["window"] = time.perf_counter() - t1
    else:
        say("candidates")
        del ga, gb  # not used by the relaxation
        cands = find_candidates(el, er, (float(lo), float(hi)), weights=p.weights,
                                profile_scale=p.profile_scale)
        p0, p0_none = initial_probabilities(cands)
        t2 = time.perf_counter()
        t["candidates"] = t2 - t1
        say("relaxation")
        rel = relax(el, er, cands, p0, p0_none, params=p.relaxation)
        match = assign_matches(cands, rel.probability, rel.no_match, n,
                               min_probability=p.acceptance)
        prob = rel.probability
        best = np.where(match >= 0, match, group_argmax(prob, cands.starts))
        has = best >= 0
        bi = np.maximum(best, 0)
        nan = np.full(n, np.nan)
        fields = dict(
            edge_disparity=np.where(has, cands.disparity[bi], nan) if len(cands) else nan,
            edge_confidence=np.where(has, prob[bi], nan) if len(cands) else nan,
            edge_right=np.where(has, cands.right[bi], -1).astype(np.intp) if len(cands)
            else np.full(n, -1, dtype=np.intp),
            accepted=match >= 0, window=None, candidates=cands, relaxation=rel, match=match)
        t["relaxation"] = time.perf_counter() - t2
    return fields, el, er
