"""N-view capture folders: written, read back equal, two-view folders read as N = 2,
bad folders refused naming the file and the view."""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml

from robostereo.errors import InputError, PlausibilityWarning
from robostereo.geometry.camera import SEED_CAMERA
from robostereo.geometry.poses import SE3, se3_from_scara
from robostereo.robot.capture.capture_folder import read_capture, write_capture
from robostereo.robot.views.viewpoints import ViewsCapture
from robostereo.robot.views.views_folder import (
    is_views_folder,
    read_views_capture,
    views_folder_files,
    write_views_capture,
)

W, H = SEED_CAMERA.image_size


def _images(n: int, seed: int = 0) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    return tuple(rng.integers(0, 128, (H, W), dtype=np.uint8) for _ in range(n))


@pytest.fixture(scope="module")
def line_capture() -> ViewsCapture:
    poses = tuple(se3_from_scara(400.0 + x, 5.0, 1050.0, 0.1) for x in (-40, -20, 0, 20, 40))
    return ViewsCapture(_images(5), SEED_CAMERA, poses, depth_range_mm=(950.0, 1100.0),
                        notes={"robot": {"name": "sim"}, "scene": "block"})


@pytest.fixture(scope="module")
def folder(line_capture, tmp_path_factory) -> Path:
    return write_views_capture(tmp_path_factory.mktemp("views") / "cap", line_capture)


@pytest.fixture(scope="module")
def six_axis_two_view():
    from robostereo.robot.simulated.sixaxis_rig import simulate_six_axis_capture

    return simulate_six_axis_capture("block").capture


def _edit(src: Path, dst: Path, edit) -> Path:
    shutil.copytree(src, dst)
    p = dst / "capture.yaml"
    data = yaml.safe_load(p.read_text())
    edit(data)
    p.write_text(yaml.safe_dump(data))
    return dst


def test_written_views_read_back_with_equal_images_and_poses(line_capture, folder):
    back = read_views_capture(folder)
    assert sorted(p.name for p in folder.iterdir()) == [
        "capture.yaml", "view_00.png", "view_01.png", "view_02.png", "view_03.png",
        "view_04.png"]
    assert len(back) == 5 and back.names == tuple(f"view_{k:02d}.png" for k in range(5))
    for a, b in zip(back.images, line_capture.images, strict=True):
        assert a.dtype == np.uint8 and np.array_equal(a, b)
    for a, b in zip(back.poses, line_capture.poses, strict=True):
        assert np.allclose(a.matrix, b.matrix, atol=1e-9)
    assert back.camera == line_capture.camera
    assert back.depth_range_mm == line_capture.depth_range_mm
    assert back.bit_depth == line_capture.bit_depth
    assert back.disparity_uncertainty_px == line_capture.disparity_uncertainty_px
    assert dict(back.notes) == dict(line_capture.notes)
    assert is_views_folder(folder)
    assert [p.name for p in views_folder_files(folder)] == [
        "capture.yaml", *(f"view_{k:02d}.png" for k in range(5))]


def test_flange_views_keep_their_flanges_and_hand_eye(six_axis_two_view, tmp_path):
    vc = ViewsCapture.from_capture(six_axis_two_view)
    assert vc.flanges is not None
    d = write_views_capture(tmp_path / "f", vc)
    data = yaml.safe_load((d / "capture.yaml").read_text())
    assert "hand_eye" in data and all(set(v) == {"image", "flange"} for v in data["views"])
    back = read_views_capture(d)
    for a, b in zip(back.flanges, vc.flanges, strict=True):
        assert np.allclose(a.matrix, b.matrix, atol=1e-9)
    assert np.allclose(back.hand_eye.matrix, vc.hand_eye.matrix, atol=1e-9)
    for a, b in zip(back.poses, vc.poses, strict=True):
        assert np.allclose(a.matrix, b.matrix, atol=1e-6)


