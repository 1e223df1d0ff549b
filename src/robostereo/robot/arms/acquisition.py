"""The thesis's acquisition program and the camera on the arm (thesis 4.1, 4.2.1, fig. 4-2).

A VAL-II program moves the camera on the AdeptOne's forearm
(:class:`~robostereo.robot.arms.scara.AdeptOne`) to two viewpoints ``D`` apart on a
baseline above the object and grabs an image at each.  This module gives

* :class:`Robot` and :class:`CameraDevice`, the two small protocols the acquisition
  needs (move the camera's optical centre; grab an image);
* :class:`SimulatedCamera`, an adapter that renders what the camera sees from the
  robot's current pose with a render function passed in (e.g.
  :func:`robostereo.simulation.render`);
* :func:`acquire_stereo_pair`, the thesis's acquisition program, and its result
  :class:`StereoAcquisition`.

Frames: the robot's base frame is the world frame (millimetres, Z up).  Angles are
radians in the API.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_finite, require_positive
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import Pose
from robostereo.geometry.scara_rectification import EpipolarGeometry
from robostereo.robot.arms.scara import Elbow, Joints

__all__ = [
    "CameraDevice",
    "Robot",
    "SimulatedCamera",
    "StereoAcquisition",
    "acquire_stereo_pair",
]


@runtime_checkable
class Robot(Protocol):
    """A robot that moves a downward-looking camera in the horizontal plane."""

    def move_camera(
        self, x: float, y: float, *, phi: float | None = None, elbow: Elbow = "righty"
    ) -> Pose:
        """Move the optical centre to world ``(x, y)``; return the pose as reported."""
        ...

    @property
    def joints(self) -> Joints:
        """Current joint values."""
        ...

    def reported_pose(self) -> Pose:
        """The camera pose that the robot reports (what the software believes)."""
        ...


@runtime_checkable
class CameraDevice(Protocol):
    """A camera that grabs one grey image ``(H, W)`` (VAL-II ``VPICTURE``)."""

    def grab(self) -> NDArray[Any]:
        """Grab an image, shape ``(H, W)``."""
        ...


# ---------------------------------------------------------------------- simulated camera


class SimulatedCamera:
    """A :class:`CameraDevice` that renders the scene from the robot's current pose.

    Parameters
    ----------
    scene : object
        Whatever `render_fn` takes (e.g. a :class:`robostereo.simulation.Scene`).
    camera : Camera
    robot : Robot
        The robot carrying the camera.  The image is rendered from
        ``robot.actual_pose()`` if the robot has it (the true pose, without the
        repeatability error of the reported one), else from ``robot.reported_pose()``.
    rng : numpy.random.Generator or None
        Passed to `render_fn` as ``rng=`` (sensor noise).
    render_fn : callable
        ``render_fn(scene, camera, pose, rng=rng, **render_kwargs)`` returning an object
        with ``.image`` ``(H, W)`` (such as ``robostereo.simulation.render``'s
        ``Rendering``) or the image itself.
    render_kwargs : mapping, optional
        Extra keyword arguments for `render_fn` (e.g. ``noise_sigma``).

    Attributes
    ----------
    last_rendering : object or None
        What `render_fn` returned at the last :meth:`grab` (depth, labels ground truth).
    last_pose : Pose or None
        The pose the last image was rendered from.
    """

    def __init__(
        self,
        scene: Any,
        camera: Camera,
        robot: Robot,
        rng: np.random.Generator | None,
        render_fn: Callable[..., Any],
        render_kwargs: Mapping[str, Any] | None = None,
    ) -> None:
        if not callable(render_fn):
            raise InputError("render_fn must be callable: render_fn(scene, camera, pose, rng=...)")
        self.scene = scene
        self.camera = camera
        self.robot = robot
        self.rng = rng
        self.render_fn = render_fn
        self.render_kwargs: dict[str, Any] = dict(render_kwargs or {})
        self.last_rendering: Any = None
        self.last_pose: Pose | None = None

    def grab(self) -> NDArray[Any]:
        """Render and return the image ``(H, W)`` seen from the robot's current pose."""
        actual = getattr(self.robot, "actual_pose", None)
        pose = actual() if callable(actual) else self.robot.reported_pose()
        result = self.render_fn(
            self.scene, self.camera, pose, rng=self.rng, **self.render_kwargs
        )
        image = np.asarray(getattr(result, "image", result))
        _check_image(image, self.camera, "rendered image")
        self.last_rendering = result
        self.last_pose = pose
        return image


