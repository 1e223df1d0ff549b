"""N viewpoints of one camera: N-view captures, their folders, and locating edge points.

Modules
-------
:mod:`~robostereo.robot.views.viewpoints`
    :class:`ViewsCapture` (N grabbed views and their poses) and the viewpoint patterns
    (line, cross, arc).
:mod:`~robostereo.robot.views.views_folder`
    N-view capture folders: ``capture.yaml`` with a list of views; a two-view folder
    reads as N = 2.
:mod:`~robostereo.robot.views.locating`
    :func:`locate_views`: each view the reference in turn, its stages run, the points
    gathered and reported once.
:mod:`~robostereo.robot.views.views_parameters`
    :class:`ViewsParameters`, its tuning.
:mod:`~robostereo.robot.views.located_points`
    :class:`LocatedViews`, its result: each point's bound (eq. 9 generalised,
    :func:`views_bound`) and confidence (:func:`views_confidence`).
:mod:`~robostereo.robot.views.prepared_views`
    Its first stages: the views prepared, the reference's edge points.
:mod:`~robostereo.robot.views.ray_search`
    Each reference edge point's ray searched in inverse depth; the ray's geometry.
:mod:`~robostereo.robot.views.point_refinement`
    Each 3-D point refined by least squares over the views that agree.
:mod:`~robostereo.robot.views.edge_votes`
    Edge votes where windows fail, the views left out at occlusions.
:mod:`~robostereo.robot.views.pose_check`
    The views' poses checked against the epipolar geometry their images show.
:mod:`~robostereo.robot.views.edge_profiles`
    An edge beside an opposite edge placed by two blurred steps; each view's blur.
:mod:`~robostereo.robot.views.views_kernels`, :mod:`~robostereo.robot.views.edge_profile_kernels`
    Their numba kernels.

Imports: :mod:`robostereo.errors`, :mod:`robostereo.geometry`, :mod:`robostereo.io`,
:mod:`robostereo.matcher` and :mod:`robostereo.robot.capture` (the two-view folder
format); not the arms, hand-eye, planning or the simulators.
"""

from robostereo.robot.views.located_points import (
    CONFIDENCE_WEIGHTS,
    DISTINCT_FLOOR,
    LocatedViews,
    confidence_features,
    confidence_features_from,
    confidence_terms,
    point_noise_px,
    residual_noise_px,
    views_bound,
    views_confidence,
)
from robostereo.robot.views.locating import locate_views, reference_order
from robostereo.robot.views.pose_check import (
    EPIPOLAR_TOLERANCE_DEG,
    EPIPOLAR_TOLERANCE_PX,
    MIN_PLACES,
    EpipolarCheck,
    corners_to_track,
    epipolar_check,
    fundamental_from_poses,
    pose_offset_px,
    views_epipolar_checks,
    warn_disagreeing,
)
from robostereo.robot.views.viewpoints import (
    MAX_SPAN_MM,
    PATTERNS,
    ViewsCapture,
    view_offsets,
)
from robostereo.robot.views.views_folder import (
    VIEWS_KEYS,
    is_views_folder,
    read_views_capture,
    views_capture_to_dict,
    views_folder_files,
    write_views_capture,
)
from robostereo.robot.views.views_parameters import ViewsParameters

__all__ = [
    "CONFIDENCE_WEIGHTS",
    "DISTINCT_FLOOR",
    "EPIPOLAR_TOLERANCE_DEG",
    "EPIPOLAR_TOLERANCE_PX",
    "MAX_SPAN_MM",
    "MIN_PLACES",
    "PATTERNS",
    "VIEWS_KEYS",
    "EpipolarCheck",
    "LocatedViews",
    "ViewsCapture",
    "ViewsParameters",
    "confidence_features",
    "confidence_features_from",
    "confidence_terms",
    "corners_to_track",
    "epipolar_check",
    "fundamental_from_poses",
    "is_views_folder",
    "locate_views",
    "point_noise_px",
    "pose_offset_px",
    "read_views_capture",
    "reference_order",
    "residual_noise_px",
    "view_offsets",
    "views_bound",
    "views_capture_to_dict",
    "views_confidence",
    "views_epipolar_checks",
    "views_folder_files",
    "warn_disagreeing",
    "write_views_capture",
]
