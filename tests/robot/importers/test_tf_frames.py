"""Tests for robostereo.robot.importers.tf_frames: the /tf tree, its chains and the
interpolation of its dynamic edges."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.importers.tf_frames import TransformTree

S = 1_000_000_000  # ns


def _q(rotvec) -> list[float]:
    return Rotation.from_rotvec(rotvec).as_quat().tolist()


def test_a_dynamic_edge_is_interpolated_linearly_and_by_slerp_between_its_samples():
    tree = TransformTree.from_transforms([
        (10 * S, "base", "flange", [0.0, 0.0, 0.0], _q([0, 0, 0]), False),
        (11 * S, "base", "flange", [0.4, -0.2, 0.0], _q([0, 0, np.pi / 2]), False)])
    pose = tree.chain_poses("base", "flange", [10 * S + 250_000_000])[0]
    np.testing.assert_allclose(pose.translation, [100.0, -50.0, 0.0], atol=1e-9)  # mm
    np.testing.assert_allclose(pose.rotvec, [0, 0, np.pi / 8], atol=1e-12)  # a quarter
    # a sample repeated at one stamp: the last one counts
    tree = TransformTree.from_transforms([
        (0, "a", "b", [1.0, 0, 0], _q([0, 0, 0]), False),
        (0, "a", "b", [2.0, 0, 0], _q([0, 0, 0]), False),
        (S, "a", "b", [2.0, 0, 0], _q([0, 0, 0]), False)])
    assert tree.chain_poses("a", "b", [0])[0].translation[0] == pytest.approx(2000.0)


def test_a_chain_through_a_common_ancestor_composes_both_branches():
    T_wa = SE3.from_rotvec([100.0, 0, 0], [0.3, 0, 0])
    T_wb = SE3.from_rotvec([0, 200.0, 50.0], [0, 0.2, -0.1])
    T_bc = SE3.from_rotvec([0, 0, 30.0], [0.1, 0.1, 0.1])

    def row(stamp, parent, child, T, static):
        return (stamp, parent, child, T.translation / 1000, T.quaternion, static)

    tree = TransformTree.from_transforms([
        row(0, "/world", "/a", T_wa, True), row(0, "world", "b", T_wb, False),
        row(2 * S, "world", "b", T_wb, False), row(0, "b", "c", T_bc, True)])
    pose = tree.chain_poses("a", "/c", [S])[0]  # the leading / of ROS 1 ignored
    want = T_wa.inv() @ T_wb @ T_bc
    np.testing.assert_allclose(pose.matrix, want.matrix, atol=1e-9)
    back = tree.chain_poses("c", "a", [S])[0]
    np.testing.assert_allclose(back.matrix, want.inv().matrix, atol=1e-9)


def test_stamps_past_a_dynamic_edge_are_held_within_the_tolerance_and_refused_beyond():
    tree = TransformTree.from_transforms([
        (5 * S, "base", "flange", [0.0, 0, 0], _q([0, 0, 0]), False),
        (6 * S, "base", "flange", [1.0, 0, 0], _q([0, 0, 0]), False)])
    held = tree.chain_poses("base", "flange", [6 * S + 9_000_000])[0]
    assert held.translation[0] == pytest.approx(1000.0)
    with pytest.raises(InputError, match=r"the image at 6\.011000 s lies outside the tf "
                                         r"from 'base' to 'flange' \(5\.000000 \.\. 6\.000000"):
        tree.chain_poses("base", "flange", [6 * S + 11_000_000])
    with pytest.raises(InputError, match="outside"):
        tree.chain_poses("base", "flange", [4 * S])
    # a wider tolerance holds it
    assert tree.chain_poses("base", "flange", [4 * S], tolerance_s=1.5)[0].translation[0] == 0


def test_frames_in_separate_trees_or_absent_have_no_chain():
    tree = TransformTree.from_transforms([
        (0, "base", "flange", [0.0, 0, 0], _q([0, 0, 0]), True),
        (0, "odom", "camera", [0.0, 0, 0], _q([0, 0, 0]), True)])
    with pytest.raises(InputError, match=r"no tf chain from 'base' to 'camera': they are in "
                                         r"separate trees \(roots 'base' and 'odom'\)"):
        tree.chain_poses("base", "camera", [0])
    with pytest.raises(InputError, match="no frame 'tool0' in /tf or /tf_static"):
        tree.chain_poses("base", "tool0", [0])


def test_a_frame_published_under_two_parents_is_refused_on_a_chain_through_it():
    tree = TransformTree.from_transforms([
        (0, "base", "flange", [0.0, 0, 0], _q([0, 0, 0]), False),
        (0, "world", "flange", [0.0, 0, 0], _q([0, 0, 0]), True),
        (0, "base", "other", [0.0, 0, 0], _q([0, 0, 0]), True),
        (0, "flange", "camera", [0.0, 0, 0], _q([0, 0, 0]), True)])
    assert tree.chain_poses("base", "other", [0])[0].angle == 0.0  # not through it
    with pytest.raises(InputError, match="goes through 'flange', published under 'base' "
                                         r"\(dynamic\) and 'world' \(static\)"):
        tree.chain_poses("base", "camera", [0])


def test_a_transform_that_is_not_finite_is_refused():
    with pytest.raises(InputError, match="from 'a' to 'b'"):
        TransformTree.from_transforms([(0, "a", "b", [np.nan, 0, 0], [0, 0, 0, 1], True)])
    with pytest.raises(InputError, match="from 'a' to 'b'"):
        TransformTree.from_transforms([(0, "a", "b", [0, 0, 0], [0, 0, 0, 0], True)])
