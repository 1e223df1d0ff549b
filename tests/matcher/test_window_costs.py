"""Window costs against brute force: placements, bands, paths and the half-size pass."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from synthetic import layered_pair

from robostereo.errors import InputError
from robostereo.matcher.edges import detect_edges
from robostereo.matcher.grey_levels import to_grey
from robostereo.matcher.pipeline import MatchParameters, match_stereo
from robostereo.matcher.window_costs import (
    COARSE_MARGIN,
    MIN_BAND_ROWS,
    POINT_WORK_PX,
    _halve,
    band_rows,
    census_transform,
    coarse_matches,
    coarse_range,
    sobel_x,
    window_costs,
)
from robostereo.matcher.window_kernels import (
    OUT_OF_VIEW,
    PATH_MAX_DISPARITIES,
    STREAM_COLUMNS,
    StreamImages,
    StreamSettings,
    stream_rows,
)


def _brute(left, right, rows, cols, d_lo, d_hi, vertical, trunc=64, *, placements=False):
    """Every window cost by plain numpy: pixel costs, 9 x 9 sums, the placements (their
    least, or with ``placements`` each one's (5, N, nd) in the order centred, left,
    right, up, down, and the function that sums a window)."""
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

    if placements:
        each = np.full((5, len(rows), nd), OUT_OF_VIEW)
        for p, (dy, dx) in enumerate([(0, 0), (0, -4), (0, 4), (-4, 0), (4, 0)]):
            for i, (y, c) in enumerate(zip(rows, cols, strict=True)):
                for k in range(nd):
                    if 0 <= c - d_lo - k < w:
                        each[p, i, k] = box(k, y + dy, c + dx)
        return each, box
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


def test_side_evidence_columns_equal_brute_force():
    """The placement that wins, its own second cost, each side window's own best, the
    disparity of the second cost and the left-right check with the winning placement,
    on a pair with a nearer square (two surfaces under the windows at its outline)."""
    rng = np.random.default_rng(11)
    h, w = 40, 80
    back = rng.uniform(0, 127, (h, w + 20)).astype(np.float32)
    front = rng.uniform(0, 127, (h, w + 20)).astype(np.float32)
    left = back[:, :w].copy()
    right = back[:, 3:3 + w].copy()  # background disparity 3
    left[10:30, 30:50] = front[10:30, 30:50]
    right[10:30, 22:42] = front[10:30, 30:50]  # the square at disparity 8
    rows = np.array([12, 15, 20, 20, 20, 25, 28])
    cols = np.array([29, 31, 30, 49, 60, 45, 51])
    wc = window_costs(left, right, rows, cols, (0, 11), sides=True)
    each, box = _brute(left, right, rows, cols, 0, 11, True, placements=True)
    n, nd = len(rows), 12
    least = each.min(axis=0)
    k1 = np.argmin(least, axis=1)
    at = np.arange(n)
    assert np.array_equal(wc.best, k1)
    placement = np.argmax(each[:, at, k1] == least[at, k1], axis=0)  # the first of equals
    assert np.array_equal(wc.placement, placement)
    far = np.abs(np.arange(nd)[None] - k1[:, None]) > 1
    own = np.where(far & (least < OUT_OF_VIEW), each[placement, at], OUT_OF_VIEW)
    assert np.array_equal(wc.second_placement, own.min(axis=1))
    second = np.where(far, least, OUT_OF_VIEW)
    assert np.array_equal(wc.second_best, np.argmin(second, axis=1))
    assert np.array_equal(wc.second, second.min(axis=1))
    for side, p in (("left", 1), ("right", 2)):
        assert np.array_equal(getattr(wc, "best_" + side), np.argmin(each[p], axis=1))
        assert np.array_equal(getattr(wc, "cost_" + side), each[p].min(axis=1))
    # the left-right check with the winning window: the right pixel x - k1 against the
    # left pixels x - k1 + k, both windows placed as the winner
    shift = [(0, 0), (0, -4), (0, 4), (-4, 0), (4, 0)]
    for i in range(n):
        dy, dx = shift[placement[i]]
        x_right = cols[i] - k1[i]
        costs = [box(k, rows[i] + dy, x_right + k + dx) if x_right + k < w else OUT_OF_VIEW
                 for k in range(nd)]
        assert wc.right_best_placement[i] == int(np.argmin(costs)), i
    # the scene has both surfaces: some window prefers each disparity
    assert {3, 8} <= set(wc.best_left.tolist()) | set(wc.best_right.tolist())
    # without sides the other columns are the same and these are left at -1
    plain = window_costs(left, right, rows, cols, (0, 11))
    assert np.array_equal(plain.best, wc.best) and np.array_equal(plain.second, wc.second)
    assert np.all(plain.placement == -1) and np.all(plain.right_best_placement == -1)


@pytest.mark.parametrize("vertical", [False, True])
def test_rows_far_from_edge_points_are_skipped_without_changing_costs(vertical):
    """Edge points more than two windows apart: the pass leaves out the rows between
    them (no window reads those), and the costs after such a gap are still exact."""
    rng = np.random.default_rng(7)
    left = rng.uniform(0, 127, (90, 60)).astype(np.float32)
    right = np.roll(left, -4, axis=1) + rng.normal(0, 3, left.shape).astype(np.float32)
    rows, cols = np.array([3, 30, 31, 58, 86]), np.array([20, 25, 40, 33, 45])
    wc = window_costs(left, right, rows, cols, (0, 9), vertical=vertical)
    ref = _brute(left, right, rows, cols, 0, 9, vertical)
    k1 = np.argmin(ref, axis=1)
    assert np.array_equal(wc.best, k1)
    assert np.array_equal(wc.cost, ref[np.arange(len(rows)), k1])
    far = np.abs(np.arange(10)[None] - k1[:, None]) > 1
    assert np.array_equal(wc.second, np.where(far, ref, OUT_OF_VIEW).min(axis=1))


@pytest.mark.parametrize("trunc", [221, 222, 300])
def test_pixel_costs_beyond_a_byte_keep_their_value(trunc):
    """Pixel costs are held in a byte up to a truncation of 221 (34 + 221 = 255) and
    in int16 beyond it: either way the window costs equal brute force, on unrelated
    images whose pixel costs reach the truncation's limit."""
    rng = np.random.default_rng(11)
    left = rng.uniform(0, 127, (30, 50)).astype(np.float32)
    right = rng.uniform(0, 127, (30, 50)).astype(np.float32)
    # gradient differences beyond every truncation tried: pixel costs of 34 + trunc
    assert np.abs(sobel_x(left).astype(int) - sobel_x(right).astype(int)).max() > 300
    rows, cols = np.array([4, 15, 15, 26]), np.array([20, 12, 40, 33])
    wc = window_costs(left, right, rows, cols, (0, 9), gradient_truncation=trunc)
    ref = _brute(left, right, rows, cols, 0, 9, True, trunc)
    k1 = np.argmin(ref, axis=1)
    i = np.arange(len(rows))
    assert np.array_equal(wc.best, k1)
    assert np.array_equal(wc.cost, ref[i, k1])
    assert np.array_equal(wc.before, ref[i, k1 - 1])
    assert np.array_equal(wc.after, np.where(k1 < 9, ref[i, np.minimum(k1 + 1, 9)],
                                             OUT_OF_VIEW))
    far = np.abs(np.arange(10)[None] - k1[:, None]) > 1
    assert np.array_equal(wc.second, np.where(far, ref, OUT_OF_VIEW).min(axis=1))


