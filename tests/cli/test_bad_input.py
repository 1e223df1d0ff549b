"""Regression tests of the faults found with bad input, each fixed.

Every case ends in an :class:`InputError` (API) or one ``robostereo: error:`` line and
exit 2 (CLI) with no output written, or in a correct result where the input is good.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest
from synthetic import synthetic_pair

from robostereo import InputError, StereoCamera, detect_edges, match_stereo, score_matches
from robostereo.cli import main
from robostereo.io import atomic_outputs, check_outputs, load_stereo_camera, write_ply
from robostereo.matcher.pipeline import MatchParameters

RANGE = ["--min-disparity", "4", "--max-disparity", "16"]


@pytest.fixture
def pair(tmp_path: Path) -> tuple[Path, Path, np.ndarray, np.ndarray]:
    left, right, _ = synthetic_pair(np.random.default_rng(5), height=60, width=200,
                                    disparities=(8.0,))
    lp, rp = tmp_path / "l.png", tmp_path / "r.png"
    cv2.imwrite(str(lp), left)
    cv2.imwrite(str(rp), right)
    return lp, rp, left, right


def _one_error(capsys: pytest.CaptureFixture[str], word: str) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("robostereo: error:"), err
    assert word in err, err
    return err


def _files(d: Path) -> set[str]:
    return {p.name for p in d.rglob("*")}


# -- 1. PLY with zero 3-D points -------------------------------------------------------


def test_ply_of_no_points_is_an_empty_cloud(tmp_path: Path) -> None:
    for name, xyz in (("none.ply", np.zeros((0, 3))), ("nan.ply", np.full((4, 3), np.nan))):
        data = write_ply(tmp_path / name, xyz).read_bytes()
        assert data.startswith(b"ply\n") and b"element vertex 0\n" in data
        assert data.endswith(b"end_header\n")
    with pytest.raises(InputError, match=r"shape \(N, 3\)"):
        write_ply(tmp_path / "bad.ply", np.zeros((4, 2)))


def test_match_ply_with_no_and_with_all_nan_points(pair, tmp_path: Path, capsys) -> None:
    lp, rp, _, _ = pair
    flat = tmp_path / "flat.png"
    cv2.imwrite(str(flat), np.full((40, 60), 90, np.uint8))
    cam = tmp_path / "cam.yaml"
    cam.write_text("fx: 800\nfy: 800\nbaseline_mm: 60\n")
    assert main(["match", str(flat), str(flat), *RANGE, "--camera", str(cam), "-o",
                 str(tmp_path / "a.csv"), "--ply", str(tmp_path / "a.ply")]) == 0
    assert b"element vertex 0" in (tmp_path / "a.ply").read_bytes()
    # doffs -100: every disparity d - 100 < 0, so every 3-D point is NaN
    cam.write_text("fx: 800\nfy: 800\nbaseline_mm: 60\ndoffs: -100\n")
    assert main(["match", str(lp), str(rp), *RANGE, "--camera", str(cam), "-o",
                 str(tmp_path / "b.csv"), "--ply", str(tmp_path / "b.ply")]) == 0
    assert len((tmp_path / "b.csv").read_text().splitlines()) > 100
    assert b"element vertex 0" in (tmp_path / "b.ply").read_bytes()
    capsys.readouterr()


# -- 2. edge_table with edges but no candidates ----------------------------------------


def test_edge_table_without_candidates(tmp_path: Path, capsys) -> None:
    step = np.zeros((20, 60), np.uint8)
    step[:, 30:] = 200
    flat = np.full((20, 60), 100, np.uint8)
    res = match_stereo(step, flat, (0, 10), params=MatchParameters(method="relaxation"))
    assert len(res.left_edges) > 0 and len(res.candidates) == 0
    t = res.edge_table()
    assert len(t["x"]) == len(res.left_edges) and np.isnan(t["disparity"]).all()
    lp, rp = tmp_path / "s.png", tmp_path / "f.png"
    cv2.imwrite(str(lp), step)
    cv2.imwrite(str(rp), flat)
    assert main(["match", str(lp), str(rp), "--min-disparity", "0", "--max-disparity", "10",
                 "-o", str(tmp_path / "m.csv"), "--edges", str(tmp_path / "e.csv")]) == 0
    assert len((tmp_path / "e.csv").read_text().splitlines()) == len(res.left_edges) + 1


# -- 3. relaxation with candidates but no neighbour link -------------------------------


def test_relaxation_without_neighbour_links() -> None:
    # a noise image against itself at a wrong disparity: one chance pairing (seed 11
    # gives one whether the edges are placed on the smoothed or the blurred image)
    img = np.random.default_rng(11).integers(0, 256, (6, 40)).astype(np.uint8)
    res = match_stereo(img, img, (3.0, 3.0), params=MatchParameters(method="relaxation"))
    assert len(res.candidates) > 0
    assert len(match_stereo(img, img, (3.0, 3.0)).left_edges) == len(res.left_edges)
    assert all(h.dtype == np.float64 for h in res.relaxation.history)


# -- 4. output paths ------------------------------------------------------------------


def test_bad_output_paths_are_refused_before_any_work(pair, tmp_path: Path, capsys) -> None:
    lp, rp, _, _ = pair
    (tmp_path / "adir").mkdir()
    base = ["match", str(lp), str(rp), *RANGE]
    out = str(tmp_path / "m.csv")
    cases = [
        (["-o", str(tmp_path / "adir")], "is a folder"),
        (["-o", out, "--edges", str(tmp_path / "adir")], "is a folder"),
        (["-o", out, "--overlay", str(tmp_path / "adir")], "is a folder"),
        (["-o", str(lp)], "is an input"),
        (["-o", out, "--edges", out], "same file as -o"),
        (["-o", out, "--overlay", str(tmp_path / "." / "m.csv")], "same file as -o"),
        (["-o", "/proc/robostereo-m.csv"], "/proc"),
    ]
    before = _files(tmp_path)
    for extra, word in cases:
        assert main([*base, *extra]) == 2, extra
        _one_error(capsys, word)
        assert _files(tmp_path) == before, extra
    cam = tmp_path / "cam.yaml"
    cam.write_text("fx: 800\nfy: 800\nbaseline_mm: 60\n")
    assert main([*base, "--camera", str(cam), "-o", out, "--ply", str(cam)]) == 2
    _one_error(capsys, "is an input")


def test_outputs_are_all_or_nothing(pair, tmp_path: Path, capsys, monkeypatch) -> None:
    import robostereo.plots

    lp, rp, _, _ = pair

    def broken(*args, **kwargs):
        raise InputError("overlay: cannot render")

    monkeypatch.setattr(robostereo.plots, "save_overlay", broken)
    before = _files(tmp_path)
    assert main(["match", str(lp), str(rp), *RANGE, "-o", str(tmp_path / "m.csv"),
                 "--edges", str(tmp_path / "e.csv"), "--overlay", str(tmp_path / "o.png")]) == 2
    _one_error(capsys, "cannot render")
    assert _files(tmp_path) == before  # neither the CSV nor the edges, no temporary file


def test_a_failed_write_leaves_no_output(pair, tmp_path: Path, capsys) -> None:
    """/proc takes no new files, even for root: the PLY fails after the matching, and the
    CSV, complete by then, is not renamed into place either."""
    lp, rp, _, _ = pair
    cam = tmp_path / "cam.yaml"
    cam.write_text("fx: 800\nfy: 800\nbaseline_mm: 60\n")
    before = _files(tmp_path)
    assert main(["match", str(lp), str(rp), *RANGE, "--camera", str(cam), "-o",
                 str(tmp_path / "m.csv"), "--ply", "/proc/robostereo-m.ply"]) == 2
    _one_error(capsys, "/proc/robostereo-m.ply: cannot write")
    assert _files(tmp_path) == before


def test_rig_outputs_are_checked_and_all_or_nothing(pair, tmp_path: Path, capsys) -> None:
    from robostereo.geometry.calibration import StereoCalibration
    from robostereo.io.calibration_files import write_opencv_calibration

    lp, rp, _, _ = pair
    K = np.array([[800.0, 0, 99.5], [0, 800.0, 29.5], [0, 0, 1]])
    cal = write_opencv_calibration(
        StereoCalibration(K, None, K, None, np.eye(3), [-60, 0, 0], (200, 60)),
        tmp_path / "rig.yml")
    base = ["rig", str(lp), str(rp), "--calibration", str(cal), *RANGE]
    before = _files(tmp_path)
    assert main([*base, "-o", str(cal)]) == 2
    _one_error(capsys, "is an input")
    assert main([*base, "-o", str(tmp_path / "m.csv"), "--ply", "/proc/robostereo.ply"]) == 2
    _one_error(capsys, "cannot write")
    assert _files(tmp_path) == before
    assert main([*base, "-o", str(tmp_path / "m.csv"), "--ply", str(tmp_path / "m.ply")]) == 0
    assert (tmp_path / "m.ply").read_bytes().startswith(b"ply")


def test_an_unwritable_output_folder_is_refused(tmp_path: Path, monkeypatch) -> None:
    import os

    real = os.access
    monkeypatch.setattr(os, "access", lambda p, mode: False if Path(p) == tmp_path
                        else real(p, mode))  # as if read-only (root may write anyway)
    with pytest.raises(InputError, match="is not writable"):
        check_outputs({"-o": tmp_path / "m.csv"})


def test_atomic_outputs_keeps_old_files_on_failure(tmp_path: Path) -> None:
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    a.write_text("old")
    with pytest.raises(RuntimeError), atomic_outputs({"a": a, "b": b}) as tmp:
        tmp["a"].write_text("new")
        raise RuntimeError("stop")
    assert a.read_text() == "old" and not b.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]
    with pytest.raises(InputError, match="does not exist"):
        check_outputs({"-o": tmp_path / "no" / "x.csv"})


# -- 6. float images ------------------------------------------------------------------


def test_float_images_have_full_scale_one(pair) -> None:
    _, _, left, right = pair
    ref = match_stereo(left, right, (4, 16))
    unit = match_stereo(left / 255.0, right / 255.0, (4, 16))
    assert len(ref) > 100 and np.allclose(unit.disparity, ref.disparity, atol=1e-3)
    with pytest.raises(InputError, match=r"0\.\.1 \(full scale 1\.0\), got 43 \.\. 235"):
        match_stereo(left.astype(np.float32), right.astype(np.float32), (4, 16))
    scaled = match_stereo(left.astype(float), right.astype(float), (4, 16),
                          params=MatchParameters(bit_depth=8))
    assert np.allclose(scaled.disparity, ref.disparity, atol=1e-3)
    with pytest.raises(InputError, match="real grey levels"):
        match_stereo(left.astype(complex), right.astype(complex), (4, 16))
    with pytest.raises(InputError, match="real grey levels"):
        detect_edges(left > 100)


def test_float_tiff_in_the_cli(pair, tmp_path: Path, capsys) -> None:
    _, _, left, right = pair
    for scale, name in ((255.0, "u"), (1.0, "w")):
        cv2.imwrite(str(tmp_path / f"{name}l.tif"), (left / scale).astype(np.float32))
        cv2.imwrite(str(tmp_path / f"{name}r.tif"), (right / scale).astype(np.float32))
    assert main(["match", str(tmp_path / "ul.tif"), str(tmp_path / "ur.tif"), *RANGE,
                 "-o", str(tmp_path / "m.csv")]) == 0
    assert len((tmp_path / "m.csv").read_text().splitlines()) > 100
    capsys.readouterr()
    assert main(["match", str(tmp_path / "wl.tif"), str(tmp_path / "wr.tif"), *RANGE,
                 "-o", str(tmp_path / "n.csv")]) == 2
    _one_error(capsys, "full scale 1.0")
    assert not (tmp_path / "n.csv").exists()


# -- 8. API validation ----------------------------------------------------------------


def test_api_validation_gaps(pair) -> None:
    _, _, left, right = pair
    with pytest.raises(InputError, match="row_step must be an integer"):
        MatchParameters(row_step=2.0)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="row_step must be an integer"):
        detect_edges(left, row_step=2.0)  # type: ignore[arg-type]
    for bad in (5, (1,), (1, 2, 3), "ab", (1, "x"), None, (np.nan, 3)):
        with pytest.raises(InputError, match="disparity_range"):
            match_stereo(left, right, bad)  # type: ignore[arg-type]
    res = match_stereo(left, right, (4, 16), params=MatchParameters(method="relaxation"))
    with pytest.raises(InputError, match="iteration must be an integer >= 0"):
        res.matches_after(-100)
    assert np.array_equal(res.matches_after(100), res.match)
    with pytest.raises(InputError, match=r"shape \(200,\)"):
        match_stereo(left[0], right[0], (4, 16))
    with pytest.raises(InputError, match="cx must be within"):
        StereoCamera(800.0, 800.0, 60.0, cx=1e308)
    with pytest.raises(TypeError, match="params must be a MatchParameters"):
        match_stereo(left, right, (4, 16), params={"threshold": 4})  # type: ignore[arg-type]


def test_camera_yaml_with_absurd_principal_point(tmp_path: Path) -> None:
    cam = tmp_path / "cam.yaml"
    cam.write_text("fx: 800\nfy: 800\nbaseline_mm: 60\ncx: 1e308\n")
    with pytest.raises(InputError, match=r"cam\.yaml: cx must be within"):
        load_stereo_camera(cam)
    from robostereo.geometry.camera import camera_from_dict

    with pytest.raises(InputError, match=r"cap\.yaml: principal_point must be within"):
        camera_from_dict({"focal_length_mm": 25, "pixel_pitch_mm": [0.01, 0.01],
                          "image_size": [640, 480], "principal_point": [1e308, 0]},
                         source="cap.yaml")


def test_huge_range_bounds_stay_in_the_range(pair) -> None:
    _, _, left, right = pair
    res = match_stereo(left, right, (-1e18, 12.0), params=MatchParameters(method="relaxation"))
    assert res.disparity_range == (-199.0, 12.0)
    assert len(res) > 100 and (res.candidates.disparity <= 12.5).all()
    win = match_stereo(left, right, (-1e18, 12.0))
    assert len(win) > 100 and (win.disparity <= 12.5).all()
    wide = match_stereo(left, right, (4.0, 1e18))
    assert wide.disparity_range == (4.0, 199.0)
    with pytest.raises(InputError, match=r"lies outside -199 \.\. 199"):
        match_stereo(left, right, (1000, 1001))


def test_score_matches_refuses_points_off_the_map() -> None:
    gt = np.full((4, 10), 5.0)
    assert score_matches([0, 3], [0.0, 9.4], [5.0, 5.0], gt).matched == 2
    for rows, x in (([0, 4], [1.0, 2.0]), ([0, -1], [1.0, 2.0]), ([0, 1], [1.0, 9.6]),
                    ([0, 1], [-0.7, 2.0]), ([0, 1.5], [1.0, 2.0]), ([0, 1], [np.nan, 2.0])):
        with pytest.raises(InputError, match=r"rows must|x must"):
            score_matches(rows, x, [5.0, 5.0], gt)
    with pytest.raises(InputError, match="one length"):
        score_matches([0, 1], [1.0], [5.0, 5.0], gt)


# -- 9. smaller ones ------------------------------------------------------------------


def test_range_wider_than_the_image_gets_a_note(pair, tmp_path: Path, capsys) -> None:
    lp, rp, _, _ = pair
    assert main(["match", str(lp), str(rp), "--min-disparity", "4", "--max-disparity", "900",
                 "-o", str(tmp_path / "m.csv")]) == 0
    err = capsys.readouterr().err
    assert "note: disparity range limited to 4 .. 199 (the image is 200 pixels wide)" in err
    assert main(["match", str(lp), str(rp), "--min-disparity", "1000", "--max-disparity",
                 "1001", "-o", str(tmp_path / "n.csv")]) == 2
    _one_error(capsys, "lies outside")


def test_scheduler_that_is_not_an_address(tmp_path: Path, capsys) -> None:
    pytest.importorskip("distributed")
    root = tmp_path / "in" / "p"
    root.mkdir(parents=True)
    left, right, _ = synthetic_pair(np.random.default_rng(1), height=40, width=120)
    cv2.imwrite(str(root / "left.png"), left)
    cv2.imwrite(str(root / "right.png"), right)
    assert main(["batch", str(tmp_path / "in"), "--out", str(tmp_path / "out"), *RANGE,
                 "--scheduler", "notaurl"]) == 2
    _one_error(capsys, "cannot reach the Dask scheduler at 'notaurl'")


def test_evaluate_names_a_corrupt_ground_truth(tmp_path: Path, capsys) -> None:
    scene = tmp_path / "myscene"
    scene.mkdir()
    left, right, _ = synthetic_pair(np.random.default_rng(2), height=40, width=120)
    cv2.imwrite(str(scene / "left.png"), left)
    cv2.imwrite(str(scene / "right.png"), right)
    (scene / "gt_disp_left.png").write_bytes(b"\x89PNG\r\n\x1a\n truncated")
    assert main(["evaluate", str(scene), "--no-sgbm"]) == 2
    err = _one_error(capsys, "gt_disp_left.png: cannot decode image")
    assert "scale" not in err


def test_evaluate_with_a_huge_range_bound(tmp_path: Path, capsys) -> None:
    scene = tmp_path / "myscene"
    scene.mkdir()
    left, right, gt = synthetic_pair(np.random.default_rng(2), height=40, width=120)
    cv2.imwrite(str(scene / "left.png"), left)
    cv2.imwrite(str(scene / "right.png"), right)
    cv2.imwrite(str(scene / "gt_disp_left.png"), np.nan_to_num(gt * 4, nan=0).astype(np.uint8))
    (tmp_path / "scenes.json").write_text('{"scenes": {"myscene": {"scale": 4}}}')
    assert main(["evaluate", str(scene), "--min-disparity=-1e18", "--max-disparity", "16"]) == 0
    assert "disparity -119 .. 16 px" in capsys.readouterr().out  # SGBM searched it too
    # a range up to the image's width leaves SGBM too little room: it finds nothing
    assert main(["evaluate", str(scene), "--min-disparity", "4", "--max-disparity=1e9"]) == 0
    assert "disparity 4 .. 119 px" in capsys.readouterr().out


def test_corrupt_png_gives_our_line_only(pair, tmp_path: Path) -> None:
    lp, rp, _, _ = pair
    bad = tmp_path / "cut.png"
    bad.write_bytes(lp.read_bytes()[:200])
    r = subprocess.run([sys.executable, "-m", "robostereo.cli", "match", str(bad), str(rp),
                        *RANGE, "-o", str(tmp_path / "m.csv")],
                       capture_output=True, text=True, timeout=120, check=False)
    assert r.returncode == 2
    assert r.stderr.splitlines() == [r.stderr.strip()] and "cut.png" in r.stderr
    assert "WARN" not in r.stderr and "ERROR" not in r.stderr


def test_triangulate_never_reports_a_depth_of_zero_or_inf() -> None:
    from robostereo import triangulate

    cam = StereoCamera(1.0, 1.0, 5.125652948320123e-275)  # found by hypothesis: z = 0.0
    xyz, zb = triangulate(cam, [0.0, 2.0748874128225062e49, 1.0, 0.0],
                          [0.0, 0.0, 0.0, -np.inf], [0, 0, 0, 0], (1, 1))
    assert np.isnan(xyz[[0, 1, 3]]).all() and np.isnan(zb[[0, 1, 3]]).all()
    assert xyz[2, 2] > 0
    with pytest.raises(InputError, match="one length"):
        triangulate(cam, [1.0, 2.0], [0.0], [0, 0], (1, 1))


def test_opencv_matrix_without_cols_does_not_abort(pair, tmp_path: Path) -> None:
    """cv2.FileNode.mat() aborts the whole process on an opencv-matrix without ``cols``
    (found by hypothesis); the matrix is now read from its data."""
    from robostereo.geometry.calibration import StereoCalibration
    from robostereo.io.calibration_files import write_opencv_calibration

    lp, rp, _, _ = pair
    K = np.array([[800.0, 0, 99.5], [0, 800.0, 29.5], [0, 0, 1]])
    cal = write_opencv_calibration(
        StereoCalibration(K, None, K, None, np.eye(3), [-60, 0, 0], (200, 60)),
        tmp_path / "rig.yaml")
    lines = cal.read_text().splitlines()
    k1 = next(i for i, ln in enumerate(lines) if ln.startswith("K1:"))
    del lines[k1 + 2]  # K1's "cols: 3"
    assert "cols" not in lines[k1 + 2] and "rows" in lines[k1 + 1]
    cal.write_text("\n".join(lines) + "\n")
    r = subprocess.run([sys.executable, "-m", "robostereo.cli", "rig", str(lp), str(rp),
                        "--calibration", str(cal), *RANGE, "-o", str(tmp_path / "m.csv")],
                       capture_output=True, text=True, timeout=120, check=False)
    assert r.returncode == 0, r.stderr


def test_relaxation_coefficients_that_break_the_arithmetic_are_refused() -> None:
    from robostereo import RelaxationParameters

    # a denormal no-match support made probabilities of 3 (found by hypothesis)
    for kw in ({"no_match_support": 1.401298464324817e-45}, {"no_match_support": 1e300},
               {"b_partial": -0.2}, {"neighbour_radius": -1.0}):
        with pytest.raises(InputError, match="must be"):
            RelaxationParameters(**kw)
    img = np.random.default_rng(0).integers(0, 256, (9, 12)).astype(np.uint8)
    res = match_stereo(img, img, (0, 0), params=MatchParameters(
        method="relaxation",
        relaxation=RelaxationParameters(iterations=1, no_match_support=1e-6)))
    p = res.relaxation.probability
    assert ((p >= 0) & (p <= 1 + 1e-9)).all()


def test_calibration_that_hung_opencv(pair, tmp_path: Path) -> None:
    """cv2.FileStorage loops forever on this damaged YAML header (found by fuzzing); the
    calibration files are now parsed in Python."""
    from robostereo.geometry.calibration import StereoCalibration
    from robostereo.io.calibration_files import write_opencv_calibration

    lp, rp, _, _ = pair
    K = np.array([[800.0, 0, 99.5], [0, 800.0, 29.5], [0, 0, 1]])
    cal = write_opencv_calibration(
        StereoCalibration(K, None, K, None, np.eye(3), [-60, 0, 0], (200, 60)),
        tmp_path / "rig.yml")
    text = cal.read_text()
    cal.write_text("%YA." + text[text.index("ncv-matrix"):])
    r = subprocess.run([sys.executable, "-m", "robostereo.cli", "rig", str(lp), str(rp),
                        "--calibration", str(cal), *RANGE, "-o", str(tmp_path / "m.csv")],
                       capture_output=True, text=True, timeout=60, check=False)
    assert r.returncode == 2 and "rig.yml: cannot parse calibration file" in r.stderr
    assert len(r.stderr.splitlines()) == 1


def test_opencv_nan_and_inf_spellings_are_read(tmp_path: Path) -> None:
    from robostereo.io.calibration_files import read_calibration

    K = np.array([[800.0, 0, 99.5], [0, 800.0, 29.5], [0, 0, 1]])
    for ext in ("yml", "json", "xml"):
        fs = cv2.FileStorage(str(tmp_path / f"c.{ext}"), cv2.FILE_STORAGE_WRITE)
        for key, v in (("K1", K), ("D1", np.zeros(5)), ("K2", K), ("D2", np.zeros(5)),
                       ("R", np.eye(3)), ("T", np.array([[np.nan], [0.0], [0.0]]))):
            fs.write(key, v)
        fs.write("image_size", np.array([[200, 60]]))
        fs.release()
        with pytest.raises(InputError, match=rf"c\.{ext}: T must be finite"):
            read_calibration(tmp_path / f"c.{ext}")


# -- issue 36, 8: an alias bomb and absurd camera numbers in capture.yaml --------------


@pytest.mark.parametrize(("old", "new", "word"), [
    ("depth_range_mm: [900.0, 1100.0]", "depth_range_mm: *l8", "alias bomb"),
    ("focal_length_mm: 25.0", "focal_length_mm: 1.0e+6", "focal_length_mm / pixel_pitch_mm"),
    ("disparity_px: 0.2", "disparity_px: 1.0e+308", "disparity_px"),
])
def test_locate_refuses_a_bomb_or_an_absurd_number_in_one_line_writing_nothing(
        tmp_path: Path, capsys, old: str, new: str, word: str) -> None:
    from robostereo.geometry.camera import SEED_CAMERA
    from robostereo.geometry.poses import se3_from_scara
    from robostereo.robot.views import ViewsCapture, write_views_capture

    w, h = SEED_CAMERA.image_size
    folder = write_views_capture(tmp_path / "cap", ViewsCapture(
        tuple(np.zeros((h, w), np.uint8) for _ in range(3)), SEED_CAMERA,
        tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20, 0, 20)),
        depth_range_mm=(900.0, 1100.0)))
    yml = folder / "capture.yaml"
    bomb = "robot:\n  l0: &l0 [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"  l{i}: &l{i} [{', '.join([f'*l{i - 1}'] * 9)}]\n" for i in range(1, 9))
    yml.write_text((bomb if "*l8" in new else "") + yml.read_text().replace(old, new))
    before = _files(tmp_path)
    assert main(["locate", str(folder), "-o", str(tmp_path / "out.csv")]) == 2
    _one_error(capsys, word)
    assert _files(tmp_path) == before
