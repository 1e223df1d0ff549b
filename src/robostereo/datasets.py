"""Stereo scenes with ground-truth disparity, for evaluation.

:func:`load_scene` reads a rectified pair and its ground-truth disparity from a
directory in one of these layouts:

* the project's developer set (``left.*``, ``right.*``, ``gt_disp_left.*`` and
  optionally ``gt_disp_right.*``, with the scale in a ``scenes.json`` beside the scene
  directories), e.g. ``/work/shared/data/stereo/tsukuba``;
* Middlebury 2001 (``im2.ppm``, ``im6.ppm``, ``disp2.pgm`` [, ``disp6.pgm``], scale 8)
  and 2003 (same names, scale 4 for ``cones`` and ``teddy``), and the original Tsukuba
  names (``scene1.row3.col3.ppm``, ``scene1.row3.col4.ppm``, ``truedisp.row3.col3.pgm``,
  scale 16);
* Middlebury 2005/2006 (``view1.png``, ``view5.png``, ``disp1.png`` [, ``disp5.png``],
  scale given by the caller);
* Middlebury 2014/2021 and MiddEval3 (``im0.png``, ``im1.png``, ``disp0.pfm`` or
  ``disp0GT.pfm`` [, ``disp1.pfm``], ``calib.txt``).

Integer ground truth is ``d = raw / scale`` with ``raw == 0`` unknown; PFM ground truth
is in pixels with ``inf`` unknown.  Unknown disparities become NaN.  Disparity follows
the project's convention: the left pixel ``(x, y)`` matches the right pixel
``(x - d, y)``.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.geometry.calibrated_rectification import check_image_size
from robostereo.geometry.calibration import StereoCalibration
from robostereo.io.calibration_files import read_middlebury_calib
from robostereo.io.images import load_image, read_pfm

__all__ = [
    "KNOWN_SCALES",
    "StereoScene",
    "available_scenes",
    "disparity_consistency",
    "find_data_dir",
    "load_scene",
]

PathLike = str | Path

KNOWN_SCALES: dict[str, int] = {
    "tsukuba": 16,
    "venus": 8,
    "sawtooth": 8,
    "bull": 8,
    "poster": 8,
    "barn1": 8,
    "barn2": 8,
    "map": 8,
    "cones": 4,
    "teddy": 4,
}
"""Ground-truth scale (``d = raw / scale``) of the integer-coded Middlebury 2001/2003 scenes."""

_IMAGE_EXTS = (".png", ".ppm", ".pgm", ".pnm", ".tif", ".tiff", ".bmp", ".jpg", ".jpeg")


# ---------------------------------------------------------------------------- scenes


@dataclass(frozen=True, eq=False)
class StereoScene:
    """A rectified stereo pair with ground-truth disparity.

    Attributes
    ----------
    name : str
        Scene name (the directory name unless given).
    left, right : ndarray, shape (H, W) or (H, W, C)
        The images as stored (dtype kept).
    gt_disparity : ndarray, shape (H, W), float64
        Disparity of the left view in pixels, NaN where unknown; the left pixel
        ``(x, y)`` matches the right pixel ``(x - d, y)``.
    disparity_range : tuple of float
        ``(min, max)`` of the known ground truth.
    calib : StereoCalibration or None
        From ``calib.txt`` (Middlebury 2014/2021), else None.
    gt_disparity_right : ndarray, shape (H, W), or None
        Disparity of the right view (right ``(x, y)`` matches left ``(x + d, y)``).
    bit_depth : int
        Bits per sample of the left image.
    path : Path or None
        The scene directory.
    """

    name: str
    left: NDArray[Any]
    right: NDArray[Any]
    gt_disparity: NDArray[np.float64]
    disparity_range: tuple[float, float]
    calib: StereoCalibration | None = None
    gt_disparity_right: NDArray[np.float64] | None = None
    bit_depth: int = 8
    path: Path | None = None

    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)`` of the images."""
        return int(self.left.shape[0]), int(self.left.shape[1])

    @property
    def known(self) -> NDArray[np.bool_]:
        """Mask of pixels with ground truth, shape (H, W)."""
        return np.isfinite(self.gt_disparity)

    @property
    def unknown_fraction(self) -> float:
        """Fraction of left pixels without ground truth."""
        return float(1.0 - self.known.mean())


