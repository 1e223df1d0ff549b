"""The handeye and simulate-handeye commands refuse bad input: exit 2, one line, no output."""

from __future__ import annotations

import random
import sys

import pytest
import yaml

from robostereo.cli import main
from robostereo.robot.handeye import write_views
from robostereo.robot.simulated.sixaxis_handeye import simulate_handeye_views


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("he") / "views"
    v, truth = simulate_handeye_views(views=8, seed=2)
    write_views(d, v, extra={"truth.yaml": truth})
    return d


def _edit(src, dst, change):
    dst.mkdir()
    for p in src.iterdir():
        (dst / p.name).write_bytes(p.read_bytes())
    spec = yaml.safe_load((dst / "views.yaml").read_text())
    change(spec)
    (dst / "views.yaml").write_text(yaml.safe_dump(spec))
    return dst


def _refused(capsys, argv, out, *words):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("robostereo: error: ") and err.count("\n") == 1, err
    for w in words:
        assert w in err, err
    assert out is None or not out.exists()
    return err


def _metres(spec):
    for v in spec["views"]:
        v["flange"]["position"] = [x / 1000.0 for x in v["flange"]["position"]]


def _square(spec):
    spec["board"]["square_mm"] = spec["board"]["square_mm"] / 10.0


def _shuffle(spec):
    flanges = [v["flange"] for v in spec["views"]]
    random.Random(0).shuffle(flanges)
    for v, f in zip(spec["views"], flanges, strict=True):
        v["flange"] = f


@pytest.mark.parametrize("change", [_metres, _square, _shuffle])
def test_implausible_results_are_refused_naming_the_file(folder, tmp_path, capsys, change):
    d = _edit(folder, tmp_path / "bad", change)
    out = tmp_path / "cam.yaml"
    _refused(capsys, ["handeye", str(d), "-o", str(out)], out,
             f"{d / 'views.yaml'}: implausible hand-eye result", "square_mm", "unit: m",
             "pose order", "worst views: ")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad"]


def test_symmetric_board_and_bad_numbers_are_refused(folder, tmp_path, capsys):
    out = tmp_path / "cam.yaml"

    def even(spec):
        spec["board"]["inner_corners"] = [8, 6]
    d = _edit(folder, tmp_path / "even", even)
    _refused(capsys, ["handeye", str(d), "-o", str(out)], out,
             f"{d / 'views.yaml'}: board: inner_corners 8 x 6: columns + rows is even",
             "9 x 6", "ChArUco")
    for k, value in enumerate([float("inf"), float("nan"), 0.0, -0.005]):
        def pitch(spec, value=value):
            spec["pixel_pitch_mm"] = value
        d = _edit(folder, tmp_path / f"pitch{k}", pitch)
        _refused(capsys, ["handeye", str(d), "-o", str(out)], out,
                 f"{d / 'views.yaml'}: pixel_pitch_mm must be a finite number > 0")

    def garble(spec):
        spec["views"][5]["flange"]["quaternion"] = [0.0, 0.0, 0.0, 0.0]
    d = _edit(folder, tmp_path / "garbled", garble)
    _refused(capsys, ["handeye", str(d), "-o", str(out)], out,
             f"{d / 'views.yaml'}: views[5] (view_05.png): flange:")


def test_handeye_never_overwrites_an_input(folder, tmp_path, capsys):
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    for name in ("views.yaml", "view_00.png"):
        _refused(capsys, ["handeye", str(folder), "-o", str(folder / name)], None,
                 "is an input of the command")
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == before


