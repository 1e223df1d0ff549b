"""Frames that cannot be right: a view much less sharp than the others, named and left out.

A robot grabs its views one by one, and one of them can fail: a black frame, one grabbed
out of focus or in the dark, an image of another bit depth.  Such a view does not make
wrong matches by itself, but it vetoes right ones: with the plane sweep one black frame
of three left no point at all.  :func:`frame_sharpness` measures each view's strongest
edges against the other views'; :func:`failed_frames` names the views far below them;
:func:`~robostereo.robot.views.locating.locate_views` warns about each and locates the
others (``ViewsParameters.min_frame_sharpness``).

The measure is a high percentile (:data:`SHARPNESS_PERCENTILE`) of the gradient
magnitude (a 1-pixel Gaussian, then Sobel, on the thesis's grey scale of the capture's
bit depth), over the median of the views'.  Views of one scene from nearby viewpoints
see the same edges at the same contrast; a blur of sigma ``s`` divides a step's peak
gradient by about ``sqrt(1 + s**2 / b**2)`` (``b`` the optics' own blur), a darker
exposure by the exposure's ratio.

References
----------
Kim (1989), the thesis, 3.1 (edge points: the gradient along the epipolar lines).
"""

from __future__ import annotations

import math

import cv2
import numpy as np
from numpy.typing import NDArray

from robostereo.errors import warn_input
from robostereo.geometry.poses import as_se3
from robostereo.matcher.grey_levels import to_grey
from robostereo.robot.views.viewpoints import ViewsCapture

__all__ = [
    "DUPLICATE_TURN_DEG",
    "SHARPNESS_PERCENTILE",
    "duplicate_views",
    "failed_frames",
    "frame_sharpness",
    "grey_gradient",
    "usable_views",
]

SHARPNESS_PERCENTILE = 99.8
"""The percentile of a view's gradient magnitude that stands for its strongest edges.

Edges cover a few per cent of a view, and fewer where part of the scene leaves the
image: the simulated six-axis arm's cross of 5, the block raised 79.65 mm, sees the
block's top partly outside one view, whose 99.5th percentile then fell off its edges
onto the ground (0.43 of the median view's: left out as blurred, a right view).  Of
99.5, 99.8, 99.9 and 99.95 on twenty captures (below), 99.8 kept every sharp view
highest (0.90 and up; 0.43, 0.80 and 0.76 with the others) and put every view blurred
by sigma 4 px lowest (0.50 at most; 0.65, 0.52, 0.47)."""

DUPLICATE_TURN_DEG = 0.1
"""Two views whose optical centres lie within the capture's baseline uncertainty and whose
orientations differ by at most this (degrees) are one view grabbed twice."""


def grey_gradient(capture: ViewsCapture, k: int) -> tuple[NDArray[np.float32],
                                                           NDArray[np.float32]]:
    """View `k`'s gradient ``(gx, gy)``, each (H, W), grey levels per pixel on the thesis's
    scale of the capture's bit depth, after a Gaussian of one pixel."""
    g = to_grey(np.asarray(capture.images[k], dtype=np.float64), bit_depth=capture.bit_depth)
    g = cv2.GaussianBlur(np.asarray(g, dtype=np.float32), (0, 0), 1.0)
    # Sobel's 3 x 3 kernel is 8 times the gradient per pixel
    return (cv2.Sobel(g, cv2.CV_32F, 1, 0, ksize=3) / 8.0,
            cv2.Sobel(g, cv2.CV_32F, 0, 1, ksize=3) / 8.0)


def frame_sharpness(capture: ViewsCapture) -> NDArray[np.float64]:
    """Each view's strongest edges over the median view's, shape (N,).

    Parameters
    ----------
    capture : ViewsCapture

    Returns
    -------
    ndarray, shape (N,)
        The :data:`SHARPNESS_PERCENTILE` of each view's gradient magnitude over the
        median of the views' (1 for a view like the others; 0 for a blank frame).

    Notes
    -----
    On twenty captures (the simulated SCARA and six-axis arm, block at two heights and
    hub-pulley, lines and crosses of 5; issue 34's renders, crosses of 5 of six
    families at 400-1000 mm; three and eight real DTU views) every view lay at
    0.90-1.21.  The middle view blurred by a Gaussian of sigma 4 px fell to 0.31-0.50,
    of sigma 2 px to 0.53-0.81; darkened to a fifth, 0.19-0.25; black, 0.

    Examples
    --------
    >>> from robostereo.geometry.camera import SEED_CAMERA
    >>> from robostereo.geometry.poses import se3_from_scara
    >>> w, h = SEED_CAMERA.image_size
    >>> rng = np.random.default_rng(0)
    >>> img = (rng.random((h, w)) * 127).astype(np.uint8)
    >>> images = (img, img, np.zeros_like(img))
    >>> poses = tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20.0, 0.0, 20.0))
    >>> cap = ViewsCapture(images, SEED_CAMERA, poses, depth_range_mm=(900, 1100))
    >>> frame_sharpness(cap).round(2).tolist()
    [1.0, 1.0, 0.0]
    """
    peaks = np.empty(len(capture))
    for k in range(len(capture)):
        gx, gy = grey_gradient(capture, k)
        peaks[k] = float(np.percentile(np.hypot(gx, gy), SHARPNESS_PERCENTILE))
    mid = float(np.median(peaks))
    return peaks / mid if mid > 0 else np.zeros(len(capture))