def find_data_dir() -> Path | None:
    """The developer data directory (``.../shared/data/stereo``), or None.

    Looks in order at ``$ROBOSTEREO_DATA``, ``<repo>/../shared/data/stereo`` (from this
    file's location) and ``./../shared/data/stereo`` (from the working directory).

    Raises
    ------
    InputError
        ``$ROBOSTEREO_DATA`` is set but is not a directory.
    """
    env = os.environ.get("ROBOSTEREO_DATA")
    if env:
        p = Path(env).expanduser()
        if not p.is_dir():
            raise InputError(f"ROBOSTEREO_DATA={env} is not a directory")
        return p
    here = Path(__file__).resolve()
    candidates = []
    if len(here.parents) > 3:
        candidates.append(here.parents[3] / "shared" / "data" / "stereo")
    candidates.append(Path.cwd() / ".." / "shared" / "data" / "stereo")
    for c in candidates:
        if c.is_dir():
            return c.resolve()
    return None


def _read_index(data_dir: Path) -> dict[str, Any] | None:
    index = data_dir / "scenes.json"
    if not index.is_file():
        return None
    try:
        doc = json.loads(index.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise InputError(f"{index}: cannot parse ({e.__class__.__name__})") from None
    scenes = doc.get("scenes") if isinstance(doc, dict) else None
    if not isinstance(scenes, dict):
        raise InputError(f"{index}: expected an object with a 'scenes' mapping")
    return scenes


def available_scenes(data_dir: PathLike | None = None) -> list[str]:
    """Scene names listed in ``scenes.json`` of `data_dir` (default :func:`find_data_dir`)."""
    d = find_data_dir() if data_dir is None else Path(data_dir)
    if d is None:
        return []
    scenes = _read_index(d)
    return sorted(scenes) if scenes else []


def _find(directory: Path, stem: str) -> Path | None:
    for ext in _IMAGE_EXTS:
        for cand in (directory / (stem + ext), directory / (stem + ext.upper())):
            if cand.is_file():
                return cand
    return None


def _integer_disparity(path: Path, scale: float) -> NDArray[np.float64]:
    raw, _ = load_image(path)
    if raw.ndim != 2:
        raise InputError(f"{path}: ground-truth disparity must be single-channel, got {raw.shape}")
    d = raw.astype(np.float64) / float(scale)
    d[raw == 0] = np.nan
    return d


def _pfm_disparity(path: Path) -> NDArray[np.float64]:
    a = read_pfm(path)
    if a.ndim != 2:
        raise InputError(f"{path}: ground-truth disparity must be a one-channel Pf, got {a.shape}")
    d = a.astype(np.float64)
    d[~np.isfinite(d)] = np.nan
    return d


def _check_scale(scale: Any) -> float:
    if not isinstance(scale, int | float) or not np.isfinite(scale) or scale <= 0:
        raise InputError(f"scale must be a finite number > 0, got {scale}")
    return float(scale)


def load_scene(
    path: PathLike,
    *,
    scale: float | None = None,
    name: str | None = None,
) -> StereoScene:
    """Load a rectified stereo scene with ground truth from a directory.

    Parameters
    ----------
    path : str or Path
        The scene directory, or a scene name listed in the ``scenes.json`` of
        :func:`find_data_dir` (e.g. ``"tsukuba"``).
    scale : float, optional
        ``d = raw / scale`` for integer-coded ground truth; overrides ``scenes.json`` and
        :data:`KNOWN_SCALES`.  Required for unknown names in the 2005/2006 layout and
        for the developer layout without ``scenes.json``.
    name : str, optional
        Scene name; default the directory name (lower-cased when looking up scales).

    Returns
    -------
    StereoScene

    Raises
    ------
    InputError
        Missing directory or files, unknown layout, unknown scale, images or ground truth
        of mismatched sizes (naming the file), no known ground truth at all.

    Notes
    -----
    1. Recognise the layout from the file names (see the module docstring), in the
       order: developer set, Middlebury 2014/2021, 2001/2003, original Tsukuba,
       2005/2006.
    2. Choose the scale: `scale`, else ``scenes.json`` beside the scene directory, else
       :data:`KNOWN_SCALES` by name, else the layout's default (8 for
       ``im2/im6/disp2.pgm``).
    3. Load the images with :func:`load_image` and the ground truth (``raw / scale``
       with 0 -> NaN, or PFM with inf -> NaN); check that every map has the left
       image's size and, with ``calib.txt``, that the images have the calibrated size.
    """
    if scale is not None:
        scale = _check_scale(scale)
    d = Path(path)
    if not d.is_dir():
        data_dir = find_data_dir()
        cand = data_dir / str(path) if data_dir is not None and str(path).isidentifier() else None
        if cand is None or not cand.is_dir():
            raise InputError(f"{path}: scene directory not found")
        d = cand
    scene_name = name if name is not None else d.resolve().name
    key = scene_name.lower()
    calib: StereoCalibration | None = None
    right_gt_path: Path | None = None

    left_p, right_p = _find(d, "left"), _find(d, "right")
    gt_p = _find(d, "gt_disp_left")
    if left_p and right_p and gt_p:  # (a) the developer set
        right_gt_path = _find(d, "gt_disp_right")
        if scale is None:
            scenes = _read_index(d.resolve().parent)
            entry = scenes.get(scene_name) if scenes else None
            if isinstance(entry, dict) and "scale" in entry:
                scale = _check_scale(entry["scale"])
            elif key in KNOWN_SCALES:
                scale = float(KNOWN_SCALES[key])
            else:
                load_image(gt_p)  # a corrupt file is the error to report, not the scale
                raise InputError(
                    f"{gt_p}: disparity scale unknown (no scenes.json entry for "
                    f"{scene_name!r}); pass scale="
                )
        gt_loader = _integer_disparity
    elif (d / "im0.png").is_file() and (d / "im1.png").is_file():  # (c) Middlebury 2014/2021
        left_p, right_p = d / "im0.png", d / "im1.png"
        gt_p = next((q for q in (d / "disp0.pfm", d / "disp0GT.pfm") if q.is_file()), None)
        if gt_p is None:
            raise InputError(f"{d}: Middlebury 2014 layout needs disp0.pfm or disp0GT.pfm")
        right_gt_path = next(
            (q for q in (d / "disp1.pfm", d / "disp1GT.pfm") if q.is_file()), None
        )
        if (d / "calib.txt").is_file():
            calib = read_middlebury_calib(d / "calib.txt").calibration
        gt_loader = None
    elif _find(d, "im2") and _find(d, "im6") and _find(d, "disp2"):  # (b) 2001 / 2003
        left_p, right_p, gt_p = _find(d, "im2"), _find(d, "im6"), _find(d, "disp2")
        right_gt_path = _find(d, "disp6")
        if scale is None:
            scale = float(KNOWN_SCALES.get(key, 8))
        gt_loader = _integer_disparity
    elif _find(d, "scene1.row3.col3") and _find(d, "scene1.row3.col4"):  # original Tsukuba
        left_p, right_p = _find(d, "scene1.row3.col3"), _find(d, "scene1.row3.col4")
        gt_p = _find(d, "truedisp.row3.col3")
        if gt_p is None:
            raise InputError(f"{d}: Tsukuba layout needs truedisp.row3.col3.pgm")
        scale = 16.0 if scale is None else scale
        gt_loader = _integer_disparity
    elif _find(d, "view1") and _find(d, "view5") and _find(d, "disp1"):  # (b) 2005 / 2006
        left_p, right_p, gt_p = _find(d, "view1"), _find(d, "view5"), _find(d, "disp1")
        right_gt_path = _find(d, "disp5")
        if scale is None:
            load_image(gt_p)  # a corrupt file is the error to report, not the scale
            raise InputError(f"{gt_p}: disparity scale of 2005/2006 layout unknown, pass scale=")
        gt_loader = _integer_disparity
    else:
        raise InputError(
            f"{d}: no known stereo layout (left/right/gt_disp_left, im0/im1/disp0.pfm, "
            "im2/im6/disp2, view1/view5/disp1)"
        )
    assert left_p is not None and right_p is not None and gt_p is not None

    left, depth = load_image(left_p)
    right, _ = load_image(right_p)
    if right.shape != left.shape:
        raise InputError(f"{right_p}: right image has shape {right.shape}, left {left.shape}")
    if calib is not None:
        check_image_size(calib, left.shape, left_p)

    def load_gt(p: Path) -> NDArray[np.float64]:
        g = _pfm_disparity(p) if gt_loader is None else gt_loader(p, float(scale or 1.0))
        if g.shape != left.shape[:2]:
            raise InputError(
                f"{p}: ground truth is {g.shape[1]} x {g.shape[0]} (W x H), the left image "
                f"{left.shape[1]} x {left.shape[0]}"
            )
        g.setflags(write=False)
        return g

    gt = load_gt(gt_p)
    gt_right = load_gt(right_gt_path) if right_gt_path is not None else None
    known = np.isfinite(gt)
    if not known.any():
        raise InputError(f"{gt_p}: ground truth has no known disparity")
    left.setflags(write=False)
    right.setflags(write=False)
    return StereoScene(
        name=scene_name, left=left, right=right, gt_disparity=gt,
        disparity_range=(float(gt[known].min()), float(gt[known].max())), calib=calib,
        gt_disparity_right=gt_right, bit_depth=depth, path=d,
    )  # fmt: skip


def _grey(image: NDArray[Any]) -> NDArray[np.float64]:
    a = np.asarray(image, dtype=np.float64)
    if a.ndim == 3:
        a = a[:, :, :3].mean(axis=2)
    return a


def disparity_consistency(
    scene: StereoScene,
    *,
    rng: np.random.Generator,
    n_points: int = 500,
    shift: float = 1.0,
    top_fraction: float = 0.2,
) -> tuple[float, float]:
    """Photometric check of the ground truth: mean ``|left(x, y) - right(x - d, y)|``.

    Parameters
    ----------
    scene : StereoScene
    rng : numpy.random.Generator
        Chooses the sample pixels.
    n_points : int
        Number of sample pixels.
    shift : float
        Disparity offset of the comparison value.
    top_fraction : float
        Sample among the known pixels whose horizontal gradient is in this top fraction.

    Returns
    -------
    mad, mad_shifted : float
        Mean absolute grey difference (grey = mean of the colour channels) with the
        ground truth ``d`` and with ``d + shift``; a correct ground truth (right scale and
        direction) gives ``mad`` well below ``mad_shifted``.

    Notes
    -----
    1. Grey images; horizontal gradient ``|I(x+1) - I(x-1)| / 2``.
    2. Candidate pixels: known ``d``, gradient in the top `top_fraction`, and both
       ``x - d`` and ``x - d - shift`` inside the right image.
    3. Sample `n_points` without replacement; read the right image with linear
       interpolation along the row.
    """
    if n_points < 1:
        raise InputError(f"n_points must be >= 1, got {n_points}")
    if not 0.0 < top_fraction <= 1.0:
        raise InputError(f"top_fraction must be in (0, 1], got {top_fraction}")
    gl, gr = _grey(scene.left), _grey(scene.right)
    w = gl.shape[1]
    grad = np.zeros_like(gl)
    grad[:, 1:-1] = np.abs(gl[:, 2:] - gl[:, :-2]) / 2.0
    d = scene.gt_disparity
    known = np.isfinite(d)
    thresh = np.quantile(grad[known], 1.0 - top_fraction)
    yy, xx = np.nonzero(known & (grad >= thresh))
    dd = d[yy, xx]
    ok = (xx - dd - max(shift, 0.0) >= 0) & (xx - dd - min(shift, 0.0) <= w - 1)
    yy, xx, dd = yy[ok], xx[ok], dd[ok]
    if yy.size == 0:
        raise InputError(f"scene {scene.name}: no pixels with known disparity to compare")
    pick = rng.choice(yy.size, size=min(n_points, yy.size), replace=False)
    yy, xx, dd = yy[pick], xx[pick], dd[pick]

    def sample(xs: NDArray[np.float64]) -> NDArray[np.float64]:
        x0 = np.clip(np.floor(xs).astype(int), 0, w - 2)
        t = xs - x0
        return (1.0 - t) * gr[yy, x0] + t * gr[yy, x0 + 1]

    ref = gl[yy, xx]
    mad = float(np.mean(np.abs(ref - sample(xx - dd))))
    mad_shifted = float(np.mean(np.abs(ref - sample(xx - dd - shift))))
    return mad, mad_shifted
