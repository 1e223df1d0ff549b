"""Scoring sparse matches against ground-truth disparity: the project's evaluation rule.

The rule, the same everywhere in robostereo (tests, ``robostereo evaluate``, the demo):

* an edge point *counts* when the ground truth at its nearest pixel is known;
* a match is *false* when its disparity differs by more than ``tolerance`` (1 px) from
  every known ground-truth disparity at the edge's nearest pixel and at its left and
  right neighbours (an edge lies between two pixels);
* *% matched* is matched counted edges over counted edges; *% false* is false
  matches over matched counted edges; the disparity RMS is over correct matches,
  against the nearest of those ground-truth values.

The same scoring is applied to a dense disparity map (OpenCV's StereoSGBM) read at
the same pixels, so the two are compared point for point.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.edges import to_grey
from robostereo.errors import InputError

__all__ = ["MatchScore", "sample_dense", "score_matches"]


@dataclass(frozen=True)
class MatchScore:
    """Matched and false figures of a set of edge points against ground truth.

    Attributes
    ----------
    counted : int
        Edge points whose ground truth is known.
    matched : int
        Counted edge points that have a match.
    false : int
        Matched counted points whose disparity is wrong by the rule above.
    rms : float
        Disparity RMS error of the correct matches (pixels); NaN if there are none.
    """

    counted: int
    matched: int
    false: int
    rms: float

    @property
    def matched_fraction(self) -> float:
        return self.matched / self.counted if self.counted else float("nan")

    @property
    def false_fraction(self) -> float:
        return self.false / self.matched if self.matched else 0.0

    def as_dict(self) -> dict[str, float]:
        d: dict[str, float] = dict(asdict(self))
        d["matched_fraction"] = self.matched_fraction
        d["false_fraction"] = self.false_fraction
        return d


def score_matches(
    rows: ArrayLike,
    x: ArrayLike,
    disparity: ArrayLike,
    gt_disparity: NDArray[np.floating],
    *,
    tolerance: float = 1.0,
) -> MatchScore:
    """Score matched edge points by the project's evaluation rule.

    Parameters
    ----------
    rows : array_like of int, shape (N,)
        Image row of each edge point.
    x : array_like of float, shape (N,)
        Sub-pixel column of each edge point in the left image.
    disparity : array_like of float, shape (N,)
        Found disparity, NaN where the point is unmatched.
    gt_disparity : ndarray, shape (H, W)
        Ground-truth disparity of the left image, NaN where unknown.
    tolerance : float
        Largest disparity error of a correct match, pixels.

    Returns
    -------
    MatchScore

    Examples
    --------
    >>> gt = np.full((1, 4), 5.0); gt[0, 3] = np.nan
    >>> score_matches([0, 0, 0, 0], [0.4, 1.6, 2.2, 3.0], [5.5, 7.0, np.nan, 5.0], gt)
    MatchScore(counted=3, matched=2, false=1, rms=0.5)
    """
    r = np.asarray(rows, dtype=np.intp)
    xs = np.asarray(x, dtype=float)
    d = np.asarray(disparity, dtype=float)
    gt = np.asarray(gt_disparity, dtype=float)
    if gt.ndim != 2:
        raise InputError(f"gt_disparity must be an (H, W) map, got shape {gt.shape}")
    h, w = gt.shape
    c = np.clip(np.rint(xs).astype(np.intp), 0, w - 1)
    r = np.clip(r, 0, h - 1)
    known = np.isfinite(gt[r, c])
    nb = np.stack([gt[r, np.clip(c + o, 0, w - 1)] for o in (-1, 0, 1)], axis=1)
    err = np.abs(nb - d[:, None])
    best = np.nanmin(np.where(np.isfinite(err), err, np.inf), axis=1)
    matched = known & np.isfinite(d)
    false = matched & (best > tolerance)
    good = matched & ~false
    rms = float(np.sqrt(np.mean(best[good] ** 2))) if good.any() else float("nan")
    return MatchScore(
        counted=int(known.sum()), matched=int(matched.sum()), false=int(false.sum()), rms=rms
    )


def sample_dense(dense: NDArray[np.floating], rows: ArrayLike, x: ArrayLike) -> NDArray[np.float64]:
    """Read a dense disparity map at the edge points' nearest pixels.

    Parameters
    ----------
    dense : ndarray, shape (H, W)
        Disparity map, NaN where the dense matcher gave none.
    rows, x : array_like, shape (N,)
        Rows and sub-pixel columns of the edge points.

    Returns
    -------
    ndarray, shape (N,)
    """
    d = np.asarray(dense, dtype=float)
    h, w = d.shape
    r = np.clip(np.asarray(rows, dtype=np.intp), 0, h - 1)
    c = np.clip(np.rint(np.asarray(x, dtype=float)).astype(np.intp), 0, w - 1)
    return d[r, c]


def sgbm_disparity(
    left: ArrayLike,
    right: ArrayLike,
    disparity_range: tuple[float, float],
    *,
    block_size: int = 5,
    uniqueness_ratio: int = 10,
    bit_depth: int | None = None,
) -> NDArray[np.float64]:
    """OpenCV StereoSGBM on the same pair and range: the project's dense reference.

    Parameters
    ----------
    left, right : array_like, shape (H, W) or (H, W, 3|4)
    disparity_range : tuple of float
        ``(min, max)`` disparity; SGBM searches ``numDisparities`` rounded up to a
        multiple of 16 from ``floor(min)``, and values above ``max + 0.5`` are dropped.
    block_size, uniqueness_ratio : int
        SGBM's ``blockSize`` (5) and ``uniquenessRatio`` (10); ``P1 = 8 * block_size**2``
        and ``P2 = 32 * block_size**2`` as OpenCV's documentation recommends for grey input.

    Returns
    -------
    ndarray, shape (H, W)
        Disparity in pixels, NaN where SGBM gives none.
    """
    import cv2

    lo, hi = disparity_range
    g = [np.clip(np.rint(to_grey(im, bit_depth=bit_depth) * 2.0), 0, 255).astype(np.uint8)
         for im in (left, right)]
    n = int(np.ceil((np.floor(hi) - np.floor(lo) + 1) / 16.0) * 16)
    sgbm = cv2.StereoSGBM_create(
        minDisparity=int(np.floor(lo)), numDisparities=n, blockSize=block_size,
        uniquenessRatio=uniqueness_ratio, P1=8 * block_size**2, P2=32 * block_size**2,
    )
    d = sgbm.compute(g[0], g[1]).astype(float) / 16.0
    d[(d < np.floor(lo)) | (d > hi + 0.5)] = np.nan
    return d
