"""The window matcher's kernels against brute force, and the confidence model."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic import layered_pair

from robostereo.confidence import (
    DEFAULT_MODEL,
    FEATURES,
    ConfidenceModel,
    calibration_table,
    fit_confidence,
    isotonic,
)
from robostereo.errors import InputError
from robostereo.evaluation import coverage_curve, match_errors
from robostereo.pipeline import MatchParameters, match_stereo
from robostereo.window import OUT_OF_VIEW, census_transform, sobel_x, window_costs


def _brute(left, right, rows, cols, d_lo, d_hi, vertical, trunc=64):
    """Every window cost by plain numpy: pixel costs, 9 x 9 sums, the placements."""
    h, w = left.shape
    cl, cr = census_transform(left), census_transform(right)
    sl, sr = sobel_x(left).astype(int), sobel_x(right).astype(int)
    popcount = np.vectorize(lambda v: bin(int(v)).count("1"))
    nd = d_hi - d_lo + 1
    pix = np.full((nd, h, w), 34 + trunc)
    for k, d in enumerate(range(d_lo, d_hi + 1)):
        x = np.arange(max(d, 0), min(w, w + d))
        pix[k][:, x] = popcount(cl[:, x] ^ cr[:, x - d]) + np.minimum(
            np.abs(sl[:, x] - sr[:, x - d]), trunc)

    def box(k, y, x):
        ys = np.clip(np.arange(y - 4, y + 5), 0, h - 1)
        return sum(pix[k][ys, xx].sum() if 0 <= xx < w else 9 * (34 + trunc)
                   for xx in range(x - 4, x + 5))

    offs = [(0, -4), (0, 0), (0, 4)] + ([(-4, 0), (4, 0)] if vertical else [])
    out = np.full((len(rows), nd), OUT_OF_VIEW)
    for i, (y, c) in enumerate(zip(rows, cols, strict=True)):
        for k in range(nd):
            if 0 <= c - d_lo - k < w:
                out[i, k] = min(box(k, y + dy, c + dx) for dy, dx in offs)
    return out


@pytest.mark.parametrize("vertical", [False, True])
def test_window_costs_equal_brute_force(vertical):
    rng = np.random.default_rng(3)
    left = rng.uniform(0, 127, (40, 70)).astype(np.float32)
    right = np.roll(left, -5, axis=1) + rng.normal(0, 3, left.shape).astype(np.float32)
    rows, cols = np.array([2, 10, 10, 20, 37]), np.array([15, 20, 40, 33, 50])
    wc = window_costs(left, right, rows, cols, (0, 12), vertical=vertical)
    ref = _brute(left, right, rows, cols, 0, 12, vertical)
    k1 = np.argmin(ref, axis=1)
    assert np.array_equal(wc.best, k1)
    assert np.array_equal(wc.cost, ref[np.arange(5), k1])
    far = np.abs(np.arange(13)[None] - k1[:, None]) > 1
    assert np.array_equal(wc.second, np.where(far, ref, OUT_OF_VIEW).min(axis=1))
    assert np.array_equal(wc.before, ref[np.arange(5), k1 - 1])
    row = _brute(left, right, rows, cols, 0, 12, False)
    assert np.array_equal(wc.best_row, np.argmin(row, axis=1))
    assert np.all(wc.in_view == (ref < OUT_OF_VIEW).sum(axis=1))


@pytest.mark.parametrize("threads", ["2", "3"])
def test_bands_on_threads_give_the_same_costs(monkeypatch, threads):
    """One band or several: the kernel's output is the same (bands repeat a few rows),
    and so is the whole match."""
    left, right, _ = layered_pair(np.random.default_rng(5), height=200, width=200)
    g = [np.asarray(im, np.float32) * np.float32(127 / 255) for im in (left, right)]
    monkeypatch.setenv("ROBOSTEREO_THREADS", "1")
    res1 = match_stereo(left, right, (4.0, 27.0))
    e = res1.left_edges
    one = window_costs(*g, e.row, e.column, (4, 27))
    monkeypatch.setenv("ROBOSTEREO_THREADS", threads)
    res2 = match_stereo(left, right, (4.0, 27.0))
    two = window_costs(*g, e.row, e.column, (4, 27))
    for name in ("best", "cost", "second", "best_row", "right_best"):
        assert np.array_equal(getattr(one, name), getattr(two, name)), name
    assert np.array_equal(res1.edge_disparity, res2.edge_disparity, equal_nan=True)
    assert np.array_equal(res1.edge_confidence, res2.edge_confidence, equal_nan=True)


def test_thread_count_is_validated(monkeypatch):
    from robostereo.parallel import n_threads, run_all

    monkeypatch.setenv("ROBOSTEREO_THREADS", "zero")
    with pytest.raises(InputError, match="ROBOSTEREO_THREADS"):
        n_threads()
    monkeypatch.setenv("ROBOSTEREO_THREADS", "2")

    def boom() -> int:
        raise ValueError("second call failed")

    # an error on a pool thread reaches the caller, after the other calls have ended
    with pytest.raises(ValueError, match="second call"):
        run_all([lambda: 1, boom])


def test_the_unrolled_census_is_the_generic_one():
    from robostereo.window import _census

    g = np.random.default_rng(3).integers(0, 4, (23, 31)).astype(np.float32)  # many ties
    padded = np.pad(g, ((2, 2), (3, 3)), mode="edge")
    assert np.array_equal(census_transform(g), _census(padded, 23, 31, 3, 2))


def test_census_and_out_of_view():
    g = np.arange(35, dtype=np.float32).reshape(5, 7)
    c = census_transform(g)
    # the centre pixel (2, 3): the 17 neighbours before it in raster order are darker
    assert bin(int(c[2, 3])).count("1") == 17
    with pytest.raises(InputError, match="census size"):
        census_transform(g, size=(8, 5))
    # a point whose every right pixel is outside the image has no best disparity
    wc = window_costs(g, g, np.array([2]), np.array([1]), (5, 6))
    assert wc.best[0] == -1 and wc.in_view[0] == 0


def test_isotonic_and_the_model():
    _, ky = isotonic([0, 1, 2, 3, 4], [0.0, 1.0, 0.0, 1.0, 1.0])
    assert np.all(np.diff(ky) >= 0) and ky[-1] == 1.0
    with pytest.raises(InputError, match="non-decreasing"):
        ConfidenceModel((0.0, 1.0), (0.9, 0.1))
    with pytest.raises(InputError, match="features"):
        DEFAULT_MODEL(np.zeros((3, 2)))
    # more evidence never lowers the confidence
    f = np.zeros((50, len(FEATURES)))
    f[:, 0] = f[:, 1] = np.linspace(0, 1, 50)
    f[:, 3] = 1.0
    p = DEFAULT_MODEL(f)
    assert np.all(np.diff(p) >= 0) and 0.0 <= p[0] < p[-1] <= 1.0


def test_confidence_on_synthetic_occlusions_is_calibrated_and_informative():
    """Layered pairs the model was not fitted on: the confidence curve fitted on two
    pairs is calibrated on a third, and the most confident matches are the cleanest."""
    rng = np.random.default_rng(77)
    sets = []
    for _ in range(3):
        left, right, gt = layered_pair(rng, height=160, width=300)
        res = match_stereo(left, right, (4.0, 27.0))
        e = res.left_edges
        known, err = match_errors(e.row, e.x, res.edge_disparity, gt)
        take = known & np.isfinite(err)
        sets.append((res.window.features[take], err[take] <= 1.0, res, gt))
    x = np.concatenate([s[0] for s in sets[:2]])
    y = np.concatenate([s[1] for s in sets[:2]])
    model = fit_confidence(x, y)
    f, ok, res, gt = sets[2]
    c, frac, n = calibration_table(model(f), ok)
    ece = np.sum(n[n > 0] * np.abs(c[n > 0] - frac[n > 0])) / n.sum()
    assert ece < 0.1
    e = res.left_edges
    curve = coverage_curve(e.row, e.x, res.edge_disparity, res.edge_confidence, gt)
    assert curve.false_rate[len(curve.false_rate) // 2] < curve.false_rate[-1]


def _paths_reference(bm, m, w, p1, p2, step):
    """Both scanline paths by the textbook recursion, on every ``step``-th column."""
    cost = bm[:, m:m + w:step].T.astype(float)  # (columns, nd)

    def one(c):
        out = np.empty_like(c)
        out[0] = c[0]
        for x in range(1, len(c)):
            prev = out[x - 1]
            near = np.minimum(np.r_[np.inf, prev[:-1]], np.r_[prev[1:], np.inf]) + p1
            out[x] = c[x] + np.minimum(np.minimum(prev, near), prev.min() + p2) - prev.min()
        return out

    return one(cost), one(cost[::-1])[::-1]


def test_paths_are_the_semi_global_recursion():
    from robostereo.window import PATH_COLUMN_STEP, _scanline

    rng = np.random.default_rng(4)
    nd, w, m = 7, 41, 8
    bm = rng.integers(0, 3000, (nd, w + 2 * m)).astype(np.int16)
    n = -(-w // PATH_COLUMN_STEP)
    fwd, bwd = np.zeros((w, nd), np.float32), np.zeros((w, nd), np.float32)
    bufs = [np.empty(nd, np.float32) for _ in range(4)]
    _scanline(bm, m, w, 1, np.float32(405), np.float32(2000), np.empty((w, nd), np.float32),
              fwd, bwd, *bufs)
    ref_f, ref_b = _paths_reference(bm, m, w, 405.0, 2000.0, PATH_COLUMN_STEP)
    assert np.allclose(fwd[:n], ref_f) and np.allclose(bwd[:n], ref_b)


def test_paths_carry_the_disparity_into_a_repeated_pattern():
    """Stripes of period 8 between two textured parts, shifted 5 px: a window inside
    the stripes matches 5 and 13 alike; the paths along the rows take 5 from the
    textured parts."""
    rng = np.random.default_rng(11)
    h, w, d, period = 60, 240, 5, 8
    scene = rng.uniform(20, 230, (h, w + d)).astype(np.float32)
    stripes = np.where((np.arange(w + d) // (period // 2)) % 2 == 0, 60.0, 190.0)
    scene[:, 80:170] = stripes[80:170]
    left, right = scene[:, :w], scene[:, d:]  # left x shows what right x - d shows
    left, right = (np.clip(im + rng.normal(0, 2.0, im.shape), 0, 255).astype(np.uint8)
                   for im in (left, right))  # sensor noise of each camera
    with_paths = match_stereo(left, right, (0.0, 16.0))
    without = match_stereo(left, right, (0.0, 16.0),
                           params=MatchParameters(paths=False))
    e = with_paths.left_edges
    inside = (e.x > 110) & (e.x < 140) & (e.row > 6) & (e.row < h - 6)
    assert inside.sum() > 50

    def right_share(res):
        return float(np.mean(np.abs(res.edge_disparity[inside] - d) < 1.0))

    # without the paths the two periods are near-equal; with them nearly all are right
    assert right_share(with_paths) > 0.95
    assert right_share(with_paths) > right_share(without) + 0.1


def test_path_penalties_are_validated():
    g = np.zeros((20, 30), np.float32)
    for bad in [(5.0,), (-1.0, 2.0), (5.0, 1.0), (np.nan, 2.0), (5.0, 1e6)]:
        with pytest.raises(InputError, match="path_penalties"):
            window_costs(g, g, np.array([10]), np.array([15]), (0, 4), path_penalties=bad)
    with pytest.raises(InputError, match="paths"):
        MatchParameters(paths="yes")  # type: ignore[arg-type]


def test_paths_bin_a_wide_range():
    """Over more than PATH_MAX_DISPARITIES the path disparities are bins; the best
    whole disparity inside the best bin is still the true one."""
    from robostereo.window import PATH_MAX_DISPARITIES

    rng = np.random.default_rng(8)
    d, w = 150, 420
    scene = rng.uniform(0, 127, (40, w + d)).astype(np.float32)
    left, right = scene[:, :w], scene[:, d:]
    rows = np.repeat(np.arange(10, 30), 5)
    cols = np.tile(np.array([200, 240, 280, 320, 360]), 20)
    wide = (0, 2 * PATH_MAX_DISPARITIES)
    wc = window_costs(left, right, rows, cols, wide)
    assert np.all(wc.best_path == d) and np.all(wc.best == d)
    assert np.all(wc.second_path > wc.cost_path)


def test_coarse_range_holds_the_scene_and_drops_the_rest():
    """Layered scenes (disparities 5..26) searched over 0..150: the half-size pass keeps
    every disparity the edge points have and cuts most of the rest."""
    from robostereo.edges import detect_edges, to_grey
    from robostereo.window import COARSE_MARGIN, coarse_range

    rng = np.random.default_rng(21)
    for _ in range(3):
        left, right, gt = layered_pair(rng, height=200, width=360)
        e = detect_edges(left, threshold=8.0)
        lo, hi = coarse_range(to_grey(left), to_grey(right), e.row, e.column, (0, 150))
        true = gt[e.row, e.column]
        true = true[np.isfinite(true)]
        # some edge points at the far left are out of view; all the rest are kept
        assert lo <= np.quantile(true, 0.01) and hi >= np.quantile(true, 0.99)
        assert 0 <= lo and hi <= 26 + 2 * COARSE_MARGIN + 1


def test_coarse_range_leaves_narrow_ranges_and_degenerate_input_whole():
    from robostereo.window import coarse_range

    g = np.zeros((12, 30), np.float32)  # too small to halve into a window
    assert coarse_range(g, g, np.array([5]), np.array([9]), (0, 100)) == (0, 100)
    rng = np.random.default_rng(3)
    big = rng.uniform(0, 127, (60, 120)).astype(np.float32)
    none = np.array([], np.int64)
    assert coarse_range(big, big, none, none, (0, 100)) == (0, 100)


def test_coarse_search_of_a_wide_range_matches_like_the_tight_one():
    """A generous range (0..150) gives the matches of the true range (4..27) with the
    half-size pass, which searches a fifth of the disparities."""
    rng = np.random.default_rng(5)
    shares = {"tight": [], "coarse": [], "whole": []}
    for _ in range(2):
        left, right, gt = layered_pair(rng, height=200, width=360)
        runs = {"tight": match_stereo(left, right, (4.0, 27.0)),
                "coarse": match_stereo(left, right, (0.0, 150.0)),
                "whole": match_stereo(left, right, (0.0, 150.0),
                                      params=MatchParameters(coarse=False))}
        assert runs["coarse"].window.costs.n_disparities < 60
        assert runs["whole"].window.costs.n_disparities == 151
        for k, res in runs.items():
            e = res.left_edges
            known, err = match_errors(e.row, e.x, res.accepted_disparity(), gt)
            shares[k].append(np.mean(err[known] <= 1.0))
    tight, coarse, whole = (float(np.mean(v)) for v in shares.values())
    assert coarse >= tight - 0.02
    assert coarse >= whole - 0.01


def test_coarse_search_only_for_wide_ranges():
    from robostereo.window import COARSE_MIN_DISPARITIES

    rng = np.random.default_rng(6)
    left, right, _ = layered_pair(rng, height=120, width=240)
    narrow = (0.0, float(COARSE_MIN_DISPARITIES - 1))
    a = match_stereo(left, right, narrow)
    b = match_stereo(left, right, narrow, params=MatchParameters(coarse=False))
    assert np.array_equal(a.edge_disparity, b.edge_disparity, equal_nan=True)
    assert a.window.costs.n_disparities == COARSE_MIN_DISPARITIES
    with pytest.raises(InputError, match="coarse"):
        MatchParameters(coarse=1)  # type: ignore[arg-type]


def test_coarse_range_with_masks_and_odd_sizes():
    """All-valid masks change nothing; the binning drops an odd last row and column
    and a mask keeps a binned pixel only where its four sources are valid."""
    from robostereo.edges import detect_edges, to_grey
    from robostereo.window import _halve, coarse_range

    rng = np.random.default_rng(9)
    left, right, _ = layered_pair(rng, height=161, width=331)
    gl, gr = to_grey(left), to_grey(right)
    e = detect_edges(left, threshold=8.0)
    ones = np.ones(gl.shape, bool)
    plain = coarse_range(gl, gr, e.row, e.column, (0, 120))
    assert coarse_range(gl, gr, e.row, e.column, (0, 120), valid_left=ones,
                        valid_right=ones) == plain
    assert _halve(gl).shape == (80, 165)
    assert np.allclose(_halve(gl)[3, 7], gl[6:8, 14:16].mean())
    m = ones.copy()
    m[10, 21] = False
    hm = _halve(m, mask=True)
    assert not hm[5, 10] and hm.sum() == hm.size - 1
