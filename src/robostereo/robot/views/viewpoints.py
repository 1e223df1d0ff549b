"""Captures of N views: one camera moved by the robot to N viewpoints.

The thesis grabs two views (4.2); a robot can grab more at almost no cost
(multiple-baseline stereo [1]_). A :class:`ViewsCapture` holds N >= 2 grabbed images
with the one camera and each view's camera pose ``T_world_camera`` (world mm), as the
robot reported them or as flange poses and a hand-eye transform. Any two of its views
make a two-view :class:`~robostereo.robot.capture.capture_folder.Capture`
(:meth:`ViewsCapture.pair`), so everything that works on a pair works on each pair of an
N-view capture, and a two-view capture is an N-view capture with N = 2
(:meth:`ViewsCapture.from_capture`).

Positions of N viewpoints in a pattern around a centre view come from
:func:`view_offsets` (multiple-baseline stereo [1]_).

References
----------
.. [1] M. Okutomi and T. Kanade, "A multiple-baseline stereo", IEEE PAMI 15(4), 1993.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_positive, shown
from robostereo.geometry.camera import Camera
from robostereo.geometry.plausibility import check_depth_disparities, check_uncertainties
from robostereo.geometry.poses import SE3, Pose, as_se3
from robostereo.robot.capture.capture_folder import DISPARITY_UNCERTAINTY_PX, Capture
from robostereo.robot.capture.capture_keys import default_focal_uncertainty_mm

__all__ = [
    "MAX_SPAN_MM",
    "PATTERNS",
    "ViewsCapture",
    "view_offsets",
]

Pattern = Literal["line", "cross", "arc"]

#: the viewpoint patterns of :func:`view_offsets`
PATTERNS: tuple[str, ...] = ("line", "cross", "arc")

MAX_SPAN_MM = 1e6
"""Longest span :func:`view_offsets` lays out, mm (a kilometre: beyond any robot's reach;
the command line's ``--span`` limit)."""


def view_offsets(pattern: Pattern, count: int, span_mm: float, *,
                 depth_mm: float | None = None) -> NDArray[np.float64]:
    """Optical-centre offsets of `count` viewpoints in a pattern, in the centre camera's frame.

    Parameters
    ----------
    pattern : {'line', 'cross', 'arc'}
        ``'line'``: evenly along the camera's x axis (the thesis's baseline direction),
        `span_mm` end to end; ``'cross'``: the centre view plus the others evenly on two
        arms along x and y, each arm `span_mm` end to end (odd `count` >= 5 keeps the
        cross symmetric); ``'arc'``: evenly along x on a circle about the point
        `depth_mm` ahead of the centre view, `span_mm` the chord, so every view keeps the
        object at the same distance (the views turn towards it: see Notes).
    count : int
        Number of views, 2..100.
    span_mm : float
        Distance between the outermost viewpoints, mm, > 0 and at most
        :data:`MAX_SPAN_MM`.
    depth_mm : float, optional
        ``'arc'`` only: distance of the centre of the circle from the centre view, mm.

    Returns
    -------
    ndarray, shape (count, 3)
        ``(x, y, z)`` offsets in mm in the centre camera's frame (x to the image's right,
        y down the image, z along the optical axis); rows ordered along the pattern.

    Raises
    ------
    InputError
        An unknown pattern; a count that is not a whole number in 2..100 (or under 3
        for a cross); a span that is not a finite number in (0, :data:`MAX_SPAN_MM`], or
        so short that two views fall on one point; an arc without `depth_mm` or whose
        span reaches its diameter.

    Notes
    -----
    For ``'arc'`` the view at offset ``o`` looks at the arc's centre ``(0, 0, depth_mm)``;
    its turn about the camera's y axis is ``atan2(-o_x, depth_mm - o_z)``.  Line and
    cross views keep the centre view's orientation (a pure translation, the thesis's
    motion, 2.2).

    Examples
    --------
    >>> view_offsets("line", 5, 80.0)[:, 0].tolist()
    [-40.0, -20.0, 0.0, 20.0, 40.0]
    >>> view_offsets("cross", 5, 80.0).round(1).tolist()
    [[0.0, 0.0, 0.0], [-40.0, 0.0, 0.0], [40.0, 0.0, 0.0], [0.0, -40.0, 0.0], [0.0, 40.0, 0.0]]
    """
    if pattern not in PATTERNS:
        raise InputError(f"pattern must be one of {', '.join(PATTERNS)}, got {pattern!r}")
    whole = isinstance(count, numbers.Integral) or (
        isinstance(count, float) and count.is_integer())
    if isinstance(count, bool) or not whole or not 2 <= count <= 100:
        raise InputError(f"count (the number of views) must be a whole number in 2..100, "
                         f"got {count!r}")
    count = int(count)
    require_positive("span_mm", span_mm)
    if span_mm > MAX_SPAN_MM:
        raise InputError(f"span_mm must be at most {MAX_SPAN_MM:g} mm, got {span_mm:g}")
    half = 0.5 * float(span_mm)
    out = np.zeros((count, 3))
    if pattern == "line":
        out[:, 0] = np.linspace(-half, half, count)
    elif pattern == "cross":
        if count < 3:
            raise InputError(f"a cross needs at least 3 views, got count = {count}")
        # the centre view first, then the others shared between the two arms
        rest = count - 1
        nx = (rest + 1) // 2
        ny = rest - nx
        xs = _arm(nx, half)
        ys = _arm(ny, half)
        out[1:1 + nx, 0] = xs
        out[1 + nx:, 1] = ys
    else:
        if depth_mm is None:
            raise InputError("pattern 'arc' needs depth_mm, the distance to the object")
        require_positive("depth_mm", depth_mm)
        if half >= depth_mm:
            raise InputError(f"span_mm {span_mm:g} is too long for an arc at depth_mm "
                             f"{depth_mm:g}: the chord must be shorter than the diameter")
        a = math.asin(half / depth_mm)
        ang = np.linspace(-a, a, count)
        out[:, 0] = depth_mm * np.sin(ang)
        out[:, 2] = depth_mm * (1.0 - np.cos(ang))
    gaps = np.abs(np.diff(out, axis=0)).max(axis=1)  # no squares: they underflow
    if not (gaps > 0).all():  # spans under floating point's reach: steps of zero
        raise InputError(f"span_mm {span_mm:g} is too short to put {count} views apart")
    return out


def _arm(n: int, half: float) -> NDArray[np.float64]:
    """`n` positions on an arm from -half to half, leaving out its centre (the centre view).

    Each side takes its views evenly out to `half`; an odd `n` puts one more on the + side.
    """
    plus = (n + 1) // 2
    minus = n - plus
    return np.concatenate([-half * np.arange(minus, 0, -1) / max(minus, 1),
                           half * np.arange(1, plus + 1) / max(plus, 1)])


@dataclass(frozen=True)
class ViewsCapture:
    """N grabbed views with the camera and the poses the robot reported.

    Attributes
    ----------
    images : tuple of ndarray, each shape (H, W) or (H, W, 3)
        Grabbed, unrectified images (grey levels as grabbed), all of the camera's size.
    camera : Camera
    poses : tuple of SE3
        Camera pose of each view (``T_world_camera``, world mm): SCARA
        :class:`~robostereo.geometry.poses.Pose` s or any :class:`SE3`.
    depth_range_mm : tuple of float
        ``(near, far)`` expected depth of the object in front of the cameras, mm (each
        pair of views has its own disparity range, so N views take a depth range).
    bit_depth : int
        Significant bits of the grey levels (7 for the thesis's camera).
    baseline_uncertainty_mm, focal_length_uncertainty_mm, disparity_uncertainty_px : float
        ``dD`` (mm), ``ds`` (mm) and ``d(disp)`` (px) of eq. (9), for every pair of
        views; ``ds`` defaults to 0.01 mm for a physical camera and 0 for one in
        pixels (``d(fx) / fx`` over its nominal 1 mm lens).
    rotation_uncertainty_deg : float
        How far each view's orientation may be off, degrees (as
        :class:`~robostereo.robot.capture.capture_folder.Capture`'s; default 0).
    hand_eye_uncertainty_deg : float
        How far the hand-eye's rotation may be off, degrees (as ``Capture``'s).
    names : tuple of str or None
        File name of each view's image in a capture folder (e.g. ``view_00.png``).
    notes : mapping
        Free-form ``robot`` and ``scene`` notes (written, never read).
    flanges, hand_eye : tuple of SE3, SE3 or None
        Where the poses came from, when they came from the robot's flange poses and a
        hand-eye transform (``pose = flange @ hand_eye``).

    Examples
    --------
    >>> from robostereo.geometry.camera import SEED_CAMERA
    >>> from robostereo.geometry.poses import se3_from_scara
    >>> w, h = SEED_CAMERA.image_size
    >>> images = tuple(np.zeros((h, w), np.uint8) for _ in range(3))
    >>> poses = tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20.0, 0.0, 20.0))
    >>> cap = ViewsCapture(images, SEED_CAMERA, poses, depth_range_mm=(900.0, 1100.0))
    >>> len(cap), round(cap.span_mm, 1)
    (3, 40.0)
    >>> cap.pair(0, 2).pose_right.x
    20.0
    """

    images: tuple[NDArray[Any], ...]
    camera: Camera
    poses: tuple[Pose | SE3, ...]
    depth_range_mm: tuple[float, float]
    bit_depth: int = 7
    baseline_uncertainty_mm: float = 0.01
    focal_length_uncertainty_mm: float = None  # type: ignore[assignment]
    disparity_uncertainty_px: float = DISPARITY_UNCERTAINTY_PX
    rotation_uncertainty_deg: float = 0.0
    hand_eye_uncertainty_deg: float = 0.0
    names: tuple[str, ...] | None = None
    notes: Mapping[str, Any] = field(default_factory=dict)
    flanges: tuple[SE3, ...] | None = None
    hand_eye: SE3 | None = None

    @classmethod
    def from_flange(cls, images: Sequence[NDArray[Any]], camera: Camera, *,
                    flanges: Sequence[SE3], hand_eye: SE3, **kwargs: Any) -> ViewsCapture:
        """A capture whose camera poses are ``flange @ hand_eye`` (eye-in-hand).

        Parameters
        ----------
        images : sequence of ndarray, each shape (H, W) or (H, W, 3)
            The N grabbed images, as for the class.
        camera : Camera
        flanges : sequence of SE3
            The robot's flange pose of each view (``T_world_flange``, world mm).
        hand_eye : SE3
            The camera in the flange's frame (``T_flange_camera``, mm).
        **kwargs
            The other attributes of the class (``depth_range_mm`` is required).
        """
        if not isinstance(hand_eye, SE3):
            raise InputError(f"hand_eye must be an SE3, got {type(hand_eye).__name__}")
        flanges = tuple(flanges)
        for k, f in enumerate(flanges):
            if not isinstance(f, SE3):
                raise InputError(f"flange of view {k} must be an SE3, got {type(f).__name__}")
        return cls(tuple(images), camera, tuple(f @ hand_eye for f in flanges),
                   flanges=flanges, hand_eye=hand_eye, **kwargs)

    @classmethod
    def from_capture(cls, capture: Capture) -> ViewsCapture:
        """The two views of a two-view :class:`Capture` (left first).

        A capture that gives only a ``disparity_range`` takes the depths it means for its
        own baseline (``Z = fx D / d``); a range that reaches zero disparity is refused,
        since infinitely far has no depth range.
        """
        if capture.depth_range_mm is not None:
            depth = capture.depth_range_mm
        else:
            assert capture.disparity_range is not None
            lo, hi = capture.disparity_range
            if lo <= 0:
                raise InputError(f"disparity_range {[lo, hi]} reaches zero disparity: give "
                                 "the capture a depth_range_mm [near, far] for N views")
            fb = capture.stereo_camera().fx * capture.epipolar.baseline_mm
            depth = (fb / hi, fb / lo)
        flanges = None
        if capture.flange_left is not None and capture.flange_right is not None:
            flanges = (capture.flange_left, capture.flange_right)
        return cls((capture.left, capture.right), capture.camera,
                   (capture.pose_left, capture.pose_right), depth_range_mm=depth,
                   bit_depth=capture.bit_depth,
                   baseline_uncertainty_mm=capture.baseline_uncertainty_mm,
                   focal_length_uncertainty_mm=capture.focal_length_uncertainty_mm,
                   disparity_uncertainty_px=capture.disparity_uncertainty_px,
                   rotation_uncertainty_deg=capture.rotation_uncertainty_deg,
                   hand_eye_uncertainty_deg=capture.hand_eye_uncertainty_deg,
                   notes=dict(capture.notes), flanges=flanges, hand_eye=capture.hand_eye)

    def __post_init__(self) -> None:
        if self.focal_length_uncertainty_mm is None:
            object.__setattr__(self, "focal_length_uncertainty_mm",
                               default_focal_uncertainty_mm(self.camera))
        object.__setattr__(self, "images", tuple(self.images))
        object.__setattr__(self, "poses", tuple(self.poses))
        n = len(self.images)
        if n < 2:
            raise InputError(f"a capture needs at least two views, got {n}")
        if len(self.poses) != n:
            raise InputError(f"every view needs a pose: {n} images but {len(self.poses)} "
                             "poses")
        w, h = self.camera.image_size
        for k, img in enumerate(self.images):
            shape = np.shape(img)
            if len(shape) not in (2, 3) or shape[:2] != (h, w):
                raise InputError(f"view {self.view_name(k)}: the image must be {w} x {h} pixels "
                                 f"(the camera's image_size), got shape {shape}")
        for k, p in enumerate(self.poses):
            if not isinstance(p, SE3):
                raise InputError(f"view {self.view_name(k)}: the pose must be a Pose or an SE3, "
                                 f"got {type(p).__name__}")
        b = self.bit_depth
        if isinstance(b, bool) or not isinstance(b, int | np.integer) or not 1 <= b <= 16:
            raise InputError(f"bit_depth must be an integer in 1..16, got {shown(b)}")
        for k, img in enumerate(self.images):
            a = np.asarray(img)
            if np.issubdtype(a.dtype, np.integer) and a.size and a.max() >= 2**b:
                raise InputError(f"view {self.view_name(k)}: grey level {int(a.max())} >= "
                                 f"2**bit_depth = {2**b}")
        rng = self.depth_range_mm
        ok = isinstance(rng, list | tuple) and len(rng) == 2 and not any(
            isinstance(v, bool) for v in rng)
        try:
            near, far = (float(rng[0]), float(rng[1])) if ok else (math.nan, math.nan)
        except (TypeError, ValueError, OverflowError):
            near = far = math.nan
        if not (math.isfinite(near) and math.isfinite(far) and 0 < near <= far):
            raise InputError(f"depth_range_mm must be [near, far] with 0 < near <= far, got "
                             f"{shown(rng)}")
        object.__setattr__(self, "depth_range_mm", (near, far))
        check_uncertainties(self.camera.focal_length_mm, w,
                            baseline_mm=self.baseline_uncertainty_mm,
                            focal_length_mm_unc=self.focal_length_uncertainty_mm,
                            disparity_px=self.disparity_uncertainty_px,
                            rotation_deg=self.rotation_uncertainty_deg,
                            hand_eye_deg=self.hand_eye_uncertainty_deg)
        if self.names is not None:
            object.__setattr__(self, "names", tuple(str(s) for s in self.names))
            if len(self.names) != n or len(set(self.names)) != n:
                raise InputError(f"names must be {n} different file names, got "
                                 f"{list(self.names)}")
        if self.flanges is not None:
            object.__setattr__(self, "flanges", tuple(self.flanges))
            if len(self.flanges) != n or self.hand_eye is None:
                raise InputError("flanges need one flange pose per view and the hand_eye")
        # the views must not all stand at one point: nothing to triangulate from
        if not math.isfinite(self.span_mm):
            raise InputError(f"the {n} views' optical centres are not a finite distance "
                             f"apart (largest coordinate {np.abs(self.centres).max():.3g} mm)")
        if self.span_mm <= self.baseline_uncertainty_mm:
            raise InputError(
                f"all {n} views stand at one point (largest distance between optical centres "
                f"{self.span_mm:.3g} mm, not longer than its uncertainty "
                f"{self.baseline_uncertainty_mm:g} mm): move the camera between them")
        # the widest pair bounds the inverse-depth grid of the ray search
        check_depth_disparities(self.camera.fx, self.span_mm, (near, far), w)

    def view_name(self, k: int) -> str:
        """View `k` as errors and warnings name it: ``2 (view_02.png)``, or ``2``."""
        if self.names is not None and len(self.names) > k:
            return f"{k} ({self.names[k]})"
        return str(k)

    def __len__(self) -> int:
        return len(self.images)

    @property
    def centres(self) -> NDArray[np.float64]:
        """Optical centres of the views in the world, shape (N, 3), mm."""
        return np.array([as_se3(p).translation for p in self.poses])

    @property
    def span_mm(self) -> float:
        """Largest distance between two views' optical centres, mm."""
        c = self.centres
        d = c[:, None, :] - c[None, :, :]
        return float(np.sqrt(np.max(np.einsum("ijk,ijk->ij", d, d))))

    def subset(self, keep: Sequence[int]) -> ViewsCapture:
        """The views `keep` (indices, in that order) as a capture of their own (two or more).

        >>> from robostereo.geometry.camera import SEED_CAMERA
        >>> from robostereo.geometry.poses import se3_from_scara
        >>> w, h = SEED_CAMERA.image_size
        >>> images = tuple(np.zeros((h, w), np.uint8) for _ in range(3))
        >>> poses = tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20.0, 0.0, 20.0))
        >>> cap = ViewsCapture(images, SEED_CAMERA, poses, depth_range_mm=(900.0, 1100.0))
        >>> round(cap.subset([0, 2]).span_mm, 1)
        40.0
        """
        keep = [int(k) for k in keep]
        if any(not 0 <= k < len(self) for k in keep):
            raise InputError(f"keep must be view indices in 0..{len(self) - 1}, got {keep}")
        pick = lambda seq: None if seq is None else tuple(seq[k] for k in keep)  # noqa: E731
        return replace(self, images=pick(self.images), poses=pick(self.poses),
                       names=pick(self.names), flanges=pick(self.flanges))

    def pair(self, i: int, j: int) -> Capture:
        """Views `i` and `j` as a two-view :class:`Capture` (`i` left, `j` right)."""
        n = len(self)
        for name, k in (("i", i), ("j", j)):
            if isinstance(k, bool) or int(k) != k or not 0 <= k < n:
                raise InputError(f"{name} must be a view index in 0..{n - 1}, got {k!r}")
        if i == j:
            raise InputError(f"a pair needs two different views, got i = j = {i}")
        kwargs: dict[str, Any] = {}
        if self.flanges is not None and self.hand_eye is not None:
            kwargs = {"flange_left": self.flanges[i], "flange_right": self.flanges[j],
                      "hand_eye": self.hand_eye}
        return Capture(
            left=self.images[i], right=self.images[j], camera=self.camera,
            pose_left=self.poses[i], pose_right=self.poses[j], bit_depth=self.bit_depth,
            depth_range_mm=self.depth_range_mm,
            baseline_uncertainty_mm=self.baseline_uncertainty_mm,
            focal_length_uncertainty_mm=self.focal_length_uncertainty_mm,
            disparity_uncertainty_px=self.disparity_uncertainty_px,
            rotation_uncertainty_deg=self.rotation_uncertainty_deg,
            hand_eye_uncertainty_deg=self.hand_eye_uncertainty_deg,
            notes=dict(self.notes), **kwargs)
