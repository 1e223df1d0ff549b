"""The N-view commands: ``capture --views``, ``locate`` on an N-view folder, ``demo
--views``, ``plan --views``; their bad input (one line, exit 2, nothing written)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from robostereo.cli import main
from robostereo.geometry.camera import SEED_CAMERA
from robostereo.robot.views.views_folder import read_views_capture


def _contents(folder: Path) -> dict[Path, bytes | None]:
    """Every path under `folder`, with the bytes of each file (None for a folder)."""
    return {p: p.read_bytes() if p.is_file() else None for p in sorted(folder.rglob("*"))}


def _refused(args: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str],
             word: str) -> str:
    """Exit code 2, one ``robostereo: error:`` line naming `word`, nothing written (no
    output, no ``.part``) and every input under `tmp_path` untouched."""
    before = _contents(tmp_path)
    rc = main([str(a) for a in args])
    out, err = capsys.readouterr()
    assert rc == 2 and out == "", (rc, out, err)
    assert len(err.splitlines()) == 1 and err.startswith("robostereo: error: "), err
    assert word in err, err
    assert _contents(tmp_path) == before
    return err.strip()


@pytest.fixture(scope="module")
def views_dir(tmp_path_factory) -> Path:
    """Three views of the block on a line over 40 mm, from the command."""
    d = tmp_path_factory.mktemp("cli-views") / "cap"
    assert main(["capture", "--views", "3", "--span", "40", "--out", str(d)]) == 0
    return d


def _edited(src: Path, dst: Path, edit) -> Path:
    shutil.copytree(src, dst)
    p = dst / "capture.yaml"
    data = yaml.safe_load(p.read_text())
    edit(data, dst)
    p.write_text(yaml.safe_dump(data))
    return dst


# -- capture ---------------------------------------------------------------------------


def test_capture_with_views_writes_a_folder_of_that_many_views_on_the_pattern(views_dir):
    cap = read_views_capture(views_dir)
    assert len(cap) == 3 and cap.names == ("view_00.png", "view_01.png", "view_02.png")
    c = cap.centres
    assert np.linalg.norm(c[2] - c[0]) == pytest.approx(40.0, abs=1e-6)
    assert np.allclose(c[1], 0.5 * (c[0] + c[2]), atol=1e-6)  # evenly on the line
    assert np.ptp(c[:, 2]) < 1e-6  # the SCARA keeps its height
    assert all(im.shape == (SEED_CAMERA.image_size[1], SEED_CAMERA.image_size[0])
               for im in cap.images)
    # a textured block: the views differ where the block moves in the image
    assert np.abs(cap.images[0].astype(int) - cap.images[2]).mean() > 0.5


def test_capture_with_views_on_the_six_axis_arm_records_flanges_and_hand_eye(tmp_path):
    d = tmp_path / "six"
    assert main(["capture", "--views", "2", "--span", "30", "--robot", "six-axis",
                 "--out", str(d)]) == 0
    cap = read_views_capture(d)
    assert len(cap) == 2 and cap.flanges is not None and cap.hand_eye is not None
    for pose, flange in zip(cap.poses, cap.flanges, strict=True):
        assert np.allclose(pose.matrix, (flange @ cap.hand_eye).matrix)
    assert cap.span_mm == pytest.approx(30.0, abs=0.5)  # estimated hand-eye: not exact
    data = yaml.safe_load((d / "capture.yaml").read_text())
    assert "hand_eye" in data and all("flange" in v for v in data["views"])


def test_capture_without_views_is_the_two_view_capture(tmp_path):
    assert main(["capture", "--out", str(tmp_path / "two")]) == 0
    assert sorted(p.name for p in (tmp_path / "two").iterdir()) == [
        "capture.yaml", "left.png", "right.png"]


@pytest.mark.parametrize(("extra", "word"), [
    (["--views", "1"], "--views must be in 2..100, got 1"),
    (["--views", "101"], "--views must be in 2..100, got 101"),
    (["--views", "5", "--pattern", "zigzag"], "--pattern must be one of line, cross, arc"),
    (["--views", "5", "--span", "0"], "--span must be > 0 mm"),
    (["--views", "5", "--span", "-10"], "--span must be > 0 mm"),
    (["--pattern", "cross"], "--pattern needs --views N"),
    (["--span", "40"], "--span needs --views N"),
    (["--views", "2", "--pattern", "cross"], "cross needs --views >= 3"),
    (["--views", "5", "--baseline", "30"], "--baseline is for two views"),
    (["--views", "5", "--seed", "-1"], "--seed must be >= 0"),
    (["--views", "5", "--robot", "six-axis", "--center", "300", "0"], "--center"),
    (["--views", "5", "--robot", "six-axis", "--tilt", "85"], "--tilt"),
])
def test_capture_refuses_bad_view_options_before_any_work(extra, word, tmp_path, capsys):
    _refused(["capture", "--out", tmp_path / "c", *extra], tmp_path, capsys, word)


def test_capture_views_into_a_full_folder_is_refused(tmp_path, capsys):
    full = tmp_path / "full"
    full.mkdir()
    (full / "x").write_text("x")
    _refused(["capture", "--views", "3", "--out", full], tmp_path, capsys,
             "exists and is not an empty folder")


# -- locate ----------------------------------------------------------------------------


def _block_top_mm() -> float:
    """The simulated block's top above the table (the scene's own default height)."""
    import inspect

    from robostereo.simulation.scenes import seed_block_scene

    return float(inspect.signature(seed_block_scene).parameters["height_mm"].default)


def test_locate_on_a_views_folder_writes_each_point_with_bound_confidence_and_view_count(
        views_dir, tmp_path, capsys):
    from robostereo.robot.views.locating import locate_views

    csv, ply = tmp_path / "p.csv", tmp_path / "p.ply"
    assert main(["locate", str(views_dir), "-o", str(csv), "--ply", str(ply)]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{views_dir}: 3 views, ") and str(csv) in out
    t = np.genfromtxt(csv, delimiter=",", names=True)
    for col in ("X_w", "Y_w", "Z_w", "bound_mm", "confidence", "view_count"):
        assert col in t.dtype.names
    assert len(t) > 100
    assert f"element vertex {len(t)}\n".encode() in ply.read_bytes()
    import trimesh

    verts = trimesh.load(ply, file_type="ply").metadata["_ply_raw"]["vertex"]["data"]
    for col in ("bound_mm", "confidence", "view_count"):
        assert np.allclose(verts[col], t[col], rtol=1e-5, atol=1e-5), col
    # the same points as the library's, to the CSV's six significant digits
    lib = locate_views(read_views_capture(views_dir)).table()
    for col in ("Z_w", "bound_mm", "confidence", "view_count"):
        assert np.allclose(t[col], lib[col], rtol=1e-5, atol=1e-4), col
    assert ((t["view_count"] >= 2) & (t["view_count"] <= 3)).all()
    assert ((t["confidence"] >= 0) & (t["confidence"] <= 1)).all()
    # the block's top edges: nearly all within their bound of the true height
    within = np.abs(t["Z_w"] - _block_top_mm()) <= t["bound_mm"]
    assert within.mean() > 0.9, within.mean()


def test_locate_threshold_reaches_the_n_view_search_more_points_at_a_lower_one(
        views_dir, tmp_path, capsys):
    counts = {}
    for t in ("16", "5"):
        csv = tmp_path / f"t{t}.csv"
        assert main(["locate", str(views_dir), "-o", str(csv), "--threshold", t]) == 0
        counts[t] = len(np.genfromtxt(csv, delimiter=",", names=True))
    capsys.readouterr()
    assert counts["5"] > counts["16"] > 0, counts  # the block: 293 and 287
    # the pairs' two-view matcher takes it too
    for t in ("16", "5"):
        csv = tmp_path / f"p{t}.csv"
        assert main(["locate", str(views_dir), "-o", str(csv), "--threshold", t,
                     "--matcher", "pairs"]) == 0
        counts["p" + t] = len(np.genfromtxt(csv, delimiter=",", names=True))
    capsys.readouterr()
    assert counts["p5"] > counts["p16"] > 0, counts


def test_locate_refuses_a_threshold_that_is_not_positive(views_dir, tmp_path, capsys):
    _refused(["locate", views_dir, "-o", tmp_path / "p.csv", "--threshold", "0"],
             tmp_path, capsys, "threshold")


def test_a_two_view_folder_read_as_two_views_gives_the_two_view_points(tmp_path):
    from robostereo.robot.capture import locate_capture, write_capture
    from robostereo.robot.simulated.scara_rig import simulate_capture
    from robostereo.robot.views.locating import locate_views

    d = write_capture(tmp_path / "two", simulate_capture("block", seed=0).capture)
    today = locate_capture(d)
    two = locate_views(read_views_capture(d))  # through the two-view matcher (issue 34)
    assert len(two) == len(today) > 100
    np.testing.assert_allclose(two.world, today.world, atol=1e-9)
    np.testing.assert_allclose(two.bound_mm, today.z_bound, atol=1e-9)
    np.testing.assert_allclose(two.confidence, today.probability)


def test_locate_matcher_chooses_pairs_or_the_sweep_for_n_views_only(views_dir, tmp_path,
                                                                    capsys):
    from robostereo.robot.views.locating import locate_views
    from robostereo.robot.views.views_parameters import ViewsParameters

    cap = read_views_capture(views_dir)
    for matcher in ("pairs", "sweep"):
        csv = tmp_path / f"{matcher}.csv"
        assert main(["locate", str(views_dir), "--matcher", matcher, "-o", str(csv)]) == 0
        t = np.genfromtxt(csv, delimiter=",", names=True)
        lib = locate_views(cap, params=ViewsParameters(matcher=matcher))
        assert len(t) == len(lib) > 100
        np.testing.assert_allclose(t["Z_w"], lib.world[:, 2], rtol=1e-5, atol=1e-4)
    capsys.readouterr()
    # pairs: every point from the centre view, each seen by it and one or two others
    t = np.genfromtxt(tmp_path / "pairs.csv", delimiter=",", names=True)
    assert set(np.unique(t["reference"])) == {1.0}
    # a two-view folder has one matcher: the option is refused, nothing written
    from robostereo.robot.capture import write_capture
    from robostereo.robot.simulated.scara_rig import simulate_capture

    two = write_capture(tmp_path / "two", simulate_capture("block", seed=0).capture)
    before = sorted(p.name for p in two.iterdir())
    assert main(["locate", str(two), "--matcher", "pairs"]) == 2
    err = capsys.readouterr().err
    assert "--matcher" in err and "capture.yaml" in err and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in two.iterdir()) == before


# -- locate: bad N-view folders --------------------------------------------------------


def _other_size(data, d):
    cv2.imwrite(str(d / "view_01.png"), np.zeros((100, 120), np.uint8))


@pytest.mark.parametrize(("edit", "word"), [
    (_other_size, "views[1] (view_01.png): the image is 120 x 100 pixels"),
    (lambda data, d: data["views"][2].pop("pose"), "views[2] (view_02.png): missing key "
                                                   "'pose'"),
    (lambda data, d: [v.update(pose=data["views"][0]["pose"]) for v in data["views"]],
     "stand at one point"),
    (lambda data, d: data.update(views=data["views"][:1]), "at least two views, got 1"),
    (lambda data, d: data["views"][1].update(image="view_00.png"), "the same image file"),
    (lambda data, d: data["views"][1].update(image="./view_00.png"),
     "views[1] (./view_00.png): the same image file as views[0]"),
    (lambda data, d: ((d / "link.png").symlink_to("view_00.png"),
                      data["views"][2].update(image="link.png")),
     "views[2] (link.png): the same image file as views[0]"),
    (lambda data, d: (d / "view_02.png").unlink(), "views[2] (view_02.png)"),
    (lambda data, d: (d / "view_01.png").write_bytes(b"\x89PNG\r\n not an image"),
     "views[1] (view_01.png): "),
])
def test_locate_refuses_a_bad_views_folder_in_one_line_writing_nothing(views_dir, tmp_path,
                                                                       capsys, edit, word):
    d = _edited(views_dir, tmp_path / "bad", edit)
    err = _refused(["locate", d, "--ply", tmp_path / "p.ply"], tmp_path, capsys, word)
    assert str(d / "capture.yaml") in err


@pytest.mark.parametrize(("outputs", "word"), [
    (["-o", "{d}/view_01.png"], "-o {d}/view_01.png is an input"),
    (["-o", "{d}/capture.yaml"], "-o {d}/capture.yaml is an input"),
    (["-o", "{d}/../c/./capture.yaml"], "is an input"),
    (["--ply", "{d}/view_02.png"], "--ply {d}/view_02.png is an input"),
    (["-o", "{d}/p.csv", "--ply", "{d}/p.csv"], "--ply {d}/p.csv is the same file as -o"),
    (["--ply", "{d}/located.csv"], "the same file as -o"),  # -o's default
    (["--fuse", "{d}"], "--fuse"),
])
def test_locate_refuses_an_input_or_one_file_twice_as_its_outputs(views_dir, tmp_path,
                                                                   capsys, outputs, word):
    d = tmp_path / "c"
    shutil.copytree(views_dir, d)
    _refused(["locate", d, *(o.format(d=d) for o in outputs)], tmp_path, capsys,
             word.format(d=d))


@pytest.mark.parametrize("views_first", [True, False])
def test_locate_fuse_names_the_n_view_folder_whichever_it_is(views_dir, tmp_path, capsys,
                                                             views_first):
    """``--fuse`` merges two-view captures: the error names the folder of N views, not
    the two-view one beside it (it named the first folder whichever was at fault)."""
    two = tmp_path / "two"
    assert main(["capture", "--out", str(two)]) == 0
    views = tmp_path / "views"
    shutil.copytree(views_dir, views)
    capsys.readouterr()
    first, second = (views, two) if views_first else (two, views)
    err = _refused(["locate", first, "--fuse", second], tmp_path, capsys, "--fuse")
    assert err.startswith(f"robostereo: error: {views / 'capture.yaml'}: has N views"), err
    assert str(two) not in err


# -- plan ------------------------------------------------------------------------------


def _json(args: list[str], capsys) -> dict:
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


def test_plan_with_two_views_is_todays_plan(capsys):
    base = ["plan", "--depth", "1000", "--accuracy", "2", "--json"]
    today = _json(base, capsys)
    two = _json([*base, "--views", "2"], capsys)
    assert two["views"] == 2 and two["pattern"] == "line"
    assert two["span_mm"] == today["baseline_mm"]
    assert two["disparity_range"] == today["disparity_range"]
    assert two["bound_terms_mm"] == today["bound_terms_mm"]


def test_plan_with_more_views_needs_less_span_and_auto_keeps_neighbours_close(capsys):
    base = ["plan", "--depth", "1000", "--accuracy", "1", "--json"]
    spans = [_json([*base, "--views", str(n)], capsys)["span_mm"] for n in (2, 5, 9)]
    assert spans[0] > spans[1] > spans[2]
    auto = _json([*base, "--views", "auto"], capsys)
    assert auto["views"] > 2 and auto["step_disparity_px"] <= 30.0
    assert main(["plan", "--depth", "1000", "--accuracy", "1", "--views", "5", "--pattern",
                 "cross"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("5 views on a cross spanning") and "as precise as two views" in out


@pytest.mark.parametrize(("extra", "word"), [
    (["--views", "1"], "--views must be in 2..100, got 1"),
    (["--views", "many"], "--views must be a whole number"),
    (["--views", "5", "--pattern", "zigzag"], "--pattern must be one of"),
    (["--pattern", "line"], "--pattern needs --views"),
    (["--views", "5", "--image", "x.png"], "--image"),
])
def test_plan_refuses_bad_view_options(extra, word, tmp_path, capsys):
    _refused(["plan", "--depth", "1000", "--accuracy", "1", *extra], tmp_path, capsys, word)


# -- demo ------------------------------------------------------------------------------


def test_demo_with_views_prints_the_issue_keys_as_json_and_as_lines(capsys):
    """Two views (the quickest run): the keys, the lift near the truth, fractions."""
    from robostereo.cli.demo import print_views_demo

    s = _json(["demo", "--views", "2", "--span", "40", "--json"], capsys)
    for key in ("views", "lift_mm", "lift_true_mm", "max_abs_error_mm", "all_within_bound",
                "outline_coverage", "pulley_matched", "pulley_false", "seconds"):
        assert key in s, key
    assert s["views"] == 2 and isinstance(s["all_within_bound"], bool)
    assert abs(s["lift_mm"] - s["lift_true_mm"]) < 2.0
    for key in ("outline_coverage", "pulley_matched", "pulley_false"):
        assert 0.0 <= s[key] <= 1.0, key
    print_views_demo(s)
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "2 views on a line spanning 40 mm, AdeptOne"
    assert any(ln.split()[:2] == ["lift", "measured,"] for ln in lines)
    assert any(ln.strip().startswith("every point within its bound") and
               ln.split()[-1] in ("yes", "NO") for ln in lines)


# -- demo: bad options ------------------------------------------------------------------


@pytest.mark.parametrize(("extra", "word"), [
    (["--views", "1"], "--views must be in 2..100"),
    (["--views", "101"], "--views must be in 2..100"),
    (["--views", "5", "--pattern", "zigzag"], "--pattern must be one of"),
    (["--views", "5", "--span", "0"], "--span must be > 0"),
    (["--span", "80"], "--span needs --views"),
    (["--views", "5", "--out", "{tmp}/o"], "--out"),
    (["--views", "5", "--seed", "-2"], "--seed"),
])
def test_demo_refuses_bad_view_options(extra, word, tmp_path, capsys):
    _refused(["demo", *(a.replace("{tmp}", str(tmp_path)) for a in extra)], tmp_path, capsys,
             word)
