"""Rectification with fill, locate, and the demo/capture/locate commands."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.experiments import run_block_experiment
from robostereo.geometry.camera import SEED_CAMERA, Camera
from robostereo.geometry.poses import Pose
from robostereo.geometry.scara_rectification import EpipolarGeometry
from robostereo.matcher.edges import detect_edges
from robostereo.robot.capture import fill_invalid_rows, locate, rectify_pair
from robostereo.robot.simulated.scara_rig import RigSetup, SimulatedCapture, simulate_capture


@pytest.fixture(scope="module")
def block_sim() -> SimulatedCapture:
    return simulate_capture("block", seed=0)


def test_fill_invalid_rows_known_answer():
    img = np.array([[np.nan, np.nan, 4.0, 6.0, np.nan], [1.0, 2.0, 3.0, 4.0, 5.0]])
    out = fill_invalid_rows(img, np.isfinite(img))
    assert out.tolist() == [[4.0, 4.0, 4.0, 6.0, 6.0], [1.0, 2.0, 3.0, 4.0, 5.0]]


def test_rectified_fill_makes_no_edges():
    """A rolled view of a vertical step: after rectification and fill, edge points only at
    the step, none at the boundary of the filled region (the fill is flat along rows)."""
    cam = Camera(image_size=(200, 160))
    left, right = Pose(-10.0, 0.0, 1000.0, 0.25), Pose(10.0, 0.0, 1000.0, 0.2)
    g = EpipolarGeometry.from_poses(cam, left, right)
    # a world step edge at X = 0 on the table, seen by the left camera: build its image
    xs, ys = np.meshgrid(np.arange(200.0), np.arange(160.0))
    pts = cam.backproject(np.column_stack([xs.ravel(), ys.ravel()]), np.full(xs.size, 1000.0),
                          left)
    img = np.where(pts[:, 0] < 0.0, 20.0, 100.0).reshape(xs.shape)
    pair = rectify_pair(img, img, g)
    assert not pair.valid_left.all() and np.isfinite(pair.left).all()
    e = detect_edges(pair.left, threshold=8.0, bit_depth=7)
    # the step is at rectified column where X = 0 projects for the left (virtual) camera
    col = cam.project([[0.0, 0.0, 0.0]], g.virtual_pose("left"))[0][0, 0]
    assert len(e) > 100
    assert np.abs(e.x - col).max() < 1.5


def test_locate_points_are_the_block(block_sim):
    """Known answer: the block's top at z = 50 mm, its faces at x = 357.4 -+ 11.8 mm."""
    loc = locate(block_sim.capture)
    w = loc.world
    on_top = np.abs(w[:, 2] - 50.0) <= loc.z_bound
    assert on_top.mean() > 0.95
    centre_x = 400.0 - 43.3
    near_face = np.minimum(np.abs(w[:, 0] - (centre_x - 11.8)), np.abs(w[:, 0] - (centre_x + 11.8)))
    assert np.median(near_face) < 0.2
    # the left pixel in the grabbed image: the projection of the located world point
    uv, _ = SEED_CAMERA.project(w, block_sim.capture.pose_left)
    assert np.abs(uv - loc.left_pixel).max() < 0.05
    # eq. 9 bound: dD and ds terms plus d(disp) = 0.2 px at 1000 mm -> 7.8 mm
    assert np.median(loc.z_bound) == pytest.approx(0.5 + 0.4 + 0.2 * 1000 / 29.07, abs=0.1)


def test_cli_capture_then_locate_gives_the_demo_points(tmp_path, capsys):
    """`robostereo capture` + `robostereo locate` = the demo's block run (lift 0, seed 0)."""
    d = tmp_path / "cap"
    assert main(["capture", "--out", str(d), "--scene", "block", "--seed", "0"]) == 0
    assert main(["locate", str(d), "-o", str(tmp_path / "pts.csv"), "--ply",
                 str(tmp_path / "pts.ply")]) == 0
    out = capsys.readouterr().out
    assert "located" in out
    rows = np.genfromtxt(tmp_path / "pts.csv", delimiter=",", names=True)
    demo = run_block_experiment(setup=RigSetup(), seed=0, lifts_mm=(0.0, 79.65))
    ref = demo.heights[0].located
    assert rows.shape[0] == len(ref)
    assert np.allclose(np.column_stack([rows["X_w"], rows["Y_w"], rows["Z_w"]]), ref.world,
                       atol=1e-3)
    assert np.allclose(rows["z_bound"], ref.z_bound, atol=1e-3)
    assert (tmp_path / "pts.ply").read_bytes().startswith(b"ply")
    # default output: DIR/located.csv
    assert main(["locate", str(d)]) == 0
    assert (d / "located.csv").is_file()