def test_reject_outliers_and_known_intrinsics(folder, tmp_path, capsys):
    def swap(spec):  # one view paired with a slightly wrong flange pose
        spec["views"][3]["flange"]["position"][0] += 4.0
    d = _edit(folder, tmp_path / "swap", swap)
    out = tmp_path / "cam.yaml"
    err = _refused(capsys, ["handeye", str(d), "-o", str(out)], out, "implausible")
    assert "worst views: " + str(d / "view_03.png") in err
    assert main(["handeye", str(d), "-o", str(out), "--reject-outliers"]) == 0
    text = capsys.readouterr().out
    assert "rejected as outliers: view_03.png" in text
    data = yaml.safe_load(out.read_text())
    assert data["rejected_views"] == ["view_03.png"] and len(data["views"]) == 7
    truth = yaml.safe_load((folder / "truth.yaml").read_text())
    cam = tmp_path / "true_camera.yaml"
    cam.write_text(yaml.safe_dump({"camera": truth["camera"], "hand_eye": truth["hand_eye"]}))
    out2 = tmp_path / "cam2.yaml"
    assert main(["handeye", str(folder), "-o", str(out2), "--intrinsics", str(cam)]) == 0
    assert "camera (held fixed)" in capsys.readouterr().out
    data = yaml.safe_load(out2.read_text())
    assert data["camera"]["principal_point"] == truth["camera"]["principal_point"]


def test_simulate_handeye_bounds_and_early_output_checks(tmp_path, capsys):
    out = tmp_path / "many"
    _refused(capsys, ["simulate-handeye", "--out", str(out), "--views", "100000"], out,
             "--views must be <= 200")
    _refused(capsys, ["simulate-handeye", "--out", str(out), "--views", "2"], out,
             "--views must be >= 3")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="needs /proc")
@pytest.mark.parametrize("argv", [["simulate-handeye"], ["demo", "--robot", "six-axis"]])
def test_an_unwritable_out_is_found_before_any_work(capsys, argv):
    # /proc takes no new folder, not even from root: the probe must fail at once
    _refused(capsys, [*argv, "--out", "/proc/robostereo-test"], None,
             "/proc/robostereo-test: folder /proc is not writable")


def test_intrinsics_from_a_stereo_camera_yaml_are_refused(folder, tmp_path, capsys):
    stereo = tmp_path / "stereo.yaml"
    stereo.write_text("fx: 800.0\nfy: 800.0\ncx: 320.0\ncy: 240.0\nbaseline_mm: 60.0\n")
    out = tmp_path / "cam.yaml"
    _refused(capsys, ["handeye", str(folder), "-o", str(out), "--intrinsics", str(stereo)],
             out, "--intrinsics", "stereo camera YAML")


def test_advise_writes_flange_poses_with_the_camera_file(folder, tmp_path, capsys):
    """--advise: four flange poses in views.yaml's pose form and the spread at each tilt,
    written with the camera file or not at all."""
    from robostereo.geometry.poses import pose_from_dict

    out, adv = tmp_path / "cam.yaml", tmp_path / "advice.yaml"
    assert main(["handeye", str(folder), "-o", str(out), "--advise", str(adv)]) == 0
    text = capsys.readouterr().out
    assert "4 more views tilted" in text and f"-> {adv}" in text
    data = yaml.safe_load(adv.read_text())
    assert data["mode"] == "eye-in-hand" and len(data["flange_poses"]) == 4
    poses = [pose_from_dict(p) for p in data["flange_poses"]]
    assert len({tuple(p.translation.round(3)) for p in poses}) == 4
    rows = [c for c in data["candidates"] if c["sigma"] is not None]
    assert rows and all(c["sigma"]["rotation_deg"] <= data["current_sigma"]["rotation_deg"]
                        for c in rows)  # four views more never pin it less
    assert data["advised_tilt_deg"] in [c["tilt_deg"] for c in rows]
    c2 = tmp_path / "c2.yaml"
    for clash in (c2, folder / "views.yaml"):  # the camera file, an input
        before = (folder / "views.yaml").read_bytes()
        _refused(capsys, ["handeye", str(folder), "-o", str(c2), "--advise", str(clash)], c2)
        assert (folder / "views.yaml").read_bytes() == before
