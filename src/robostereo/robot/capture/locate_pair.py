"""Locating a capture's object points in the world frame (the thesis, 2.2, 3.6, 4.2).

A *capture* is what the thesis's VAL-II program leaves behind: two grabbed images, the
camera and the two camera poses the robot reported.  :func:`locate` turns one into 3-D
points in the robot's world frame with a per-point depth bound:

1. the epipolar frame of the two poses: for two SCARA poses (camera looking down,
   equal heights, no lens distortion) the thesis's
   (:class:`~robostereo.geometry.scara_rectification.EpipolarGeometry`: ``alpha``,
   ``theta_l``, ``theta_r``, ``D``), for any other pair of 6-DoF poses
   :class:`~robostereo.geometry.pose_rectification.GeneralEpipolarGeometry` (relative pose,
   OpenCV ``stereoRectify`` with the intrinsics and distortion);
2. each image rectified (rows become epipolar lines), the pixels whose source lies
   outside the grabbed image filled by replicating the nearest valid pixel of the
   same row (:func:`rectify_pair`);
3. the matcher of chapter 3 (:func:`robostereo.matcher.pipeline.match_stereo`) on the two
   rectified images, within the capture's disparity range, told which pixels are
   filled so that no edge point whose features would see the fill is used;
4. eq. (6)-(9) (:func:`robostereo.geometry.triangulation.triangulate`) in the epipolar frame,
   then :meth:`~robostereo.geometry.scara_rectification.EpipolarGeometry.to_world`.

The captures themselves and their folders (:class:`Capture`, :func:`read_capture`,
:func:`write_capture`, the folder format) are in :mod:`robostereo.robot.capture.capture_folder`;
their names are re-exported here.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, warn_input
from robostereo.geometry.pose_rectification import GeneralEpipolarGeometry
from robostereo.geometry.scara_rectification import rectified_valid_mask
from robostereo.matcher.parameters import MatchParameters
from robostereo.matcher.pipeline import MatchResult, match_stereo
from robostereo.robot.capture.capture_folder import (
    CAPTURE_YAML,
    Capture,
    Geometry,
    Rectification,
    read_capture,
)
from robostereo.robot.capture.capture_keys import hand_eye_bound_mm

__all__ = [
    "MIN_EDGE_POINTS_FOR_FRACTION",
    "MIN_LOCATED_FRACTION",
    "LocateParameters",
    "Located",
    "RectifiedPair",
    "check_shared_scene",
    "fill_invalid_rows",
    "locate",
    "locate_capture",
    "rectify_pair",
    "searched_depths",
]


# ------------------------------------------------------------------------ rectification


def fill_invalid_rows(image: ArrayLike, valid: ArrayLike) -> NDArray[np.float64]:
    """Fill invalid pixels with the nearest valid pixel of the same row.

    Along a row the fill is constant, so it adds no gradient along the epipolar line
    (no edge points) beyond what the valid pixel already has.  Rows without any valid
    pixel take the value 0.

    Parameters
    ----------
    image : array_like, shape (H, W)
    valid : array_like of bool, shape (H, W)
        True where `image` holds data; the valid pixels of a row must be contiguous
        (true of a rectified image, whose valid region is a parallelogram).

    Returns
    -------
    ndarray of float64, shape (H, W)

    Examples
    --------
    >>> img = np.array([[np.nan, 3.0, 5.0, np.nan], [np.nan] * 4])
    >>> fill_invalid_rows(img, np.isfinite(img))
    array([[3., 3., 5., 5.],
           [0., 0., 0., 0.]])
    """
    img = np.array(image, dtype=np.float64)
    ok = np.asarray(valid, dtype=bool)
    if img.ndim != 2 or ok.shape != img.shape:
        raise InputError(f"image and valid must be (H, W) of one shape, got {img.shape} "
                         f"and {ok.shape}")
    w = img.shape[1]
    cols = np.arange(w)[None, :]
    before = np.maximum.accumulate(np.where(ok, cols, -1), axis=1)
    after = np.minimum.accumulate(np.where(ok, cols, w)[:, ::-1], axis=1)[:, ::-1]
    src = np.where(before >= 0, before, after)
    has = (src >= 0) & (src < w)
    vals = np.take_along_axis(img, np.clip(src, 0, w - 1), axis=1)
    out = np.where(ok, img, np.where(has, vals, 0.0))
    return out


@dataclass(frozen=True)
class RectifiedPair:
    """The two views rectified to the epipolar frame.

    Attributes
    ----------
    left, right : ndarray of float64, shape (H, W)
        Rectified images on the capture's grey scale, invalid pixels filled
        (:func:`fill_invalid_rows`).
    valid_left, valid_right : ndarray of bool, shape (H, W)
        Pixels whose source lies inside the grabbed image.
    geometry : EpipolarGeometry or GeneralEpipolarGeometry
    """

    left: NDArray[np.float64]
    right: NDArray[np.float64]
    valid_left: NDArray[np.bool_]
    valid_right: NDArray[np.bool_]
    geometry: Geometry


def _grey(image: NDArray[Any]) -> NDArray[np.float64]:
    img = np.asarray(image)
    if img.ndim == 3:
        from robostereo.matcher.grey_levels import to_grey

        # colour: luminance on the image's own scale (to_grey with bit depth 7 keeps it)
        return to_grey(img.astype(np.float64), bit_depth=7).astype(np.float64)
    return img.astype(np.float64)


def rectify_pair(
    left: ArrayLike,
    right: ArrayLike,
    geometry: Geometry,
    *,
    interpolation: Literal["nearest", "linear", "cubic", "lanczos4"] = "linear",
) -> RectifiedPair:
    """Rectify both views and fill what falls outside the images.

    The thesis's theta rectification for an :class:`EpipolarGeometry`, OpenCV's
    (with undistortion) for a
    :class:`~robostereo.geometry.pose_rectification.GeneralEpipolarGeometry`.

    Parameters
    ----------
    left, right : array_like, shape (H, W) (or (H, W, 3) colour)
        Grabbed images of the left and right viewpoints.
    geometry : EpipolarGeometry or GeneralEpipolarGeometry
    interpolation : str
        Interpolator of :func:`robostereo.geometry.scara_rectification.rectify_image`
        (default linear: on the simulated block its sub-pixel edges were nearer the
        truth than cubic's).

    Returns
    -------
    RectifiedPair

    Notes
    -----
    1. ``geometry.rectify(image, side)`` for each side (NaN outside the source image).
    2. Fill each row's NaN run with the row's nearest valid pixel, which puts no
       gradient along the row: no fake edge points at the fill boundary.

    References
    ----------
    Kim (1989), the thesis, 2.2 (each image turned by its theta), 4.2.1.
    """
    out: dict[str, Any] = {}
    for side, img in (("left", left), ("right", right)):
        r = geometry.rectify(_grey(np.asarray(img)), side, interpolation=interpolation)
        if isinstance(geometry, GeneralEpipolarGeometry):
            valid = geometry.valid_mask(side)
        else:
            valid = rectified_valid_mask(geometry.camera, geometry.theta(side))
        out[side] = fill_invalid_rows(r, valid)
        out[f"valid_{side}"] = valid
    return RectifiedPair(geometry=geometry, **out)


# ------------------------------------------------------------------------------ locate


@dataclass(frozen=True)
class LocateParameters:
    """Tuning of :func:`locate`.

    Attributes
    ----------
    match : MatchParameters
        The matcher's parameters; its ``bit_depth`` is replaced by the capture's.
        Default: robostereo's defaults (sub-pixel edges, threshold 8, every row).
    interpolation : str
        Rectification interpolator (:func:`rectify_pair`).
    rectification : {'auto', 'theta', 'general'}
        :meth:`Capture.geometry`: the thesis's theta rectification for SCARA captures
        and OpenCV's for all others (``'auto'``), or one of them forced.
    """

    match: MatchParameters = field(default_factory=MatchParameters)
    interpolation: Literal["nearest", "linear", "cubic", "lanczos4"] = "linear"
    rectification: Rectification = "auto"

    def __post_init__(self) -> None:
        if not isinstance(self.match, MatchParameters):
            raise InputError("match must be a MatchParameters")
        if self.rectification not in ("auto", "theta", "general"):
            raise InputError(f"rectification must be 'auto', 'theta' or 'general', got "
                             f"{self.rectification!r}")


@dataclass(frozen=True)
class Located:
    """Object points found in a capture.

    Attributes
    ----------
    capture : Capture
    rectified : RectifiedPair
    result : MatchResult
        The matcher's full result on the rectified pair (all stages).
    row, x_left, x_right, disparity, probability : ndarray, shape (M,)
        Reported matches: rectified row and columns (pixels), disparity, probability.
    epipolar_xyz : ndarray, shape (M, 3)
        Eq. (6)-(8) in the epipolar frame, millimetres.
    z_bound : ndarray, shape (M,)
        Eq. (9) depth bound, millimetres.
    world : ndarray, shape (M, 3)
        The points in the world frame, millimetres.
    left_pixel : ndarray, shape (M, 2)
        ``(x, y)`` of each left point in the grabbed (unrectified) left image.
    disparity_range : tuple of float
    """

    capture: Capture
    rectified: RectifiedPair
    result: MatchResult
    row: NDArray[np.intp]
    x_left: NDArray[np.float64]
    x_right: NDArray[np.float64]
    disparity: NDArray[np.float64]
    probability: NDArray[np.float64]
    epipolar_xyz: NDArray[np.float64]
    z_bound: NDArray[np.float64]
    world: NDArray[np.float64]
    left_pixel: NDArray[np.float64]
    disparity_range: tuple[float, float]

    def __len__(self) -> int:
        return int(self.row.shape[0])

    @property
    def geometry(self) -> Geometry:
        return self.rectified.geometry

    def matches_after(self, iteration: int) -> NDArray[np.intp]:
        """Accepted matches after `iteration` relaxation iterations, -1 for none
        (:meth:`MatchResult.matches_after`)."""
        return self.result.matches_after(iteration)

    def table(self) -> dict[str, NDArray[Any]]:
        """The columns ``robostereo locate`` writes.

        ``X_w, Y_w, Z_w`` (world, mm), ``X, Y, Z`` (epipolar frame, mm), ``z_bound``
        (eq. 9, mm), ``row, x_left, x_right`` (rectified pixels), ``u_left, v_left``
        (pixel position in the grabbed left image), ``disparity`` (px), ``confidence``
        (the match's probability of being right).
        """
        return {
            "X_w": self.world[:, 0], "Y_w": self.world[:, 1], "Z_w": self.world[:, 2],
            "X": self.epipolar_xyz[:, 0], "Y": self.epipolar_xyz[:, 1],
            "Z": self.epipolar_xyz[:, 2], "z_bound": self.z_bound,
            "row": self.row, "x_left": self.x_left, "x_right": self.x_right,
            "u_left": self.left_pixel[:, 0], "v_left": self.left_pixel[:, 1],
            "disparity": self.disparity, "confidence": self.probability,
        }


MIN_LOCATED_FRACTION = 0.05
"""Fewest located edge points, as a fraction of the left view's, before :func:`locate`
warns that the poses are probably wrong (order or convention).

Correct simulated captures located 48.8 % (six-axis hub-pulley, the worst) to 100 %
(SCARA block and hub-pulley, six-axis block); the six-axis block with its hand-eye
quaternion read in (w, x, y, z) order located 0 of 411, and a tester's capture with a
(w, x, y, z) quaternion 0.6 % (65 of 11 018).  5 % lies ten times below the worst
correct capture and well above the wrong ones; a scene of few, weak or occluded edges
can fall below it rightly, hence a warning, not an error.  Not every wrong pose shows:
both camera poses' quaternions in (w, x, y, z) order still located 94 % of the block
(a consistent but wrong world frame)."""

MIN_EDGE_POINTS_FOR_FRACTION = 200
"""Left edge points below which the located fraction says nothing (no warning)."""

_SCENE_GRID = 21  # pixels per image side sampled by the shared-scene check
_SCENE_DEPTHS = 9  # depths sampled over the searched range


def searched_depths(capture: Capture, geometry: Geometry,
                    drange: tuple[float, float]) -> tuple[float, float] | None:
    """``(near, far)`` depth, mm, that a locate searches: the capture's
    ``depth_range_mm``, or the disparity range's ``fx D / d`` (a disparity below a
    quarter pixel taken as a quarter pixel); None if it searches no positive depth."""
    if capture.depth_range_mm is not None:
        return capture.depth_range_mm
    lo, hi = drange
    if not hi > 0:
        return None
    f = float(capture.stereo_camera(geometry).fx) * geometry.baseline_mm
    return f / hi, f / max(lo, 0.25)


def check_shared_scene(capture: Capture, geometry: Geometry,
                       drange: tuple[float, float]) -> None:
    """Raise :class:`InputError` if no point of either view, at the searched depths,
    falls inside the other view's image.

    Parameters
    ----------
    capture : Capture
    geometry : EpipolarGeometry or GeneralEpipolarGeometry
    drange : tuple of float
        The disparity range searched.

    Notes
    -----
    1. The searched depths (:func:`searched_depths`), 9 of them, geometric.
    2. A 21 x 21 grid of each view's pixels back-projected to each depth
       (:meth:`Camera.backproject`, distortion included) and projected into the other
       view (:meth:`Camera.project`).
    3. Views share a scene when some of these points lie in front of the other camera
       and inside its image, both ways.  Rectified rows shared by both views (the
       former check) are not enough: two views side by side 400 mm apart share every
       row and no scene, and their "matches" lay 4.3 m below the table.
    """
    depths = searched_depths(capture, geometry, drange)
    if depths is None:
        return
    cam = capture.camera
    w, h = cam.image_size
    g = np.linspace(0.0, 1.0, _SCENE_GRID)
    u, v = np.meshgrid(g * (w - 1), g * (h - 1))
    pix = np.column_stack([u.ravel(), v.ravel()])
    zs = np.geomspace(depths[0], depths[1], _SCENE_DEPTHS)
    pix_all = np.tile(pix, (len(zs), 1))
    z_all = np.repeat(zs, len(pix))
    poses = {"left": capture.pose_left, "right": capture.pose_right}
    for a, b in (("left", "right"), ("right", "left")):
        world = cam.backproject(pix_all, z_all, poses[a])
        with np.errstate(all="ignore"):
            uv, z = cam.project(world, poses[b])
        inside = (z > 0) & (uv[:, 0] >= -0.5) & (uv[:, 0] <= w - 0.5) \
            & (uv[:, 1] >= -0.5) & (uv[:, 1] <= h - 0.5)
        if not inside.any():
            raise InputError(
                f"the two views share no scene: no point of the {a} view at depths "
                f"{depths[0]:.4g} .. {depths[1]:.4g} mm falls in the {b} image (views "
                f"{geometry.baseline_mm:.4g} mm apart); check the poses and the depth or "
                "disparity range")


def locate(capture: Capture, *, params: LocateParameters | None = None,
           source: str = "capture") -> Located:
    """Match a capture's two views and give the object points in the world frame.

    Parameters
    ----------
    capture : Capture
    params : LocateParameters, optional
    source : str
        Name of the capture in errors and warnings (its file, when read from one).

    Returns
    -------
    Located

    Raises
    ------
    InputError
        Views that share no scene at the searched depths (:func:`check_shared_scene`).

    Warns
    -----
    PlausibilityWarning
        Fewer than :data:`MIN_LOCATED_FRACTION` of the left edge points located.

    Notes
    -----
    1. Epipolar frame of the two reported poses (the thesis, 2.2; :meth:`Capture.geometry`).
    2. Check that the views share a scene (:func:`check_shared_scene`).
    3. Rectify and fill (:func:`rectify_pair`).
    4. :func:`robostereo.matcher.pipeline.match_stereo` with the capture's bit depth and
       disparity range (chapter 3).
    5. Eq. (6)-(9) with :func:`robostereo.geometry.triangulation.triangulate` (rectified
       ``fx``, ``fy`` are the camera's, the frame holds both views; ``D`` from the poses),
       then to the world frame.
    6. Each left point mapped back to the grabbed image (exact point map).
    7. Warn when few edge points located (:data:`MIN_LOCATED_FRACTION`).

    References
    ----------
    Kim (1989), the thesis, 2.2, chapter 3, 3.6 (eq. 6-8), 3.7 (eq. 9), 4.2.
    """
    p = params or LocateParameters()
    try:
        geometry = capture.geometry(p.rectification)
        drange = capture.resolved_disparity_range(geometry)
        if not drange[1] >= 1.0:
            raise InputError(
                f"baseline D = {geometry.baseline_mm:.3g} mm gives disparities of at most "
                f"{drange[1]:g} px over the searched range: too short to measure depth")
        check_shared_scene(capture, geometry, drange)
        if isinstance(geometry, GeneralEpipolarGeometry):
            geometry.check_overlap()
    except InputError as e:
        msg = str(e)
        raise InputError(msg if msg.startswith(source) else f"{source}: {msg}") from None
    rect = rectify_pair(capture.left, capture.right, geometry,
                        interpolation=p.interpolation)
    mp = replace(p.match, bit_depth=int(capture.bit_depth))
    sc = capture.stereo_camera(geometry)
    result = match_stereo(rect.left, rect.right, drange, params=mp, camera=sc,
                          valid_left=rect.valid_left, valid_right=rect.valid_right)
    n_edges = len(result.left_edges)
    if n_edges >= MIN_EDGE_POINTS_FOR_FRACTION and len(result) < MIN_LOCATED_FRACTION * n_edges:
        warn_input(f"{source}: only {len(result)} of {n_edges} edge points located "
                   f"({100 * len(result) / n_edges:.1f} %, under "
                   f"{100 * MIN_LOCATED_FRACTION:g} %): are the poses right (left/right "
                   "order, quaternion order x, y, z, w, hand-eye direction, unit)?")
    rows, xl, xr = result.rows, result.x_left, result.x_right
    xyz, zb = result.triangulated()
    if len(rows) and capture.hand_eye_uncertainty_deg:  # the world tilts with the hand-eye
        zb = zb + hand_eye_bound_mm(xyz[:, 2], capture.hand_eye_uncertainty_deg)
    world = geometry.to_world(xyz) if len(rows) else np.zeros((0, 3))
    pix = geometry.from_rectified(np.column_stack([xl, rows.astype(float)]), "left") \
        if len(rows) else np.zeros((0, 2))
    return Located(
        capture=capture, rectified=rect, result=result,
        row=rows, x_left=xl, x_right=xr, disparity=result.disparity,
        probability=result.probability, epipolar_xyz=xyz, z_bound=zb, world=world,
        left_pixel=pix, disparity_range=drange,
    )


def locate_capture(
    directory: str | os.PathLike[str], *, params: LocateParameters | None = None
) -> Located:
    """:func:`read_capture` then :func:`locate`; writes nothing.

    Parameters
    ----------
    directory : path
        A capture folder (format: :mod:`robostereo.robot.capture.capture_folder`).
    params : LocateParameters, optional

    Returns
    -------
    Located
        ``.world`` (M, 3) world millimetres, ``.z_bound`` (M,) eq. (9) bounds,
        ``.table()`` the columns of ``robostereo locate``.
    """
    from pathlib import Path

    return locate(read_capture(directory), params=params,
                  source=str(Path(directory) / CAPTURE_YAML))
