"""Reading and writing stereo calibration files.

A :class:`~robostereo.geometry.calibration.StereoCalibration` can be read from

* OpenCV ``FileStorage`` files (YAML, XML or JSON) with keys ``K1 D1 K2 D2 R T``
  (``M1``/``M2`` accepted for ``K1``/``K2``) and the image size
  (:func:`read_opencv_calibration`, written by :func:`write_opencv_calibration`);
* a ROS ``camera_info`` YAML pair ``left.yaml``/``right.yaml``
  (:func:`read_ros_calibration`);
* a Middlebury 2014/2021 ``calib.txt`` (:func:`read_middlebury_calib`), which
  describes an already rectified pair;

and :func:`read_calibration` picks the reader from a file's contents.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import yaml
from numpy.typing import NDArray

from robostereo.errors import InputError, require_file
from robostereo.geometry.calibration import (
    StereoCalibration,
    check_camera_matrix,
    check_distortion,
    check_rotation,
    check_size,
    frozen_array,
)

__all__ = [
    "MiddleburyCalib",
    "calibration_matrix",
    "read_calibration",
    "read_calibration_mapping",
    "read_middlebury_calib",
    "read_opencv_calibration",
    "read_ros_calibration",
    "write_opencv_calibration",
]

PathLike = str | Path

def _require_file(path: PathLike) -> Path:
    return require_file(path, "calibration file")


_SPECIAL = {".nan": "nan", ".inf": "inf", "-.inf": "-inf", "+.inf": "inf"}
"""OpenCV's spelling of NaN and infinities in FileStorage files (``.Nan``, ``-.Inf``)."""


def _opencv_specials(text: str, *, json_text: bool) -> str:
    """``.Nan``/``.Inf`` as written by OpenCV, in the spelling of JSON or YAML 1.1."""
    def repl(m: re.Match[str]) -> str:
        sign, word = m.group(1), m.group(2).lower()
        if json_text:
            return "NaN" if word == "nan" else f"{sign}Infinity"
        return f"{sign}.{word}"

    return re.sub(r"(?<![\w.])([-+]?)\.(Nan|NaN|NAN|nan|Inf|INF|inf)\b", repl, text)


def _is_xml(path: Path) -> bool:
    try:
        with open(path, "rb") as fh:
            head = fh.read(256)
    except OSError:
        return False
    return head.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<")


def _xml_value(el: Any, path: Path, depth: int = 0) -> Any:
    """The value of an element of an OpenCV FileStorage XML file: a dict of its children,
    a list for ``<_>`` items, numbers (a list for ``data`` or several) or text."""
    if depth > 20:
        raise InputError(f"{path}: calibration XML nested too deeply")
    kids = list(el)
    if kids:
        if all(k.tag == "_" for k in kids):
            return [_xml_value(k, path, depth + 1) for k in kids]
        return {k.tag: _xml_value(k, path, depth + 1) for k in kids}
    text = el.text or ""
    try:
        nums = [float(_SPECIAL.get(t.lower(), t)) for t in text.split()]
    except ValueError:
        return text.strip()
    return nums if el.tag == "data" or len(nums) != 1 else nums[0]


def _load_xml(path: Path) -> dict[str, Any]:
    """Parse an OpenCV FileStorage XML file (``<opencv_storage>``) into a dict.

    Read in Python, not with ``cv2.FileStorage``: OpenCV's parser can abort the process
    or loop forever on a malformed file.
    """
    import xml.etree.ElementTree as ET

    try:
        root = ET.fromstring(path.read_bytes())
    except (OSError, ValueError, ET.ParseError) as e:
        raise InputError(f"{path}: cannot parse calibration XML ({e.__class__.__name__})") from None
    if root.tag != "opencv_storage":
        raise InputError(f"{path}: expected an OpenCV <opencv_storage> XML file, got <{root.tag}>")
    return {child.tag: _xml_value(child, path) for child in root}


