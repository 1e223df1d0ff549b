"""COLMAP's binary model files: ``cameras.bin``, ``images.bin``, ``points3D.bin``.

Little-endian records, as COLMAP's ``WriteCamerasBinary`` and the others write them
(``src/colmap/scene/reconstruction_io.cc``)::

    cameras.bin    uint64 n; n x (int32 id, int32 model, uint64 width, uint64 height,
                   double params[model's count])
    images.bin     uint64 n; n x (int32 id, double qw qx qy qz tx ty tz, int32 camera,
                   char name[] NUL-terminated, uint64 m, m x (double x, y, int64 point))
    points3D.bin   uint64 n; n x (uint64 id, double x y z, uint8 r g b, double error,
                   uint64 t, t x (int32 image, int32 point2D))

Each reader gives what :mod:`~robostereo.robot.importers.colmap`'s text readers give.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from robostereo.errors import InputError

__all__ = ["MODEL_IDS", "read_cameras_bin", "read_images_bin", "read_points3d_bin"]

#: COLMAP's camera model ids -> (name, number of parameters)
MODEL_IDS = {0: ("SIMPLE_PINHOLE", 3), 1: ("PINHOLE", 4), 2: ("SIMPLE_RADIAL", 4),
             3: ("RADIAL", 5), 4: ("OPENCV", 8), 5: ("OPENCV_FISHEYE", 8),
             6: ("FULL_OPENCV", 12), 7: ("FOV", 5), 8: ("SIMPLE_RADIAL_FISHEYE", 4),
             9: ("RADIAL_FISHEYE", 5), 10: ("THIN_PRISM_FISHEYE", 12)}


class _Reader:
    """Little-endian values read one after another from a file's bytes."""

    def __init__(self, path: Path) -> None:
        self.path = path
        try:
            self.data = path.read_bytes()
        except OSError as exc:
            raise InputError(f"{path}: cannot read the COLMAP model file ({exc})") from None
        self.at = 0

    def take(self, fmt: str) -> tuple:
        size = struct.calcsize("<" + fmt)
        if self.at + size > len(self.data):
            raise InputError(f"{self.path}: ends inside a record (truncated, or not "
                             "COLMAP's binary format)")
        out = struct.unpack_from("<" + fmt, self.data, self.at)
        self.at += size
        return out

    def count(self, what: str) -> int:
        n = int(self.take("Q")[0])
        if n > len(self.data):
            raise InputError(f"{self.path}: {n:,} {what} in {len(self.data):,} bytes: not "
                             "COLMAP's binary format")
        return n


def read_cameras_bin(path: str | Path) -> dict[int, tuple[str, list[float]]]:
    """``{camera id: (model name, params)}`` of a ``cameras.bin``."""
    r = _Reader(Path(path))
    out = {}
    for _ in range(r.count("cameras")):
        cid, model, _w, _h = r.take("iiQQ")
        if model not in MODEL_IDS:
            raise InputError(f"{path}: camera {cid} has model id {model}, not COLMAP's")
        name, n = MODEL_IDS[model]
        out[int(cid)] = (name, [float(v) for v in r.take(f"{n}d")])
    return out


def read_images_bin(path: str | Path
                    ) -> list[tuple[int, list[float], list[float], int, str]]:
    """``[(image id, (qw, qx, qy, qz), (tx, ty, tz), camera id, name)]`` of an
    ``images.bin``."""
    r = _Reader(Path(path))
    out = []
    for _ in range(r.count("images")):
        iid, qw, qx, qy, qz, tx, ty, tz, cid = r.take("i7di")
        end = r.data.find(b"\0", r.at)
        if end < 0:
            raise InputError(f"{path}: image {iid}'s name is not NUL-terminated")
        name = r.data[r.at:end].decode("utf-8", errors="replace")
        r.at = end + 1
        m = r.count("2-D points")
        r.take(f"{3 * m}d" if m else "")  # x, y (doubles) and the int64 id: 24 bytes
        out.append((int(iid), [qw, qx, qy, qz], [tx, ty, tz], int(cid), name))
    return out


def read_points3d_bin(path: str | Path) -> tuple[np.ndarray, list[set[int]]]:
    """The points ``(N, 3)`` of a ``points3D.bin`` and the image ids of each track."""
    r = _Reader(Path(path))
    xyz, seen = [], []
    for _ in range(r.count("points")):
        _pid, x, y, z, _r, _g, _b, _err = r.take("Q3d3Bd")
        t = r.count("track entries")
        track = r.take(f"{2 * t}i") if t else ()
        xyz.append((x, y, z))
        seen.append(set(track[0::2]))
    return np.array(xyz, dtype=float).reshape(-1, 3), seen
