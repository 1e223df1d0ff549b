"""The N-view kernels (the fit's residuals, the gradient) against the same sums in numpy."""

import numpy as np
from scipy.spatial.transform import Rotation

from robostereo.robot.views.views_kernels import central_gradient, normal_residuals


def _setup(rng: np.random.Generator, m: int = 40, nv: int = 4):
    K = np.array([[800.0, 0.0, 320.0], [0.0, 790.0, 240.0], [0.0, 0.0, 1.0]])
    # cameras 1000 mm above the table, looking down, turned a little each
    down = Rotation.from_euler("x", 180.0, degrees=True)
    R = np.stack([(down * Rotation.from_rotvec(rng.normal(0.0, 0.1, 3))).as_matrix()
                  for _ in range(nv + 1)])
    C = np.column_stack([rng.uniform(-60.0, 60.0, (nv + 1, 2)), np.full(nv + 1, 1000.0)])
    e_ref = rng.uniform([50.0, 50.0], [590.0, 430.0], (m, 2))
    a = rng.uniform(0.0, 2 * np.pi, m)
    n_ref = np.column_stack([np.cos(a), np.sin(a)])
    t = rng.normal(0.0, 0.5, m)
    rho = 1.0 / rng.uniform(850.0, 1000.0, m)
    return K, R, C, e_ref, n_ref, t, rho


def _world(K, R, C, e_ref, n_ref, t, rho):
    p = e_ref + t[:, None] * n_ref
    hom = np.column_stack([p, np.ones(len(p))]) @ np.linalg.inv(K).T
    return C[0] + (hom @ R[0].T) / rho[:, None]


def _project(K, R, C, world, v):
    pc = (world - C[v]) @ R[v]
    return pc[:, :2] / pc[:, 2:3] * np.diag(K)[:2] + K[:2, 2]


def test_the_residual_kernel_is_the_normal_distance_of_the_projection():
    rng = np.random.default_rng(3)
    K, R, C, e_ref, n_ref, t, rho = _setup(rng)
    world = _world(K, R, C, e_ref, n_ref, t, rho)
    m, nv = len(t), len(R) - 1
    uv = np.stack([_project(K, R, C, world, v) for v in range(1, nv + 1)], axis=1)
    # edges off the projections along and across their normals
    a = rng.uniform(0.0, 2 * np.pi, (m, nv))
    normal = np.stack([np.cos(a), np.sin(a)], axis=2)
    across = rng.normal(0.0, 2.0, (m, nv))
    along = rng.normal(0.0, 5.0, (m, nv))
    tangent = np.stack([-normal[:, :, 1], normal[:, :, 0]], axis=2)
    edge = uv - across[:, :, None] * normal + along[:, :, None] * tangent
    got = normal_residuals(e_ref, n_ref, t, rho, np.linalg.inv(K), R[0], C[0], R[1:], C[1:],
                           K, edge, normal)
    want = np.einsum("mvi,mvi->mv", normal, uv - edge)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-8)
    # the residual measures only the distance across the edge
    np.testing.assert_allclose(got, across, rtol=0, atol=1e-8)
    # and moves with the depth: a point 50 mm off its depth is pixels off in some view
    far = normal_residuals(e_ref, n_ref, t, 1.0 / (1.0 / rho + 50.0), np.linalg.inv(K),
                           R[0], C[0], R[1:], C[1:], K, edge, normal)
    assert np.median(np.max(np.abs(far - got), axis=1)) > 1.0


def test_the_gradient_kernel_is_half_the_central_differences():
    rng = np.random.default_rng(4)
    s = (rng.random((23, 31)) * 127).astype(np.float32)
    gx, gy = np.full_like(s, np.nan), np.full_like(s, np.nan)
    central_gradient(s, gx, gy)
    want_x, want_y = np.zeros_like(s), np.zeros_like(s)
    want_x[:, 1:-1] = (s[:, 2:] - s[:, :-2]) * np.float32(0.5)
    want_y[1:-1] = (s[2:] - s[:-2]) * np.float32(0.5)
    assert np.array_equal(gx, want_x) and np.array_equal(gy, want_y)


def test_the_edge_peak_kernel_finds_where_a_ray_crosses_an_edge():
    from robostereo.robot.views.views_kernels import ray_edge_peaks

    # a view whose gradient across x peaks on the column x = 50.3 (a blurred edge); rays
    # whose images move along x by 10000 px per unit of inverse depth cross it where
    # rho = (50.3 - x0) / 1e4
    h, w = 40, 100
    xx = np.arange(w, dtype=float)
    gx = np.repeat((12.0 * np.exp(-0.5 * (xx - 50.3) ** 2))[None], h, axis=0).astype(np.float32)
    gy = np.zeros_like(gx)
    x0 = np.array([20.0, 30.0, 20.0])
    a = np.column_stack([x0, [15.0, 20.0, -30.0], np.ones(3)])  # the third: above the image
    b = np.tile([1e4, 0.0, 0.0], (3, 1))
    normals = np.tile([1.0, 0.0], (3, 1))
    grid = np.arange(0.0, 0.0065, 1e-4)
    point, k, frac = ray_edge_peaks(gx, gy, a, b, normals, grid, 4.0, 3)
    assert point.tolist() == [0, 1]
    rho = grid[k] + np.clip(frac, -0.5, 0.5) * 1e-4
    np.testing.assert_allclose(rho, (50.3 - x0[:2]) / 1e4, atol=0.2e-4)
    # a stronger threshold than the ridge: no peak; the wrong polarity: none either
    assert len(ray_edge_peaks(gx, gy, a, b, normals, grid, 20.0, 3)[0]) == 0
    assert len(ray_edge_peaks(gx, gy, a, b, -normals, grid, 4.0, 3)[0]) == 0
