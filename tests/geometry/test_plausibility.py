"""Bounds a real capture's numbers stay within: focal length in pixels, image size,
translations, eq. 9's uncertainties, the disparities of a depth range."""

from __future__ import annotations

import pytest

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera, camera_from_dict
from robostereo.geometry.plausibility import (
    MAX_TRANSLATION_MM,
    check_depth_disparities,
    check_uncertainties,
)
from robostereo.geometry.poses import SE3, Pose, pose_from_dict

CAM = {"focal_length_mm": 25.0, "pixel_pitch_mm": [0.0172, 0.0137], "image_size": [509, 481]}


@pytest.mark.parametrize(("key", "value"), [
    ("focal_length_mm", 1e6), ("focal_length_mm", 1e308), ("focal_length_mm", 1e-6),
    ("pixel_pitch_mm", [1e-300, 0.0137]), ("pixel_pitch_mm", [0.0172, 1e-300]),
])
def test_a_focal_length_no_real_camera_has_in_pixels_is_refused(key, value) -> None:
    with pytest.raises(InputError, match=r"cam.yaml: focal_length_mm / pixel_pitch_mm = "):
        camera_from_dict({**CAM, key: value}, source="cam.yaml")


@pytest.mark.parametrize(("key", "value"), [
    ("focal_length_mm", 10**4000), ("image_size", [10**4000, 481]),
    ("principal_point", [10**4000, 240.0]), ("grey_levels", 10**4000),
])
def test_an_integer_too_big_for_a_float_is_refused_naming_the_key(key, value) -> None:
    with pytest.raises(InputError, match=rf"cam.yaml: key '{key}' .*<integer of"):
        camera_from_dict({**CAM, key: value}, source="cam.yaml")


def test_an_image_side_beyond_any_sensor_is_refused() -> None:
    with pytest.raises(InputError, match=r"image_size must be .* 100,000 pixels"):
        Camera(image_size=(50_900_000_000, 481))


def test_translations_beyond_any_robot_are_refused_naming_the_key() -> None:
    with pytest.raises(InputError, match=r"p.yaml: key 'x' = 1e\+308 mm is beyond"):
        pose_from_dict({"x": 1e308, "y": 0, "z": 1000}, source="p.yaml")
    with pytest.raises(InputError, match=r"p.yaml: key 'phi_deg' = 1e\+308"):
        pose_from_dict({"x": 0, "y": 0, "z": 1000, "phi_deg": 1e308}, source="p.yaml")
    with pytest.raises(InputError, match=r"p.yaml: .*translation component"):
        pose_from_dict({"position": [0, 0, 1e308], "quaternion": [0, 0, 0, 1]},
                       source="p.yaml")
    with pytest.raises(InputError, match=r"p.yaml: .*position must be 3 numbers"):
        pose_from_dict({"position": [0, 0, 10**400], "quaternion": [0, 0, 0, 1]},
                       source="p.yaml")
    with pytest.raises(InputError, match="beyond"):
        Pose(2 * MAX_TRANSLATION_MM, 0.0, 1000.0)
    assert SE3.from_rotvec([0, 0, MAX_TRANSLATION_MM], [0, 0, 0]).translation[2] == 1e9


def test_a_quaternion_of_norm_zero_is_refused() -> None:
    with pytest.raises(InputError, match=r"p.yaml: quaternion must have norm 1"):
        pose_from_dict({"position": [0, 0, 0], "quaternion": [0, 0, 0, 0]}, source="p.yaml")


@pytest.mark.parametrize(("kw", "key"), [
    ({"disparity_px": 1e308}, "disparity_px"), ({"disparity_px": 510.0}, "disparity_px"),
    ({"disparity_px": -0.1}, "disparity_px"), ({"focal_length_mm_unc": 25.0}, "focal_length_mm"),
    ({"baseline_mm": float("inf")}, "baseline_mm"), ({"baseline_mm": 10**400}, "baseline_mm"),
])
def test_uncertainties_that_leave_the_depth_bound_empty_are_refused(kw, key) -> None:
    args = {"baseline_mm": 0.01, "focal_length_mm_unc": 0.01, "disparity_px": 0.2, **kw}
    with pytest.raises(InputError, match=f"uncertainty '{key}'"):
        check_uncertainties(25.0, 509, **args)


def test_uncertainties_up_to_the_limits_are_accepted() -> None:
    check_uncertainties(25.0, 509, baseline_mm=0.0, focal_length_mm_unc=24.9, disparity_px=509)


def test_a_depth_range_spanning_more_disparities_than_two_images_is_refused() -> None:
    check_depth_disparities(1453.5, 20.0, (850.0, 1e308), 509)  # far: disparity 0
    for rng in [(1e-300, 1070.0), (1.0, 1070.0)]:
        with pytest.raises(InputError, match=r"depth_range_mm .* more than twice the image"):
            check_depth_disparities(1453.5, 20.0, rng, 509)