class _OpenCVYamlLoader(yaml.SafeLoader):
    """PyYAML loader that understands ``!!opencv-matrix`` tags."""


def _opencv_matrix(loader: yaml.SafeLoader, node: yaml.Node) -> dict[str, Any]:
    return loader.construct_mapping(node, deep=True)  # type: ignore[arg-type]


_OpenCVYamlLoader.add_constructor("tag:yaml.org,2002:opencv-matrix", _opencv_matrix)
_OpenCVYamlLoader.add_constructor("tag:yaml.org,2002:opencv-nd-matrix", _opencv_matrix)


def _load_plain(path: Path) -> dict[str, Any]:
    """Parse JSON or YAML (with the OpenCV ``%YAML:1.0`` header tolerated) into a dict."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(f"{path}: cannot read calibration file ({e.__class__.__name__})") from None
    try:
        if path.suffix.lower() == ".json" or text.lstrip().startswith("{"):
            data = json.loads(_opencv_specials(text, json_text=True))
        else:
            text = _opencv_specials(text, json_text=False)
            text = re.sub(r"^%YAML[: ]?[0-9.]*\s*$", "", text, count=1, flags=re.MULTILINE)
            data = yaml.load(text, Loader=_OpenCVYamlLoader)  # a SafeLoader subclass
    except (json.JSONDecodeError, yaml.YAMLError) as e:
        first = str(e).splitlines()[0] if str(e) else e.__class__.__name__
        raise InputError(f"{path}: cannot parse calibration file ({first})") from None
    if not isinstance(data, dict):
        raise InputError(f"{path}: calibration file must hold a mapping of keys, got {type(data)}")
    return data


def _as_array(path: Path, name: str, value: Any) -> NDArray[np.float64]:
    """An OpenCV-matrix dict, a ROS ``{rows, cols, data}`` dict, a list or an array -> ndarray."""
    if isinstance(value, Mapping):
        if "data" not in value:
            raise InputError(f"{path}: {name} must be a matrix with a 'data' list")
        try:
            data = np.asarray(value["data"], dtype=float).ravel()
        except (TypeError, ValueError):
            raise InputError(f"{path}: {name} data must be numbers") from None
        rows, cols = value.get("rows"), value.get("cols")
        if isinstance(rows, int | float) and isinstance(cols, int | float):
            if not all(math.isfinite(v) and v == int(v) and v >= 0 for v in (rows, cols)):
                raise InputError(f"{path}: {name} rows and cols must be whole numbers, got "
                                 f"{rows!r}, {cols!r}")
            if int(rows) * int(cols) != data.size:
                raise InputError(
                    f"{path}: {name} has {data.size} values, expected rows*cols = "
                    f"{int(rows)}*{int(cols)}"
                )
            return data.reshape(int(rows), int(cols))
        return data
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{path}: {name} must be numbers, got {value!r}") from None


def read_calibration_mapping(path: PathLike) -> tuple[Path, dict[str, Any]]:
    """The keys of one calibration file (OpenCV ``FileStorage`` YAML, XML or JSON, or a
    ROS ``camera_info`` YAML), parsed in Python; the file's checked path with them."""
    p = _require_file(path)
    return p, (_load_xml(p) if _is_xml(p) else _load_plain(p))


def calibration_matrix(path: Path, name: str, value: Any) -> NDArray[np.float64]:
    """A matrix of a calibration file as an array: an OpenCV matrix, a ROS
    ``{rows, cols, data}`` mapping or nested lists."""
    return _as_array(path, name, value)


_OPENCV_KEYS = (
    "K1", "M1", "D1", "K2", "M2", "D2", "R", "T",
    "image_size", "imageSize", "width", "height", "image_width", "image_height",
)  # fmt: skip


def _pick(path: Path, data: Mapping[str, Any], *names: str) -> Any:
    for n in names:
        if n in data and data[n] is not None:
            return data[n]
    raise InputError(f"{path}: missing key {' or '.join(names)}")


