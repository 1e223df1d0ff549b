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
:mod:`~robostereo.evaluation.depth_maps`
    Ground-truth depth maps of capture folders: where they are, PFM, NPY and PNG.
:mod:`~robostereo.evaluation.capture_scoring`
    :func:`evaluate_capture_depth`: a capture's located points and StereoSGBM's scored
    against a depth map (3-D errors, coverage of the edge pixels both views see).

Imports: :mod:`robostereo.errors`, :mod:`robostereo.geometry`, :mod:`robostereo.io`,
:mod:`robostereo.datasets` and :mod:`robostereo.matcher`; modules in the order above
import only the ones before them.
"""

from robostereo.evaluation.capture_scoring import (
    COVER_PX,
    CaptureEvaluation,
    CapturePoints,
    DepthFigures,
    SgbmPair,
    depth_errors,
    depth_figures,
    evaluate_capture_depth,
    format_capture_evaluation,
    occlusion_tolerance_mm,
    sgbm_points,
    shared_edge_pixels,
)
from robostereo.evaluation.depth_maps import (
    DEFAULT_DEPTH_SCALE,
    DEPTH_FOLDER,
    DEPTH_SUFFIXES,
    DepthFiles,
    capture_depth_files,
    depth_map_bytes,
    depth_map_files,
    read_depth_map,
    write_depth_map,
)
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
    "COVER_PX",
    "CURVE_LEVELS",
    "DEFAULT_DEPTH_SCALE",
    "DEPTH_FOLDER",
    "DEPTH_SUFFIXES",
    "HIDDEN",
    "OUTLINE_LEVELS",
    "RULES",
    "SGBM_SWEEP",
    "UNKNOWN",
    "VISIBLE",
    "CaptureEvaluation",
    "CapturePoints",
    "CoverageCurve",
    "DepthFigures",
    "DepthFiles",
    "MatchScore",
    "MethodFigures",
    "MethodPoints",
    "MissingBreakdown",
    "OffsetSummary",
    "OutlineFigures",
    "RowBoundaries",
    "SceneEvaluation",
    "SgbmPair",
    "SplitFigures",
    "Visibility",
    "VisibilityFigures",
    "boundary_offsets",
    "capture_depth_files",
    "check_points",
    "coverage_curve",
    "cross_check_occlusion",
    "depth_errors",
    "depth_figures",
    "depth_map_bytes",
    "depth_map_files",
    "depth_step_mask",
    "edge_visibility",
    "errors_3d",
    "evaluate_capture_depth",
    "evaluate_scene",
    "expected_calibration_error",
    "format_capture_evaluation",
    "format_evaluation",
    "format_outline_figures",
    "format_visibility_figures",
    "left_visibility",
    "match_errors",
    "missing_breakdown",
    "near_steps",
    "nearest_ground_truth",
    "occlusion_tolerance_mm",
    "outline_figures",
    "read_depth_map",
    "row_boundaries",
    "rule_errors",
    "sample_dense",
    "score_matches",
    "settings_curve",
    "sgbm_curve",
    "sgbm_disparity",
    "sgbm_input",
    "sgbm_points",
    "sgbm_sweep",
    "shared_edge_pixels",
    "silhouette_errors",
    "silhouette_offsets",
    "surface_distances",
    "visibility_figures",
    "write_depth_map",
    "zbuffer_occlusion",
]
