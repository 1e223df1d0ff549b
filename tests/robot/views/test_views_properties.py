"""Property tests (hypothesis) of N-view captures: folders, view patterns and view plans.

Generated N-view ``capture.yaml`` files -- every pose form, flange poses with a hand-eye,
keys missing, extra or of the wrong type, NaN and infinities, duplicate images, images
of another size, one view, all views at one point, units -- are read into a valid
:class:`~robostereo.robot.views.viewpoints.ViewsCapture` or refused with a one-line
:class:`~robostereo.errors.InputError`, never another exception; an unbroken file reads
back the poses it was written from.  Written captures read back equal.
:func:`~robostereo.robot.views.viewpoints.view_offsets` and
:func:`~robostereo.robot.planning.views_plan.plan_views` on generated arguments return
valid results or refuse them; two views on a line plan as
:func:`~robostereo.robot.planning.baseline_plan.plan_baseline`, and a planned span
reaches the wanted accuracy by the bound its docstring gives.  The profiles are those of
``tests/test_properties.py`` (``ROBOSTEREO_HYPOTHESIS``, set in ``conftest.py``).
"""

from __future__ import annotations

import math
import tempfile
import warnings
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest
import yaml

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import event, given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from robostereo.errors import InputError  # noqa: E402
from robostereo.geometry.camera import Camera, camera_from_dict  # noqa: E402
from robostereo.geometry.poses import SE3, Pose, se3_from_scara  # noqa: E402
from robostereo.robot.planning import (  # noqa: E402
    plan_baseline,
    plan_views,
    views_baseline_factor,
)
from robostereo.robot.views.viewpoints import PATTERNS, ViewsCapture, view_offsets  # noqa: E402
from robostereo.robot.views.views_folder import read_views_capture, write_views_capture  # noqa: E402

# a NumPy warning printed to the user is a fault too: overflow, division by zero...
pytestmark = pytest.mark.filterwarnings("error::RuntimeWarning")

W, H = 16, 12
CAMERA = {"focal_length_mm": 25.0, "pixel_pitch_mm": [0.0172, 0.0137], "image_size": [W, H]}


def _near_enough(poses: list[SE3]) -> float:
    """The nearest depth, mm, at which the widest pair of `poses` (plus the hand-eye's
    few mm) sees disparities of at most the image width: the depth range then spans at
    most that, which a real capture does (robostereo.geometry.plausibility)."""
    t = np.array([p.translation for p in poses])
    span = float(np.max(np.linalg.norm(t[:, None] - t[None, :], axis=-1)))
    fx = CAMERA["focal_length_mm"] / CAMERA["pixel_pitch_mm"][0]
    return fx * (span + 10.0) / W


