"""Captures: two grabbed views with the camera and the poses, and their folders.

A *capture* is what the thesis's VAL-II program leaves behind (the thesis, 4.2): two
grabbed images, the camera and the two camera poses the robot reported
(:class:`Capture`).  It knows its epipolar frame (:meth:`Capture.geometry`): for two
SCARA poses (camera looking down, equal heights, no lens distortion) the thesis's
(:class:`~robostereo.geometry.scara_rectification.EpipolarGeometry`: ``alpha``,
``theta_l``, ``theta_r``, ``D``), for any other pair of 6-DoF poses
:class:`~robostereo.geometry.pose_rectification.GeneralEpipolarGeometry` (relative
pose, OpenCV ``stereoRectify`` with the intrinsics and distortion).  :func:`write_capture` and
:func:`read_capture` keep it in a folder; :func:`robostereo.robot.capture.locate_pair.locate`
turns it into 3-D points.

Capture folder format (``DIR/``)::

    left.png, right.png   the grabbed (unrectified) images, 8-bit PNG, grey levels as
                          grabbed (0..127 for the thesis's 7-bit camera)
    capture.yaml          camera:          camera mapping (robostereo.geometry.camera YAML keys:
                                           physical, or fx, fy, cx, cy / K in pixels;
                                           optional distortion [k1, k2, p1, p2, k3]),
                                           or the path of an OpenCV or ROS camera file
                          pose_left:       camera pose of each view, world frame, in
                          pose_right:      any form of robostereo.geometry.poses
                                           ({x, y, z (mm), phi_deg} for a SCARA), or
                          flange_left:     the flange poses the robot reported plus
                          flange_right:    the flange-to-camera transform (hand-eye
                          hand_eye:        calibration): camera = flange @ hand_eye
                          bit_depth:       7 (optional; default the PNG's)
                          disparity_range: [min, max] px (optional), or
                          depth_range_mm:  [near, far] expected depth of the object
                          pose_convention: camera_to_world (default) or world_to_camera
                                           (pose_left/right are extrinsics [R | t])
                          uncertainty:     {baseline_mm, focal_length_mm, disparity_px,
                                            rotation_deg, hand_eye_deg}
                                           (optional, eq. 9; focal_px in place of
                                           focal_length_mm for a camera in pixels)
                          robot, scene:    free-form notes (optional, not read)
                          depth_left:      ground-truth depth maps (optional, read only
                          depth_right:     by robostereo evaluate: PFM, NPY or 16-bit PNG;
                          depth_scale:     PNG units per mm, default 1)

The baseline ``D`` and its direction ``alpha`` come from the two poses.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_finite, require_positive, shown
from robostereo.evaluation.depth_maps import depth_map_files
from robostereo.geometry.camera import Camera, camera_to_dict
from robostereo.geometry.plausibility import check_depth_disparities, check_uncertainties
from robostereo.geometry.pose_rectification import GeneralEpipolarGeometry
from robostereo.geometry.poses import SE3, Pose, as_se3
from robostereo.geometry.poses import pose_from_dict as any_pose_from_dict
from robostereo.geometry.poses import pose_to_dict as any_pose_to_dict
from robostereo.geometry.scara_rectification import EpipolarGeometry
from robostereo.geometry.triangulation import StereoCamera
from robostereo.robot.capture.capture_keys import (
    TWO_VIEW_DEPTH_KEYS,
    camera_pose_from_dict,
    check_views_share_scene,
    default_focal_uncertainty_mm,
    extras_from_dict,
    extras_to_dict,
    pose_convention,
    rotation_disparity_px,
    warn_identity_hand_eye,
    warn_metres,
)

__all__ = [
    "CAPTURE_YAML",
    "DISPARITY_UNCERTAINTY_PX",
    "Capture",
    "Geometry",
    "Rectification",
    "capture_from_acquisition",
    "capture_to_dict",
    "disparity_range_from_depth",
    "read_capture",
    "warn_units",
    "write_capture",
]

CAPTURE_YAML = "capture.yaml"
_IMAGES = ("left.png", "right.png")
_KEYS = (
    "camera", "pose_left", "pose_right", "flange_left", "flange_right", "hand_eye",
    "bit_depth", "disparity_range", "depth_range_mm", "uncertainty", "robot", "scene",
    "pose_convention", *TWO_VIEW_DEPTH_KEYS,
)
Rectification = Literal["auto", "theta", "general"]
Geometry = EpipolarGeometry | GeneralEpipolarGeometry

DISPARITY_UNCERTAINTY_PX = 0.2
"""``d(disp)`` of eq. (9) for sub-pixel edges, pixels.

