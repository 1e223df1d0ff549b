"""Edge points beside an edge of opposite polarity, placed by two blurred steps: on
profiles and views this file renders itself (not the project's simulator)."""

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter
from scipy.special import ndtr

from robostereo.errors import InputError
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import se3_from_scara
from robostereo.robot.views.edge_profiles import (
    estimate_blur,
    fit_one_step,
    profiles,
    two_step_edges,
)
from robostereo.robot.views.locating import locate_views
from robostereo.robot.views.viewpoints import ViewsCapture
from robostereo.robot.views.views_parameters import ViewsParameters

SUB = 3  # rays a pixel across: edges at multiples of 1/3 px are where the renderer puts them
BLUR = 0.9


def _rows(levels: np.ndarray, rng: np.random.Generator, h: int = 40) -> np.ndarray:
    """An image of `h` equal rows from grey levels given every 1/SUB px, blurred, noisy."""
    img = np.tile(levels.reshape(-1, SUB).mean(axis=1), (h, 1))
    return (gaussian_filter(img, BLUR) + rng.normal(0.0, 0.75, img.shape)).astype(np.float32)


def _gap(gap: float, rng: np.random.Generator, edge: float = 60.5) -> np.ndarray:
    """Bright (90) | a dark gap (30) `gap` px wide | bright (80) from `edge` on."""
    x = (np.arange(120 * SUB) + 0.5) / SUB - 0.5
    return _rows(30.0 + 60.0 * (x < edge - gap) + 50.0 * (x >= edge), rng)


def _peak(img: np.ndarray) -> float:
    """The thesis's edge position on row 20 (the gradient's peak and a parabola), on the
    image lightly blurred as the N-view locate places its edges."""
    g = gaussian_filter(img, (0, 0.7))
    d = np.zeros_like(g)
    d[:, 1:-1] = (g[:, 2:] - g[:, :-2]) / 2
    row = d[20]
    k = 55 + int(np.argmax(row[55:66]))
    return k + 0.5 * (row[k - 1] - row[k + 1]) / (row[k - 1] - 2 * row[k] + row[k + 1])


@pytest.fixture(scope="module")
def blur() -> float:
    # a lonely edge at 8 degrees: every sub-pixel phase
    rng = np.random.default_rng(0)
    a = np.radians(8.0)
    yy, xx = np.mgrid[0:40 * SUB, 0:120 * SUB]
    d = ((xx + 0.5) / SUB - 0.5 - 60.0) * np.cos(a) + ((yy + 0.5) / SUB - 0.5 - 20.0) * np.sin(a)
    img = (30.0 + 50.0 * (d >= 0)).reshape(40, SUB, 120, SUB).mean(axis=(1, 3))
    img = (gaussian_filter(img, BLUR) + rng.normal(0.0, 0.75, img.shape)).astype(np.float32)
    y = np.arange(5, 35, dtype=float)
    pts = np.column_stack([60.0 - (y - 20.0) * np.tan(a), y])
    return estimate_blur(img, pts, np.tile([np.cos(a), np.sin(a)], (len(y), 1)))


def test_the_blur_is_estimated_from_isolated_edges(blur):
    # the renderer's blur and the pixels' own width: sqrt(0.9^2 + 1/12) = 0.945
    assert abs(blur - np.hypot(BLUR, np.sqrt(1 / 12))) < 0.1


def test_an_edge_beside_a_narrow_gap_is_placed_at_its_step(blur):
    rng = np.random.default_rng(1)
    normal = np.tile([1.0, 0.0], (20, 1))
    peak_err, fit_err = [], []
    for gap in (4 / 3, 5 / 3, 2.0):
        img = _gap(gap, rng)
        p = _peak(img)
        pts, moved = two_step_edges(img, np.column_stack([np.full(20, p), np.arange(10.0, 30.0)]),
                                    normal, blur)
        assert moved.all()
        peak_err.append(abs(p - 60.5))
        fit_err.append(abs(float(np.median(pts[:, 0])) - 60.5))
    # the gap pushes the peak 0.6-0.8 px away from it; the fit takes most of that back
    assert min(peak_err) > 0.4
    assert np.mean(fit_err) < 0.4 * np.mean(peak_err)


