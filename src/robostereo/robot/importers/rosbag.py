"""ROS bags: a camera's images, its ``camera_info`` and the arm's ``/tf`` as views.

A ROS 1 bag (``.bag``) or a ROS 2 bag (a folder with ``metadata.yaml`` and its
``sqlite3`` or ``mcap`` files) is read with the ``rosbags`` library
(``pip install 'robostereo[ros]'``):

* the images: ``sensor_msgs/Image`` (``mono8``, ``mono16``, ``rgb8``, ``bgr8``,
  ``rgba8``, ``bgra8``) or ``sensor_msgs/CompressedImage`` (JPEG or PNG), stamped by
  their ``header.stamp``; each chosen image is written to a work folder (a raw one as
  PNG, a compressed one as it is) for
  :func:`~robostereo.robot.importers.imported_views.views_capture_from_imported`,
  which makes it 8-bit grey as for every importer;
* the camera: ``sensor_msgs/CameraInfo`` (:func:`intrinsics_from_camera_info`): ``K``
  (OpenCV's convention, as robostereo's: the top-left pixel's centre at ``(0, 0)``),
  the image size, ``D`` of the ``plumb_bob`` or ``rational_polynomial`` model in
  OpenCV's order;
* the poses: ``tf2_msgs/TFMessage`` on ``/tf`` and ``/tf_static``
  (:class:`~robostereo.robot.importers.tf_frames.TransformTree`), the camera frame's
  pose in the base frame at each image's stamp, metres to millimetres; the base frame
  is the capture's world, the poses ``T_world_camera``.  The camera frame must be the
  optical one (``z`` along the optical axis, ``x`` right and ``y`` down in the image,
  ROS's ``*_optical_frame``), the frame the ``camera_info`` describes.

Which images: every one (:data:`MANY_IMAGES` and more: a warning), one per interval
(`every`: the first of each), or the nearest to given stamps (`at`).  Each view's key
is the image's number on its topic in stamp order (``0``, ``1``, ...), which
``--views`` names.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, warn_input
from robostereo.robot.importers.imported_views import Imported, ImportedView
from robostereo.robot.importers.tf_frames import TF_TOLERANCE_S, TransformTree, frame_name

__all__ = [
    "IMAGE_ENCODINGS",
    "INSTALL_HINT",
    "MANY_IMAGES",
    "choose_images",
    "image_from_message",
    "intrinsics_from_camera_info",
    "read_rosbag",
]

INSTALL_HINT = "import rosbag needs the rosbags library: pip install 'robostereo[ros]'"
"""The one line that says how to install what reading a bag needs."""

MANY_IMAGES = 50
"""Images taken (every image of the topic, by default) above which a warning suggests
``--every`` or ``--at``: each view costs the N-view locate time."""

#: ``sensor_msgs/Image`` encodings read: channels, dtype and the OpenCV conversion to BGR
IMAGE_ENCODINGS = {
    "mono8": (1, np.uint8, None), "8uc1": (1, np.uint8, None),
    "mono16": (1, np.uint16, None), "16uc1": (1, np.uint16, None),
    "bgr8": (3, np.uint8, None), "rgb8": (3, np.uint8, cv2.COLOR_RGB2BGR),
    "bgra8": (4, np.uint8, None), "rgba8": (4, np.uint8, cv2.COLOR_RGBA2BGRA),
}

_IMAGE_TYPES = ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage")
_INFO_TYPE = "sensor_msgs/msg/CameraInfo"
_TF_TYPE = "tf2_msgs/msg/TFMessage"
_NS = 1_000_000_000


def _stamp_ns(header: Any) -> int:
    return int(header.stamp.sec) * _NS + int(header.stamp.nanosec)


def image_from_message(msg: Any, topic: str) -> tuple[NDArray[Any], bytes | None]:
    """The image of a ``sensor_msgs/Image`` or ``CompressedImage`` message.

    Returns
    -------
    image : ndarray, shape (H, W) or (H, W, C)
        As OpenCV holds it (colour in BGR(A) order), ``uint8`` or ``uint16``.
    encoded : bytes or None
        A compressed message's file bytes (JPEG or PNG), else None.

    Raises
    ------
    InputError
        An encoding not read, data shorter than its rows, undecodable compressed data;
        naming the topic.
    """
    if hasattr(msg, "format"):  # CompressedImage
        raw = bytes(np.asarray(msg.data, dtype=np.uint8))
        if not (raw.startswith(b"\x89PNG") or raw.startswith(b"\xff\xd8")):
            raise InputError(f"{topic}: a compressed image that is neither JPEG nor PNG "
                             f"(format {msg.format!r})")
        img = cv2.imdecode(np.frombuffer(raw, np.uint8), cv2.IMREAD_UNCHANGED)
        if img is None:
            raise InputError(f"{topic}: a compressed image does not decode "
                             f"(format {msg.format!r})")
        return img, raw
    enc = str(msg.encoding).strip().lower()
    if enc not in IMAGE_ENCODINGS:
        raise InputError(f"{topic}: image encoding {msg.encoding!r} is not read "
                         f"(encodings: mono8, mono16, rgb8, bgr8, rgba8, bgra8)")
    channels, dtype, code = IMAGE_ENCODINGS[enc]
    h, w, step = int(msg.height), int(msg.width), int(msg.step)
    row = w * channels * np.dtype(dtype).itemsize
    data = np.asarray(msg.data, dtype=np.uint8)
    if h < 1 or w < 1 or step < row or data.size < step * (h - 1) + row:
        raise InputError(f"{topic}: a {enc} image of {w} x {h} px has {data.size} bytes "
                         f"of data, step {step}: too few")
    data = np.pad(data[: step * h], (0, max(0, step * h - data.size)))
    rows = data.reshape(h, step)[:, :row]
    order = ">" if int(msg.is_bigendian) else "<"
    img = rows.copy().view(np.dtype(dtype).newbyteorder(order)).reshape(h, w, channels)
    img = img.astype(dtype)[..., 0] if channels == 1 else img.astype(dtype)
    return (cv2.cvtColor(img, code) if code is not None else img), None


def intrinsics_from_camera_info(msg: Any, topic: str
                                ) -> tuple[NDArray[np.float64], tuple[int, int],
                                           tuple[float, ...]]:
    """``K`` (3, 3), the image size ``(width, height)`` and distortion ``(k1, k2, p1,
    p2[, k3])`` of a ``sensor_msgs/CameraInfo``.

    ``plumb_bob`` is ``(k1, k2, p1, p2, k3)`` and ``rational_polynomial`` ``(k1, k2,
    p1, p2, k3, k4, k5, k6)``, both OpenCV's order; the capture's camera models up to
    ``k3``, so ``k4 .. k6`` must be zero.

    Raises
    ------
    InputError
        Another distortion model, ``k4 .. k6`` not zero, binning or a region of
        interest (the images would not be the full sensor's), a ``K`` of no camera;
        naming the topic.
    """
    K = np.asarray(getattr(msg, "k", getattr(msg, "K", None)), dtype=float).reshape(-1)
    D = np.asarray(getattr(msg, "d", getattr(msg, "D", ())), dtype=float).reshape(-1)
    size = (int(msg.width), int(msg.height))
    model = str(msg.distortion_model).strip().lower()
    if K.size != 9 or not np.all(np.isfinite(K)) or K[0] <= 0 or K[4] <= 0:
        raise InputError(f"{topic}: camera_info's K is not a camera's ({K.tolist()})")
    if min(size) < 1:
        raise InputError(f"{topic}: camera_info has no image size ({size[0]} x {size[1]})")
    if max(int(msg.binning_x), 1) != 1 or max(int(msg.binning_y), 1) != 1:
        raise InputError(f"{topic}: camera_info has binning {msg.binning_x} x "
                         f"{msg.binning_y}: only full-resolution images are read")
    roi = msg.roi
    if int(roi.width) and (int(roi.x_offset), int(roi.y_offset), int(roi.width),
                           int(roi.height)) != (0, 0, *size):
        raise InputError(f"{topic}: camera_info has a region of interest: only full "
                         "images are read")
    if D.size and model not in ("plumb_bob", "rational_polynomial"):
        raise InputError(f"{topic}: distortion_model {msg.distortion_model!r} is not read "
                         "(plumb_bob, rational_polynomial)")
    if not np.all(np.isfinite(D)):
        raise InputError(f"{topic}: camera_info's D is not finite")
    if D.size > 5 and np.any(D[5:] != 0):
        raise InputError(f"{topic}: {model} with k4 .. k6 {D[5:8].tolist()} not zero: the "
                         "capture's camera models (k1, k2, p1, p2, k3)")
    D = D[:5]
    if D.size not in (0, 4, 5):
        raise InputError(f"{topic}: camera_info's D has {D.size} coefficients (4, 5 or 8)")
    return K.reshape(3, 3), size, tuple(float(v) for v in D)


def choose_images(stamps_ns: Sequence[int], *, at: Sequence[float] | None = None,
                  every: float | None = None) -> list[int]:
    """Indices of the images to take, in stamp order.

    Parameters
    ----------
    stamps_ns : sequence of int
        The images' stamps, increasing, nanoseconds.
    at : sequence of float, optional
        Stamps, seconds (as the bag's headers: since the epoch of its clock): the
        image nearest each; each must lie within the images' span (half the median
        interval beyond its ends at most) and pick an image of its own.
    every : float, optional
        Seconds: the first image of each interval from the first image on.

    >>> s = [k * 100_000_000 for k in range(12)]  # 10 images a second
    >>> choose_images(s, every=0.25)
    [0, 3, 5, 8, 10]
    >>> choose_images(s, at=[0.42, 0.09])
    [4, 1]
    """
    s = np.asarray(stamps_ns, dtype=np.int64)
    if at is not None and every is not None:
        raise InputError("give --at or --every, not both")
    if every is not None:
        if not (np.isfinite(every) and every > 0):
            raise InputError(f"--every must be > 0 seconds, got {every:g}")
        step = max(round(every * _NS), 1)
        bins = (s - s[0]) // step
        return [int(i) for i in np.flatnonzero(np.r_[True, bins[1:] != bins[:-1]])]
    if at is None:
        return list(range(len(s)))
    pad = int(np.median(np.diff(s)) // 2) if len(s) > 1 else 0
    out: list[int] = []
    for t in at:
        if not np.isfinite(t):
            raise InputError(f"--at: stamps must be finite seconds, got {t!r}")
        tn = round(t * _NS)
        if not s[0] - pad <= tn <= s[-1] + pad:
            raise InputError(f"--at: no image near {t:.6f} s (the images span "
                             f"{s[0] / _NS:.6f} .. {s[-1] / _NS:.6f} s)")
        i = int(np.argmin(np.abs(s - tn)))
        if i in out:
            raise InputError(f"--at: {t:.6f} s picks the image at {s[i] / _NS:.6f} s again")
        out.append(i)
    return out


@dataclass(frozen=True)
class _Topics:
    image: Any
    info: Any
    tf: list[Any]


def _connections(reader: Any, bag: Path, image_topic: str, info_topic: str) -> _Topics:
    by_topic: dict[str, list[Any]] = {}
    for c in reader.connections:
        by_topic.setdefault(c.topic, []).append(c)

    def one(topic: str, types: tuple[str, ...], what: str) -> list[Any]:
        if topic not in by_topic:
            have = sorted(t for t, cs in by_topic.items() if cs[0].msgtype in types)
            raise InputError(f"{bag}: no topic {topic} (its {what} topics: "
                             f"{', '.join(have) or 'none'})")
        cs = by_topic[topic]
        if cs[0].msgtype not in types:
            raise InputError(f"{bag}: {topic} is {cs[0].msgtype}, not "
                             f"{' or '.join(types)}")
        return cs

    tf = [c for t in ("/tf", "/tf_static", "tf", "tf_static") for c in by_topic.get(t, [])
          if c.msgtype == _TF_TYPE]
    return _Topics(one(image_topic, _IMAGE_TYPES, "image"),
                   one(info_topic, (_INFO_TYPE,), "camera_info"), tf)


def _camera(reader: Any, topics: _Topics, info_topic: str
            ) -> tuple[NDArray[np.float64], tuple[int, int], tuple[float, ...]]:
    """The camera of the first ``camera_info``; refused if a later one differs."""
    first = None
    for conn, _, raw in reader.messages(connections=topics.info):
        cam = intrinsics_from_camera_info(reader.deserialize(raw, conn.msgtype), info_topic)
        if first is None:
            first = cam
        elif (cam[1] != first[1] or cam[2] != first[2]
              or not np.allclose(cam[0], first[0], rtol=0, atol=1e-6)):
            raise InputError(f"{info_topic}: the camera_info changes within the bag "
                             f"(K {first[0].ravel().tolist()}, then "
                             f"{cam[0].ravel().tolist()})")
    if first is None:
        raise InputError(f"{info_topic}: no camera_info message")
    return first


def _tree(reader: Any, topics: _Topics) -> TransformTree:
    rows = []
    for conn, _, raw in reader.messages(connections=topics.tf):
        static = conn.topic.lstrip("/") == "tf_static"
        for tr in reader.deserialize(raw, conn.msgtype).transforms:
            t, q = tr.transform.translation, tr.transform.rotation
            rows.append((_stamp_ns(tr.header), tr.header.frame_id, tr.child_frame_id,
                         (t.x, t.y, t.z), (q.x, q.y, q.z, q.w), static))
    return TransformTree.from_transforms(rows)


def read_rosbag(bag: str | os.PathLike[str], *, image_topic: str, camera_info_topic: str,
                base_frame: str, camera_frame: str, images: str | os.PathLike[str],
                at: Sequence[float] | None = None, every: float | None = None,
                tf_tolerance_s: float = TF_TOLERANCE_S) -> Imported:
    """The views of a camera on an arm recorded in a ROS bag.

    Parameters
    ----------
    bag : path
        A ROS 1 ``.bag`` file or a ROS 2 bag folder (or a ``.db3`` / ``.mcap`` file in
        it).
    image_topic : str
        ``sensor_msgs/Image`` or ``sensor_msgs/CompressedImage``.
    camera_info_topic : str
        ``sensor_msgs/CameraInfo`` of the same camera.
    base_frame : str
        The tf frame that is the capture's world (the arm's base).
    camera_frame : str
        The camera's optical frame in tf.
    images : path
        An existing folder the chosen images are written to (as ``frame_NNNNN.png``,
        or ``.jpg`` for JPEG messages), to be read by
        :func:`~robostereo.robot.importers.imported_views.views_capture_from_imported`.
    at, every
        Which images (:func:`choose_images`); default every one.
    tf_tolerance_s : float
        :data:`~robostereo.robot.importers.tf_frames.TF_TOLERANCE_S`.

    Returns
    -------
    Imported
        Views keyed by image number, ``T_world_camera`` in mm (world = `base_frame`),
        no depth range (a bag has none: give one).

    Raises
    ------
    InputError
        ``rosbags`` missing (:data:`INSTALL_HINT`), an unreadable bag, a missing topic
        or one of another type, an image whose size is not the ``camera_info``'s, no
        tf chain from `base_frame` to `camera_frame`, an image stamp outside the
        dynamic transforms' span; each in one line naming the bag, topic or frames.

    Notes
    -----
    1. Open the bag; find the image, ``camera_info`` and tf connections.
    2. Read the camera (:func:`intrinsics_from_camera_info`), every image's stamp,
       and the tf tree; choose the images (:func:`choose_images`).
    3. Compose ``T_base_camera`` at the chosen stamps
       (:meth:`~robostereo.robot.importers.tf_frames.TransformTree.chain_poses`).
    4. Decode the chosen images (:func:`image_from_message`), check their size and
       write them to `images`.
    """
    try:
        from rosbags.highlevel import AnyReader, AnyReaderError
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise InputError(INSTALL_HINT) from None
    path, out = Path(bag), Path(images)
    if path.is_file() and path.suffix != ".bag" and (path.parent / "metadata.yaml").is_file():
        path = path.parent  # a ROS 2 bag's .db3 or .mcap file: its folder
    if not (path.is_file() or (path.is_dir() and (path / "metadata.yaml").is_file())):
        raise InputError(f"{path}: not a ROS bag (a .bag file, or a ROS 2 bag folder with "
                         "metadata.yaml)")
    try:
        with AnyReader([path], default_typestore=get_typestore(Stores.LATEST)) as reader:
            return _read(reader, path, out, image_topic, camera_info_topic, base_frame,
                         camera_frame, at, every, tf_tolerance_s)
    except AnyReaderError as exc:
        raise InputError(f"{path}: cannot read the bag ({exc})") from None
    except (OSError, ValueError, KeyError) as exc:  # rosbags's storage layers
        if isinstance(exc, InputError):
            raise
        raise InputError(f"{path}: cannot read the bag ({exc.__class__.__name__}: "
                         f"{exc})") from None


def _read(reader: Any, path: Path, out: Path, image_topic: str, info_topic: str,
          base_frame: str, camera_frame: str, at: Sequence[float] | None,
          every: float | None, tolerance_s: float) -> Imported:
    topics = _connections(reader, path, image_topic, info_topic)
    K, size, dist = _camera(reader, topics, info_topic)
    stamps, frames = [], set()
    for conn, _, raw in reader.messages(connections=topics.image):
        header = reader.deserialize(raw, conn.msgtype).header
        stamps.append(_stamp_ns(header))
        frames.add(frame_name(header.frame_id))
    if not stamps:
        raise InputError(f"{image_topic}: no image in {path}")
    order = np.argsort(np.asarray(stamps, dtype=np.int64), kind="stable")
    sorted_stamps = np.asarray(stamps, dtype=np.int64)[order]
    chosen = choose_images(sorted_stamps, at=at, every=every)
    if at is None and every is None and len(chosen) > MANY_IMAGES:
        warn_input(f"{image_topic}: {len(chosen)} images taken, each a view: --every "
                   "SECONDS or --at STAMPS takes fewer")
    poses = _tree(reader, topics).chain_poses(
        base_frame, camera_frame, sorted_stamps[chosen], tolerance_s=tolerance_s)
    frames.discard("")
    if frames and frame_name(camera_frame) not in frames:
        warn_input(f"{image_topic}: the images are in frame '{sorted(frames)[0]}', not "
                   f"--camera-frame '{frame_name(camera_frame)}' (is it the optical frame?)")
    wanted = {int(order[i]): k for k, i in enumerate(chosen)}  # message number -> view
    files: dict[int, Path] = {}
    for n, (conn, _, raw) in enumerate(reader.messages(connections=topics.image)):
        if n not in wanted:
            continue
        img, encoded = image_from_message(reader.deserialize(raw, conn.msgtype), image_topic)
        if (img.shape[1], img.shape[0]) != size:
            raise InputError(f"{info_topic}: camera_info is {size[0]} x {size[1]} px but "
                             f"the images on {image_topic} are {img.shape[1]} x "
                             f"{img.shape[0]}")
        name = out / f"frame_{chosen[wanted[n]]:05d}"
        if encoded is None:
            f = name.with_suffix(".png")
            if not cv2.imwrite(str(f), img):
                raise InputError(f"{f}: cannot write the image")
        else:
            f = name.with_suffix(".png" if encoded.startswith(b"\x89PNG") else ".jpg")
            f.write_bytes(encoded)
        files[wanted[n]] = f
    views = []
    for k, i in enumerate(chosen):
        views.append(ImportedView(str(i), files[k], K, poses[k], dist))
    return Imported(tuple(views), None, {}, source=str(path))
