"""Tuning of the matcher: :class:`MatchParameters`, the options of
:func:`~robostereo.matcher.pipeline.match_stereo` (thesis chapter 3 and robostereo's
window method), validated when made.

>>> MatchParameters().acceptance == DEFAULT_MIN_CONFIDENCE["window"]
True
>>> MatchParameters(gradient_truncation=400)
Traceback (most recent call last):
...
robostereo.errors.InputError: gradient_truncation must be in 0..300, got 400
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace

from robostereo.errors import (
    InputError,
    require_finite,
    require_int,
    require_positive,
)
from robostereo.matcher.candidates import SimilarityWeights
from robostereo.matcher.edges import check_edge_blur
from robostereo.matcher.relaxation import RelaxationParameters

__all__ = ["DEFAULT_MIN_CONFIDENCE", "METHODS", "MatchParameters"]

#: the matchers of :func:`~robostereo.matcher.pipeline.match_stereo`
METHODS = ("window", "relaxation")

#: least confidence of an accepted match, per method (see :class:`MatchParameters`)
DEFAULT_MIN_CONFIDENCE = {"window": 20 / 21, "relaxation": 0.7}
"""Window method: a match is accepted when it is at least 20 / 21 = 95.2 % likely right,
the decision that weighs one false match as 20 missed ones.  Chosen held out as the
lowest threshold at which every other developer scene is at most 1 % false by the
silhouette rule (``benchmarks/fit_confidence.py --rule silhouette``), it would be
0.905-0.952 (0.91 on all six), but below 20 / 21 a mis-posed capture's chance pairings
pass too (8 % of its edge points at 0.91 against 3.6 % here) and the plausibility
warning of :func:`robostereo.robot.capture.locate_pair.locate` no longer fires.  Relaxation: the
probability above which robostereo's relaxation accepts (the thesis's mode: 0.5)."""


@dataclass(frozen=True)
class MatchParameters:
    """Tuning of :func:`~robostereo.matcher.pipeline.match_stereo`.  Defaults:
    robostereo's; :meth:`thesis`: the thesis's.

    Attributes
    ----------
    method : str
        ``"window"`` (default): every disparity of the range scored at each left edge
        point by side-aware census windows, with a left-right check and a calibrated
        confidence (:func:`robostereo.matcher.window_match.window_match`).  ``"relaxation"``: the
        thesis's matcher, right edge points as candidates, relaxation on edge
        connectivity (3.2-3.5).
    threshold : float
        Least gradient magnitude of a left edge point (0..127 grey scale; thesis 8.0).
    right_threshold_ratio : float
        Right-image edge points need ``threshold * right_threshold_ratio``: a left
        edge's true partner just under the threshold stays a candidate (default
        0.75; the thesis: 1).
    row_step : int
        Spacing of the epipolar lines used, in rows.
    subpixel : bool
        Sub-pixel edge positions (the thesis: whole pixels).
    weights : SimilarityWeights
        Weights of GI, PI, AI in ``w`` (thesis: 1/3 each).
    profile_scale : float or None
        Edge-profile factor of ``w`` (see :func:`~robostereo.matcher.candidates.find_candidates`);
        None for the thesis's ``w``.
    relaxation : RelaxationParameters
        Iterations (5) and coefficients of the relaxation; the no-match label's
        support is 0.6 (1.0 in the thesis's mode).  Used by the relaxation method.
    min_confidence : float or None
        Least confidence (window method: calibrated ``P(correct)``; relaxation: the
        match probability) of an accepted match; None: the method's default,
        :data:`DEFAULT_MIN_CONFIDENCE` (the thesis's mode 0.5).  Lower it for more
        matches, raise it for fewer false ones.
    gradient_truncation : int
        Window method: largest gradient difference per pixel pair (0..300).
    paths : bool
        Window method: also aggregate the window costs along the rows (two paths of
        semi-global matching, :func:`robostereo.matcher.window_costs.window_costs`), which carries
        the disparity of textured parts into repeated patterns and weak texture.
        False: a tenth to a quarter faster, worse there; the confidence is then conservative
        (its calibration was fitted with the paths).
    coarse : bool
        Window method: a range of more than 64 whole disparities is first narrowed
        to the part the scene holds by a pass at half size
        (:func:`robostereo.matcher.window_costs.coarse_range`), so a generous range costs little
        more than a tight one.  False: the whole range is searched.
    bit_depth : int or None
        Bit depth of the input grey levels; None: from the dtype.
    contour : bool
        Window method: also accept a match of confidence at least 0.80 when at least
        half of the places 8 lines up and down its edge contour hold a match of its
        disparity (within 1 px) accepted on its own: the thesis's figural continuity
        (3.4; :func:`robostereo.matcher.window_match.contour_accepted`).  The
        confidences are unchanged.  Off by default: on the six developer scenes it
        raises coverage near depth steps by 0.6-4.0 points and away by 0.4-2.9, 271
        more matches of which 5 are false by the silhouette rule (4 on motorcycle,
        whose default point goes from 0.58 to 0.63 % false).
    edge_blur_px : float or None
        Sub-pixel edge positions (both images) moved towards the gradient's peak on the
        grey levels blurred by a Gaussian of this sigma (pixels), beyond a dead zone of
        :data:`~robostereo.matcher.edge_kernels.FINE_DEAD_ZONE_PX`; the edge points are
        still found on the thesis's 5 x 5 smoothed image (see
        :func:`~robostereo.matcher.edges.detect_edges`).  None: the smoothed image's
        positions.  The 5 x 5 filter lets texture within about 2 px pull an edge's peak;
        at an outline the texture behind differs between the views, so the pull moves
        the outline and does not cancel in the disparity.  The default 0.85 (with the
        0.05 px dead zone) was chosen leave-one-scene-out over the synthetic occluder
        pairs (seeds 0-7, one scene) and the six developer scenes among None, 0-1.5
        without a dead zone and 0.5-1.0 with one of 0.05 or 0.1 px: of those that left
        the simulated robot's block (the demo) as it was, the one with the least mean
        ratio of the silhouette edges' median offset from the boundary to today's, with
        the disparity RMS away from steps at most 3 % above today's on every other
        scene; it won every fold.  On the occluder pairs the matched silhouette edges'
        median offset fell from 0.28 to 0.22 px (see ``docs/guide/development-log.md``).
    photometric : bool
        Window method: where the two views' grey levels at the accepted matches differ
        by more than noise (a gain, offset, exposure or gamma change), match again with
        the right view's mapped to the left's (:mod:`~robostereo.matcher.photometric`).
        A 30 % gain costs the developer scenes 4-22 points of coverage without it.
    rows_check : bool
        Window method: measure how far the rows of the two views disagree at the accepted
        matches (:func:`~robostereo.matcher.alignment.row_offset`); beyond
        :data:`~robostereo.matcher.alignment.ROW_TOLERANCE_PX` warn
        (:class:`~robostereo.errors.PlausibilityWarning`) and match again with the right
        view moved.  A 1 px offset takes the developer scenes to 1.0-6.5 % false without it.
    """

    method: str = "window"
    threshold: float = 8.0
    right_threshold_ratio: float = 0.75
    row_step: int = 1
    subpixel: bool = True
    weights: SimilarityWeights = field(default_factory=SimilarityWeights)
    profile_scale: float | None = 10.0
    relaxation: RelaxationParameters = field(
        default_factory=lambda: RelaxationParameters(no_match_support=0.6)
    )
    min_confidence: float | None = None
    gradient_truncation: int = 64
    paths: bool = True
    coarse: bool = True
    bit_depth: int | None = None
    contour: bool = False
    edge_blur_px: float | None = 0.85
    photometric: bool = True
    rows_check: bool = True

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise InputError(f"method must be one of {', '.join(METHODS)}, got {self.method!r}")
        require_positive("threshold", self.threshold)
        require_positive("right_threshold_ratio", self.right_threshold_ratio)
        if self.min_confidence is not None:
            require_finite("min_confidence", self.min_confidence)
            if not 0.0 <= self.min_confidence <= 1.0:
                raise InputError(f"min_confidence must be in 0..1, got {self.min_confidence}")
        require_int("row_step", self.row_step, minimum=1)
        require_int("gradient_truncation", self.gradient_truncation, minimum=0)
        for name in ("paths", "coarse", "contour", "photometric", "rows_check"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(f"{name} must be True or False, got {getattr(self, name)!r}")
        if self.gradient_truncation > 300:
            raise InputError(f"gradient_truncation must be in 0..300, got "
                             f"{self.gradient_truncation}")
        if self.bit_depth is not None:
            require_int("bit_depth", self.bit_depth, minimum=1)
        check_edge_blur(self.edge_blur_px)
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

    @property
    def acceptance(self) -> float:
        """The least confidence of an accepted match in force (see ``min_confidence``)."""
        if self.min_confidence is not None:
            return float(self.min_confidence)
        return DEFAULT_MIN_CONFIDENCE[self.method]

    @classmethod
    def thesis(cls, **changes: object) -> MatchParameters:
        """The thesis's matcher: relaxation, whole-pixel edges, its ``w``, one threshold.

        >>> p = MatchParameters.thesis()
        >>> p.method, p.subpixel, p.profile_scale, p.right_threshold_ratio, p.acceptance
        ('relaxation', False, None, 1.0, 0.5)
        """
        base = cls(
            method="relaxation", right_threshold_ratio=1.0, subpixel=False, profile_scale=None,
            relaxation=RelaxationParameters(no_match_support=1.0), min_confidence=0.5,
            edge_blur_px=None, photometric=False, rows_check=False,
        )
        return replace(base, **changes)  # type: ignore[arg-type]

    @classmethod
    def seed(cls, **changes: object) -> MatchParameters:
        """Deprecated name of :meth:`thesis` (it clashes with random seeds); goes in the
        next release."""
        warnings.warn("MatchParameters.seed() is deprecated, use MatchParameters.thesis()",
                      DeprecationWarning, stacklevel=2)
        return cls.thesis(**changes)
