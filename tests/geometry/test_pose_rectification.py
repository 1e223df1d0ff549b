"""Tests for robostereo.geometry.pose_rectification: general-pose rectification
(stereoRectify) and its agreement with the thesis's theta path."""

from __future__ import annotations

import numpy as np
import pytest
import yaml
from scipy.spatial import cKDTree

from robostereo.errors import InputError
from robostereo.experiments import RigSetup, simulate_capture
from robostereo.geometry.camera import Camera
from robostereo.geometry.pose_rectification import GeneralEpipolarGeometry
from robostereo.geometry.poses import SE3, as_se3
from robostereo.robot.capture import (
    Capture,
    LocateParameters,
    locate,
    locate_capture,
    read_capture,
    write_capture,
)

CAM = Camera(image_size=(320, 240), pixel_pitch_mm=(0.01, 0.012),
             distortion=(-0.15, 0.05, 0.001, -0.0005, 0.0))


def _poses() -> tuple[SE3, SE3]:
    a = SE3.look_at([-20.0, -380.0, 700.0], [0.0, 0.0, 0.0])
    b = SE3.look_at([18.0, -360.0, 690.0], [5.0, 3.0, 0.0], up=(0.05, 1.0, 0.0))
    return a, b


def test_points_land_on_one_row_with_positive_disparity():
    a, b = _poses()
    g = GeneralEpipolarGeometry.from_poses(CAM, a, b)
    rng = np.random.default_rng(0)
    P = rng.uniform([-40, -40, 0], [40, 40, 60], (50, 3))
    pl = g.to_rectified(CAM.project(P, a)[0], "left")
    pr = g.to_rectified(CAM.project(P, b)[0], "right")
    assert np.abs(pl[:, 1] - pr[:, 1]).max() < 1e-6
    d = pl[:, 0] - pr[:, 0]
    assert (d > 0).all()
    # eq. 8 in the epipolar frame, then to the world: the points come back
    K = g.K_rect
    Z = K[0, 0] * g.baseline_mm / d
    X = (g.baseline_mm / 2) * ((pl[:, 0] - K[0, 2]) + (pr[:, 0] - K[0, 2])) / d
    Y = g.baseline_mm * (K[0, 0] / K[1, 1]) * (pl[:, 1] - K[1, 2]) / d
    assert np.allclose(g.to_world(np.column_stack([X, Y, Z])), P, atol=1e-6)
    # the distorted pixel map inverts
    uv = CAM.project(P, a)[0]
    assert np.allclose(g.from_rectified(g.to_rectified(uv, "left"), "left"), uv, atol=1e-6)


def test_baseline_along_columns_is_turned_to_rows():
    """A camera moved along its image's y axis (OpenCV would rectify to columns)."""
    a = SE3.look_at([0.0, 0.0, 700.0], [0.0, 0.0, 0.0])
    b = SE3(a.rotation, a.translation + 25.0 * a.rotation[:, 1])
    g = GeneralEpipolarGeometry.from_poses(CAM, a, b)
    P = np.array([[10.0, 5.0, 0.0], [-20.0, 12.0, 30.0]])
    pl = g.to_rectified(CAM.project(P, a)[0], "left")
    pr = g.to_rectified(CAM.project(P, b)[0], "right")
    assert np.allclose(pl[:, 1], pr[:, 1], atol=1e-6) and (pl[:, 0] > pr[:, 0]).all()


def test_zero_baseline_and_no_overlap():
    a, _ = _poses()
    with pytest.raises(InputError, match="coincide"):
        GeneralEpipolarGeometry.from_poses(CAM, a, a)
    far = SE3(a.rotation, a.translation + 2000.0 * a.rotation[:, 0])
    turned = far @ SE3.from_rotvec([0, 0, 0], [0.0, 1.2, 0.0])
    with pytest.raises(InputError, match="do not overlap"):
        GeneralEpipolarGeometry.from_poses(CAM, a, turned).check_overlap()


@pytest.fixture(scope="module")
def scara_captures():
    setup = RigSetup(direction_deg=35.0, roll_deg=10.0)
    return {lift: simulate_capture("block", setup=setup, lift_mm=lift, seed=0)
            for lift in (0.0, 79.65)}


