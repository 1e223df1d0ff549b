"""Tests of the simulated camera: geometry against Camera.project, exact depth, noise."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robostereo.camera import SEED_CAMERA, Camera, Pose
from robostereo.errors import InputError
from robostereo.simulation import (
    Box,
    Cylinder,
    Disc,
    NoiseTexture,
    Scene,
    TablePlane,
    hub_pulley_scene,
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


def test_labels_of_yawed_box_seen_from_yawed_camera() -> None:
    box = Box((10.0, -20.0), 0.0, (40.0, 25.0, 30.0), yaw=0.5, albedo=0.9)
    scene = Scene((TablePlane(0.0, 0.2), box))
    pose = Pose(0.0, 0.0, 900.0, phi=-0.7)
    r = render(scene, CAM, pose)
    c, s = math.cos(0.5), math.sin(0.5)
    for scale, label in ((0.9, 1), (1.1, 0)):
        lx = np.array([-1, 1, 1, -1, 0.0, 0.0]) * 20.0 * scale
        ly = np.array([-1, -1, 1, 1, 1, -1]) * 12.5 * scale
        pts = np.column_stack([10 + c * lx - s * ly, -20 + s * lx + c * ly, np.full(6, 30.0)])
        if label == 0:
            pts[:, 2] = 0.0  # just outside the box, on the table
        uv, _ = CAM.project(pts, pose)
        ij = np.rint(uv[:, ::-1]).astype(int)
        assert (r.labels[ij[:, 0], ij[:, 1]] == label).all()
    # depth on the top face is exactly camera height - top
    assert np.all(r.depth[r.labels == 1] >= 870.0 - 1e-9)
    assert np.sum(np.isclose(r.depth[r.labels == 1], 870.0, atol=1e-9)) > 1000


def test_hit_points_lie_on_their_surfaces() -> None:
    # back-projecting every pixel centre with its depth lands on the labelled primitive
    scene = hub_pulley_scene(center_xy=(200.0, -50.0))
    pose = Pose(230.0, -40.0, 1070.0, phi=0.3)
    r = render(scene, CAM, pose, supersample=1)
    jj, ii = np.meshgrid(np.arange(CAM.width), np.arange(CAM.height))
    pts = CAM.backproject(np.column_stack([jj.ravel(), ii.ravel()]), r.depth.ravel(), pose)
    lab = r.labels.ravel()
    prims = scene.primitives
    rr = np.hypot(pts[:, 0] - 200.0, pts[:, 1] + 50.0)
    assert np.allclose(pts[lab == 0, 2], 0.0, atol=1e-9)  # table
    hub = prims[9]
    assert isinstance(hub, Cylinder)
    on_hub = lab == 9
    # hub: either its top annulus (z = 70, r in [10, 24]) or the inside of its bore
    top = np.isclose(pts[:, 2], 70.0, atol=1e-9)
    assert np.all(rr[on_hub & top] <= 24 + 1e-6) and np.all(rr[on_hub & top] >= 10 - 1e-6)
    # walls: the bore's (r = 10) and the outer one above the boss (r = 24, z >= 32)
    wall = on_hub & ~top
    bore = np.isclose(rr, 10.0, atol=1e-6)
    outer = np.isclose(rr, 24.0, atol=1e-6) & (pts[:, 2] >= 32.0 - 1e-6)
    assert np.all(bore[wall] | outer[wall])
    assert np.any(bore & wall) and np.any(outer & wall)  # both seen from the side
    web = prims[4]
    assert isinstance(web, Disc)
    assert np.allclose(pts[lab == 4, 2], 20.0, atol=1e-9)
    assert np.all(rr[lab == 4] >= 24 - 1e-6) and np.all(rr[lab == 4] <= 76 + 1e-6)


def test_holes_and_bores_show_the_table() -> None:
    scene = hub_pulley_scene()
    pose = scene.view_pose
    r = render(scene, CAM, pose, supersample=1)
    hole_centres = [
        (56 * math.cos(a), 56 * math.sin(a), 0.0) for a in np.deg2rad(np.arange(8) * 45 + 22.5)
    ]
    uv, _ = CAM.project([*hole_centres, (0.0, 0.0, 0.0)], pose)
    ij = np.rint(uv[:, ::-1]).astype(int)
    assert (r.labels[ij[:, 0], ij[:, 1]] == 0).all()
    assert r.depth[240, 254] == 1070.0  # the principal ray, straight down the bore


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


def test_lift_moves_the_block_top_by_lift_mm() -> None:
    base = seed_block_scene()
    lifted = seed_block_scene(lift_mm=79.65)
    assert lifted.top_z - base.top_z == pytest.approx(79.65, abs=1e-12)
    assert (lifted.left_x, lifted.right_x, lifted.width) == (base.left_x, base.right_x, 23.6)
    pose = base.view_pose
    assert lifted.view_pose == pose
    uv, _ = CAM.project([[0.0, 0.0, base.top_z]], pose)  # block centre column/row
    i, j = round(uv[0, 1]), round(uv[0, 0])
    d0 = render(base, CAM, pose, supersample=1).depth[i, j]
    d1 = render(lifted, CAM, pose, supersample=1).depth[i, j]
    assert d0 == pytest.approx(1000.0, abs=1e-9)
    assert d0 - d1 == pytest.approx(79.65, abs=1e-9)


def test_block_seen_where_table_5_1_puts_it() -> None:
    scene = seed_block_scene()
    pose = scene.view_pose
    assert scene.left_x - pose.x == pytest.approx(-55.1)
    assert scene.right_x - pose.x == pytest.approx(-31.5)
    # epipolar Y = -world Y for alpha = 0: table 5-1's y from +55 to -10 mm is covered
    assert scene.front_y - pose.y < -55.0 and scene.back_y - pose.y > 10.0
    r = render(scene, CAM, pose)
    cols = np.nonzero((r.labels == 1).any(axis=0))[0]
    assert cols.max() < 254 - 40  # left of the image centre
    rows = np.nonzero((r.labels == 1).any(axis=1))[0]
    assert len(range(rows.min(), rows.max() + 1, 8)) >= 13  # crosses >= 13 lines


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


def test_texture_modulates_the_table_smoothly() -> None:
    tex = NoiseTexture.from_rng(np.random.default_rng(3), amplitude=0.2)
    assert tex.factor(np.array([0.0]), np.array([0.0]))[0] == pytest.approx(
        1 + 0.2 * tex.values[0, 0]
    )
    # periodic: one period (64 cells of 4 mm) further gives the same factor
    x = np.array([1.3, 77.7])
    assert np.allclose(tex.factor(x, x), tex.factor(x + 256.0, x - 512.0))
    scene = Scene((TablePlane(0.0, 0.5, texture=tex),), light_direction=(0, 0, 1))
    img = render(scene, CAM, Pose(0.0, 0.0, 1000.0)).intensity
    assert img.std() > 2.0  # visible pattern
    assert np.abs(np.diff(img, axis=1)).max() < 3.0  # but no edges (threshold 8)


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


def test_hub_pulley_gives_several_hundred_edge_points() -> None:
    from robostereo.edges import detect_edges

    scene = hub_pulley_scene()
    mid = scene.view_pose
    counts = []
    for dx in (-10.0, 10.0):
        pose = Pose(mid.x + dx, mid.y, mid.z)
        img = render(scene, CAM, pose, noise_sigma=0.7, rng=np.random.default_rng(2)).image
        counts.append(len(detect_edges(img, bit_depth=7, threshold=8.0, row_step=8)))
    assert all(500 <= n <= 1200 for n in counts), counts  # seed: 818 and 815
    assert abs(counts[0] - counts[1]) < 0.05 * counts[0]


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
