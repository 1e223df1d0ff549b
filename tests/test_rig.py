"""Tests for robostereo.rig: a synthetic calibrated rig with lens distortion, end to end.

The scene (left camera frame, millimetres) is a slanted textured background plane and a
nearer textured rectangle.  Each view is rendered exactly through the rig's distortion:
every original pixel is undistorted (OpenCV's model, iterated to 1e-12) into a ray, the
ray is intersected with the scene and the texture is read there.  The texture is vertical
stripes with smooth (Gaussian-blurred, sigma = 0.4 mm ~ 0.3 px) edges, so no aliasing.
"""

from __future__ import annotations

import re
from pathlib import Path

import cv2
import numpy as np
import pytest
from scipy.special import ndtr

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.geometry.calibrated_rectification import rectify_stereo
from robostereo.geometry.calibration import StereoCalibration
from robostereo.io.calibration_files import write_opencv_calibration
from robostereo.matcher.pipeline import MatchParameters
from robostereo.rig import disparity_range_for_depth, load_rig_pair, match_rig, valid_mask

W, H = 640, 480
K1 = np.array([[700.0, 0.0, 322.0], [0.0, 702.0, 236.0], [0.0, 0.0, 1.0]])
K2 = np.array([[705.0, 0.0, 316.0], [0.0, 703.0, 244.0], [0.0, 0.0, 1.0]])
D1 = np.array([-0.15, 0.06, 0.0008, -0.0006, 0.0])
D2 = np.array([-0.12, 0.04, -0.0005, 0.0007, 0.0])
R = cv2.Rodrigues(np.deg2rad([0.8, -2.0, 1.2]).reshape(3, 1))[0]
T = np.array([-60.0, 0.8, 1.5])  # x_right = R x_left + T, mm
DEPTH = (700.0, 1500.0)