def test_a_two_view_folder_reads_as_two_views_left_first(six_axis_two_view, tmp_path):
    d = write_capture(tmp_path / "two", six_axis_two_view)
    assert not is_views_folder(d)
    two = read_capture(d)
    vc = read_views_capture(d)
    assert len(vc) == 2 and vc.names == ("left.png", "right.png")
    assert np.array_equal(vc.images[0], two.left) and np.array_equal(vc.images[1], two.right)
    assert np.allclose(vc.poses[0].matrix, two.pose_left.matrix)
    assert np.allclose(vc.poses[1].matrix, two.pose_right.matrix)
    assert vc.depth_range_mm == two.depth_range_mm
    assert [p.name for p in views_folder_files(d)] == ["capture.yaml", "left.png",
                                                       "right.png"]


def test_a_scara_two_view_folder_of_disparities_takes_their_depths(tmp_path):
    from robostereo.robot.simulated.scara_rig import simulate_capture

    cap = simulate_capture("block", seed=0).capture
    d = write_capture(tmp_path / "s", cap)
    vc = read_views_capture(d)
    pair = vc.pair(0, 1)
    assert pair.pose_left.x == cap.pose_left.x and pair.pose_right.x == cap.pose_right.x
    near, far = vc.depth_range_mm
    assert near <= 1000.0 <= far  # the block's top is about a metre below the camera


def _bad_size(d: Path) -> None:
    import cv2

    cv2.imwrite(str(d / "view_02.png"), np.zeros((H - 1, W), np.uint8))


@pytest.mark.parametrize(("edit", "files", "message"), [
    (lambda v: v["views"][3].pop("pose"), None, r"views\[3\] \(view_03\.png\): missing key "
                                                r"'pose'"),
    (lambda v: v.update(views=v["views"][:1]), None, "at least two views, got 1"),
    (lambda v: v["views"][4].update(image="view_01.png"), None,
     r"views\[4\] \(view_01\.png\): the same image file as views\[1\]"),
    (lambda v: [x.update(pose=v["views"][0]["pose"]) for x in v["views"]], None,
     "one point"),
    (lambda v: v["views"][2].update(image="gone.png"), None, r"views\[2\] \(gone\.png\)"),
    (None, _bad_size, r"views\[2\] \(view_02\.png\): the image is 509 x 480 pixels"),
    (lambda v: v["views"][1].update(image="../x.png"), None, "inside the capture folder"),
    (lambda v: v["views"][0].update(flange=v["views"][0]["pose"]), None, "not both"),
    (lambda v: v["views"][1].update(flange=v["views"][1].pop("pose")), None,
     r"views\[1\] \(view_01\.png\): gives 'flange' where the views before give the other"),
    (lambda v: [x.update(flange=x.pop("pose")) for x in v["views"]], None,
     r"views\[0\] \(view_00\.png\): a flange pose needs the top-level key 'hand_eye'"),
    (lambda v: v.update(disparity_range=[20, 30]), None, "depth_range_mm"),
    (lambda v: v.pop("depth_range_mm"), None, "missing key 'depth_range_mm'"),
    (lambda v: v["views"][0].update(colour=1), None, r"views\[0\]: unknown key 'colour'"),
])
def test_bad_views_folders_are_refused_naming_the_file_and_view(folder, tmp_path, edit, files,
                                                                 message):
    d = _edit(folder, tmp_path / "bad", edit or (lambda v: None))
    if files is not None:
        files(d)
    with pytest.raises(InputError, match=message) as info:
        read_views_capture(d)
    assert str(info.value).startswith(str(d / "capture.yaml"))
    assert "\n" not in str(info.value)


def _images_named(folder: Path, dst: Path, count: int, name_of) -> Path:
    """A copy of `folder` with its first `count` views, view k's image named
    ``name_of(k, dst)``."""
    def edit(v):
        v["views"] = v["views"][:count]
        for k, view in enumerate(v["views"]):
            view["image"] = str(name_of(k, dst))
    return _edit(folder, dst, edit)


