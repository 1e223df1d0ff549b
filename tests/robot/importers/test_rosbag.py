"""Tests for robostereo.robot.importers.rosbag: ROS 1 and ROS 2 bags of a camera on an
arm (images rendered from known poses, camera_info, /tf and /tf_static) to views."""

from __future__ import annotations

import sys
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from rosbag_sources import EPOCH_NS, bag_scene, write_bag
from view_renders import RenderSpec, render_views

from robostereo.errors import InputError, PlausibilityWarning
from robostereo.geometry.poses import SE3
from robostereo.robot.importers import read_rosbag, views_capture_from_imported
from robostereo.robot.importers.rosbag import (
    choose_images,
    image_from_message,
    intrinsics_from_camera_info,
)

pytest.importorskip("rosbags")

TOPICS = {"image_topic": "/camera/image", "camera_info_topic": "/camera/camera_info",
          "base_frame": "base", "camera_frame": "camera_optical"}


@pytest.fixture(scope="module")
def rendered():
    """Three views 60 mm apart over the textured box (lens k1 = -0.1), as a bag scene."""
    cap, truth = render_views(RenderSpec(count=3, span_mm=60.0, seed=3))
    dist = [*cap.camera.distortion, 0.0]
    return cap, truth, bag_scene(list(cap.images), cap.camera.K, dist, list(cap.poses))


def _read(bag: Path, tmp_path: Path, **kw):
    work = tmp_path / f"work-{len(list(tmp_path.iterdir()))}"
    work.mkdir()
    return read_rosbag(bag, images=work, **{**TOPICS, **kw})


def _angle(a: SE3, b: SE3) -> float:
    return float(np.linalg.norm((a.inv() @ b).rotvec))


@pytest.mark.parametrize(("version", "encoding", "storage"), [
    (1, "mono8", ""), (2, "png", "sqlite3"), (2, "rgb8", "mcap")])
def test_imported_poses_are_the_rendered_views_through_the_interpolated_tf_chain(
        rendered, tmp_path, version, encoding, storage):
    cap, _, scene = rendered
    bag = write_bag(tmp_path / ("b.bag" if version == 1 else "b"), scene, version=version,
                    encoding=encoding, storage=storage)
    if version == 2:  # the storage file names its folder
        bag = next(p for p in bag.iterdir() if p.suffix in (".db3", ".mcap"))
    imported = _read(bag, tmp_path)
    assert [v.key for v in imported.views] == ["0", "1", "2"]
    for view, truth in zip(imported.views, cap.poses, strict=True):
        assert np.abs(view.pose.translation - truth.translation).max() < 0.01  # mm
        assert _angle(view.pose, truth) < 1e-4
        np.testing.assert_allclose(view.K, cap.camera.K)
        assert view.distortion == (*cap.camera.distortion, 0.0)
    # the flange samples nearest an image's stamp are far off it: interpolation counts
    flange_rows = [r for r in scene.tf_rows() if r[2] == "flange"]
    nearest = min(flange_rows, key=lambda r: abs(r[0] - scene.stamps_ns[1]))[3]
    assert np.linalg.norm((nearest @ scene.tf_rows()[0][3]).translation
                          - cap.poses[1].translation) > 1.0


def test_compressed_and_raw_images_give_the_same_capture(rendered, tmp_path):
    cap, _, scene = rendered
    caps = {}
    for enc in ("mono8", "mono16", "rgb8", "png", "jpeg"):
        bag = write_bag(tmp_path / f"{enc}.bag", scene, encoding=enc)
        caps[enc] = views_capture_from_imported(_read(bag, tmp_path),
                                                depth_range_mm=cap.depth_range_mm)
    for enc in ("mono8", "mono16", "rgb8", "png"):
        for a, b in zip(caps[enc].images, cap.images, strict=True):
            np.testing.assert_array_equal(a, b)
        assert caps[enc].camera == caps["mono8"].camera
        assert all(np.allclose(p.matrix, q.matrix) for p, q in
                   zip(caps[enc].poses, caps["mono8"].poses, strict=True))
    # JPEG: lossy, a grey level or two
    for a, b in zip(caps["jpeg"].images, cap.images, strict=True):
        assert np.abs(a.astype(int) - b).mean() < 2.0
    assert caps["jpeg"].camera == caps["mono8"].camera


def test_images_outside_the_tf_span_are_refused_beyond_the_tolerance(rendered, tmp_path):
    _, _, scene = rendered
    # the last transform is 61 ms after the last image: 65 ms is held (10 ms tolerance)
    held = _read(write_bag(tmp_path / "held.bag", scene, image_delay_s=0.065), tmp_path)
    assert len(held.views) == 3
    bag = write_bag(tmp_path / "late.bag", scene, image_delay_s=0.2)
    with pytest.raises(InputError, match=r"outside the tf from 'base' to 'flange'.*no "
                                         r"extrapolation past 0.01 s"):
        _read(bag, tmp_path)