def read_opencv_calibration(
    path: PathLike,
    *,
    extrinsics_path: PathLike | None = None,
    image_size: tuple[int, int] | None = None,
    unit_to_mm: float = 1.0,
) -> StereoCalibration:
    """Read a stereo calibration written by ``cv2.FileStorage`` (YAML, XML or JSON).

    Parameters
    ----------
    path : str or Path
        File with ``K1 D1 K2 D2 R T`` (``M1``/``M2`` are accepted for ``K1``/``K2``, as
        OpenCV's ``stereo_calib`` sample writes) and the image size as ``image_size`` or
        ``imageSize`` (``[width, height]``) or ``width``/``height``
        (``image_width``/``image_height``).
    extrinsics_path : str or Path, optional
        A second file whose keys complete the first (``stereo_calib`` writes the
        intrinsics and the extrinsics ``R``, ``T`` to two files).
    image_size : tuple of int, optional
        ``(width, height)`` to use when the files do not store it.
    unit_to_mm : float
        Millimetres per unit of ``T`` in the file (the unit of the calibration target's
        square size): 1 for mm, 1000 for metres, 25.4 for inches.

    Returns
    -------
    StereoCalibration
        With ``T`` converted to millimetres.

    Raises
    ------
    InputError
        Missing, empty or unparsable file, missing key or invalid value (one line naming
        the file and the field).

    Notes
    -----
    1. Parse each file in Python -- XML with :mod:`xml.etree.ElementTree`, JSON with
       :mod:`json`, YAML with PyYAML (``!!opencv-matrix`` and ``!!opencv-nd-matrix``
       understood; ``{rows, cols, data}`` or plain nested lists accepted) -- not with
       ``cv2.FileStorage``, which can abort the process or hang on a malformed file.
    2. Merge the keys (the first file wins), pick the aliases, scale ``T``.
    3. Validate (see :class:`StereoCalibration`).
    """
    if not (isinstance(unit_to_mm, int | float) and math.isfinite(unit_to_mm) and unit_to_mm > 0):
        raise InputError(f"unit_to_mm must be a finite number > 0, got {unit_to_mm}")
    files = [_require_file(path)]
    if extrinsics_path is not None:
        files.append(_require_file(extrinsics_path))
    data: dict[str, Any] = {}
    for f in reversed(files):
        data.update(_load_xml(f) if _is_xml(f) else _load_plain(f))
    src = " + ".join(str(f) for f in files)
    p0 = files[0] if len(files) == 1 else Path(src)
    K1 = _as_array(p0, "K1", _pick(p0, data, "K1", "M1"))
    K2 = _as_array(p0, "K2", _pick(p0, data, "K2", "M2"))
    D1 = _as_array(p0, "D1", _pick(p0, data, "D1"))
    D2 = _as_array(p0, "D2", _pick(p0, data, "D2"))
    R = _as_array(p0, "R", _pick(p0, data, "R"))
    T = _as_array(p0, "T", _pick(p0, data, "T"))
    if image_size is not None:
        size: Any = image_size
    elif "image_size" in data or "imageSize" in data:
        size = _as_array(p0, "image_size", _pick(p0, data, "image_size", "imageSize"))
    elif {"width", "image_width"} & data.keys() and {"height", "image_height"} & data.keys():
        size = [_pick(p0, data, "width", "image_width"), _pick(p0, data, "height", "image_height")]
    else:
        raise InputError(
            f"{src}: missing key image_size (or imageSize, or width and height); "
            "pass image_size=(w, h)"
        )
    try:
        T_mm = np.asarray(T, dtype=float) * float(unit_to_mm)
    except (TypeError, ValueError):
        raise InputError(f"{src}: T must be numbers, got {T!r}") from None
    return StereoCalibration(K1, D1, K2, D2, R, T_mm, size, source=src)