def test_an_edge_without_an_opposite_one_nearby_is_left_where_it_is(blur):
    img = _gap(20.0, np.random.default_rng(2))
    pts = np.column_stack([np.full(10, 60.5), np.arange(10.0, 20.0)])
    out, moved = two_step_edges(img, pts, np.tile([1.0, 0.0], (10, 1)), blur)
    assert not moved.any() and np.array_equal(out, pts)


def _fit_one_step_numpy(s, prof, iterations=8):
    """The single-step fit written in numpy over all profiles at once: the reference the
    numba kernel must reproduce (same start, damping, clipping and refusals)."""
    m = len(prof)
    s0, sig = np.zeros(m), np.ones(m)
    lo_s, hi_s = s.min(axis=1), s.max(axis=1)
    lo = np.mean(prof, axis=1, where=s <= lo_s[:, None] + 1.5)
    hi = np.mean(prof, axis=1, where=s >= hi_s[:, None] - 1.5)
    a, b = lo, hi - lo
    for _ in range(iterations):
        z = (s - s0[:, None]) / sig[:, None]
        ph, pd = ndtr(z), np.exp(-0.5 * z * z) / np.sqrt(2.0 * np.pi)
        r = prof - (a[:, None] + b[:, None] * ph)
        J = np.stack([np.ones_like(z), ph, -b[:, None] * pd / sig[:, None],
                      -b[:, None] * pd * z / sig[:, None]], axis=2)
        JtJ = np.einsum("msi,msj->mij", J, J)
        JtJ = JtJ + 1e-3 * np.eye(4) * np.diagonal(JtJ, axis1=1, axis2=2)[:, None, :]
        d = np.linalg.solve(JtJ + 1e-12 * np.eye(4), np.einsum("msi,ms->mi", J, r)[:, :, None])
        a, b = a + d[:, 0, 0], b + d[:, 1, 0]
        s0 = np.clip(s0 + d[:, 2, 0], lo_s, hi_s)
        sig = np.clip(sig + d[:, 3, 0], 0.2, 3.0)
    rms = np.sqrt(np.mean((prof - (a[:, None] + b[:, None] * ndtr((s - s0[:, None])
                                                                   / sig[:, None]))) ** 2, axis=1))
    bad = ~np.isfinite(rms) | (sig <= 0.2) | (sig >= 3.0)
    return tuple(np.where(bad, np.nan, x) for x in (s0, sig, rms))


def test_the_single_step_fit_finds_a_known_step_and_blur_as_numpy_does():
    rng = np.random.default_rng(7)
    a = np.radians(rng.uniform(-40.0, 40.0, 60))
    step = rng.uniform(-0.5, 0.5, 60)
    sigma = rng.uniform(0.6, 1.6, 60)
    yy, xx = np.mgrid[0:21, 0:21].astype(float)
    imgs, pts, nrm = [], [], []
    for k in range(60):
        n = np.array([np.cos(a[k]), np.sin(a[k])])
        d = (xx - 10.0) * n[0] + (yy - 10.0) * n[1] - step[k]
        imgs.append(20.0 + 70.0 * ndtr(d / sigma[k]) + rng.normal(0.0, 0.75, d.shape))
        pts.append([10.0, 10.0])
        nrm.append(n)
    s, prof = [], []
    for img, p, n in zip(imgs, pts, nrm, strict=True):
        sk, gk = profiles(img.astype(np.float32), np.array([p]), np.array([n]))
        s.append(sk[0])
        prof.append(gk[0])
    s, prof = np.array(s), np.array(prof)
    # a third of the profiles flat (no step: the fit may run the blur to a bound)
    flat = np.arange(60) % 3 == 2
    prof[flat] = 50.0 + rng.normal(0.0, 0.75, prof[flat].shape)
    s0, sig, rms = fit_one_step(s, prof)
    ref = _fit_one_step_numpy(s, prof)
    for got, want in zip((s0, sig, rms), ref, strict=True):
        assert np.array_equal(np.isnan(got), np.isnan(want))
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)
    # and the fit is right where there is a step: within 0.1 px, the blur within 0.15 px
    assert np.isfinite(s0[~flat]).all()
    assert np.max(np.abs(s0 - step)[~flat]) < 0.1
    assert np.max(np.abs(sig - sigma)[~flat]) < 0.15
    assert np.median(rms[~flat]) < 1.0


def test_bad_profiles_for_the_single_step_fit_are_refused():
    with pytest.raises(InputError, match="prof"):
        fit_one_step(np.zeros((2, 11)), np.zeros((2, 10)))
    with pytest.raises(InputError, match="iterations"):
        fit_one_step(np.zeros((2, 11)), np.zeros((2, 11)), iterations=-1)