def test_demo_command(tmp_path, capsys):
    out = tmp_path / "figs"
    assert main(["demo", "--out", str(out), "--seed", "1"]) == 0
    text = capsys.readouterr().out
    assert "Table 5-1(a)" in text and "Hub-pulley" in text and "measured lift" in text
    # the thesis's figures are called the thesis's, not "seed" (a random-number seed)
    assert "(thesis: lift 79.65 mm" in text and "seed:" not in text
    assert sorted(p.name for p in out.iterdir()) == ["block_iterations.png", "points_3d.png",
                                                     "pulley_iterations.png"]
    assert main(["demo", "--seed", "-1", "--out", str(tmp_path / "x")]) == 2
    assert not (tmp_path / "x").exists()


# -- plausibility checks, on views of a small renderer of our own (not the simulator) --


def _render_plane(camera: Camera, pose, *, cell_mm: float = 9.0) -> np.ndarray:
    """A 7-bit view of the plane z = 0 tiled with turned cells of random grey, ray-cast with
    4 x 4 samples a pixel (anti-aliased: edges move by fractions of a pixel)."""
    from robostereo.geometry.poses import as_se3

    w, h = camera.image_size
    k = 4
    off = (np.arange(k) + 0.5) / k - 0.5
    u, v = np.meshgrid((np.arange(w)[:, None] + off).ravel(),
                       (np.arange(h)[:, None] + off).ravel())
    cx, cy = camera.principal_point
    rays = np.stack([(u - cx) / camera.fx, (v - cy) / camera.fy, np.ones_like(u)], axis=-1)
    T = as_se3(pose)
    d = rays @ T.rotation.T
    s = -T.translation[2] / d[..., 2]
    p = T.translation + s[..., None] * d
    c, sn = np.cos(0.5), np.sin(0.5)  # cells turned: no edge along a whole row
    i = np.floor((c * p[..., 0] - sn * p[..., 1]) / cell_mm).astype(np.int64)
    j = np.floor((sn * p[..., 0] + c * p[..., 1]) / cell_mm).astype(np.int64)
    grey = ((i * 7919 + j * 104729 + (i * j) % 97) % 97).astype(float)  # per cell, fixed
    grey = grey.reshape(h, k, w, k).mean(axis=(1, 3))
    return np.rint(15 + grey).astype(np.uint8)


def _plane_capture(x_left: float, x_right: float, **kw):
    from robostereo.geometry.poses import SE3
    from robostereo.robot.capture import Capture

    cam = SEED_CAMERA
    poses = [SE3.look_at([x, 0.0, 1000.0], [x, 0.0, 0.0], up=(0.0, -1.0, 0.0))
             for x in (x_left, x_right)]
    return Capture(left=_render_plane(cam, poses[0]), right=_render_plane(cam, poses[1]),
                   camera=cam, pose_left=poses[0], pose_right=poses[1], **kw)


def test_views_that_share_no_scene_are_refused_naming_the_capture():
    """400 mm apart at 1 m the seed camera's views (350 mm wide there) share nothing;
    every rectified row is shared all the same, which the former check counted."""
    cap = _plane_capture(-200.0, 200.0, depth_range_mm=(900.0, 1100.0))
    with pytest.raises(InputError, match=r"^cap\.yaml: the two views share no scene"):
        locate(cap, source="cap.yaml")
    cap = _plane_capture(-200.0, 200.0, disparity_range=(540.0, 660.0))
    with pytest.raises(InputError, match="share no scene"):
        locate(cap)


def test_views_of_one_plane_locate_it_without_warnings():
    import warnings

    cap = _plane_capture(-15.0, 15.0, depth_range_mm=(900.0, 1100.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        located = locate(cap)
    assert len(located) > 0.3 * len(located.result.left_edges)
    # the plane z = 0: most points within their eq. 9 bound
    assert np.mean(np.abs(located.world[:, 2]) <= located.z_bound) > 0.9


def test_few_located_edge_points_warn():
    """The right pose's quaternion read in (w, x, y, z) order: the poses say something
    the images do not, and hardly any edge point finds a partner."""
    from dataclasses import replace

    from scipy.spatial.transform import Rotation

    from robostereo.errors import PlausibilityWarning
    from robostereo.geometry.poses import SE3

    good = _plane_capture(-15.0, 15.0, depth_range_mm=(900.0, 1100.0))
    x, y, z, w = good.pose_right.quaternion
    misread = SE3(Rotation.from_quat([w, x, y, z]).as_matrix(), good.pose_right.translation)
    bad = replace(good, pose_right=misread)
    with pytest.warns(PlausibilityWarning, match=r"^c\.yaml: only \d+ of \d+ edge points"):
        located = locate(bad, source="c.yaml")
    assert len(located) < 0.05 * len(located.result.left_edges)