def _result_or_refusal(call: Any, *args: Any, **kwargs: Any) -> Any:
    """The call's result, or None after checking that it raised a one-line InputError."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # plausibility warnings
            return call(*args, **kwargs)
    except InputError as e:
        msg = str(e)
        assert msg and "\n" not in msg, repr(msg)
        return None


def _png(height: int, width: int, seed: int) -> bytes:
    img = np.random.default_rng(seed).integers(0, 128, (height, width), dtype=np.uint8)
    return cv2.imencode(".png", img)[1].tobytes()


PNG = _png(H, W, 0)
PNG_OTHER_SIZE = _png(H - 2, W, 1)

# -- strategies ----------------------------------------------------------------------

any_float = st.floats(allow_nan=True, allow_infinity=True)
junk = st.one_of(st.none(), st.booleans(), st.text(max_size=4), any_float,
                 st.integers(-10**20, 10**20), st.lists(st.integers(), max_size=3),
                 st.dictionaries(st.text(max_size=3), st.integers(), max_size=2))


@st.composite
def true_poses(draw: st.DrawFn, x_mm: float = 0.0) -> SE3:
    """A camera pose near the thesis's: about 1 m above the table, any small turn; `x_mm`
    added to its x."""
    t = [x_mm + draw(st.floats(-500, 500)), draw(st.floats(-500, 500)),
         draw(st.floats(500, 1500))]
    if draw(st.booleans()):
        return se3_from_scara(*t, draw(st.floats(-math.pi, math.pi)))
    r = [draw(st.floats(-0.5, 0.5)) for _ in range(3)]
    return SE3.from_rotvec(t, [math.pi + r[0], r[1], r[2]])


def _pose_dict(pose: SE3, form: str) -> dict[str, Any]:
    """`pose` written in one of the file forms of :mod:`robostereo.geometry.poses`."""
    t = [float(v) for v in pose.translation]
    if form == "scara" and isinstance(pose, Pose):
        return {"x": pose.x, "y": pose.y, "z": pose.z, "phi_deg": math.degrees(pose.phi)}
    if form == "matrix":
        return {"matrix": pose.matrix.tolist()}
    if form == "rotvec":
        return {"position": t, "rotvec": [float(v) for v in pose.rotvec]}
    q = [float(v) for v in pose.quaternion]
    if form == "metres":
        return {"position": [v / 1000.0 for v in t], "quaternion": q, "unit": "m"}
    if form == "ros":
        return {"translation": dict(zip("xyz", [v / 1000.0 for v in t], strict=True)),
                "rotation": dict(zip("xyzw", q, strict=True))}
    return {"position": t, "quaternion": q}


FORMS = ("scara", "matrix", "rotvec", "quaternion", "metres", "ros")


def _breakages(doc: dict[str, Any], draw: st.DrawFn) -> None:
    """Break `doc` once, in one of the ways a hand-written or robot-written file can."""
    views = doc.get("views")
    if not (isinstance(views, list) and views and all(isinstance(v, dict) and (
            "pose" in v or "flange" in v) for v in views)):  # broken already
        doc["views"] = [*views, {}] if isinstance(views, list) else draw(junk)
        return
    k = draw(st.integers(0, len(views) - 1))
    key = "flange" if "flange" in views[k] else "pose"
    how = draw(st.sampled_from([
        "drop top", "extra top", "junk top", "drop view key", "extra view key",
        "junk pose", "nan in pose", "both pose and flange", "duplicate image",
        "one point", "few views", "views junk", "depth range", "unit", "hand_eye",
        "bit_depth", "uncertainty", "camera size", "image junk",
    ]))
    if how == "drop top":
        doc.pop(draw(st.sampled_from(sorted(doc))))
    elif how == "extra top":
        doc[draw(st.sampled_from(["other", "disparity_range", "pose_left"]))] = [1, 2]
    elif how == "junk top":
        doc[draw(st.sampled_from(sorted(doc)))] = draw(junk)
    elif how == "drop view key":
        views[k].pop(draw(st.sampled_from(sorted(views[k]))))
    elif how == "extra view key":
        views[k][draw(st.sampled_from(["other", "unit", "depth"]))] = 1
    elif how == "junk pose":
        views[k][key] = draw(junk)
    elif how == "nan in pose" and isinstance(views[k][key], dict) and views[k][key]:
        pose = views[k][key]
        field = draw(st.sampled_from(sorted(pose)))
        bad = draw(st.sampled_from([math.nan, math.inf, -math.inf, "1", None, True, 1e200]))
        pose[field] = ([bad] * len(pose[field]) if isinstance(pose[field], list)
                       else {s: bad for s in pose[field]} if isinstance(pose[field], dict)
                       else bad)
    elif how == "both pose and flange":
        views[k]["flange" if key == "pose" else "pose"] = views[k][key]
    elif how == "duplicate image":
        views[k]["image"] = views[(k + 1) % len(views)]["image"]
    elif how == "one point":
        for v in views:
            v[key] = views[k][key]
    elif how == "few views":
        doc["views"] = views[:draw(st.integers(0, 1))]
    elif how == "views junk":
        views[k] = draw(junk)
    elif how == "depth range":
        doc["depth_range_mm"] = draw(st.sampled_from(
            [[1000.0, 900.0], [0, 100], [-5, 100], [math.nan, 1e3], [100, math.inf], [100],
             [100, 200, 300], "900..1100", [True, 1000]]))
    elif how == "unit" and isinstance(views[k][key], dict):
        pose = views[k][key]
        if "position" in pose or "matrix" in pose:
            pose["unit"] = draw(st.sampled_from(["km", "", None, "m"]))
    elif how == "hand_eye":
        doc["hand_eye"] = draw(st.one_of(junk, st.just({"position": [0, 0, 50],
                                                        "quaternion": [0, 0, 0, 1]})))
    elif how == "bit_depth":
        doc["bit_depth"] = draw(st.one_of(junk, st.integers(-2, 20)))
    elif how == "uncertainty":
        doc["uncertainty"] = draw(st.one_of(junk, st.fixed_dictionaries(
            {}, optional={"baseline_mm": junk, "disparity_px": junk, "other": junk})))
    elif how == "camera size" and isinstance(doc.get("camera"), dict):
        doc["camera"]["image_size"] = draw(st.sampled_from([[W, H - 2], [W + 1, H], [0, H],
                                                            [W, -H], [W], "16x12"]))
    else:
        views[k]["image"] = draw(st.sampled_from(["../x.png", "/etc/passwd", "", "missing.png",
                                                  "capture.yaml", "a\\b.png", 5]))


@st.composite
def views_documents(draw: st.DrawFn) -> tuple[dict[str, Any], list[SE3] | None, str]:
    """A capture.yaml mapping, the camera poses it means when unbroken (else None), and
    which view's image (if any) is written at another size."""
    n = draw(st.integers(2, 6))
    flange_form = draw(st.booleans())
    truths = [draw(true_poses()) for _ in range(n)]
    forms = draw(st.lists(st.sampled_from(FORMS), min_size=n, max_size=n))
    doc: dict[str, Any] = {"camera": dict(CAMERA), "views": []}
    if flange_form:
        hand_eye = SE3.from_rotvec([draw(st.floats(-60, 60)), 0.0, draw(st.floats(0, 120))],
                                   [0.0, 0.0, draw(st.floats(-1, 1))])
        doc["hand_eye"] = _pose_dict(hand_eye, draw(st.sampled_from(FORMS[1:])))
        poses = [f @ hand_eye for f in truths]
    else:
        poses = truths
    for k, (pose, form) in enumerate(zip(truths, forms, strict=True)):
        doc["views"].append({"image": f"v{k}.png", "flange" if flange_form else "pose":
                             _pose_dict(pose, form)})
    near = _near_enough(poses) + draw(st.floats(10, 2000))
    doc["depth_range_mm"] = [near, near + draw(st.floats(0, 1000))]
    if draw(st.booleans()):
        doc["bit_depth"] = draw(st.integers(7, 16))
    if draw(st.booleans()):
        doc["uncertainty"] = {"baseline_mm": draw(st.floats(0, 1)),
                              "disparity_px": draw(st.floats(0, 1))}
    if draw(st.booleans()):
        doc["robot"] = {"name": "sim"}
    spread = max(np.ptp([p.translation for p in poses], axis=0))
    unbroken = spread > 1.0
    for _ in range(draw(st.integers(0, 2))):
        _breakages(doc, draw)
        unbroken = False
    other_size = ""
    if draw(st.integers(0, 9)) == 0:
        other_size = draw(st.sampled_from([f"v{k}.png" for k in range(n)]))
        unbroken = False
    return doc, (poses if unbroken else None), other_size