def test_bad_reach_is_refused():
    with pytest.raises(InputError, match="reach_px"):
        two_step_edges(np.zeros((9, 9), np.float32), np.zeros((1, 2)), np.ones((1, 2)), 1.0,
                       reach_px=0)
    with pytest.raises(InputError, match="opposite_edge_px"):
        ViewsParameters(opposite_edge_px=-1.0)


CAMERA = Camera(image_size=(240, 160))
PLATE = 100.0  # the height (mm) of a plate over x < 0; the camera is 1000 mm up
BAND = (5.8, 25.0)  # a bright band on the table beyond the plate's edge, x in mm


def _render(x_cam: float, rng: np.random.Generator) -> np.ndarray:
    """Ray-cast grey levels: the plate (80) occludes the dark table (30) and its bright
    band (100); the dark strip between the plate's edge and the band is 2 px wide from
    the view at x = -40 mm and wider from the others (parallax)."""
    w, h = CAMERA.image_size
    cx, cy = CAMERA.principal_point
    u = (np.arange(w)[:, None] + (np.arange(12) + 0.5) / 12 - 0.5).ravel()
    v = (np.arange(h)[:, None] + (np.arange(2) + 0.5) / 2 - 0.5).ravel()
    uu, vv = np.meshgrid(u, v)
    dx, dy = (uu - cx) / CAMERA.fx, -(vv - cy) / CAMERA.fy
    xt, yt = x_cam + dx * 1000.0, dy * 1000.0
    grey = np.where((xt >= BAND[0]) & (xt <= BAND[1]), 100.0, 30.0 + 3.0 * np.sin(yt / 3.0))
    grey = np.where(x_cam + dx * (1000.0 - PLATE) < 0.0, 80.0, grey)
    img = grey.reshape(h, 2, w, 12).mean(axis=(1, 3))
    img = gaussian_filter(img, BLUR) + rng.normal(0.0, 0.75, img.shape)
    return np.clip(np.rint(img), 0, 127).astype(np.uint8)


def test_a_band_seen_through_a_narrowing_gap_is_located_within_its_bounds():
    rng = np.random.default_rng(5)
    xs = (-40.0, -20.0, 0.0, 20.0, 40.0)
    cap = ViewsCapture(tuple(_render(x, rng) for x in xs), CAMERA,
                       tuple(se3_from_scara(x, 0.0, 1000.0) for x in xs),
                       depth_range_mm=(850.0, 1050.0))
    err = {}
    for reach in (None, ViewsParameters().opposite_edge_px):
        loc = locate_views(cap, params=ViewsParameters(matcher="sweep", opposite_edge_px=reach))
        on = (np.abs(loc.world[:, 0] - BAND[0]) < 1.0) & (np.abs(loc.world[:, 2]) < 10.0)
        assert on.sum() > 100
        err[reach] = (np.abs(loc.world[on, 2]), loc.bound_mm[on])
    assert reach is not None
    # the narrow view's peak is pushed off the band: several mm, beyond the bounds
    assert np.median(err[None][0]) > 2.0
    assert np.median(err[reach][0]) < 0.5 * np.median(err[None][0])
    assert np.mean(err[reach][0] <= err[reach][1]) > 0.95


def test_the_opposite_edge_kernel_reads_the_central_line_as_the_profiles_do():
    from robostereo.robot.views.edge_profile_kernels import opposite_edges
    from robostereo.robot.views.edge_profiles import PROFILE_HALF_PX, _opposite_peak

    rng = np.random.default_rng(8)
    img = _gap(5 / 3, rng)  # a narrow gap: opposite edges to find
    grey = np.concatenate([img, (rng.random((40, 120)) * 127).astype(np.float32)])
    p = rng.uniform(-2.0, [122.0, 82.0], (3000, 2))  # some beyond the borders
    a = rng.uniform(0.0, 2 * np.pi, 3000)
    n = np.column_stack([np.cos(a), np.sin(a)])
    s, prof = profiles(grey, p, n, along=0)
    want = _opposite_peak(s, prof, 3.0, 4.0)
    got = opposite_edges(grey, p, n, PROFILE_HALF_PX, 3.0, 4.0)
    assert np.array_equal(got, want, equal_nan=True)
    assert 0.05 < np.mean(np.isfinite(got)) < 0.95
