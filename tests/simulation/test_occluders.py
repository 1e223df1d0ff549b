"""Tests for the synthetic occluder pairs (robostereo.simulation.occluders)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.ndimage import binary_dilation, map_coordinates

from robostereo.errors import InputError
from robostereo.evaluation.outlines import OffsetSummary, RowBoundaries, silhouette_offsets
from robostereo.evaluation.rules import depth_step_mask, near_steps, score_matches
from robostereo.matcher.pipeline import MatchParameters, match_stereo
from robostereo.simulation.occluders import Occluder, occluder_pair


@pytest.fixture(scope="module")
def pairs():
    return [occluder_pair(seed) for seed in (3, 11)]


def test_warping_the_right_view_by_the_ground_truth_gives_the_left(pairs) -> None:
    for p in pairs:
        h, w = p.left.shape
        yc, xc = np.mgrid[0:h, 0:w].astype(float)
        xr = xc - p.disparity
        warped = map_coordinates(p.right.astype(float), [yc, xr], order=1, mode="nearest")
        # pixels that see one surface in both views, not beside an outline
        lo = np.clip(np.floor(xr).astype(int), 0, w - 1)
        hi = np.clip(lo + 1, 0, w - 1)
        rows = yc.astype(int)
        keep = (~binary_dilation(p.occluded | p.mixed_left, iterations=1)
                & ~p.mixed_right[rows, lo] & ~p.mixed_right[rows, hi] & (xr >= 1))
        assert keep.mean() > 0.8
        diff = np.abs(warped - p.left)[keep]
        assert np.median(diff) < 1.0 and np.percentile(diff, 99) < 8.0
        # a ground truth one pixel off is seen at once
        off = map_coordinates(p.right.astype(float), [yc, xr - 1.0], order=1, mode="nearest")
        assert np.median(np.abs(off - p.left)[keep]) > 4 * np.median(diff) + 2


def test_occlusion_is_a_band_as_wide_as_the_gap_left_of_each_contour(pairs) -> None:
    checked = 0
    for p in pairs:
        h, w = p.left.shape
        a, bx, by = p.background
        for o in p.occluders:
            for i in range(h):
                xs = o.crossings(float(i))
                if xs.size != 2 or xs[1] - xs[0] < 3:
                    continue
                x0, x1 = xs
                # background pixel x is hidden when its right position x - d_bg(x)
                # falls inside the object's there, [x0 - d, x1 - d]: a band as wide as
                # the gap (or the object, where it is narrower), ending at x0
                start = (x0 - o.disparity + a + by * i) / (1 - bx)
                end = min(x0, (x1 - o.disparity + a + by * i) / (1 - bx))
                width = end - start
                left = np.arange(int(np.floor(start - 3)), int(np.ceil(x0)))
                left = left[(left >= 0) & (left < x0)]
                run = int(p.occluded[i, left].sum())
                assert abs(run - width) <= 1.0, (i, run, width)
                right = np.arange(int(np.ceil(x1)), min(w, int(x1) + 30))
                assert not p.occluded[i, right].any()
                checked += 1
    assert checked > 300


def test_ground_truth_and_boundaries_of_a_rectangle() -> None:
    p = occluder_pair(5, height=60, width=120, gaps=(9.0,), shapes=("rectangle",))
    (o,) = p.occluders
    xmin, ymin = o.vertices.min(axis=0)
    xmax, ymax = o.vertices.max(axis=0)
    rows, x, side, near = p.boundaries()
    inside_rows = np.arange(int(np.ceil(ymin)), int(np.floor(ymax)) + 1)
    assert sorted(set(rows.tolist())) == inside_rows.tolist()
    assert np.allclose(x[side == 1], xmin) and np.allclose(x[side == -1], xmax)
    assert np.all(near == o.disparity)
    i = int(inside_rows[len(inside_rows) // 2])
    assert p.disparity[i, int(np.ceil(xmin))] == o.disparity
    assert p.disparity[i, int(np.floor(xmin))] == pytest.approx(
        float(p.background_disparity(np.floor(xmin), i)))
    # the outline is anti-aliased: pixels it crosses are mixed, the others pure
    assert p.mixed_left[i, int(np.floor(xmin + 0.5))] and not p.mixed_left[i, 3]


def test_pairs_are_deterministic_from_the_seed() -> None:
    a, b, c = occluder_pair(4, height=40), occluder_pair(4, height=40), occluder_pair(5,
                                                                                      height=40)
    assert np.array_equal(a.left, b.left) and np.array_equal(a.right, b.right)
    assert not np.array_equal(a.left, c.left)
    with pytest.raises(InputError, match="shape must be one of"):
        occluder_pair(0, shapes=("circle",))
    with pytest.raises(InputError, match="vertices"):
        Occluder(np.zeros((2, 2)), 5.0)


def test_the_matcher_at_its_default_point_is_fair_on_occluders(pairs) -> None:
    """Bounded false rate by the silhouette rule, near steps and away; silhouette edges
    within a pixel of the exact boundary (median), a loose guard on the localisation."""
    offsets = []
    for p in pairs:
        res = match_stereo(p.left, p.right, p.disparity_range)
        e, d = res.left_edges, res.accepted_disparity()
        near = near_steps(e.row, e.x, depth_step_mask(p.disparity))
        for sub in (near, ~near):
            s = score_matches(e.row, e.x, d, p.disparity, rule="silhouette", subset=sub)
            assert s.counted > 100 and s.matched > 0.2 * s.counted
            assert s.false_fraction < 0.03
        offsets.append(silhouette_offsets(e.row, e.x, d, RowBoundaries(*p.boundaries()))[1])
    o = OffsetSummary.of(np.concatenate(offsets))
    assert o.count > 40 and o.median_abs_px < 1.0


def test_silhouette_edges_lie_nearer_exact_outlines_than_on_the_smoothed_image(
        held_out_occluders) -> None:
    """On held-out occluder pairs, the silhouette edges the default matcher accepts lie a
    median within about a quarter pixel of the exact outline (0.231 px measured; 0.219
    on the benchmark's seeds 0-7), closer than when the thesis's 5 x 5 smoothed image
    places them (0.255 px): the smoothing lets the texture behind the object, which
    differs between the views, pull the edge."""
    offsets: dict[float | None, list[np.ndarray]] = {None: [], 0.85: []}
    for p in held_out_occluders:
        for blur, out in offsets.items():
            res = match_stereo(p.left, p.right, p.disparity_range,
                               params=MatchParameters(edge_blur_px=blur))
            out.append(silhouette_offsets(res.left_edges.row, res.left_edges.x,
                                          res.accepted_disparity(),
                                          RowBoundaries(*p.boundaries()))[1])
    now, smoothed = (OffsetSummary.of(np.concatenate(offsets[b])) for b in (0.85, None))
    assert MatchParameters().edge_blur_px == 0.85
    assert now.count > 100 and now.median_abs_px <= 0.27
    assert now.median_abs_px <= smoothed.median_abs_px - 0.01