def _check_image(image: NDArray[Any], camera: Camera, name: str) -> None:
    w, h = camera.image_size
    if image.ndim != 2 or image.shape != (h, w):
        raise InputError(f"{name} must have shape (H, W) = ({h}, {w}), got {image.shape}")


# ---------------------------------------------------------------------- acquisition


@dataclass(frozen=True)
class StereoAcquisition:
    """Two views grabbed by :func:`acquire_stereo_pair`.

    Attributes
    ----------
    left_image, right_image : ndarray, shape (H, W)
        Grabbed images (read-only copies).
    pose_left, pose_right : Pose
        Camera poses as the robot reported them; left at ``-D/2`` along the baseline.
    camera : Camera
    joints : tuple of Joints
        Joint values at the left and the right viewpoint.
    """

    left_image: NDArray[Any]
    right_image: NDArray[Any]
    pose_left: Pose
    pose_right: Pose
    camera: Camera
    joints: tuple[Joints, Joints]

    @property
    def epipolar(self) -> EpipolarGeometry:
        """Epipolar frame of the two reported poses (alpha, theta_l, theta_r, D)."""
        return EpipolarGeometry.from_poses(self.camera, self.pose_left, self.pose_right)


def acquire_stereo_pair(
    robot: Robot,
    device: CameraDevice | Callable[[Robot], CameraDevice],
    camera: Camera,
    *,
    center_xy: tuple[float, float],
    baseline_mm: float = 20.0,
    direction_deg: float | None = None,
    elbow: Elbow = "righty",
) -> StereoAcquisition:
    """Move the camera to two viewpoints on a baseline and grab an image at each.

    Parameters
    ----------
    robot : Robot
    device : CameraDevice or callable
        The camera, or a factory ``device(robot) -> CameraDevice``.
    camera : Camera
        Intrinsics; the grabbed images must be ``camera.image_size``.
    center_xy : tuple of float
        Mid-baseline point (world ``(x, y)``, mm) above the object.
    baseline_mm : float
        ``D``, default 20 mm as in the thesis.
    direction_deg : float or None
        Baseline direction ``alpha`` from world X, degrees, counter-clockwise.  None:
        along the camera's x axis at the centre (so that ``theta`` is small).
    elbow : {'righty', 'lefty', 'auto'}
        Elbow solution, the same for every move.

    Returns
    -------
    StereoAcquisition

    Notes
    -----
    The thesis's VAL-II program (4.1, 4.2.1, figure 4-2):

    1. move the camera above the object, to `center_xy`;
    2. choose the baseline direction ``alpha`` (`direction_deg`, or the camera's yaw);
    3. move to ``center - (D/2) u`` with ``u = (cos alpha, sin alpha)``, grab the left
       image (``VPICTURE``), record the reported pose and the joints;
    4. move to ``center + (D/2) u``, grab the right image, record.

    With the forearm mount the yaw follows the arm, so the two views have different
    ``phi``; :attr:`StereoAcquisition.epipolar` gives ``theta_l`` and ``theta_r``.

    References
    ----------
    Seed 4.1, 4.2.1 and figure 4-2.
    """
    require_positive("baseline_mm", baseline_mm)
    if len(center_xy) != 2:
        raise InputError(f"center_xy must be (x, y), got {center_xy}")
    cx, cy = float(center_xy[0]), float(center_xy[1])
    require_finite("center_xy", [cx, cy])
    if direction_deg is not None:
        require_finite("direction_deg", direction_deg)
    if not isinstance(device, CameraDevice):
        if not callable(device):
            raise InputError("device must have grab() or be a factory device(robot)")
        device = device(robot)
    pose_c = robot.move_camera(cx, cy, elbow=elbow)
    alpha = pose_c.phi if direction_deg is None else math.radians(direction_deg)
    u = np.array([math.cos(alpha), math.sin(alpha)]) * (baseline_mm / 2.0)
    views = []
    for sign in (-1.0, 1.0):
        pose = robot.move_camera(cx + sign * float(u[0]), cy + sign * float(u[1]), elbow=elbow)
        image = np.array(device.grab(), copy=True)
        _check_image(image, camera, "grabbed image")
        image.setflags(write=False)
        views.append((image, pose, robot.joints))
    (li, lp, lj), (ri, rp, rj) = views
    return StereoAcquisition(li, ri, lp, rp, camera, (lj, rj))