def test_scara_captures_agree_on_both_paths(scara_captures):
    """The seed's theta rectification and the general (stereoRectify) path on the same
    SCARA captures: the same edge points, the same world points to well inside eq. 9."""
    tops = {}
    for lift, sim in scara_captures.items():
        top = 50.0 + lift
        a = locate(sim.capture, params=LocateParameters(rectification="theta"))
        b = locate(sim.capture, params=LocateParameters(rectification="general"))
        assert len(a) > 200 and abs(len(a) - len(b)) <= 0.05 * len(a)
        dist, idx = cKDTree(b.left_pixel).query(a.left_pixel)
        same = dist < 0.3
        assert same.mean() > 0.5
        dz = a.world[same, 2] - b.world[idx[same], 2]
        # one edge point, two resamplings: the depths differ by much less than the bound
        assert np.abs(dz).max() < 0.2 * np.median(a.z_bound)
        assert abs(dz.mean()) < 0.05
        for name, L in (("theta", a), ("general", b)):
            m = np.abs(L.world[:, 2] - top) < 8
            assert (np.abs(L.world[m, 2] - top) <= L.z_bound[m]).all()
            tops[name, lift] = L.world[m, 2].mean()
    for name in ("theta", "general"):
        assert tops[name, 79.65] - tops[name, 0.0] == pytest.approx(79.65, abs=0.5)
    assert tops["theta", 0.0] == pytest.approx(tops["general", 0.0], abs=0.05)


def test_capture_yaml_general_forms(scara_captures, tmp_path):
    """A SCARA capture rewritten with 6-DoF camera poses, and as flange poses plus a
    hand-eye transform, locates the same points."""
    sim = scara_captures[0.0]
    cap = sim.capture
    ref = locate(cap, params=LocateParameters(rectification="general"))
    d6 = tmp_path / "six"
    six = Capture(left=cap.left, right=cap.right, camera=cap.camera,
                  pose_left=as_se3(cap.pose_left), pose_right=as_se3(cap.pose_right),
                  bit_depth=cap.bit_depth, depth_range_mm=cap.depth_range_mm)
    write_capture(d6, six)
    data = yaml.safe_load((d6 / "capture.yaml").read_text())
    assert set(data["pose_left"]) == {"position", "quaternion"}
    he = SE3.from_rotvec([3.0, -40.0, 120.0], [0.1, -0.2, 0.3])
    dfl = tmp_path / "flange"
    write_capture(dfl, Capture.from_flange(
        flange_left=as_se3(cap.pose_left) @ he.inv(),
        flange_right=as_se3(cap.pose_right) @ he.inv(),
        hand_eye=he, left=cap.left, right=cap.right, camera=cap.camera,
        bit_depth=cap.bit_depth, depth_range_mm=cap.depth_range_mm))
    data = yaml.safe_load((dfl / "capture.yaml").read_text())
    assert {"flange_left", "flange_right", "hand_eye"} <= set(data) and "pose_left" not in data
    assert not read_capture(dfl).is_scara
    for d in (d6, dfl):
        L = locate_capture(d)
        assert len(L) == len(ref)
        assert np.allclose(L.world, ref.world, atol=1e-3)
    # both forms at once is refused
    data["pose_left"] = {"x": 0, "y": 0, "z": 1000}
    (dfl / "capture.yaml").write_text(yaml.safe_dump(data))
    with pytest.raises(InputError, match="not both"):
        read_capture(dfl)


def test_bad_six_dof_capture_files(scara_captures, tmp_path, capsys):
    """Non-orthonormal rotations and coinciding optical centres: one line, exit 2."""
    from robostereo.cli import main

    cap = scara_captures[0.0].capture
    d = tmp_path / "c"
    write_capture(d, Capture(left=cap.left, right=cap.right, camera=cap.camera,
                             pose_left=as_se3(cap.pose_left),
                             pose_right=as_se3(cap.pose_right), bit_depth=cap.bit_depth,
                             depth_range_mm=cap.depth_range_mm))
    good = yaml.safe_load((d / "capture.yaml").read_text())
    for change, message in (
        ({"pose_right": {"matrix": np.diag([1.0, 1.0, 1.2, 1.0]).tolist()}}, "orthonormal"),
        ({"pose_right": good["pose_left"]}, "coincide"),
        ({"pose_right": {"position": [0, 0, 0], "quaternion": [0, 0, 1, 1]}}, "norm 1"),
    ):
        (d / "capture.yaml").write_text(yaml.safe_dump({**good, **change}))
        assert main(["locate", str(d)]) == 2
        err = capsys.readouterr().err
        assert err.startswith("robostereo: error: ") and message in err and err.count("\n") == 1
        assert not (d / "located.csv").exists()


