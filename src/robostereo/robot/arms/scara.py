"""The robot that carries the camera: an AdeptOne SCARA arm (thesis 4.1, figure 4-2).

The thesis's camera rides on the distal end of the AdeptOne's forearm and is moved by a
VAL-II program to two viewpoints ``D`` apart on a baseline above the object, where an
image is grabbed at each (thesis 4.1, 4.2.1).  This module gives the arm:

* :class:`AdeptOne`, the 4-axis SCARA with forward and inverse kinematics (both elbow
  solutions), joint limits, a forearm or a flange camera mount and optional
  repeatability noise on the reported pose;
* its :class:`Joints`, :class:`JointLimits` (:data:`ADEPTONE_LIMITS`) and
  :class:`CameraMount`.

The acquisition program that moves it and the camera it carries are in
:mod:`robostereo.robot.arms.acquisition`.

Frames: the robot's base frame is the world frame (millimetres, Z up, joint 1 axis
on the Z axis).  Angles are radians in the API.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import (
    InputError,
    UnreachablePoseError,
    require_finite,
    require_nonnegative,
    require_positive,
)
from robostereo.geometry.camera import wrap_angle
from robostereo.geometry.poses import Pose

__all__ = [
    "ADEPTONE_LIMITS",
    "ADEPTONE_LINK1_MM",
    "ADEPTONE_LINK2_MM",
    "ADEPTONE_REPEATABILITY_MM",
    "AdeptOne",
    "CameraMount",
    "Elbow",
    "JointLimits",
    "Joints",
]

Elbow = Literal["righty", "lefty", "auto"]

ADEPTONE_LINK1_MM = 425.0
"""Inner link (joint 1 to joint 2 axis), millimetres."""
ADEPTONE_LINK2_MM = 375.0
"""Outer link (joint 2 to joint 3/4 axis), millimetres."""
ADEPTONE_REPEATABILITY_MM = 0.025
"""Published X-Y repeatability of the AdeptOne, +- millimetres."""

_TOL = 1e-9


@dataclass(frozen=True)
class Joints:
    """Joint values of a 4-axis SCARA.

    Parameters
    ----------
    theta1, theta2 : float
        Revolute joints about vertical axes (shoulder, elbow), radians,
        counter-clockwise seen from above; ``theta2 = 0`` is the stretched arm.
    d3 : float
        Prismatic vertical joint, millimetres down from the top of its stroke.
    theta4 : float
        Roll of the tool flange about the joint-3 axis, radians.
    """

    theta1: float = 0.0
    theta2: float = 0.0
    d3: float = 0.0
    theta4: float = 0.0

    def __post_init__(self) -> None:
        require_finite("joints", [self.theta1, self.theta2, self.d3, self.theta4])

    def degrees(self) -> tuple[float, float, float, float]:
        """``(theta1 deg, theta2 deg, d3 mm, theta4 deg)`` for display."""
        return (
            math.degrees(self.theta1),
            math.degrees(self.theta2),
            self.d3,
            math.degrees(self.theta4),
        )


@dataclass(frozen=True)
class JointLimits:
    """Joint ranges ``(low, high)``: radians for the revolute joints, mm for ``d3``."""

    theta1: tuple[float, float] = (math.radians(-150.0), math.radians(150.0))
    theta2: tuple[float, float] = (math.radians(-147.0), math.radians(147.0))
    d3: tuple[float, float] = (0.0, 195.0)
    theta4: tuple[float, float] = (math.radians(-277.0), math.radians(277.0))

    def __post_init__(self) -> None:
        for name in ("theta1", "theta2", "d3", "theta4"):
            lo, hi = getattr(self, name)
            require_finite(f"limits.{name}", [lo, hi])
            if not lo <= hi:
                raise InputError(f"limits.{name} must be (low, high) with low <= high")

    def violation(self, joints: Joints) -> str | None:
        """A one-line description of the first limit `joints` violate, or None."""
        for i, name in enumerate(("theta1", "theta2", "d3", "theta4"), start=1):
            lo, hi = getattr(self, name)
            v = getattr(joints, name)
            if not lo - _TOL <= v <= hi + _TOL:
                if name == "d3":
                    return f"joint 3 limit: d3 = {v:.3f} mm outside [{lo:g}, {hi:g}] mm"
                return (
                    f"joint {i} limit: {name} = {math.degrees(v):.2f} deg outside "
                    f"[{math.degrees(lo):.0f}, {math.degrees(hi):.0f}] deg"
                )
        return None


ADEPTONE_LIMITS = JointLimits()
"""AdeptOne joint ranges as published (to the best of our knowledge): J1 +-150 deg,
J2 +-147 deg, J3 0..195 mm stroke, J4 +-277 deg."""


@dataclass(frozen=True)
class CameraMount:
    """Where the camera sits on the arm.

    Parameters
    ----------
    kind : {'forearm', 'flange'}
        ``'forearm'`` (the thesis: on the distal end of link 2): the camera yaw is
        ``theta1 + theta2 + yaw_offset`` and its height is fixed.  ``'flange'``: on the
        joint-4 flange; joint 3 sets the height and joint 4 the yaw
        ``theta1 + theta2 + theta4 + yaw_offset``.
    dx_mm, dy_mm : float
        Optical centre in the frame of the forearm (x along link 2, away from the
        elbow; y 90 deg counter-clockwise), from the joint-3 axis, millimetres.  For the
        flange mount the frame turns with joint 4.
    z_mm : float
        Height of the optical centre: fixed for the forearm mount; at ``d3 = 0`` (top
        of the stroke) for the flange mount, which gives ``z = z_mm - d3``.
        Default 1050 mm: the table (z = 0) is 1050 mm below the camera and the top of
        the thesis's 50-mm block 1000 mm below it, as in the thesis's first data set.
    yaw_offset : float
        Camera yaw relative to link 2 (forearm) or to the flange (flange), radians.
    """

    kind: Literal["forearm", "flange"] = "forearm"
    dx_mm: float = 0.0
    dy_mm: float = 0.0
    z_mm: float = 1050.0
    yaw_offset: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in ("forearm", "flange"):
            raise InputError(f"mount kind must be 'forearm' or 'flange', got {self.kind!r}")
        require_finite("mount", [self.dx_mm, self.dy_mm, self.z_mm, self.yaw_offset])


def _rot2(a: float) -> NDArray[np.float64]:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


class AdeptOne:
    """AdeptOne 4-axis SCARA carrying a camera (thesis 4.1).

    Parameters
    ----------
    mount : CameraMount
        Where the camera is; default: on the forearm, optical centre on the joint-3
        axis at 1050 mm, yaw along link 2.
    link1_mm, link2_mm : float
        Link lengths, default 425 and 375 mm (reach 800 mm).
    limits : JointLimits
        Joint ranges, default :data:`ADEPTONE_LIMITS`.
    repeatability_mm : float
        If > 0, the reported optical centre differs from the true one by an error drawn
        from `rng` at every move: x and y each normal with standard deviation
        ``repeatability_mm / 3``, clipped to ``+-repeatability_mm``.  The AdeptOne's
        published value is :data:`ADEPTONE_REPEATABILITY_MM` (0.025 mm).
    yaw_repeatability : float
        The same for the reported yaw, radians.
    rng : numpy.random.Generator or None
        Source of the repeatability errors (required when one is > 0).
    joints : Joints
        Initial joint values (default all zero: the stretched arm along +X).

    Notes
    -----
    Forward kinematics: joint-3 axis at ``w = L1 e(t1) + L2 e(t1 + t2)`` with
    ``e(a) = (cos a, sin a)``; camera at ``w + Rz(psi) (dx, dy)`` with ``psi = t1 + t2``
    (forearm) or ``t1 + t2 + t4`` (flange); yaw ``psi + yaw_offset``.

    Inverse kinematics (forearm): the offset folds into an effective link 2,
    ``L2' = |(L2 + dx, dy)|`` at angle ``delta = atan2(dy, L2 + dx)``, so that the camera
    is at ``L1 e(t1) + L2' e(t1 + q)``, ``q = t2 + delta``.  Then
    ``cos q = (r^2 - L1^2 - L2'^2) / (2 L1 L2')``, ``q = +acos`` for ``'righty'`` and
    ``-acos`` for ``'lefty'``, ``t1 = atan2(y, x) - atan2(L2' sin q, L1 + L2' cos q)``.
    Flange: the wrist is ``(x, y) - Rz(psi) (dx, dy)`` for the requested yaw, solved
    with ``L1, L2``; ``t4 = psi - t1 - t2`` (the turn within the J4 range nearest to
    the current one); ``d3 = z_mm - z``.

    Elbow: ``'righty'`` is ``q > 0`` (elbow turning counter-clockwise, like a right arm
    seen from above), ``'lefty'`` ``q < 0``; ``'auto'`` keeps the current elbow if it
    reaches and takes the other otherwise.

    References
    ----------
    Seed 4.1 (AdeptOne, camera on the distal end of the forearm, 2-DOF horizontal
    camera motion) and figure 4-2.

    Examples
    --------
    Hand check: ``cos q = (500^2 + 100^2 - 425^2 - 375^2) / (2 * 425 * 375) = -0.19216``,
    ``q = 101.079 deg``, ``t1 = atan2(100, 500) - atan2(368.05, 352.94) = -34.888 deg``.

    >>> robot = AdeptOne()
    >>> pose = robot.move_camera(500.0, 100.0)
    >>> round(pose.x, 9), round(pose.y, 9), pose.z, round(math.degrees(pose.phi), 3)
    (500.0, 100.0, 1050.0, 66.191)
    >>> [round(v, 3) for v in robot.joints.degrees()]
    [-34.888, 101.079, 0.0, 0.0]
    >>> robot.move_camera(900.0, 0.0)
    Traceback (most recent call last):
    ...
    robostereo.errors.UnreachablePoseError: AdeptOne cannot reach camera (x, y) = ... mm: \
    outside the annulus 50.0 <= r <= 800.0 mm (r = 900.000 mm)
    """

    def __init__(
        self,
        *,
        mount: CameraMount | None = None,
        link1_mm: float = ADEPTONE_LINK1_MM,
        link2_mm: float = ADEPTONE_LINK2_MM,
        limits: JointLimits = ADEPTONE_LIMITS,
        repeatability_mm: float = 0.0,
        yaw_repeatability: float = 0.0,
        rng: np.random.Generator | None = None,
        joints: Joints | None = None,
    ) -> None:
        require_positive("link1_mm", link1_mm)
        require_positive("link2_mm", link2_mm)
        require_nonnegative("repeatability_mm", repeatability_mm)
        require_nonnegative("yaw_repeatability", yaw_repeatability)
        if (repeatability_mm > 0 or yaw_repeatability > 0) and not isinstance(
            rng, np.random.Generator
        ):
            raise InputError("rng must be a numpy.random.Generator when repeatability > 0")
        self.mount = CameraMount() if mount is None else mount
        self.link1_mm = float(link1_mm)
        self.link2_mm = float(link2_mm)
        self.limits = limits
        self.repeatability_mm = float(repeatability_mm)
        self.yaw_repeatability = float(yaw_repeatability)
        self._rng = rng
        start = Joints() if joints is None else joints
        bad = limits.violation(start)
        if bad:
            raise UnreachablePoseError(f"initial joints: {bad}")
        self._joints = start
        self._reported = self.forward(start)

    # ------------------------------------------------------------------ kinematics

    def wrist(self, joints: Joints) -> NDArray[np.float64]:
        """``(x, y)`` of the joint-3/4 axis for `joints`, shape ``(2,)``, millimetres."""
        t1, t12 = joints.theta1, joints.theta1 + joints.theta2
        return np.array([
            self.link1_mm * math.cos(t1) + self.link2_mm * math.cos(t12),
            self.link1_mm * math.sin(t1) + self.link2_mm * math.sin(t12),
        ])

    def forward(self, joints: Joints) -> Pose:
        """Camera pose (optical centre and yaw) for `joints` (no limit check).

        >>> AdeptOne().forward(Joints(0.0, math.pi / 2))
        Pose(x=425.0, y=375.0, z=1050.0, phi=1.5707963267948966)
        """
        m = self.mount
        psi = joints.theta1 + joints.theta2
        z = m.z_mm
        if m.kind == "flange":
            psi += joints.theta4
            z = m.z_mm - joints.d3
        xy = self.wrist(joints) + _rot2(psi) @ np.array([m.dx_mm, m.dy_mm])
        return Pose(float(xy[0]), float(xy[1]), float(z), wrap_angle(psi + m.yaw_offset))

    @property
    def annulus_mm(self) -> tuple[float, float]:
        """``(r_min, r_max)`` of the camera's horizontal reach, ignoring joint limits.

        For the flange mount this is the wrist's reach (the camera is offset from it).
        """
        l2 = self._effective_link2()[0] if self.mount.kind == "forearm" else self.link2_mm
        return abs(self.link1_mm - l2), self.link1_mm + l2

    def _effective_link2(self) -> tuple[float, float]:
        m = self.mount
        a, b = self.link2_mm + m.dx_mm, m.dy_mm
        return math.hypot(a, b), math.atan2(b, a)

    def _two_link(
        self, x: float, y: float, l2: float, target: str
    ) -> dict[str, tuple[float, float]]:
        """Both ``(theta1, q)`` solutions of a 2-link arm L1, l2 reaching ``(x, y)``."""
        l1 = self.link1_mm
        r = math.hypot(x, y)
        r_min, r_max = abs(l1 - l2), l1 + l2
        if r > r_max * (1 + 1e-12) or r < r_min * (1 - 1e-12) or l2 == 0:
            raise UnreachablePoseError(
                f"AdeptOne cannot reach {target}: outside the annulus "
                f"{r_min:.1f} <= r <= {r_max:.1f} mm (r = {r:.3f} mm)"
            )
        c = (r * r - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
        c = min(1.0, max(-1.0, c))
        s = math.sqrt(max(0.0, 1.0 - c * c))
        out = {}
        for elbow, sign in (("righty", 1.0), ("lefty", -1.0)):
            q = math.atan2(sign * s, c)
            t1 = math.atan2(y, x) - math.atan2(l2 * math.sin(q), l1 + l2 * math.cos(q))
            out[elbow] = (wrap_angle(t1), q)
        return out

    def _current_elbow(self) -> str:
        q = self._joints.theta2
        if self.mount.kind == "forearm":
            q += self._effective_link2()[1]
        return "righty" if math.sin(q) >= 0 else "lefty"

    def inverse(
        self,
        x: float,
        y: float,
        *,
        phi: float | None = None,
        z: float | None = None,
        elbow: Elbow = "righty",
    ) -> Joints:
        """Joint values that put the camera's optical centre at ``(x, y)``.

        Parameters
        ----------
        x, y : float
            Target optical centre in the world, millimetres.
        phi : float or None
            Camera yaw, radians.  Flange mount: None keeps the current yaw.  Forearm
            mount: the yaw follows the arm, so `phi` is only accepted if it is the yaw
            the arm takes at ``(x, y)`` with this elbow (to 1e-9 rad).
        z : float or None
            Optical-centre height; flange mount only (None keeps ``d3``); the forearm
            mount accepts only its fixed height.
        elbow : {'righty', 'lefty', 'auto'}
            Elbow solution (see the class notes).

        Returns
        -------
        Joints

        Raises
        ------
        UnreachablePoseError
            One line naming the target and why: outside the annulus, a joint limit, or a
            yaw / height the mount cannot give.
        """
        require_finite("camera target (x, y)", [x, y])
        if elbow not in ("righty", "lefty", "auto"):
            raise InputError(f"elbow must be 'righty', 'lefty' or 'auto', got {elbow!r}")
        target = f"camera (x, y) = ({x:.3f}, {y:.3f}) mm"
        order = [elbow] if elbow != "auto" else [self._current_elbow()]
        if elbow == "auto":
            order.append("lefty" if order[0] == "righty" else "righty")
        m = self.mount
        cur = self._joints
        solutions: list[tuple[str, Joints]] = []
        if m.kind == "forearm":
            if z is not None and abs(z - m.z_mm) > _TOL:
                raise UnreachablePoseError(
                    f"AdeptOne cannot reach {target} at z = {z:.3f} mm: the forearm-mounted "
                    f"camera stays at z = {m.z_mm:.3f} mm"
                )
            l2e, delta = self._effective_link2()
            sols = self._two_link(x, y, l2e, target)
            for e in order:
                t1, q = sols[e]
                solutions.append((e, Joints(t1, wrap_angle(q - delta), cur.d3, cur.theta4)))
        else:
            psi = (self.forward(cur).phi if phi is None else phi) - m.yaw_offset
            require_finite("phi", psi)
            wx, wy = np.array([x, y]) - _rot2(psi) @ np.array([m.dx_mm, m.dy_mm])
            d3 = cur.d3 if z is None else m.z_mm - z
            require_finite("z", d3)
            sols = self._two_link(float(wx), float(wy), self.link2_mm, target)
            for e in order:
                t1, q = sols[e]
                t2 = wrap_angle(q)
                solutions.append((e, Joints(t1, t2, d3, self._theta4(psi - t1 - t2))))
        reasons = []
        for e, j in solutions:
            bad = self.limits.violation(j)
            if bad is None and m.kind == "forearm" and phi is not None:
                got = self.forward(j).phi
                if abs(wrap_angle(got - phi)) > _TOL:
                    bad = (
                        f"the forearm-mounted camera's yaw there is {math.degrees(got):.3f} deg, "
                        f"not phi = {math.degrees(phi):.3f} deg"
                    )
            if bad is None:
                return j
            reasons.append(f"{bad} ({e})")
        raise UnreachablePoseError(f"AdeptOne cannot reach {target}: " + "; ".join(reasons))

    def _theta4(self, t4: float) -> float:
        """The value ``t4 + 2 pi k`` inside the J4 range nearest the current theta4."""
        lo, hi = self.limits.theta4
        cur = self._joints.theta4
        k0 = round((cur - t4) / (2 * math.pi))
        cands = [t4 + 2 * math.pi * k for k in range(k0 - 2, k0 + 3)]
        inside = [c for c in cands if lo - _TOL <= c <= hi + _TOL]
        return min(inside or cands, key=lambda c: abs(c - cur))

    # ------------------------------------------------------------------ motion

    @property
    def joints(self) -> Joints:
        """Current joint values."""
        return self._joints

    def actual_pose(self) -> Pose:
        """Where the camera really is: forward kinematics of the current joints."""
        return self.forward(self._joints)

    def reported_pose(self) -> Pose:
        """The pose the robot reports: the actual pose plus its repeatability error."""
        return self._reported

    def move_joints(self, joints: Joints) -> Pose:
        """Move to `joints` (limits checked); return the reported camera pose."""
        bad = self.limits.violation(joints)
        if bad:
            raise UnreachablePoseError(f"AdeptOne cannot move to joints {joints}: {bad}")
        self._joints = joints
        self._reported = self._report(self.forward(joints))
        return self._reported

    def move_camera(
        self,
        x: float,
        y: float,
        *,
        phi: float | None = None,
        z: float | None = None,
        elbow: Elbow = "righty",
    ) -> Pose:
        """Move the camera's optical centre to ``(x, y)`` (see :meth:`inverse`).

        Returns
        -------
        Pose
            The reached pose as the robot reports it.
        """
        return self.move_joints(self.inverse(x, y, phi=phi, z=z, elbow=elbow))

    def _report(self, pose: Pose) -> Pose:
        if self.repeatability_mm == 0 and self.yaw_repeatability == 0:
            return pose
        assert self._rng is not None
        r, ry = self.repeatability_mm, self.yaw_repeatability
        ex, ey = np.clip(self._rng.normal(0.0, r / 3.0, size=2), -r, r) if r > 0 else (0, 0)
        ephi = float(np.clip(self._rng.normal(0.0, ry / 3.0), -ry, ry)) if ry > 0 else 0.0
        return Pose(pose.x + float(ex), pose.y + float(ey), pose.z, wrap_angle(pose.phi + ephi))
