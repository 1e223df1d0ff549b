"""Folders of N-view captures: ``capture.yaml`` with a list of views, and its images.

A :class:`~robostereo.robot.views.viewpoints.ViewsCapture` (N >= 2 views of one camera moved by the
robot) is kept in a folder by :func:`write_views_capture` and read back by
:func:`read_views_capture`, which reads the two-view folders of
:mod:`robostereo.robot.capture.capture_folder` as well (as N = 2, left view first).

Folder format (``DIR/``)::

    view_00.png, ...      the grabbed (unrectified) images, 8-bit PNG, grey levels as
                          grabbed (0..127 for the thesis's 7-bit camera)
    capture.yaml          camera:          camera mapping or camera file (as in a two-view
                                           capture: physical, or in pixels)
                          pose_convention: camera_to_world (default) or world_to_camera:
                                           what every view's pose maps
                          views:           one entry per view, in order:
                            - image: view_00.png   the view's image, in DIR
                              pose: {...}          its camera pose (T_world_camera) in
                                                   any form of robostereo.geometry.poses
                              pose_convention: ... (optional) this view's own
                              depth: depth/view_00.pfm  (optional) its ground-truth
                                                   depth map, read only by
                                                   robostereo evaluate
                            - image: view_01.png   or the flange pose the robot
                              flange: {...}        reported, with a top-level hand_eye
                          hand_eye:        flange-to-camera transform (with flange views:
                                           camera = flange @ hand_eye)
                          depth_range_mm:  [near, far] expected depth of the object
                          bit_depth:       7 (optional; default the PNGs')
                          uncertainty:     {baseline_mm, focal_length_mm, disparity_px,
                                            rotation_deg, hand_eye_deg}
                                           (optional, eq. 9; focal_px for a camera in
                                           pixels)
                          robot, scene:    free-form notes (optional, not read)
                          depth_scale:     units per mm of 16-bit PNG depth maps
                                           (optional, default 1)

Every view gives either ``pose`` or ``flange``, and all views the same one.  N views
need a depth range (each pair of views has its own disparity range), so
``disparity_range`` belongs to two-view folders only.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping, Sequence
from pathlib import Path, PurePosixPath
from typing import Any

import numpy as np

from robostereo.errors import InputError, shown
from robostereo.evaluation.depth_maps import depth_map_files
from robostereo.geometry.camera import camera_to_dict
from robostereo.geometry.poses import SE3, as_se3, pose_from_dict, pose_to_dict
from robostereo.robot.capture.capture_folder import CAPTURE_YAML, read_capture
from robostereo.robot.capture.capture_keys import (
    DEPTH_SCALE_KEY,
    VIEW_DEPTH_KEY,
    camera_pose_from_dict,
    check_views_share_scene,
    extras_from_dict,
    extras_to_dict,
    pose_convention,
    warn_identity_hand_eye,
    warn_metres,
)
from robostereo.robot.views.viewpoints import ViewsCapture

__all__ = [
    "VIEWS_KEYS",
    "is_views_folder",
    "read_views_capture",
    "views_capture_to_dict",
    "views_folder_files",
    "write_views_capture",
]

#: the top-level keys of an N-view ``capture.yaml``
VIEWS_KEYS: tuple[str, ...] = (
    "camera", "views", "hand_eye", "depth_range_mm", "bit_depth", "uncertainty", "robot",
    "scene", "pose_convention", DEPTH_SCALE_KEY,
)
_VIEW_KEYS = ("image", "pose", "flange", "pose_convention", VIEW_DEPTH_KEY)


def _image_names(capture: ViewsCapture) -> tuple[str, ...]:
    """The capture's own file names when they can be written into a folder, otherwise
    ``view_00.png``, ``view_01.png``, ..."""
    n = len(capture)
    if capture.names is not None:
        for k, name in enumerate(capture.names):
            p = PurePosixPath(name)
            if len(p.parts) != 1 or name in (".", "..") or p.suffix.lower() != ".png" \
                    or name == CAPTURE_YAML or "\\" in name:
                raise InputError(f"names: view {k}'s file name {name!r} must be a plain file "
                                 "name ending in .png")
        return capture.names
    width = max(2, len(str(n - 1)))
    return tuple(f"view_{k:0{width}d}.png" for k in range(n))


def views_capture_to_dict(capture: ViewsCapture,
                          names: tuple[str, ...] | None = None) -> dict[str, Any]:
    """The ``capture.yaml`` mapping of an N-view capture.

    Parameters
    ----------
    capture : ViewsCapture
    names : tuple of str, optional
        The image file of each view; default the capture's `names`, or ``view_00.png``,
        ``view_01.png``, ...

    Returns
    -------
    dict
        Plain YAML values; flange poses and ``hand_eye`` when the capture has them,
        otherwise the camera poses.
    """

    names = _image_names(capture) if names is None else names
    flanges = capture.flanges if capture.hand_eye is not None else None
    views = []
    for k, name in enumerate(names):
        if flanges is not None:
            views.append({"image": name, "flange": pose_to_dict(flanges[k])})
        else:
            views.append({"image": name, "pose": pose_to_dict(capture.poses[k])})
    out: dict[str, Any] = {"camera": camera_to_dict(capture.camera), "views": views}
    if flanges is not None:
        assert capture.hand_eye is not None
        out["hand_eye"] = pose_to_dict(capture.hand_eye)
    out["depth_range_mm"] = [float(v) for v in capture.depth_range_mm]
    out["bit_depth"] = int(capture.bit_depth)
    out.update(extras_to_dict(capture))
    return out


def write_views_capture(directory: str | os.PathLike[str], capture: ViewsCapture, *,
                        depth_maps: Sequence[Any] | None = None,
                        depth_suffix: str = ".npy") -> Path:
    """Write an N-view capture folder: one PNG per view and ``capture.yaml``.

    The folder is assembled beside `directory` and renamed into place at the end, so a
    failure leaves nothing behind.  `directory` must not exist or be an empty folder.

    Parameters
    ----------
    directory : path
    capture : ViewsCapture
        Grey (H, W) images of integers 0..255.  Its `names` (plain ``.png`` file names)
        name the images; without them ``view_00.png``, ``view_01.png``, ...
    depth_maps : sequence of ndarray, optional
        One (H, W) ground-truth depth map per view (mm along its optical axis), written
        as ``depth/<image stem><depth_suffix>`` for ``robostereo evaluate``, in the same
        all-or-nothing folder as the images.
    depth_suffix : {'.npy', '.pfm'}
        The depth maps' file type.

    Returns
    -------
    Path
        `directory`.

    Raises
    ------
    InputError
        The parent folder is missing, `directory` is a non-empty folder or a file, an
        image is not 8-bit representable, or a name is not a plain ``.png`` file name.

    Examples
    --------
    >>> import tempfile
    >>> from robostereo.geometry.camera import SEED_CAMERA
    >>> from robostereo.geometry.poses import se3_from_scara
    >>> w, h = SEED_CAMERA.image_size
    >>> cap = ViewsCapture(tuple(np.zeros((h, w), np.uint8) for _ in range(3)), SEED_CAMERA,
    ...                    tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20, 0, 20)),
    ...                    depth_range_mm=(900.0, 1100.0))
    >>> d = write_views_capture(Path(tempfile.mkdtemp()) / "cap", cap)
    >>> sorted(p.name for p in d.iterdir())
    ['capture.yaml', 'view_00.png', 'view_01.png', 'view_02.png']
    >>> [p.x for p in read_views_capture(d).poses]
    [-20.0, 0.0, 20.0]
    """
    if not isinstance(capture, ViewsCapture):
        raise InputError(f"capture must be a ViewsCapture, got {type(capture).__name__}")
    names = _image_names(capture)
    images = {}
    for k, (name, img) in enumerate(zip(names, capture.images, strict=True)):
        a = np.asarray(img)
        if a.ndim != 2 or not np.issubdtype(a.dtype, np.integer) or a.min() < 0 \
                or a.max() > 255:
            raise InputError(f"view {k} ({name}): the image must be a grey (H, W) image of "
                             "integers 0..255 to be written as an 8-bit PNG")
        images[name] = a.astype(np.uint8)
    from robostereo.io import folder_yaml_text, write_image_folder

    text = folder_yaml_text(views_capture_to_dict(capture, names))
    return write_image_folder(directory, images, {CAPTURE_YAML: text},
                              depth_map_files([Path(n).stem for n in names], depth_maps,
                                              suffix=depth_suffix))


def is_views_folder(directory: str | os.PathLike[str]) -> bool:
    """Whether `directory` holds an N-view capture (a ``views:`` list in its
    ``capture.yaml``) rather than a two-view one.

    A folder without a readable ``capture.yaml`` is not one (False): its reader says
    what is wrong with it.
    """
    from robostereo.io import read_folder_yaml

    try:
        data, _ = read_folder_yaml(directory, CAPTURE_YAML, folder="capture")
    except InputError:
        return False
    return isinstance(data, Mapping) and "views" in data


def views_folder_files(directory: str | os.PathLike[str]) -> list[Path]:
    """The files a capture folder's reader opens: ``capture.yaml``, the camera file it
    names (if any) and every view's image (two-view folders: ``left.png`` and
    ``right.png``); for refusing them as outputs.

    A file list that cannot be read (a bad ``capture.yaml``) gives only ``capture.yaml``;
    :func:`read_views_capture` reports what is wrong with it.
    """
    from robostereo.io import read_folder_yaml

    d = Path(directory)
    out = [d / CAPTURE_YAML]
    try:
        data, _ = read_folder_yaml(d, CAPTURE_YAML, folder="capture")
    except InputError:
        return out
    if not isinstance(data, Mapping):
        return out
    if isinstance(data.get("camera"), str):  # a camera file the folder names
        out.append(d / data["camera"])
    if "views" not in data:
        return [*out, d / "left.png", d / "right.png"]
    views = data["views"]
    if isinstance(views, list):
        out += [d / str(v["image"]) for v in views
                if isinstance(v, Mapping) and isinstance(v.get("image"), str)]
    return out


def read_views_capture(directory: str | os.PathLike[str]) -> ViewsCapture:
    """Read a capture folder of N views, or a two-view one as N = 2.

    Parameters
    ----------
    directory : path
        A folder written by :func:`write_views_capture` (or by hand, or a robot), or a
        two-view folder of :func:`~robostereo.robot.capture.capture_folder.write_capture`.

    Returns
    -------
    ViewsCapture
        With `names` the image files (``left.png``, ``right.png`` for a two-view folder).

    Raises
    ------
    InputError
        One line naming the file and, where one is at fault, the view: a missing folder,
        ``capture.yaml`` or image, invalid YAML, unknown or bad keys, fewer than two
        views, a view without a pose (or without a flange pose, or flange poses without
        ``hand_eye``), two views of one image file (under any name: ``./a.png``, a link),
        an image that cannot be decoded or whose size is not the camera's, all views at
        one point; a two-view folder whose disparity range reaches zero (it has no depth
        range).

    Notes
    -----
    Warns (:class:`~robostereo.errors.PlausibilityWarning`) as two-view folders do when
    every translation of the views' poses (or flanges, or ``hand_eye``) written with a
    ``position`` or ``matrix`` and no ``unit`` is under
    :data:`~robostereo.robot.capture.capture_folder.METRES_AS_MM_BELOW` mm while the object is
    100 mm or more away (metres written as millimetres), and when ``hand_eye`` is the
    identity (a placeholder, not a calibration).
    """
    from robostereo.io import folder_file, read_folder_yaml
    from robostereo.io.images import load_image

    data, ypath = read_folder_yaml(directory, CAPTURE_YAML, folder="capture")
    d = ypath.parent
    src = str(ypath)
    if isinstance(data, Mapping) and "views" not in data:
        two = read_capture(d)
        try:
            vc = ViewsCapture.from_capture(two)
        except InputError as exc:
            raise InputError(f"{src}: {exc}") from None
        return dataclasses.replace(vc, names=("left.png", "right.png"))
    if not isinstance(data, Mapping):
        raise InputError(f"{src}: expected a mapping with keys camera, views, "
                         "depth_range_mm")
    unknown = [k for k in data if k not in VIEWS_KEYS]
    if unknown:
        hint = (" (N views take depth_range_mm, each pair has its own disparities)"
                if unknown[0] == "disparity_range" else "")
        raise InputError(f"{src}: unknown key '{unknown[0]}' in a capture with views "
                         f"(allowed: {', '.join(VIEWS_KEYS)}){hint}")
    for key in ("camera", "depth_range_mm"):
        if key not in data:
            raise InputError(f"{src}: missing key '{key}'")
    from robostereo.io.camera_file import camera_from_entry

    camera = camera_from_entry(data["camera"], d, src)
    convention = pose_convention(data, src)
    views = data["views"]
    if not isinstance(views, list):
        raise InputError(f"{src}: key 'views' must be a list of {{image, pose}} or "
                         f"{{image, flange}} entries, got {type(views).__name__}")
    if len(views) < 2:
        raise InputError(f"{src}: views: a capture needs at least two views, got "
                         f"{len(views)}")
    hand_eye = None
    if data.get("hand_eye") is not None:
        hand_eye = as_se3(pose_from_dict(data["hand_eye"], source=f"{src}: hand_eye"))
    names: list[str] = []
    files: list[Path] = []
    poses: list[SE3] = []
    flanges: list[SE3] = []
    kinds: set[str] = set()
    for k, view in enumerate(views):
        where = f"{src}: views[{k}]"
        if not isinstance(view, Mapping):
            raise InputError(f"{where}: expected a mapping {{image, pose}} or "
                             f"{{image, flange}}, got {shown(view)}")
        bad = [key for key in view if key not in _VIEW_KEYS]
        if bad:
            raise InputError(f"{where}: unknown key '{bad[0]}' (allowed: "
                             f"{', '.join(_VIEW_KEYS)})")
        name = view.get("image")
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"{where}: missing key 'image' (the view's image file)")
        where = f"{src}: views[{k}] ({name})"
        try:  # an absolute path into the folder is taken relative to it
            name = folder_file(d, name)
        except InputError:
            raise InputError(f"{where}: the image must be a file inside the capture "
                             "folder") from None
        # one file under two names ('./a.png', a link to a.png) is one image too
        file = (d / name).resolve()
        if file in files:
            raise InputError(f"{where}: the same image file as views[{files.index(file)}]: "
                             "every view needs its own image")
        names.append(name)
        files.append(file)
        has = [key for key in ("pose", "flange") if key in view]
        if not has:
            raise InputError(f"{where}: missing key 'pose' (the camera pose; or 'flange' "
                             "with a top-level hand_eye)")
        if len(has) == 2:
            raise InputError(f"{where}: give 'pose' or 'flange', not both")
        kinds.add(has[0])
        if len(kinds) > 1:
            raise InputError(f"{where}: gives '{has[0]}' where the views before give the "
                             "other: give every view a pose, or every view a flange")
        if has[0] == "flange":
            if hand_eye is None:
                raise InputError(f"{where}: a flange pose needs the top-level key "
                                 "'hand_eye' (camera = flange @ hand_eye)")
            f = as_se3(pose_from_dict(view["flange"], source=f"{where}: flange"))
            flanges.append(f)
            poses.append(f @ hand_eye)
        else:
            poses.append(camera_pose_from_dict(view["pose"], f"{where}: pose",
                                               pose_convention(view, where, convention)))
    if hand_eye is not None and not flanges:
        raise InputError(f"{src}: key 'hand_eye' is for views given by 'flange'; these "
                         "views give camera poses")
    w, h = camera.image_size
    images = []
    bits = []
    for k, name in enumerate(names):
        where = f"{src}: views[{k}] ({name})"
        try:
            img, b = load_image(d / name)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
        if img.shape[:2] != (h, w):
            raise InputError(f"{where}: the image is {img.shape[1]} x {img.shape[0]} pixels, "
                             f"the camera's image_size is {w} x {h}")
        images.append(img)
        bits.append(b)
    kw = _settings(data, src, max(bits), camera)
    try:
        if flanges:
            assert hand_eye is not None
            capture = ViewsCapture.from_flange(images, camera, flanges=flanges,
                                               hand_eye=hand_eye, names=tuple(names),
                                               **kw)
        else:
            capture = ViewsCapture(tuple(images), camera, tuple(poses), names=tuple(names),
                                   **kw)
    except InputError as exc:
        raise InputError(f"{src}: {exc}") from None
    _warn_units(data, capture, src)
    if not flanges:
        check_views_share_scene(camera, [as_se3(p) for p in capture.poses],
                                capture.depth_range_mm,
                                [f"views[{k}] ({n})" for k, n in enumerate(names)], src,
                                convention)
    return capture


def _settings(data: Mapping[str, Any], src: str, file_bits: int,
              camera: Any) -> dict[str, Any]:
    """``depth_range_mm``, ``bit_depth``, the eq. 9 uncertainties and the notes of a views
    file."""
    rng = data["depth_range_mm"]
    ok = isinstance(rng, list) and len(rng) == 2 and all(
        isinstance(v, int | float) and not isinstance(v, bool) for v in rng)
    if not ok:
        raise InputError(f"{src}: key 'depth_range_mm' must be [near, far] in mm, got "
                         f"{shown(rng)}")
    kw: dict[str, Any] = {"depth_range_mm": tuple(rng)}  # the capture checks the values
    bit_depth = data.get("bit_depth", file_bits)
    if isinstance(bit_depth, bool) or not isinstance(bit_depth, int):
        raise InputError(f"{src}: key 'bit_depth' must be an integer, got {shown(bit_depth)}")
    kw["bit_depth"] = bit_depth
    kw.update(extras_from_dict(data, src, camera))
    return kw


def _warn_units(data: Mapping[str, Any], capture: ViewsCapture, src: str) -> None:
    """Warn about translations that look like metres read as mm, and an identity hand-eye
    (the checks of :func:`~robostereo.robot.capture.capture_folder.warn_units`, for views)."""
    far = capture.depth_range_mm[1]
    if far >= 100.0:
        key = "flange" if capture.flanges is not None else "pose"
        warn_metres(src, f"every view's {key}", [v.get(key) for v in data["views"]],
                    list(capture.flanges if capture.flanges is not None else capture.poses),
                    far)
        if capture.hand_eye is not None:
            warn_metres(src, "hand_eye", [data.get("hand_eye")], [capture.hand_eye], far,
                        hand_eye=True)
    warn_identity_hand_eye(src, capture.hand_eye)
