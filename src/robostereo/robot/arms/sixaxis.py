"""A six-axis arm (UR5-like) carrying a wrist camera: kinematics and a simulated camera.

The thesis's SCARA keeps the camera looking down (thesis 4.1).  A six-axis arm points it
anywhere; :class:`SixAxisArm` is a standard Denavit-Hartenberg model with the UR5's
published dimensions and joint ranges, forward kinematics ``T_base_flange(q)`` and
a numerical inverse (damped least squares from several starts, within the limits).
:data:`WRIST_CAMERA` and :data:`WRIST_HAND_EYE` are the simulated wrist camera (with
lens distortion) and its true pose on the flange.

Frames: the base frame is the world frame (millimetres, Z up, joint 1 on the Z axis,
the base on the table ``z = 0``); angles are radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import least_squares

from robostereo.errors import InputError, UnreachablePoseError
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3

__all__ = [
    "UR5_DH",
    "UR5_LIMITS",
    "WRIST_CAMERA",
    "WRIST_HAND_EYE",
    "DHLink",
    "SixAxisArm",
]


@dataclass(frozen=True)
class DHLink:
    """One link in standard DH: ``Rz(theta + offset) Tz(d) Tx(a) Rx(alpha)``.

    ``d``, ``a`` in millimetres; ``alpha``, ``offset`` in radians.
    """

    d: float
    a: float
    alpha: float
    offset: float = 0.0


UR5_DH: tuple[DHLink, ...] = (
    DHLink(89.159, 0.0, math.pi / 2),
    DHLink(0.0, -425.0, 0.0),
    DHLink(0.0, -392.25, 0.0),
    DHLink(109.15, 0.0, math.pi / 2),
    DHLink(94.65, 0.0, -math.pi / 2),
    DHLink(82.3, 0.0, 0.0),
)
"""UR5 (Universal Robots' published DH parameters), millimetres; reach about 850 mm."""

UR5_LIMITS: tuple[tuple[float, float], ...] = (
    (-2 * math.pi, 2 * math.pi),
    (-2 * math.pi, 2 * math.pi),
    (-math.pi, math.pi),  # the elbow cannot pass through the upper arm
    (-2 * math.pi, 2 * math.pi),
    (-2 * math.pi, 2 * math.pi),
    (-2 * math.pi, 2 * math.pi),
)
"""Joint ranges, radians: +-360 deg, the elbow +-180 deg (self-collision)."""

WRIST_CAMERA = Camera(
    focal_length_mm=6.0, pixel_pitch_mm=(0.0048, 0.0048), image_size=(640, 480),
    principal_point=(322.5, 236.0), grey_levels=256,
    distortion=(-0.12, 0.03, 0.0005, -0.0003, 0.0),
)
"""The simulated wrist camera: 640 x 480 px, 6 mm lens, 4.8 um pixels (fx = 1250 px,
a 29 x 22 degree view), 8-bit grey, barrel distortion (k1 = -0.12: 3.6 px at the
corners)."""

WRIST_HAND_EYE = SE3.from_rotvec([32.0, -58.0, 41.0], [0.015, -0.025, 0.35])
"""True ``T_flange_camera`` of the simulated wrist camera: 32, -58, 41 mm off the
flange centre, turned 20 degrees about the tool axis and tilted slightly."""


def _dh(link: DHLink, theta: float) -> NDArray[np.float64]:
    ct, st = math.cos(theta + link.offset), math.sin(theta + link.offset)
    ca, sa = math.cos(link.alpha), math.sin(link.alpha)
    return np.array([
        [ct, -st * ca, st * sa, link.a * ct],
        [st, ct * ca, -ct * sa, link.a * st],
        [0.0, sa, ca, link.d],
        [0.0, 0.0, 0.0, 1.0],
    ])


_STARTS_DEG = (
    (0, -90, 90, -90, -90, 0),
    (0, -60, 100, -130, -90, 0),
    (30, -100, 80, -70, -90, 30),
    (-30, -80, 110, -120, -90, -30),
    (0, -120, 60, -30, -90, 0),
    (90, -90, 90, -90, -90, 0),
)


@dataclass(frozen=True)
class SixAxisArm:
    """A six-axis arm in standard DH form (default: a UR5).

    Parameters
    ----------
    links : sequence of DHLink
        Six links.
    limits : sequence of (low, high)
        Joint ranges, radians.
    base : SE3
        ``T_world_base`` (default identity: the base frame is the world frame).

    Examples
    --------
    >>> arm = SixAxisArm()
    >>> q = np.radians([10.0, -80.0, 95.0, -105.0, -90.0, 20.0])
    >>> T = arm.forward(q)
    >>> q2 = arm.inverse(T, q0=q + 0.1)
    >>> [round(v, 6) for v in T.distance_to(arm.forward(q2))]
    [0.0, 0.0]
    >>> arm.inverse(SE3.from_rotvec([2000.0, 0.0, 300.0], [np.pi, 0.0, 0.0]))
    Traceback (most recent call last):
    ...
    robostereo.errors.UnreachablePoseError: unreachable pose: flange at (2000.0, 0.0, 300.0) mm ...
    """

    links: tuple[DHLink, ...] = UR5_DH
    limits: tuple[tuple[float, float], ...] = UR5_LIMITS
    base: SE3 = field(default_factory=SE3.identity)

    def __post_init__(self) -> None:
        if len(self.links) != 6 or len(self.limits) != 6:
            raise InputError(f"a six-axis arm needs 6 links and 6 limits, got "
                             f"{len(self.links)} and {len(self.limits)}")
        for i, (lo, hi) in enumerate(self.limits, start=1):
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise InputError(f"limits of joint {i} must be (low, high), low < high, "
                                 f"got {(lo, hi)}")

    def _joints(self, q: ArrayLike) -> NDArray[np.float64]:
        v = np.asarray(q, dtype=float)
        if v.shape != (6,) or not np.all(np.isfinite(v)):
            raise InputError(f"joints must be 6 finite angles (radians), got {q!r}")
        return v

    def violation(self, q: ArrayLike) -> str | None:
        """A one-line description of the first joint limit `q` violates, or None."""
        v = self._joints(q)
        for i, ((lo, hi), x) in enumerate(zip(self.limits, v, strict=True), start=1):
            if not lo - 1e-9 <= x <= hi + 1e-9:
                return (f"joint {i} = {math.degrees(x):.2f} deg outside "
                        f"[{math.degrees(lo):.0f}, {math.degrees(hi):.0f}] deg")
        return None

    def forward(self, q: ArrayLike) -> SE3:
        """``T_world_flange`` at joints `q` (radians), millimetres."""
        v = self._joints(q)
        M = self.base.matrix
        for link, theta in zip(self.links, v, strict=True):
            M = M @ _dh(link, float(theta))
        return SE3.from_matrix(M)

    def inverse(
        self, target: SE3, *, q0: ArrayLike | None = None, tolerance_mm: float = 1e-6
    ) -> NDArray[np.float64]:
        """Joints that put the flange at `target` (``T_world_flange``), within the limits.

        Parameters
        ----------
        target : SE3
        q0 : array_like, shape (6,), optional
            Start (e.g. the current joints); the solution nearest it is preferred.
        tolerance_mm : float
            Largest position error accepted (the rotation error is held to the same
            over a 100 mm lever).

        Returns
        -------
        ndarray, shape (6,)

        Raises
        ------
        UnreachablePoseError
            No start converges within the joint limits.

        Notes
        -----
        Damped least squares (:func:`scipy.optimize.least_squares`, trust region with
        the joint bounds) on the 6-vector ``(p(q) - p*, 100 mm * log(R*^T R(q)))`` from
        `q0` and a few standard arm configurations; the converged solution nearest `q0`
        wins.
        """
        if not isinstance(target, SE3):
            raise InputError(f"target must be an SE3, got {type(target).__name__}")
        lo = np.array([a for a, _ in self.limits])
        hi = np.array([b for _, b in self.limits])
        starts = [np.radians(s) for s in _STARTS_DEG]
        if q0 is not None:
            starts.insert(0, np.clip(self._joints(q0), lo, hi))
        ref = starts[0]
        lever = 100.0

        def resid(q: NDArray[np.float64]) -> NDArray[np.float64]:
            T = self.forward(q)
            dr = (target.inv() @ T).rotvec
            return np.concatenate([T.translation - target.translation, lever * dr])

        best: NDArray[np.float64] | None = None
        for s in starts:
            sol = least_squares(resid, np.clip(s, lo + 1e-9, hi - 1e-9), bounds=(lo, hi),
                                xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=400)
            if np.abs(sol.fun).max() <= tolerance_mm:
                if best is None or np.abs(sol.x - ref).sum() < np.abs(best - ref).sum():
                    best = sol.x
                if q0 is not None and s is starts[0]:
                    break
        if best is None:
            p = target.translation
            raise UnreachablePoseError(
                f"unreachable pose: flange at ({p[0]:.1f}, {p[1]:.1f}, {p[2]:.1f}) mm "
                "cannot be reached within the joint limits"
            )
        return best

    def camera_pose(self, q: ArrayLike, hand_eye: SE3) -> SE3:
        """``T_world_camera = T_world_flange(q) @ hand_eye``."""
        return self.forward(q) @ hand_eye

    def move_camera(
        self, camera_pose: SE3, hand_eye: SE3, *, q0: ArrayLike | None = None
    ) -> tuple[NDArray[np.float64], SE3]:
        """Joints and flange pose that put the camera at `camera_pose`.

        Returns ``(q, T_world_flange)``; raises UnreachablePoseError.
        """
        flange = camera_pose @ hand_eye.inv()
        q = self.inverse(flange, q0=q0)
        return q, self.forward(q)

    def reach_mm(self) -> float:
        """Distance from the shoulder to the wrist centre, stretched: ``|a2| + |a3|``."""
        return float(sum(abs(link.a) for link in self.links))