@pytest.mark.parametrize(("kw", "words"), [
    ({"camera_frame": "camera_link"}, "no tf chain from 'base' to 'camera_link'"),
    ({"base_frame": "world"}, "no tf chain from 'world' to 'camera_optical'"),
    ({"image_topic": "/cam/image_raw"}, "no topic /cam/image_raw (its image topics: "
                                        "/camera/image)"),
    ({"camera_info_topic": "/camera/image"}, "/camera/image is "
                                             "sensor_msgs/msg/CompressedImage, not "
                                             "sensor_msgs/msg/CameraInfo"),
])
def test_a_missing_frame_chain_or_topic_is_refused_in_one_line(rendered, tmp_path, kw, words):
    _, _, scene = rendered
    bag = write_bag(tmp_path / "b", scene, version=2, encoding="png")
    with pytest.raises(InputError) as exc, warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)  # the images' frame differs
        _read(bag, tmp_path, **kw)
    assert words in str(exc.value) and "\n" not in str(exc.value)


def test_images_in_another_frame_than_the_camera_frame_warn(rendered, tmp_path):
    _, _, scene = rendered
    bag = write_bag(tmp_path / "b.bag", scene, image_frame="/camera_link")
    with pytest.warns(PlausibilityWarning, match="the images are in frame 'camera_link', "
                                                 "not --camera-frame 'camera_optical'"):
        assert len(_read(bag, tmp_path).views) == 3
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        same = write_bag(tmp_path / "same.bag", scene, image_frame="/camera_optical")
        _read(same, tmp_path, base_frame="/base")  # ROS 1's leading /: the same frames


def test_a_bag_without_tf_static_has_no_chain_to_the_camera(rendered, tmp_path):
    _, _, scene = rendered
    bag = write_bag(tmp_path / "b.bag", scene, leave_out=("/tf_static",))
    with pytest.raises(InputError, match="no tf chain from 'base' to 'camera_optical'"):
        _read(bag, tmp_path)


def test_camera_info_of_another_size_than_the_images_is_refused_naming_the_topic(
        rendered, tmp_path):
    _, _, scene = rendered
    bag = write_bag(tmp_path / "b.bag", scene, info_size=(320, 240))
    with pytest.raises(InputError, match=r"/camera/camera_info: camera_info is 320 x 240 px "
                                         r"but the images on /camera/image are 640 x 480"):
        _read(bag, tmp_path)


def test_a_path_that_is_not_a_bag_is_refused(tmp_path):
    (tmp_path / "folder").mkdir()
    with pytest.raises(InputError, match="not a ROS bag"):
        _read(tmp_path / "folder", tmp_path)
    (tmp_path / "x.bag").write_bytes(b"not a bag at all")
    with pytest.raises(InputError, match="cannot read the bag"):
        _read(tmp_path / "x.bag", tmp_path)


def test_without_rosbags_the_error_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)
    with pytest.raises(InputError, match=r"pip install 'robostereo\[ros\]'"):
        _read(tmp_path / "x.bag", tmp_path)


def _small_scene(n: int, step_s: float):
    rng = np.random.default_rng(4)
    images = [rng.integers(0, 256, (48, 64)).astype(np.uint8) for _ in range(n)]
    K = np.array([[80.0, 0, 31.5], [0, 80.0, 23.5], [0, 0, 1]])
    poses = [SE3.look_at([10.0 * k, 0.0, -500.0], [0.0, 0.0, 0.0], up=(0.0, -1.0, 0.0))
             for k in range(n)]
    return bag_scene(images, K, [], poses, gaps_s=(step_s,) * (n - 1))


def test_every_takes_the_first_image_of_each_interval(tmp_path):
    scene = _small_scene(12, 0.1)  # 10 images a second, 1.1 s
    bag = write_bag(tmp_path / "b.bag", scene)
    imported = _read(bag, tmp_path, every=0.25)
    assert [v.key for v in imported.views] == ["0", "3", "5", "8", "10"]
    assert np.allclose(imported.views[2].pose.translation, scene.poses[5].translation)
    assert len(_read(bag, tmp_path, every=0.5).views) == 3
    assert len(_read(bag, tmp_path).views) == 12


