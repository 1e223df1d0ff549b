"""What two-view and N-view capture files share: the camera, the poses, eq. 9, notes.

* ``camera:`` in either form of :func:`~robostereo.geometry.camera.camera_from_dict`
  (physical, or in pixels: ``fx, fy, cx, cy`` or ``K``) or the path of an OpenCV or
  ROS camera file (:func:`~robostereo.io.camera_file.camera_from_entry`);
* ``pose_convention:`` ``camera_to_world`` (``T_world_camera``, the default) or
  ``world_to_camera`` (the extrinsics of COLMAP, MVSNet and OpenCV, ``[R | t]`` with
  ``x_cam = R x_world + t``), for the camera poses (not the flange poses or
  ``hand_eye``, which are the robot's): :func:`pose_convention`,
  :func:`camera_pose_from_dict`;
* a mix-up of the two caught where the images show it: views none of whose scene, at
  the depth range, any other view sees (:func:`check_views_share_scene`);
* the ``uncertainty`` mapping of eq. 9 (:func:`extras_from_dict`,
  :func:`extras_to_dict`): ``focal_length_mm`` for a physical camera, ``focal_px``
  for a camera in pixels (default 0: a calibration's focal length is known in pixels
  only, and its error, when known, is given in pixels), so that no invented unit
  changes a bound;
* the warnings about metres written as millimetres and an identity hand-eye;
* the ground-truth depth map keys (:data:`TWO_VIEW_DEPTH_KEYS`, :data:`VIEW_DEPTH_KEY`),
  accepted here and read only by ``robostereo evaluate``
  (:mod:`robostereo.evaluation.depth_maps`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from robostereo.errors import InputError, shown, warn_input
from robostereo.geometry.camera import Camera
from robostereo.geometry.mapping_checks import is_number
from robostereo.geometry.poses import SE3, Pose, as_se3, pose_from_dict

__all__ = [
    "DEFAULT_FOCAL_UNCERTAINTY_MM",
    "DEPTH_SCALE_KEY",
    "METRES_AS_MM_BELOW",
    "POSE_CONVENTIONS",
    "TWO_VIEW_DEPTH_KEYS",
    "VIEW_DEPTH_KEY",
    "camera_pose_from_dict",
    "check_views_share_scene",
    "default_focal_uncertainty_mm",
    "extras_from_dict",
    "extras_to_dict",
    "hand_eye_bound_mm",
    "pose_convention",
    "rotation_disparity_px",
    "shared_scene_fractions",
    "warn_identity_hand_eye",
    "warn_metres",
]

POSE_CONVENTIONS = ("camera_to_world", "world_to_camera")
"""The values of ``pose_convention``: what a camera pose in a capture file maps."""

DEFAULT_FOCAL_UNCERTAINTY_MM = 0.01
"""eq. 9's ``ds`` of a physical camera when the file gives none, mm."""

#: ``uncertainty`` keys of a capture file and the capture attributes they fill (eq. 9)
_UNCERTAINTY = (("baseline_mm", "baseline_uncertainty_mm"),
                ("focal_length_mm", "focal_length_uncertainty_mm"),
                ("disparity_px", "disparity_uncertainty_px"),
                ("rotation_deg", "rotation_uncertainty_deg"),
                ("hand_eye_deg", "hand_eye_uncertainty_deg"))
_PIXEL_UNCERTAINTY = (("baseline_mm", "baseline_uncertainty_mm"),
                      ("focal_px", "focal_length_uncertainty_mm"),
                      ("disparity_px", "disparity_uncertainty_px"),
                      ("rotation_deg", "rotation_uncertainty_deg"),
                      ("hand_eye_deg", "hand_eye_uncertainty_deg"))

DEPTH_SCALE_KEY = "depth_scale"
"""Top-level key of a capture file: the units per mm of its 16-bit PNG depth maps."""

TWO_VIEW_DEPTH_KEYS = ("depth_left", "depth_right", DEPTH_SCALE_KEY)
"""Top-level keys of a two-view capture file naming its ground-truth depth maps (and
their PNG scale); the capture readers accept them and read nothing from them."""

VIEW_DEPTH_KEY = "depth"
"""Key of a view of an N-view capture file naming its ground-truth depth map."""

_SCENE_GRID = 9  # pixels per image side sampled by the shared-scene check
_SCENE_DEPTHS = 5  # depths sampled over the depth range


