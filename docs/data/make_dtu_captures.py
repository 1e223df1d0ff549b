"""Make the capture folders of ``docs/data/dtu_scan24`` from DTU MVS scan 24.

Reads scan 24 of the DTU MVS data set (Aanæs et al., IJCV 2016) in the layout the IDR
and NeuS papers distribute (``image/NNNNNN.png``, ``mask/NNN.png``,
``cameras_sphere.npz``) from ``--source``, ``$ROBOSTEREO_DTU`` or
``../shared/data/robot/dtu_scan24`` beside the repository (only the images and the
cameras are read), and writes into ``--out``
(default: the ``dtu_scan24`` folder beside this script)::

    pair/     a two-view capture folder: capture.yaml, left.png (DTU view 1),
              right.png (view 2)
    views/    an N-view capture folder: capture.yaml with views:, image_000.png,
              image_001.png, image_002.png (views 0, 1, 2)
    heldout/  view 3, which neither folder uses, to check located points against:
              image_003.png and view.yaml (its camera and pose; robostereo does not
              read this file)

How each file is made:

* image: DTU's RGB image (lens distortion already removed) turned grey with OpenCV's
  weights and halved with pixel-area averaging, 1600 x 1200 to 800 x 600;
* camera pose: the top three rows of ``world_mat_i`` are ``P = K [R | t]`` (world to
  image, mm); :func:`cv2.decomposeProjectionMatrix` gives ``K``, ``R`` (world to
  camera) and the optical centre ``C``, and the pose robostereo wants is
  ``T_world_camera`` (camera to world): rotation ``R^T``, translation ``C``;
* camera: ``K`` halved for the halved images, ``f / 2`` and ``(c + 0.5) / 2 - 0.5``
  (pixel centres at whole coordinates, as in OpenCV and robostereo; taken to be DTU's
  too).  robostereo's camera today has only a physical form, a focal length and a pixel
  pitch in mm, so a pitch is chosen: :data:`PITCH_MM` horizontally, an arbitrary round
  number; the focal length is ``fx * pitch`` and the vertical pitch ``focal / fy``.
  The points do not depend on the choice, the eq. 9 bound does (its focal-length term
  is ``uncertainty: focal_length_mm``, 0.01 mm by default, over that focal length);
* depth range: 500 .. 850 mm along the optical axis (the house lies 540-790 mm from
  these cameras).

Run ``python docs/data/make_dtu_captures.py`` to write the folders again (an existing
``--out`` folder's three sub-folders are replaced) or ``--check`` to compare what it
would write with what is there (exit code 1 when they differ).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np
import yaml

from robostereo import SE3, Camera, Capture, ViewsCapture, write_capture, write_views_capture
from robostereo.geometry.camera import camera_to_dict
from robostereo.geometry.poses import pose_to_dict
from robostereo.io import folder_yaml_text, write_image_folder

HERE = Path(__file__).resolve().parent

#: DTU views of the two-view folder (left, right), of the N-view folder, and held out
PAIR = (1, 2)
VIEWS = (0, 1, 2)
HELD_OUT = 3

#: image scale: 1600 x 1200 to 800 x 600
SCALE = 0.5

#: horizontal pixel pitch, mm, of the halved images: an arbitrary round number (the
#: camera has a physical form only today); the points do not depend on it, the bound does
PITCH_MM = 0.01

#: depth along the optical axis to search, mm
DEPTH_RANGE_MM = (500.0, 850.0)

CITATION = ("DTU MVS scan 24 (Aanaes, Jensen, Vogiatzis, Tola and Dahl, Large-scale data "
            "for multiple-view stereopsis, IJCV 2016)")


def default_source() -> Path | None:
    """``$ROBOSTEREO_DTU``, else ``../shared/data/robot/dtu_scan24`` beside the repository,
    when it exists."""
    env = os.environ.get("ROBOSTEREO_DTU")
    for d in ([Path(env)] if env else []) + [HERE.parents[2] / "shared/data/robot/dtu_scan24"]:
        if (d / "cameras_sphere.npz").is_file():
            return d
    return None


def decompose(P: np.ndarray) -> tuple[np.ndarray, SE3]:
    """``K`` (3, 3) and the pose ``T_world_camera`` of a projection ``P = K [R | t]``.

    Parameters
    ----------
    P : ndarray, shape (3, 4)
        World (mm) to image (px); DTU's are float32, decomposed in float64.
    """
    K, R, c, *_ = cv2.decomposeProjectionMatrix(np.asarray(P, dtype=np.float64))
    K = K / K[2, 2]
    centre = (c[:3] / c[3]).ravel()
    return K, SE3(R.T, np.round(centre, 4))  # the centre to 0.1 um: a shorter file


def grey_image(source: Path, view: int) -> np.ndarray:
    """DTU's image of `view`, grey, halved by pixel-area averaging: ``(600, 800)`` uint8."""
    img = cv2.imread(str(source / "image" / f"{view:06d}.png"), cv2.IMREAD_GRAYSCALE)
    if img is None:
        raise SystemExit(f"{source}: cannot read image/{view:06d}.png")
    h, w = img.shape
    return cv2.resize(img, (round(w * SCALE), round(h * SCALE)), interpolation=cv2.INTER_AREA)


