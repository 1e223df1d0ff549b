"""Planning a capture: the baseline for an accuracy, N views' span, the direction, fusing.

Modules
-------
:mod:`~robostereo.robot.planning.baseline_plan`
    :func:`plan_baseline`: eq. 9 (thesis 3.7) inverted for the baseline ``D`` that
    bounds the depth error at a target depth by a wanted accuracy; the disparity range
    to search.
:mod:`~robostereo.robot.planning.views_plan`
    :func:`plan_views`: the same for N views in a pattern (their span and number);
    :func:`views_baseline_factor`, the two-view baseline the N views' bound equals.
:mod:`~robostereo.robot.planning.baseline_direction`
    :func:`best_baseline_direction`: the direction to move the camera so that most of
    an image's edges cross the epipolar lines.
:mod:`~robostereo.robot.planning.fusion`
    :func:`fuse_located`: the points of two captures merged into one set, each keeping
    its eq. 9 bound.

Imports: :mod:`robostereo.errors`, :mod:`robostereo.geometry` and
:mod:`robostereo.robot.views` (the viewpoint patterns); it may import the arms, the
captures, the hand-eye and the views, none of which imports it (of the robot side, only
:mod:`robostereo.robot.simulated` does).
"""

from robostereo.robot.planning.baseline_direction import (
    BaselineDirection,
    best_baseline_direction,
)
from robostereo.robot.planning.baseline_plan import (
    MIN_PLAN_DISPARITY_PX,
    BaselinePlan,
    plan_baseline,
)
from robostereo.robot.planning.fusion import FusedPoints, fuse_located
from robostereo.robot.planning.views_plan import (
    NEIGHBOUR_DISPARITY_PX,
    ViewsPlan,
    plan_views,
    views_baseline_factor,
)

__all__ = [
    "MIN_PLAN_DISPARITY_PX",
    "NEIGHBOUR_DISPARITY_PX",
    "BaselineDirection",
    "BaselinePlan",
    "FusedPoints",
    "ViewsPlan",
    "best_baseline_direction",
    "fuse_located",
    "plan_baseline",
    "plan_views",
    "views_baseline_factor",
]