def rotation_disparity_px(focal_px: float, rotation_deg: float) -> float:
    """The disparity two views' orientations can be off by, pixels: each view turned up to
    `rotation_deg` (``uncertainty: rotation_deg``) about an axis across its baseline moves
    its image by ``f tan(rotation)`` along the epipolar lines, the pair's disparity by up
    to twice that (eq. 9's ``d(disp)`` gains it, as a worst case like its other terms).

    >>> round(rotation_disparity_px(800.0, 0.05), 3)
    1.396
    """
    return 2.0 * focal_px * math.tan(math.radians(rotation_deg))


def hand_eye_bound_mm(depth_mm: Any, hand_eye_deg: float) -> Any:
    """How far a hand-eye rotation off by up to `hand_eye_deg` (``uncertainty:
    hand_eye_deg``) can move a point at `depth_mm`: every view's camera turns with it
    about its optical centre, so the point moves ``Z tan(hand_eye)`` (across its ray,
    where no image can show it: the world frame tilts), which each bound gains.

    >>> round(float(hand_eye_bound_mm(1000.0, 0.1)), 2)
    1.75
    """
    return np.asarray(depth_mm, dtype=float) * math.tan(math.radians(hand_eye_deg))


def default_focal_uncertainty_mm(camera: Camera) -> float:
    """eq. 9's ``ds`` when none is given: :data:`DEFAULT_FOCAL_UNCERTAINTY_MM` for a
    physical camera, 0 for a camera in pixels (its focal length has no mm to be
    uncertain in; give ``uncertainty: {focal_px}`` from the calibration)."""
    return 0.0 if camera.in_pixels else DEFAULT_FOCAL_UNCERTAINTY_MM


def pose_convention(data: Mapping[str, Any], source: str,
                    default: str = "camera_to_world") -> str:
    """A mapping's ``pose_convention`` (one of :data:`POSE_CONVENTIONS`), else `default`.

    >>> pose_convention({"pose_convention": "world_to_camera"}, "capture.yaml")
    'world_to_camera'
    >>> pose_convention({}, "capture.yaml")
    'camera_to_world'
    """
    value = data.get("pose_convention", default)
    if value not in POSE_CONVENTIONS:
        raise InputError(f"{source}: key 'pose_convention' must be "
                         f"{' or '.join(POSE_CONVENTIONS)}, got {shown(value)}")
    return str(value)


def camera_pose_from_dict(value: Any, source: str, convention: str) -> SE3:
    """A camera pose of a capture file as ``T_world_camera``.

    Parameters
    ----------
    value : mapping
        A pose in any form of :func:`~robostereo.geometry.poses.pose_from_dict`.
    source : str
        The file and key, for messages.
    convention : {'camera_to_world', 'world_to_camera'}
        What `value` maps; ``world_to_camera`` (an extrinsic ``[R | t]``) is inverted.

    Examples
    --------
    >>> T = camera_pose_from_dict({"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 500],
    ...                                       [0, 0, 0, 1]]}, "c.yaml", "world_to_camera")
    >>> T.translation.tolist()
    [0.0, 0.0, -500.0]
    """
    pose = pose_from_dict(value, source=source)
    if convention == "camera_to_world":
        return pose
    if isinstance(pose, Pose):
        raise InputError(f"{source}: the SCARA form {{x, y, z, phi_deg}} is the camera's "
                         "own pose: pose_convention world_to_camera is for the other forms")
    return as_se3(pose).inv()


