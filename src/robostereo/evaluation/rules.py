"""The scoring rules: when a match is false, where the depth steps are, calibration.

Two rules judge a matched edge point at sub-pixel column ``x`` of row ``r`` against the
ground-truth disparity of the left view (NaN where unknown).  Under both, a point is
*counted* when the ground truth at its nearest pixel ``(r, round(x))`` is known, so
the two rules count the same points and give the same % matched; they differ in which
ground-truth pixels a match may agree with:

``"project"`` (the project's rule, kept for continuity)
    false when the disparity differs by more than ``tolerance`` (1 px) from every known
    ground truth at the nearest pixel and at its left and right neighbours.
``"silhouette"`` (the silhouette rule)
    false when the disparity differs by more than ``tolerance`` (1 px; 3 px is KITTI's
    custom) from the ground truth at *every known pixel of its row whose centre lies
    within 2 px* of the edge's sub-pixel position (``|j - x| <= 2``: four or five
    pixels).  An edge on an occluding contour lies between two surfaces and its right
    disparity is the nearer surface's; its sub-pixel position is often 1-2 px from
    where the ground truth's foreground ends, so the project's three pixels can all be
    background.

A pixel is *near a depth step* when it lies within 4 px (a 9 x 9 neighbourhood,
Chebyshev distance <= 4) of a ground-truth disparity step of more than 2 px: a pixel
whose known disparity differs by more than 2 px from a known 4-neighbour (left,
right, up or down; 8-neighbours on request).  Unknown pixels make no steps.  An edge
point is near a step when its nearest pixel is (:func:`depth_step_mask`,
:func:`near_steps`).

% matched is matched counted points over counted points, % false is false matches over
matched counted points (:class:`MatchScore`); a coverage curve takes points by
decreasing confidence (:func:`coverage_curve`); the expected calibration error of a
confidence is :func:`expected_calibration_error`.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.ndimage import maximum_filter

from robostereo.errors import InputError, require_int, require_nonnegative
from robostereo.matcher.confidence import calibration_table

__all__ = [
    "RULES",
    "CoverageCurve",
    "MatchScore",
    "check_points",
    "coverage_curve",
    "depth_step_mask",
    "expected_calibration_error",
    "match_errors",
    "near_steps",
    "rule_errors",
    "score_matches",
    "silhouette_errors",
]

#: the scoring rules, by name: the project's and the silhouette rule
RULES: tuple[str, ...] = ("project", "silhouette")


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
        Matched counted points whose disparity is wrong by the rule used.
    rms : float
        Disparity RMS error of the correct matches (pixels); NaN if there are none.
    """

    counted: int
    matched: int
    false: int
    rms: float

    def __post_init__(self) -> None:
        if not 0 <= self.false <= self.matched <= self.counted:
            raise InputError(f"MatchScore needs 0 <= false <= matched <= counted, got "
                             f"{self.false}, {self.matched}, {self.counted}")

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


