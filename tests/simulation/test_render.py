"""Tests of rendering: geometry against Camera.project, exact depth, shading, noise."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.geometry.camera import SEED_CAMERA, Camera
from robostereo.geometry.poses import Pose
from robostereo.simulation import (
    Box,
    Cylinder,
    Disc,
    Scene,
    TablePlane,
    render,
    sample_offsets,
    seed_block_scene,
    true_disparity,
)

CAM = SEED_CAMERA


def edge_columns(img: np.ndarray, rows: np.ndarray, u: float, inside: int, outside: int) -> float:
    """Mean column of the 50% crossing between the plateaus at ``u + inside`` and
    ``u + outside`` (columns relative to the rounded `u`), linearly interpolated."""
    j = round(u)
    img = img.astype(float)
    a = img[rows, j + inside].mean()
    b = img[rows, j + outside].mean()
    mid = 0.5 * (a + b)
    lo, hi = j - 4, j + 5
    cols = []
    for row in rows:
        p = img[row, lo:hi]
        s = np.sign(p - mid)
        k = np.nonzero(s[:-1] != s[1:])[0]
        assert len(k) == 1, f"no single crossing on row {row}: {p}"
        k = k[0]
        cols.append(lo + k + (mid - p[k]) / (p[k + 1] - p[k]))
    return float(np.mean(cols))


def top_edge(scene, pose: Pose, x_world: float) -> tuple[float, np.ndarray]:
    """Projected column of the block top's edge at world x, and the rows it spans
    (5 mm in from the ends)."""
    ys = np.array([scene.front_y + 5.0, scene.back_y - 5.0])
    pts = np.column_stack([np.full(2, x_world), ys, np.full(2, scene.top_z)])
    uv, _ = CAM.project(pts, pose)
    assert abs(uv[0, 0] - uv[1, 0]) < 1e-9  # a vertical image line for a yaw-0 camera
    r0, r1 = sorted(uv[:, 1])
    return float(uv[0, 0]), np.arange(math.ceil(r0), math.floor(r1) + 1)


# ----------------------------------------------------------------------------- geometry


@pytest.mark.parametrize("shift", [0.0, 0.23, 0.61])
def test_block_top_edges_at_projected_columns(shift: float) -> None:
    # shift the block by a fraction of a pixel so the edge falls at various phases
    dx_mm = shift * 1000.0 / CAM.fx
    scene = seed_block_scene(center_xy=(dx_mm, 0.0))
    pose = Pose(43.3, 22.5, 1050.0)  # the block moves, the camera stays
    r = render(scene, CAM, pose)
    # left face is hidden: the top meets the table; right face is seen as a thin strip
    u_left, rows = top_edge(scene, pose, scene.left_x)
    u_right, _ = top_edge(scene, pose, scene.right_x)
    assert edge_columns(r.intensity, rows, u_left, +6, -5) == pytest.approx(u_left, abs=0.1)
    assert edge_columns(r.intensity, rows, u_right, -6, +2) == pytest.approx(u_right, abs=0.1)
    # the quantised image agrees as well
    assert edge_columns(r.image, rows, u_left, +6, -5) == pytest.approx(u_left, abs=0.1)


def test_without_supersampling_the_edge_is_off() -> None:
    # control for the test above: one ray per pixel puts the edge at a pixel boundary
    scene = seed_block_scene()
    pose = scene.view_pose
    u_left, rows = top_edge(scene, pose, scene.left_x)
    r1 = render(scene, CAM, pose, supersample=1)
    err = abs(edge_columns(r1.intensity, rows, u_left, +6, -5) - u_left)
    assert err > 0.2  # u_left = 173.91: the step lies between columns 173 and 174


# ----------------------------------------------------------------------------- depth


@pytest.mark.parametrize("supersample", [1, 2, 3])
def test_flat_table_depth_is_exact(supersample: int) -> None:
    scene = Scene((TablePlane(z=12.5, albedo=0.4),))
    pose = Pose(-37.0, 81.0, 1012.5, phi=1.1)
    r = render(scene, CAM, pose, supersample=supersample)
    assert r.depth.shape == (481, 509) and r.depth.dtype == np.float64
    assert np.all(r.depth == 1000.0)
    assert np.all(r.labels == 0)


def test_no_hit_gives_inf_depth_and_label_minus_one() -> None:
    scene = Scene((Disc((0.0, 0.0), 0.0, 10.0, albedo=0.8),), background=0.0)
    r = render(scene, CAM, Pose(0.0, 0.0, 1000.0), blur_sigma_px=0.0)
    assert r.labels[0, 0] == -1 and np.isinf(r.depth[0, 0]) and r.image[0, 0] == 0
    # the disc of radius 10 mm at 1000 mm spans 14.5 px horizontally, 18.2 px vertically
    assert r.labels[240, 254] == 0
    assert r.labels[240, 254 + 14] == 0 and r.labels[240, 254 + 15] == -1
    assert r.labels[240 + 18, 254] == 0 and r.labels[240 + 19, 254] == -1


def test_true_disparity_matches_rendered_stereo_pair() -> None:
    scene = seed_block_scene()
    mid = scene.view_pose
    left = Pose(mid.x - 10.0, mid.y, mid.z)
    right = Pose(mid.x + 10.0, mid.y, mid.z)
    rl, rr = render(scene, CAM, left), render(scene, CAM, right)
    ul, rows = top_edge(scene, left, scene.left_x)
    ur, _ = top_edge(scene, right, scene.left_x)
    measured = edge_columns(rl.intensity, rows, ul, 6, -5) - edge_columns(
        rr.intensity, rows, ur, 6, -5
    )
    d = true_disparity(rl.depth, CAM, 20.0)
    assert d[rows[0], round(ul) + 5] == pytest.approx(CAM.fx * 20.0 / 1000.0)
    assert measured == pytest.approx(CAM.fx * 20.0 / 1000.0, abs=0.1)
    assert true_disparity([[np.inf]], CAM, 20.0)[0, 0] == 0.0


# ----------------------------------------------------------------------------- image


def flat(albedo: float = 0.5) -> Scene:
    return Scene((TablePlane(0.0, albedo),), light_direction=(0.0, 0.0, 1.0))


def test_shading_is_lambertian_with_ambient() -> None:
    # top of the block: n = +z; the lit right face: n = +x; table: n = +z
    scene = seed_block_scene()
    light = np.asarray(scene.light_direction)
    assert light == pytest.approx(np.array([0.3, -0.2, 1.0]) / math.sqrt(1.13))
    r = render(scene, CAM, scene.view_pose, blur_sigma_px=0.0)
    top = 0.85 * (0.15 + 0.8 * light[2]) * 127
    table = 0.3 * (0.15 + 0.8 * light[2]) * 127
    side = 0.85 * (0.15 + 0.8 * light[0]) * 127
    u, rows = top_edge(scene, scene.view_pose, 0.0)  # the block's centre line
    assert r.intensity[rows, round(u)] == pytest.approx(top, abs=1e-9)
    assert r.intensity[5, 5] == pytest.approx(table, abs=1e-9)
    # the right face, seen edge-on between x = -45.8 and -43.6 px from the centre
    assert r.intensity[rows, 254 - 45] == pytest.approx(side, abs=1e-9)
    # a flat plane lit from straight above: albedo * (ambient + intensity)
    r2 = render(flat(0.5), CAM, Pose(0, 0, 1000.0), supersample=1)
    assert np.allclose(r2.intensity, 0.5 * 0.95 * 127) and np.all(r2.image == 60)


def test_determinism_with_same_rng() -> None:
    scene = seed_block_scene(texture_rng=np.random.default_rng(5))
    again = seed_block_scene(texture_rng=np.random.default_rng(5))
    kw = dict(noise_sigma=1.5, supersample=2)
    a = render(scene, CAM, scene.view_pose, rng=np.random.default_rng(11), **kw)
    b = render(again, CAM, again.view_pose, rng=np.random.default_rng(11), **kw)
    c = render(scene, CAM, scene.view_pose, rng=np.random.default_rng(12), **kw)
    assert np.array_equal(a.image, b.image) and np.array_equal(a.depth, b.depth)
    assert not np.array_equal(a.image, c.image)
    assert np.array_equal(a.intensity, c.intensity)  # the noise-free image does not change
    other = seed_block_scene(texture_rng=np.random.default_rng(6))
    d = render(other, CAM, other.view_pose, rng=np.random.default_rng(11), **kw)
    assert not np.array_equal(a.image, d.image)  # another texture


def test_noise_statistics() -> None:
    pose = Pose(0.0, 0.0, 1000.0)
    r = render(flat(0.5), CAM, pose, noise_sigma=2.0, rng=np.random.default_rng(0))
    err = r.image.astype(float) - r.intensity  # intensity = 60.325 everywhere
    assert err.mean() == pytest.approx(0.0, abs=0.02)
    # Gaussian noise plus uniform rounding error: sqrt(4 + 1/12)
    assert err.std() == pytest.approx(math.sqrt(4.0 + 1.0 / 12.0), rel=0.01)
    # neighbouring pixels are independent
    corr = np.corrcoef(err[:, :-1].ravel(), err[:, 1:].ravel())[0, 1]
    assert abs(corr) < 0.01


def test_quantisation_range_and_dtype() -> None:
    pose = Pose(0.0, 0.0, 1000.0)
    bright = Scene((TablePlane(0.0, 1.0),), light_intensity=1.0, ambient=0.5)
    r = render(bright, CAM, pose, noise_sigma=3.0, rng=np.random.default_rng(1))
    assert r.image.dtype == np.uint8 and r.image.shape == (481, 509)
    assert np.allclose(r.intensity, 127.0, atol=1e-9)  # radiance 1.44 saturates first
    # the clipped noise leaves 127 where the noise is > -0.5: Phi(0.5 / 3) = 0.5662
    assert r.image.max() == 127 and np.mean(r.image == 127) == pytest.approx(0.5662, abs=0.005)
    dark = render(flat(0.0), CAM, pose, noise_sigma=3.0, rng=np.random.default_rng(1))
    assert dark.image.min() == 0 and np.mean(dark.image == 0) == pytest.approx(0.5662, abs=0.005)
    assert dark.image.max() <= 20  # 6.5 sigma
    cam8 = Camera(grey_levels=256)
    assert render(bright, cam8, pose).image.max() == 255
    assert render(flat(0.5), cam8, pose).image[0, 0] == round(0.475 * 255)


def test_sample_offsets_are_n_rooks() -> None:
    for s in (2, 3, 4):
        off = sample_offsets(s)
        assert off.shape == (s * s, 2)
        expected = (np.arange(s * s) + 0.5) / (s * s) - 0.5
        assert np.allclose(np.sort(off[:, 0]), expected)
        assert np.allclose(np.sort(off[:, 1]), expected)
    assert np.allclose(sample_offsets(3)[4], 0.0)  # centre ray for odd s


# ----------------------------------------------------------------------------- input


def test_bad_input_raises_input_error() -> None:
    pose = Pose(0.0, 0.0, 1000.0)
    with pytest.raises(InputError, match="rng"):
        render(flat(), CAM, pose, noise_sigma=1.0)
    with pytest.raises(InputError, match="supersample"):
        render(flat(), CAM, pose, supersample=0)
    with pytest.raises(InputError, match="blur_sigma_px"):
        render(flat(), CAM, pose, blur_sigma_px=-1.0)
    with pytest.raises(InputError, match="albedo"):
        TablePlane(0.0, 1.5)
    with pytest.raises(InputError, match="inner_radius"):
        Cylinder((0.0, 0.0), 0.0, 5.0, 10.0, inner_radius=6.0)
    with pytest.raises(InputError, match="primitives"):
        Scene(("table",))  # type: ignore[arg-type]
    with pytest.raises(InputError, match="lift_mm"):
        seed_block_scene(lift_mm=-60.0)
    with pytest.raises(InputError, match="size"):
        Box((0.0, 0.0), 0.0, (1.0, -2.0, 3.0))