def test_at_takes_the_images_nearest_the_stamps(tmp_path):
    scene = _small_scene(6, 0.1)
    bag = write_bag(tmp_path / "b.bag", scene)
    t0 = scene.stamps_ns[0] / 1e9
    imported = _read(bag, tmp_path, at=[t0 + 0.42, t0 + 0.04])
    assert [v.key for v in imported.views] == ["4", "0"]
    assert np.allclose(imported.views[0].pose.translation, scene.poses[4].translation)
    with pytest.raises(InputError, match=r"no image near 3\.000000 s"):
        _read(bag, tmp_path, at=[3.0])  # seconds since the bag's start: not its clock


def test_more_than_fifty_images_warn(tmp_path):
    scene = _small_scene(52, 0.05)
    bag = write_bag(tmp_path / "b.bag", scene)
    with pytest.warns(PlausibilityWarning, match="52 images taken"):
        _read(bag, tmp_path)


def test_choose_images_refuses_a_stamp_picking_an_image_twice():
    s = [EPOCH_NS + k * 100_000_000 for k in range(5)]
    with pytest.raises(InputError, match="again"):
        choose_images(s, at=[s[1] / 1e9, s[1] / 1e9 + 0.01])
    with pytest.raises(InputError, match="--every must be > 0"):
        choose_images(s, every=0.0)


# ---------------------------------------------------------------- messages


def _raw(encoding: str, pixels: np.ndarray, *, big: bool = False, pad: int = 0):
    h, w = pixels.shape[:2]
    data = np.ascontiguousarray(pixels).view(np.uint8).reshape(h, -1)
    data = np.pad(data, ((0, 0), (0, pad)))
    return SimpleNamespace(encoding=encoding, height=h, width=w, step=data.shape[1],
                           is_bigendian=int(big), data=data.ravel())


def test_raw_images_of_each_encoding_come_out_in_opencvs_order():
    rgb = np.random.default_rng(0).integers(0, 256, (5, 7, 3)).astype(np.uint8)
    bgr, _ = image_from_message(_raw("rgb8", rgb, pad=3), "/t")
    np.testing.assert_array_equal(bgr, rgb[..., ::-1])
    np.testing.assert_array_equal(image_from_message(_raw("bgr8", rgb), "/t")[0], rgb)
    rgba = np.concatenate([rgb, np.full((5, 7, 1), 255, np.uint8)], axis=2)
    np.testing.assert_array_equal(image_from_message(_raw("rgba8", rgba), "/t")[0],
                                  rgba[..., [2, 1, 0, 3]])
    np.testing.assert_array_equal(image_from_message(_raw("bgra8", rgba), "/t")[0], rgba)
    grey16 = np.arange(35, dtype=np.uint16).reshape(5, 7) * 1000
    np.testing.assert_array_equal(image_from_message(_raw("mono16", grey16.astype(">u2"),
                                                          big=True), "/t")[0], grey16)
    with pytest.raises(InputError, match="/t: image encoding 'bayer_rggb8' is not read"):
        image_from_message(_raw("bayer_rggb8", rgb[..., 0]), "/t")
    short = _raw("mono8", rgb[..., 0])
    short.data = short.data[:-1]
    with pytest.raises(InputError, match="too few"):
        image_from_message(short, "/t")


def _info(model: str, D: list[float], **kw):
    roi = SimpleNamespace(x_offset=0, y_offset=0, width=0, height=0)
    return SimpleNamespace(**{"k": [500.0, 0, 319.5, 0, 505.0, 239.5, 0, 0, 1], "d": D,
                              "width": 640, "height": 480, "distortion_model": model,
                              "binning_x": 0, "binning_y": 0, "roi": roi, **kw})


def test_camera_info_distortion_models_become_opencv_coefficients():
    K, size, d = intrinsics_from_camera_info(_info("plumb_bob", [-0.1, 0.01, 0, 0, 0]), "/i")
    assert size == (640, 480) and K[1, 1] == 505.0 and d == (-0.1, 0.01, 0.0, 0.0, 0.0)
    d = intrinsics_from_camera_info(_info("rational_polynomial", [-0.1, 0.01, 0.001, 0, 0.02,
                                                                  0, 0, 0]), "/i")[2]
    assert d == (-0.1, 0.01, 0.001, 0.0, 0.02)
    assert intrinsics_from_camera_info(_info("", []), "/i")[2] == ()
    with pytest.raises(InputError, match=r"/i: rational_polynomial with k4 \.\. k6"):
        intrinsics_from_camera_info(_info("rational_polynomial", [0.1] * 8), "/i")
    with pytest.raises(InputError, match="/i: distortion_model 'equidistant' is not read"):
        intrinsics_from_camera_info(_info("equidistant", [0.1] * 4), "/i")
    with pytest.raises(InputError, match="/i: camera_info has binning 2 x 2"):
        intrinsics_from_camera_info(_info("plumb_bob", [], binning_x=2, binning_y=2), "/i")
