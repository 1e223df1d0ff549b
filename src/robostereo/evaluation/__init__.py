"""Scoring matches against ground truth: the rules, outlines, visibility, the scene scorer.

Modules
-------
:mod:`~robostereo.evaluation.rules`
    The project's rule and the silhouette rule, the depth-step mask, coverage curves,
    the expected calibration error, :func:`score_matches`.
:mod:`~robostereo.evaluation.visibility`
    Which left pixels the right view sees (ground truth), why points go missing.
:mod:`~robostereo.evaluation.outlines`
    Figures near and away from depth steps, 3-D surface distances, boundary offsets.
:mod:`~robostereo.evaluation.scorer`
    :func:`evaluate_scene`: a scene scored, robostereo and OpenCV's StereoSGBM at the
    same pixels; its report.

Imports: :mod:`robostereo.errors`, :mod:`robostereo.geometry`, :mod:`robostereo.io`,
:mod:`robostereo.datasets` and :mod:`robostereo.matcher`; modules in the order above
import only the ones before them.
"""

from robostereo.evaluation.outlines import (
    OUTLINE_LEVELS,
    MethodPoints,
    OffsetSummary,
    OutlineFigures,
    RowBoundaries,
    SplitFigures,
    boundary_offsets,
    format_outline_figures,
    outline_figures,
    row_boundaries,
    settings_curve,
    silhouette_offsets,
    surface_distances,
)
from robostereo.evaluation.rules import (
    RULES,
    CoverageCurve,
    MatchScore,
    check_points,
    coverage_curve,
    depth_step_mask,
    expected_calibration_error,
    match_errors,
    near_steps,
    rule_errors,
    score_matches,
    silhouette_errors,
)
from robostereo.evaluation.scorer import (
    CURVE_LEVELS,
    SGBM_SWEEP,
    MethodFigures,
    SceneEvaluation,
    errors_3d,
    evaluate_scene,
    format_evaluation,
    nearest_ground_truth,
    sample_dense,
    sgbm_curve,
    sgbm_disparity,
    sgbm_input,
    sgbm_sweep,
)
from robostereo.evaluation.visibility import (
    BREAKDOWN,
    HIDDEN,
    UNKNOWN,
    VISIBLE,
    MissingBreakdown,
    Visibility,
    VisibilityFigures,
    cross_check_occlusion,
    edge_visibility,
    format_visibility_figures,
    left_visibility,
    missing_breakdown,
    visibility_figures,
    zbuffer_occlusion,
)

__all__ = [
    "BREAKDOWN",
    "CURVE_LEVELS",
    "HIDDEN",
    "OUTLINE_LEVELS",
    "RULES",
    "SGBM_SWEEP",
    "UNKNOWN",
    "VISIBLE",
    "CoverageCurve",
    "MatchScore",
    "MethodFigures",
    "MethodPoints",
    "MissingBreakdown",
    "OffsetSummary",
    "OutlineFigures",
    "RowBoundaries",
    "SceneEvaluation",
    "SplitFigures",
    "Visibility",
    "VisibilityFigures",
    "boundary_offsets",
    "check_points",
    "coverage_curve",
    "cross_check_occlusion",
    "depth_step_mask",
    "edge_visibility",
    "errors_3d",
    "evaluate_scene",
    "expected_calibration_error",
    "format_evaluation",
    "format_outline_figures",
    "format_visibility_figures",
    "left_visibility",
    "match_errors",
    "missing_breakdown",
    "near_steps",
    "nearest_ground_truth",
    "outline_figures",
    "row_boundaries",
    "rule_errors",
    "sample_dense",
    "score_matches",
    "settings_curve",
    "sgbm_curve",
    "sgbm_disparity",
    "sgbm_input",
    "sgbm_sweep",
    "silhouette_errors",
    "silhouette_offsets",
    "surface_distances",
    "visibility_figures",
    "zbuffer_occlusion",
]