def _turned_pair(turn_deg: float) -> tuple[Camera, SE3, SE3]:
    """Two views 60 mm apart, the right one turned `turn_deg` about its optical axis (as
    DTU's neighbouring views turn 27 deg), both looking at the origin 700 mm away."""
    cam = Camera(image_size=(320, 240), pixel_pitch_mm=(0.02, 0.02))
    a = SE3.look_at([-30.0, -100.0, 700.0], [0.0, 0.0, 0.0])
    b = SE3.look_at([30.0, -100.0, 700.0], [0.0, 0.0, 0.0])
    b = b @ SE3.from_rotvec([0.0, 0.0, 0.0], [0.0, 0.0, np.radians(turn_deg)])
    return cam, a, b


def _share_in_frames(g: GeneralEpipolarGeometry, cam: Camera, a: SE3, b: SE3) -> float:
    """Share of the left pixels the right view sees at 650 mm that lie inside both
    rectified frames' valid areas."""
    w, h = cam.image_size
    u, v = np.meshgrid(np.arange(2.0, w - 2, 4.0), np.arange(2.0, h - 2, 4.0))
    pix = np.column_stack([u.ravel(), v.ravel()])
    uv, _ = cam.project(cam.backproject(pix, np.full(len(pix), 650.0), a), b)
    seen = (uv[:, 0] >= 0) & (uv[:, 0] <= w - 1) & (uv[:, 1] >= 0) & (uv[:, 1] <= h - 1)
    inside = np.ones(len(pix), dtype=bool)
    for side, p in (("left", pix), ("right", uv)):
        mask = g.valid_mask(side)
        ij = np.rint(g.to_rectified(p, side)).astype(int)
        ok = (ij[:, 0] >= 0) & (ij[:, 0] < mask.shape[1]) & (ij[:, 1] >= 0) \
            & (ij[:, 1] < mask.shape[0])
        ok[ok] = mask[ij[ok, 1], ij[ok, 0]]
        inside &= ok
    return float(inside[seen].mean())


def test_rectified_frames_hold_every_pixel_both_views_see_when_a_view_is_turned():
    cam, a, b = _turned_pair(27.0)
    g = GeneralEpipolarGeometry.from_poses(cam, a, b)
    kept = GeneralEpipolarGeometry.from_poses(cam, a, b, frame="camera")
    assert _share_in_frames(g, cam, a, b) >= 0.995
    assert _share_in_frames(kept, cam, a, b) <= 0.9  # the camera's frame cuts corners off
    # the pixel scale is the camera's; the frame grows, within its clip
    assert g.K_rect[0, 0] == cam.fx and g.K_rect[1, 1] == cam.fy
    w, h = g.size_rect
    assert cam.width < w <= 2 * cam.width and h <= 2 * cam.height
    # a point still lands on one row of both frames, at its disparity
    P = np.array([[5.0, -8.0, 40.0]])
    pl = g.to_rectified(cam.project(P, a)[0], "left")
    pr = g.to_rectified(cam.project(P, b)[0], "right")
    assert abs(pl[0, 1] - pr[0, 1]) < 1e-6
    Z = g.K_rect[0, 0] * g.baseline_mm / (pl[0, 0] - pr[0, 0])
    assert Z == pytest.approx(g.from_world(P)[0, 2], rel=1e-9)


def test_rectified_frame_of_views_that_are_not_turned_is_the_shared_rows():
    """Two views side by side, not turned: the rows are the camera's, the columns
    widen by the disparity at infinity (zero) plus the turn stereoRectify adds (none)."""
    cam, a, b = _turned_pair(0.0)
    g = GeneralEpipolarGeometry.from_poses(cam, a, b)
    w, h = g.size_rect
    assert abs(h - cam.height) <= 40 and w >= cam.width
    with pytest.raises(InputError, match="frame"):
        GeneralEpipolarGeometry.from_poses(cam, a, b, frame="image")