def _valid(cap: ViewsCapture) -> None:
    assert isinstance(cap, ViewsCapture) and len(cap) >= 2
    assert len(cap.poses) == len(cap) and len(set(cap.names)) == len(cap)
    for img in cap.images:
        assert img.shape[:2] == (cap.camera.image_size[1], cap.camera.image_size[0])
    for p in cap.poses:
        assert isinstance(p, SE3) and np.isfinite(p.matrix).all()
    near, far = cap.depth_range_mm
    assert 0 < near <= far < math.inf and cap.span_mm > 0


@given(item=views_documents(), text=st.one_of(st.none(), st.text(max_size=40)))
def test_a_generated_views_file_reads_as_a_valid_capture_or_is_refused_in_one_line(
        item, text) -> None:
    doc, poses, other_size = item
    with tempfile.TemporaryDirectory() as d:
        dd = Path(d)
        (dd / "capture.yaml").write_text(yaml.safe_dump(doc) if text is None else text)
        for k in range(6):
            name = f"v{k}.png"
            (dd / name).write_bytes(PNG_OTHER_SIZE if name == other_size else PNG)
        cap = _result_or_refusal(read_views_capture, dd)
    event("refused" if cap is None else "unbroken, read" if poses is not None else "read")
    if cap is None:
        assert poses is None or text is not None, "an unbroken file was refused"
        return
    _valid(cap)
    if poses is not None and text is None:
        assert len(cap) == len(poses)
        for got, want in zip(cap.poses, poses, strict=True):
            assert np.allclose(got.matrix, want.matrix, rtol=0, atol=1e-6)


