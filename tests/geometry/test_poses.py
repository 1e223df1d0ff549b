"""Tests for robostereo.geometry.poses: SE3, the SCARA Pose, and the pose file forms."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import (
    SE3,
    Pose,
    as_se3,
    pose_from_dict,
    pose_to_dict,
    relative_pose,
    scara_from_se3,
    scara_pose_from_dict,
    se3_from_scara,
)


def _random_pose(rng: np.random.Generator) -> SE3:
    return SE3(Rotation.random(random_state=rng).as_matrix(), rng.uniform(-500, 500, 3))


def test_compose_invert_apply():
    rng = np.random.default_rng(1)
    a, b = _random_pose(rng), _random_pose(rng)
    p = rng.normal(size=(5, 3)) * 100
    assert np.allclose((a @ b).apply(p), a.apply(b.apply(p)))
    assert np.allclose((a @ a.inv()).matrix, np.eye(4), atol=1e-12)
    assert np.allclose(a.inv().apply(a.apply(p)), p)
    t, r = a.distance_to(a @ SE3.from_rotvec([0, 0, 0], [0, 0, 0.01]))
    assert t == pytest.approx(0.0, abs=1e-9) and r == pytest.approx(0.01)


def test_forms_agree():
    """Matrix, quaternion (x, y, z, w), rotation vector and ROS (metres) give one pose."""
    rng = np.random.default_rng(2)
    T = _random_pose(rng)
    q, rv, t = T.quaternion, T.rotvec, T.translation
    forms = [
        {"matrix": T.matrix.tolist()},
        {"position": t.tolist(), "quaternion": q.tolist()},
        {"position": t.tolist(), "rotvec": rv.tolist()},
        {"position": (t / 1000).tolist(), "rotvec": rv.tolist(), "unit": "m"},
        {"translation": dict(zip("xyz", (t / 1000).tolist(), strict=True)),
         "rotation": dict(zip("xyzw", q.tolist(), strict=True))},
    ]
    for f in forms:
        P = pose_from_dict(f)
        assert isinstance(P, SE3)
        dt, dr = T.distance_to(P)
        assert dt < 1e-9 and dr < 1e-9, f
    assert T.distance_to(as_se3(pose_from_dict(pose_to_dict(T))))[0] < 1e-6
    # ROS order: (x, y, z, w); a half turn about x
    Rx = pose_from_dict({"position": [0, 0, 0], "quaternion": [1, 0, 0, 0]}).rotation
    assert np.allclose(Rx, np.diag([1.0, -1.0, -1.0]))


def test_scara_form_keeps_its_meaning():
    """{x, y, z, phi_deg} is today's SCARA pose, and its SE3 projects the same pixels."""
    p = pose_from_dict({"x": 400.0, "y": 10.0, "z": 1050.0, "phi_deg": 30.0})
    assert isinstance(p, Pose) and p.phi == pytest.approx(math.radians(30.0))
    cam = Camera()
    P = np.array([[380.0, 30.0, 50.0], [420.0, -20.0, 0.0]])
    uv1, z1 = cam.project(P, p)
    uv2, z2 = cam.project(P, as_se3(p))
    assert np.allclose(uv1, uv2) and np.allclose(z1, z2)
    assert pose_to_dict(p) == {"x": 400.0, "y": 10.0, "z": 1050.0, "phi_deg": 30.0}


def test_relative_pose_is_opencv_convention():
    rng = np.random.default_rng(3)
    a, b = _random_pose(rng), _random_pose(rng)
    rel = relative_pose(a, b)
    P = rng.normal(size=(4, 3)) * 100
    x_left = a.inv().apply(P)
    x_right = b.inv().apply(P)
    assert np.allclose(x_right, x_left @ rel.rotation.T + rel.translation)


@pytest.mark.parametrize("data, message", [
    ({"matrix": np.diag([1.0, 1.0, 1.01, 1.0]).tolist()}, "orthonormal"),
    ({"matrix": np.diag([1.0, 1.0, -1.0, 1.0]).tolist()}, "det"),
    ({"matrix": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}, "4 x 4"),
    ({"position": [0, 0, 0], "quaternion": [0, 0, 0, 2]}, "norm 1"),
    ({"position": [0, 0], "rotvec": [0, 0, 0]}, "position"),
    ({"position": [0, 0, 0]}, "quaternion"),
    ({"position": [0, 0, 0], "rotvec": [0, 0, float("nan")]}, "rotvec"),
    ({"position": [0, 0, 0], "rotvec": [0, 0, 0], "unit": "cm"}, "unit"),
    ({"position": [0, 0, 0], "rotvec": [0, 0, 0], "colour": 1}, "unknown key 'colour'"),
    ({"frame": "tool0"}, "not a pose"),
])
def test_bad_poses(data, message):
    with pytest.raises(InputError, match=message) as e:
        pose_from_dict(data, source="cap.yaml: pose_left")
    assert str(e.value).startswith("cap.yaml: pose_left") and "\n" not in str(e.value)


def test_look_at():
    T = SE3.look_at([0.0, -300.0, 800.0], [0.0, 0.0, 0.0])
    uv, z = Camera().project([[0.0, 0.0, 0.0]], T)
    assert np.allclose(uv, [Camera().principal_point])
    assert z[0] == pytest.approx(math.hypot(300, 800))
    with pytest.raises(InputError, match="coincide"):
        SE3.look_at([1.0, 2.0, 3.0], [1.0, 2.0, 3.0])


# ------------------------------------------------------------------ the SCARA pose