def write_opencv_calibration(
    calibration: StereoCalibration, path: PathLike, *, unit_to_mm: float = 1.0
) -> Path:
    """Write a calibration with ``cv2.FileStorage`` (format from the suffix: .yml/.yaml/.xml/.json).

    Keys: ``K1 D1 K2 D2 R T`` (``T`` divided by `unit_to_mm`) and ``image_size``
    ``[width, height]``; readable by :func:`read_opencv_calibration`.
    """
    p = Path(path)
    fs = cv2.FileStorage(str(p), cv2.FILE_STORAGE_WRITE)
    try:
        for key in ("K1", "D1", "K2", "D2", "R"):
            fs.write(key, np.asarray(getattr(calibration, key), dtype=float).copy())
        fs.write("T", (calibration.T / float(unit_to_mm)).reshape(3, 1).copy())
        fs.startWriteStruct("image_size", cv2.FileNode_SEQ)
        for v in calibration.image_size:
            fs.write("", int(v))
        fs.endWriteStruct()
    finally:
        fs.release()
    return p


def read_ros_calibration(
    left_path: PathLike, right_path: PathLike, *, unit_to_mm: float = 1000.0
) -> StereoCalibration:
    """Read a ROS ``camera_info`` YAML pair (``left.yaml``, ``right.yaml``).

    Parameters
    ----------
    left_path, right_path : str or Path
        Files with ``image_width``, ``image_height``, ``camera_matrix``,
        ``distortion_model`` (``plumb_bob`` or ``rational_polynomial``),
        ``distortion_coefficients``, ``rectification_matrix`` and ``projection_matrix``,
        as ``camera_calibration`` writes them.
    unit_to_mm : float
        Millimetres per unit of the projection matrices' translation column; ROS uses
        metres (REP 103), hence 1000.

    Returns
    -------
    StereoCalibration
        ``T`` in millimetres.

    Notes
    -----
    ROS stores the rectification of each camera, not the relative pose.  With
    ``R_i`` = ``rectification_matrix`` (original camera frame -> rectified frame,
    ``x_rect_i = R_i x_i``, OpenCV's ``R1``/``R2``) and ``P_i = [K'_i | p_i]`` the
    projection matrices, the two rectified frames are parallel and the rectified right
    frame is the rectified left frame shifted by ``t = K'_2^-1 p_2 - K'_1^-1 p_1``
    (for a horizontal rig ``t = (Tx, 0, 0)`` with ``P_2[0, 3] = Tx fx' = -fx' B``):
    ``x_rect_2 = x_rect_1 + t``.  Hence

    1. ``x_2 = R_2^T x_rect_2 = R_2^T R_1 x_1 + R_2^T t``, so
    2. ``R = R_2^T R_1`` and ``T = R_2^T t * unit_to_mm``, ``|T| = B``.
    """
    lp, rp = _require_file(left_path), _require_file(right_path)
    if not (isinstance(unit_to_mm, int | float) and math.isfinite(unit_to_mm) and unit_to_mm > 0):
        raise InputError(f"unit_to_mm must be a finite number > 0, got {unit_to_mm}")
    parts = []
    for p in (lp, rp):
        d = _load_plain(p)
        model = str(d.get("distortion_model", "plumb_bob")).strip().lower()
        if model not in ("plumb_bob", "rational_polynomial", ""):
            raise InputError(
                f"{p}: distortion_model must be plumb_bob or rational_polynomial, got {model!r}"
            )
        K = _as_array(p, "camera_matrix", _pick(p, d, "camera_matrix"))
        K = check_camera_matrix(str(p), "camera_matrix", K)
        D_raw = d.get("distortion_coefficients")
        D = None if D_raw is None else _as_array(p, "distortion_coefficients", D_raw)
        D = check_distortion(str(p), "distortion_coefficients", D)
        Rr = check_rotation(
            str(p), "rectification_matrix",
            _as_array(p, "rectification_matrix", _pick(p, d, "rectification_matrix")),
        )  # fmt: skip
        P = _as_array(p, "projection_matrix", _pick(p, d, "projection_matrix"))
        if P.size != 12 or not np.all(np.isfinite(P)):
            raise InputError(f"{p}: projection_matrix must be a finite 3x4 matrix")
        P = P.reshape(3, 4)
        check_camera_matrix(str(p), "projection_matrix[:, :3]", P[:, :3])
        size = check_size(
            str(p), "image_width/image_height",
            [_pick(p, d, "image_width"), _pick(p, d, "image_height")],
        )  # fmt: skip
        parts.append((K, D, Rr, P, size))
    (K1, D1, R1, P1, s1), (K2, D2, R2, P2, s2) = parts
    if s1 != s2:
        raise InputError(f"{rp}: image size {s2} differs from the left camera's {s1} ({lp})")
    t = np.linalg.solve(P2[:, :3], P2[:, 3]) - np.linalg.solve(P1[:, :3], P1[:, 3])
    if not np.any(t != 0):
        raise InputError(f"{rp}: projection_matrix has no baseline (P[0, 3] = P[1, 3] = 0)")
    R = R2.T @ R1
    T = R2.T @ t * float(unit_to_mm)
    return StereoCalibration(K1, D1, K2, D2, R, T, s1, source=f"{lp} + {rp}")


