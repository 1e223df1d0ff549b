"""The whole matcher of seed chapter 3: from a rectified pair to matched edge points.

:func:`match_stereo` runs the stages in order and keeps each one's output for
inspection: edge points of both images with their features (3.1-3.2), candidate
pairs with similarity indices (3.2-3.3, 3.5), probabilities after every relaxation
iteration (3.4), the accepted matches and, given a :class:`StereoCamera`, their 3-D
points and depth bounds (3.6-3.7).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.edges import EdgeSet, detect_edges, to_grey
from robostereo.errors import (
    InputError,
    require_finite,
    require_int,
    require_positive,
    require_range,
)
from robostereo.matching import (
    Candidates,
    SimilarityWeights,
    assign_matches,
    find_candidates,
    initial_probabilities,
)
from robostereo.relaxation import RelaxationParameters, RelaxationResult, relax
from robostereo.triangulation import StereoCamera, triangulate

__all__ = ["MatchParameters", "MatchResult", "match_stereo", "searched_range"]


@dataclass(frozen=True)
class MatchParameters:
    """Tuning of :func:`match_stereo`.  Defaults: robostereo's; :meth:`seed`: the seed's.

    Attributes
    ----------
    threshold : float
        Least gradient magnitude of a left edge point (0..127 grey scale; seed 8.0).
    right_threshold_ratio : float
        Right-image edge points need ``threshold * right_threshold_ratio``: a left
        edge's true partner just under the threshold stays a candidate (default
        0.75; the seed: 1).
    row_step : int
        Spacing of the epipolar lines used, in rows.
    subpixel : bool
        Sub-pixel edge positions (the seed: whole pixels).
    weights : SimilarityWeights
        Weights of GI, PI, AI in ``w`` (seed: 1/3 each).
    profile_scale : float or None
        Edge-profile factor of ``w`` (see :func:`~robostereo.matching.find_candidates`);
        None for the seed's ``w``.
    relaxation : RelaxationParameters
        Iterations (5) and coefficients of the relaxation; the no-match label's
        support is 0.6 (1.0 in the seed's mode).
    min_probability : float
        Least probability of an accepted match (0.7; the seed's mode 0.5).
    bit_depth : int or None
        Bit depth of the input grey levels; None: from the dtype.
    """

    threshold: float = 8.0
    right_threshold_ratio: float = 0.75
    row_step: int = 1
    subpixel: bool = True
    weights: SimilarityWeights = field(default_factory=SimilarityWeights)
    profile_scale: float | None = 10.0
    relaxation: RelaxationParameters = field(
        default_factory=lambda: RelaxationParameters(no_match_support=0.6)
    )
    min_probability: float = 0.7
    bit_depth: int | None = None

    def __post_init__(self) -> None:
        require_positive("threshold", self.threshold)
        require_positive("right_threshold_ratio", self.right_threshold_ratio)
        require_finite("min_probability", self.min_probability)
        if not 0.0 <= self.min_probability <= 1.0:
            raise InputError(f"min_probability must be in 0..1, got {self.min_probability}")
        require_int("row_step", self.row_step, minimum=1)
        if self.bit_depth is not None:
            require_int("bit_depth", self.bit_depth, minimum=1)
        if self.profile_scale is not None:
            require_positive("profile_scale", self.profile_scale)
        if not isinstance(self.subpixel, bool):
            raise InputError(f"subpixel must be True or False, got {self.subpixel!r}")
        if not isinstance(self.weights, SimilarityWeights):
            raise TypeError(f"weights must be a SimilarityWeights, got "
                            f"{type(self.weights).__name__}")
        if not isinstance(self.relaxation, RelaxationParameters):
            raise TypeError(f"relaxation must be a RelaxationParameters, got "
                            f"{type(self.relaxation).__name__}")

    @classmethod
    def seed(cls, **changes: object) -> MatchParameters:
        """The seed's matcher: whole-pixel edges, its ``w``, one threshold.

        >>> p = MatchParameters.seed()
        >>> p.subpixel, p.profile_scale, p.right_threshold_ratio
        (False, None, 1.0)
        """
        base = cls(
            right_threshold_ratio=1.0, subpixel=False, profile_scale=None,
            relaxation=RelaxationParameters(no_match_support=1.0), min_probability=0.5,
        )
        return replace(base, **changes)  # type: ignore[arg-type]


@dataclass(frozen=True)
class MatchResult:
    """Everything :func:`match_stereo` found, stage by stage.

    Attributes
    ----------
    left_edges, right_edges : EdgeSet
        Edge points and features of the two images (seed 3.1-3.2).
    candidates : Candidates
        Candidate pairs with GI, PI, AI and ``w`` (3.2-3.3).
    relaxation : RelaxationResult
        Probabilities after each iteration (3.4).
    match : ndarray of int, shape (N_left,)
        Index into ``candidates`` of each left edge's accepted match, -1 if none.
    camera : StereoCamera or None
        Geometry used for 3-D points.
    image_shape : tuple of int
        ``(H, W)``.
    disparity_range : tuple of float
    parameters : MatchParameters
    timings : dict
        Seconds spent per stage.
    """

    left_edges: EdgeSet
    right_edges: EdgeSet
    candidates: Candidates
    relaxation: RelaxationResult
    match: NDArray[np.intp]
    camera: StereoCamera | None
    image_shape: tuple[int, int]
    disparity_range: tuple[float, float]
    parameters: MatchParameters
    timings: dict[str, float]

    # -- per matched point -------------------------------------------------------
    @property
    def matched(self) -> NDArray[np.intp]:
        """Indices of the matched left edge points, shape ``(K,)``."""
        return np.nonzero(self.match >= 0)[0]

    def __len__(self) -> int:
        return int(np.count_nonzero(self.match >= 0))

    @property
    def rows(self) -> NDArray[np.intp]:
        return self.left_edges.row[self.matched]

    @property
    def x_left(self) -> NDArray[np.float64]:
        return self.left_edges.x[self.matched]

    @property
    def x_right(self) -> NDArray[np.float64]:
        return self.right_edges.x[self.candidates.right[self.match[self.matched]]]

    @property
    def disparity(self) -> NDArray[np.float64]:
        return self.candidates.disparity[self.match[self.matched]]

    @property
    def probability(self) -> NDArray[np.float64]:
        return self.relaxation.probability[self.match[self.matched]]

    def triangulated(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """3-D points ``(K, 3)`` in the epipolar frame (mm) and depth bounds ``(K,)``.

        Raises :class:`~robostereo.errors.InputError` without a camera.
        """
        if self.camera is None:
            raise InputError("3-D points need a camera (focal length, pixel pitch, baseline)")
        return triangulate(self.camera, self.x_left, self.x_right, self.rows, self.image_shape)

    def table(self) -> dict[str, NDArray]:
        """Matched points as columns: row, x_left, x_right, disparity, probability and,
        with a camera, X, Y, Z, z_bound."""
        cols: dict[str, NDArray] = {
            "row": self.rows, "x_left": self.x_left, "x_right": self.x_right,
            "disparity": self.disparity, "probability": self.probability,
        }
        if self.camera is not None:
            xyz, zb = self.triangulated()
            cols.update(X=xyz[:, 0], Y=xyz[:, 1], Z=xyz[:, 2], z_bound=zb)
        return cols

    def edge_table(self) -> dict[str, NDArray]:
        """Every left edge point with its features and its match (NaN where none)."""
        e = self.left_edges
        has = self.match >= 0
        m = self.match[has]
        x_right, disparity, probability = (np.full(len(e), np.nan) for _ in range(3))
        x_right[has] = self.right_edges.x[self.candidates.right[m]]
        disparity[has] = self.candidates.disparity[m]
        probability[has] = self.relaxation.probability[m]
        return {
            "row": e.row, "x": e.x, "sign": e.sign, "magnitude": e.magnitude,
            "pattern": e.pattern, "mean_grey": e.mean_grey, "x_right": x_right,
            "disparity": disparity, "probability": probability,
        }

    def matches_after(self, iteration: int) -> NDArray[np.intp]:
        """The matches accepted from the probabilities after ``iteration`` iterations.

        Returns an array like :attr:`match` (the seed's figure 4-4 shows these after
        0, 1, 3 and 5 iterations); beyond the iterations run, the final matches.
        Raises :class:`~robostereo.errors.InputError` unless ``iteration`` is an
        integer >= 0.
        """
        k = min(require_int("iteration", iteration, minimum=0),
                len(self.relaxation.history) - 1)
        return assign_matches(
            self.candidates, self.relaxation.history[k], self.relaxation.none_history[k],
            len(self.left_edges), min_probability=self.parameters.min_probability,
        )

    def disparity_of(self, match: NDArray[np.intp]) -> NDArray[np.float64]:
        """Disparity per left edge point for a match array, NaN where unmatched."""
        m = np.asarray(match)
        if m.shape != self.match.shape or m.dtype.kind not in "iu" or (
                m.size and not -1 <= m.min() <= m.max() < len(self.candidates)):
            raise InputError(f"match must be an array like MatchResult.match "
                             f"({self.match.shape[0]} candidate indices or -1)")
        out = np.full(m.shape, np.nan)
        out[m >= 0] = self.candidates.disparity[m[m >= 0]]
        return out


def _check_pair(left: ArrayLike, right: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    a, b = np.asarray(left), np.asarray(right)
    for name, im in (("left image", a), ("right image", b)):
        if im.ndim not in (2, 3):
            raise InputError(f"{name} must be a grey (H, W) or colour (H, W, 3|4) image, "
                             f"got shape {im.shape}")
    if a.size == 0 or b.size == 0:
        raise InputError("images must not be empty")
    if a.shape[:2] != b.shape[:2]:
        raise InputError(
            f"left and right images differ in size: {a.shape[1]} x {a.shape[0]} and "
            f"{b.shape[1]} x {b.shape[0]} pixels"
        )
    return a, b


def searched_range(disparity_range: tuple[float, float], width: int) -> tuple[float, float]:
    """The part of `disparity_range` that an image `width` pixels wide can hold.

    No pair of pixels is more than ``width - 1`` apart, so the search is limited to
    ``-(width - 1) .. width - 1``; a range entirely outside it is refused.

    >>> searched_range((0, 1000), 200)
    (0.0, 199.0)
    >>> searched_range((300, 400), 200)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: disparity_range 300.0 .. 400.0 lies outside -199 .. 199, ...
    """
    lo, hi = require_range("disparity_range", disparity_range)
    m = float(width - 1)
    if hi < -m or lo > m:
        raise InputError(f"disparity_range {lo} .. {hi} lies outside {-m:g} .. {m:g}, the "
                         f"disparities of an image {width} pixels wide")
    return max(lo, -m), min(hi, m)


def match_stereo(
    left: ArrayLike,
    right: ArrayLike,
    disparity_range: tuple[float, float],
    *,
    params: MatchParameters | None = None,
    camera: StereoCamera | None = None,
    valid_left: ArrayLike | None = None,
    valid_right: ArrayLike | None = None,
    progress: Callable[[str], None] | None = None,
) -> MatchResult:
    """Match the edge points of a rectified stereo pair (seed chapter 3).

    Parameters
    ----------
    left, right : array_like, shape (H, W) or (H, W, 3|4)
        Rectified images (epipolar lines are rows), grey or colour, 8 or 16 bit.
    disparity_range : tuple of float
        ``(min, max)`` of ``x_left - x_right`` in pixels: the matchable region (3.5).
        The search is limited to ``-(W - 1) .. W - 1`` (:func:`searched_range`); the
        result's ``disparity_range`` is the range searched.
    params : MatchParameters, optional
    camera : StereoCamera, optional
        With a camera the result also holds 3-D points and depth bounds.
    valid_left, valid_right : array_like of bool, shape (H, W), optional
        Pixels that hold image data, e.g. the part of a rectified image that has a
        source; edge points whose features would see other pixels are not used
        (:func:`~robostereo.edges.usable_pixels`), so the fill of a rectification
        makes no false edges.
    progress : callable, optional
        Called with the name of each stage as it starts.

    Returns
    -------
    MatchResult

    Raises
    ------
    InputError
        Images that are not (H, W) or (H, W, 3|4) real-valued arrays of one size, a
        float image outside 0..1 without ``params.bit_depth`` (see
        :func:`~robostereo.edges.to_grey`), NaN grey levels, a malformed or empty
        `disparity_range` or one outside the image's (one line naming the parameter).
    TypeError
        `params` or `camera` of the wrong type.

    Notes
    -----
    1. Edge points and features in both images (:func:`~robostereo.edges.detect_edges`).
    2. Candidates, similarity indices and ``w`` (:func:`~robostereo.matching.find_candidates`).
    3. Initial probabilities, eq. (1)-(3).
    4. Relaxation, eq. (4)-(5) (:func:`~robostereo.relaxation.relax`).
    5. Acceptance: one match per left and per right edge point
       (:func:`~robostereo.matching.assign_matches`).

    A pair with no edge points gives an empty result, not an error.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> row = np.repeat(rng.integers(0, 2, 40) * 200, 6)[:200].astype(np.uint8)
    >>> left = np.tile(row, (20, 1)); right = np.roll(left, -7, axis=1)
    >>> res = match_stereo(left, right, (0, 12))
    >>> len(res) > 0, set(np.round(res.disparity).tolist())
    (True, {7.0})
    """
    if params is not None and not isinstance(params, MatchParameters):
        raise TypeError(f"params must be a MatchParameters, got {type(params).__name__}")
    if camera is not None and not isinstance(camera, StereoCamera):
        raise TypeError(f"camera must be a StereoCamera, got {type(camera).__name__}")
    p = params or MatchParameters()
    a, b = _check_pair(left, right)
    lo, hi = searched_range(disparity_range, int(a.shape[1]))
    say = progress or (lambda _stage: None)
    t: dict[str, float] = {}
    t0 = time.perf_counter()
    say("edges")
    ga = to_grey(a, bit_depth=p.bit_depth, name="left image")
    gb = to_grey(b, bit_depth=p.bit_depth, name="right image")
    el = detect_edges(a, threshold=p.threshold, row_step=p.row_step, subpixel=p.subpixel,
                      grey=ga, valid=valid_left)
    er = detect_edges(b, threshold=p.threshold * p.right_threshold_ratio, row_step=p.row_step,
                      subpixel=p.subpixel, grey=gb, valid=valid_right)
    t1 = time.perf_counter()
    t["edges"] = t1 - t0
    say("candidates")
    cands = find_candidates(el, er, (float(lo), float(hi)), weights=p.weights,
                            profile_scale=p.profile_scale)
    p0, p0_none = initial_probabilities(cands)
    t2 = time.perf_counter()
    t["candidates"] = t2 - t1
    say("relaxation")
    rel = relax(el, er, cands, p0, p0_none, params=p.relaxation)
    match = assign_matches(cands, rel.probability, rel.no_match, len(el),
                           min_probability=p.min_probability)
    t["relaxation"] = time.perf_counter() - t2
    t["total"] = time.perf_counter() - t0
    return MatchResult(
        left_edges=el, right_edges=er, candidates=cands, relaxation=rel, match=match,
        camera=camera, image_shape=(int(a.shape[0]), int(a.shape[1])),
        disparity_range=(float(lo), float(hi)), parameters=p, timings=t,
    )
