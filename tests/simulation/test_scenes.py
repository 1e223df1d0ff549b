"""Tests of the thesis's scenes: the block where table 5-1 puts it, the hub-pulley."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robostereo.geometry.camera import SEED_CAMERA
from robostereo.geometry.poses import Pose
from robostereo.simulation.render import render
from robostereo.simulation.scenes import hub_pulley_scene, seed_block_scene

CAM = SEED_CAMERA


def test_holes_and_bores_show_the_table() -> None:
    scene = hub_pulley_scene()
    pose = scene.view_pose
    r = render(scene, CAM, pose, supersample=1)
    hole_centres = [
        (56 * math.cos(a), 56 * math.sin(a), 0.0) for a in np.deg2rad(np.arange(8) * 45 + 22.5)
    ]
    uv, _ = CAM.project([*hole_centres, (0.0, 0.0, 0.0)], pose)
    ij = np.rint(uv[:, ::-1]).astype(int)
    assert (r.labels[ij[:, 0], ij[:, 1]] == 0).all()
    assert r.depth[240, 254] == 1070.0  # the principal ray, straight down the bore


def test_lift_moves_the_block_top_by_lift_mm() -> None:
    base = seed_block_scene()
    lifted = seed_block_scene(lift_mm=79.65)
    assert lifted.top_z - base.top_z == pytest.approx(79.65, abs=1e-12)
    assert (lifted.left_x, lifted.right_x, lifted.width) == (base.left_x, base.right_x, 23.6)
    pose = base.view_pose
    assert lifted.view_pose == pose
    uv, _ = CAM.project([[0.0, 0.0, base.top_z]], pose)  # block centre column/row
    i, j = round(uv[0, 1]), round(uv[0, 0])
    d0 = render(base, CAM, pose, supersample=1).depth[i, j]
    d1 = render(lifted, CAM, pose, supersample=1).depth[i, j]
    assert d0 == pytest.approx(1000.0, abs=1e-9)
    assert d0 - d1 == pytest.approx(79.65, abs=1e-9)


def test_block_seen_where_table_5_1_puts_it() -> None:
    scene = seed_block_scene()
    pose = scene.view_pose
    assert scene.left_x - pose.x == pytest.approx(-55.1)
    assert scene.right_x - pose.x == pytest.approx(-31.5)
    # epipolar Y = -world Y for alpha = 0: table 5-1's y from +55 to -10 mm is covered
    assert scene.front_y - pose.y < -55.0 and scene.back_y - pose.y > 10.0
    r = render(scene, CAM, pose)
    cols = np.nonzero((r.labels == 1).any(axis=0))[0]
    assert cols.max() < 254 - 40  # left of the image centre
    rows = np.nonzero((r.labels == 1).any(axis=1))[0]
    assert len(range(rows.min(), rows.max() + 1, 8)) >= 13  # crosses >= 13 lines


def test_hub_pulley_gives_several_hundred_edge_points() -> None:
    from robostereo.matcher.edges import detect_edges

    scene = hub_pulley_scene()
    mid = scene.view_pose
    counts = []
    for dx in (-10.0, 10.0):
        pose = Pose(mid.x + dx, mid.y, mid.z)
        img = render(scene, CAM, pose, noise_sigma=0.7, rng=np.random.default_rng(2)).image
        counts.append(len(detect_edges(img, bit_depth=7, threshold=8.0, row_step=8)))
    assert all(500 <= n <= 1200 for n in counts), counts  # the thesis: 818 and 815
    assert abs(counts[0] - counts[1]) < 0.05 * counts[0]