@st.composite
def captures(draw: st.DrawFn) -> ViewsCapture:
    n = draw(st.integers(2, 5))
    poses = [draw(true_poses(1001.0 * k)) for k in range(n)]  # never at one point
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    bits = draw(st.integers(1, 8))
    images = [rng.integers(0, 2**bits, (H, W), dtype=np.uint8) for _ in range(n)]
    near = _near_enough(poses) + draw(st.floats(1, 2000))
    kw: dict[str, Any] = dict(
        depth_range_mm=(near, near + draw(st.floats(0, 1000))), bit_depth=bits,
        baseline_uncertainty_mm=draw(st.floats(0, 0.5)),
        focal_length_uncertainty_mm=draw(st.floats(0, 1)),
        disparity_uncertainty_px=draw(st.floats(0, 2)))
    if draw(st.booleans()):
        kw["names"] = tuple(f"{draw(st.sampled_from(['a', 'view', 'img-']))}{k}.png"
                            for k in range(n))
    camera = camera_from_dict(CAMERA)
    if draw(st.booleans()):
        hand_eye = SE3.from_rotvec([draw(st.floats(-60, 60)), 0.0, draw(st.floats(10, 120))],
                                   [0.0, 0.0, draw(st.floats(-1, 1))])
        return ViewsCapture.from_flange(images, camera, flanges=poses, hand_eye=hand_eye, **kw)
    return ViewsCapture(tuple(images), camera, tuple(poses), **kw)


@given(cap=captures())
def test_a_written_capture_reads_back_with_equal_images_and_poses(cap) -> None:
    with tempfile.TemporaryDirectory() as d, warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        back = read_views_capture(write_views_capture(Path(d) / "cap", cap))
    assert len(back) == len(cap)
    for a, b in zip(back.images, cap.images, strict=True):
        assert np.array_equal(a, b)
    # the YAML keeps positions to 1e-9 mm and quaternions to 1e-12
    for a, b in zip(back.poses, cap.poses, strict=True):
        assert np.allclose(a.translation, b.translation, rtol=0, atol=1e-6)
        assert np.allclose(a.rotation, b.rotation, rtol=0, atol=1e-9)
        assert isinstance(a, Pose) == isinstance(b, Pose)
    if cap.flanges is not None:
        assert back.flanges is not None and back.hand_eye is not None
        assert np.allclose(back.hand_eye.matrix, cap.hand_eye.matrix, rtol=0, atol=1e-6)
    assert back.depth_range_mm == cap.depth_range_mm
    assert back.bit_depth == cap.bit_depth
    for attr in ("baseline_uncertainty_mm", "focal_length_uncertainty_mm",
                 "disparity_uncertainty_px"):
        assert getattr(back, attr) == getattr(cap, attr)
    if cap.names is not None:
        assert back.names == cap.names


