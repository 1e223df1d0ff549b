"""`robostereo match`: outputs, summary, and bad input (exit 2, no partial files)."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from synthetic import synthetic_pair

from robostereo.cli import main


@pytest.fixture
def pair(tmp_path, rng):
    import cv2

    left, right, _ = synthetic_pair(rng, height=60, width=200, disparities=(8.0,))
    lp, rp = tmp_path / "l.png", tmp_path / "r.png"
    cv2.imwrite(str(lp), left)
    cv2.imwrite(str(rp), right)
    cam = tmp_path / "cam.yaml"
    cam.write_text("focal_length_mm: 25.0\npixel_pitch_mm: [0.0172, 0.0137]\nbaseline_mm: 20.0\n")
    return lp, rp, cam


def _rows(path: Path) -> list[dict[str, str]]:
    with open(path) as fh:
        return list(csv.DictReader(fh))


def test_match_writes_all_outputs(pair, tmp_path, capsys):
    lp, rp, cam = pair
    out = tmp_path / "m.csv"
    rc = main([
        "match", str(lp), str(rp), "--min-disparity", "4", "--max-disparity", "16",
        "--camera", str(cam), "-o", str(out), "--ply", str(tmp_path / "m.ply"),
        "--edges", str(tmp_path / "e.csv"), "--overlay", str(tmp_path / "o.png"),
    ])
    assert rc == 0
    summary = capsys.readouterr().out.strip().splitlines()
    assert len(summary) == 1 and "matched" in summary[0] and "ms" in summary[0]
    rows = _rows(out)
    assert list(rows[0])[:5] == ["row", "x_left", "x_right", "disparity", "confidence"]
    assert all(float(r["confidence"]) >= 0.95 for r in rows)
    assert {"X", "Y", "Z", "z_bound"} <= set(rows[0])
    d = np.array([float(r["disparity"]) for r in rows])
    assert np.allclose(d, 8.0, atol=0.15)
    z = np.array([float(r["Z"]) for r in rows])
    assert np.allclose(z, 25.0 / 0.0172 * 20.0 / d, rtol=1e-5)
    edges = _rows(tmp_path / "e.csv")
    assert len(edges) >= len(rows)
    assert {"row", "x", "sign", "magnitude", "pattern", "mean_grey", "x_right", "disparity",
            "confidence", "accepted"} == set(edges[0])
    assert sum(1 for e in edges if e["accepted"] == "1") == len(rows)
    # every edge point with a best candidate has its confidence, accepted or not
    assert sum(1 for e in edges if e["confidence"] != "") >= len(rows)
    ply = (tmp_path / "m.ply").read_bytes()
    assert ply.startswith(b"ply") and f"element vertex {len(rows)}".encode() in ply
    assert (tmp_path / "o.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_match_without_camera_has_disparities_only(pair, tmp_path):
    lp, rp, _ = pair
    out = tmp_path / "m.csv"
    assert main(["match", str(lp), str(rp), "--min-disparity", "4", "--max-disparity", "16",
                 "-o", str(out)]) == 0
    assert list(_rows(out)[0]) == ["row", "x_left", "x_right", "disparity", "confidence"]


def _bad(tmp_path, args, capsys, word):
    before = set(tmp_path.iterdir())
    rc = main(args)
    err = capsys.readouterr().err.strip()
    assert rc == 2
    assert len(err.splitlines()) == 1 and err.startswith("robostereo: error:") and word in err
    assert set(tmp_path.iterdir()) == before  # no partial output


def test_bad_inputs_exit_2_without_output(pair, tmp_path, capsys):
    import cv2

    lp, rp, _cam = pair
    out = str(tmp_path / "out.csv")
    rng_ = ["--min-disparity", "4", "--max-disparity", "16"]
    _bad(tmp_path, ["match", str(tmp_path / "missing.png"), str(rp), *rng_, "-o", out],
         capsys, "missing.png")
    garbage = tmp_path / "garbage.png"
    garbage.write_bytes(b"not an image at all")
    _bad(tmp_path, ["match", str(garbage), str(rp), *rng_, "-o", out], capsys, "garbage.png")
    small = tmp_path / "small.png"
    cv2.imwrite(str(small), np.zeros((30, 40), np.uint8))
    _bad(tmp_path, ["match", str(lp), str(small), *rng_, "-o", out], capsys, "differ in size")
    _bad(tmp_path, ["match", str(lp), str(rp), "--min-disparity", "9", "--max-disparity", "3",
                    "-o", out], capsys, "empty")
    for text, word in [("focal_length_mm: .nan\npixel_pitch_mm: [0.01, 0.01]\nbaseline_mm: 20\n",
                        "focal_length_mm"),
                       ("focal_length_mm: 25\npixel_pitch_mm: [0.01, 0.01]\nbaseline_mm: -2\n",
                        "baseline_mm"),
                       ("fx: 0\nfy: 100\nbaseline_mm: 20\n", "fx")]:
        bad_cam = tmp_path / "bad_cam.yaml"
        bad_cam.write_text(text)
        _bad(tmp_path, ["match", str(lp), str(rp), *rng_, "--camera", str(bad_cam),
                        "-o", out, "--ply", str(tmp_path / "x.ply")], capsys, word)
        bad_cam.unlink()
    _bad(tmp_path, ["match", str(lp), str(rp), *rng_, "-o", str(tmp_path / "no" / "o.csv")],
         capsys, "does not exist")


def test_constant_images_give_an_empty_result_and_a_warning(tmp_path, capsys):
    import cv2

    flat = tmp_path / "flat.png"
    cv2.imwrite(str(flat), np.full((40, 50), 100, np.uint8))
    out = tmp_path / "m.csv"
    assert main(["match", str(flat), str(flat), "--min-disparity", "0", "--max-disparity", "9",
                 "-o", str(out)]) == 0
    assert "no edge points" in capsys.readouterr().err
    assert out.read_text().strip() == "row,x_left,x_right,disparity,confidence"


def test_sixteen_bit_input(tmp_path, rng):
    import cv2

    left, right, _ = synthetic_pair(rng, height=40, width=160, disparities=(6.5,))
    runs = {}
    for depth, scale in ((16, 257), (8, 1)):
        for name, img in ((f"l{depth}.png", left), (f"r{depth}.png", right)):
            cv2.imwrite(str(tmp_path / name), img.astype(np.uint16 if depth == 16 else np.uint8)
                        * scale)
        out = tmp_path / f"m{depth}.csv"
        assert main(["match", str(tmp_path / f"l{depth}.png"), str(tmp_path / f"r{depth}.png"),
                     "--min-disparity", "2", "--max-disparity", "12", "-o", str(out)]) == 0
        runs[depth] = np.array([float(r["disparity"]) for r in _rows(out)])
    d = runs[16]
    # 16 bits scaled by 257 are the same grey levels: the same matches as the 8-bit pair
    assert np.array_equal(d, runs[8])
    # a half-pixel shift is the hardest for census windows: most within 0.15 px, all
    # within the evaluation rule's pixel
    assert d.size > 100 and np.mean(np.abs(d - 6.5) < 0.15) > 0.8
    assert np.all(np.abs(d - 6.5) < 1.0)


def test_console_script_runs():
    r = subprocess.run([sys.executable, "-m", "robostereo.cli", "--version"],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0 and r.stdout.startswith("robostereo ")


def test_min_confidence_and_method_options(pair, tmp_path, capsys):
    lp, rp, _ = pair
    base = ["match", str(lp), str(rp), "--min-disparity", "4", "--max-disparity", "16"]
    counts = {}
    for t in ("0", "0.97", "0.999"):
        out = tmp_path / f"m{t}.csv"
        assert main([*base, "-o", str(out), "--min-confidence", t]) == 0
        counts[t] = len(_rows(out))
    assert counts["0"] >= counts["0.97"] >= counts["0.999"] and counts["0"] > counts["0.999"]
    edges = tmp_path / "e.csv"
    assert main([*base, "-o", str(tmp_path / "all.csv"), "--min-confidence", "0",
                 "--edges", str(edges)]) == 0
    assert sum(1 for e in _rows(edges) if e["confidence"] != "") == counts["0"]
    out = tmp_path / "r.csv"
    assert main([*base, "-o", str(out), "--method", "relaxation"]) == 0
    assert len(_rows(out)) > 0
    capsys.readouterr()
    for bad in (["--min-confidence", "1.5"], ["--min-confidence", "nan"], ["--method", "sgm"]):
        with pytest.raises(SystemExit) as exc:  # argparse: usage line and one error line
            main([*base, "-o", str(tmp_path / "bad.csv"), *bad])
        assert exc.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()[-1]
        assert "min-confidence" in err or "method" in err
        assert not (tmp_path / "bad.csv").exists()


def test_no_paths_no_coarse_and_contour_reach_the_matcher():
    import argparse

    from robostereo.cli._args import add_matcher_args, matcher_params
    from robostereo.matcher.pipeline import MatchParameters

    ap = argparse.ArgumentParser()
    add_matcher_args(ap)
    default = matcher_params(ap.parse_args([]), MatchParameters())
    assert default.paths and default.coarse and not default.contour
    p = matcher_params(ap.parse_args(["--no-paths", "--no-coarse", "--contour"]),
                       MatchParameters())
    assert not p.paths and not p.coarse and p.contour


def test_match_says_when_the_views_grey_levels_differ(tmp_path, rng, capsys):
    import cv2

    left, right, _ = synthetic_pair(rng, height=90, width=260)
    bright = np.clip(np.rint(1.35 * right.astype(float) + 6), 0, 255).astype(np.uint8)
    lp, rp = tmp_path / "l.png", tmp_path / "r.png"
    cv2.imwrite(str(lp), left)
    cv2.imwrite(str(rp), bright)
    args = ["match", str(lp), str(rp), "--min-disparity", "4", "--max-disparity", "16"]
    assert main([*args, "-o", str(tmp_path / "a.csv")]) == 0
    assert "grey levels differ" in capsys.readouterr().err
    assert main([*args, "-o", str(tmp_path / "b.csv"), "--no-photometric"]) == 0
    assert "grey levels differ" not in capsys.readouterr().err
    assert len(_rows(tmp_path / "a.csv")) > 0


def test_match_warns_when_the_rows_disagree(tmp_path, capsys):
    import cv2

    rng = np.random.default_rng(7)
    blocks = cv2.resize(rng.integers(0, 256, (40, 60)).astype(np.uint8), (240, 160),
                        interpolation=cv2.INTER_NEAREST)
    left = cv2.GaussianBlur(blocks, (0, 0), 0.8)  # edges both ways, corners
    right = cv2.warpAffine(np.roll(left, -9, axis=1), np.float32([[1, 0, 0], [0, 1, 1.2]]),
                           (240, 160), flags=cv2.INTER_LINEAR,
                           borderMode=cv2.BORDER_REPLICATE)
    lp, rp = tmp_path / "l.png", tmp_path / "r.png"
    cv2.imwrite(str(lp), left)
    cv2.imwrite(str(rp), right)
    args = ["match", str(lp), str(rp), "--min-disparity", "0", "--max-disparity", "20"]
    assert main([*args, "-o", str(tmp_path / "a.csv")]) == 0
    assert "rows of the two views disagree by +1.2" in capsys.readouterr().err
    assert main([*args, "-o", str(tmp_path / "b.csv"), "--no-rows-check"]) == 0
    assert "rows of the two views disagree" not in capsys.readouterr().err
