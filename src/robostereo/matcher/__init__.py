"""The matcher: from a rectified stereo pair to matched edge points (the thesis, chapter 3).

The modules in pipeline order:

* :mod:`~robostereo.matcher.grey_levels`: grey levels on the thesis's 0..127 scale and
  its 5 x 5 smoothing filter (3.1);
* :mod:`~robostereo.matcher.edges`: edge points along the epipolar lines, found to
  sub-pixel precision (3.1-3.2; :mod:`~robostereo.matcher.edge_kernels`: its numba
  kernels);
* :mod:`~robostereo.matcher.edge_features`: the edge points' features and their container
  :class:`EdgeSet`, connectivity and pattern types (3.2);
* :mod:`~robostereo.matcher.window_costs`: side-aware census + gradient window costs
  of every disparity at the left edge points, the paths along the rows, the half-size
  pass that narrows a wide range (checks, bands, threads);
* :mod:`~robostereo.matcher.window_kernels`: its numba kernels (census, Sobel, the
  pass down the image, the evidence), constants first;
* :mod:`~robostereo.matcher.window_match`: the best disparity of each left edge point
  made sub-pixel, its evidence and its confidence (the default method);
* :mod:`~robostereo.matcher.confidence`: the calibrated model from evidence to
  ``P(correct)`` (3.3, eq. 2);
* :mod:`~robostereo.matcher.alignment`: the rows' offset between the views at the
  accepted matches, tracked by Lucas-Kanade (:mod:`~robostereo.matcher.alignment_kernels`);
* :mod:`~robostereo.matcher.photometric`: the two views' grey levels compared at the
  accepted matches, and the map that corrects the right view's where they differ
  (:mod:`~robostereo.matcher.photometric_kernels`: its numba kernel);
* :mod:`~robostereo.matcher.stages`: one match, all stages, as the pipeline runs it once
  and again where a check calls for it;
* :mod:`~robostereo.matcher.candidates`: the thesis's right-edge candidates, similarity
  indices GI, PI, AI, initial probabilities and acceptance (3.2-3.3, 3.5);
* :mod:`~robostereo.matcher.relaxation`: relaxation on edge connectivity (3.4);
* :mod:`~robostereo.matcher.pipeline`: :func:`match_stereo`, all stages in one call,
  and its parameters and result;
* :mod:`~robostereo.matcher.parallel`: the threads the stages share.
"""

from robostereo.matcher.alignment import ROW_TOLERANCE_PX, RowOffset, moved_rows, row_offset
from robostereo.matcher.candidates import (
    Candidates,
    SimilarityWeights,
    assign_matches,
    find_candidates,
    group_argmax,
    group_max,
    group_sum,
    initial_probabilities,
    pair_similarity,
)
from robostereo.matcher.confidence import (
    DEFAULT_MODEL,
    FEATURES,
    ConfidenceModel,
    calibration_table,
    fit_confidence,
    isotonic,
)
from robostereo.matcher.edge_features import (
    EdgeSet,
    connectivity,
    pattern_difference,
    pattern_type,
)
from robostereo.matcher.edges import detect_edges, usable_pixels
from robostereo.matcher.grey_levels import SEED_KERNEL, smooth, to_grey
from robostereo.matcher.parallel import n_threads, run_all
from robostereo.matcher.parameters import DEFAULT_MIN_CONFIDENCE, METHODS, MatchParameters
from robostereo.matcher.photometric import (
    GreyMap,
    fit_grey_map,
    grey_correction,
    grey_difference,
    grey_pairs,
    views_differ,
)
from robostereo.matcher.pipeline import (
    PARABOLA_DISPARITY_UNCERTAINTY_PX,
    MatchResult,
    match_stereo,
    searched_range,
    warm_up,
)
from robostereo.matcher.relaxation import (
    RelaxationParameters,
    RelaxationResult,
    connectivity_coefficient,
    neighbours,
    relax,
    support_structure,
)
from robostereo.matcher.window_costs import (
    COARSE_MARGIN,
    PATH_PENALTIES,
    WindowCosts,
    census_transform,
    coarse_matches,
    coarse_range,
    sobel_x,
    window_costs,
)
from robostereo.matcher.window_match import (
    COARSE_MIN_DISPARITIES,
    SWAP_UNIQUENESS,
    WindowMatch,
    window_match,
)

__all__ = [
    "COARSE_MARGIN",
    "COARSE_MIN_DISPARITIES",
    "DEFAULT_MIN_CONFIDENCE",
    "DEFAULT_MODEL",
    "FEATURES",
    "METHODS",
    "PARABOLA_DISPARITY_UNCERTAINTY_PX",
    "PATH_PENALTIES",
    "ROW_TOLERANCE_PX",
    "SEED_KERNEL",
    "SWAP_UNIQUENESS",
    "Candidates",
    "ConfidenceModel",
    "EdgeSet",
    "GreyMap",
    "MatchParameters",
    "MatchResult",
    "RelaxationParameters",
    "RelaxationResult",
    "RowOffset",
    "SimilarityWeights",
    "WindowCosts",
    "WindowMatch",
    "assign_matches",
    "calibration_table",
    "census_transform",
    "coarse_matches",
    "coarse_range",
    "connectivity",
    "connectivity_coefficient",
    "detect_edges",
    "find_candidates",
    "fit_confidence",
    "fit_grey_map",
    "grey_correction",
    "grey_difference",
    "grey_pairs",
    "group_argmax",
    "group_max",
    "group_sum",
    "initial_probabilities",
    "isotonic",
    "match_stereo",
    "moved_rows",
    "n_threads",
    "neighbours",
    "pair_similarity",
    "pattern_difference",
    "pattern_type",
    "relax",
    "row_offset",
    "run_all",
    "searched_range",
    "smooth",
    "sobel_x",
    "support_structure",
    "to_grey",
    "usable_pixels",
    "views_differ",
    "warm_up",
    "window_costs",
    "window_match",
]