@dataclass(frozen=True, eq=False)
class MiddleburyCalib:
    """Contents of a Middlebury 2014/2021 ``calib.txt`` (an already rectified pair).

    Attributes
    ----------
    cam0, cam1 : ndarray, shape (3, 3)
        Intrinsics of the left (``im0``) and right (``im1``) images.
    doffs : float
        ``cx1 - cx0``, pixels; depth ``Z = baseline * f / (d + doffs)``.
    baseline_mm : float
        Camera baseline, millimetres.
    width, height : int
        Image size, pixels.
    ndisp : int or None
        Conservative bound on the number of disparity levels.
    vmin, vmax : float or None
        Tight bounds on the valid disparities (pixels).
    calibration : StereoCalibration
        ``K1 = cam0``, ``K2 = cam1``, no distortion, ``R = I``, ``T = (-baseline, 0, 0)``.
    """

    cam0: NDArray[np.float64]
    cam1: NDArray[np.float64]
    doffs: float
    baseline_mm: float
    width: int
    height: int
    ndisp: int | None
    vmin: float | None
    vmax: float | None
    calibration: StereoCalibration


_MB_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def read_middlebury_calib(path: PathLike) -> MiddleburyCalib:
    """Read a Middlebury 2014/2021 ``calib.txt``.

    The file has ``key=value`` lines: ``cam0=[f 0 cx0; 0 f cy; 0 0 1]``, ``cam1=[...]``,
    ``doffs``, ``baseline`` (mm), ``width``, ``height``, ``ndisp`` and optionally
    ``isint``, ``vmin``, ``vmax``, ``dyavg``, ``dymax``.

    Raises
    ------
    InputError
        Missing or unreadable file, missing key, bad number, or ``doffs`` differing from
        ``cx1 - cx0`` by more than 0.01 px.

    Examples
    --------
    >>> import tempfile, os
    >>> text = ("cam0=[1000 0 300; 0 1000 200; 0 0 1]\\ncam1=[1000 0 320; 0 1000 200; 0 0 1]\\n"
    ...         "doffs=20\\nbaseline=150.5\\nwidth=640\\nheight=400\\nndisp=100\\n")
    >>> d = tempfile.mkdtemp(); p = os.path.join(d, "calib.txt")
    >>> _ = open(p, "w").write(text)
    >>> mb = read_middlebury_calib(p)
    >>> mb.doffs, mb.baseline_mm, mb.calibration.T.tolist(), mb.ndisp
    (20.0, 150.5, [-150.5, 0.0, 0.0], 100)
    """
    p = _require_file(path)
    try:
        text = p.read_text(encoding="utf-8", errors="strict")
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(f"{p}: cannot read calib.txt ({e.__class__.__name__})") from None
    kv: dict[str, str] = {}
    for line in text.splitlines():
        if "=" in line:
            k, v = line.split("=", 1)
            kv[k.strip()] = v.strip()

    def number(key: str, required: bool = True) -> float | None:
        if key not in kv:
            if required:
                raise InputError(f"{p}: missing key {key}")
            return None
        if not re.fullmatch(_MB_NUMBER, kv[key]):
            raise InputError(f"{p}: {key} must be a number, got {kv[key]!r}")
        v = float(kv[key])
        if not math.isfinite(v):
            raise InputError(f"{p}: {key} must be finite, got {kv[key]!r}")
        return v

    def matrix(key: str) -> NDArray[np.float64]:
        if key not in kv:
            raise InputError(f"{p}: missing key {key}")
        body = kv[key].strip().lstrip("[").rstrip("]")
        toks = body.replace(";", " ").replace(",", " ").split()
        if len(toks) != 9 or not all(re.fullmatch(_MB_NUMBER, t) for t in toks):
            raise InputError(f"{p}: {key} must be [f 0 cx; 0 f cy; 0 0 1], got {kv[key]!r}")
        return check_camera_matrix(str(p), key, np.array([float(t) for t in toks]).reshape(3, 3))

    cam0, cam1 = matrix("cam0"), matrix("cam1")
    doffs = number("doffs")
    baseline = number("baseline")
    width, height = number("width"), number("height")
    ndisp = number("ndisp", required=False)
    vmin, vmax = number("vmin", required=False), number("vmax", required=False)
    assert doffs is not None and baseline is not None
    if baseline <= 0:
        raise InputError(f"{p}: baseline must be > 0 (millimetres), got {baseline}")
    size = check_size(str(p), "width/height", [width, height])
    if abs((cam1[0, 2] - cam0[0, 2]) - doffs) > 0.01:
        raise InputError(
            f"{p}: doffs must equal cx1 - cx0 = {cam1[0, 2] - cam0[0, 2]:g}, got {doffs:g}"
        )
    calib = StereoCalibration(
        cam0, None, cam1, None, np.eye(3), [-baseline, 0.0, 0.0], size, source=str(p)
    )
    return MiddleburyCalib(
        frozen_array(cam0), frozen_array(cam1), float(doffs), float(baseline), size[0], size[1],
        None if ndisp is None else int(ndisp), vmin, vmax, calib,
    )  # fmt: skip


def read_calibration(
    path: PathLike,
    right_path: PathLike | None = None,
    *,
    unit_to_mm: float | None = None,
    image_size: tuple[int, int] | None = None,
) -> StereoCalibration:
    """Read any supported calibration file, choosing the reader from its contents.

    * ``calib.txt`` / ``*.txt`` with ``cam0=`` -> :func:`read_middlebury_calib`;
    * two paths, or a YAML with ``camera_matrix`` -> :func:`read_ros_calibration`
      (`unit_to_mm` default 1000);
    * otherwise -> :func:`read_opencv_calibration` (`unit_to_mm` default 1); a second path
      is then taken as the extrinsics file when the first has no ``camera_matrix``.
    """
    p = _require_file(path)
    head = p.read_bytes()[:4096]
    if b"cam0=" in head.replace(b" ", b""):
        return read_middlebury_calib(p).calibration
    if b"camera_matrix" in head:
        if right_path is None:
            raise InputError(f"{p}: a ROS camera_info file needs the right camera's file too")
        return read_ros_calibration(p, right_path, unit_to_mm=unit_to_mm or 1000.0)
    return read_opencv_calibration(
        p, extrinsics_path=right_path, image_size=image_size, unit_to_mm=unit_to_mm or 1.0
    )
