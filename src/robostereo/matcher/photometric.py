"""The two views' grey levels compared at matched places, and corrected where they differ.

The window costs (census and Sobel, :mod:`~robostereo.matcher.window_costs`) and the
thesis's edge features (3.2) assume that a scene point has about the same grey level in
both views.  Two cameras, or one camera whose exposure changed between the two
viewpoints, break that [1]_ [2]_: a 30 % gain on the right view costs the default
matcher 4-22 points of coverage on the developer scenes, though the census alone does
not mind it.

After a first match the accepted matches say which left pixel sees what right pixel.
:func:`grey_pairs` reads the grey levels of both views a few pixels either side of each
match along its row; :func:`views_differ` says whether a gain and offset
(:func:`grey_difference`) bring them much closer than they are, and only then
:func:`fit_grey_map` fits a non-decreasing map from right to left grey levels to the
pairs (:func:`grey_correction` does the three) and
:func:`~robostereo.matcher.pipeline.match_stereo` matches again with the right view's
grey levels mapped.  On pairs whose views agree the first match is the result,
unchanged; ``benchmarks/bench_checks.py`` measures both.

References
----------
.. [1] R. Szeliski, *Computer Vision: Algorithms and Applications*, 2nd ed., Springer
   2022, section 12.3 (robust matching costs; bias and gain between the two views).
.. [2] H. Hirschmuller and D. Scharstein, "Evaluation of stereo matching costs on
   images with radiometric differences", IEEE TPAMI 31(9), 2009.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_finite, require_int, require_one_length
from robostereo.matcher.confidence import isotonic
from robostereo.matcher.grey_levels import to_grey
from robostereo.matcher.photometric_kernels import difference_kernel, places_kernel

__all__ = [
    "MIN_PAIRS",
    "PAIR_OFFSETS",
    "RESIDUAL_RATIO",
    "GreyMap",
    "fit_grey_map",
    "grey_correction",
    "grey_difference",
    "grey_pairs",
    "views_differ",
]

#: columns either side of a match, along its row, whose grey levels are compared: not
#: the edge's own column, where the sub-pixel position makes the steepest difference
PAIR_OFFSETS: tuple[int, ...] = (-3, -2, 2, 3)
#: least number of grey-level pairs for a map to be fitted and trusted
MIN_PAIRS: int = 400
#: the views differ when a gain and offset at least halve the pairs' median absolute
#: difference (:func:`views_differ`).  On the six developer scenes the ratio is
#: 0.97-1.15 (no second match); a 5 % gain on the right view gives 1.35-3.07, a 10 %
#: gain 2.46-5.22, a gain of 0.7 with an offset of 20, a gamma of 0.7 or a 30 % gain
#: 4.3-13.2 (``benchmarks/bench_checks.py``).  Below it the coverage the difference
#: costs is small (a 5 % gain: 0.4-1.8 points); the ratio only decides when the time
#: of a second match is spent
RESIDUAL_RATIO: float = 2.0
#: groups of equal count the pairs are pooled into before the non-decreasing fit
_GROUPS = 32
#: at most this many matches are read (evenly spaced): the map has 32 knots
_MAX_MATCHES = 250


@dataclass(frozen=True)
class GreyMap:
    """A non-decreasing map from the right view's grey levels to the left's.

    Attributes
    ----------
    right_knots, left_knots : tuple of float
        The map, piecewise linear through ``(right_knots[k], left_knots[k])``, both
        non-decreasing, ``right_knots`` increasing; beyond the ends it keeps the end
        knots' offset (slope 1).  Grey levels on :func:`~robostereo.matcher.grey_levels.to_grey`'s
        0..127 scale.
    residual_identity, residual_mapped : float
        Median absolute difference of the pairs' grey levels, left minus right, as they
        are and with the right ones mapped (for the record: whether the views differ is
        decided by :func:`views_differ`).
    n_pairs : int
        Number of pairs fitted.

    Examples
    --------
    >>> m = GreyMap((10.0, 100.0), (15.0, 105.0), 5.0, 0.5, 800)
    >>> m(np.array([0.0, 10.0, 55.0, 127.0])).tolist()
    [5.0, 15.0, 60.0, 132.0]
    """

    right_knots: tuple[float, ...]
    left_knots: tuple[float, ...]
    residual_identity: float
    residual_mapped: float
    n_pairs: int

    def __post_init__(self) -> None:
        r = np.asarray(self.right_knots, dtype=float)
        g = np.asarray(self.left_knots, dtype=float)
        if r.ndim != 1 or r.shape != g.shape or r.size == 0:
            raise InputError(f"right_knots and left_knots must be of one length >= 1, got "
                             f"{r.size} and {g.size}")
        require_finite("right_knots", r.tolist())
        require_finite("left_knots", g.tolist())
        if np.any(np.diff(r) <= 0) or np.any(np.diff(g) < 0):
            raise InputError("grey map knots must increase (right) and not decrease (left)")
        for name in ("residual_identity", "residual_mapped"):
            require_finite(name, getattr(self, name))
            if getattr(self, name) < 0:
                raise InputError(f"{name} must be >= 0, got {getattr(self, name)}")
        require_int("n_pairs", self.n_pairs, minimum=0)

    def __call__(self, grey: ArrayLike) -> NDArray[np.float32]:
        """The right view's grey levels ``(H, W)`` (any shape) mapped to the left's."""
        g = np.asarray(grey, dtype=np.float32)
        r = np.asarray(self.right_knots, dtype=np.float32)
        lk = np.asarray(self.left_knots, dtype=np.float32)
        out = np.interp(g, r, lk).astype(np.float32)
        below, above = g < r[0], g > r[-1]
        out[below] = g[below] + (lk[0] - r[0])
        out[above] = g[above] + (lk[-1] - r[-1])
        return out


def _grey_at(image: np.ndarray, rows: NDArray[np.intp], cols: NDArray[np.intp],
             bit_depth: int | None) -> NDArray[np.float64]:
    """Grey levels (:func:`to_grey`) of the pixels ``(rows, cols)`` of ``image``, ``(M,)``."""
    return to_grey(image[rows, cols][None], bit_depth=bit_depth)[0].astype(np.float64)


def grey_pairs(left: ArrayLike, right: ArrayLike, rows: ArrayLike, x: ArrayLike,
               disparity: ArrayLike, *, bit_depth: int | None = None
               ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Grey levels of the two views at the places that matches pair.

    Parameters
    ----------
    left, right : array_like, shape (H, W) or (H, W, 3|4)
        The images as given to :func:`~robostereo.matcher.pipeline.match_stereo`.
    rows, x, disparity : array_like, shape (N,)
        Matches: left edge point ``(x, row)`` sees right ``(x - disparity, row)``.  At most
        250 of them are read, evenly spaced.
    bit_depth : int, optional
        As :func:`~robostereo.matcher.grey_levels.to_grey`.

    Returns
    -------
    left_grey, right_grey : ndarray, shape (M,)
        For each match and each column offset ``o`` of :data:`PAIR_OFFSETS` whose pixels
        lie in both images: the left grey level at column ``round(x) + o`` and the right
        one at ``round(x) + o - disparity``, linearly interpolated along the row.
    """
    a, b = np.asarray(left), np.asarray(right)
    y = np.asarray(rows, dtype=np.intp).ravel()
    xs = np.asarray(x, dtype=float).ravel()
    d = np.asarray(disparity, dtype=float).ravel()
    require_one_length(("rows", "x", "disparity"), y, xs, d)
    h, w = a.shape[:2]
    # -- one pair per match and offset, where both pixels (and the right neighbour used
    #    for the interpolation) lie in the images
    yy, xl, x0, t = places_kernel(y.astype(np.int64), np.ascontiguousarray(xs),
                                  np.ascontiguousarray(d), np.asarray(PAIR_OFFSETS, np.int64),
                                  h, w, _MAX_MATCHES)
    k = yy.size
    if k == 0:
        return np.zeros(0), np.zeros(0)
    if a.dtype == b.dtype and a.shape[2:] == b.shape[2:]:  # one conversion for all three
        grey = to_grey(np.concatenate([a[yy, xl], b[yy, x0], b[yy, x0 + 1]])[None],
                       bit_depth=bit_depth)[0].astype(np.float64)
    else:
        grey = np.concatenate([_grey_at(a, yy, xl, bit_depth),
                               _grey_at(b, np.concatenate([yy, yy]),
                                        np.concatenate([x0, x0 + 1]), bit_depth)])
    return grey[:k], (1.0 - t) * grey[k:2 * k] + t * grey[2 * k:]