def test_scara_pose_is_an_se3_with_exact_matrices() -> None:
    p = Pose(10.0, -5.0, 900.0, 0.3)
    assert isinstance(p, SE3)
    c, s = math.cos(0.3), math.sin(0.3)
    exact = np.array([[c, s, 0.0], [s, -c, 0.0], [0.0, 0.0, -1.0]])
    assert np.array_equal(p.rotation, exact)  # bit for bit, not re-orthonormalised
    assert np.array_equal(p.position, np.array([10.0, -5.0, 900.0]))
    assert np.array_equal(p.translation, p.position)
    assert np.array_equal(p.apply([0.0, 0.0, 100.0]), exact @ [0.0, 0.0, 100.0] + p.position)


def test_scara_pose_equality_hash_and_repr_are_of_its_four_numbers() -> None:
    a, b = Pose(1.0, 2.0, 3.0, 0.5), Pose(1.0, 2.0, 3.0, 0.5)
    assert a == b and hash(a) == hash(b) and len({a, b}) == 1
    assert a != Pose(1.0, 2.0, 3.0, 0.6)
    assert repr(a) == "Pose(x=1.0, y=2.0, z=3.0, phi=0.5)"
    assert Pose(0.0, 0.0, 1.0) == Pose(0.0, 0.0, 1.0, 0.0)
    assert a != SE3(a.rotation, a.translation)  # a plain SE3 compares by identity
    with pytest.raises(InputError, match="pose"):
        Pose(math.nan, 0.0, 1.0)


def test_as_se3_of_a_scara_pose_is_the_plain_reorthonormalised_se3() -> None:
    p = Pose(-25.0, 3.0, 900.0, 0.05)
    T = as_se3(p)
    assert type(T) is SE3
    ref = SE3(p.rotation, p.position)
    assert np.array_equal(T.rotation, ref.rotation)
    assert np.array_equal(T.translation, ref.translation)
    assert np.array_equal(SE3.from_scara(p).rotation, ref.rotation)
    q = Pose(35.0, -2.0, 905.0, -0.04)
    rel = relative_pose(p, q)
    assert type(rel) is SE3
    assert np.array_equal(rel.rotation, (SE3(q.rotation, q.position).inv() @ ref).rotation)


def test_se3_from_scara_and_scara_from_se3_round_trip() -> None:
    rng = np.random.default_rng(3)
    for x, y, z, phi in rng.uniform([-500, -500, 500, -math.pi], [500, 500, 1500, math.pi],
                                    size=(20, 4)):
        T = se3_from_scara(x, y, z, phi)
        assert T == Pose(x, y, z, phi)
        assert scara_from_se3(T) is T  # a Pose is returned as it is
        back = scara_from_se3(SE3(T.rotation, T.translation))  # a plain SE3 looking down
        assert type(back) is Pose
        assert back.position == pytest.approx(T.position, abs=1e-9)
        assert math.remainder(back.phi - phi, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
        assert np.allclose(back.rotation, T.rotation, atol=1e-9)


def test_scara_from_se3_refuses_a_tilted_camera() -> None:
    tilted = SE3.look_at([0.0, -400.0, 900.0], [0.0, 0.0, 0.0])
    with pytest.raises(InputError, match="straight down"):
        scara_from_se3(tilted)
    with pytest.raises(InputError, match="SE3"):
        scara_from_se3("pose")  # type: ignore[arg-type]


def test_one_pose_from_dict_reads_the_scara_form() -> None:
    p = pose_from_dict({"x": 400.0, "y": 10.0, "z": 1050.0, "phi_deg": 30.0})
    assert p == Pose(400.0, 10.0, 1050.0, math.radians(30.0))
    assert p == scara_pose_from_dict({"x": 400.0, "y": 10.0, "z": 1050.0, "phi_deg": 30.0})
    assert pose_from_dict({"x": 1, "y": 2, "z": 3}).phi == 0.0
    assert pose_to_dict(p) == {"x": 400.0, "y": 10.0, "z": 1050.0, "phi_deg": 30.0}
    with pytest.raises(InputError, match=r"left\.yaml: missing key 'z'"):
        pose_from_dict({"x": 0, "y": 10}, source="left.yaml")
    with pytest.raises(InputError, match=r"p\.yaml: unknown key 'phi'"):
        scara_pose_from_dict({"x": 0, "y": 1, "z": 2, "phi": 3}, source="p.yaml")


def test_quaternions_printed_with_few_decimals_are_normalised_with_a_warning():
    from scipy.spatial.transform import Rotation

    from robostereo.errors import PlausibilityWarning

    rng = np.random.default_rng(5)
    for decimals in (3, 4, 5):
        for q in Rotation.random(50, random_state=rng).as_quat():
            printed = np.round(q, decimals).tolist()
            with warnings.catch_warnings(record=True) as rec:
                warnings.simplefilter("always")
                T = pose_from_dict({"position": [0, 0, 0], "quaternion": printed},
                                   source="left.yaml")
            noted = [str(w.message) for w in rec if w.category is PlausibilityWarning]
            off = abs(np.linalg.norm(printed) - 1)
            assert len(noted) == (off > 1e-6)  # the former tolerance: silent below
            assert all(m.startswith("left.yaml: quaternion of norm") for m in noted)
            assert np.degrees(T.distance_to(SE3(Rotation.from_quat(q).as_matrix(),
                                                np.zeros(3)))[1]) < 0.2


def test_a_quaternion_far_from_unit_norm_is_refused_naming_the_file():
    for q in ([0.0, 0.0, 0.0, 2.0], [0.5, 0.5, 0.5, 0.49], [1.0, 1.0, 0.0, 0.0]):
        with pytest.raises(InputError, match=r"^a\.yaml: quaternion must have norm 1 .*x, y, z, w"):
            pose_from_dict({"position": [0, 0, 0], "quaternion": q}, source="a.yaml")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an exact unit quaternion: no warning
        pose_from_dict({"position": [0, 0, 0], "quaternion": [0, 0, 0, 1]})
