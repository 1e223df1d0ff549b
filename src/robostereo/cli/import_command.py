"""``robostereo import``: another tool's cameras and images as an N-view capture folder.

``import idr CAMERAS_NPZ --images DIR --out CAP``, ``import mvsnet DIR --out CAP`` and
``import colmap MODEL_DIR --images DIR --out CAP`` read their cameras
(``import rosbag``: :mod:`robostereo.cli.import_rosbag`)
(:mod:`robostereo.robot.importers`), choose views (``--views``), scale images and
intrinsics together (``--scale``) and write the folder
(:func:`~robostereo.robot.views.views_folder.write_views_capture`), with the depth
range the data gives (IDR's bounding sphere, MVSNet's depth lines, COLMAP's points)
or ``--depth-range NEAR FAR``.  Parses, loads, calls the library and writes; every
user error is one line, exit code 2, nothing written.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from robostereo.cli._args import finite, require_empty_folder
from robostereo.cli.import_rosbag import add_rosbag_parser
from robostereo.errors import InputError

__all__ = ["add_import_parser", "run_import"]

_UNITS = {"mm": 1.0, "cm": 10.0, "m": 1000.0}


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, required=True, metavar="CAP",
                   help="the N-view capture folder to write (new or empty)")
    p.add_argument("--views", metavar="IDS",
                   help="comma-separated view ids to keep, in order (e.g. 0,1,2); "
                        "default every view")
    p.add_argument("--scale", type=finite("--scale"), default=1.0,
                   help="image scale in (0, 1]: images and intrinsics together "
                        "(default 1)")
    p.add_argument("--depth-range", type=finite("--depth-range"), nargs=2,
                   metavar=("NEAR", "FAR"),
                   help="depth of the object along the optical axis, mm (default: the "
                        "data's; required where it has none)")
    p.add_argument("--unit", choices=sorted(_UNITS), default="mm",
                   help="the unit of the data's world (default mm: DTU and MVSNet's DTU "
                        "are in mm; a COLMAP model is in its own)")


def add_import_parser(sub: Any) -> None:
    p = sub.add_parser(
        "import", help="another tool's cameras and images as an N-view capture folder",
        description="Read cameras and images of IDR/NeuS (DTU), MVSNet, COLMAP or a ROS "
                    "bag and write an N-view capture folder that locate reads.")
    kinds = p.add_subparsers(dest="kind", required=True, metavar="FORMAT")
    idr = kinds.add_parser("idr", help="IDR / NeuS cameras.npz (world_mat_K, scale_mat_K)")
    idr.add_argument("cameras", type=Path, metavar="CAMERAS_NPZ")
    idr.add_argument("--images", type=Path, required=True, metavar="DIR",
                     help="the image folder (files sorted by name are views 0, 1, ...)")
    _common(idr)
    mvs = kinds.add_parser("mvsnet", help="MVSNet folder: cams/*_cam.txt, images/")
    mvs.add_argument("folder", type=Path, metavar="DIR")
    mvs.add_argument("--intrinsics-scale", type=finite("--intrinsics-scale"), default=1.0,
                     help="factor on the camera files' fx, fy, cx, cy (MVSNet's DTU "
                          "training cameras: 4)")
    mvs.add_argument("--pair-of", metavar="ID",
                     help="keep view ID and its best neighbours from pair.txt (in place of "
                          "--views)")
    mvs.add_argument("--neighbours", type=int, default=2,
                     help="how many of pair.txt's neighbours --pair-of keeps (default 2)")
    mvs.add_argument("--depths", type=Path, metavar="DIR",
                     help="ground-truth depth maps (depth_map_0000.pfm or 00000000.pfm), "
                          "written on the image grid as CAP/depth/<image>.pfm for "
                          "robostereo evaluate")
    _common(mvs)
    col = kinds.add_parser("colmap", help="COLMAP model, text or binary: cameras, images, "
                                          "points3D")
    col.add_argument("model", type=Path, metavar="MODEL_DIR")
    col.add_argument("--images", type=Path, required=True, metavar="DIR",
                     help="the folder the model's image names are relative to")
    _common(col)
    add_rosbag_parser(kinds)  # its own handler: robostereo.cli.import_rosbag
    p.set_defaults(handler=run_import)


def _pair_views(args: argparse.Namespace) -> str:
    """``--views`` of ``--pair-of ID``: the view and its ``--neighbours`` best ones."""
    from robostereo.robot.importers.mvsnet import read_pairs

    if args.views is not None:
        raise InputError("give --views or --pair-of, not both")
    if not 1 <= args.neighbours <= 100:
        raise InputError(f"--neighbours must be 1 .. 100, got {args.neighbours}")
    if not str(args.pair_of).isdigit():
        raise InputError(f"--pair-of must be a view number, got {args.pair_of!r}")
    pairs = read_pairs(args.folder / "pair.txt")
    ref = int(args.pair_of)
    if ref not in pairs:
        raise InputError(f"{args.folder / 'pair.txt'}: no view {ref}")
    return ",".join(str(v) for v in [ref, *pairs[ref][: args.neighbours]])


def run_import(args: argparse.Namespace) -> int:
    from robostereo.robot.importers import (
        parse_view_selection,
        read_colmap,
        read_idr,
        read_mvsnet,
        views_capture_from_imported,
    )
    from robostereo.robot.views.views_folder import write_views_capture

    require_empty_folder(args.out)
    unit = _UNITS[args.unit]
    if args.kind == "idr":
        imported = read_idr(args.cameras, args.images, unit_to_mm=unit)
    elif args.kind == "mvsnet":
        imported = read_mvsnet(args.folder, intrinsics_scale=args.intrinsics_scale,
                               unit_to_mm=unit)
    else:
        imported = read_colmap(args.model, args.images, unit_to_mm=unit)
    views = args.views
    if getattr(args, "pair_of", None) is not None:
        views = _pair_views(args)
    select = parse_view_selection(views, [v.key for v in imported.views])
    depth = None
    if args.depth_range is not None:
        near, far = args.depth_range
        if not 0 < near <= far:
            raise InputError(f"--depth-range must be NEAR FAR with 0 < NEAR <= FAR, got "
                             f"{near:g} {far:g}")
        depth = (near, far)
    notes = {"scene": {"imported_from": f"{args.kind} {imported.source}",
                       "views": [imported.views[i].key for i in select],
                       "scale": float(args.scale), "unit": args.unit}}
    cap = views_capture_from_imported(imported, select=select, scale=args.scale,
                                      depth_range_mm=depth, notes=notes)
    depths = _mvsnet_depths(args, imported, select, cap)  # read before writing anything
    # the depth maps in the same all-or-nothing folder, where evaluate looks
    maps = [depths[n] for n in cap.names] if depths else None
    write_views_capture(args.out, cap, depth_maps=maps, depth_suffix=".pfm")
    near, far = cap.depth_range_mm
    w, h = cap.camera.image_size
    print(f"{args.out}: {len(cap)} views of {args.kind} {imported.source}, {w} x {h} px, "
          f"fx {cap.camera.fx:.2f} px, depths {near:.1f} .. {far:.1f} mm"
          + (f", {len(depths)} depth maps" if depths else ""))
    return 0


def _mvsnet_depths(args: argparse.Namespace, imported: Any, select: list[int],
                   cap: Any) -> dict[str, Any]:
    """``--depths``: the chosen views' maps on the capture's image grid, by image name."""
    if getattr(args, "depths", None) is None:
        return {}
    from robostereo.robot.importers.mvsnet import read_mvsnet_depths

    keys = [imported.views[i].key for i in select]
    maps = read_mvsnet_depths(args.depths, keys, cap.camera.image_size,
                              unit_to_mm=_UNITS[args.unit])
    return {name: maps[k] for name, k in zip(cap.names, keys, strict=True)}