def shared_scene_fractions(camera: Camera, poses: Sequence[SE3],
                           depth_range_mm: tuple[float, float]) -> np.ndarray:
    """For each view, the share of its scene at the depth range that another view sees.

    Parameters
    ----------
    camera : Camera
    poses : sequence of SE3
        ``T_world_camera`` of each view.
    depth_range_mm : tuple of float
        ``(near, far)`` along the optical axis, mm.

    Returns
    -------
    ndarray, shape (N,)
        Per view: of a ``9 x 9`` grid of its pixels at 5 depths over the range, the
        share that falls in front of some other view and inside its image.

    Notes
    -----
    1. Back-project the grid at each depth into the world from each view.
    2. Project every such point into every other view; count it seen where its depth
       is positive and its pixel inside the image.
    3. A view whose share is 0 sees nothing the others see: its pose points away from
       theirs, as when a world-to-camera extrinsic is read as a camera pose.
    """
    w, h = camera.image_size
    u, v = np.meshgrid(np.linspace(0, w - 1, _SCENE_GRID), np.linspace(0, h - 1, _SCENE_GRID))
    uv = np.column_stack([u.ravel(), v.ravel()])
    near, far = depth_range_mm
    depths = np.linspace(near, far, _SCENE_DEPTHS)
    uvz = np.repeat(uv, depths.size, axis=0)
    z = np.tile(depths, len(uv))
    out = np.zeros(len(poses))
    for k, pk in enumerate(poses):
        world = camera.backproject(uvz, z, pk)
        seen = np.zeros(len(world), bool)
        for j, pj in enumerate(poses):
            if j == k:
                continue
            px, d = camera.project(world, pj)
            with np.errstate(invalid="ignore"):
                seen |= (d > 0) & (px[:, 0] >= -0.5) & (px[:, 0] <= w - 0.5) \
                    & (px[:, 1] >= -0.5) & (px[:, 1] <= h - 0.5)
        out[k] = seen.mean()
    return out


def check_views_share_scene(camera: Camera, poses: Sequence[SE3],
                            depth_range_mm: tuple[float, float], names: Sequence[str],
                            source: str, convention: str = "camera_to_world") -> None:
    """Catch camera poses in the wrong convention where the images can show it.

    Warns (:class:`~robostereo.errors.PlausibilityWarning`) naming each view whose
    scene at the depth range no other view sees (:func:`shared_scene_fractions`), or,
    when that holds for every view, once for all (no pair of views can locate a
    point).  The message suggests the ``pose_convention`` key.  A warning, not an
    error: a capture is still written and read back whatever its poses (locating
    refuses a pair with no shared scene,
    :func:`~robostereo.robot.capture.locate_pair.check_shared_scene`).
    """
    share = shared_scene_fractions(camera, poses, depth_range_mm)
    other = next(c for c in POSE_CONVENTIONS if c != convention)
    hint = (f"are the poses {other.replace('_', '-')}, read as {convention.replace('_', '-')}? "
            f"set 'pose_convention: {other}'")
    lost = np.flatnonzero(share == 0)
    rng = f"[{depth_range_mm[0]:g}, {depth_range_mm[1]:g}] mm"
    if len(lost) == len(poses):
        warn_input(f"{source}: no view sees what another sees at depth_range_mm "
                   f"{rng} (the optical axes point apart): {hint}")
        return
    for k in lost:
        warn_input(f"{source}: view {names[k]}: no other view sees its scene at "
                   f"depth_range_mm {rng}: {hint}")


METRES_AS_MM_BELOW = 5.0
"""Largest translation, mm, that :func:`warn_units` takes for metres written as mm.

A flange or camera pose lies hundreds of millimetres from a robot's base and a camera
some tens from the flange; in metres the same numbers are under 2 (a 2 m reach), so a
file whose translations of one key are all under 5 "mm" while the scene lies 100 mm or
more away (``depth_range_mm``, when given) almost surely holds metres."""



def warn_metres(source: str, what: str, written: list[Any], poses: list[Any],
                far: float | None, *, hand_eye: bool = False) -> None:
    """Warn when poses written with a translation and no ``unit`` all lie within
    :data:`METRES_AS_MM_BELOW` mm of the origin: metres written as millimetres.

    Parameters
    ----------
    source : str
        The file, for the message.
    what : str
        The keys the poses were read from, for the message.
    written : list
        The poses as written (mappings); only those in a form with a translation
        (``position`` or ``matrix``) and without ``unit`` are judged, all or none.
    poses : list of SE3
        The poses read from them.
    far : float or None
        The scene's far depth, mm, when known (the caller skips scenes under 100 mm).
    hand_eye : bool
        A hand-eye transform: an all-zero translation is the identity placeholder
        (:func:`warn_identity_hand_eye`), not metres.
    """
    if not all(isinstance(r, Mapping) and ("position" in r or "matrix" in r)
               and "unit" not in r for r in written):
        return
    t = float(np.abs(np.array([as_se3(p).translation for p in poses])).max())
    if t < METRES_AS_MM_BELOW and (not hand_eye or t > 0):
        where = f" with the scene {far:g} mm away" if far is not None else ""
        warn_input(f"{source}: {what}: every translation is under "
                   f"{METRES_AS_MM_BELOW:g} mm (largest {t:.4g}){where}: metres written as "
                   "millimetres? add 'unit: m'")


