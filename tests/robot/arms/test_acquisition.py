"""Tests for robostereo.robot.arms.acquisition: the protocols, the simulated camera and
the thesis's acquisition program on the AdeptOne."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robostereo.errors import InputError, UnreachablePoseError
from robostereo.geometry.camera import SEED_CAMERA, Camera
from robostereo.geometry.scara_rectification import EpipolarGeometry
from robostereo.robot.arms.acquisition import (
    CameraDevice,
    Robot,
    SimulatedCamera,
    acquire_stereo_pair,
)
from robostereo.robot.arms.scara import AdeptOne, CameraMount

DEG = math.pi / 180.0
FOREARM_OFFSET = CameraMount(dx_mm=60.0, dy_mm=-45.0, z_mm=1040.0, yaw_offset=0.3)


class _RecordingCamera:
    """A CameraDevice that writes the true camera x into its image and records poses."""

    def __init__(self, robot: AdeptOne, camera: Camera) -> None:
        self.robot, self.camera, self.poses = robot, camera, []

    def grab(self) -> np.ndarray:
        pose = self.robot.actual_pose()
        self.poses.append(pose)
        return np.full((self.camera.height, self.camera.width), pose.x)


def test_protocols_are_satisfied():
    robot = AdeptOne()
    assert isinstance(robot, Robot)
    assert isinstance(_RecordingCamera(robot, SEED_CAMERA), CameraDevice)


@pytest.mark.parametrize("direction_deg", [0.0, 35.0, -120.0, None])
def test_acquisition_poses_are_d_apart_along_direction(direction_deg):
    robot = AdeptOne(mount=FOREARM_OFFSET)
    device = _RecordingCamera(robot, SEED_CAMERA)
    acq = acquire_stereo_pair(robot, device, SEED_CAMERA, center_xy=(480.0, -150.0),
                              baseline_mm=20.0, direction_deg=direction_deg)
    pl, pr = acq.pose_left, acq.pose_right
    if direction_deg is None:  # along the camera's x axis at the centre
        direction = robot.forward(robot.inverse(480.0, -150.0)).phi
    else:
        direction = direction_deg * DEG
    u = np.array([math.cos(direction), math.sin(direction)])
    assert pr.position[:2] - pl.position[:2] == pytest.approx(20.0 * u, abs=1e-9)
    assert (pl.position[:2] + pr.position[:2]) / 2 == pytest.approx([480.0, -150.0], abs=1e-9)
    # images were grabbed at the two viewpoints, in order
    assert [p.x for p in device.poses] == pytest.approx([pl.x, pr.x], abs=1e-9)
    assert acq.left_image[0, 0] == pytest.approx(pl.x) and not acq.left_image.flags.writeable
    assert acq.joints[0] != acq.joints[1]
    # forearm mount: the yaw follows theta1 + theta2 + offset, different at the two views
    for pose, j in zip((pl, pr), acq.joints, strict=True):
        assert pose.phi == pytest.approx(
            math.remainder(j.theta1 + j.theta2 + 0.3, 2 * math.pi), abs=1e-12)
    g = acq.epipolar
    assert g.alpha == pytest.approx(math.remainder(direction, 2 * math.pi), abs=1e-9)
    assert g.baseline_mm == pytest.approx(20.0, abs=1e-9)
    assert g.theta_l == pytest.approx(math.remainder(pl.phi - direction, 2 * math.pi), abs=1e-9)
    assert g.theta_r == pytest.approx(math.remainder(pr.phi - direction, 2 * math.pi), abs=1e-9)
    assert abs(g.theta_l - g.theta_r) > 0.01  # the two rolls differ (seed's theta_l, theta_r)


def test_acquisition_rectified_rows_agree_with_rolls():
    """Poses from the robot (different yaws): world points share rows after rectification."""
    robot = AdeptOne()
    acq = acquire_stereo_pair(robot, lambda r: _RecordingCamera(r, SEED_CAMERA), SEED_CAMERA,
                              center_xy=(350.0, 420.0), baseline_mm=20.0, direction_deg=80.0)
    g = acq.epipolar
    assert acq.pose_left.phi != pytest.approx(acq.pose_right.phi, abs=1e-3)
    rng = np.random.default_rng(0)
    P = np.column_stack([rng.uniform(300, 400, 100), rng.uniform(370, 470, 100),
                         rng.uniform(0, 50, 100)])
    yl = g.to_rectified(SEED_CAMERA.project(P, acq.pose_left)[0], "left")
    yr = g.to_rectified(SEED_CAMERA.project(P, acq.pose_right)[0], "right")
    assert np.abs(yl[:, 1] - yr[:, 1]).max() < 1e-9
    assert yl[:, 0] - yr[:, 0] == pytest.approx(SEED_CAMERA.fx * 20.0 / (1050.0 - P[:, 2]))


def test_acquisition_errors():
    robot = AdeptOne()

    class _Wrong:
        def grab(self) -> np.ndarray:
            return np.zeros((10, 10))

    with pytest.raises(InputError, match="grabbed image must have shape"):
        acquire_stereo_pair(robot, _Wrong(), SEED_CAMERA, center_xy=(500.0, 0.0))
    with pytest.raises(InputError, match="baseline_mm"):
        acquire_stereo_pair(robot, _Wrong(), SEED_CAMERA, center_xy=(500.0, 0.0),
                            baseline_mm=0.0)
    with pytest.raises(UnreachablePoseError, match="annulus"):
        acquire_stereo_pair(robot, _RecordingCamera(robot, SEED_CAMERA), SEED_CAMERA,
                            center_xy=(795.0, 0.0), baseline_mm=20.0, direction_deg=0.0)


def test_simulated_camera_adapter_uses_actual_pose():
    rng = np.random.default_rng(4)
    robot = AdeptOne(repeatability_mm=0.025, rng=rng)
    calls = []

    def fake_render(scene, camera, pose, *, rng=None, gain=1.0):
        calls.append((scene, pose, rng, gain))
        return np.full((camera.height, camera.width), 7, dtype=np.uint8)

    cam = SimulatedCamera("scene", SEED_CAMERA, robot, rng, fake_render, {"gain": 2.0})
    robot.move_camera(500.0, 50.0)
    img = cam.grab()
    assert img.shape == (481, 509) and img[0, 0] == 7
    scene, pose, got_rng, gain = calls[0]
    assert scene == "scene" and got_rng is rng and gain == 2.0
    assert pose == robot.actual_pose() and pose != robot.reported_pose()
    assert cam.last_pose == pose
    with pytest.raises(InputError, match="render_fn"):
        SimulatedCamera("scene", SEED_CAMERA, robot, rng, "render")  # type: ignore[arg-type]


def test_simulated_acquisition_block_disparity():
    """End to end with the simulator: the block's top edges shift by fx D / 1000 px."""
    sim = pytest.importorskip("robostereo.simulation")
    centre = (500.0, 100.0)
    scene = sim.seed_block_scene(center_xy=centre, offset_xy=(0.0, 0.0))
    robot = AdeptOne()  # camera 1050 mm above the table: block top 1000 mm below

    def render(scene, camera, pose, *, rng=None):
        return sim.render(scene, camera, pose, supersample=3, blur_sigma_px=0.6, rng=rng)

    device = SimulatedCamera(scene, SEED_CAMERA, robot, None, render)
    acq = acquire_stereo_pair(robot, device, SEED_CAMERA, center_xy=centre, baseline_mm=20.0)
    assert float(device.last_rendering.depth[240, 254]) == pytest.approx(1000.0, abs=0.5)
    g: EpipolarGeometry = acq.epipolar
    left = g.rectify(acq.left_image, "left", interpolation="linear")
    right = g.rectify(acq.right_image, "right", interpolation="linear")
    # the row through the block's top centre, in the rectified images
    row = round(float(SEED_CAMERA.project([[*centre, 50.0]], g.virtual_pose("left"))[0][0, 1]))
    expect = SEED_CAMERA.fx * 20.0 / 1000.0  # 29.07 px

    def crossings(profile: np.ndarray) -> np.ndarray:
        v = np.nan_to_num(profile, nan=float(np.nanmin(profile)))
        level = (v.max() + v.min()) / 2
        s = v - level
        k = np.flatnonzero(np.sign(s[:-1]) != np.sign(s[1:]))
        return k + s[k] / (s[k] - s[k + 1])

    disparities = []
    for r in range(row - 40, row + 41, 8):
        xl, xr = crossings(left[r]), crossings(right[r])
        assert len(xl) == 2 and len(xr) == 2
        disparities.extend(xl - xr)
    # rendering samples 3 x 3 rays per pixel and 7-bit grey levels: a few 0.1 px of jitter
    assert np.abs(np.asarray(disparities) - expect).max() < 0.4
    assert np.median(disparities) == pytest.approx(expect, abs=0.1)
    # and the same rows show the same content (up to the shift)
    shifted = np.roll(right, round(expect), axis=1)
    ok = np.isfinite(left) & np.isfinite(shifted)
    near = np.abs(left - shifted)[ok]
    assert np.median(near) < 1.0