# -- view patterns and plans -----------------------------------------------------------

def mostly(good: st.SearchStrategy[Any], bad: st.SearchStrategy[Any]) -> st.SearchStrategy[Any]:
    """`good` four times in five, else `bad`: the valid paths get checked too."""
    return st.integers(0, 4).flatmap(lambda k: good if k else bad)


counts = mostly(st.integers(2, 12), st.one_of(st.integers(-3, 110), st.sampled_from(
    [2.0, 2.5, 5.0, math.nan, math.inf, True, "5", None, np.int64(5)])))
lengths = mostly(st.floats(1e-3, 1e4), st.one_of(any_float, st.sampled_from(
    [0.0, -1.0, 5e-324, 1e-300, 1e300, "80", None])))
patterns = mostly(st.sampled_from(PATTERNS), st.one_of(st.just("zigzag"), junk))


@given(pattern=patterns, count=counts, span=lengths, depth=st.one_of(st.none(), lengths))
def test_view_offsets_are_a_valid_pattern_or_refused(pattern, count, span, depth) -> None:
    o = _result_or_refusal(view_offsets, pattern, count, span, depth_mm=depth)
    event("refused" if o is None else f"laid out: {pattern}")
    if o is None:
        return
    assert o.shape == (int(count), 3) and np.isfinite(o).all()
    apart = np.abs(o[:, None] - o[None]).max(axis=2)
    assert (apart[~np.eye(len(o), dtype=bool)] > 0).all(), "two views at one point"
    u = o / span  # in units of the span: squares of tiny spans underflow
    if pattern in ("line", "arc"):
        assert np.linalg.norm(u[-1] - u[0]) == pytest.approx(1.0, rel=1e-9)
    if pattern == "arc":
        r = depth / span  # hypot: no squares to overflow at r = 1e154
        assert (u[:, 1] == 0).all()
        assert np.hypot(u[:, 0], u[:, 2] - r) == pytest.approx(r, rel=1e-9)
    if pattern == "cross":
        assert (o[0] == 0).all() and (np.count_nonzero(o, axis=1)[1:] == 1).all()
        assert np.abs(u).max() == pytest.approx(0.5, rel=1e-12)


def _independent_factor(pattern: str, offsets: np.ndarray) -> float:
    """``D_eff / S`` by the formulas of the docstring: the closed form for a line,
    ``sqrt(2 sum (b_i - mean b)^2)`` along x for an arc, and for a cross along the
    direction of least scatter (the smaller root of the 2 x 2 scatter's quadratic)."""
    n = len(offsets)
    if pattern == "line":
        return math.sqrt(n * (n + 1) / (6.0 * (n - 1)))
    xy = offsets[:, :2] - offsets[:, :2].mean(axis=0)
    if pattern == "arc":
        span = float(np.linalg.norm(offsets[-1] - offsets[0]))
        return math.sqrt(2.0 * float(np.sum(xy[:, 0] ** 2))) / span
    a, c = float(np.sum(xy[:, 0] ** 2)), float(np.sum(xy[:, 1] ** 2))
    b = float(np.sum(xy[:, 0] * xy[:, 1]))
    least = 0.5 * (a + c) - math.hypot(0.5 * (a - c), b)
    return math.sqrt(2.0 * least) / (2.0 * float(np.abs(offsets).max()))


extreme = st.one_of(any_float, st.sampled_from([1e-300, 1e300, 5e-324, 0.0, -1.0]))
depths = mostly(st.floats(200, 5000), extreme)
accuracies = mostly(st.floats(0.05, 20), extreme)
nears = mostly(st.none(), st.one_of(st.floats(1, 5000), extreme))
uncertainties = mostly(st.just(0.2), st.one_of(st.floats(0, 2), extreme))


