"""``robostereo import rosbag``: a camera's images and the arm's tf in a ROS bag as an
N-view capture folder.

``import rosbag BAG --image-topic T --camera-info-topic T --base-frame B --camera-frame C
--depth-range NEAR FAR --out CAP [--at STAMPS | --every SECONDS] [--views IDS]
[--scale S]`` reads the bag (:func:`~robostereo.robot.importers.rosbag.read_rosbag`),
chooses images (``--at``, ``--every``, then ``--views``), scales images and intrinsics
together and writes the folder.  The chosen images pass through a temporary folder
that is removed.  Parses, loads, calls the library and writes; every user error is one
line, exit code 2, nothing written (``rosbags`` missing: how to install it).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path
from typing import Any

from robostereo.cli._args import finite, require_empty_folder
from robostereo.errors import InputError

__all__ = ["add_rosbag_parser", "parse_stamps", "run_import_rosbag"]


def parse_stamps(text: str) -> list[float]:
    """``--at``: comma-separated stamps, seconds.

    >>> parse_stamps("1700000000.5, 1700000001.25")
    [1700000000.5, 1700000001.25]
    """
    try:
        out = [float(t) for t in str(text).split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"--at must be comma-separated stamps in seconds, "
                                         f"got {text!r}") from None
    return out


def add_rosbag_parser(kinds: Any) -> None:
    """The ``rosbag`` format of ``robostereo import``."""
    p = kinds.add_parser(
        "rosbag", help="ROS 1 .bag or ROS 2 bag folder: images, camera_info, tf",
        description="Read a camera's images (sensor_msgs/Image or CompressedImage), its "
                    "camera_info and the camera's pose in the base frame from /tf and "
                    "/tf_static at each image's stamp (metres to mm) from a ROS bag.")
    p.add_argument("bag", type=Path, metavar="BAG",
                   help="a ROS 1 .bag file or a ROS 2 bag folder (metadata.yaml; or its "
                        ".db3 / .mcap file)")
    p.add_argument("--image-topic", required=True, metavar="TOPIC",
                   help="sensor_msgs/Image or sensor_msgs/CompressedImage")
    p.add_argument("--camera-info-topic", required=True, metavar="TOPIC",
                   help="sensor_msgs/CameraInfo of the same camera")
    p.add_argument("--base-frame", required=True, metavar="FRAME",
                   help="the tf frame that is the capture's world (the arm's base)")
    p.add_argument("--camera-frame", required=True, metavar="FRAME",
                   help="the camera's optical frame in tf (z along the optical axis)")
    which = p.add_mutually_exclusive_group()
    which.add_argument("--at", type=parse_stamps, metavar="STAMPS",
                       help="comma-separated stamps, seconds (as the headers): the image "
                            "nearest each")
    which.add_argument("--every", type=finite("--every"), metavar="SECONDS",
                       help="one image per interval of SECONDS (the first of each)")
    p.add_argument("--out", type=Path, required=True, metavar="CAP",
                   help="the N-view capture folder to write (new or empty)")
    p.add_argument("--views", metavar="IDS",
                   help="comma-separated image numbers to keep, in order; default every "
                        "image --at or --every took")
    p.add_argument("--scale", type=finite("--scale"), default=1.0,
                   help="image scale in (0, 1]: images and intrinsics together "
                        "(default 1)")
    p.add_argument("--depth-range", type=finite("--depth-range"), nargs=2,
                   metavar=("NEAR", "FAR"),
                   help="depth of the object along the optical axis, mm (required: a bag "
                        "has none)")
    p.set_defaults(handler=run_import_rosbag)


def run_import_rosbag(args: argparse.Namespace) -> int:
    from robostereo.robot.importers import (
        parse_view_selection,
        read_rosbag,
        views_capture_from_imported,
    )
    from robostereo.robot.views.views_folder import write_views_capture

    require_empty_folder(args.out)
    if args.depth_range is None:
        raise InputError(f"{args.bag}: a bag has no depth range: give --depth-range NEAR "
                         "FAR (mm along the optical axis)")
    near, far = args.depth_range
    if not 0 < near <= far:
        raise InputError(f"--depth-range must be NEAR FAR with 0 < NEAR <= FAR, got "
                         f"{near:g} {far:g}")
    with tempfile.TemporaryDirectory(prefix="robostereo-rosbag-") as work:
        imported = read_rosbag(args.bag, image_topic=args.image_topic,
                               camera_info_topic=args.camera_info_topic,
                               base_frame=args.base_frame, camera_frame=args.camera_frame,
                               images=work, at=args.at, every=args.every)
        select = parse_view_selection(args.views, [v.key for v in imported.views])
        notes = {"scene": {"imported_from": f"rosbag {imported.source}",
                           "image_topic": args.image_topic,
                           "camera_info_topic": args.camera_info_topic,
                           "base_frame": args.base_frame, "camera_frame": args.camera_frame,
                           "views": [imported.views[i].key for i in select],
                           "scale": float(args.scale), "unit": "m"}}
        cap = views_capture_from_imported(imported, select=select, scale=args.scale,
                                          depth_range_mm=(near, far), notes=notes)
    write_views_capture(args.out, cap)
    w, h = cap.camera.image_size
    print(f"{args.out}: {len(cap)} views of rosbag {imported.source}, {w} x {h} px, "
          f"fx {cap.camera.fx:.2f} px, depths {near:.1f} .. {far:.1f} mm")
    return 0