@pytest.mark.parametrize("trunc", [64, 250])
def test_a_pair_of_two_invalid_pixels_costs_the_most_too(trunc):
    """Pixels outside both views' valid parts (say the fill of two rectified images):
    every pair with one costs at least the truncation, a pair of two included (their
    Sobel marks used to differ by more than int16 holds, wrapping to a cost below zero,
    so that two masked regions matched each other best)."""
    rng = np.random.default_rng(5)
    left = rng.uniform(0, 127, (30, 60)).astype(np.float32)
    right = rng.uniform(0, 127, (30, 60)).astype(np.float32)
    valid = np.ones(left.shape, bool)
    valid[:, :30] = False  # the same columns invalid in both views
    rows, cols = np.array([10, 15, 20]), np.array([12, 14, 16])
    wc = window_costs(left, right, rows, cols, (0, 8), gradient_truncation=trunc,
                      valid_left=valid, valid_right=valid)
    assert np.all(wc.cost >= 81 * trunc)


def test_byte_and_int16_rings_give_the_same_summary():
    """The uint8 ring of pixel costs (default truncation) against the int16 one: every
    column of the summary, paths and side columns included, is the same."""
    left, right, _ = layered_pair(np.random.default_rng(6), height=120, width=160)
    g = [np.asarray(im, np.float32) * np.float32(127 / 255) for im in (left, right)]
    e = detect_edges(left, grey=to_grey(left))
    mask = np.ones((1, 1), np.bool_)
    images = StreamImages(g[0], g[1], mask, mask, False, False)
    row_start = np.searchsorted(e.row, np.arange(g[0].shape[0] + 1)).astype(np.int64)
    columns = np.ascontiguousarray(e.column, np.int32)
    outs = []
    for ring_type in (np.uint8, np.int16):
        settings = StreamSettings(
            d_min=2, n_disparities=30, truncation=np.int16(64), pixel_cost_max=np.int16(98),
            ring_type=ring_type, half_window=4, vertical=True, p1=405, p2=2025,
            path_row_step=5, sides=True)
        out = np.full((len(columns), len(STREAM_COLUMNS)), -1, np.int32)
        stream_rows(images, settings, row_start, columns, 0, g[0].shape[0], out)
        outs.append(out)
    assert len(columns) > 100 and np.all(outs[0][:, 0] >= 0)
    assert np.array_equal(outs[0], outs[1])


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


