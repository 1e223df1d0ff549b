"""Tests for robostereo.cli.import_rosbag: ``robostereo import rosbag`` on bags of
rendered views, the folder it writes located, and its bad input (one line, exit 2,
nothing written)."""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml
from rosbag_sources import bag_scene, write_bag
from view_renders import RenderSpec, render_views

from robostereo.cli import main
from robostereo.errors import PlausibilityWarning
from robostereo.robot.views.views_folder import read_views_capture

pytest.importorskip("rosbags")

TOPICS = ["--image-topic", "/camera/image", "--camera-info-topic", "/camera/camera_info",
          "--base-frame", "base", "--camera-frame", "camera_optical"]


@pytest.fixture(scope="module")
def bag(tmp_path_factory):
    """A ROS 2 bag (PNG images) of three rendered views 60 mm apart, and its truth."""
    cap, truth = render_views(RenderSpec(count=3, span_mm=60.0, seed=3))
    scene = bag_scene(list(cap.images), cap.camera.K, [*cap.camera.distortion, 0.0],
                      list(cap.poses))
    d = tmp_path_factory.mktemp("rosbag")
    return write_bag(d / "bag", scene, version=2, encoding="png"), scene, cap, truth


def _contents(folder: Path) -> dict[Path, bytes | None]:
    return {p: p.read_bytes() if p.is_file() else None for p in sorted(folder.rglob("*"))}


def _refused(args: list[str], folder: Path, capsys, words: str) -> str:
    before = _contents(folder)
    rc = main([str(a) for a in args])
    out, err = capsys.readouterr()
    assert rc == 2 and out == "", (rc, out, err)
    assert len(err.splitlines()) == 1 and err.startswith("robostereo: error: "), err
    assert words in err, err
    assert _contents(folder) == before
    return err


def test_import_rosbag_writes_a_folder_that_locate_places_on_the_rendered_surface(
        bag, tmp_path, capsys):
    path, _, cap, truth = bag
    out = tmp_path / "cap"
    near, far = cap.depth_range_mm
    assert main(["import", "rosbag", str(path), *TOPICS, "--depth-range", str(near),
                 str(far), "--out", str(out)]) == 0
    assert f"{out}: 3 views of rosbag {path}, 640 x 480 px, fx 800.00 px" in \
        capsys.readouterr().out
    back = read_views_capture(out)
    assert back.names == ("frame_00000.png", "frame_00001.png", "frame_00002.png")
    for a, b in zip(back.poses, cap.poses, strict=True):
        assert np.abs(a.translation - b.translation).max() < 0.01
        assert np.linalg.norm((a.inv() @ b).rotvec) < 1e-4
    notes = yaml.safe_load((out / "capture.yaml").read_text())
    assert "rosbag" in str(notes) and "camera_optical" in str(notes)
    csv = tmp_path / "points.csv"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        assert main(["locate", str(out), "-o", str(csv)]) == 0
    capsys.readouterr()
    t = np.genfromtxt(csv, delimiter=",", names=True)
    err = truth.surface_distance(np.column_stack([t["X_w"], t["Y_w"], t["Z_w"]]))
    # measured: 155 points, median 0.09 mm, 95th percentile 1.7 mm (as the render's
    # own capture located directly)
    assert len(t) > 100
    assert np.median(err) < 0.3 and np.percentile(err, 95) < 3.0


def test_import_rosbag_every_and_views_choose_the_images(bag, tmp_path, capsys):
    path, scene, cap, _ = bag
    out = tmp_path / "cap"
    # images 0.6 and 0.7 s apart: one per second takes the first and the third
    assert main(["import", "rosbag", str(path), *TOPICS, "--every", "1.0", "--scale", "0.5",
                 "--depth-range", "300", "500", "--out", str(out)]) == 0
    back = read_views_capture(out)
    assert back.names == ("frame_00000.png", "frame_00002.png")
    assert back.camera.image_size == (320, 240)
    assert np.allclose(back.poses[1].translation, cap.poses[2].translation, atol=0.01)
    t1 = scene.stamps_ns[1] / 1e9
    out2 = tmp_path / "cap2"
    assert main(["import", "rosbag", str(path), *TOPICS, "--at", f"{t1 + 0.01}", "--views",
                 "1", "--depth-range", "300", "500", "--out", str(out2)]) == 2
    assert "at least two views" in capsys.readouterr().err
    assert main(["import", "rosbag", str(path), *TOPICS, "--views", "2,1",
                 "--depth-range", "300", "500", "--out", str(out2)]) == 0
    assert read_views_capture(out2).names == ("frame_00002.png", "frame_00001.png")


@pytest.mark.parametrize(("change", "words"), [
    ({"--camera-frame": "camera_link"}, "no tf chain from 'base' to 'camera_link'"),
    ({"--image-topic": "/image_raw"}, "no topic /image_raw"),
    ({"--depth-range": None}, "give --depth-range NEAR FAR"),
    ({"--every": "-1"}, "--every must be > 0"),
])
def test_import_rosbag_refuses_bad_input_in_one_line_writing_nothing(
        bag, tmp_path, capsys, change, words):
    path = bag[0]
    args = dict(zip(TOPICS[::2], TOPICS[1::2], strict=True))
    args["--depth-range"] = ["300", "500"]
    args.update(change)
    argv = ["import", "rosbag", path]
    for k, v in args.items():
        if v is not None:
            argv += [k, *(v if isinstance(v, list) else [v])]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        _refused([*argv, "--out", tmp_path / "cap"], path.parent, capsys, words)
    assert not (tmp_path / "cap").exists()


def test_import_rosbag_refuses_images_of_another_size_than_camera_info(bag, tmp_path, capsys):
    _, scene, _, _ = bag
    small = write_bag(tmp_path / "small.bag", scene, info_size=(320, 240))
    _refused(["import", "rosbag", small, *TOPICS, "--depth-range", "300", "500", "--out",
              tmp_path / "cap"], tmp_path, capsys,
             "/camera/camera_info: camera_info is 320 x 240 px but the images on "
             "/camera/image are 640 x 480")


def test_import_rosbag_without_rosbags_says_how_to_install_it(bag, tmp_path, capsys,
                                                               monkeypatch):
    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)
    _refused(["import", "rosbag", bag[0], *TOPICS, "--depth-range", "300", "500", "--out",
              tmp_path / "cap"], tmp_path, capsys, "pip install 'robostereo[ros]'")
