"""Small ROS bags written for the rosbag importer's tests, with the rosbags writer: a
camera on an arm's flange, its images (rendered, with known poses), ``camera_info``, the
flange moving on ``/tf`` (base to flange) and the hand-eye on ``/tf_static`` (flange to
camera), in ROS 1 (``.bag``) and ROS 2 (``sqlite3``, ``mcap``) form.

The flange's transforms are stamped off the images' stamps: around each image it moves
at a constant twist through the pose that puts the camera at the view, so that the
translation's linear and the rotation's spherical interpolation at the image's stamp
give the view's pose exactly, and the samples nearest the stamp are millimetres and
milliradians off it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np
from scipy.spatial.transform import Rotation

from robostereo.geometry.poses import SE3

__all__ = ["EPOCH_NS", "HAND_EYE", "TF_OFFSETS_S", "BagScene", "bag_scene", "write_bag"]

EPOCH_NS = 1_700_000_000 * 1_000_000_000
"""The bags' clock: images from 1.0 s after this on."""
HAND_EYE = SE3.from_rotvec([30.0, -20.0, 80.0], [0.1, -0.2, 1.0])
"""``T_flange_camera``, mm."""
TF_OFFSETS_S = (-0.047, -0.013, 0.029, 0.061)
"""Stamps of the flange's transforms around each image's, seconds."""
_V_MM_S = np.array([120.0, -80.0, 40.0])
_W_RAD_S = np.array([0.3, 0.2, -0.4])


@dataclass
class BagScene:
    """What a bag holds: images (8-bit grey), their stamps, the camera and its poses."""

    images: list[np.ndarray]
    stamps_ns: list[int]
    K: np.ndarray
    D: list[float]
    poses: list[SE3]
    frame_id: str = "camera_optical"
    extra_tf: list[tuple[int, str, str, SE3, bool]] = field(default_factory=list)

    def tf_rows(self) -> list[tuple[int, str, str, SE3, bool]]:
        """``(stamp_ns, parent, child, T_parent_child (mm), static)``."""
        rows = [(0, "flange", self.frame_id, HAND_EYE, True),
                (0, "flange", "gripper", SE3.from_rotvec([0, 0, 150.0], [0, 0, 0]), True)]
        for t, pose in zip(self.stamps_ns, self.poses, strict=True):
            flange = pose @ HAND_EYE.inv()
            for d in TF_OFFSETS_S:
                moved = SE3(flange.rotation @ Rotation.from_rotvec(_W_RAD_S * d).as_matrix(),
                            flange.translation + _V_MM_S * d)
                rows.append((t + round(d * 1e9), "base", "flange", moved, False))
        return rows + list(self.extra_tf)


def bag_scene(images: list[np.ndarray], K: np.ndarray, D: list[float], poses: list[SE3],
              gaps_s: tuple[float, ...] = (0.6, 0.7)) -> BagScene:
    """Images at 1.0 s (plus 123 456 789 ns) after :data:`EPOCH_NS` and `gaps_s` apart."""
    offsets = np.round(np.r_[0, np.cumsum(gaps_s)[: len(images) - 1]] * 1e9)
    t = [EPOCH_NS + 1_123_456_789 + int(v) for v in offsets]  # integers: exact to the ns
    return BagScene(list(images), t, np.asarray(K, float), list(D), list(poses))


def _typestore(version: int):
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC if version == 1 else Stores.ROS2_HUMBLE)
    if "tf2_msgs/msg/TFMessage" not in ts.fielddefs:
        ts.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms",
                                       "tf2_msgs/msg/TFMessage"))
    return ts


