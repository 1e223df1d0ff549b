"""``robostereo evaluate`` on capture folders with ground-truth depth maps."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml
from view_renders import RenderSpec, render_views, write_with_depth

from robostereo.cli import main
from robostereo.evaluation import (
    CapturePoints,
    depth_errors,
    shared_edge_pixels,
    write_depth_map,
)

#: the tests' print-textured box, 400 mm away
_SPEC = RenderSpec(texture="print", count=2, span_mm=40.0, jitter_deg=0.0, jitter_mm=0.0)


@pytest.fixture(scope="module")
def renders(tmp_path_factory):
    cap, truth = render_views(_SPEC)
    return cap, truth, tmp_path_factory.mktemp("depth_captures")


@pytest.fixture(scope="module")
def two_view(renders) -> Path:
    cap, truth, root = renders
    return write_with_depth(root / "two", cap, truth, two_view=True, keys=True)


def _json(capsys, *args: str) -> list[dict]:
    assert main(["evaluate", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _method(ev: dict, name: str) -> dict:
    return next(m for m in ev["methods"] if m["method"] == name)


def test_a_rendered_capture_is_located_within_half_a_millimetre_of_its_depth_map(
        two_view: Path, capsys) -> None:
    (ev,) = _json(capsys, str(two_view))
    assert ev["kind"] == "capture" and ev["reference"] == "left.png"
    ours, sgbm = _method(ev, "robostereo"), _method(ev, "sgbm")
    # measured: median 0.31 mm, p95 1.07 mm, 94 % within 1 mm, coverage 83.7 %
    assert ours["points"] > 5000 and ours["with_truth"] == ours["points"]
    assert ours["median_mm"] < 0.6 and ours["p95_mm"] < 2.5
    assert ours["within_1mm"] > 0.85 and ours["beyond_5mm"] < 0.01
    assert ours["within_bound"] > 0.9
    assert 0.6 < ours["coverage"] <= 1.0 and ours["edges"] > 10000
    # SGBM at the same edge pixels: measured median 1.18 mm (its disparities lock to
    # whole pixels on the flat ground), coverage 98.4 %
    assert sgbm["edges"] == ours["edges"] and 0.9 < sgbm["coverage"] <= 1.0
    assert 0.3 < sgbm["median_mm"] < 3.0 and sgbm["within_bound"] is None


def test_a_capture_whose_pose_is_off_scores_a_larger_error(
        two_view: Path, tmp_path: Path, capsys) -> None:
    off = shutil.copytree(two_view, tmp_path / "off")
    data = yaml.safe_load((off / "capture.yaml").read_text())
    data["pose_right"]["position"][0] -= 2.0  # baseline 42 mm where the views were 40 apart
    (off / "capture.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    (good,) = _json(capsys, str(two_view), "--no-sgbm")
    (bad,) = _json(capsys, str(off), "--no-sgbm")
    g, b = _method(good, "robostereo"), _method(bad, "robostereo")
    # depth scales with the baseline: 5 % of ~420 mm, about 20 mm
    assert b["median_mm"] > 10.0 > 20 * g["median_mm"]
    assert b["within_bound"] < 0.1 and len(bad["methods"]) == 1


def test_the_table_has_a_row_per_method_and_plots_are_written(
        two_view: Path, tmp_path: Path, capsys) -> None:
    assert main(["evaluate", str(two_view), "--plot", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "reference left.png (paired with right.png)" in out
    rows = [line.split() for line in out.splitlines() if line.startswith("  ")]
    assert [r[0] for r in rows] == ["method", "robostereo", "SGBM"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["two_coverage.png",
                                                           "two_depth_errors.png"]


def test_n_view_capture_is_scored_from_its_central_view(renders, capsys) -> None:
    cap, truth = render_views(RenderSpec(texture="print", count=3, span_mm=40.0))
    d = write_with_depth(renders[2] / "three", cap, truth, suffix=".png", keys=True,
                         depth_scale=10.0)
    (ev,) = _json(capsys, str(d))
    assert ev["reference"] == "1 (view_01.png)"
    ours, sgbm = _method(ev, "robostereo"), _method(ev, "sgbm")
    assert ours["median_mm"] < 0.6 and 0.6 < ours["coverage"] <= 1.0
    assert sgbm["coverage"] > 0.9 and sgbm["median_mm"] < 4.0


def test_a_simulated_scara_capture_scores_against_its_rendered_depth(
        tmp_path: Path, capsys) -> None:
    from robostereo.robot.capture import write_capture
    from robostereo.robot.simulated.scara_rig import simulate_capture

    sim = simulate_capture("block")
    d = write_capture(tmp_path / "block", sim.capture)
    (d / "depth").mkdir()
    for side, r in zip(("left", "right"), sim.renderings, strict=True):
        write_depth_map(d / "depth" / f"{side}.npy", r.depth)
    (ev,) = _json(capsys, str(d))
    ours, sgbm = _method(ev, "robostereo"), _method(ev, "sgbm")
    assert ours["points"] > 100 and ours["median_mm"] < 2.0
    assert 0.3 < ours["coverage"] <= 1.0 and sgbm["coverage"] > 0


def _one_error(capsys, text: str) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and text in err[0], err
    return err[0]


def test_a_depth_map_of_another_size_is_refused_naming_it(
        two_view: Path, tmp_path: Path, capsys) -> None:
    d = shutil.copytree(two_view, tmp_path / "small")
    write_depth_map(d / "depth" / "left.pfm", np.ones((48, 64)))
    assert main(["evaluate", str(d), "--json"]) == 2
    _one_error(capsys, "depth/left.pfm: the depth map is 64 x 48 pixels, the camera's "
                       "image_size is 640 x 480")


def test_a_missing_depth_map_is_refused_naming_it(
        two_view: Path, tmp_path: Path, capsys) -> None:
    d = shutil.copytree(two_view, tmp_path / "gone")
    (d / "depth" / "right.pfm").unlink()
    assert main(["evaluate", str(d)]) == 2
    _one_error(capsys, "depth/right.pfm: depth map not found")
    shutil.rmtree(d / "depth")
    data = yaml.safe_load((d / "capture.yaml").read_text())
    del data["depth_left"], data["depth_right"]
    (d / "capture.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    assert main(["evaluate", str(d)]) == 2
    _one_error(capsys, "capture.yaml: no depth map for the reference view left.png")


@pytest.mark.parametrize("flag", [["--scale", "4"], ["--no-curves"], ["--rule", "silhouette"],
                                  ["--min-disparity", "10", "--max-disparity", "40"]])
def test_scene_options_with_only_capture_folders_are_refused_naming_them(
        two_view: Path, capsys, flag) -> None:
    assert main(["evaluate", str(two_view), *flag]) == 2
    named = [f for f in flag if f.startswith("--")]
    _one_error(capsys, f"{', '.join(named)}: for scene folders with ground-truth disparities")


def test_point_errors_are_measured_on_the_true_surface(renders) -> None:
    cap, truth, _ = renders
    cam, pose, depth = cap.camera, cap.poses[0], truth.renderings[0].depth
    pix = np.array([[320.0, 240.0], [100.0, 400.0]])
    world = cam.backproject(pix, depth[[240, 400], [320, 100]], pose)
    axis = pose.rotation[:, 2]
    e = depth_errors(pix, world + 3.0 * axis, cam, pose, depth)  # 3 mm deeper
    np.testing.assert_allclose(e["depth_error_mm"], 3.0, atol=0.2)
    assert (e["error_mm"] >= 2.5).all() and (e["error_mm"] <= 3.5).all()
    pts = CapturePoints(pix, world)
    assert len(pts) == 2
    edges = shared_edge_pixels(cap.images[0], depth, cam, pose, cap.poses[1],
                               truth.renderings[1].depth, bit_depth=8)
    # all of them with truth, each seen by the other view
    assert len(edges) > 1000
    assert np.isfinite(depth[edges[:, 1].astype(int), edges[:, 0].astype(int)]).all()


def test_capture_depth_maps_writes_what_evaluate_reads(tmp_path: Path, capsys) -> None:
    """``robostereo capture --depth-maps`` then ``robostereo evaluate``: no files needed."""
    cap = tmp_path / "cap"
    assert main(["capture", "--out", str(cap), "--depth-maps"]) == 0
    assert sorted(p.name for p in (cap / "depth").iterdir()) == ["left.npy", "right.npy"]
    depth = np.load(cap / "depth" / "left.npy")
    assert depth.shape == (481, 509) and 900 < np.nanmedian(depth) < 1100
    capsys.readouterr()
    ev = _json(capsys, str(cap))[0]
    ours = _method(ev, "robostereo")
    assert ours["points"] > 100 and ours["median_mm"] < 1.5
    # without the flag, no depth folder and evaluate refuses in one line
    plain = tmp_path / "plain"
    assert main(["capture", "--out", str(plain)]) == 0
    assert not (plain / "depth").exists()
    capsys.readouterr()
    assert main(["evaluate", str(plain)]) == 2
    _one_error(capsys, "no depth map for the reference view left.png")