def warn_identity_hand_eye(source: str, hand_eye: SE3 | None) -> None:
    """Warn when a capture file's ``hand_eye`` is the identity: a placeholder, not a
    calibration."""
    if hand_eye is not None and np.allclose(hand_eye.matrix, np.eye(4), atol=1e-9):
        warn_input(f"{source}: hand_eye is the identity (camera frame = flange frame): a "
                   "placeholder, not a calibration? (robostereo handeye estimates it)")


def extras_to_dict(capture: Any) -> dict[str, Any]:
    """The ``uncertainty`` mapping and the ``robot``/``scene`` notes of a capture file.

    What two-view (:class:`~robostereo.robot.capture.capture_folder.Capture`) and N-view
    (:class:`~robostereo.robot.views.viewpoints.ViewsCapture`) files share: `capture` has
    the eq. 9 attributes ``baseline_uncertainty_mm``, ``focal_length_uncertainty_mm``,
    ``disparity_uncertainty_px``, ``notes`` and its ``camera``; a camera in pixels
    writes the focal term as ``focal_px``.
    """
    from robostereo.io import plain_values

    pixels = capture.camera.in_pixels
    keys = _PIXEL_UNCERTAINTY if pixels else _UNCERTAINTY
    unc = {key: float(getattr(capture, attr)) for key, attr in keys}
    for key in ("rotation_deg", "hand_eye_deg"):  # written only when given: as before
        if not unc[key]:
            del unc[key]
    if pixels:  # a nominal 1 mm lens over pixels of 1/fx mm: ds = d(fx) / fx
        unc["focal_px"] = float(capture.focal_length_uncertainty_mm * capture.camera.fx)
    out: dict[str, Any] = {"uncertainty": unc}
    for k in ("robot", "scene"):
        if k in capture.notes:
            out[k] = plain_values(capture.notes[k])
    return out


def extras_from_dict(data: Mapping[str, Any], source: str,
                     camera: Camera | None = None) -> dict[str, Any]:
    """The eq. 9 uncertainties and the notes of a parsed capture file, as the keyword
    arguments of :class:`~robostereo.robot.capture.capture_folder.Capture` or
    :class:`~robostereo.robot.views.viewpoints.ViewsCapture`.

    Parameters
    ----------
    data : mapping
        The parsed file.
    source : str
        The file, for messages.
    camera : Camera, optional
        The file's camera: one in pixels takes ``focal_px`` (pixels, default 0) where a
        physical one takes ``focal_length_mm`` (mm, default
        :data:`DEFAULT_FOCAL_UNCERTAINTY_MM`).

    Raises
    ------
    InputError
        ``uncertainty`` not a mapping of its three keys, or ``focal_px`` not a finite
        number in ``[0, fx)``; the message names `source`.  The other values are checked
        by the capture (:func:`~robostereo.geometry.plausibility.check_uncertainties`).
    """
    pixels = camera is not None and camera.in_pixels
    table = _PIXEL_UNCERTAINTY if pixels else _UNCERTAINTY
    kw: dict[str, Any] = {}
    unc = data.get("uncertainty") or {}
    keys = [key for key, _ in table]
    if not isinstance(unc, Mapping) or any(k not in keys for k in unc):
        form = ("a camera in pixels: focal_px, not focal_length_mm" if pixels
                else "focal_px is for a camera in pixels")
        raise InputError(f"{source}: key 'uncertainty' must be a mapping of "
                         f"{', '.join(keys)} ({form})")
    for key, attr in table:
        if key in unc:
            v = unc[key]
            if key == "focal_px":
                assert camera is not None
                if not (is_number(v) and np.isfinite(float(v)) and 0 <= v < camera.fx):
                    raise InputError(f"{source}: uncertainty 'focal_px' must be a finite "
                                     f"number >= 0 and below fx ({camera.fx:g} px), got "
                                     f"{shown(v)}")
                kw[attr] = float(v) / camera.fx
                continue
            try:  # the capture checks the values (an int too big for a float stays)
                kw[attr] = float(v) if isinstance(v, int | float) and v is not True else v
            except OverflowError:
                kw[attr] = v
    kw["notes"] = {k: data[k] for k in ("robot", "scene") if k in data}
    return kw
