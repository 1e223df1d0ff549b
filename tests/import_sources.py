"""Small IDR, MVSNet and COLMAP sources written for the importers' tests: three views
of a camera on an arc 600 mm from an object, their cameras in each tool's files."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from robostereo.geometry.poses import SE3

__all__ = ["CENTRE", "H", "K", "W", "poses", "projected", "sphere_points", "write_colmap",
           "write_colmap_binary",
           "write_idr", "write_images", "write_mvsnet"]

K = np.array([[500.0, 0.0, 159.5], [0.0, 505.0, 119.5], [0.0, 0.0, 1.0]])
W, H = 320, 240
CENTRE = np.array([20.0, -10.0, 650.0])


def poses(n: int = 3) -> list[SE3]:
    out = []
    for a in np.radians(np.linspace(-10.0, 10.0, n)):
        eye = CENTRE + 600.0 * np.array([np.sin(a), 0.2, -np.cos(a)])
        out.append(SE3.look_at(eye, CENTRE, up=(0.0, -1.0, 0.0)))
    return out


def sphere_points(n: int = 500, radius: float = 100.0) -> np.ndarray:
    rng = np.random.default_rng(5)
    d = rng.normal(size=(n, 3))
    return CENTRE + radius * d / np.linalg.norm(d, axis=1)[:, None] * rng.uniform(0, 1, (n, 1))


def write_images(folder: Path, names: list[str], size=(W, H)) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(1)
    for n in names:
        cv2.imwrite(str(folder / n), rng.integers(0, 256, (size[1], size[0], 3)).astype(
            np.uint8))


def projected(P: np.ndarray, M: np.ndarray) -> np.ndarray:
    h = np.c_[P, np.ones(len(P))] @ M.T
    return h[:, :2] / h[:, 2:]


def write_idr(tmp_path: Path) -> Path:
    S = np.diag([120.0, 120.0, 120.0, 1.0])
    S[:3, 3] = CENTRE
    arrays = {}
    for i, p in enumerate(poses()):
        world_to_cam = p.inv().matrix
        M = np.eye(4)
        M[:3] = K @ world_to_cam[:3]
        arrays[f"world_mat_{i}"] = M.astype(np.float32)
        arrays[f"scale_mat_{i}"] = S.astype(np.float32)
    np.savez(tmp_path / "cameras.npz", **arrays)
    write_images(tmp_path / "image", [f"{i:06d}.png" for i in range(3)])
    return tmp_path / "cameras.npz"


def write_mvsnet(tmp_path: Path, *, depth_line: str = "425.0 2.5") -> Path:
    d = tmp_path / "scan"
    (d / "cams").mkdir(parents=True)
    for i, p in enumerate(poses()):
        E = np.round(p.inv().matrix, 6)  # printed with 6 decimals, as MVSNet's files
        Kq = K.copy()
        Kq[:2] /= 4.0  # MVSNet's DTU cameras: a quarter of the image size
        text = "extrinsic\n" + "\n".join(" ".join(f"{v:.6f}" for v in r) for r in E)
        text += "\n\nintrinsic\n" + "\n".join(" ".join(f"{v:.6f}" for v in r) for r in Kq)
        (d / "cams" / f"{i:08d}_cam.txt").write_text(text + f"\n\n{depth_line}\n")
    (d / "pair.txt").write_text("3\n0\n2 1 10.0 2 5.0\n1\n2 0 10.0 2 9.0\n2\n2 1 9.0 0 5.0\n")
    write_images(d / "images", [f"{i:08d}.jpg" for i in range(3)])
    return d


def write_colmap(tmp_path: Path, model_line: str) -> Path:
    m = tmp_path / "sparse"
    m.mkdir()
    (m / "cameras.txt").write_text("# Camera list\n" + model_line + "\n")
    lines = ["# Image list"]
    P = sphere_points(60)
    for i, p in enumerate(poses(), 1):
        T = p.inv()
        qx, qy, qz, qw = T.quaternion
        tx, ty, tz = T.translation
        lines += [f"{i} {qw} {qx} {qy} {qz} {tx} {ty} {tz} 1 view{i}.png", ""]
    (m / "images.txt").write_text("\n".join(lines) + "\n")
    pts = [f"{k} {x} {y} {z} 0 0 0 0.5 1 0 2 0 3 0" for k, (x, y, z) in enumerate(P)]
    (m / "points3D.txt").write_text("# 3D point list\n" + "\n".join(pts) + "\n")
    write_images(tmp_path / "images", [f"view{i}.png" for i in (1, 2, 3)])
    return m


def write_colmap_binary(text_model: Path) -> Path:
    """The binary files (``*.bin``) of a text model of :func:`write_colmap`, beside it in
    ``sparse_bin``, written record by record as COLMAP does."""
    import struct

    out = text_model.parent / "sparse_bin"
    out.mkdir()
    ids = {"SIMPLE_PINHOLE": 0, "PINHOLE": 1, "SIMPLE_RADIAL": 2, "RADIAL": 3, "OPENCV": 4}
    rows = [ln.split() for ln in (text_model / "cameras.txt").read_text().splitlines()
            if ln and not ln.startswith("#")]
    data = struct.pack("<Q", len(rows))
    for t in rows:
        data += struct.pack("<iiQQ", int(t[0]), ids[t[1]], int(t[2]), int(t[3]))
        data += struct.pack(f"<{len(t) - 4}d", *map(float, t[4:]))
    (out / "cameras.bin").write_bytes(data)
    rows = [ln.split() for ln in (text_model / "images.txt").read_text().splitlines()
            if ln and not ln.startswith("#")]
    data = struct.pack("<Q", len(rows))
    for t in rows:
        data += struct.pack("<i7di", int(t[0]), *map(float, t[1:8]), int(t[8]))
        data += t[9].encode() + b"\0" + struct.pack("<Q", 1) + struct.pack("<2dq", 1, 2, -1)
    (out / "images.bin").write_bytes(data)
    rows = [ln.split() for ln in (text_model / "points3D.txt").read_text().splitlines()
            if ln and not ln.startswith("#")]
    data = struct.pack("<Q", len(rows))
    for t in rows:
        track = list(map(int, t[8:]))
        data += struct.pack("<Q3d3Bd", int(t[0]), *map(float, t[1:4]), 0, 0, 0, float(t[7]))
        data += struct.pack("<Q", len(track) // 2) + struct.pack(f"<{len(track)}i", *track)
    (out / "points3D.bin").write_bytes(data)
    return out
