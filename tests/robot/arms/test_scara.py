"""Tests for robostereo.robot.arms.scara: AdeptOne kinematics, limits, mounts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robostereo.errors import InputError, UnreachablePoseError
from robostereo.geometry.poses import Pose
from robostereo.robot.arms.scara import (
    ADEPTONE_LIMITS,
    AdeptOne,
    CameraMount,
    Joints,
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


def test_pose_type():
    assert isinstance(AdeptOne().reported_pose(), Pose)