@pytest.mark.parametrize("count", [2, 5])
@pytest.mark.parametrize("way", ["as given", "folder by a link", "files by a link"])
def test_an_absolute_image_path_inside_the_folder_is_accepted(line_capture, folder, tmp_path,
                                                              count, way):
    """capture.yaml's ``image:`` as an absolute path into the folder (written by a robot
    that knows only absolute paths) is the folder's file: it was refused as outside."""
    real = tmp_path / "real"
    link = tmp_path / "link"
    link.symlink_to(real, target_is_directory=True)
    named = {"as given": real, "folder by a link": real, "files by a link": link}[way]
    _images_named(folder, real, count, lambda k, d: named / f"view_{k:02d}.png")
    read_from = link if way == "folder by a link" else real
    back = read_views_capture(read_from)
    assert back.names == tuple(f"view_{k:02d}.png" for k in range(count))  # as relative
    for a, b in zip(back.images, line_capture.images[:count], strict=True):
        assert np.array_equal(a, b)
    assert [p.name for p in views_folder_files(read_from)][1:] == list(back.names)


@pytest.mark.parametrize("count", [2, 5])
@pytest.mark.parametrize("where", ["another folder", "a linked subfolder", "dot-dot"])
def test_an_absolute_image_path_outside_the_folder_is_still_refused(folder, tmp_path, count,
                                                                    where):
    outside = tmp_path / "outside"
    outside.mkdir()
    shutil.copy(folder / "view_01.png", outside / "view_01.png")

    def name_of(k, d):
        if k != 1:
            return d / f"view_{k:02d}.png"
        if where == "another folder":
            return outside / "view_01.png"
        if where == "a linked subfolder":  # inside by its path, outside by its link
            (d / "sub").symlink_to(outside, target_is_directory=True)
            return d / "sub" / "view_01.png"
        return f"{d}/../outside/view_01.png"

    d = _images_named(folder, tmp_path / "cap", count, name_of)
    with pytest.raises(InputError, match=r"views\[1\] \(.*view_01\.png\): the image must be "
                                         "a file inside the capture folder") as info:
        read_views_capture(d)
    assert str(info.value).startswith(str(d / "capture.yaml"))


def test_writing_refuses_colour_and_leaves_nothing(line_capture, tmp_path):
    import dataclasses

    colour = tuple(np.dstack([im] * 3) for im in line_capture.images)
    bad = dataclasses.replace(line_capture, images=colour)
    with pytest.raises(InputError, match=r"view 0 \(view_00\.png\)"):
        write_views_capture(tmp_path / "c", bad)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(InputError, match="plain file name"):
        write_views_capture(tmp_path / "c", dataclasses.replace(
            line_capture, names=tuple(f"sub/{k}.png" for k in range(5))))
    assert list(tmp_path.iterdir()) == []


def test_translations_in_metres_warn_and_an_identity_hand_eye_warns(tmp_path):
    poses = tuple(SE3.from_rotvec([x, 0.0, 1.0], np.zeros(3)) for x in (-0.02, 0.0, 0.02))
    vc = ViewsCapture(_images(3), SEED_CAMERA, poses, depth_range_mm=(900.0, 1100.0))
    d = write_views_capture(tmp_path / "m", vc)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        read_views_capture(d)
    assert any(issubclass(w.category, PlausibilityWarning) and "unit: m" in str(w.message)
               for w in got)
    flanged = ViewsCapture.from_flange(
        _images(3), SEED_CAMERA, hand_eye=SE3.identity(),
        flanges=tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20.0, 0.0, 20.0)),
        depth_range_mm=(900.0, 1100.0))
    d2 = write_views_capture(tmp_path / "he", flanged)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        read_views_capture(d2)
    assert any("hand_eye is the identity" in str(w.message) for w in got)


# -- absurd numbers and alias bombs in two-view and N-view capture.yaml (issue 36, 8) --


def _folders(tmp_path: Path) -> dict[str, Path]:
    """A two-view and a three-view folder of the seed camera, 20 mm apart, 1 m away."""
    two = tmp_path / "two"
    from robostereo.geometry.poses import Pose
    from robostereo.robot.capture.capture_folder import Capture

    left, right = _images(2)
    write_capture(two, Capture(left=left, right=right, camera=SEED_CAMERA,
                               pose_left=Pose(-10.0, 0.0, 1000.0),
                               pose_right=Pose(10.0, 0.0, 1000.0),
                               depth_range_mm=(900.0, 1100.0)))
    three = tmp_path / "three"
    write_views_capture(three, ViewsCapture(
        _images(3), SEED_CAMERA, tuple(se3_from_scara(x, 0.0, 1000.0) for x in (-20, 0, 20)),
        depth_range_mm=(900.0, 1100.0)))
    return {"two-view": two, "N-view": three}


