"""The whole matcher of thesis chapter 3: from a rectified pair to matched edge points.

:func:`match_stereo` runs the stages in order and keeps each one's output for
inspection: edge points of both images with their features (3.1-3.2), candidate
pairs with similarity indices (3.2-3.3, 3.5), probabilities after every relaxation
iteration (3.4), the accepted matches and, given a :class:`StereoCamera`, their 3-D
points and depth bounds (3.6-3.7).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import (
    InputError,
    require_finite,
    require_int,
    require_range,
    warn_input,
)
from robostereo.geometry.triangulation import StereoCamera, triangulate
from robostereo.matcher.alignment import RowOffset, moved_rows, row_offset
from robostereo.matcher.candidates import (
    Candidates,
    assign_matches,
)
from robostereo.matcher.edge_features import EdgeSet
from robostereo.matcher.grey_levels import to_grey
from robostereo.matcher.parameters import (  # noqa: F401  (kept importable from here)
    DEFAULT_MIN_CONFIDENCE,
    METHODS,
    MatchParameters,
)
from robostereo.matcher.photometric import GreyMap, grey_correction
from robostereo.matcher.relaxation import RelaxationResult
from robostereo.matcher.stages import match_once
from robostereo.matcher.window_match import (
    WindowMatch,
    contour_accepted,
)

__all__ = [
    "PARABOLA_DISPARITY_UNCERTAINTY_PX",
    "MatchResult",
    "match_stereo",
    "searched_range",
    "warm_up",
]


#: ``d(disp)`` (pixels) of a match whose sub-pixel disparity is the vertex of the window
#: costs' parabola rather than a right edge point's position: on the synthetic pairs with
#: exact ground truth (tests/synthetic.py, 6 + 6 pairs) their correct matches were at most
#: 0.68 px off (95 % within 0.61), against 0.12 px (99 %) on a right edge point
PARABOLA_DISPARITY_UNCERTAINTY_PX = 0.75

def _window_accepted(params: MatchParameters, left: EdgeSet, disparity: NDArray[np.float64],
                     confidence: NDArray[np.float64], level: float) -> NDArray[np.bool_]:
    """The window method's acceptance at confidence `level`, ``(N,)`` bool: with the
    edge contour's support where ``params.contour``
    (:func:`~robostereo.matcher.window_match.contour_accepted`), else the confidence
    alone (NaN: not accepted)."""
    if params.contour:
        return contour_accepted(left, disparity, confidence, level)
    return np.nan_to_num(confidence, nan=-1.0) >= level


@dataclass(frozen=True)
class MatchResult:
    """Everything :func:`match_stereo` found, stage by stage.

    Per left edge point (arrays of shape ``(N_left,)``) it holds the best match the
    method found, its confidence and whether it was accepted; the rest is what each
    stage left for inspection.

    Attributes
    ----------
    left_edges, right_edges : EdgeSet
        Edge points and features of the two images (thesis 3.1-3.2).
    edge_disparity : ndarray of float
        Disparity of each left edge point's best match, NaN where it has none.
    edge_confidence : ndarray of float
        Its confidence: the calibrated ``P(correct)`` (window method) or the
        relaxation's probability; NaN where there is no best match.  The no-match
        label has ``1 - confidence``.
    edge_right : ndarray of int
        Right edge point of the best match, -1 where it lands on none.
    accepted : ndarray of bool
        The best match is accepted (confidence at least ``parameters.acceptance``;
        the relaxation also gives each right edge point to one left edge point).
    window : WindowMatch or None
        Window method: costs, features and confidences.
    candidates : Candidates or None
        Relaxation method: candidate pairs with GI, PI, AI and ``w`` (3.2-3.3).
    relaxation : RelaxationResult or None
        Relaxation method: probabilities after each iteration (3.4).
    match : ndarray of int or None
        Relaxation method: index into ``candidates`` of each left edge's accepted
        match, -1 if none.
    camera : StereoCamera or None
        Geometry used for 3-D points.
    image_shape : tuple of int
        ``(H, W)``.
    disparity_range : tuple of float
    parameters : MatchParameters
    timings : dict
        Seconds spent per stage.
    grey_map : GreyMap or None
        Where ``parameters.photometric`` found the views' grey levels to differ: the map
        of the right view's to the left's with which this (second) match was made
        (:mod:`~robostereo.matcher.photometric`); None where they agreed (one match).
    row_offset : RowOffset or None
        With ``parameters.rows_check``: the rows' offset at the first match's accepted
        matches; where ``row_offset.misaligned`` the right view was moved by it and
        matched again.  None where the check was off or could not track enough places.
    """

    left_edges: EdgeSet
    right_edges: EdgeSet
    edge_disparity: NDArray[np.float64]
    edge_confidence: NDArray[np.float64]
    edge_right: NDArray[np.intp]
    accepted: NDArray[np.bool_]
    window: WindowMatch | None
    candidates: Candidates | None
    relaxation: RelaxationResult | None
    match: NDArray[np.intp] | None
    camera: StereoCamera | None
    image_shape: tuple[int, int]
    disparity_range: tuple[float, float]
    parameters: MatchParameters
    timings: dict[str, float]
    grey_map: GreyMap | None = None
    row_offset: RowOffset | None = None

    # -- per matched point -------------------------------------------------------
    @property
    def matched(self) -> NDArray[np.intp]:
        """Indices of the matched left edge points, shape ``(K,)``."""
        return np.nonzero(self.accepted)[0]

    def __len__(self) -> int:
        return int(np.count_nonzero(self.accepted))

    @property
    def rows(self) -> NDArray[np.intp]:
        return self.left_edges.row[self.matched]

    @property
    def x_left(self) -> NDArray[np.float64]:
        return self.left_edges.x[self.matched]

    @property
    def x_right(self) -> NDArray[np.float64]:
        return self.x_left - self.disparity

    @property
    def disparity(self) -> NDArray[np.float64]:
        return self.edge_disparity[self.matched]

    @property
    def confidence(self) -> NDArray[np.float64]:
        """Confidence of each matched point, shape ``(K,)``."""
        return self.edge_confidence[self.matched]

    @property
    def probability(self) -> NDArray[np.float64]:
        """The match probability of each matched point: its confidence."""
        return self.confidence

    def accepted_disparity(self, min_confidence: float | None = None) -> NDArray[np.float64]:
        """Disparity per left edge point, NaN where not accepted.

        With ``min_confidence``, the acceptance is redone at that level from the best
        matches (window method, with the contour's support if ``parameters.contour``;
        for the relaxation, from its final probabilities).
        """
        if min_confidence is None:
            return np.where(self.accepted, self.edge_disparity, np.nan)
        require_finite("min_confidence", min_confidence)
        if not 0.0 <= min_confidence <= 1.0:
            raise InputError(f"min_confidence must be in 0..1, got {min_confidence}")
        if self.relaxation is not None and self.candidates is not None:
            m = assign_matches(self.candidates, self.relaxation.probability,
                               self.relaxation.no_match, len(self.left_edges),
                               min_probability=min_confidence)
            return self.disparity_of(m)
        ok = _window_accepted(self.parameters, self.left_edges, self.edge_disparity,
                             self.edge_confidence, min_confidence)
        return np.where(ok, self.edge_disparity, np.nan)

    def triangulated(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """3-D points ``(K, 3)`` in the epipolar frame (mm) and depth bounds ``(K,)``.

        Raises :class:`~robostereo.errors.InputError` without a camera.
        """
        if self.camera is None:
            raise InputError("3-D points need a camera (focal length, pixel pitch, baseline)")
        return triangulate(self.camera, self.x_left, self.x_right, self.rows, self.image_shape,
                           disparity_uncertainty_px=self.disparity_uncertainty_px)

    @property
    def disparity_uncertainty_px(self) -> NDArray[np.float64]:
        """``d(disp)`` of each matched point for eq. (9), shape ``(K,)``: the camera's
        (sub-pixel edge positions) where the match lands on a right edge point, at
        least :data:`PARABOLA_DISPARITY_UNCERTAINTY_PX` where its sub-pixel disparity is
        the vertex of a cost parabola (window method, no right edge point there).
        Raises :class:`~robostereo.errors.InputError` without a camera."""
        if self.camera is None:
            raise InputError("d(disp) needs a camera (its disparity_uncertainty_px)")
        base = self.camera.disparity_uncertainty_px
        on_edge = self.edge_right[self.matched] >= 0
        return np.where(on_edge, base, max(base, PARABOLA_DISPARITY_UNCERTAINTY_PX))

    def table(self) -> dict[str, NDArray]:
        """Matched points as columns: row, x_left, x_right, disparity, confidence and,
        with a camera, X, Y, Z, z_bound."""
        cols: dict[str, NDArray] = {
            "row": self.rows, "x_left": self.x_left, "x_right": self.x_right,
            "disparity": self.disparity, "confidence": self.confidence,
        }
        if self.camera is not None:
            xyz, zb = self.triangulated()
            cols.update(X=xyz[:, 0], Y=xyz[:, 1], Z=xyz[:, 2], z_bound=zb)
        return cols

    def edge_table(self) -> dict[str, NDArray]:
        """Every left edge point with its features, its best match and its confidence.

        ``x_right, disparity, confidence`` hold the best match wherever there is one
        (so that all of them, thresholded anywhere, give the whole coverage curve);
        ``accepted`` is 1 where it was accepted.
        """
        e = self.left_edges
        has = np.isfinite(self.edge_disparity)
        nan = np.full(len(e), np.nan)
        return {
            "row": e.row, "x": e.x, "sign": e.sign, "magnitude": e.magnitude,
            "pattern": e.pattern, "mean_grey": e.mean_grey,
            "x_right": np.where(has, e.x - self.edge_disparity, nan),
            "disparity": self.edge_disparity,
            "confidence": self.edge_confidence,
            "accepted": self.accepted.astype(np.int8),
        }

    def _relaxation_only(self, what: str) -> tuple[Candidates, RelaxationResult]:
        if self.candidates is None or self.relaxation is None:
            raise InputError(f"{what} needs the relaxation method (method='relaxation')")
        return self.candidates, self.relaxation

    def matches_after(self, iteration: int) -> NDArray[np.intp]:
        """The matches accepted from the probabilities after ``iteration`` iterations.

        Relaxation method only.  Returns an array like :attr:`match` (the thesis's
        figure 4-4 shows these after 0, 1, 3 and 5 iterations); beyond the iterations
        run, the final matches.  Raises :class:`~robostereo.errors.InputError` unless
        ``iteration`` is an integer >= 0.
        """
        cands, rel = self._relaxation_only("matches_after")
        k = min(require_int("iteration", iteration, minimum=0), len(rel.history) - 1)
        return assign_matches(
            cands, rel.history[k], rel.none_history[k],
            len(self.left_edges), min_probability=self.parameters.acceptance,
        )

    def disparity_of(self, match: NDArray[np.intp]) -> NDArray[np.float64]:
        """Disparity per left edge point for a relaxation match array, NaN where unmatched."""
        cands, _ = self._relaxation_only("disparity_of")
        m = np.asarray(match)
        assert self.match is not None
        if m.shape != self.match.shape or m.dtype.kind not in "iu" or (
                m.size and not -1 <= m.min() <= m.max() < len(cands)):
            raise InputError(f"match must be an array like MatchResult.match "
                             f"({self.match.shape[0]} candidate indices or -1)")
        out = np.full(m.shape, np.nan)
        out[m >= 0] = cands.disparity[m[m >= 0]]
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
    """Match the edge points of a rectified stereo pair (thesis chapter 3).

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
        (:func:`~robostereo.matcher.edges.usable_pixels`), so the fill of a rectification
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
        :func:`~robostereo.matcher.grey_levels.to_grey`), NaN grey levels, a malformed or empty
        `disparity_range` or one outside the image's (one line naming the parameter).
    TypeError
        `params` or `camera` of the wrong type.

    Notes
    -----
    1. Edge points and features in both images (:func:`~robostereo.matcher.edges.detect_edges`).

    Window method (default):

    2. Every whole-pixel disparity of the range scored at each left edge point with
       side-aware census + gradient windows, the left-right check, the window costs
       aggregated along the rows (two scanline paths; ``params.paths``), sub-pixel
       disparity from the right edge point there
       (:func:`~robostereo.matcher.window_match.window_match`).
    3. Confidence ``P(correct)`` from the evidence by the calibrated model
       (:mod:`~robostereo.matcher.confidence`); the no-match label wins below
       ``params.acceptance``.
    4. ``params.photometric``: where the views' grey levels at the accepted matches
       differ, steps 1-3 again with the right view's mapped to the left's.

    Relaxation method (the thesis's, ``MatchParameters.thesis()``):

    2. Candidates, similarity indices and ``w``
       (:func:`~robostereo.matcher.candidates.find_candidates`).
    3. Initial probabilities, eq. (1)-(3).
    4. Relaxation, eq. (4)-(5) (:func:`~robostereo.matcher.relaxation.relax`).
    5. Acceptance: one match per left and per right edge point
       (:func:`~robostereo.matcher.candidates.assign_matches`).

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

    def accept(e: EdgeSet, d: NDArray[np.float64], c: NDArray[np.float64]) -> NDArray[np.bool_]:
        return _window_accepted(p, e, d, c, p.acceptance)

    fields, el, er = match_once(a, b, lo, hi, p, valid_left, valid_right, say, t, None, accept)
    first_match = sum(t.values())  # its stages, the only ones timed so far

    # -- the rows: matched again with the right view moved where they disagree
    rows = None
    if p.method == "window" and p.rows_check:
        t2, acc = time.perf_counter(), fields["accepted"]
        rows = row_offset(a, b, el.row[acc], el.x[acc], fields["edge_disparity"][acc])
        t["rows_check"] = time.perf_counter() - t2
        if rows is not None and rows.misaligned:
            warn_input(f"the rows of the two views disagree by {rows.describe()} at "
                       f"{rows.n_places} matched places: not epipolar lines; matched again "
                       "with the right view moved (check the rectification, calibration or "
                       "poses)")
            say("rows disagree: matching again")
            move = (rows.offset_px, rows.tilt_px, rows.stretch_px)
            b = moved_rows(b, *move)
            if valid_right is not None:
                moved = moved_rows(np.asarray(valid_right, np.float32), *move)
                valid_right = moved >= 0.999  # every pixel it reads was valid
            del fields, el, er  # the first match is not held while the second is made
            fields, el, er = match_once(a, b, lo, hi, p, valid_left, valid_right, say, t,
                                        None, accept)
            t["first_match"] = first_match

    # -- the views' grey levels compared at the accepted matches; matched again with the
    #    right view's mapped where they differ
    grey_map = None
    if p.method == "window" and p.photometric:
        t2, acc = time.perf_counter(), fields["accepted"]
        grey_map = grey_correction(a, b, el.row[acc], el.x[acc], fields["edge_disparity"][acc],
                                   bit_depth=p.bit_depth)
        t["photometric"] = time.perf_counter() - t2
        if grey_map is not None:
            say("grey levels differ: matching again")
            del fields, el, er
            fields, el, er = match_once(a, b, lo, hi, p, valid_left, valid_right, say, t,
                                        grey_map, accept)
            t["first_match"] = first_match
    t["total"] = time.perf_counter() - t0
    return MatchResult(
        left_edges=el, right_edges=er, **fields,  # type: ignore[arg-type]
        camera=camera, image_shape=(int(a.shape[0]), int(a.shape[1])),
        disparity_range=(float(lo), float(hi)), parameters=p, timings=t, grey_map=grey_map,
        row_offset=rows,
    )


def warm_up() -> None:
    """Load (or compile) the numba kernels once, on a tiny pair, so that the first real
    match is timed like the others (``robostereo evaluate`` calls it)."""
    g = np.random.default_rng(0).integers(0, 255, (128, 96)).astype(np.uint8)
    match_stereo(g, np.roll(g, -2, axis=1), (0.0, 4.0))
    to_grey(np.dstack([g, g, g]))  # and the colour conversion (and its check)
