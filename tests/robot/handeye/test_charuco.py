"""ChArUco boards: the board keys, corners with ids, partial views calibrated.

The views come from ``tests/board_renders.py``: OpenCV's drawing of the board
(``CharucoBoard.generateImage``) warped into the tests' own ray caster (pinhole,
k1 = -0.1, 640 x 480, f 800 px, 1.5 grey levels of noise), one quarter of the board in
each view covered by a grey patch (or out of the frame); eye-in-hand a 9 x 6-square
board of 20 mm squares (15 mm markers) 420-520 mm away, eye-to-hand 10 x 7 squares of
30 mm (22 mm markers) 650-750 mm away, 14 views each.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from board_renders import (
    BASE_CAMERA,
    X_TRUE,
    charuco_corners_in_image,
    render_charuco_eye_to_hand_views,
    render_charuco_views,
)

from robostereo.errors import InputError, PlausibilityWarning
from robostereo.io import write_image_folder
from robostereo.robot.handeye import (
    MIN_CHARUCO_CORNERS,
    Charuco,
    CharucoCorners,
    calibrate_eye_in_hand,
    calibrate_eye_to_hand,
    charuco_view_problem,
    detect_charuco,
    read_views,
)


@pytest.fixture(scope="module")
def in_hand():
    return {seed: render_charuco_views(seed) for seed in range(3)}


@pytest.fixture(scope="module")
def to_hand():
    return {seed: render_charuco_eye_to_hand_views(seed) for seed in range(3)}


def _board(r):
    return Charuco(r.squares, r.square_mm, r.marker_mm, r.dictionary)


def _errors(truth, T):
    t, r = truth.distance_to(T)
    return t, math.degrees(r)


def test_detected_corner_ids_name_the_board_points_seen(in_hand):
    r = in_hand[0]
    board = _board(r)
    c, rows = r.squares
    # the renders' board frame, built independently: inner corner (i, j) at (i+1, j+1) squares
    xs, ys = np.meshgrid(np.arange(1, c), np.arange(1, rows))
    grid = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)]) * r.square_mm
    for img, T, quarter in zip(r.images[:4], r.camera_board, r.hidden, strict=False):
        found = detect_charuco(img, board)
        truth = charuco_corners_in_image(T.inv(), r.squares, r.square_mm)
        assert np.all(np.diff(found.ids) > 0)
        assert np.array_equal(found.object_points, grid[found.ids])
        # every corner found is where its id puts it (0.036 px RMS, under 0.15 px max)
        assert np.abs(found.pixels - truth[found.ids]).max() < 0.25
        # a quarter hidden: about three quarters of the 40 corners, none deep in the patch
        assert 18 <= len(found.ids) <= 32
        far_x = grid[found.ids, 0] < r.square_mm * 2 if quarter in (0, 2) else \
            grid[found.ids, 0] > (c - 2) * r.square_mm
        far_y = grid[found.ids, 1] < r.square_mm * 2 if quarter in (0, 1) else \
            grid[found.ids, 1] > (rows - 2) * r.square_mm
        assert not np.any(far_x & far_y), quarter


def test_corner_refinement_beats_opencvs_next_to_the_markers(in_hand):
    board = _board(in_hand[0])
    err_cv, err = [], []
    for r in in_hand.values():
        for img, T in zip(r.images[:5], r.camera_board, strict=False):
            truth = charuco_corners_in_image(T.inv(), r.squares, r.square_mm)
            raw = detect_charuco(img, board, refine=False)
            fine = detect_charuco(img, board)
            assert np.array_equal(raw.ids, fine.ids)
            err_cv.append(raw.pixels - truth[raw.ids])
            err.append(fine.pixels - truth[fine.ids])
    rms_cv, rms = (float(np.sqrt(np.mean(np.sum(np.concatenate(e) ** 2, axis=1))))
                   for e in (err_cv, err))
    # measured: OpenCV's 0.07-0.08 px RMS, refined 0.03-0.04 px
    assert rms < 0.05 and rms < 0.7 * rms_cv, (rms, rms_cv)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_partial_charuco_views_calibrate_the_camera_on_the_flange(in_hand, seed):
    r = in_hand[seed]
    cal = calibrate_eye_in_hand(r.images, r.flange_poses, _board(r), pixel_pitch_mm=0.005)
    t, rot = _errors(X_TRUE, cal.hand_eye)
    # measured (seeds 0-2): 0.013-0.087 mm, 0.023-0.034 deg (the chessboard: 0.04-0.10
    # mm, 0.024-0.043 deg)
    assert t < 0.3 and rot < 0.05, (t, rot)
    assert cal.camera.fx == pytest.approx(800.0, rel=2e-3)
    assert cal.corners_per_view.shape == (14,) and cal.corners_per_view.max() < 34
    assert cal.corners_per_view.min() >= MIN_CHARUCO_CORNERS and not cal.left_out
    assert cal.reprojection_rms_px < 0.1


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_partial_charuco_views_calibrate_a_fixed_camera(to_hand, seed):
    r = to_hand[seed]
    cal = calibrate_eye_to_hand(r.images, r.flange_poses, _board(r), pixel_pitch_mm=0.005)
    t, rot = _errors(BASE_CAMERA, cal.base_camera)
    # measured (seeds 0-2): 0.007-0.10 mm, 0.023-0.032 deg (the chessboard: 0.08-0.23
    # mm, 0.015-0.050 deg)
    assert t < 0.3 and rot < 0.05, (t, rot)
    assert cal.corners_per_view.max() < 48 and cal.reprojection_rms_px < 0.1


def test_known_intrinsics_agree_with_partial_views_and_pin_both_modes(in_hand, to_hand):
    import warnings

    from robostereo.geometry.camera import Camera

    camera = Camera(focal_length_mm=4.0, pixel_pitch_mm=(0.005, 0.005), image_size=(640, 480),
                    principal_point=(320.0, 240.0), distortion=(-0.1, 0.0, 0.0, 0.0, 0.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")   # the views' own intrinsics agree: no warning
        for renders, solve, truth in ((in_hand, calibrate_eye_in_hand, X_TRUE),
                                      (to_hand, calibrate_eye_to_hand, BASE_CAMERA)):
            for r in renders.values():
                cal = solve(r.images, r.flange_poses, _board(r), camera=camera)
                t, rot = _errors(truth, cal.hand_eye)
                # measured (seeds 0-2, both modes): 0.007-0.031 mm, 0.0007-0.0025 deg;
                # OpenCV's corners as they come: 0.027-0.074 mm, 0.003-0.007 deg
                assert t < 0.05 and rot < 0.004, (t, rot)


@pytest.mark.parametrize("mode", ["eye-in-hand", "eye-to-hand"])
def test_boards_partly_out_of_the_frame_calibrate(mode):
    if mode == "eye-in-hand":
        r, solve, truth = render_charuco_views(1, hide="frame"), calibrate_eye_in_hand, X_TRUE
    else:
        r = render_charuco_eye_to_hand_views(1, hide="frame")
        solve, truth = calibrate_eye_to_hand, BASE_CAMERA
    cal = solve(r.images, r.flange_poses, _board(r), pixel_pitch_mm=0.005)
    t, rot = _errors(truth, cal.hand_eye)
    # measured (seeds 0-2, both modes): 0.008-0.027 mm, 0.002-0.016 deg
    assert t < 0.3 and rot < 0.05, (t, rot)
    assert cal.corners_per_view.min() < len(_board(r).object_points)


def test_views_without_enough_corners_are_named_and_left_out(in_hand):
    r = in_hand[2]
    images = list(r.images)
    images[3] = np.full_like(images[3], 110)             # no board
    images[7] = images[7].copy()
    images[7][:, 120:] = 110                              # a sliver of the board
    names = [f"view_{i:02d}.png" for i in range(14)]
    with pytest.warns(PlausibilityWarning) as seen:
        cal = calibrate_eye_in_hand(images, r.flange_poses, _board(r), names=names,
                                    pixel_pitch_mm=0.005)
    said = [str(w.message) for w in seen]
    assert any(s.startswith("view_03.png: ChArUco board 9 x 6 squares (DICT_5X5_100): 0 "
                            "ChArUco corners found") and s.endswith("view left out")
               for s in said), said
    assert cal.left_out == ("view_03.png", "view_07.png")
    assert len(cal.names) == 12 and "view_07.png" not in cal.names
    t, rot = _errors(X_TRUE, cal.hand_eye)
    assert t < 0.3 and rot < 0.05
    out = cal.to_dict()
    assert out["left_out_views"] == ["view_03.png", "view_07.png"]
    assert [v["corners"] for v in out["views"]] == cal.corners_per_view.tolist()
    blank = [np.full_like(images[0], 110)] * 2 + list(images[:2])
    with pytest.warns(PlausibilityWarning), pytest.raises(
            InputError, match=r"^renders: hand-eye needs at least 3 usable views, got 2: the "
                              r"ChArUco board .* found in too few views"):
        calibrate_eye_in_hand(blank, r.flange_poses[:4], _board(r), source="renders")


def test_corners_on_one_line_give_no_pose():
    b = Charuco((8, 6), 12.0, 9.0, "DICT_5X5_100")
    row = CharucoCorners(np.arange(7), np.zeros((7, 2)), b.object_points[:7])
    assert charuco_view_problem(row, b) == "its 7 ChArUco corners lie on one line"
    two_rows = np.r_[0:4, 7:11]
    ok = CharucoCorners(two_rows, np.zeros((8, 2)), b.object_points[two_rows])
    assert charuco_view_problem(ok, b) is None
    few = CharucoCorners(two_rows[:5], np.zeros((5, 2)), b.object_points[two_rows[:5]])
    assert "5 ChArUco corners found" in charuco_view_problem(few, b)


def test_legacy_boards_are_found_only_with_the_legacy_flag():
    legacy = Charuco((7, 6), 20.0, 15.0, "DICT_4X4_50", legacy=True)
    image = legacy.image(4.0, margin_mm=20.0)
    assert len(detect_charuco(image, legacy).ids) == 30
    today = Charuco((7, 6), 20.0, 15.0, "DICT_4X4_50")
    assert len(detect_charuco(image, today).ids) < MIN_CHARUCO_CORNERS


def _views_folder(tmp_path, board):
    d = tmp_path / "v"
    img = np.full((48, 64), 128, np.uint8)
    data = {"board": board, "pixel_pitch_mm": 0.005,
            "views": [{"image": f"view_{i}.png",
                       "flange": {"position": [i, 0, 0], "quaternion": [0, 0, 0, 1]}}
                      for i in range(3)]}
    write_image_folder(d, {f"view_{i}.png": img for i in range(3)},
                       {"views.yaml": yaml.safe_dump(data)})
    return d


def test_a_board_file_with_charuco_keys_is_read(tmp_path):
    d = _views_folder(tmp_path, {"type": "charuco", "squares": [9, 6], "square_mm": 20,
                                 "marker_mm": 15, "dictionary": "5x5_100"})
    b = read_views(d).board
    assert b == Charuco((9, 6), 20.0, 15.0, "DICT_5X5_100")
    assert b.square_mm == 20.0 and isinstance(b.square_mm, float) and not b.legacy
    (tmp_path / "2").mkdir()
    d2 = _views_folder(tmp_path / "2", {"type": "charuco", "squares": [7, 6], "square_mm": 20,
                                        "marker_mm": 15, "dictionary": "DICT_APRILTAG_36H11",
                                        "legacy": True})
    assert read_views(d2).board == Charuco((7, 6), 20.0, 15.0, "DICT_APRILTAG_36h11", True)


@pytest.mark.parametrize("change, message", [
    ({"dictionary": "DICT_5X5_99"}, r"dictionary 'DICT_5X5_99' is not an OpenCV ArUco "
                                    r"dictionary \(e\.g\. DICT_5X5_100"),
    ({"marker_mm": 20}, r"marker_mm must be below square_mm, got 20\.0 and 20\.0"),
    ({"squares": [3, 3]}, r"squares 3 x 3 is too small: a ChArUco board needs at least 6 "
                          r"inner corners"),
    ({"squares": [9, 6, 2]}, r"squares must be \[columns, rows\], got \[9, 6, 2\]"),
    ({"squares": [20, 20], "dictionary": "DICT_4X4_50"},
     r"squares 20 x 20 needs 200 markers but DICT_4X4_50 has only 50; use a larger "
     r"dictionary \(e\.g\. DICT_4X4_1000\)"),
    ({"marker_size": 15}, r"unknown key marker_size for a ChArUco board \(keys: type, "
                          r"squares, square_mm, marker_mm, dictionary, legacy\)"),
    ({"dictionary": None}, r"a ChArUco board needs dictionary"),
    ({"legacy": "yes"}, r"legacy must be true or false, got 'yes'"),
    ({"square_mm": "twenty"}, r"square_mm must be a finite number > 0, got 'twenty'"),
])
def test_bad_charuco_keys_are_refused_in_one_line(tmp_path, change, message):
    board = {"type": "charuco", "squares": [9, 6], "square_mm": 20.0, "marker_mm": 15.0,
             "dictionary": "DICT_5X5_100"}
    board.update(change)
    board = {k: v for k, v in board.items() if v is not None}
    d = _views_folder(tmp_path, board)
    with pytest.raises(InputError, match=r"^.*views\.yaml: board: " + message) as exc:
        read_views(d)
    assert "\n" not in str(exc.value)


def test_handeye_refuses_an_unknown_dictionary_with_exit_2_and_no_output(tmp_path, capsys):
    from robostereo.cli import main

    d = _views_folder(tmp_path, {"type": "charuco", "squares": [9, 6], "square_mm": 20.0,
                                 "marker_mm": 15.0, "dictionary": "DICT_5X5_99"})
    out = tmp_path / "camera.yaml"
    assert main(["handeye", str(d), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "board: dictionary 'DICT_5X5_99' is not an OpenCV" in err
    assert not out.exists()