def failed_frames(capture: ViewsCapture, min_sharpness: float) -> list[tuple[int, float]]:
    """The views whose :func:`frame_sharpness` is below `min_sharpness`, with it.

    Parameters
    ----------
    capture : ViewsCapture
    min_sharpness : float
        In (0, 1).

    Returns
    -------
    list of (int, float)
        ``(view, sharpness)`` of each such view, in view order.
    """
    s = frame_sharpness(capture)
    return [(int(k), float(s[k])) for k in np.nonzero(s < min_sharpness)[0]]


def duplicate_views(capture: ViewsCapture) -> list[tuple[int, int, float]]:
    """Views grabbed at the pose of an earlier view: ``(view, earlier, distance_mm)``.

    Two views at one pose see the scene along the same rays: they measure no depth
    between them, and every point they both reach is reported twice.  A view counts as
    a repeat when its optical centre lies within ``capture.baseline_uncertainty_mm`` of
    an earlier view's and its orientation within :data:`DUPLICATE_TURN_DEG` of it.

    Parameters
    ----------
    capture : ViewsCapture

    Returns
    -------
    list of (int, int, float)
        Each repeated view, the first view at its pose, and their centres' distance (mm).

    Examples
    --------
    >>> from robostereo.geometry.camera import SEED_CAMERA
    >>> from robostereo.geometry.poses import se3_from_scara
    >>> w, h = SEED_CAMERA.image_size
    >>> images = tuple(np.zeros((h, w), np.uint8) for _ in range(3))
    >>> poses = tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20.0, 20.0, -20.0))
    >>> duplicate_views(ViewsCapture(images, SEED_CAMERA, poses, depth_range_mm=(900, 1100)))
    [(2, 0, 0.0)]
    """
    c = capture.centres
    poses = [as_se3(p) for p in capture.poses]
    turn = math.radians(DUPLICATE_TURN_DEG)
    out: list[tuple[int, int, float]] = []
    for k in range(1, len(capture)):
        d = np.linalg.norm(c[:k] - c[k], axis=1)
        for j in np.nonzero(d <= capture.baseline_uncertainty_mm)[0]:
            if (poses[int(j)].inv() @ poses[k]).angle <= turn:
                out.append((k, int(j), float(d[j])))
                break
    return out


def usable_views(capture: ViewsCapture, min_sharpness: float | None,
                 source: str = "capture") -> list[int]:
    """The views to locate from: each view grabbed twice (:func:`duplicate_views`) and
    each failed frame (:func:`failed_frames`, when `min_sharpness` is given) named in a
    warning and left out, while two or more views remain.

    Parameters
    ----------
    capture : ViewsCapture
    min_sharpness : float or None
        ``ViewsParameters.min_frame_sharpness``.
    source : str
        The capture's name in the warnings.

    Returns
    -------
    list of int
        The views kept, in order.
    """
    n = len(capture)
    repeats = duplicate_views(capture)
    for k, j, d in repeats:
        warn_input(f"{source}: view {capture.view_name(k)} stands at the pose of view "
                   f"{capture.view_name(j)} ({d:.3g} mm apart, turned under "
                   f"{DUPLICATE_TURN_DEG:g} degrees): the same view twice; left out")
    keep = [k for k in range(n) if k not in {r[0] for r in repeats}]
    if min_sharpness is None:
        return keep
    failed = [(keep[i], s) for i, s in failed_frames(capture.subset(keep), min_sharpness)]
    rest = [k for k in keep if k not in dict(failed)]
    for k, s in failed:
        what = "left out" if len(rest) >= 2 else "kept: fewer than two views would remain"
        warn_input(f"{source}: view {capture.view_name(k)} looks blurred, dark or blank: its "
                   f"strongest edges are {s:.2f} of the median view's (under "
                   f"{min_sharpness:g}); {what}")
    return rest if len(rest) >= 2 else keep