@given(depth=depths, accuracy=accuracies, views=st.one_of(st.none(), counts),
       pattern=patterns, near=nears, far_extra=st.floats(0, 2000), unc=uncertainties)
def test_a_view_plan_is_valid_and_its_span_reaches_the_accuracy(
        depth, accuracy, views, pattern, near, far_extra, unc) -> None:
    camera = Camera()
    rng = None if near is None else (near, near + far_extra if math.isfinite(near) else near)
    plan = _result_or_refusal(plan_views, camera, depth, accuracy, views=views,
                              pattern=pattern, depth_range_mm=rng,
                              disparity_uncertainty_px=unc)
    event("refused" if plan is None else f"planned: {pattern}")
    if plan is None:
        return
    assert 2 <= plan.views <= 100 and plan.pattern == pattern
    assert math.isfinite(plan.span_mm) and plan.span_mm > 0 and 0 < plan.step_mm <= plan.span_mm
    if views is not None:
        assert plan.views == int(views)
    else:  # the fewest views that keep neighbours close
        first = 3 if pattern == "cross" else 2
        assert plan.step_disparity_px <= 20.0 * 25.0 / 0.0172 / 1000.0 * (1 + 1e-12)
        if plan.views > first:
            fewer = _result_or_refusal(plan_views, camera, depth, accuracy,
                                       views=plan.views - 1, pattern=pattern,
                                       depth_range_mm=rng, disparity_uncertainty_px=unc)
            assert fewer is None or fewer.step_disparity_px > plan.step_disparity_px
    # eq. 9 with the views' effective baseline gives the wanted accuracy
    o = view_offsets(pattern, plan.views, plan.span_mm,
                     depth_mm=depth if pattern == "arc" else None)
    d_eff = plan.span_mm * _independent_factor(pattern, o / plan.span_mm)
    assert d_eff == pytest.approx(plan.effective_baseline_mm, rel=1e-6)
    Z, f = float(depth), camera.fx
    bound = 0.01 * Z / d_eff + 0.01 * Z / camera.focal_length_mm + unc * Z * Z / (f * d_eff)
    assert bound == pytest.approx(accuracy, rel=1e-6)
    if pattern == "line" and plan.views == 2:
        assert plan.span_mm == pytest.approx(plan.effective_baseline_mm, rel=1e-12)


@given(depth=depths, accuracy=accuracies, near=nears, far_extra=st.floats(0, 2000),
       unc=uncertainties)
def test_two_views_on_a_line_plan_as_the_two_view_plan(depth, accuracy, near, far_extra,
                                                       unc) -> None:
    camera = Camera()
    rng = None if near is None else (near, near + far_extra if math.isfinite(near) else near)
    kw = dict(depth_range_mm=rng, disparity_uncertainty_px=unc)
    two = _result_or_refusal(plan_baseline, camera, depth, accuracy, **kw)
    views = _result_or_refusal(plan_views, camera, depth, accuracy, views=2, **kw)
    assert (two is None) == (views is None)
    event("refused" if two is None else "planned")
    if two is None:
        return
    assert views.span_mm == two.baseline_mm == views.step_mm
    assert views.disparity_range == two.disparity_range
    assert views.bound_terms_mm == two.bound_terms_mm
    assert views.step_disparity_px == pytest.approx(two.disparity_px, rel=1e-12)


@given(pattern=patterns, count=counts, span=lengths, depth=st.one_of(st.none(), lengths))
def test_the_views_baseline_factor_is_positive_or_refused(pattern, count, span,
                                                          depth) -> None:
    k = _result_or_refusal(views_baseline_factor, pattern, count, span_mm=span,
                           depth_mm=depth)
    if k is not None:
        assert math.isfinite(k) and k > 0
