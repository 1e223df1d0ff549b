"""The baseline direction: where to move the camera so that the edges can be matched.

:func:`best_baseline_direction` picks, from an image of the scene, the direction to
move the camera so that most edges cross the epipolar lines (an edge parallel to the
baseline lies along an epipolar line and cannot be matched: the thesis's block lost
its short edges that way).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError

__all__ = [
    "BaselineDirection",
    "best_baseline_direction",
]


@dataclass(frozen=True)
class BaselineDirection:
    """The baseline direction chosen from an image (:func:`best_baseline_direction`).

    Attributes
    ----------
    direction_deg : float
        Direction in the image, degrees from the image's x axis towards its y axis
        (down), in ``[0, 180)``: move the camera along ``cos * x_c + sin * y_c``.
    matchable_fraction : float
        Share of the edge strength whose edges cross the epipolar lines at
        `min_crossing_deg` or more along that direction.
    matchable_fraction_x : float
        The same for the image's x axis (the usual horizontal baseline).
    scores : ndarray, shape (180,)
        The fraction for every whole degree.
    """

    direction_deg: float
    matchable_fraction: float
    matchable_fraction_x: float
    scores: NDArray[np.float64]


def best_baseline_direction(
    image: ArrayLike, *, min_crossing_deg: float = 30.0, threshold: float = 8.0
) -> BaselineDirection:
    """The baseline direction that makes most of an image's edges cross epipolar lines.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Grey image of the scene, on the 0..127 scale of the thesis (scale 8-bit images
        by 0.5) or any scale with `threshold` to match.
    min_crossing_deg : float
        An edge counts as matchable when it crosses the epipolar lines (the baseline
        direction) at this angle or more; below it the matcher sees it as a smear along
        the line.
    threshold : float
        Least gradient magnitude of an edge pixel (grey levels per pixel).

    Returns
    -------
    BaselineDirection

    Notes
    -----
    Sobel gradients of the image smoothed by a 5 x 5 Gaussian; an edge pixel with
    gradient angle ``g`` crosses a baseline at angle ``t`` at ``90 - |g - t|`` degrees
    (mod 180).  The edge strengths are histogrammed by ``g mod 180`` in 1-degree bins
    and the histogram is summed circularly over ``|g - t| <= 90 - min_crossing_deg``
    for every ``t``.
    """
    try:
        raw = np.asarray(image)
        if raw.dtype.kind not in "biuf":
            raise TypeError
        img = raw.astype(np.float64)
    except (TypeError, ValueError):
        raise InputError(f"image must be a grey (H, W) array of numbers, got "
                         f"{type(image).__name__}") from None
    if img.ndim != 2 or min(img.shape) < 5:
        raise InputError(f"image must be a grey (H, W) image of at least 5 x 5 pixels, got "
                         f"shape {img.shape}")
    if not np.isfinite(img).all():
        raise InputError("image has NaN or infinite grey levels")
    if np.abs(img).max() > 1e30:
        raise InputError(f"image grey levels must be within +-1e30, got {np.abs(img).max():g}")
    img = img.astype(np.float32)
    for name, v in (("min_crossing_deg", min_crossing_deg), ("threshold", threshold)):
        if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
            raise InputError(f"{name} must be a finite number, got {v!r}")
    if not 0 < min_crossing_deg < 90:
        raise InputError(f"min_crossing_deg must be in (0, 90), got {min_crossing_deg}")
    if not threshold > 0:
        raise InputError(f"threshold must be > 0, got {threshold}")
    s = cv2.GaussianBlur(img, (5, 5), 1.0)
    gx = cv2.Sobel(s, cv2.CV_32F, 1, 0, ksize=3) / 8.0
    gy = cv2.Sobel(s, cv2.CV_32F, 0, 1, ksize=3) / 8.0
    mag = np.hypot(gx, gy)
    edge = mag >= threshold
    if not edge.any():
        raise InputError(f"no edges of gradient >= {threshold} in the image")
    ang = np.degrees(np.arctan2(gy[edge], gx[edge])) % 180.0
    hist = np.bincount(np.minimum(ang.astype(int), 179), weights=mag[edge], minlength=180)
    half = round(90 - min_crossing_deg)
    window = np.zeros(180)
    window[: half + 1] = 1.0
    window[180 - half:] = 1.0
    # circular correlation: scores[t] = sum_g hist[g] * window[(g - t) mod 180]
    scores = np.real(np.fft.ifft(np.fft.fft(hist) * np.conj(np.fft.fft(window))))
    scores = np.clip(scores, 0.0, None) / hist.sum()
    best = int(np.argmax(scores))
    return BaselineDirection(direction_deg=float(best), matchable_fraction=float(scores[best]),
                             matchable_fraction_x=float(scores[0]), scores=scores)