def grey_difference(left_grey: ArrayLike, right_grey: ArrayLike) -> tuple[float, float]:
    """How far apart matched grey levels are, as they are and after a gain and offset.

    Parameters
    ----------
    left_grey, right_grey : array_like, shape (M,)
        Grey levels of the same scene points in the two views (:func:`grey_pairs`).

    Returns
    -------
    as_they_are, after_gain_and_offset : float
        Median absolute difference ``left - right``, and ``left - (a * right + b)`` with
        ``a, b`` fitted by least squares, then again without the pairs more than three
        times the median difference off the first line (two parameters: it cannot fit
        the noise).  NaN, NaN with fewer than 8 pairs.

    Examples
    --------
    >>> g = np.linspace(5, 120, 1000)
    >>> [round(v, 3) for v in grey_difference(g, 1.25 * g - 4)]
    [11.625, 0.0]
    """
    gl, gr = _pairs(left_grey, right_grey)
    if gl.size < 8:
        return float("nan"), float("nan")
    as_they_are, fitted = difference_kernel(np.ascontiguousarray(gl), np.ascontiguousarray(gr))
    return float(as_they_are), float(fitted)


def views_differ(left_grey: ArrayLike, right_grey: ArrayLike) -> bool:
    """The two views' grey levels differ: at least :data:`MIN_PAIRS` pairs, and a gain
    and offset make their median absolute difference more than :data:`RESIDUAL_RATIO`
    times smaller (:func:`grey_difference`).

    >>> rng = np.random.default_rng(1)
    >>> g = rng.uniform(5, 120, 2000)
    >>> r = g + rng.normal(0, 1, g.size)  # the same scene points, one exposure, noise
    >>> views_differ(g, 1.1 * r), views_differ(g, r + 0.3), views_differ(g[:100], 2 * r[:100])
    (True, False, False)
    """
    gl, gr = _pairs(left_grey, right_grey)
    if gl.size < MIN_PAIRS:
        return False
    as_they_are, fitted = grey_difference(gl, gr)
    return bool(as_they_are > RESIDUAL_RATIO * fitted)