def _stripes(rng: np.random.Generator, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    edges = np.cumsum(rng.uniform(11.0, 24.0, int((hi - lo) / 11.0) + 2)) + lo
    steps = rng.uniform(60.0, 90.0, edges.size) * rng.choice([-1.0, 1.0], edges.size)
    levels = np.empty(edges.size + 1)
    levels[0] = 128.0
    for i, s in enumerate(steps):  # keep the grey levels inside 30..225
        levels[i + 1] = levels[i] + (s if 30 <= levels[i] + s <= 225 else -s)
    return edges, levels


def _texture(u: np.ndarray, edges: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """Piecewise-constant stripes in u blurred by a Gaussian of 0.4 mm (exact, via ndtr)."""
    k = np.clip(np.searchsorted(edges, u), 1, edges.size - 1)
    near = np.where(np.abs(u - edges[k - 1]) < np.abs(u - edges[np.minimum(k, edges.size - 1)]),
                    k - 1, k)
    return levels[near] + (levels[near + 1] - levels[near]) * ndtr((u - edges[near]) / 0.4)


class Scene:
    """Background plane ``Z = 1200 + 0.25 X - 0.1 Y`` and a rectangle ``Z = 850``."""

    def __init__(self, rng: np.random.Generator) -> None:
        self.bg = _stripes(rng, -900.0, 900.0)
        self.fg = _stripes(rng, -400.0, 400.0)

    def cast(self, origin: np.ndarray, dirs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """First hit of each ray: points (N, 3) and grey levels (N,)."""
        o = np.broadcast_to(origin, dirs.shape)
        n = np.array([-0.25, 0.1, 1.0])  # background: n . P = 1200
        t_bg = (1200.0 - o @ n) / (dirs @ n)
        t_fg = (850.0 - o[:, 2]) / dirs[:, 2]
        p_fg = o + t_fg[:, None] * dirs
        in_fg = (p_fg[:, 0] > -260) & (p_fg[:, 0] < -20) & (np.abs(p_fg[:, 1]) < 140)
        fg = in_fg & (t_fg > 0) & (t_fg < t_bg)
        t = np.where(fg, t_fg, t_bg)
        p = o + t[:, None] * dirs
        u = p[:, 0] + 0.08 * p[:, 1]  # slightly slanted stripes
        grey = np.where(fg, _texture(u, *self.fg), _texture(u, *self.bg))
        return p, grey


def _rays(pixels: np.ndarray, K: np.ndarray, D: np.ndarray) -> np.ndarray:
    crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 100, 1e-12)
    n = cv2.undistortPoints(pixels.reshape(-1, 1, 2), K, D, criteria=crit).reshape(-1, 2)
    return np.column_stack([n, np.ones(len(n))])


def _centre_right() -> np.ndarray:
    return -R.T @ T  # right optical centre in the left frame


def render_pair(scene: Scene, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    yy, xx = np.mgrid[0:H, 0:W].astype(float)
    pix = np.column_stack([xx.ravel(), yy.ravel()])
    _, gl = scene.cast(np.zeros(3), _rays(pix, K1, D1))
    _, gr = scene.cast(_centre_right(), _rays(pix, K2, D2) @ R)  # R^T d, as rows
    out = []
    for g in (gl, gr):
        img = g.reshape(H, W) + rng.normal(0.0, 1.0, (H, W))
        out.append(np.clip(np.rint(img), 0, 255).astype(np.uint8))
    return out[0], out[1]


@pytest.fixture(scope="module")
def rig() -> StereoCalibration:
    return StereoCalibration(K1, D1, K2, D2, R, T, (W, H), source="rig.yml")


@pytest.fixture(scope="module")
def rendered() -> tuple[Scene, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(42)
    scene = Scene(rng)
    left, right = render_pair(scene, rng)
    return scene, left, right


@pytest.fixture(scope="module")
def result(rig, rendered):
    """The rig path with the default matcher.  This scene's slanted stripes of a few
    grey levels are periodic for census windows: without the paths along the rows the
    window method matched 5950 points here, 97.9 % within their bound; with them
    15458, 99.6 % (the seed's relaxation: 25667, 99.9 %)."""
    _, left, right = rendered
    return match_rig(left, right, rig, depth_range_mm=DEPTH,
                     params=MatchParameters())


def test_round_trip_recovers_the_scene(result, rendered) -> None:
    """Rectify, match, triangulate: recovered points within their eq. (9) bound.

    Tolerance: the calibration is exact (dD = ds = 0), so eq. (9) reduces to
    ``Z^2 d(disp) / (fx B)``; d(disp) = 0.5 px covers sub-pixel edge positions after one
    bilinear resampling (the core matcher's synthetic RMS is <= 0.1 px before
    resampling; measured here 0.14 px RMS, 99.5 % under 0.38 px).  At Z = 1200 mm
    that is 17 mm.  99 % of the points must be within it and the RMS (of the points
    within 50 mm) under 0.4 of it, i.e. 0.2 px of disparity.
    """
    scene, _, _ = rendered
    tab = result.table()
    n = len(tab["row"])
    assert n > 3000
    # truth: the ray through the original left pixel of each match
    orig = np.column_stack([tab["x_original"], tab["y_original"]])
    truth, _ = scene.cast(np.zeros(3), _rays(orig, K1, D1))
    xyz = np.column_stack([tab["X"], tab["Y"], tab["Z"]])
    # the reported 3-D point lies on that ray: projecting it gives the original pixel
    proj, _ = cv2.projectPoints(xyz, np.zeros(3), np.zeros(3), K1, D1)
    assert np.abs(proj.reshape(-1, 2) - orig).max() < 1e-6
    # leave out points whose truth is ambiguous: depth steps within 2 px, or hidden from
    # the right camera (occluded)
    steps = np.zeros(n, bool)
    for dx in (-2.0, 2.0):
        p2, _ = scene.cast(np.zeros(3), _rays(orig + np.array([dx, 0.0]), K1, D1))
        steps |= np.abs(p2[:, 2] - truth[:, 2]) > 20.0
    cr = _centre_right()
    to_p = truth - cr
    hit, _ = scene.cast(cr, to_p / np.linalg.norm(to_p, axis=1, keepdims=True))
    hidden = np.linalg.norm(hit - cr, axis=1) < np.linalg.norm(to_p, axis=1) - 1.0
    keep = ~steps & ~hidden
    assert keep.sum() > 0.9 * n
    dz = np.abs(xyz[keep, 2] - truth[keep, 2])
    bound = tab["z_bound"][keep]
    assert np.all(np.isfinite(bound)) and np.all(bound > 0)
    within = dz <= bound
    assert within.mean() >= 0.99, f"{within.mean():.4f} within the bound"
    rms = float(np.sqrt(np.mean(np.minimum(dz, 50.0) ** 2)))
    assert rms < 0.4 * float(np.median(bound)), (rms, float(np.median(bound)))
    dist = np.linalg.norm(xyz[keep] - truth[keep], axis=1)
    # the 3-D error is mostly along the ray: its median within a quarter of the bound
    assert np.median(dist) < 0.25 * float(np.median(bound))


def test_rectified_columns_and_depth_range(result, rig) -> None:
    tab = result.table()
    rect = result.rectification
    lo, hi = disparity_range_for_depth(rect, *DEPTH)
    # the range's rule: whole-pixel bounds, half a pixel outside kept
    assert np.all((tab["disparity"] >= lo - 0.5) & (tab["disparity"] <= hi + 0.5))
    np.testing.assert_allclose(tab["x_left"] - tab["x_right"], tab["disparity"], atol=1e-9)
    # hand check of eq. (8) through the one path: Z_rect = fx B / (d + doffs)
    xyz_rect = np.column_stack([tab["X"], tab["Y"], tab["Z"]]) @ rect.R1.T
    np.testing.assert_allclose(xyz_rect[:, 2],
                               rect.fx * rect.baseline_mm / (tab["disparity"] + rect.doffs))
    assert result.left_rectified.shape == (H, W)


def test_valid_mask_and_fill_border(rig) -> None:
    rect = rectify_stereo(rig, alpha=1.0)  # keeps every pixel: black fill at the borders
    m = valid_mask(rect, "left")
    assert 0.5 < m.mean() < 1.0 and not m[0, 0]
    # a uniform grey pair: the only edges are the fill's borders; none may be matched
    grey = np.full((H, W), 150, np.uint8)
    res = match_rig(grey, grey, rect, (0.0, 60.0))
    assert len(res) == 0 and len(res.match.left_edges) == 0


def test_size_mismatch_names_the_file(rig, rendered) -> None:
    _, left, right = rendered
    with pytest.raises(InputError, match=r"^right\.png: image is 639 x 480 .*rig\.yml"):
        match_rig(left, right[:, :-1], rig, (0, 60), names=("left.png", "right.png"))
    with pytest.raises(InputError, match="either a disparity range or a depth range"):
        match_rig(left, right, rig)


def test_cli_rig(tmp_path: Path, rig, rendered, capsys) -> None:
    _, left, right = rendered
    cal = write_opencv_calibration(rig, tmp_path / "rig.yml")
    cv2.imwrite(str(tmp_path / "l.png"), left)
    cv2.imwrite(str(tmp_path / "r.png"), right)
    out = tmp_path / "pts.csv"
    rc = main(["rig", str(tmp_path / "l.png"), str(tmp_path / "r.png"), "--calibration",
               str(cal), "--min-depth", "700", "--max-depth", "1500", "-o", str(out),
               "--ply", str(tmp_path / "pts.ply")])
    assert rc == 0
    assert re.search(rf"\d ms -> {re.escape(str(out))}\n", capsys.readouterr().out)
    head = out.read_text().splitlines()[0].split(",")
    assert head == ["row", "x_left", "x_right", "disparity", "confidence", "x_original",
                    "y_original", "X", "Y", "Z", "z_bound"]
    assert len(out.read_text().splitlines()) > 3000
    assert (tmp_path / "pts.ply").stat().st_size > 1000
    # a calibration for another image size: one line naming the image, exit 2, no output
    small = StereoCalibration(K1, D1, K2, D2, R, T, (W - 40, H), source="x")
    cal2 = write_opencv_calibration(small, tmp_path / "small.yml")
    out2 = tmp_path / "none.csv"
    rc = main(["rig", str(tmp_path / "l.png"), str(tmp_path / "r.png"), "--calibration",
               str(cal2), "--min-disparity", "0", "--max-disparity", "60", "-o", str(out2)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out2.exists()
    assert err[-1].startswith(f"robostereo: error: {tmp_path / 'l.png'}: image is 640 x 480")


@pytest.mark.parametrize("bad, msg", [
    ("K1: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 0]\n",
     "K1 must be invertible"),
    ("K1: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n  data: [.nan, 0, 0, 0, 1, 0, 0, 0, 1]\n",
     "K1 must be finite"),
])
def test_bad_calibration_matrix(tmp_path: Path, rig, bad: str, msg: str) -> None:
    good = write_opencv_calibration(rig, tmp_path / "good.yml").read_text()
    start = good.index("K1:")
    end = good.index("D1:")
    p = tmp_path / "bad.yml"
    p.write_text(good[:start] + bad + good[end:])
    img = tmp_path / "a.png"
    cv2.imwrite(str(img), np.zeros((H, W), np.uint8))
    with pytest.raises(InputError, match=rf"bad\.yml: {msg}"):
        load_rig_pair(img, img, p)


def test_middlebury_rig_is_used_as_it_is(tmp_path: Path) -> None:
    """An already rectified rig (calib.txt): no resampling, disparities keep doffs."""
    from robostereo.io.calibration_files import read_middlebury_calib

    p = tmp_path / "calib.txt"
    p.write_text("cam0=[700 0 320; 0 700 240; 0 0 1]\ncam1=[700 0 335; 0 700 240; 0 0 1]\n"
                 "doffs=15\nbaseline=100\nwidth=640\nheight=480\nndisp=64\n")
    calib = read_middlebury_calib(p).calibration
    rng = np.random.default_rng(5)
    row = np.repeat(rng.integers(30, 220, 80), 8)[:W].astype(np.uint8)
    left = np.tile(row, (H, 1))
    right = np.roll(left, -20, axis=1)  # d = 20 px: Z = 700 * 100 / (20 + 15) = 2000 mm
    res = match_rig(left, right, calib, (10.0, 30.0))
    assert np.array_equal(res.left_rectified, left) and res.rectification.doffs == 15.0
    tab = res.table()
    inner = (tab["x_left"] > 40) & (tab["x_left"] < W - 40)
    assert inner.sum() > 1000
    np.testing.assert_allclose(tab["Z"][inner], 2000.0, rtol=2e-3)
    np.testing.assert_allclose(tab["x_original"], tab["x_left"], atol=1e-9)


def test_cli_rig_writes_points_in_the_robot_base_frame(tmp_path: Path, rig, rendered,
                                                       capsys) -> None:
    import yaml

    from robostereo.geometry.camera import camera_to_dict
    from robostereo.geometry.poses import pose_to_dict
    from robostereo.robot.simulated.cell_handeye import BASE_CAMERA, CELL_CAMERA

    scene, left, right = rendered
    cal = write_opencv_calibration(rig, tmp_path / "rig.yml")
    cv2.imwrite(str(tmp_path / "l.png"), left)
    cv2.imwrite(str(tmp_path / "r.png"), right)
    cell = tmp_path / "cell.yaml"  # the left camera in the simulated cell's base frame
    cell.write_text(yaml.safe_dump({"mode": "eye-to-hand", "camera": camera_to_dict(CELL_CAMERA),
                                    "base_camera": pose_to_dict(BASE_CAMERA)}))
    out = tmp_path / "pts.csv"
    argv = ["rig", str(tmp_path / "l.png"), str(tmp_path / "r.png"), "--calibration", str(cal),
            "--min-depth", "700", "--max-depth", "1500", "-o", str(out)]
    assert main([*argv, "--base-camera", str(cell), "--ply", str(tmp_path / "b.ply")]) == 0
    assert re.search(r"\d ms \(also in the base frame\) -> ", capsys.readouterr().out)
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert data.dtype.names[-3:] == ("X_base", "Y_base", "Z_base") and data.size > 3000
    xyz = np.column_stack([data["X"], data["Y"], data["Z"]])
    base = np.column_stack([data["X_base"], data["Y_base"], data["Z_base"]])
    # the truth: the scene point behind each matched left pixel, in the base frame
    pix = np.column_stack([data["x_original"], data["y_original"]])
    rays = _rays(pix, K1, D1)
    truth, _ = scene.cast(np.zeros(3), rays)
    err = np.linalg.norm(base - BASE_CAMERA.apply(truth), axis=1)
    assert np.allclose(base, BASE_CAMERA.apply(xyz), atol=0.02)  # the CSV: 6 digits
    assert np.median(err) < np.median(data["z_bound"]) and np.mean(err < 3 * data["z_bound"]) > 0.95
    # not an eye-to-hand file, or a camera of another size: one line, nothing written
    hand = tmp_path / "hand.yaml"
    hand.write_text(yaml.safe_dump({"camera": camera_to_dict(CELL_CAMERA),
                                    "hand_eye": pose_to_dict(BASE_CAMERA)}))
    out2 = tmp_path / "none.csv"
    argv[-1] = str(out2)
    assert main([*argv, "--base-camera", str(hand)]) == 2
    assert "an eye-in-hand calibration (hand_eye)" in capsys.readouterr().err
    small = camera_to_dict(CELL_CAMERA)
    small["image_size"] = [320, 240]
    cell.write_text(yaml.safe_dump({"camera": small, "base_camera": pose_to_dict(BASE_CAMERA)}))
    assert main([*argv, "--base-camera", str(cell)]) == 2
    assert "image size 320 x 240 is not the rig's 640 x 480" in capsys.readouterr().err
    assert not out2.exists()
