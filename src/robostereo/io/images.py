"""Reading and writing image files: grey and colour images, PFM disparity maps.

:func:`load_image` reads PPM/PGM/PNG/TIFF (8 or 16 bit, grey, RGB or RGBA) with its
bit depth; :func:`read_pfm` and :func:`write_pfm` read and write the float PFM maps of
Middlebury 2014/2021.
"""

from __future__ import annotations

import contextlib
import os
import re
import sys
import tempfile
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import cv2
import imageio.v3 as iio
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_file

__all__ = [
    "load_image",
    "read_pfm",
    "write_pfm",
]

PathLike = str | os.PathLike[str]


def _pnm_maxval(data: bytes) -> int | None:
    """``maxval`` from a binary/ASCII PNM header (P2, P3, P5, P6), or None."""
    sep = rb"(?:\s+|#[^\n]*\n)+"
    m = re.match(rb"P[2356]" + sep + rb"(\d+)" + sep + rb"(\d+)" + sep + rb"(\d+)", data)
    return int(m.group(3)) if m else None


@contextlib.contextmanager
def _native_stderr_captured() -> Iterator[list[str]]:
    """File descriptor 2 taken into a temporary file while the block runs; yields the
    list that receives its lines.  libpng writes its complaints there from C (``libpng
    error: PNG input buffer is incomplete``), past OpenCV's log level and Python."""
    lines: list[str] = []
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):  # no fd 2 (embedded): nothing to capture
        yield lines
        return
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            yield lines
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            lines.extend(tmp.read().decode("utf-8", "replace").splitlines())


def _cv2_decode(raw: bytes) -> NDArray[Any] | None:
    """``cv2.imdecode`` with OpenCV's and libpng's lines silenced; None where it cannot
    decode or libpng reported an error (a truncated PNG decodes with a complaint)."""
    import cv2.utils.logging as cv_log

    level = cv_log.getLogLevel()
    cv_log.setLogLevel(cv_log.LOG_LEVEL_SILENT)
    try:
        with _native_stderr_captured() as lines:
            img = cv2.imdecode(np.frombuffer(raw, dtype=np.uint8), cv2.IMREAD_UNCHANGED)
    except cv2.error:
        return None
    finally:
        cv_log.setLogLevel(level)
    others = [ln for ln in lines if not ln.startswith("libpng")]
    if others:  # not ours to swallow: another thread's, or a library's other notice
        print("\n".join(others), file=sys.stderr)
    if any(ln.startswith("libpng error") for ln in lines):
        return None
    return img


def load_image(path: PathLike) -> tuple[NDArray[Any], int]:
    """Read an image file (PPM/PGM/PNG/TIFF, 8 or 16 bit, grey, RGB or RGBA).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    image : ndarray, shape (H, W) or (H, W, C)
        In the file's dtype (``uint8``, ``uint16``, ...); colour channels in RGB(A) order.
    bit_depth : int
        Significant bits per sample: from ``maxval`` for PNM files (e.g. 10 for
        ``maxval = 1023``), otherwise the dtype's size (8, 16, 32).

    Raises
    ------
    InputError
        Missing, empty or undecodable file (one line naming the file); a float image
        with NaN or grey levels outside 0..1.

    Notes
    -----
    Decoded with OpenCV (``cv2.imdecode``, ``IMREAD_UNCHANGED``, BGR -> RGB), falling
    back to imageio for formats OpenCV does not read; OpenCV's own log lines are
    silenced, the error is ours.  A float image (e.g. a float32 TIFF) is read as
    full scale 1.0 -- grey levels 0..1, the convention of image libraries -- and
    returned as ``uint16`` (``round(v * 65535)``, bit depth 16), so it matches like
    a 16-bit file; floats outside 0..1 are refused (convert them to integers first).
    """
    p = require_file(path, "image file")
    try:
        raw = p.read_bytes()
    except OSError as e:
        raise InputError(f"{p}: cannot read image file ({e.__class__.__name__})") from None
    img = _cv2_decode(raw)
    if img is not None and img.ndim == 3:
        code = {3: cv2.COLOR_BGR2RGB, 4: cv2.COLOR_BGRA2RGBA}.get(img.shape[2])
        img = cv2.cvtColor(img, code) if code is not None else img
    if img is None:
        try:
            with warnings.catch_warnings():  # imageio's notices: the error is ours
                warnings.simplefilter("ignore")
                img = np.asarray(iio.imread(p))
        except Exception as e:  # imageio raises many types for bad files
            raise InputError(
                f"{p}: cannot decode image (expected PPM/PGM/PNG/TIFF; {e.__class__.__name__})"
            ) from None
    if img.ndim == 3 and img.shape[2] == 1:
        img = img[:, :, 0]
    if img.ndim not in (2, 3) or img.size == 0:
        raise InputError(f"{p}: image must be (H, W) or (H, W, C) and non-empty, got {img.shape}")
    if img.dtype.kind not in "uif":
        raise InputError(f"{p}: image samples must be integers or floats, got {img.dtype}")
    if img.dtype.kind == "f":
        if not np.isfinite(img).all():
            raise InputError(f"{p}: float image contains NaN or infinite grey levels")
        lo, hi = float(img.min()), float(img.max())
        if lo < 0.0 or hi > 1.0:
            raise InputError(
                f"{p}: float image has grey levels {lo:g} .. {hi:g}; float images are read "
                "as full scale 1.0 (0..1): scale it to 0..1 or save it as 8/16-bit integers"
            )
        return np.rint(img * 65535.0).astype(np.uint16), 16
    maxval = _pnm_maxval(raw[:64])
    if maxval is not None and maxval > 0:
        depth = int(maxval).bit_length()
    else:
        depth = img.dtype.itemsize * 8
    return img, depth