def grey_correction(left: ArrayLike, right: ArrayLike, rows: ArrayLike, x: ArrayLike,
                    disparity: ArrayLike, *, bit_depth: int | None = None) -> GreyMap | None:
    """The map the right view's grey levels need, or None where the views agree.

    :func:`grey_pairs` at the matches ``(rows, x, disparity)`` (``(N,)`` each, the
    accepted ones of a first match), :func:`views_differ` on them, and where they differ
    :func:`fit_grey_map`.  None too with fewer than :data:`MIN_PAIRS` pairs possible.
    """
    if np.size(rows) * len(PAIR_OFFSETS) < MIN_PAIRS:
        return None
    pairs = grey_pairs(left, right, rows, x, disparity, bit_depth=bit_depth)
    return fit_grey_map(*pairs) if views_differ(*pairs) else None


def _pairs(left_grey: ArrayLike, right_grey: ArrayLike
           ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    gl = np.asarray(left_grey, dtype=float).ravel()
    gr = np.asarray(right_grey, dtype=float).ravel()
    require_one_length(("left_grey", "right_grey"), gl, gr)
    ok = np.isfinite(gl) & np.isfinite(gr)
    return gl[ok], gr[ok]


def fit_grey_map(left_grey: ArrayLike, right_grey: ArrayLike) -> GreyMap:
    """Fit a non-decreasing map from right to left grey levels to matched pairs.

    Parameters
    ----------
    left_grey, right_grey : array_like, shape (M,)
        Grey levels of the same scene points in the two views (:func:`grey_pairs`).

    Returns
    -------
    GreyMap
        The map and how well it and the identity explain the pairs.

    Notes
    -----
    1. The pairs are sorted by their right grey level and pooled into 32 groups of
       equal count; each group gives its median right and median left grey level
       (medians: the few wrong matches and the pairs across a depth step do not pull).
    2. A non-decreasing fit of the groups' left medians on their right medians (pool
       adjacent violators, :func:`~robostereo.matcher.confidence.isotonic`) is the map:
       an exposure, gain, offset or gamma change between the views is monotone.
    3. The residuals are the pairs' median absolute left-minus-right difference, as
       they are and mapped.  They describe the fit; the decision to use it rests on the
       two-parameter :func:`views_differ`, which the map's freedom cannot flatter.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> g = rng.uniform(5, 120, 4000)
    >>> m = fit_grey_map(g, 0.8 * g + 3 + rng.normal(0, 0.5, g.size))
    >>> round(float(m(np.array([83.0]))[0]), 0), m.residual_identity > 10 * m.residual_mapped
    (100.0, True)
    """
    gl, gr = _pairs(left_grey, right_grey)
    n = int(gl.size)
    if n < _GROUPS:
        return GreyMap((0.0,), (0.0,), 0.0, 0.0, n)
    # -- 1. equal-count groups along the right grey level, their medians
    med_r, med_l, sizes = _group_medians_of(gl, gr, _GROUPS)
    # -- 2. non-decreasing fit; groups of one right median are merged
    kx, ky = isotonic(med_r, med_l, sizes.astype(float))
    kx, first = np.unique(kx, return_index=True)
    m = GreyMap(tuple(kx.tolist()), tuple(ky[first].tolist()), 0.0, 0.0, n)
    # -- 3. the residuals
    return GreyMap(m.right_knots, m.left_knots, float(np.median(np.abs(gl - gr))),
                   float(np.median(np.abs(gl - m(gr)))), n)


def _group_medians_of(gl: NDArray[np.float64], gr: NDArray[np.float64], groups: int
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """The pairs sorted by ``gr`` in ``groups`` runs of equal count: each run's median
    ``gr`` and median ``gl`` ``(groups,)``, and the runs' sizes."""
    n = int(gr.size)
    group = np.arange(n) * groups // n  # of the sorted pairs
    starts = np.searchsorted(group, np.arange(groups))
    sizes = np.diff(np.append(starts, n))
    mid = (starts + (sizes - 1) // 2, starts + sizes // 2)
    r = np.sort(gr)
    # the left grey levels sorted within each run: the run's number plus a fraction
    lo, span = float(gl.min()), float(np.ptp(gl)) + 1.0
    within = np.sort(group + (gl[np.argsort(gr, kind="stable")] - lo) / span) - group
    return (0.5 * (r[mid[0]] + r[mid[1]]),
            (0.5 * (within[mid[0]] + within[mid[1]])) * span + lo, sizes)