def _edited(folder: Path, old: str, new: str, prefix: str = "") -> Path:
    path = folder / "capture.yaml"
    text = path.read_text()
    assert old in text, (old, text)
    path.write_text(prefix + text.replace(old, new, 1))
    return folder


BOMB = "robot:\n  l0: &l0 [x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"  l{i}: &l{i} [{', '.join([f'*l{i - 1}'] * 9)}]\n" for i in range(1, 9))
BIG = "9" * 4000  # an integer too big for a float (Python reads up to 4300 digits)

ABSURD = [  # (old text, new text, a word the message must hold)
    ("focal_length_mm: 25.0", "focal_length_mm: 1.0e+6", "focal_length_mm / pixel_pitch_mm"),
    ("focal_length_mm: 25.0", "focal_length_mm: 1.0e+308", "focal_length_mm / pixel_pitch_mm"),
    ("pixel_pitch_mm: [0.0172, 0.0137]", "pixel_pitch_mm: [1.0e-300, 0.0137]",
     "focal_length_mm / pixel_pitch_mm"),
    ("focal_length_mm: 25.0", f"focal_length_mm: {BIG}", "'focal_length_mm'"),
    ("image_size: [509, 481]", f"image_size: [{BIG}, 481]", "'image_size'"),
    ("image_size: [509, 481]", "image_size: [50900000000, 481]", "image_size"),
    ("grey_levels: 128", f"grey_levels: {BIG}", "'grey_levels'"),
    ("disparity_px: 0.2", "disparity_px: 1.0e+308", "'disparity_px'"),
    ("disparity_px: 0.2", f"disparity_px: {BIG}", "'disparity_px'"),
    ("focal_length_mm: 0.01", "focal_length_mm: 30.0", "'focal_length_mm'"),
    ("depth_range_mm: [900.0, 1100.0]", "depth_range_mm: [1.0e-300, 1100.0]", "depth_range_mm"),
    ("depth_range_mm: [900.0, 1100.0]", f"depth_range_mm: [900.0, {BIG}]", "depth_range_mm"),
    ("depth_range_mm: [900.0, 1100.0]", "depth_range_mm: [1100.0, 900.0]", "depth_range_mm"),
    ("z: 1000.0", "z: 1.0e+308", "'z'"),
    ("z: 1000.0", f"z: {BIG}", "'z'"),
    ("phi_deg: 0.0", "phi_deg: 1.0e+308", "'phi_deg'"),
]


@pytest.mark.parametrize("kind", ["two-view", "N-view"])
@pytest.mark.parametrize(("old", "new", "word"), ABSURD)
def test_absurd_numbers_are_refused_in_one_line_naming_the_key(tmp_path, kind, old, new,
                                                                word) -> None:
    folder = _edited(_folders(tmp_path)[kind], old, new)
    with pytest.raises(InputError, match=None) as info:
        read_views_capture(folder)
    message = str(info.value)
    assert word in message and "\n" not in message and len(message) < 400, message


@pytest.mark.parametrize("kind", ["two-view", "N-view"])
@pytest.mark.parametrize(("old", "new"), [
    ("focal_length_mm: 25.0", "focal_length_mm: *l8"),
    ("depth_range_mm: [900.0, 1100.0]", "depth_range_mm: *l8"),
    ("disparity_px: 0.2", "disparity_px: *l8"),
])
def test_an_alias_bomb_under_robot_read_from_a_key_is_refused_in_one_line(
        tmp_path, kind, old, new) -> None:
    folder = _edited(_folders(tmp_path)[kind], old, new, prefix=BOMB)
    with pytest.raises(InputError, match="alias bomb") as info:
        read_views_capture(folder)
    assert "capture.yaml" in str(info.value) and len(str(info.value)) < 200


def test_plausible_numbers_still_read(tmp_path) -> None:
    for folder in _folders(tmp_path).values():
        cap = read_views_capture(_edited(folder, "disparity_px: 0.2", "disparity_px: 509"))
        assert cap.disparity_uncertainty_px == 509.0