def check_points(
    rows: ArrayLike, x: ArrayLike, disparity: ArrayLike, gt_disparity: ArrayLike,
    tolerance: float = 0.0,
) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Checked arrays ``(rows, x, disparity, gt)`` of the scoring functions.

    Points off the map are refused (:class:`InputError`), not moved to the border.

    >>> r, x, d, g = check_points([0], [1.4], [3.0], np.zeros((2, 3)))
    >>> r.tolist(), x.tolist(), g.shape
    ([0], [1.4], (2, 3))
    """
    try:
        arrays = [np.asarray(v, dtype=float) for v in (rows, x, disparity, gt_disparity)]
    except (TypeError, ValueError):
        raise InputError("rows, x, disparity and gt_disparity must be arrays of numbers") from None
    r, xs, d, gt = arrays
    if gt.ndim != 2 or gt.size == 0:
        raise InputError(f"gt_disparity must be a non-empty (H, W) map, got shape {gt.shape}")
    if not (r.ndim == xs.ndim == d.ndim == 1 and r.shape == xs.shape == d.shape):
        raise InputError(f"rows, x and disparity must be 1-D arrays of one length, got shapes "
                         f"{r.shape}, {xs.shape}, {d.shape}")
    require_nonnegative("tolerance", tolerance)
    h, w = gt.shape
    if not (np.isfinite(r).all() and (r == np.rint(r)).all() and (r >= 0).all()
            and (r <= h - 1).all()):
        raise InputError(f"rows must be whole numbers in 0..{h - 1} (the map's rows)")
    if not (np.isfinite(xs).all() and (xs >= -0.5).all() and (xs < w - 0.5).all()):
        raise InputError(f"x must be finite and inside the map: -0.5 <= x < {w - 0.5}")
    return r.astype(np.intp), xs, d, gt


def _row_errors(
    r: NDArray[np.intp], xs: NDArray[np.float64], d: NDArray[np.float64],
    gt: NDArray[np.float64], columns: NDArray[np.intp], use: NDArray[np.bool_],
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """Counted points and least ``|d - gt|`` over the columns ``columns[n, k]`` where
    ``use[n, k]`` (known values only)."""
    w = gt.shape[1]
    c = np.rint(xs).astype(np.intp)
    known = np.isfinite(gt[r, c])
    nb = gt[r[:, None], np.clip(columns, 0, w - 1)]
    err = np.where(use, np.abs(nb - d[:, None]), np.nan)
    best = np.min(np.where(np.isfinite(err), err, np.inf), axis=1, initial=np.inf)
    ok = known & np.isfinite(d) & np.isfinite(best)
    return known, np.where(ok, best, np.nan)


def match_errors(
    rows: ArrayLike, x: ArrayLike, disparity: ArrayLike, gt_disparity: NDArray[np.floating]
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """Per edge point: is its ground truth known, and its error by the project's rule.

    Parameters
    ----------
    rows, x, disparity : array_like, shape (N,)
        Rows, sub-pixel columns and found disparities (NaN where unmatched).
    gt_disparity : ndarray, shape (H, W)
        Ground truth, NaN where unknown.

    Returns
    -------
    known : ndarray of bool, shape (N,)
        The ground truth at the nearest pixel is known.
    error : ndarray, shape (N,)
        Smallest ``|d - gt|`` over the nearest pixel and its left and right neighbours
        (known values only); NaN where unmatched or unknown.

    Examples
    --------
    >>> gt = np.array([[4.0, 5.0, 6.0, np.nan]])
    >>> k, e = match_errors([0, 0, 0], [1.2, 2.0, 3.0], [6.5, np.nan, 6.0], gt)
    >>> k.tolist(), e.tolist()
    ([True, True, False], [0.5, nan, nan])
    """
    r, xs, d, gt = check_points(rows, x, disparity, gt_disparity)
    cols = np.rint(xs).astype(np.intp)[:, None] + np.arange(-1, 2)
    return _row_errors(r, xs, d, gt, cols, np.ones(cols.shape, dtype=bool))


def silhouette_errors(
    rows: ArrayLike, x: ArrayLike, disparity: ArrayLike, gt_disparity: NDArray[np.floating],
    *, radius: float = 2.0,
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """Per edge point: is its ground truth known, and its error by the silhouette rule.

    Parameters
    ----------
    rows, x, disparity : array_like, shape (N,)
        Rows, sub-pixel columns and found disparities (NaN where unmatched).
    gt_disparity : ndarray, shape (H, W)
        Ground truth, NaN where unknown.
    radius : float
        The rule's reach: pixels ``j`` of the row with ``|j - x| <= radius`` (2 px).

    Returns
    -------
    known : ndarray of bool, shape (N,)
        The ground truth at the nearest pixel is known (the same points as
        :func:`match_errors` counts).
    error : ndarray, shape (N,)
        Smallest ``|d - gt|`` over the known pixels of the row within ``radius`` of
        ``x``; NaN where unmatched or unknown.

    Examples
    --------
    A silhouette row: the foreground (disparity 9) ends between pixels 2 and 3.  An
    edge found at x = 3.9 with the foreground's disparity: the project's rule looks at
    pixels 3, 4, 5 (all background) and calls it false; the silhouette rule looks at
    pixels 2..5 and calls it right.  At x = 4.3 both look only at background.

    >>> gt = np.array([[9.0, 9.0, 9.0, 4.0, 4.0, 4.0, 4.0, 4.0]])
    >>> silhouette_errors([0, 0], [4.3, 3.9], [9.0, 9.0], gt)[1].tolist()
    [5.0, 0.0]
    >>> match_errors([0, 0], [4.3, 3.9], [9.0, 9.0], gt)[1].tolist()
    [5.0, 5.0]
    """
    require_nonnegative("radius", radius)
    r, xs, d, gt = check_points(rows, x, disparity, gt_disparity)
    k = int(np.ceil(radius)) + 1
    cols = np.floor(xs).astype(np.intp)[:, None] + np.arange(-k + 1, k + 1)
    w = gt.shape[1]
    use = (np.abs(cols - xs[:, None]) <= radius + 1e-9) & (cols >= 0) & (cols <= w - 1)
    return _row_errors(r, xs, d, gt, cols, use)


def rule_errors(
    rows: ArrayLike, x: ArrayLike, disparity: ArrayLike, gt_disparity: NDArray[np.floating],
    *, rule: str = "project",
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """:func:`match_errors` (``rule="project"``) or :func:`silhouette_errors`
    (``rule="silhouette"``).

    >>> gt = np.array([[9.0, 9.0, 9.0, 4.0, 4.0]])
    >>> rule_errors([0], [3.9], [9.0], gt, rule="silhouette")[1].tolist()
    [0.0]
    """
    if rule == "project":
        return match_errors(rows, x, disparity, gt_disparity)
    if rule == "silhouette":
        return silhouette_errors(rows, x, disparity, gt_disparity)
    raise InputError(f"rule must be one of {', '.join(RULES)}, got {rule!r}")


def _subset(subset: ArrayLike | None, n: int) -> NDArray[np.bool_]:
    if subset is None:
        return np.ones(n, dtype=bool)
    s = np.asarray(subset)
    if s.dtype != bool or s.shape != (n,):
        raise InputError(f"subset must be a boolean array of shape ({n},), got {s.dtype} "
                         f"{s.shape}")
    return s


def score_matches(
    rows: ArrayLike,
    x: ArrayLike,
    disparity: ArrayLike,
    gt_disparity: NDArray[np.floating],
    *,
    tolerance: float = 1.0,
    rule: str = "project",
    subset: ArrayLike | None = None,
) -> MatchScore:
    """Score matched edge points by the project's rule or by the silhouette rule.

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
    rule : {"project", "silhouette"}
        Which pixels a match may agree with (see the module's docstring).
    subset : array_like of bool, shape (N,), optional
        Score only these points (e.g. :func:`near_steps`); default all.

    Returns
    -------
    MatchScore

    Raises
    ------
    InputError
        Arrays of different lengths, a map that is not (H, W), a point off the map (a
        row outside ``0..H-1`` or ``x`` outside ``-0.5 .. W-0.5``): such points are
        refused, not moved to the border; an unknown rule.

    Examples
    --------
    >>> gt = np.full((1, 4), 5.0); gt[0, 3] = np.nan
    >>> score_matches([0, 0, 0, 0], [0.4, 1.6, 2.2, 3.0], [5.5, 7.0, np.nan, 5.0], gt)
    MatchScore(counted=3, matched=2, false=1, rms=0.5)
    """
    require_nonnegative("tolerance", tolerance)
    known, err = rule_errors(rows, x, disparity, gt_disparity, rule=rule)
    keep = _subset(subset, known.shape[0])
    known = known & keep
    matched = known & np.isfinite(err)
    false = matched & (err > tolerance)
    good = matched & ~false
    rms = float(np.sqrt(np.mean(err[good] ** 2))) if good.any() else float("nan")
    return MatchScore(
        counted=int(known.sum()), matched=int(matched.sum()), false=int(false.sum()), rms=rms
    )


@dataclass(frozen=True)
class CoverageCurve:
    """Coverage against false rate as a confidence threshold is lowered.

    Attributes
    ----------
    coverage : ndarray, shape (K,)
        Matched counted points over counted points, non-decreasing.
    false_rate : ndarray, shape (K,)
        False matches over matched counted points at the same threshold.
    threshold : ndarray, shape (K,)
        The confidence (or the dense matcher's setting) of each point of the curve.
    """

    coverage: NDArray[np.float64]
    false_rate: NDArray[np.float64]
    threshold: NDArray[np.float64]

    def __post_init__(self) -> None:
        shapes = {np.shape(self.coverage), np.shape(self.false_rate), np.shape(self.threshold)}
        if len(shapes) != 1 or np.ndim(self.coverage) != 1:
            raise InputError(f"CoverageCurve arrays must be 1-D of one length, got {shapes}")

    def coverage_at(self, max_false: float) -> float:
        """Largest coverage whose false rate is at most ``max_false`` (0 if none).

        >>> CoverageCurve(np.array([0.2, 0.5, 0.9]), np.array([0.0, 0.01, 0.04]),
        ...               np.array([0.9, 0.5, 0.1])).coverage_at(0.02)
        0.5
        """
        ok = self.false_rate <= max_false
        return float(self.coverage[ok].max()) if ok.any() else 0.0


def coverage_curve(
    rows: ArrayLike, x: ArrayLike, disparity: ArrayLike, confidence: ArrayLike,
    gt_disparity: NDArray[np.floating], *, tolerance: float = 1.0, rule: str = "project",
    subset: ArrayLike | None = None,
) -> CoverageCurve:
    """The curve of a sparse matcher with a per-point confidence, by a scoring rule.

    Points are taken in order of decreasing confidence; after each, coverage and false
    rate are those of all points taken so far.  ``rule`` and ``subset`` are those of
    :func:`score_matches` (coverage is over the subset's counted points).

    Examples
    --------
    >>> gt = np.full((1, 6), 5.0)
    >>> c = coverage_curve([0] * 4, [1.0, 2.0, 3.0, 4.0], [5.0, 9.0, 5.2, np.nan],
    ...                    [0.9, 0.2, 0.8, 0.99], gt)
    >>> c.coverage.round(2).tolist(), c.false_rate.round(2).tolist()
    ([0.25, 0.5, 0.75], [0.0, 0.0, 0.33])
    """
    known, err = rule_errors(rows, x, disparity, gt_disparity, rule=rule)
    known = known & _subset(subset, known.shape[0])
    conf = np.asarray(confidence, dtype=float)
    take = known & np.isfinite(err) & np.isfinite(conf)
    order = np.nonzero(take)[0]
    order = order[np.argsort(-conf[order], kind="stable")]
    bad = np.cumsum(err[order] > tolerance)
    k = np.arange(1, order.shape[0] + 1)
    n = max(int(known.sum()), 1)
    return CoverageCurve(coverage=k / n, false_rate=bad / np.maximum(k, 1),
                         threshold=conf[order])


def depth_step_mask(
    gt_disparity: ArrayLike, *, step: float = 2.0, radius: int = 4, connectivity: int = 4,
) -> NDArray[np.bool_]:
    """Pixels near a ground-truth depth step.

    Parameters
    ----------
    gt_disparity : array_like, shape (H, W)
        Ground-truth disparity, NaN (or inf) where unknown.
    step : float
        A step is a jump of more than ``step`` px (2) between two known neighbours.
    radius : int
        Pixels within ``radius`` (4: a 9 x 9 neighbourhood) of a step pixel are near.
    connectivity : {4, 8}
        Neighbours compared: left/right/up/down (4) or also the diagonals (8).

    Returns
    -------
    ndarray of bool, shape (H, W)

    Notes
    -----
    1. A pixel is a step pixel when its disparity and a neighbour's are both known and
       differ by more than ``step`` (both pixels of the pair are step pixels).
    2. The step pixels are dilated by a ``(2 radius + 1)`` square.

    Examples
    --------
    >>> gt = np.full((3, 12), 4.0); gt[:, 6:] = 9.0; gt[:, 0] = np.nan
    >>> depth_step_mask(gt, radius=1)[0].astype(int).tolist()
    [0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0]
    """
    g = np.asarray(gt_disparity, dtype=float)
    if g.ndim != 2:
        raise InputError(f"gt_disparity must be an (H, W) map, got shape {g.shape}")
    require_nonnegative("step", step)
    radius = require_int("radius", radius, minimum=0)
    if connectivity not in (4, 8):
        raise InputError(f"connectivity must be 4 or 8, got {connectivity!r}")
    h, w = g.shape
    g = np.where(np.isfinite(g), g, np.nan)
    pad = np.pad(g, 1, constant_values=np.nan)
    steps = np.zeros(g.shape, dtype=bool)
    offsets = [(0, 1), (0, -1), (1, 0), (-1, 0)]
    if connectivity == 8:
        offsets += [(1, 1), (1, -1), (-1, 1), (-1, -1)]
    with np.errstate(invalid="ignore"):
        for dy, dx in offsets:  # NaN compares False: unknown pixels make no step
            steps |= np.abs(pad[1 + dy: 1 + dy + h, 1 + dx: 1 + dx + w] - g) > step
    if radius == 0:
        return steps
    return maximum_filter(steps, size=2 * radius + 1, mode="constant", cval=False)


def near_steps(rows: ArrayLike, x: ArrayLike, mask: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Per edge point, whether its nearest pixel ``(row, round(x))`` is in ``mask``.

    >>> m = np.zeros((2, 5), dtype=bool); m[1, 3] = True
    >>> near_steps([1, 1, 0], [2.6, 2.4, 3.0], m).tolist()
    [True, False, False]
    """
    m = np.asarray(mask, dtype=bool)
    h, w = m.shape
    r = np.clip(np.asarray(rows, dtype=np.intp), 0, h - 1)
    c = np.clip(np.rint(np.asarray(x, dtype=float)).astype(np.intp), 0, w - 1)
    return m[r, c]


def expected_calibration_error(
    confidence: ArrayLike, correct: ArrayLike, *, bins: int = 10
) -> float:
    """Expected calibration error of a confidence: the count-weighted mean, over
    ``bins`` equal-width bins of ``[0, 1]``, of ``|mean confidence - fraction right|``.

    Parameters
    ----------
    confidence : array_like, shape (N,)
        Probability of being right given to each match, in ``[0, 1]``.
    correct : array_like of bool, shape (N,)
        Whether each match is right (by a rule).
    bins : int
        Number of bins (10).

    Returns
    -------
    float
        NaN when there are no matches.

    References
    ----------
    .. [1] M. P. Naeini, G. Cooper, M. Hauskrecht, "Obtaining well calibrated
       probabilities using Bayesian binning", AAAI (2015), eq. (3) (ECE).

    Examples
    --------
    Right 3 times in 4 at confidence 0.75 is calibrated; always sure, half right is not:

    >>> expected_calibration_error([0.75] * 4, [True, True, True, False])
    0.0
    >>> expected_calibration_error([1.0] * 4, [True, False, True, False])
    0.5
    """
    c = np.asarray(confidence, dtype=float)
    ok = np.asarray(correct, dtype=bool)
    if c.shape != ok.shape or c.ndim != 1:
        raise InputError(f"confidence and correct must be 1-D of one length, got "
                         f"{c.shape}, {ok.shape}")
    bins = require_int("bins", bins, minimum=1)
    if c.size == 0:
        return float("nan")
    if not (np.isfinite(c).all() and (c >= 0).all() and (c <= 1).all()):
        raise InputError("confidence must be finite numbers in 0..1")
    mean_c, frac, n = calibration_table(c, ok, bins=bins)
    full = n > 0
    return float(np.sum(n[full] * np.abs(mean_c[full] - frac[full])) / n.sum())