def camera_of(Ks: list[np.ndarray], size: tuple[int, int]) -> Camera:
    """The halved images' camera from the views' ``K`` (all alike to 0.01 px)."""
    K = np.mean(Ks, axis=0)
    if max(float(np.abs(k - K).max()) for k in Ks) > 0.01 or abs(K[0, 1]) > 0.01:
        raise SystemExit("the views' intrinsics differ, or K has a skew")
    fx, fy = round(K[0, 0] * SCALE, 4), round(K[1, 1] * SCALE, 4)
    cx = round((K[0, 2] + 0.5) * SCALE - 0.5, 4)
    cy = round((K[1, 2] + 0.5) * SCALE - 0.5, 4)
    focal = round(fx * PITCH_MM, 9)
    return Camera(focal_length_mm=focal, pixel_pitch_mm=(PITCH_MM, round(focal / fy, 12)),
                  image_size=size, principal_point=(cx, cy), grey_levels=256)


def notes(views: tuple[int, ...]) -> dict[str, object]:
    """The free-form ``robot`` and ``scene`` notes of a folder (not read)."""
    return {"robot": {"what": "a camera on an industrial robot arm (DTU's), poses from "
                              "DTU's calibration, camera to world"},
            "scene": {"source": CITATION, "dtu_views": list(views),
                      "made_by": "docs/data/make_dtu_captures.py"}}


def make(source: Path, out: Path) -> None:
    """Write ``pair/``, ``views/`` and ``heldout/`` into `out` (which must exist)."""
    npz = np.load(source / "cameras_sphere.npz")
    wanted = sorted(set(PAIR) | set(VIEWS) | {HELD_OUT})
    K, pose, image = {}, {}, {}
    for v in wanted:
        K[v], pose[v] = decompose(npz[f"world_mat_{v}"][:3])
        image[v] = grey_image(source, v)
    h, w = image[wanted[0]].shape
    camera = camera_of([K[v] for v in wanted], (w, h))

    left, right = PAIR
    write_capture(out / "pair", Capture(
        left=image[left], right=image[right], camera=camera, pose_left=pose[left],
        pose_right=pose[right], bit_depth=8, depth_range_mm=DEPTH_RANGE_MM,
        notes=notes(PAIR)))
    write_views_capture(out / "views", ViewsCapture(
        tuple(image[v] for v in VIEWS), camera, tuple(pose[v] for v in VIEWS),
        depth_range_mm=DEPTH_RANGE_MM, bit_depth=8,
        names=tuple(f"image_{v:03d}.png" for v in VIEWS), notes=notes(VIEWS)))
    held = {
        "image": f"image_{HELD_OUT:03d}.png",
        "camera": camera_to_dict(camera),
        "pose": pose_to_dict(pose[HELD_OUT]),
        "scene": notes((HELD_OUT,))["scene"],
    }
    write_image_folder(out / "heldout",
                       {held["image"]: image[HELD_OUT]},
                       {"view.yaml": "# a view held out of pair/ and views/, to check located "
                                     "points against (not read by robostereo)\n"
                                     + folder_yaml_text(held)})


def _same(a: object, b: object) -> bool:
    """Parsed YAML values equal, numbers to 1e-9 (relative): the last digits of a
    decomposition may differ between OpenCV builds."""
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float | int) and isinstance(b, float | int) \
            and not isinstance(a, bool) and not isinstance(b, bool):
        return bool(np.isclose(a, b, rtol=1e-9, atol=1e-9))
    return a == b


def differences(a: Path, b: Path) -> list[str]:
    """Files of the two folders that differ: PNGs by their pixels, YAML by its values
    (:func:`_same`)."""
    names = sorted({p.relative_to(a) for p in a.rglob("*") if p.is_file()}
                   | {p.relative_to(b) for p in b.rglob("*") if p.is_file()})
    out = []
    for n in names:
        pa, pb = a / n, b / n
        if not (pa.is_file() and pb.is_file()):
            out.append(f"{n}: only in one")
        elif n.suffix == ".png":
            ia, ib = (cv2.imread(str(p), cv2.IMREAD_UNCHANGED) for p in (pa, pb))
            if ia.shape != ib.shape or not np.array_equal(ia, ib):
                out.append(f"{n}: pixels differ")
        elif not _same(*(yaml.safe_load(p.read_text(encoding="utf-8")) for p in (pa, pb))):
            out.append(f"{n}: differs")
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--source", type=Path, default=None,
                    help="DTU scan 24 in the IDR layout (default $ROBOSTEREO_DTU or "
                         "../shared/data/robot/dtu_scan24)")
    ap.add_argument("--out", type=Path, default=HERE / "dtu_scan24")
    ap.add_argument("--check", action="store_true",
                    help="compare with the folders in --out instead of writing them")
    args = ap.parse_args(argv)
    source = args.source or default_source()
    if source is None or not (source / "cameras_sphere.npz").is_file():
        print("DTU scan 24 not found: give --source or set $ROBOSTEREO_DTU", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory() as tmp:
        make(source, Path(tmp))
        if args.check:
            diff = differences(Path(tmp), args.out)
            print("\n".join(diff) if diff else f"{args.out}: as the script writes it")
            return 1 if diff else 0
        args.out.mkdir(parents=True, exist_ok=True)
        for sub in ("pair", "views", "heldout"):
            shutil.rmtree(args.out / sub, ignore_errors=True)
            shutil.copytree(Path(tmp) / sub, args.out / sub)
    print(f"wrote {args.out}/pair, views and heldout from {source}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
