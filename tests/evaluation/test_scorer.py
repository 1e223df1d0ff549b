"""Tests for the scene evaluation (robostereo.evaluation.scorer) and ``robostereo evaluate``."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import cv2
import numpy as np
import pytest
from synthetic import synthetic_pair

from robostereo.cli import main
from robostereo.datasets import load_scene
from robostereo.evaluation import (
    errors_3d,
    evaluate_scene,
    format_evaluation,
    nearest_ground_truth,
    sample_dense,
    score_matches,
    sgbm_disparity,
)
from robostereo.geometry.triangulation import StereoCamera
from robostereo.io.images import write_pfm
from robostereo.matcher.pipeline import match_stereo

F, B, DOFFS = 1000.0, 150.0, 12.0


@pytest.mark.parametrize("name", ["tsukuba", "venus"])
def test_real_scene_figures_match_the_core_tests(real_scenes, name) -> None:
    """The same figures as tests/test_real_scenes.py computes by hand."""
    scene = real_scenes[name]
    ev = evaluate_scene(scene)
    ours, sgbm = ev.methods
    res = match_stereo(scene.left, scene.right, scene.disparity_range)
    e = res.left_edges
    ref = score_matches(e.row, e.x, res.accepted_disparity(), scene.gt_disparity)
    dense = sgbm_disparity(scene.left, scene.right, scene.disparity_range)
    ref_sg = score_matches(e.row, e.x, sample_dense(dense, e.row, e.x), scene.gt_disparity)
    assert (ours.counted, ours.matched, ours.false) == (ref.counted, ref.matched, ref.false)
    assert (sgbm.counted, sgbm.matched, sgbm.false) == (ref_sg.counted, ref_sg.matched,
                                                        ref_sg.false)
    assert ours.rms_px == pytest.approx(ref.rms)
    assert ev.edges_left == len(e) and ours.counted > 1000
    assert ours.matched_percent >= 80.0 and ours.false_percent < sgbm.false_percent
    assert ours.seconds > 0 and sgbm.seconds > 0 and ours.rms_3d_mm is None
    text = format_evaluation(ev)
    assert f"{ours.matched_percent:6.1f} %" in text and "SGBM" in text
    # the curves: robostereo's from the best match of every edge point, SGBM's sweep
    curve = ev.curves["robostereo"]
    assert np.all(np.diff(curve.coverage) > 0) and np.all(np.diff(curve.threshold) <= 0)
    assert curve.coverage[-1] == pytest.approx(
        np.isfinite(res.edge_disparity[np.isfinite(scene.gt_disparity[
            e.row, np.clip(np.rint(e.x).astype(int), 0, scene.shape[1] - 1)])]).sum()
        / ours.counted)
    assert len(ev.curves["sgbm"].coverage) == 26
    # the default operating point lies on robostereo's curve
    at = curve.coverage[curve.threshold >= res.parameters.acceptance]
    assert at.max() == pytest.approx(ours.matched / ours.counted)
    assert "coverage at" in text and "(confidence swept)" in text


def test_nearest_ground_truth_is_the_rule_s_reference(real_scenes) -> None:
    scene = real_scenes["venus"]
    res = match_stereo(scene.left, scene.right, scene.disparity_range)
    e = res.left_edges
    d = res.accepted_disparity()
    gt = nearest_ground_truth(e.row, e.x, d, scene.gt_disparity)
    s = score_matches(e.row, e.x, d, scene.gt_disparity)
    good = np.isfinite(gt) & (np.abs(d - gt) <= 1.0)
    assert good.sum() == s.matched - s.false
    assert np.sqrt(np.mean((d[good] - gt[good]) ** 2)) == pytest.approx(s.rms)


def test_errors_3d_by_hand() -> None:
    cam = StereoCamera(F, F, B, cx=100.0, cy=50.0, doffs=DOFFS)
    # Z = f B / (d + doffs): d = 18 -> 5000 mm, d = 13 -> 6000 mm; at x = 100 + 30, y = 50
    # X = (x - cx) Z / f: 150 and 180 mm, so |dP| = sqrt(1000^2 + 30^2)
    e = errors_3d(cam, [50], [130.0], [18.0], [13.0], (100, 200))
    assert e[0] == pytest.approx(np.hypot(1000.0, 30.0))


def _middlebury(tmp: Path, rng: np.random.Generator) -> Path:
    left, right, gt = synthetic_pair(rng)
    d = tmp / "synth2014"
    d.mkdir()
    cv2.imwrite(str(d / "im0.png"), left)
    cv2.imwrite(str(d / "im1.png"), right)
    write_pfm(d / "disp0.pfm", np.where(np.isfinite(gt), gt, np.inf).astype(np.float32))
    h, w = gt.shape
    (d / "calib.txt").write_text(
        f"cam0=[{F} 0 150; 0 {F} 60; 0 0 1]\ncam1=[{F} 0 {150 + DOFFS}; 0 {F} 60; 0 0 1]\n"
        f"doffs={DOFFS}\nbaseline={B}\nwidth={w}\nheight={h}\nndisp=32\n"
    )
    return d


def test_middlebury_calib_gives_3d_errors(tmp_path: Path, rng) -> None:
    """3-D errors of correct matches: dZ = Z * dd / (d + doffs) with d + doffs ~ 19..24,
    Z = f B / (d + doffs) ~ 6..8 m; the core's synthetic RMS <= 0.1 px bounds the 3-D
    RMS by about 0.1 * 8000 / 19 = 42 mm."""
    scene = load_scene(_middlebury(tmp_path, rng))
    assert scene.calib is not None
    ev = evaluate_scene(scene)
    ours, sgbm = ev.methods
    assert ours.matched_percent > 80.0 and ours.false == 0
    assert ours.rms_3d_mm is not None and 0 < ours.median_3d_mm <= ours.rms_3d_mm < 45.0
    assert sgbm.rms_3d_mm is not None
    z_max = F * B / (7.3 + DOFFS)
    assert ours.rms_3d_mm <= 1.05 * ours.rms_px * z_max / (7.3 + DOFFS)
    assert "3-D RMS mm" in format_evaluation(ev)


def test_cli_evaluate_glob_as_a_newcomer_runs_it(data_dir: Path, capsys) -> None:
    args = sorted(str(p) for p in data_dir.iterdir())  # README.md, scenes.json, scenes
    assert main(["evaluate", *args, "--no-curves"]) == 0
    cap = capsys.readouterr()
    assert "skipping" in cap.err and "README.md" in cap.err
    assert "tsukuba: 384 x 288 px" in cap.out and "venus: 434 x 383 px" in cap.out
    assert main(["evaluate", str(data_dir / "tsukuba"), "--json", "--no-sgbm"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc[0]["scene"] == "tsukuba" and list(doc[0]["methods"]) == ["robostereo"]
    assert doc[0]["methods"]["robostereo"]["matched_percent"] >= 80.0
    assert set(doc[0]["coverage_at_false"]["robostereo"]) == {"2%", "3%", "5%"}


def test_cli_evaluate_plots_curves_and_checks_options(data_dir: Path, tmp_path: Path,
                                                     capsys) -> None:
    assert main(["evaluate", str(data_dir / "venus"), "--plot", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "SGBM" in out and "left-right check" in out
    png = tmp_path / "venus_curves.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # a lower acceptance matches more, on the same curve
    assert main(["evaluate", str(data_dir / "venus"), "--no-sgbm", "--json",
                 "--min-confidence", "0.5"]) == 0
    lo = json.loads(capsys.readouterr().out)[0]["methods"]["robostereo"]["matched"]
    assert main(["evaluate", str(data_dir / "venus"), "--no-sgbm", "--json"]) == 0
    hi = json.loads(capsys.readouterr().out)[0]["methods"]["robostereo"]["matched"]
    assert lo > hi
    assert main(["evaluate", str(data_dir / "venus"), "--plot", str(tmp_path / "no")]) == 2
    assert "--plot" in capsys.readouterr().err


def test_cli_evaluate_rule_silhouette_forgives_what_the_project_rule_calls_false(
        data_dir: Path, capsys) -> None:
    """The silhouette rule looks at every pixel of the row within 2 px of the edge, a
    superset of the project's three: the same points counted and matched, no more
    false, and on reindeer (occluding contours matched with the nearer surface) fewer."""
    docs = {}
    for rule in ("project", "silhouette"):
        assert main(["evaluate", str(data_dir / "reindeer"), "--no-sgbm", "--json",
                     "--rule", rule]) == 0
        docs[rule] = json.loads(capsys.readouterr().out)[0]
        assert docs[rule]["rule"] == rule
    p, s = (docs[r]["methods"]["robostereo"] for r in ("project", "silhouette"))
    assert (p["counted"], p["matched"]) == (s["counted"], s["matched"])
    assert s["false"] < p["false"]
    cp, cs = (docs[r]["coverage_at_false"]["robostereo"] for r in ("project", "silhouette"))
    assert all(cs[k] >= cp[k] for k in cp)
    with pytest.raises(SystemExit) as stop:
        main(["evaluate", str(data_dir / "reindeer"), "--rule", "fair"])
    assert stop.value.code == 2 and "--rule" in capsys.readouterr().err


def test_cli_evaluate_bad_scene_reports_and_goes_on(tmp_path: Path, data_dir: Path,
                                                    capsys) -> None:
    bad = tmp_path / "tsukuba"
    shutil.copytree(data_dir / "tsukuba", bad)
    gt = cv2.imread(str(bad / "gt_disp_left.pgm"), cv2.IMREAD_UNCHANGED)
    cv2.imwrite(str(bad / "gt_disp_left.pgm"), gt[:, :-5])
    empty = tmp_path / "empty"
    empty.mkdir()
    rc = main(["evaluate", str(bad), str(empty), str(data_dir / "venus")])
    cap = capsys.readouterr()
    errs = [ln for ln in cap.err.splitlines() if ln.startswith("robostereo: error:")]
    assert rc == 2 and len(errs) == 2
    assert "gt_disp_left.pgm: ground truth is 379 x 288 (W x H)" in errs[0]
    assert str(empty) in errs[1] and "no known stereo layout" in errs[1]
    assert "venus: 434 x 383 px" in cap.out  # the good scene is still evaluated
    assert main(["evaluate", str(tmp_path / "nothing.txt")]) == 2