def _header(ts, version: int, stamp_ns: int, frame: str):
    T = ts.types
    time = T["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
    if version == 1:
        return T["std_msgs/msg/Header"](seq=0, stamp=time, frame_id=frame)
    return T["std_msgs/msg/Header"](stamp=time, frame_id=frame)


def _image(ts, version: int, img: np.ndarray, stamp: int, frame: str, encoding: str):
    T = ts.types
    h, w = img.shape
    if encoding in ("png", "jpeg"):
        ok, buf = cv2.imencode(".png" if encoding == "png" else ".jpg", img)
        assert ok
        return "sensor_msgs/msg/CompressedImage", T["sensor_msgs/msg/CompressedImage"](
            header=_header(ts, version, stamp, frame), format=f"mono8; {encoding} compressed",
            data=buf.ravel())
    if encoding == "mono16":
        data = (img.astype(np.uint16) * 256 + 128).astype("<u2")
    elif encoding == "mono8":
        data = img
    else:  # rgb8, bgr8: the grey in each channel
        data = np.repeat(img[:, :, None], 3, axis=2)
    raw = np.ascontiguousarray(data).view(np.uint8).reshape(h, -1)
    return "sensor_msgs/msg/Image", T["sensor_msgs/msg/Image"](
        header=_header(ts, version, stamp, frame), height=h, width=w, encoding=encoding,
        is_bigendian=0, step=raw.shape[1], data=raw.ravel())


def _camera_info(ts, version: int, scene: BagScene, stamp: int, size: tuple[int, int]):
    T = ts.types
    K = scene.K.ravel().astype(float)
    P = np.c_[scene.K, np.zeros(3)].ravel()
    roi = T["sensor_msgs/msg/RegionOfInterest"](x_offset=0, y_offset=0, height=0, width=0,
                                                do_rectify=False)
    mats = {"D": np.array(scene.D, float), "K": K, "R": np.eye(3).ravel(), "P": P}
    if version == 2:
        mats = {k.lower(): v for k, v in mats.items()}
    return T["sensor_msgs/msg/CameraInfo"](
        header=_header(ts, version, stamp, scene.frame_id), height=size[1], width=size[0],
        distortion_model="plumb_bob", binning_x=0, binning_y=0, roi=roi, **mats)


def _tf(ts, version: int, rows: list[tuple[int, str, str, SE3, bool]]):
    T = ts.types
    out = []
    for stamp, parent, child, pose, _ in rows:
        x, y, z = pose.translation / 1000.0
        qx, qy, qz, qw = Rotation.from_matrix(pose.rotation).as_quat()
        tr = T["geometry_msgs/msg/Transform"](
            translation=T["geometry_msgs/msg/Vector3"](x=x, y=y, z=z),
            rotation=T["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw))
        out.append(T["geometry_msgs/msg/TransformStamped"](
            header=_header(ts, version, stamp, parent), child_frame_id=child, transform=tr))
    return T["tf2_msgs/msg/TFMessage"](transforms=out)


def write_bag(path: Path, scene: BagScene, *, version: int = 1, encoding: str = "mono8",
              storage: str = "sqlite3", info_size: tuple[int, int] | None = None,
              leave_out: tuple[str, ...] = (), image_delay_s: float = 0.0,
              image_frame: str | None = None) -> Path:
    """Write `scene` as a bag: ``/camera/image`` (`encoding`: ``mono8``, ``mono16``,
    ``rgb8``, ``png``, ``jpeg``), ``/camera/camera_info`` (of `info_size`, default the
    images'), ``/tf`` (one message per sample) and ``/tf_static``; topics named in
    `leave_out` are not written; the images stamped `image_delay_s` after their poses'
    stamps, in `image_frame` (default the camera's frame in tf).  ROS 1: the file
    `path`; ROS 2: the folder `path`."""
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2

    ts = _typestore(version)
    ser = ts.serialize_ros1 if version == 1 else ts.serialize_cdr
    h, w = scene.images[0].shape
    size = info_size or (w, h)
    messages = []  # (record time, topic, type, message)
    for img, stamp in zip(scene.images, scene.stamps_ns, strict=True):
        stamp += round(image_delay_s * 1e9)
        typ, msg = _image(ts, version, img, stamp, image_frame or scene.frame_id, encoding)
        messages.append((stamp + 1000, "/camera/image", typ, msg))
        messages.append((stamp + 2000, "/camera/camera_info", "sensor_msgs/msg/CameraInfo",
                         _camera_info(ts, version, scene, stamp, size)))
    rows = scene.tf_rows()
    static = [r for r in rows if r[4]]
    messages.append((scene.stamps_ns[0] - 10**9, "/tf_static", "tf2_msgs/msg/TFMessage",
                     _tf(ts, version, static)))
    for r in rows:
        if not r[4]:
            messages.append((r[0] + 500, "/tf", "tf2_msgs/msg/TFMessage",
                             _tf(ts, version, [r])))
    messages = [m for m in messages if m[1] not in leave_out]
    messages.sort(key=lambda m: m[0])
    if version == 1:
        writer = Writer1(path)
    else:
        plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
        writer = Writer2(path, version=9, storage_plugin=plugin)
    with writer:
        conns = {}
        for _, topic, typ, _ in messages:
            if topic not in conns:
                conns[topic] = writer.add_connection(topic, typ, typestore=ts)
        for t, topic, typ, msg in messages:
            writer.write(conns[topic], t, ser(msg, typ))
    return path
