"""Tests for robostereo.robot.arms.scara: AdeptOne kinematics, limits, acquisition."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robostereo.errors import InputError, UnreachablePoseError
from robostereo.geometry.camera import SEED_CAMERA, Camera
from robostereo.geometry.poses import Pose
from robostereo.geometry.scara_rectification import EpipolarGeometry
from robostereo.robot.arms.scara import (
    ADEPTONE_LIMITS,
    AdeptOne,
    CameraDevice,
    CameraMount,
    Joints,
    Robot,
    SimulatedCamera,
    acquire_stereo_pair,
)

DEG = math.pi / 180.0
MOUNTS = {
    "forearm-on-axis": CameraMount(),
    "forearm-offset": CameraMount(dx_mm=60.0, dy_mm=-45.0, z_mm=1040.0, yaw_offset=0.3),
    "flange-offset": CameraMount(kind="flange", dx_mm=30.0, dy_mm=25.0, z_mm=1100.0,
                                 yaw_offset=-0.2),
}


def _random_joints(rng: np.random.Generator, n: int) -> list[Joints]:
    lim = ADEPTONE_LIMITS
    return [
        Joints(
            rng.uniform(*lim.theta1), rng.uniform(*lim.theta2), rng.uniform(*lim.d3),
            rng.uniform(*lim.theta4),
        )
        for _ in range(n)
    ]


def _elbow_of(robot: AdeptOne, j: Joints) -> str:
    q = j.theta2
    if robot.mount.kind == "forearm":
        m = robot.mount
        q += math.atan2(m.dy_mm, robot.link2_mm + m.dx_mm)
    return "righty" if math.sin(q) >= 0 else "lefty"


# ---------------------------------------------------------------- forward kinematics


def test_forward_known_values():
    robot = AdeptOne()
    p = robot.forward(Joints(0.0, 0.0))
    assert (p.x, p.y, p.z, p.phi) == pytest.approx((800.0, 0.0, 1050.0, 0.0))
    p = robot.forward(Joints(90 * DEG, -90 * DEG))
    assert (p.x, p.y, p.phi) == pytest.approx((375.0, 425.0, 0.0), abs=1e-12)
    # forearm offset: camera 100 mm further along link 2 and 50 mm to its left
    robot = AdeptOne(mount=CameraMount(dx_mm=100.0, dy_mm=50.0, yaw_offset=0.5))
    p = robot.forward(Joints(0.0, 90 * DEG))
    assert (p.x, p.y, p.phi) == pytest.approx((425.0 - 50.0, 375.0 + 100.0, 90 * DEG + 0.5))
    # flange mount: J3 lowers the camera, J4 turns it
    robot = AdeptOne(mount=CameraMount(kind="flange", dx_mm=10.0, z_mm=1100.0))
    p = robot.forward(Joints(0.0, 0.0, 120.0, 90 * DEG))
    assert (p.x, p.y, p.z, p.phi) == pytest.approx((800.0, 10.0, 980.0, 90 * DEG))


# ---------------------------------------------------------------- inverse kinematics


@pytest.mark.parametrize("mount", list(MOUNTS), ids=list(MOUNTS))
def test_inverse_forward_round_trip_from_joints(mount):
    """Random joints in the limits -> FK -> IK (same elbow) gives the joints and pose back."""
    rng = np.random.default_rng(11)
    robot = AdeptOne(mount=MOUNTS[mount])
    worst_mm = worst_rad = 0.0
    n = 0
    for j in _random_joints(rng, 1500):
        # stay off the stretched-arm singularity, where both elbows coincide
        q = j.theta2
        if robot.mount.kind == "forearm":
            q += math.atan2(robot.mount.dy_mm, 375.0 + robot.mount.dx_mm)
        if abs(math.sin(q)) < 1e-3:
            continue
        target = robot.forward(j)
        robot.move_joints(Joints(0.0, 0.0, j.d3, j.theta4))  # d3 kept, theta4 nearest current
        if robot.mount.kind == "forearm":
            sol = robot.inverse(target.x, target.y, elbow=_elbow_of(robot, j))
        else:
            sol = robot.inverse(target.x, target.y, phi=target.phi, z=target.z,
                                elbow=_elbow_of(robot, j))
        back = robot.forward(sol)
        worst_mm = max(worst_mm, float(np.abs(back.position - target.position).max()))
        worst_rad = max(worst_rad, abs(math.remainder(back.phi - target.phi, 2 * math.pi)))
        assert sol.theta1 == pytest.approx(j.theta1, abs=1e-7)
        assert sol.theta2 == pytest.approx(j.theta2, abs=1e-7)
        assert sol.d3 == pytest.approx(j.d3, abs=1e-9)
        assert sol.theta4 == pytest.approx(j.theta4, abs=1e-7)
        n += 1
    assert n > 1400
    assert worst_mm < 1e-9 and worst_rad < 1e-9


@pytest.mark.parametrize("mount", list(MOUNTS), ids=list(MOUNTS))
def test_inverse_forward_round_trip_over_workspace(mount):
    """Random (x, y) targets over the work area, both elbows: FK(IK(target)) = target."""
    rng = np.random.default_rng(5)
    robot = AdeptOne(mount=MOUNTS[mount])
    r = np.sqrt(rng.uniform(0.0, 850.0**2, 3000))
    a = rng.uniform(-math.pi, math.pi, 3000)
    reached = {"righty": 0, "lefty": 0}
    worst = 0.0
    for x, y in zip(r * np.cos(a), r * np.sin(a), strict=True):
        for elbow in ("righty", "lefty"):
            try:
                j = robot.inverse(float(x), float(y), elbow=elbow)
            except UnreachablePoseError:
                continue
            assert ADEPTONE_LIMITS.violation(j) is None
            p = robot.forward(j)
            worst = max(worst, abs(p.x - x), abs(p.y - y))
            reached[elbow] += 1
    assert worst < 1e-9
    assert min(reached.values()) > 1000


def test_two_elbows_differ_and_auto_keeps_current():
    robot = AdeptOne()
    jr = robot.inverse(450.0, 200.0, elbow="righty")
    jl = robot.inverse(450.0, 200.0, elbow="lefty")
    assert jr.theta2 > 0 > jl.theta2
    assert jr.theta2 == pytest.approx(-jl.theta2)  # mirror solutions of the 2-link arm
    pr, pl = robot.forward(jr), robot.forward(jl)
    assert (pr.x, pr.y) == pytest.approx((pl.x, pl.y))
    assert abs(pr.phi - pl.phi) > 0.5  # the camera yaw depends on the elbow
    robot.move_camera(450.0, 200.0, elbow="lefty")
    robot.move_camera(480.0, 150.0, elbow="auto")
    assert robot.joints.theta2 < 0
    with pytest.raises(InputError, match="elbow"):
        robot.inverse(450.0, 200.0, elbow="up")  # type: ignore[arg-type]


# ---------------------------------------------------------------- unreachable


@pytest.mark.parametrize(
    ("xy", "elbow", "reason"),
    [
        ((900.0, 0.0), "righty", "outside the annulus"),  # too far
        ((20.0, 10.0), "righty", "outside the annulus"),  # too near (r < 425 - 375)
        ((150.0, 0.0), "righty", "joint 2 limit"),  # in the annulus, needs theta2 > 147
        ((150.0, 0.0), "auto", "joint 2 limit"),
        ((-780.0, 0.0), "lefty", "joint 1 limit"),  # behind the base
        ((-780.0, 0.0), "righty", "joint 1 limit"),
    ],
)
def test_unreachable_poses_rejected(xy, elbow, reason):
    robot = AdeptOne()
    before = robot.joints
    with pytest.raises(UnreachablePoseError) as info:
        robot.move_camera(*xy, elbow=elbow)
    msg = str(info.value)
    assert reason in msg and f"({xy[0]:.3f}, {xy[1]:.3f})" in msg and "\n" not in msg
    assert robot.joints == before  # the robot did not move


def test_inner_limit_radius_from_joint2():
    """With |theta2| <= 147 deg the inner radius is |L1 + L2 e(147 deg)| = 232.2 mm."""
    robot = AdeptOne()
    r_in = math.sqrt(425**2 + 375**2 + 2 * 425 * 375 * math.cos(147 * DEG))
    assert r_in == pytest.approx(232.2, abs=0.05)
    robot.inverse(r_in + 0.01, 0.0)
    with pytest.raises(UnreachablePoseError, match="joint 2 limit"):
        robot.inverse(r_in - 0.01, 0.0)
    assert robot.annulus_mm == (50.0, 800.0)


def test_mount_constraints():
    robot = AdeptOne()
    with pytest.raises(UnreachablePoseError, match="stays at z = 1050"):
        robot.move_camera(500.0, 0.0, z=900.0)
    phi = robot.inverse(500.0, 0.0)
    ok = robot.forward(phi).phi
    robot.move_camera(500.0, 0.0, phi=ok)  # the yaw it takes anyway: accepted
    with pytest.raises(UnreachablePoseError, match="yaw there is"):
        robot.move_camera(500.0, 0.0, phi=ok + 0.1)
    flange = AdeptOne(mount=CameraMount(kind="flange", z_mm=1100.0, dx_mm=20.0))
    with pytest.raises(UnreachablePoseError, match="joint 3 limit"):
        flange.move_camera(500.0, 0.0, z=800.0)  # needs d3 = 300 > 195
    p = flange.move_camera(500.0, 0.0, z=1000.0, phi=2.0)
    assert (p.x, p.y, p.z, p.phi) == pytest.approx((500.0, 0.0, 1000.0, 2.0))
    assert flange.joints.d3 == pytest.approx(100.0)
    # phi = None keeps the camera's yaw (for a stereo pair with equal yaw)
    p2 = flange.move_camera(520.0, 30.0)
    assert p2.phi == pytest.approx(2.0) and p2.z == pytest.approx(1000.0)
    with pytest.raises(UnreachablePoseError, match="initial joints"):
        AdeptOne(joints=Joints(theta1=3.0))


# ---------------------------------------------------------------- repeatability


def test_repeatability_noise_on_reported_pose():
    rng = np.random.default_rng(2)
    robot = AdeptOne(repeatability_mm=0.025, rng=rng)
    errs = []
    for x in np.linspace(400.0, 600.0, 400):
        rep = robot.move_camera(float(x), 100.0)
        act = robot.actual_pose()
        assert (act.x, act.y) == pytest.approx((x, 100.0), abs=1e-9)
        assert robot.reported_pose() == rep
        errs.append([rep.x - act.x, rep.y - act.y])
    e = np.asarray(errs)
    assert np.abs(e).max() <= 0.025 + 1e-12
    assert e.std() == pytest.approx(0.025 / 3, rel=0.15)
    assert abs(e.mean()) < 0.002
    with pytest.raises(InputError, match="rng"):
        AdeptOne(repeatability_mm=0.025)
    exact = AdeptOne()
    assert exact.move_camera(500.0, 100.0) == exact.actual_pose()


# ---------------------------------------------------------------- acquisition


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
    robot = AdeptOne(mount=MOUNTS["forearm-offset"])
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


def test_pose_type():
    assert isinstance(AdeptOne().reported_pose(), Pose)
