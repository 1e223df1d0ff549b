"""AX = XB: the closed forms on exact and noisy motions, rotations about one axis refused."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3
from robostereo.robot.handeye.ax_xb import (
    METHODS,
    handeye_residuals,
    motion_pairs,
    solve_ax_xb,
)

X_TRUE = SE3.from_rotvec([30.0, -10.0, 60.0], [0.1, -0.3, 1.2])
BOARD_IN_BASE = SE3.from_rotvec([500.0, 0.0, 0.0], [0.0, 0.0, 0.3])


def _poses(rng, n, *, axes="any", noise=(0.0, 0.0)):
    F, C = [], []
    for _ in range(n):
        if axes == "z":  # a SCARA: every flange rotation about the vertical
            rv = np.array([0.0, 0.0, rng.uniform(-1.0, 1.0)])
        else:
            rv = rng.normal(size=3) * 0.4
        f = SE3(Rotation.from_rotvec(rv).as_matrix() @ np.diag([1.0, -1.0, -1.0]),
                rng.uniform(-100, 100, 3) + np.array([500.0, 0.0, 600.0]))
        c = (f @ X_TRUE).inv() @ BOARD_IN_BASE
        c = SE3.from_rotvec([0, 0, 0], rng.normal(size=3) * noise[1]) @ c
        C.append(SE3(c.rotation, c.translation + rng.normal(size=3) * noise[0]))
        F.append(f)
    return F, C


@pytest.mark.parametrize("method", METHODS)
def test_closed_forms_exact_and_noisy(method):
    rng = np.random.default_rng(0)
    A, B = motion_pairs(*_poses(rng, 6))
    t, r = X_TRUE.distance_to(solve_ax_xb(A, B, method=method))
    assert t < 1e-6 and r < 1e-9
    A, B = motion_pairs(*_poses(rng, 12, noise=(0.05, 1e-4)))
    X = solve_ax_xb(A, B, method=method)
    t, r = X_TRUE.distance_to(X)
    assert t < 0.5 and math.degrees(r) < 0.05
    res = handeye_residuals(A, B, X)
    assert res.rms_translation_mm < 0.5 and res.rms_rotation_deg < 0.05
    assert handeye_residuals(A, B, X_TRUE @ SE3.from_rotvec([2, 0, 0], [0, 0, 0])) \
        .rms_translation_mm > 1.0  # the residuals see a wrong X


def test_scara_rotations_are_refused():
    A, B = motion_pairs(*_poses(np.random.default_rng(1), 8, axes="z"))
    with pytest.raises(InputError, match="about one axis"):
        solve_ax_xb(A, B)
    with pytest.raises(InputError, match="method must be one of"):
        solve_ax_xb(A, B, method="horaud")  # type: ignore[arg-type]
