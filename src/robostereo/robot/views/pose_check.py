"""Do the views' poses agree with their images?  Places tracked off the epipolar lines.

The N-view search (:func:`~robostereo.robot.views.locating.locate_views`) looks for each edge
point along the epipolar lines that the poses give (thesis 2.2: the poses make the
geometry).  Poses that are slightly wrong -- a hand-eye turned by a degree about the
optical axis, flange poses of another capture -- turn those lines, and the search
still finds edge points on them, at the wrong places: on the simulated six-axis pulley
a hand-eye 1 degree off moved the located points' median height by 6 mm, with the fits'
residuals (measured along the lines) hardly changed and nothing said.

What the poses cannot fake is where the views see the same texture.  Well-structured
places of one view (Shi-Tomasi corners [1]_) are tracked into another by pyramidal
Lucas-Kanade [2]_, free in both directions; their distance from the epipolar line
that the two poses predict, perpendicular to the line, is a fraction of a pixel where
the poses are right and grows with the disparity where they are not.  The part of it
that every place of a pair shares (:func:`pose_offset_px`) is a pose error of the size
the search meets along the lines, and the N-view bounds carry it.

References
----------
.. [1] J. Shi and C. Tomasi, "Good features to track", CVPR 1994.
.. [2] J.-Y. Bouguet, "Pyramidal implementation of the Lucas Kanade feature tracker",
   Intel, 2000 (``cv2.calcOpticalFlowPyrLK``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from robostereo.errors import (
    require_finite,
    require_int,
    require_nonnegative,
    warn_input,
)
from robostereo.robot.views.prepared_views import PreparedViews

__all__ = [
    "EPIPOLAR_TOLERANCE_DEG",
    "EPIPOLAR_TOLERANCE_PX",
    "MIN_PLACES",
    "EpipolarCheck",
    "corners_to_track",
    "epipolar_check",
    "fundamental_from_poses",
    "lone_check",
    "lone_of_three",
    "pose_offset_px",
    "views_epipolar_checks",
    "warn_disagreeing",
]

#: places whose median distance from their epipolar lines exceeds this (pixels) are
#: reported, if the angle does too: on the simulated arms' right poses it is 0.05-0.32 px
#: at spans up to 40 mm and 0.45 px at 80 mm
EPIPOLAR_TOLERANCE_PX: float = 0.5
#: ... and whose median angle off the lines (their distance over how far they moved)
#: exceeds this (degrees): 0.02-0.11 on the simulated six-axis arm's right poses,
#: 0.22-0.26 on the SCARA's (its reported poses' errors); a hand-eye turned 1 degree
#: about the optical axis gives 0.99-1.02
EPIPOLAR_TOLERANCE_DEG: float = 0.5
#: least number of places tracked for a verdict
MIN_PLACES: int = 30
_MAX_CORNERS = 100
#: spacing of the places compared along an epipolar line, pixels (Lucas-Kanade reaches
#: the rest)
_LINE_STEP_PX = 3.0
_WINDOW = 21  # Lucas-Kanade window, pixels


@dataclass(frozen=True)
class EpipolarCheck:
    """How far the places tracked from one view into another lie from their epipolar
    lines.

    Attributes
    ----------
    view, other : int
        The two views (indices into the capture).
    distance_px : float
        Median distance of the tracked places from the epipolar lines the poses
        predict, pixels (undistorted images).
    angle_deg : float
        Median angle of the places' motions off their lines: the distance over how far
        each moved, degrees.  A camera turned about its optical axis by ``a`` degrees
        gives about ``a``; noise and small pose errors give a distance that grows
        with the motion, and a roughly constant angle.
    n_places : int
        Places tracked.
    offset_px : float
        Median signed distance, pixels: the part of `distance_px` that all places share
        (a pose off across the lines moves every place one way; the tracking's noise
        leaves the median near 0).

    Examples
    --------
    >>> EpipolarCheck(0, 1, 2.4, 1.1, 120).disagrees
    True
    >>> EpipolarCheck(0, 1, 0.05, 0.1, 120).disagrees, EpipolarCheck(0, 1, 0.6, 0.2, 120).disagrees
    (False, False)
    >>> EpipolarCheck(0, 1, 2.4, 1.1, 12).disagrees  # too few places for a verdict
    False
    """

    view: int
    other: int
    distance_px: float
    angle_deg: float
    n_places: int
    offset_px: float = 0.0

    def __post_init__(self) -> None:
        require_int("view", self.view, minimum=0)
        require_int("other", self.other, minimum=0)
        require_nonnegative("distance_px", self.distance_px)
        require_nonnegative("angle_deg", self.angle_deg)
        require_int("n_places", self.n_places, minimum=0)
        require_finite("offset_px", self.offset_px)

    @property
    def disagrees(self) -> bool:
        """At least :data:`MIN_PLACES` places, a median distance above
        :data:`EPIPOLAR_TOLERANCE_PX` and a median angle above
        :data:`EPIPOLAR_TOLERANCE_DEG` (the distance alone grows with the span between
        the views: a robot's reported poses have errors of their own, harmless to the
        search, which 80 mm apart already give 0.5 px)."""
        return (self.n_places >= MIN_PLACES and self.distance_px > EPIPOLAR_TOLERANCE_PX
                and self.angle_deg > EPIPOLAR_TOLERANCE_DEG)


def fundamental_from_poses(K: NDArray[np.float64], R_a: NDArray[np.float64],
                           C_a: NDArray[np.float64], R_b: NDArray[np.float64],
                           C_b: NDArray[np.float64]) -> NDArray[np.float64]:
    """The fundamental matrix ``F`` (3, 3) of two views of one pinhole camera: a pixel
    ``p_a`` of view a and its match ``p_b`` in view b satisfy ``p_b^T F p_a = 0``.

    Parameters
    ----------
    K : (3, 3)
        Pinhole intrinsics of both (undistorted) views.
    R_a, R_b : (3, 3)
        Camera-to-world rotations.
    C_a, C_b : (3,)
        Optical centres, world mm.

    Notes
    -----
    The pose of b relative to a: ``x_b = R x_a + t`` with ``R = R_b^T R_a`` and
    ``t = R_b^T (C_a - C_b)``; ``E = [t]_x R`` and ``F = K^-T E K^-1`` (Hartley &
    Zisserman, eq. 9.12 and 9.8).

    Examples
    --------
    >>> K = np.array([[800.0, 0, 320], [0, 800, 240], [0, 0, 1]])
    >>> F = fundamental_from_poses(K, np.eye(3), np.zeros(3), np.eye(3), np.array([50.0, 0, 0]))
    >>> pa, pb = np.array([300.0, 200, 1]), np.array([260.0, 200, 1])  # same row
    >>> abs(float(pb @ F @ pa)) < 1e-9
    True
    """
    R = R_b.T @ R_a
    t = R_b.T @ (np.asarray(C_a, float) - np.asarray(C_b, float))
    tx = np.array([[0.0, -t[2], t[1]], [t[2], 0.0, -t[0]], [-t[1], t[0], 0.0]])
    K_inv = np.linalg.inv(K)
    return K_inv.T @ tx @ R @ K_inv


def _as_bytes(image: NDArray[np.floating]) -> NDArray[np.uint8]:
    """Grey levels on the thesis's 0..127 scale as 8-bit (OpenCV's tracker wants it):
    doubled, rounded and saturated."""
    return cv2.convertScaleAbs(np.asarray(image, np.float32), alpha=2.0)


def _along_lines(a: NDArray[np.float32], b: NDArray[np.float32], corners: NDArray[np.float64],
                 K: NDArray[np.float64], R_a: NDArray[np.float64], C_a: NDArray[np.float64],
                 R_b: NDArray[np.float64], C_b: NDArray[np.float64],
                 depth_range_mm: tuple[float, float]) -> NDArray[np.float64]:
    """For each corner (n, 2) of `a`, the place along its epipolar line in `b` (over the
    depth range, :data:`_LINE_STEP_PX` apart, each at its nearest pixel) whose 7 x 7
    window differs least from the corner's (sum of squared differences): (n, 2), NaN
    where the line leaves `b`."""
    near, far = depth_range_mm
    rays = np.column_stack([corners, np.ones(len(corners))]) @ np.linalg.inv(K).T @ R_a.T
    ends = []
    for z in (near, far):
        pc = (C_a + rays * z - C_b) @ R_b
        with np.errstate(divide="ignore", invalid="ignore"):
            ends.append(np.where(pc[:, 2:3] > 0, pc[:, :2] / pc[:, 2:3], np.nan)
                        * np.diag(K)[:2] + K[:2, 2])
    lengths = np.linalg.norm(ends[0] - ends[1], axis=1)
    out = np.full((len(corners), 2), np.nan)
    if not np.isfinite(lengths).any():  # no line in front of view b
        return out
    length = float(np.nanmax(lengths))
    n_steps = int(min(max(np.ceil(length / _LINE_STEP_PX), 2), 1000))
    inv = np.linspace(1.0 / near, 1.0 / far, n_steps)  # even in inverse depth
    half = 3
    dy, dx = np.mgrid[-half:half + 1, -half:half + 1]
    h, w = b.shape
    for c0 in range(0, len(corners), 32):  # a few corners at a time: bounded memory
        sl = slice(c0, c0 + 32)
        pc = (C_a + rays[sl, None, :] / inv[None, :, None] - C_b) @ R_b  # (m, s, 3)
        with np.errstate(divide="ignore", invalid="ignore"):
            uv = pc[..., :2] / pc[..., 2:3] * np.diag(K)[:2] + K[:2, 2]
        inside = ((pc[..., 2] > 0) & (uv[..., 0] >= half) & (uv[..., 0] <= w - half - 2)
                  & (uv[..., 1] >= half) & (uv[..., 1] <= h - half - 2))
        cx = np.rint(corners[sl, 0]).astype(np.intp)
        cy = np.rint(corners[sl, 1]).astype(np.intp)
        patch = a[cy[:, None, None] + dy, cx[:, None, None] + dx]  # (m, 7, 7)
        # the nearest pixels: the search needs a pixel, Lucas-Kanade does the rest
        u = np.rint(np.where(inside, uv[..., 0], half)).astype(np.intp)[..., None, None] + dx
        v = np.rint(np.where(inside, uv[..., 1], half)).astype(np.intp)[..., None, None] + dy
        ssd = ((b[v, u] - patch[:, None]) ** 2).sum(axis=(2, 3))
        ssd = np.where(inside, ssd, np.inf)
        best = np.argmin(ssd, axis=1)
        found = np.isfinite(ssd[np.arange(len(best)), best])
        pick = uv[np.arange(len(best)), best]
        out[sl][found] = pick[found]
    return out


def corners_to_track(image: NDArray[np.floating]) -> NDArray[np.float64] | None:
    """Up to 100 Shi-Tomasi corners of `image` ``(H, W)`` (grey levels 0..127), at least
    8 px apart and 12 px inside the border: ``(n, 2)`` as ``(x, y)``, or None where
    there are fewer than :data:`MIN_PLACES`."""
    a = _as_bytes(image)
    h, w = a.shape
    mask = np.zeros_like(a)
    mask[12:h - 12, 12:w - 12] = 255
    corners = cv2.goodFeaturesToTrack(a, maxCorners=_MAX_CORNERS, qualityLevel=0.01,
                                      minDistance=8, blockSize=7, mask=mask)
    if corners is None or len(corners) < MIN_PLACES:
        return None
    return corners.reshape(-1, 2).astype(np.float64)


def epipolar_check(image: NDArray[np.floating], other_image: NDArray[np.floating],
                   K: NDArray[np.float64], pose: tuple[NDArray[np.float64], NDArray[np.float64]],
                   other_pose: tuple[NDArray[np.float64], NDArray[np.float64]],
                   depth_range_mm: tuple[float, float], *, view: int = 0, other: int = 1,
                   corners: NDArray[np.float64] | None = None) -> EpipolarCheck | None:
    """Track well-structured places of `image` into `other_image` and measure their
    distance from the epipolar lines that the two poses give.

    Parameters
    ----------
    image, other_image : ndarray, shape (H, W)
        The two views' undistorted grey levels (0..127), one pinhole camera `K`.
    K : (3, 3)
        Pinhole intrinsics.
    pose, other_pose : tuple of ndarray
        Each view's camera-to-world rotation (3, 3) and optical centre (3,), world mm.
    depth_range_mm : tuple of float
        ``(near, far)``: where along the rays the scene may be.
    view, other : int
        The views' indices, for the report.
    corners : ndarray, shape (n, 2), optional
        :func:`corners_to_track` of `image`, where already found.

    Returns
    -------
    EpipolarCheck or None
        None where fewer than :data:`MIN_PLACES` places were tracked both ways.

    Notes
    -----
    1. Up to 100 corners of `image` (Shi-Tomasi, at least 8 px apart, 12 px inside the
       border); `other_image` turned to `image`'s orientation by the homography of the
       points at infinity (``K R_b^T R_a K^-1``), so that views turned about their axes
       (DTU's neighbours: 27 degrees) compare windows that are not turned.
    2. Each corner's 7 x 7 window is compared along its epipolar line in
       `other_image`, every 3 px over the depth range, and the place of the least sum of squared
       differences taken (so that a texture that repeats or a wide baseline does not
       lead the tracker astray).
    3. From there, Lucas-Kanade free in both directions (21 x 21 window, one pyramid
       level: a reach of a few pixels off the line), and back; kept where the track
       back ends within 0.5 px of the corner.
    4. The distance of each tracked place (in the turned image) from the corner's
       epipolar line
       (``F = fundamental_from_poses(...)``) and its angle (the distance over how far
       the place moved); their medians.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> a = cv2.GaussianBlur(rng.uniform(0, 127, (200, 300)), (0, 0), 1.5)
    >>> b = np.roll(a, -12, axis=1)  # 12 px disparity, rows as they are
    >>> K = np.array([[800.0, 0, 150], [0, 800, 100], [0, 0, 1]])
    >>> left, right = (np.eye(3), np.zeros(3)), (np.eye(3), np.array([30.0, 0, 0]))
    >>> c = epipolar_check(a, b, K, left, right, (1000.0, 4000.0))
    >>> c.distance_px < 0.1, c.disagrees
    (True, False)
    >>> epipolar_check(a, np.roll(b, 2, axis=0), K, left, right, (1000.0, 4000.0)).disagrees
    True
    """
    R_a, C_a = (np.asarray(v, float) for v in pose)
    R_b, C_b = (np.asarray(v, float) for v in other_pose)
    fa = np.asarray(image, np.float32)
    fb = np.asarray(other_image, np.float32)
    K = np.asarray(K, float)
    if not np.allclose(R_a, R_b, atol=1e-9):
        # the other view turned to this one's orientation (the homography of the points
        # at infinity, K R_b^T R_a K^-1): windows compare and track where the views turn
        # about their axes, and what is left is the parallax along the epipolar lines
        H = K @ R_b.T @ R_a @ np.linalg.inv(K)
        h, w = fb.shape
        fb = cv2.warpPerspective(fb, H, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP)
        R_b = R_a
    a, b = _as_bytes(fa), _as_bytes(fb)
    if corners is None:
        corners = corners_to_track(fa)
        if corners is None:
            return None
    p0 = np.asarray(corners, np.float64)
    start = _along_lines(fa, fb, p0, K, R_a, C_a, R_b, C_b, depth_range_mm)
    seen = np.isfinite(start).all(axis=1)
    if seen.sum() < MIN_PLACES:
        return None
    p0, start = p0[seen].astype(np.float32), start[seen].astype(np.float32)
    lk = {"winSize": (_WINDOW, _WINDOW), "maxLevel": 1,
          "criteria": (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 30, 0.01),
          "flags": cv2.OPTFLOW_USE_INITIAL_FLOW}
    p1, ok1, _ = cv2.calcOpticalFlowPyrLK(a, b, p0.reshape(-1, 1, 2),
                                          start.reshape(-1, 1, 2).copy(), **lk)
    back, ok2, _ = cv2.calcOpticalFlowPyrLK(b, a, p1, p0.reshape(-1, 1, 2).copy(), **lk)
    good = (ok1.ravel() == 1) & (ok2.ravel() == 1) & (
        np.linalg.norm(back.reshape(-1, 2) - p0, axis=1) <= 0.5)
    if good.sum() < MIN_PLACES:
        return None
    F = fundamental_from_poses(K, R_a, C_a, R_b, C_b)
    pa = np.column_stack([p0[good], np.ones(int(good.sum()))]).astype(np.float64)
    pb = np.column_stack([p1.reshape(-1, 2)[good], np.ones(int(good.sum()))]).astype(
        np.float64)
    lines = pa @ F.T  # (n, 3): the epipolar line of each corner in the other view
    with np.errstate(divide="ignore", invalid="ignore"):
        signed = np.sum(lines * pb, axis=1) / np.hypot(lines[:, 0], lines[:, 1])
    dist = np.abs(signed)
    moved = np.linalg.norm(pb[:, :2] - pa[:, :2], axis=1)
    keep = np.isfinite(dist) & (moved > 0)
    if keep.sum() < MIN_PLACES:
        return None
    angle = np.degrees(np.arctan2(dist[keep], moved[keep]))
    return EpipolarCheck(int(view), int(other), float(np.median(dist[keep])),
                         float(np.median(angle)), int(keep.sum()),
                         float(np.median(signed[keep])))


def views_epipolar_checks(views: PreparedViews, ref: int,
                          depth_range_mm: tuple[float, float],
                          others: Sequence[int] | None = None) -> list[EpipolarCheck]:
    """:func:`epipolar_check` of view `ref` against every other view of `views` (their
    undistorted, smoothed grey levels and poses), or against `others`; the pairs without
    a verdict (too few places) are left out.

    Parameters
    ----------
    views : PreparedViews
        :func:`~robostereo.robot.views.prepared_views.prepare_views` of a capture.
    ref : int
        The view whose corners are tracked.
    depth_range_mm : tuple of float
        ``(near, far)``, the capture's.
    others : sequence of int, optional
        The views to check `ref` against (default: all the others).

    Returns
    -------
    list of EpipolarCheck
    """
    out: list[EpipolarCheck] = []
    n = views.smoothed.shape[0]
    others = [o for o in range(n) if o != ref] if others is None else list(others)
    if not others:
        return out
    corners = corners_to_track(views.smoothed[ref])
    if corners is None:
        return out
    for o in others:
        c = epipolar_check(views.smoothed[ref], views.smoothed[o], views.K,
                           (views.R[ref], views.C[ref]), (views.R[o], views.C[o]),
                           depth_range_mm, view=ref, other=o, corners=corners)
        if c is not None:
            out.append(c)
    return out


def warn_disagreeing(checks: list[EpipolarCheck]) -> None:
    """A :class:`~robostereo.errors.PlausibilityWarning` naming the pair of views whose
    tracked places lie farthest from their epipolar lines, where any pair disagrees."""
    bad = [c for c in checks if c.disagrees]
    if bad:
        c = max(bad, key=lambda c: c.distance_px)
        warn_input(f"views {c.view} and {c.other}: places tracked between them lie "
                   f"{c.distance_px:.2f} px off the epipolar lines their poses give, "
                   f"{c.angle_deg:.2f} degrees of their motion (medians of {c.n_places}; "
                   f"at most {EPIPOLAR_TOLERANCE_PX} px or {EPIPOLAR_TOLERANCE_DEG} degrees "
                   "expected): the poses or the hand-eye are off, and the located points "
                   "may be wrong")


def lone_of_three(views: PreparedViews, checks: list[EpipolarCheck],
                  depth_range_mm: tuple[float, float],
                  factor: float | None = None) -> EpipolarCheck | None:
    """Of three views, the one off the epipolar lines of both others: the reference's
    check of it disagrees, its check of the third view agrees, and the third view's of
    it disagrees too (or, with `factor`, stands out from the check that agrees as
    :func:`lone_check` asks).

    Parameters
    ----------
    views : PreparedViews
        Three views (:func:`~robostereo.robot.views.prepared_views.prepare_views`).
    checks : list of EpipolarCheck
        :func:`views_epipolar_checks` of the reference.
    depth_range_mm : tuple of float
        ``(near, far)``, the capture's.
    factor : float, optional
        ``ViewsParameters.lone_view_factor``: the third pair's check names the view too
        where its angle is more than `factor` times that of the check that agrees and
        it is over half the tolerances.  A view turned about its optical axis moves
        less across the lines of the longer baseline: of a line of 3 on a printed
        ground with the last view turned 0.5 degree, the middle view's check of it was
        1.28 px, 1.03 degrees off, the first view's 1.16 px, 0.47 degree (under the
        tolerance), the check that agrees 0.02 px, 0.01 degree.

    Returns
    -------
    EpipolarCheck or None
        The reference's check of the lone view; None unless exactly one of two checks
        disagrees and the third pair's check (tracked from the view that agrees) does.

    Notes
    -----
    :func:`lone_check` needs three checks to compare.  With three views the pair that
    does not hold the reference decides: a reference whose pose is wrong puts both its
    checks off, so where one agrees, the other view is wrong when it also disagrees
    with the view that agrees.  An error that moves a view along its baselines shows
    in no check (:mod:`~robostereo.robot.views.view_agreement` compares the pairs'
    depths for that; with three views it cannot tell which view is off).
    """
    valid = [c for c in checks if c.n_places >= MIN_PLACES]
    if views.smoothed.shape[0] != 3 or len(valid) != 2:
        return None
    off = [c for c in valid if c.disagrees]
    if len(off) != 1:
        return None
    bad = off[0]
    good = valid[0] if valid[1] is bad else valid[1]
    a, b = good.other, bad.other
    third = epipolar_check(views.smoothed[a], views.smoothed[b], views.K,
                           (views.R[a], views.C[a]), (views.R[b], views.C[b]),
                           depth_range_mm, view=a, other=b)
    if third is None:
        return None
    if third.disagrees or (factor is not None and _stands_out(third, good.angle_deg,
                                                              factor)):
        return bad
    return None


def _stands_out(check: EpipolarCheck, rest_deg: float, factor: float) -> bool:
    """Whether `check`'s angle is more than `factor` times `rest_deg` (the other checks'
    largest) and it is over half the tolerances: the leave-one-out rule."""
    return (check.angle_deg > factor * rest_deg
            and check.angle_deg > EPIPOLAR_TOLERANCE_DEG / 2
            and check.distance_px > EPIPOLAR_TOLERANCE_PX / 2)


def lone_check(checks: list[EpipolarCheck], factor: float) -> EpipolarCheck | None:
    """The one view whose tracked places lie off their epipolar lines where the other
    views' do not: the only one that :attr:`~EpipolarCheck.disagrees`, or one whose
    median angle is more than `factor` times every other's and over half
    :data:`EPIPOLAR_TOLERANCE_DEG` (and its distance over half
    :data:`EPIPOLAR_TOLERANCE_PX`): leave-one-out, below the absolute tolerance a
    robot's own pose errors need.  None with fewer than three checks (four views).

    >>> ok = [EpipolarCheck(0, k, 0.03, 0.03, 100) for k in (1, 2, 3)]
    >>> lone_check(ok + [EpipolarCheck(0, 4, 0.56, 0.44, 93)], 4.0).other
    4
    >>> lone_check(ok + [EpipolarCheck(0, 4, 0.2, 0.1, 93)], 4.0) is None
    True
    """
    valid = [c for c in checks if c.n_places >= MIN_PLACES]
    if len(valid) < 3:
        return None
    off = [c for c in valid if c.disagrees]
    if len(off) == 1:
        return off[0]
    if off:
        return None
    worst = max(valid, key=lambda c: c.angle_deg)
    rest = max(c.angle_deg for c in valid if c is not worst)
    return worst if _stands_out(worst, rest, factor) else None


def pose_offset_px(views: PreparedViews, checks: list[EpipolarCheck],
                   depth_range_mm: tuple[float, float]) -> float:
    """The poses' error across the epipolar lines that every tracked place of a pair
    shares: the root mean square of :attr:`EpipolarCheck.offset_px` over every pair of
    views, pixels (0 with no pair checked).

    Parameters
    ----------
    views : PreparedViews
        The capture's prepared views.
    checks : list of EpipolarCheck
        :func:`views_epipolar_checks` of one reference, already made; the pairs of the
        other views are checked here.
    depth_range_mm : tuple of float
        ``(near, far)``, the capture's.

    Returns
    -------
    float

    Notes
    -----
    A view's pose off by a small turn moves its image as a whole, along the epipolar
    lines as much as across them (a turn of 0.1 degree: 1.4 px at f = 800 px).  Across
    them the tracked places show it; along them it is a disparity error that a fit's
    views share and its residuals do not show.  Taken as the spread of that error, it
    enters the N-view bounds (:func:`~robostereo.robot.views.locating.locate_views`)
    beside the residuals' noise.  Every pair counts, not only the reference's: a
    pair's offset shows the component of the two images' relative shift across its
    lines, and the pairs of a cross see it in two directions.  The tracking's own
    noise moves places either way and leaves the medians near 0 (0.00-0.04 px on the
    simulator's and our renders' right poses, where the unsigned distances are
    0.01-0.18 px; an RMS of 0.3-1.7 px where every recorded pose is 0.1 degree and
    0.2 mm off).
    """
    done = {frozenset((c.view, c.other)) for c in checks}
    n = views.smoothed.shape[0]
    more = [c for a in range(n) for c in views_epipolar_checks(
        views, a, depth_range_mm,
        [b for b in range(a + 1, n) if frozenset((a, b)) not in done])]
    offsets = [c.offset_px for c in (*checks, *more)]
    if not offsets:
        return 0.0
    return float(np.sqrt(np.mean(np.square(offsets))))