@settings(max_examples=60, deadline=None)
@given(counts=st.lists(st.integers(0, 60), min_size=1, max_size=700),
       width=st.integers(8, 2000), bands=st.integers(1, 6))
def test_band_rows_cover_the_image_in_bands_of_about_equal_work(counts, width, bands):
    """Bands run from row 0 to H in order, at least MIN_BAND_ROWS rows each, no more than
    asked for; unless a band was held to its least size, each band's work is within one
    row's work (and the rows an edge point's windows reach) of an equal share."""
    c = np.asarray(counts, np.int64)
    h = c.size
    ends = band_rows(np.r_[0, np.cumsum(c)], width, bands)
    n = ends.size - 1
    assert ends[0] == 0 and ends[-1] == h and 1 <= n <= bands
    assert n == max(1, min(bands, h // MIN_BAND_ROWS))
    if n == 1:
        return
    assert np.all(np.diff(ends) >= MIN_BAND_ROWS)
    near = np.convolve((c > 0).astype(int), np.ones(17, int), "same") > 0
    row_work = np.where(near, width, 0) + POINT_WORK_PX * c
    work = np.add.reduceat(row_work, ends[:-1])
    if work.sum() and np.all(np.diff(ends)[1:-1] > MIN_BAND_ROWS) and (
            ends[1] > MIN_BAND_ROWS and h - ends[-2] > MIN_BAND_ROWS):
        assert np.all(np.abs(work - work.sum() / n) <= 2 * row_work.max()), work


def test_band_rows_follow_the_edge_points_and_keep_the_costs(monkeypatch):
    """Edge points crowded in the lower half: the bands split where half the work is,
    not half the rows, and the costs are those of one band."""
    left, right, _ = layered_pair(np.random.default_rng(8), height=260, width=240)
    g = [to_grey(im) for im in (left, right)]
    e = detect_edges(left, threshold=8.0)
    keep = (e.row >= 130) | (np.arange(len(e)) % 4 == 0)  # a quarter of the upper ones
    r, c = e.row[keep], e.column[keep]
    ends = band_rows(np.searchsorted(r, np.arange(261)).astype(np.int64), 240, 2)
    assert ends[1] > 130 + 5
    monkeypatch.setenv("ROBOSTEREO_THREADS", "1")
    one = window_costs(*g, r, c, (0, 30))
    monkeypatch.setenv("ROBOSTEREO_THREADS", "2")
    two = window_costs(*g, r, c, (0, 30))
    for name in ("best", "cost", "second", "before", "after", "best_row", "cost_row",
                 "second_row", "in_view", "right_best", "best_path", "cost_path",
                 "second_path", "before_path", "after_path"):
        assert np.array_equal(getattr(one, name), getattr(two, name)), name


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


def test_coarse_matches_lie_at_edge_points_near_their_true_disparity():
    """The half-size matches are at (halved, doubled) edge pixels, nearly all within two
    pixels of the true disparity there, and coarse_range is their hull widened by the
    margin."""
    rng = np.random.default_rng(23)
    for _ in range(2):
        left, right, gt = layered_pair(rng, height=200, width=360)
        gl, gr = to_grey(left), to_grey(right)
        e = detect_edges(left, threshold=8.0)
        r, c, d = coarse_matches(gl, gr, e.row, e.column, (0, 150))
        assert r.size > 0.2 * len(e.row) and r.shape == c.shape == d.shape
        assert np.all(np.diff(r) >= 0) and np.all(r % 2 == 0) and np.all(c % 2 == 0)
        edge_key = set(((e.row // 2) * 1000 + e.column // 2).tolist())
        assert set(((r // 2) * 1000 + c // 2).tolist()) <= edge_key
        # the truth at the 2 x 2 block's pixels: a match is right if one of them agrees
        block = np.stack([gt[r + i, c + j] for i in (0, 1) for j in (0, 1)])
        near = np.nanmin(np.abs(block - d), axis=0) <= 2
        assert near.mean() > 0.95
        lo, hi = coarse_range(gl, gr, e.row, e.column, (0, 150))
        assert (lo, hi) == (max(0, d.min() - COARSE_MARGIN), min(150, d.max() + COARSE_MARGIN))
    g = np.zeros((12, 30), np.float32)  # too small to halve into a window: none
    assert all(a.size == 0 for a in coarse_matches(g, g, np.array([5]), np.array([9]),
                                                   (0, 100)))


def test_coarse_range_leaves_narrow_ranges_and_degenerate_input_whole():
    g = np.zeros((12, 30), np.float32)  # too small to halve into a window
    assert coarse_range(g, g, np.array([5]), np.array([9]), (0, 100)) == (0, 100)
    rng = np.random.default_rng(3)
    big = rng.uniform(0, 127, (60, 120)).astype(np.float32)
    none = np.array([], np.int64)
    assert coarse_range(big, big, none, none, (0, 100)) == (0, 100)


def test_coarse_range_with_masks_and_odd_sizes():
    """All-valid masks change nothing; the binning drops an odd last row and column
    and a mask keeps a binned pixel only where its four sources are valid."""

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



def test_coarse_range_counts_a_match_only_with_a_matching_neighbour():
    """A lone edge pixel's half-size match does not narrow the range; the same match
    with neighbours two pixels around (at half size) does."""
    rng = np.random.default_rng(3)
    left = rng.uniform(0, 127, (64, 160)).astype(np.float32)
    right = np.roll(left, -20, axis=1)
    lone = coarse_range(left, right, np.array([30]), np.array([100]), (0, 100))
    r, c = np.repeat(np.arange(26, 36, 2), 5), np.tile(np.arange(92, 102, 2), 5)
    group = coarse_range(left, right, r, c, (0, 100))
    assert lone == (0, 100)
    assert group[0] <= 20 <= group[1] and group[1] - group[0] < 20
