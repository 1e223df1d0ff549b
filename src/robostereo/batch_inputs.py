"""One input of a batch (:func:`robostereo.batch.run_batch`): finding it, what shapes
its outputs, and processing it.

An input is a folder, one of

* a **pair folder**: ``left.*`` and ``right.*`` (rectified images), optionally
  ``camera.yaml`` (the camera YAML of :func:`robostereo.io.load_stereo_camera`, for
  3-D points) and ``disparity.yaml`` (``min_disparity``, ``max_disparity``; otherwise
  the batch-wide range); with a batch-wide calibration
  (:attr:`BatchOptions.calibration`) the images are the original ones of a calibrated
  rig and go through :func:`robostereo.rig.match_rig`;
* a **capture folder**: ``capture.yaml``, ``left.png``, ``right.png`` as
  ``robostereo capture`` writes it, processed by
  :func:`robostereo.robot.capture.locate_pair.locate_capture`;
* an **N-view capture folder**: ``capture.yaml`` with ``views:`` and the views' images,
  as ``robostereo capture --views N`` writes it, read by
  :func:`~robostereo.robot.views.views_folder.read_views_capture` and located by
  :func:`~robostereo.robot.views.locating.locate_views`, as ``robostereo locate`` does:
  ``NAME.csv`` has ``locate``'s N-view columns (each point with its bound, confidence
  and view count; ``NAME.ply`` those as vertex properties), and the summary row kind
  ``views``, ``matched`` and ``points_3d`` the points located (the columns of the
  matcher of two views -- edge points, disparities, the rows' and grey levels' checks --
  are blank).

:func:`find_inputs` lists the input folders of a directory (empty subfolders are not
inputs and are left out).  :func:`process_input` processes one and writes, for input
``NAME``, ``OUT/NAME.csv`` (the matched points) [and ``OUT/NAME.ply``] and then
``OUT/NAME.json`` (its summary row, :data:`SUMMARY_COLUMNS`, and timings), all
atomically; the JSON file marks the input as finished.  The marker records what shaped
the outputs (:func:`run_signature`) -- the options (range, PLY, calibration and its
contents, matcher parameters, robostereo's version) and the name, size and modification
time of every file of the input folder (and of an N-view folder's images in its
subfolders).  A failed input leaves no output.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import yaml

from robostereo.errors import InputError
from robostereo.io.yaml_loading import load_yaml
from robostereo.matcher.parameters import MatchParameters

if TYPE_CHECKING:
    from robostereo.matcher.pipeline import MatchResult

__all__ = [
    "SUMMARY_COLUMNS",
    "BatchOptions",
    "find_inputs",
    "process_input",
    "run_signature",
]

PathLike = str | os.PathLike[str]

SUMMARY_COLUMNS = (
    "input", "status", "kind", "edges_left", "edges_right", "matched", "matched_percent",
    "points_3d", "min_disparity", "max_disparity", "row_offset_px", "row_tilt_px",
    "row_stretch_px", "rows_moved", "grey_mapped", "output", "error",
)  # fmt: skip
"""Columns of ``summary.csv`` (one row per input, sorted by input name).  The checks of
:func:`~robostereo.matcher.pipeline.match_stereo` are there too, so that a batch says
which pairs were not as they should be: ``row_offset_px``, ``row_tilt_px`` and
``row_stretch_px`` the rows' measured offset (see
:class:`~robostereo.matcher.alignment.RowOffset`; blank where it could not be measured),
``rows_moved`` 1 where the right view was moved by it and matched again,
``grey_mapped`` 1 where the views' grey levels differed and were mapped before matching
again."""

_IMAGE_EXTS = (".png", ".ppm", ".pgm", ".pnm", ".tif", ".tiff", ".bmp", ".jpg", ".jpeg")


@dataclass(frozen=True)
class BatchOptions:
    """What every input of a batch shares.

    Attributes
    ----------
    disparity_range : tuple of float or None
        ``(min, max)`` for pair folders without ``disparity.yaml``.
    params : MatchParameters or None
        Matcher tuning; default ``MatchParameters()`` with each image's bit depth.
    calibration, calibration_right : str or None
        A rig calibration file (and the right ROS file) for every pair folder: the
        pairs are then original images, rectified by :func:`robostereo.rig.match_rig`.
    ply : bool
        Also write ``NAME.ply`` where 3-D points are known.
    """

    disparity_range: tuple[float, float] | None = None
    params: MatchParameters | None = None
    calibration: str | None = None
    calibration_right: str | None = None
    ply: bool = False


def _has_image(d: Path, stem: str) -> Path | None:
    for ext in _IMAGE_EXTS:
        for p in (d / f"{stem}{ext}", d / f"{stem}{ext.upper()}"):
            if p.is_file():
                return p
    return None


def _is_input(d: Path) -> bool:
    return (d / "capture.yaml").is_file() or (
        _has_image(d, "left") is not None and _has_image(d, "right") is not None
    )


def _is_empty(d: Path) -> bool:
    try:
        return next(d.iterdir(), None) is None
    except OSError:
        return False  # unreadable: processing it reports why


def find_inputs(input_dir: PathLike, *, exclude: PathLike | None = None) -> list[Path]:
    """The input folders of `input_dir`: itself if it is an input, else its subfolders.

    Parameters
    ----------
    input_dir : path
    exclude : path, optional
        A folder to leave out (the output folder, when it lies inside `input_dir`).

    Returns
    -------
    list of Path
        Sorted by name; hidden and empty folders are left out.  Other subfolders that
        are not inputs are kept: processing them reports why.

    Raises
    ------
    InputError
        `input_dir` missing, unreadable, or without any subfolder.
    """
    d = Path(input_dir)
    if not d.is_dir():
        raise InputError(f"{d}: input folder not found")
    if _is_input(d):
        return [d]
    ex = Path(exclude).resolve() if exclude is not None else None
    try:
        subs = sorted(p for p in d.iterdir() if p.is_dir() and not p.name.startswith("."))
    except OSError as e:
        raise InputError(f"{d}: cannot list folder ({e.__class__.__name__})") from None
    subs = [p for p in subs if (ex is None or p.resolve() != ex) and not _is_empty(p)]
    if not subs:
        raise InputError(
            f"{d}: no input folders (pair folders with left.* and right.*, or capture "
            "folders with capture.yaml)"
        )
    return subs


def _read_range(path: Path) -> tuple[float, float]:
    try:
        data = load_yaml(path.read_text(), str(path))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as e:
        raise InputError(f"{path}: cannot read disparity YAML ({e.__class__.__name__})") from None
    if not isinstance(data, Mapping) or not {"min_disparity", "max_disparity"} <= data.keys():
        raise InputError(f"{path}: expected keys min_disparity and max_disparity")
    try:
        lo, hi = float(data["min_disparity"]), float(data["max_disparity"])
    except (TypeError, ValueError):
        raise InputError(f"{path}: min_disparity and max_disparity must be numbers") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
        raise InputError(f"{path}: need finite min_disparity <= max_disparity, got {lo}, {hi}")
    return lo, hi


def _write_outputs(
    out: Path, name: str, table: Mapping[str, Any], xyz: Any, ply: bool,
    fields: Mapping[str, Any] | None = None,
) -> str:
    """``NAME.csv`` [and ``NAME.ply`` of `xyz` (M, 3), with the per-point `fields`],
    both or neither; an old ``NAME.ply`` not asked for now is removed."""
    from robostereo.io import atomic_outputs, write_csv, write_ply

    csv_path, ply_path = out / f"{name}.csv", out / f"{name}.ply"
    targets = {"csv": csv_path}
    if ply and xyz is not None:
        targets["ply"] = ply_path
    with atomic_outputs(targets) as tmp:  # both or neither
        write_csv(tmp["csv"], table)
        if "ply" in tmp:
            write_ply(tmp["ply"], xyz, fields=fields)
    if "ply" not in targets and ply_path.is_file():
        ply_path.unlink()  # left by a run with other options
    return csv_path.name


def _file_digest(path: str | None) -> str | None:
    if path is None:
        return None
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return "unreadable"


def run_signature(input_dir: PathLike, options: BatchOptions) -> dict[str, Any]:
    """What shapes an input's outputs: the options and the input folder's files.

    Stored in the finished marker ``NAME.json``; a rerun with another signature redoes
    the input.

    Returns
    -------
    dict
        ``options`` (the batch-wide disparity range unless the folder has its own, ply,
        matcher parameters, robostereo's version, for pair folders the calibration
        paths and SHA-256 of their contents) and ``files`` (name, size and modification
        time of every file of the input folder), JSON-serialisable.
    """
    from robostereo import __version__

    d = Path(input_dir)
    try:
        files = sorted(
            [p.name, st.st_size, st.st_mtime_ns]
            for p in d.iterdir() if p.is_file() for st in (p.stat(),)
        )
    except OSError:
        files = []
    files += _images_below(d)
    o = options
    capture = (d / "capture.yaml").is_file()  # its own range and geometry
    own_range = capture or (d / "disparity.yaml").is_file()
    calibrated = o.calibration is not None and not capture
    return {
        "options": {
            "version": __version__,
            "disparity_range": None if own_range or o.disparity_range is None else
            [float(v) for v in o.disparity_range],
            "ply": bool(o.ply),
            "params": repr(o.params),
            "calibration": o.calibration if calibrated else None,
            "calibration_sha256": _file_digest(o.calibration) if calibrated else None,
            "calibration_right": o.calibration_right if calibrated else None,
            "calibration_right_sha256": _file_digest(o.calibration_right) if calibrated
            else None,
        },
        "files": files,
    }  # fmt: skip


def _images_below(d: Path) -> list[list[Any]]:
    """Name, size and modification time of an N-view folder's images that lie in its
    subfolders (those of the folder itself are among its files already)."""
    if not _is_views(d):
        return []
    from robostereo.robot.views.views_folder import views_folder_files

    below = []
    for p in views_folder_files(d):
        rel = os.path.relpath(p, d)
        if os.sep in rel:
            try:
                st = p.stat()
            except OSError:
                continue  # the reader says what is wrong with it
            below.append([rel, st.st_size, st.st_mtime_ns])
    return sorted(below)


def _run_pair(d: Path, out: Path, options: BatchOptions) -> dict[str, Any]:
    from dataclasses import replace

    from robostereo.io import load_stereo_camera
    from robostereo.io.images import load_image
    from robostereo.matcher.pipeline import match_stereo

    lp, rp = _has_image(d, "left"), _has_image(d, "right")
    assert lp is not None and rp is not None
    rng_file = d / "disparity.yaml"
    if rng_file.is_file():
        lo, hi = _read_range(rng_file)
    elif options.disparity_range is not None:
        lo, hi = options.disparity_range
    else:
        raise InputError(f"{d}: no disparity.yaml and no batch-wide disparity range")
    left, bits_l = load_image(lp)
    right, bits_r = load_image(rp)
    if bits_l != bits_r:
        raise InputError(f"{rp}: bit depth {bits_r} differs from the left image's {bits_l}")
    base = options.params or MatchParameters()
    params = base if base.bit_depth is not None else replace(base, bit_depth=bits_l)
    if options.calibration is not None:
        from robostereo.io.calibration_files import read_calibration
        from robostereo.rig import match_rig

        calib = read_calibration(options.calibration, options.calibration_right)
        rr = match_rig(left, right, calib, (lo, hi), params=params, names=(str(lp), str(rp)))
        table = rr.table()
        xyz = np.column_stack([table["X"], table["Y"], table["Z"]])
        res, kind = rr.match, "rig"
    else:
        if right.shape[:2] != left.shape[:2]:
            raise InputError(
                f"{rp}: image is {right.shape[1]} x {right.shape[0]} (W x H), the left "
                f"image {left.shape[1]} x {left.shape[0]}"
            )
        cam_file = d / "camera.yaml"
        camera = load_stereo_camera(cam_file) if cam_file.is_file() else None
        res = match_stereo(left, right, (lo, hi), params=params, camera=camera)
        table = res.table()
        xyz = np.column_stack([table["X"], table["Y"], table["Z"]]) if camera else None
        kind = "pair"
    n_left, n = len(res.left_edges), len(res)
    return {
        "kind": kind, "edges_left": n_left, "edges_right": len(res.right_edges),
        "matched": n, "matched_percent": round(100.0 * n / n_left, 2) if n_left else 0.0,
        "points_3d": int(np.isfinite(xyz).all(axis=1).sum()) if xyz is not None else 0,
        "min_disparity": float(lo), "max_disparity": float(hi), **_checks(res),
        "output": _write_outputs(out, d.name, table, xyz, options.ply),
    }  # fmt: skip


def _run_capture(d: Path, out: Path, options: BatchOptions) -> dict[str, Any]:
    try:
        from robostereo.robot.capture import locate_capture
    except ImportError:
        raise InputError(
            f"{d / 'capture.yaml'}: capture folders need robostereo.robot.capture, which this "
            "installation lacks"
        ) from None
    located = locate_capture(d)
    table = located.table()
    res = located.result
    n_left, n = len(res.left_edges), len(located)
    lo, hi = located.disparity_range
    return {
        "kind": "capture", "edges_left": n_left, "edges_right": len(res.right_edges),
        "matched": n, "matched_percent": round(100.0 * n / n_left, 2) if n_left else 0.0,
        "points_3d": int(np.isfinite(located.world).all(axis=1).sum()),
        "min_disparity": float(lo), "max_disparity": float(hi), **_checks(res),
        "output": _write_outputs(out, d.name, table, located.world, options.ply),
    }  # fmt: skip


def _run_views(d: Path, out: Path, options: BatchOptions) -> dict[str, Any]:
    """An N-view folder, located as ``robostereo locate`` locates it: the same reader
    and locate, the same CSV columns and PLY properties."""
    from robostereo.robot.views.locating import locate_views
    from robostereo.robot.views.views_folder import read_views_capture

    located = locate_views(read_views_capture(d))
    table = located.table()
    n = len(located)
    return {
        "kind": "views", "matched": n,
        "points_3d": int(np.isfinite(located.world).all(axis=1).sum()),
        "output": _write_outputs(out, d.name, table, located.world, options.ply,
                                 fields=located.ply_fields()),
    }  # fmt: skip


def _checks(res: MatchResult) -> dict[str, Any]:
    """The summary's columns of the match's own checks (rows, grey levels)."""
    rows = res.row_offset
    return {
        "row_offset_px": "" if rows is None else round(float(rows.offset_px), 3),
        "row_tilt_px": "" if rows is None else round(float(rows.tilt_px), 3),
        "row_stretch_px": "" if rows is None else round(float(rows.stretch_px), 3),
        "rows_moved": int(rows is not None and rows.misaligned),
        "grey_mapped": int(res.grey_map is not None),
    }


def _is_views(d: Path) -> bool:
    """Whether the capture folder `d` holds N views (``views:`` in its capture.yaml)."""
    try:
        from robostereo.robot.views.views_folder import is_views_folder
    except ImportError:
        return False  # the two-view reader says what is missing
    return is_views_folder(d)


def _blank_row(name: str) -> dict[str, Any]:
    row: dict[str, Any] = dict.fromkeys(SUMMARY_COLUMNS, "")
    row["input"] = name
    return row


def process_input(
    input_dir: PathLike, out_dir: PathLike, options: BatchOptions | None = None
) -> dict[str, Any]:
    """Process one input folder and write its outputs; never raises for bad input.

    Parameters
    ----------
    input_dir : path
        A pair folder, a capture folder or an N-view capture folder (see the module
        docstring).
    out_dir : path
        Existing output folder.
    options : BatchOptions, optional

    Returns
    -------
    dict
        The summary row (:data:`SUMMARY_COLUMNS`) plus ``seconds``; ``status`` is
        ``"ok"`` or ``"error"`` with a one-line ``error`` naming the file.

    Notes
    -----
    1. Recognise the folder (``capture.yaml`` -> capture, with ``views:`` an N-view
       one; ``left.*`` and ``right.*`` -> pair; otherwise an error naming the folder:
       empty, or no such files).
    2. Match (and triangulate, where a camera or calibration is known).
    3. Write ``NAME.csv`` [and ``NAME.ply``], then ``NAME.json``, each atomically: the
       JSON file, written last, marks the input finished.
    """
    from robostereo.io import atomic_path

    d = Path(input_dir)
    out = Path(out_dir)
    opts = options or BatchOptions()
    row = _blank_row(d.name)
    t0 = time.perf_counter()
    signature = run_signature(d, opts)
    try:
        if not d.is_dir():
            raise InputError(f"{d}: input folder not found")
        try:
            entries = list(d.iterdir())
        except OSError as e:
            raise InputError(f"{d}: cannot read folder ({e.__class__.__name__})") from None
        if not entries:
            raise InputError(f"{d}: folder is empty")
        if (d / "capture.yaml").is_file():
            row.update(_run_views(d, out, opts) if _is_views(d) else
                       _run_capture(d, out, opts))
        elif _is_input(d):
            row.update(_run_pair(d, out, opts))
        else:
            raise InputError(
                f"{d}: neither a pair folder (left.* and right.*) nor a capture folder "
                "(capture.yaml)"
            )
        row["status"] = "ok"
    except InputError as e:
        row.update(status="error", error=str(e).splitlines()[0] if str(e) else "error")
    except Exception as e:  # keep the batch going; report the input as failed
        row.update(status="error", error=f"{d}: {e.__class__.__name__}: {e}".splitlines()[0])
    row["seconds"] = round(time.perf_counter() - t0, 4)
    row["signature"] = signature
    if row["status"] == "ok":
        with atomic_path(out / f"{d.name}.json") as tmp:
            tmp.write_text(json.dumps(row, indent=1, sort_keys=True))
    return row