def read_pfm(path: PathLike) -> NDArray[np.float32]:
    """Read a PFM file (Middlebury 2014/2021 disparity maps).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    ndarray, shape (H, W) (``Pf``) or (H, W, 3) (``PF``), float32
        Rows top to bottom (PFM stores them bottom to top); ``inf`` is kept (Middlebury
        uses it for unknown disparity).  The magnitude of the header's scale is ignored;
        its sign gives the byte order (negative = little-endian).

    Raises
    ------
    InputError
        Missing file, bad header or truncated data (one line naming the file).

    Examples
    --------
    >>> import tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "d.pfm")
    >>> a = np.array([[1.5, np.inf], [3.0, 4.0]], dtype=np.float32)
    >>> _ = write_pfm(p, a)
    >>> read_pfm(p).tolist()
    [[1.5, inf], [3.0, 4.0]]
    """
    p = require_file(path, "PFM file")
    try:
        data = p.read_bytes()
    except OSError as e:
        raise InputError(f"{p}: cannot read PFM file ({e.__class__.__name__})") from None
    m = re.match(rb"(P[Ff])\s+(\d+)\s+(\d+)\s+([-+]?[0-9.]+(?:[eE][-+]?\d+)?)\s", data)
    if m is None:
        raise InputError(f"{p}: not a PFM file (expected 'PF' or 'Pf', width, height, scale)")
    channels = 3 if m.group(1) == b"PF" else 1
    w, h, scale = int(m.group(2)), int(m.group(3)), float(m.group(4))
    if w <= 0 or h <= 0 or scale == 0:
        raise InputError(f"{p}: PFM header needs width, height > 0 and scale != 0: {w} {h} {scale}")
    n = w * h * channels * 4
    body = data[m.end() :]
    if len(body) < n:
        raise InputError(f"{p}: PFM data truncated: {len(body)} bytes, expected {n}")
    if len(body) > n and body[:1] == b"\n" and m.group(0).endswith(b"\r"):
        body = body[1:]  # a CRLF after the scale
    dtype = np.dtype("<f4" if scale < 0 else ">f4")
    arr = np.frombuffer(body[:n], dtype=dtype).astype(np.float32)
    shape = (h, w) if channels == 1 else (h, w, 3)
    return np.ascontiguousarray(arr.reshape(shape)[::-1])


def write_pfm(path: PathLike, array: ArrayLike, *, little_endian: bool = True) -> Path:
    """Write a float image as PFM (``Pf`` for (H, W), ``PF`` for (H, W, 3)), scale magnitude 1.

    Rows are written bottom to top, as the format requires.
    """
    a = np.asarray(array, dtype=np.float32)
    if a.ndim == 2:
        magic = b"Pf"
    elif a.ndim == 3 and a.shape[2] == 3:
        magic = b"PF"
    else:
        raise InputError(f"array must have shape (H, W) or (H, W, 3), got {a.shape}")
    h, w = a.shape[:2]
    dtype = "<f4" if little_endian else ">f4"
    header = magic + f"\n{w} {h}\n{-1.0 if little_endian else 1.0}\n".encode()
    p = Path(path)
    p.write_bytes(header + np.ascontiguousarray(a[::-1]).astype(dtype).tobytes())
    return p
