"""Tests of the primitives: labels, hit points on their surfaces, the table texture."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robostereo.geometry.camera import SEED_CAMERA
from robostereo.geometry.poses import Pose
from robostereo.simulation.primitives import Box, Cylinder, Disc, TablePlane
from robostereo.simulation.render import render
from robostereo.simulation.scenes import Scene, hub_pulley_scene
from robostereo.simulation.surfaces import NoiseTexture

CAM = SEED_CAMERA


def test_labels_of_yawed_box_seen_from_yawed_camera() -> None:
    box = Box((10.0, -20.0), 0.0, (40.0, 25.0, 30.0), yaw=0.5, albedo=0.9)
    scene = Scene((TablePlane(0.0, 0.2), box))
    pose = Pose(0.0, 0.0, 900.0, phi=-0.7)
    r = render(scene, CAM, pose)
    c, s = math.cos(0.5), math.sin(0.5)
    for scale, label in ((0.9, 1), (1.1, 0)):
        lx = np.array([-1, 1, 1, -1, 0.0, 0.0]) * 20.0 * scale
        ly = np.array([-1, -1, 1, 1, 1, -1]) * 12.5 * scale
        pts = np.column_stack([10 + c * lx - s * ly, -20 + s * lx + c * ly, np.full(6, 30.0)])
        if label == 0:
            pts[:, 2] = 0.0  # just outside the box, on the table
        uv, _ = CAM.project(pts, pose)
        ij = np.rint(uv[:, ::-1]).astype(int)
        assert (r.labels[ij[:, 0], ij[:, 1]] == label).all()
    # depth on the top face is exactly camera height - top
    assert np.all(r.depth[r.labels == 1] >= 870.0 - 1e-9)
    assert np.sum(np.isclose(r.depth[r.labels == 1], 870.0, atol=1e-9)) > 1000


def test_hit_points_lie_on_their_surfaces() -> None:
    # back-projecting every pixel centre with its depth lands on the labelled primitive
    scene = hub_pulley_scene(center_xy=(200.0, -50.0))
    pose = Pose(230.0, -40.0, 1070.0, phi=0.3)
    r = render(scene, CAM, pose, supersample=1)
    jj, ii = np.meshgrid(np.arange(CAM.width), np.arange(CAM.height))
    pts = CAM.backproject(np.column_stack([jj.ravel(), ii.ravel()]), r.depth.ravel(), pose)
    lab = r.labels.ravel()
    prims = scene.primitives
    rr = np.hypot(pts[:, 0] - 200.0, pts[:, 1] + 50.0)
    assert np.allclose(pts[lab == 0, 2], 0.0, atol=1e-9)  # table
    hub = prims[9]
    assert isinstance(hub, Cylinder)
    on_hub = lab == 9
    # hub: either its top annulus (z = 70, r in [10, 24]) or the inside of its bore
    top = np.isclose(pts[:, 2], 70.0, atol=1e-9)
    assert np.all(rr[on_hub & top] <= 24 + 1e-6) and np.all(rr[on_hub & top] >= 10 - 1e-6)
    # walls: the bore's (r = 10) and the outer one above the boss (r = 24, z >= 32)
    wall = on_hub & ~top
    bore = np.isclose(rr, 10.0, atol=1e-6)
    outer = np.isclose(rr, 24.0, atol=1e-6) & (pts[:, 2] >= 32.0 - 1e-6)
    assert np.all(bore[wall] | outer[wall])
    assert np.any(bore & wall) and np.any(outer & wall)  # both seen from the side
    web = prims[4]
    assert isinstance(web, Disc)
    assert np.allclose(pts[lab == 4, 2], 20.0, atol=1e-9)
    assert np.all(rr[lab == 4] >= 24 - 1e-6) and np.all(rr[lab == 4] <= 76 + 1e-6)


def test_texture_modulates_the_table_smoothly() -> None:
    tex = NoiseTexture.from_rng(np.random.default_rng(3), amplitude=0.2)
    assert tex.factor(np.array([0.0]), np.array([0.0]))[0] == pytest.approx(
        1 + 0.2 * tex.values[0, 0]
    )
    # periodic: one period (64 cells of 4 mm) further gives the same factor
    x = np.array([1.3, 77.7])
    assert np.allclose(tex.factor(x, x), tex.factor(x + 256.0, x - 512.0))
    scene = Scene((TablePlane(0.0, 0.5, texture=tex),), light_direction=(0, 0, 1))
    img = render(scene, CAM, Pose(0.0, 0.0, 1000.0)).intensity
    assert img.std() > 2.0  # visible pattern
    assert np.abs(np.diff(img, axis=1)).max() < 3.0  # but no edges (threshold 8)
