"""Tests of robostereo.robot.views.ray_search: the rays of reference edge points searched
in inverse depth, on views this file prepares itself."""

import numpy as np

from robostereo.matcher.grey_levels import smooth
from robostereo.robot.views.prepared_views import PreparedViews, reference_edges
from robostereo.robot.views.ray_search import search_rays


def _plane_views(baselines: tuple[float, ...], depth: float, size: tuple[int, int]):
    """Views of a fronto-parallel plane of diagonal stripes `depth` mm away, optical
    centres along x at `baselines` (mm), focal length 1000 px: prepared as
    :func:`~robostereo.robot.views.prepared_views.prepare_views` does, by hand."""
    h, w = size
    f, cx, cy = 1000.0, (w - 1) / 2, (h - 1) / 2
    yy, xx = np.mgrid[0:h, 0:w].astype(float)
    sm, gx, gy = [], [], []
    for b in baselines:
        # world mm on the plane seen at each pixel, stripes 9 mm apart across x + y
        u, v = (xx - cx) * depth / f + b, (yy - cy) * depth / f
        img = smooth(64.0 + 40.0 * np.tanh(3.0 * np.sin(2 * np.pi * (u + v) / 9.0)))
        g = np.zeros((2, h, w), np.float32)
        g[0, :, 1:-1] = (img[:, 2:] - img[:, :-2]) / 2
        g[1, 1:-1] = (img[2:] - img[:-2]) / 2
        sm.append(img), gx.append(g[0]), gy.append(g[1])
    K = np.array([[f, 0, cx], [0, f, cy], [0, 0, 1.0]])
    n = len(baselines)
    return PreparedViews(smoothed=np.stack(sm), gx=np.stack(gx), gy=np.stack(gy),
                         fine_gx=np.stack(gx), fine_gy=np.stack(gy), K=K,
                         K_inv=np.linalg.inv(K), R=np.repeat(np.eye(3)[None], n, axis=0),
                         C=np.array([[b, 0.0, 0.0] for b in baselines]))


def test_edge_points_near_the_top_and_bottom_borders_are_searched_in_the_other_views():
    # views along x see an edge point at the reference's row: one 5-6 px from the top
    # or bottom border has a window that fits in every other view, 2 px clear of the
    # border (as its own), and must be scored there, not left without a vote
    views = _plane_views((-40.0, -20.0, 0.0, 20.0, 40.0), 1000.0, (60, 160))
    edges = reference_edges(views, 2, 8.0, 5)
    y = edges.grid[:, 1]
    rim = edges.subset((y < 7) | (y > 60 - 8))
    assert len(rim) >= 20
    rays = search_rays(views, 2, rim, (800.0, 1250.0), half_window=3, step_px=0.75,
                       min_sine=float(np.sin(np.radians(15.0))), coarse_px=0.75)
    scored = np.isfinite(rays.costs).sum(axis=1)
    assert np.mean(scored >= 2) >= 0.9
    # at the plane's depth: within a search step over the 40 mm baseline (0.75 px)
    assert np.mean(np.abs(1.0 / rays.rho - 1000.0) <= 20.0) >= 0.9


def test_the_sweep_in_chunks_of_points_gives_what_it_gives_at_once(monkeypatch):
    # the sweep scores its points a bounded number of costs at a time: each point's
    # result is its own, so a chunk of one point gives every array exactly
    import robostereo.robot.views.ray_search as rs

    views = _plane_views((-40.0, -20.0, 0.0, 20.0, 40.0), 1000.0, (60, 160))
    edges = reference_edges(views, 2, 8.0, 5)
    assert len(edges) >= 50

    def search():
        return search_rays(views, 2, edges, (800.0, 1250.0), half_window=3, step_px=0.5,
                           min_sine=float(np.sin(np.radians(15.0))), coarse_px=2.0)

    whole = search()
    monkeypatch.setattr(rs, "SWEEP_CHUNK_COSTS", 1)
    chunked = search()
    for name in ("rho", "costs", "combined", "kept", "distinct"):
        np.testing.assert_array_equal(getattr(chunked, name), getattr(whole, name))
    assert np.mean(np.abs(1.0 / whole.rho - 1000.0) <= 20.0) >= 0.9