Measured on the simulated block (the thesis's 5.2 set-up, 7-bit images with 0.5 grey-level
sensor noise, rectified with linear interpolation): the disparity error of the block
edge points, 10,512 of them over both heights, 3 noise seeds, rolls of 0 and +-10
degrees and baseline directions of 0, 35 and -120 degrees, had an RMS of 0.03-0.04 px
and a maximum of 0.135 px (99th percentile 0.094 px).  0.2 px is that maximum rounded
up to the next tenth; the thesis used one whole pixel (0.00172 cm)."""



# ----------------------------------------------------------------------------- capture


@dataclass(frozen=True)
class Capture:
    """Two grabbed views with the camera and the poses the robot reported.

    Attributes
    ----------
    left, right : ndarray, shape (H, W)
        Grabbed, unrectified images (grey levels as grabbed).
    camera : Camera
    pose_left, pose_right : Pose or SE3
        Camera poses (``T_world_camera``, world mm); ``left`` is the viewpoint at
        ``-D/2`` on the baseline.  Two SCARA :class:`~robostereo.geometry.poses.Pose` s must be
        at one height (the thesis's set-up).
    bit_depth : int
        Significant bits of the grey levels (7 for the thesis's camera).
    disparity_range : tuple of float or None
        ``(min, max)`` of ``x_left - x_right`` in rectified pixels.
    depth_range_mm : tuple of float or None
        ``(near, far)`` expected depth of the object below the cameras, used when
        `disparity_range` is None.
    baseline_uncertainty_mm, focal_length_uncertainty_mm, disparity_uncertainty_px : float
        ``dD``, ``ds`` and ``d(disp)`` of eq. (9); ``ds`` defaults to 0.01 mm for a
        physical camera and 0 for one in pixels (whose nominal 1 mm lens makes ``ds``
        the focal length's relative error, ``d(fx) / fx``).
    rotation_uncertainty_deg : float
        How far each view's orientation may be off (the arm's repeatability, a hand-eye
        error as far as the flange turns between the views), degrees; the bounds' ``d(disp)``
        gains :func:`~robostereo.robot.capture.capture_keys.rotation_disparity_px`
        (default 0).
    hand_eye_uncertainty_deg : float
        How far the hand-eye's rotation may be off, degrees: each bound gains
        :func:`~robostereo.robot.capture.capture_keys.hand_eye_bound_mm` (default 0).
    notes : mapping
        Free-form ``robot`` and ``scene`` notes (written, never read).
    flange_left, flange_right, hand_eye : SE3 or None
        Where the poses came from, when they came from the robot's flange poses and a
        hand-eye transform (``pose = flange @ hand_eye``); written to ``capture.yaml``
        in place of the camera poses.
    """

    left: NDArray[Any]
    right: NDArray[Any]
    camera: Camera
    pose_left: Pose | SE3
    pose_right: Pose | SE3
    bit_depth: int = 7
    disparity_range: tuple[float, float] | None = None
    depth_range_mm: tuple[float, float] | None = None
    baseline_uncertainty_mm: float = 0.01
    focal_length_uncertainty_mm: float = None  # type: ignore[assignment]
    disparity_uncertainty_px: float = DISPARITY_UNCERTAINTY_PX
    rotation_uncertainty_deg: float = 0.0
    hand_eye_uncertainty_deg: float = 0.0
    notes: Mapping[str, Any] = field(default_factory=dict)
    flange_left: SE3 | None = None
    flange_right: SE3 | None = None
    hand_eye: SE3 | None = None

    @classmethod
    def from_flange(cls, *, flange_left: SE3, flange_right: SE3, hand_eye: SE3,
                    **kwargs: Any) -> Capture:
        """A capture whose camera poses are ``flange @ hand_eye`` (eye-in-hand)."""
        return cls(pose_left=flange_left @ hand_eye, pose_right=flange_right @ hand_eye,
                   flange_left=flange_left, flange_right=flange_right, hand_eye=hand_eye,
                   **kwargs)

    def __post_init__(self) -> None:
        if self.focal_length_uncertainty_mm is None:
            object.__setattr__(self, "focal_length_uncertainty_mm",
                               default_focal_uncertainty_mm(self.camera))
        for name in ("pose_left", "pose_right"):
            if not isinstance(getattr(self, name), Pose | SE3):
                raise InputError(f"{name} must be a Pose or an SE3, got "
                                 f"{type(getattr(self, name)).__name__}")
        w, h = self.camera.image_size
        for name in ("left", "right"):
            img = np.asarray(getattr(self, name))
            if img.ndim not in (2, 3) or img.shape[:2] != (h, w):
                raise InputError(
                    f"{name} image must be {w} x {h} pixels (the camera's image_size), "
                    f"got shape {img.shape}"
                )
        b = self.bit_depth
        if isinstance(b, bool) or not isinstance(b, int | np.integer) or not 1 <= b <= 16:
            raise InputError(f"bit_depth must be an integer in 1..16, got {shown(b)}")
        for name in ("left", "right"):
            img = np.asarray(getattr(self, name))
            if np.issubdtype(img.dtype, np.integer) and img.size and img.max() >= 2**b:
                raise InputError(
                    f"{name} image has grey level {int(img.max())} >= 2**bit_depth = {2**b}"
                )
        if self.disparity_range is None and self.depth_range_mm is None:
            raise InputError("a capture needs disparity_range [min, max] or depth_range_mm "
                             "[near, far]")
        if self.disparity_range is not None:
            lo, hi = _pair("disparity_range", self.disparity_range)
            if not lo <= hi:
                raise InputError(f"disparity_range must be [min, max] with min <= max, "
                                 f"got {[lo, hi]}")
            object.__setattr__(self, "disparity_range", (lo, hi))
        if self.depth_range_mm is not None:
            near, far = _pair("depth_range_mm", self.depth_range_mm)
            if not 0 < near <= far:
                raise InputError(f"depth_range_mm must be [near, far] with 0 < near <= far, "
                                 f"got {[near, far]}")
            object.__setattr__(self, "depth_range_mm", (near, far))
        check_uncertainties(self.camera.focal_length_mm, w,
                            baseline_mm=self.baseline_uncertainty_mm,
                            focal_length_mm_unc=self.focal_length_uncertainty_mm,
                            disparity_px=self.disparity_uncertainty_px,
                            rotation_deg=self.rotation_uncertainty_deg,
                            hand_eye_deg=self.hand_eye_uncertainty_deg)
        # math.hypot scales: no overflow for translations near the float range
        d = math.hypot(*(as_se3(self.pose_left).translation
                         - as_se3(self.pose_right).translation))
        if 0 < d <= self.baseline_uncertainty_mm:
            raise InputError(
                f"baseline D = {d:.3g} mm is not longer than its uncertainty "
                f"{self.baseline_uncertainty_mm:g} mm (eq. 9's dD): the two views are one "
                "viewpoint; move the camera further between them")
        if self.is_scara:
            if abs(self.pose_left.z - self.pose_right.z) > 1e-3:
                raise InputError(
                    "pose_left and pose_right must be at the same height (the camera moves "
                    f"horizontally), got z = {self.pose_left.z} and {self.pose_right.z} mm"
                )
            EpipolarGeometry.from_poses(self.camera, self.pose_left, self.pose_right)  # D > 0
        else:
            if not d > 1e-9:
                raise InputError(f"baseline: the two optical centres coincide (D = {d} mm)")
        if self.disparity_range is None:  # bounds the disparities searched
            check_depth_disparities(self.camera.fx, d, self.depth_range_mm, w)

    @property
    def is_scara(self) -> bool:
        """Both poses in the SCARA form (looking down) and no lens distortion: the thesis's
        theta rectification applies."""
        return (isinstance(self.pose_left, Pose) and isinstance(self.pose_right, Pose)
                and not self.camera.distortion)

    def geometry(self, rectification: Rectification = "auto") -> Geometry:
        """The epipolar frame and rectification of the two poses.

        Parameters
        ----------
        rectification : {'auto', 'theta', 'general'}
            ``'theta'``: the thesis's turn of each view about its optical axis (SCARA
            poses only); ``'general'``: OpenCV ``stereoRectify`` of the relative pose
            (any poses); ``'auto'``: theta for SCARA captures, general otherwise.
        """
        if rectification not in ("auto", "theta", "general"):
            raise InputError(f"rectification must be 'auto', 'theta' or 'general', got "
                             f"{rectification!r}")
        if rectification == "theta" or (rectification == "auto" and self.is_scara):
            if not self.is_scara:
                raise InputError("rectification 'theta' needs two SCARA poses "
                                 "{x, y, z, phi_deg} and a camera without distortion")
            return EpipolarGeometry.from_poses(self.camera, self.pose_left, self.pose_right)
        return GeneralEpipolarGeometry.from_poses(self.camera, self.pose_left, self.pose_right)

    @property
    def epipolar(self) -> Geometry:
        """:meth:`geometry` with ``'auto'``."""
        return self.geometry()

    def resolved_disparity_range(self, geometry: Geometry | None = None) -> tuple[float, float]:
        """`disparity_range`, or that of `depth_range_mm` (:func:`disparity_range_from_depth`)."""
        if self.disparity_range is not None:
            return self.disparity_range
        assert self.depth_range_mm is not None
        g = geometry if geometry is not None else self.epipolar
        return disparity_range_from_depth(self.camera, g.baseline_mm, self.depth_range_mm,
                                          fx=_rectified_fx(g))

    def stereo_camera(self, geometry: Geometry | None = None) -> StereoCamera:
        """The rectified pair's geometry for eq. (6)-(9): intrinsics, ``D`` and bounds."""
        cam = self.camera
        g = geometry if geometry is not None else self.epipolar
        if isinstance(g, GeneralEpipolarGeometry):
            K = g.K_rect
            fx, fy, cx, cy = K[0, 0], K[1, 1], K[0, 2], K[1, 2]
        else:
            fx, fy = cam.fx, cam.fy
            cx, cy = cam.principal_point
        return StereoCamera(
            fx=fx, fy=fy, baseline_mm=g.baseline_mm, cx=cx, cy=cy,
            focal_uncertainty_px=self.focal_length_uncertainty_mm / cam.pixel_pitch_mm[0]
            * fx / cam.fx,
            baseline_uncertainty_mm=self.baseline_uncertainty_mm,
            disparity_uncertainty_px=self.disparity_uncertainty_px
            + rotation_disparity_px(fx, self.rotation_uncertainty_deg),
        )


def _rectified_fx(geometry: Geometry) -> float:
    if isinstance(geometry, GeneralEpipolarGeometry):
        return float(geometry.K_rect[0, 0])
    return geometry.camera.fx


def _pair(name: str, value: object) -> tuple[float, float]:
    ok = isinstance(value, list | tuple) and len(value) == 2
    if ok:
        try:
            a, b = float(value[0]), float(value[1])  # type: ignore[index, arg-type]
        except (TypeError, ValueError, OverflowError):
            ok = False
    if not ok or isinstance(value[0], bool) or isinstance(value[1], bool):  # type: ignore[index]
        raise InputError(f"{name} must be a pair [a, b] of numbers, got {shown(value)}")
    require_finite(name, [a, b])
    return a, b


def disparity_range_from_depth(
    camera: Camera,
    baseline_mm: float,
    depth_range_mm: tuple[float, float],
    *,
    fx: float | None = None,
) -> tuple[float, float]:
    """Whole-pixel disparity range ``(floor(fx D / far), ceil(fx D / near))``.

    `fx` (pixels) defaults to the camera's; a general rectification has its own.

    Examples
    --------
    >>> from robostereo.geometry.camera import SEED_CAMERA
    >>> disparity_range_from_depth(SEED_CAMERA, 20.0, (900.0, 1100.0))
    (26.0, 33.0)
    """
    require_positive("baseline_mm", baseline_mm)
    near, far = _pair("depth_range_mm", depth_range_mm)
    require_positive("depth_range_mm near", near)
    if far < near:
        raise InputError(f"depth_range_mm must be [near, far] with near <= far, got "
                         f"{[near, far]}")
    f = (camera.fx if fx is None else fx) * baseline_mm
    return float(math.floor(f / far)), float(math.ceil(f / near))


def capture_from_acquisition(
    acquisition: Any,
    *,
    bit_depth: int = 7,
    disparity_range: tuple[float, float] | None = None,
    depth_range_mm: tuple[float, float] | None = None,
    notes: Mapping[str, Any] | None = None,
) -> Capture:
    """A :class:`Capture` of a :class:`robostereo.robot.StereoAcquisition`."""
    return Capture(
        left=np.asarray(acquisition.left_image), right=np.asarray(acquisition.right_image),
        camera=acquisition.camera, pose_left=acquisition.pose_left,
        pose_right=acquisition.pose_right, bit_depth=bit_depth,
        disparity_range=disparity_range, depth_range_mm=depth_range_mm,
        notes=dict(notes or {}),
    )


def capture_to_dict(capture: Capture) -> dict[str, Any]:
    """The ``capture.yaml`` mapping of a capture."""

    out: dict[str, Any] = {"camera": camera_to_dict(capture.camera)}
    if capture.hand_eye is not None and capture.flange_left is not None \
            and capture.flange_right is not None:
        out["flange_left"] = any_pose_to_dict(capture.flange_left)
        out["flange_right"] = any_pose_to_dict(capture.flange_right)
        out["hand_eye"] = any_pose_to_dict(capture.hand_eye)
    else:
        out["pose_left"] = any_pose_to_dict(capture.pose_left)
        out["pose_right"] = any_pose_to_dict(capture.pose_right)
    out["bit_depth"] = int(capture.bit_depth)
    if capture.disparity_range is not None:
        out["disparity_range"] = [float(v) for v in capture.disparity_range]
    if capture.depth_range_mm is not None:
        out["depth_range_mm"] = [float(v) for v in capture.depth_range_mm]
    out.update(extras_to_dict(capture))
    return out


def write_capture(directory: str | os.PathLike[str], capture: Capture, *,
                  depth_maps: Sequence[Any] | None = None) -> Path:
    """Write a capture folder (``left.png``, ``right.png``, ``capture.yaml``).

    The folder is assembled beside `directory` and renamed into place at the end, so a
    failure leaves nothing behind.  `directory` must not exist or be an empty folder.
    `depth_maps` (left, right; (H, W) mm along each optical axis, e.g. the simulator's
    renderings) are written as ``depth/left.npy`` and ``depth/right.npy`` for
    ``robostereo evaluate``.

    Returns
    -------
    Path
        `directory`.

    Raises
    ------
    InputError
        The parent folder is missing, `directory` is a non-empty folder or a file, or
        the images are not 8-bit representable.
    """
    images = []
    for name in ("left", "right"):
        img = np.asarray(getattr(capture, name))
        if img.ndim != 2 or not np.issubdtype(img.dtype, np.integer) or img.min() < 0 \
                or img.max() > 255:
            raise InputError(f"{name} image must be a grey (H, W) image of integers 0..255 "
                             "to be written as an 8-bit PNG")
        images.append(img.astype(np.uint8))
    from robostereo.io import folder_yaml_text, write_image_folder

    text = folder_yaml_text(capture_to_dict(capture))

    return write_image_folder(directory, dict(zip(_IMAGES, images, strict=True)),
                              {CAPTURE_YAML: text},
                              depth_map_files(("left", "right"), depth_maps))


def read_capture(directory: str | os.PathLike[str]) -> Capture:
    """Read a capture folder written by :func:`write_capture` (or by hand, or a robot).

    Raises
    ------
    InputError
        One line naming the file and the key: missing folder, image or ``capture.yaml``,
        invalid YAML, unknown or bad keys, images that disagree with the camera,
        coinciding or unequal-height poses.
    """
    from robostereo.io import read_folder_yaml
    from robostereo.io.images import load_image

    data, ypath = read_folder_yaml(directory, CAPTURE_YAML, folder="capture")
    d = ypath.parent
    src = str(ypath)
    if not isinstance(data, Mapping):
        raise InputError(f"{src}: expected a mapping with keys {list(_KEYS[:3])}")
    unknown = [k for k in data if k not in _KEYS]
    if unknown:
        raise InputError(f"{src}: unknown key '{unknown[0]}' (allowed: {', '.join(_KEYS)})")
    if "camera" not in data:
        raise InputError(f"{src}: missing key 'camera'")
    from robostereo.io.camera_file import camera_from_entry

    camera = camera_from_entry(data["camera"], d, src)
    convention = pose_convention(data, src)
    flange_keys = ("flange_left", "flange_right", "hand_eye")
    extra: dict[str, Any] = {}
    if any(k in data for k in flange_keys):
        if "pose_left" in data or "pose_right" in data:
            raise InputError(f"{src}: give camera poses (pose_left, pose_right) or flange "
                             "poses with hand_eye, not both")
        for k in flange_keys:
            if k not in data:
                raise InputError(f"{src}: missing key '{k}' (flange poses need "
                                 "flange_left, flange_right and hand_eye)")
        fl, fr, he = (as_se3(any_pose_from_dict(data[k], source=f"{src}: {k}"))
                      for k in flange_keys)
        poses: list[Pose | SE3] = [fl @ he, fr @ he]
        extra = {"flange_left": fl, "flange_right": fr, "hand_eye": he}
    else:
        for k in ("pose_left", "pose_right"):
            if k not in data:
                raise InputError(f"{src}: missing key '{k}'")
        poses = [camera_pose_from_dict(data[k], f"{src}: {k}", convention)
                 for k in ("pose_left", "pose_right")]
    images = []
    bits_file = []
    for name in _IMAGES:
        img, bits = load_image(d / name)
        images.append(img)
        bits_file.append(bits)
    bit_depth = data.get("bit_depth", bits_file[0])
    if isinstance(bit_depth, bool) or not isinstance(bit_depth, int):
        raise InputError(f"{src}: key 'bit_depth' must be an integer, got {shown(bit_depth)}")
    kw: dict[str, Any] = {}
    for key in ("disparity_range", "depth_range_mm"):
        if data.get(key) is not None:
            try:
                kw[key] = _pair(key, data[key])
            except InputError as exc:
                raise InputError(f"{src}: {exc}") from None
    kw.update(extras_from_dict(data, src, camera))
    try:
        capture = Capture(left=images[0], right=images[1], camera=camera, pose_left=poses[0],
                          pose_right=poses[1], bit_depth=bit_depth, **extra, **kw)
    except InputError as exc:
        raise InputError(f"{d}: {exc}") from None
    warn_units(data, capture, src)
    if capture.depth_range_mm is not None:
        check_views_share_scene(camera, [as_se3(p) for p in poses], capture.depth_range_mm,
                                ["left", "right"], src, convention)
    return capture


def warn_units(data: Mapping[str, Any], capture: Capture, source: str) -> None:
    """Warn about poses of a capture file that look like metres read as millimetres,
    and about an identity hand-eye transform.

    Parameters
    ----------
    data : mapping
        The parsed ``capture.yaml``.
    capture : Capture
        The capture read from it.
    source : str
        The file, for the messages.

    Notes
    -----
    For ``pose_left``/``pose_right`` (together), ``flange_left``/``flange_right``
    (together) and ``hand_eye``, written in a form with a translation (``position``
    or ``matrix``) and no ``unit``: a :class:`~robostereo.errors.PlausibilityWarning`
    when every translation component is under :data:`METRES_AS_MM_BELOW` mm and the
    scene's far depth is unknown or at least 100 mm.  A hand-eye transform that is the
    identity (camera frame = flange frame) is a placeholder, not a calibration: a
    warning too.
    """
    far = capture.depth_range_mm[1] if capture.depth_range_mm is not None else None
    if far is not None and far < 100.0:
        return
    groups = (("pose_left", "pose_right"), ("flange_left", "flange_right"), ("hand_eye",))
    for keys in groups:
        poses = [getattr(capture, k) for k in keys]
        if all(p is not None for p in poses):
            warn_metres(source, " and ".join(keys), [data.get(k) for k in keys], poses, far,
                        hand_eye=keys[0] == "hand_eye")
    warn_identity_hand_eye(source, capture.hand_eye)
