"""The N-view test renders of tests/view_renders.py: their truth, and the classic pair on them."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from view_renders import RenderSpec, nominal_poses, render_views, rotation_deg

from robostereo.robot.capture import locate


@pytest.fixture(scope="module")
def line3():
    return render_views(RenderSpec(count=3, span_mm=160.0, turn_deg=30.0, error_deg=0.5,
                                   error_mm=1.0, seed=2))


def _rim(labels: np.ndarray, k: int) -> np.ndarray:
    """Pixels labelled `k` with a 4-neighbour labelled otherwise, (M, 2) as (x, y)."""
    inner = labels == k
    edge = np.zeros_like(inner)
    edge[1:-1, 1:-1] = inner[1:-1, 1:-1] & ~(
        inner[:-2, 1:-1] & inner[2:, 1:-1] & inner[1:-1, :-2] & inner[1:-1, 2:])
    y, x = np.nonzero(edge)
    return np.column_stack([x, y]).astype(float)


def test_rendered_depth_lies_on_the_true_surfaces(line3):
    _cap, truth = line3
    box = truth.scene.primitives.index(truth.box)
    for pose, r in zip(truth.true_poses, truth.renderings, strict=True):
        # the box's rim: a ray cast without the lens's distortion would miss it by ~1 px
        px = _rim(r.labels, box)
        assert len(px) > 100
        world = truth.camera.backproject(px, r.depth[px[:, 1].astype(int),
                                                     px[:, 0].astype(int)], pose)
        assert np.abs(truth.box_distance(world)).max() < 1e-6
        # every pixel centre: on a true surface, and the ray's true depth is the rendered one
        rng = np.random.default_rng(0)
        px = np.column_stack([rng.integers(0, 640, 500), rng.integers(0, 480, 500)])
        z = r.depth[px[:, 1], px[:, 0]]
        world = truth.camera.backproject(px.astype(float), z, pose)
        assert truth.surface_distance(world).max() < 1e-6
        np.testing.assert_allclose(
            truth.ray_depth(pose.translation, pose.rotation[:, 2], world), z, rtol=1e-9)


def test_surface_distance_and_outline():
    _cap, truth = render_views(RenderSpec(count=2))
    top = truth.box.z_top
    assert truth.surface_distance(np.array([[0.0, 0.0, top + 3.0]]))[0] == pytest.approx(3.0)
    assert truth.surface_distance(np.array([[0.0, 0.0, top - 3.0]]))[0] == pytest.approx(3.0)
    assert truth.surface_distance(np.array([[300.0, 0.0, 5.0]]))[0] == pytest.approx(5.0)
    assert truth.near_box(np.array([[0.0, 0.0, top + 5.0], [300.0, 0.0, 5.0]])).tolist() == [
        True, False]
    outline = truth.outline()
    assert len(outline) == pytest.approx(2 * (60 + 90), abs=4)
    assert np.abs(truth.box_distance(outline)).max() < 1e-9
    np.testing.assert_allclose(outline[:, 2], top)


def test_poses_are_off_by_the_asked_amounts(line3):
    cap, truth = line3
    spec = truth.spec
    for nominal, went, true in zip(nominal_poses(spec), cap.poses, truth.true_poses,
                                   strict=True):
        assert rotation_deg(nominal, went) == pytest.approx(spec.jitter_deg, abs=1e-9)
        assert np.linalg.norm(went.translation - nominal.translation) == pytest.approx(
            spec.jitter_mm, abs=1e-9)
        assert rotation_deg(went, true) == pytest.approx(spec.error_deg, abs=1e-9)
        assert np.linalg.norm(true.translation - went.translation) == pytest.approx(
            spec.error_mm, abs=1e-9)
    ends = nominal_poses(spec)
    assert rotation_deg(ends[0], ends[-1]) == pytest.approx(30.0, abs=1e-6)
    assert np.linalg.norm(ends[0].translation - ends[-1].translation) == pytest.approx(160.0)
    _cap, still = render_views(RenderSpec(count=2, seed=2))
    for a, b in zip(still.true_poses, still.recorded_poses, strict=True):
        np.testing.assert_allclose(a.matrix, b.matrix, atol=1e-12)


def test_the_capture_records_the_lens_and_sees_the_box(line3):
    cap, truth = line3
    assert cap.camera.distortion[0] == -0.1
    assert render_views(RenderSpec(count=2, k1=0.0))[0].camera.distortion == ()
    near, far = cap.depth_range_mm
    assert near < 400.0 - 5 and far > 440.0
    seen = truth.seen_by(np.array([[0.0, 0.0, truth.box.z_top],  # the top's centre
                                   [0.0, 0.0, 0.0],  # under the box
                                   [5000.0, 0.0, 0.0]]))  # out of every image
    assert seen.tolist() == [[True] * 3, [False] * 3, [False] * 3]


def test_renders_are_deterministic_per_seed():
    a, _ = render_views(RenderSpec(count=2, texture="print"))
    b, _ = render_views(RenderSpec(count=2, texture="print"))
    c, _ = render_views(RenderSpec(count=2, texture="print", seed=1))
    assert all(np.array_equal(x, y) for x, y in zip(a.images, b.images, strict=True))
    assert not np.array_equal(a.images[0], c.images[0])


@pytest.mark.parametrize("texture", ["stripes", "print"])
def test_the_classic_pair_locates_the_box_within_its_bound(texture):
    cap, truth = render_views(RenderSpec(count=2, texture=texture))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        located = locate(cap.pair(0, 1))
    w = located.world
    assert len(w) > 500
    box = truth.near_box(w)
    assert box.sum() > 80
    assert np.percentile(truth.surface_distance(w[box]), 95) < 2.0
    o, axis = cap.poses[0].translation, cap.poses[0].rotation[:, 2]
    depth_error = np.abs((w - o) @ axis - truth.ray_depth(o, axis, w))
    assert (depth_error <= 2.0 * located.z_bound).mean() > 0.95
