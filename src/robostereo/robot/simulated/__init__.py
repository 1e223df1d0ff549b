"""The simulated robots: the thesis's AdeptOne rig, the six-axis arm, N views in a pattern.

Every module renders with :mod:`robostereo.simulation` (ray casting, exact ground
truth); they drive the demo, ``capture`` and ``simulate-handeye``, and the tests.

Modules
-------
:mod:`~robostereo.robot.simulated.scara_rig`
    The simulated AdeptOne rig (sections 4.1-4.2): the set-up (:class:`RigSetup`), the
    block and hub-pulley scenes and their captures (:func:`simulate_capture`).
:mod:`~robostereo.robot.simulated.sixaxis_rig`
    The simulated six-axis rig: the block on the table, two tilted viewpoints and their
    capture (:func:`simulate_six_axis_capture`), the renderer's options.
:mod:`~robostereo.robot.simulated.sixaxis_handeye`
    Hand-eye views of a board on the table from the six-axis arm
    (:func:`simulate_handeye_views`).
:mod:`~robostereo.robot.simulated.block_experiments`
    The block from the six-axis arm with an estimated hand-eye
    (:func:`run_six_axis_block`), and from the AdeptOne along two baselines fused
    (:func:`run_fused_block`).
:mod:`~robostereo.robot.simulated.grab_views`
    Either simulated robot grabbing N views in a pattern (:func:`simulate_views`).
:mod:`~robostereo.robot.simulated.views_truth`
    N-view located points scored against a simulated capture's truth.

Imports: everything below it, :mod:`robostereo.simulation` and every other part of
:mod:`robostereo.robot`; nothing in the robot side imports it.
"""

from robostereo.robot.simulated.block_experiments import (
    FusedBlockGain,
    SixAxisBlock,
    SixAxisHeight,
    run_fused_block,
    run_six_axis_block,
)
from robostereo.robot.simulated.grab_views import (
    ROBOTS,
    SimulatedViews,
    estimated_hand_eye,
    post_before_a_printed_plane,
    simulate_views,
)
from robostereo.robot.simulated.scara_rig import (
    SEED_LIFT_MM,
    RigSetup,
    SceneKind,
    SimulatedCapture,
    block_scene,
    pulley_scene,
    simulate_capture,
)
from robostereo.robot.simulated.sixaxis_handeye import BOARD, board_scene, simulate_handeye_views
from robostereo.robot.simulated.sixaxis_rig import (
    BLOCK_CENTER_XY,
    BLOCK_SIZE,
    SIX_AXIS_RENDER,
    SixAxisCapture,
    SixAxisViewpoints,
    render_six_axis,
    simulate_six_axis_capture,
    six_axis_block_scene,
)
from robostereo.robot.simulated.views_truth import (
    views_block_truth,
    views_correct,
    views_outline_coverage,
    views_pulley_score,
)

__all__ = [
    "BLOCK_CENTER_XY",
    "BLOCK_SIZE",
    "BOARD",
    "ROBOTS",
    "SEED_LIFT_MM",
    "SIX_AXIS_RENDER",
    "FusedBlockGain",
    "RigSetup",
    "SceneKind",
    "SimulatedCapture",
    "SimulatedViews",
    "SixAxisBlock",
    "SixAxisCapture",
    "SixAxisHeight",
    "SixAxisViewpoints",
    "block_scene",
    "board_scene",
    "estimated_hand_eye",
    "post_before_a_printed_plane",
    "pulley_scene",
    "render_six_axis",
    "run_fused_block",
    "run_six_axis_block",
    "simulate_capture",
    "simulate_handeye_views",
    "simulate_six_axis_capture",
    "simulate_views",
    "six_axis_block_scene",
    "views_block_truth",
    "views_correct",
    "views_outline_coverage",
    "views_pulley_score",
]
