"""N-view captures: their patterns, their checks, and their pairs."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.geometry.camera import SEED_CAMERA
from robostereo.geometry.poses import SE3, se3_from_scara
from robostereo.robot.capture.capture_folder import Capture
from robostereo.robot.views.viewpoints import PATTERNS, ViewsCapture, view_offsets

W, H = SEED_CAMERA.image_size


def _images(n: int) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(n)
    return tuple(rng.integers(0, 128, (H, W), dtype=np.uint8) for _ in range(n))


def _poses(xs) -> tuple[SE3, ...]:
    return tuple(se3_from_scara(float(x), 5.0, 1000.0, 0.1) for x in xs)


@pytest.mark.parametrize("count", [2, 3, 5, 9])
def test_a_line_spans_the_span_in_even_steps(count):
    o = view_offsets("line", count, 80.0)
    assert o.shape == (count, 3)
    assert np.allclose(o[:, 1:], 0.0)
    assert np.isclose(o[:, 0].max() - o[:, 0].min(), 80.0)
    assert np.allclose(np.diff(o[:, 0]), 80.0 / (count - 1))


@pytest.mark.parametrize("count", [5, 9, 13])
def test_an_odd_cross_is_symmetric_about_its_centre_view(count):
    o = view_offsets("cross", count, 60.0)
    assert np.allclose(o[0], 0.0)
    assert np.allclose(o.sum(axis=0), 0.0)
    on_x = o[np.abs(o[:, 1]) < 1e-12][1:, 0]
    on_y = o[np.abs(o[:, 0]) < 1e-12][1:, 1]
    assert len(on_x) == len(on_y) == (count - 1) // 2
    assert np.isclose(np.ptp(on_x), 60.0) and np.isclose(np.ptp(on_y), 60.0)
    assert len({tuple(r) for r in o.round(9)}) == count  # no two views at one place


def test_arc_views_keep_the_object_at_one_distance():
    o = view_offsets("arc", 7, 100.0, depth_mm=800.0)
    centre = np.array([0.0, 0.0, 800.0])
    assert np.allclose(np.linalg.norm(o - centre, axis=1), 800.0)
    assert np.isclose(np.ptp(o[:, 0]), 100.0)


@pytest.mark.parametrize("args, kwargs, match", [
    (("zigzag", 5, 80.0), {}, "pattern"),
    (("line", 1, 80.0), {}, "count"),
    (("line", 2.5, 80.0), {}, "count"),
    (("line", 5, 0.0), {}, "span_mm"),
    (("line", 5, float("nan")), {}, "span_mm"),
    (("arc", 5, 80.0), {}, "depth_mm"),
    (("arc", 5, 3000.0), {"depth_mm": 1000.0}, "diameter"),
])
def test_bad_patterns_are_refused_naming_the_parameter(args, kwargs, match):
    with pytest.raises(InputError, match=match):
        view_offsets(*args, **kwargs)


def test_patterns_lists_every_pattern_view_offsets_takes():
    for p in PATTERNS:
        assert view_offsets(p, 5, 40.0, depth_mm=500.0).shape == (5, 3)


def test_one_view_is_refused():
    with pytest.raises(InputError, match="at least two views, got 1"):
        ViewsCapture(_images(1), SEED_CAMERA, _poses([0.0]), depth_range_mm=(900, 1100))


def test_a_view_of_another_size_is_refused_naming_the_view():
    imgs = list(_images(3))
    imgs[2] = imgs[2][:-1]
    with pytest.raises(InputError, match=r"view 2 \(c.png\).*image_size"):
        ViewsCapture(tuple(imgs), SEED_CAMERA, _poses([0, 10, 20]),
                     depth_range_mm=(900, 1100), names=("a.png", "b.png", "c.png"))


def test_a_view_without_a_pose_is_refused():
    with pytest.raises(InputError, match="3 images but 2 poses"):
        ViewsCapture(_images(3), SEED_CAMERA, _poses([0, 10]), depth_range_mm=(900, 1100))


def test_views_all_at_one_point_are_refused():
    with pytest.raises(InputError, match="stand at one point"):
        ViewsCapture(_images(4), SEED_CAMERA, _poses([3.0] * 4), depth_range_mm=(900, 1100))


def test_views_too_far_apart_for_floating_point_are_refused():
    # refused when the pose is made: beyond any robot's reach (MAX_TRANSLATION_MM)
    with pytest.raises(InputError, match="beyond"):
        ViewsCapture(_images(2), SEED_CAMERA, _poses([0.0, 1e200]), depth_range_mm=(900, 1100))


@pytest.mark.parametrize("rng", [(0, 100), (200, 100), (float("inf"), 1e9), (1, True), "12"])
def test_a_bad_depth_range_is_refused(rng):
    with pytest.raises(InputError, match="depth_range_mm"):
        ViewsCapture(_images(2), SEED_CAMERA, _poses([0, 20]), depth_range_mm=rng)


def test_grey_levels_beyond_the_bit_depth_are_refused_naming_the_view():
    imgs = list(_images(3))
    imgs[1] = imgs[1].copy()
    imgs[1][0, 0] = 200
    with pytest.raises(InputError, match="view 1: grey level 200"):
        ViewsCapture(tuple(imgs), SEED_CAMERA, _poses([0, 10, 20]), depth_range_mm=(900, 1100))


def test_a_pair_of_views_is_the_two_view_capture_of_those_views():
    imgs = _images(3)
    cap = ViewsCapture(imgs, SEED_CAMERA, _poses([-20, 0, 20]), depth_range_mm=(900, 1100),
                       disparity_uncertainty_px=0.1)
    pair = cap.pair(2, 0)
    assert isinstance(pair, Capture)
    assert pair.left is imgs[2] and pair.right is imgs[0]
    assert pair.pose_left.x == 20 and pair.pose_right.x == -20
    assert pair.disparity_uncertainty_px == 0.1
    assert np.isclose(pair.epipolar.baseline_mm, 40.0)
    with pytest.raises(InputError, match="two different views"):
        cap.pair(1, 1)
    with pytest.raises(InputError, match=r"j must be a view index in 0\.\.2"):
        cap.pair(0, 3)


def test_a_two_view_capture_is_a_views_capture_of_two():
    imgs = _images(2)
    two = Capture(left=imgs[0], right=imgs[1], camera=SEED_CAMERA,
                  pose_left=se3_from_scara(-10, 0, 1000), pose_right=se3_from_scara(10, 0, 1000),
                  disparity_range=(26, 33))
    views = ViewsCapture.from_capture(two)
    assert len(views) == 2 and views.images[0] is imgs[0]
    fb = SEED_CAMERA.fx * 20.0
    assert np.allclose(views.depth_range_mm, (fb / 33, fb / 26))
    back = views.pair(0, 1)
    assert back.pose_left == two.pose_left and back.pose_right == two.pose_right


def test_flange_poses_and_the_hand_eye_make_the_camera_poses():
    hand_eye = SE3.from_rotvec([1.0, 2.0, 30.0], [0.0, 0.0, 0.2])
    flanges = tuple(SE3.from_rotvec([x, 0.0, 1000.0], [np.pi, 0.0, 0.0]) for x in (-30, 0, 30))
    cap = ViewsCapture.from_flange(_images(3), SEED_CAMERA, flanges=flanges, hand_eye=hand_eye,
                                   depth_range_mm=(800, 1200))
    for f, p in zip(flanges, cap.poses, strict=True):
        assert np.allclose((f @ hand_eye).matrix, p.matrix)
    pair = cap.pair(0, 2)
    assert pair.hand_eye is hand_eye and pair.flange_right is flanges[2]
