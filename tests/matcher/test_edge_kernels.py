"""The edge stage's kernels against plain NumPy and the grid connectivity."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from robostereo.matcher.edge_kernels import (
    connect,
    connect_sorted,
    gradient_peaks,
    mean5_at,
    rgb_to_grey,
)


def _numpy_peaks(s: np.ndarray, threshold: np.float32, m: int):
    """The peak test written with whole-array NumPy operations (float32)."""
    mag = np.zeros_like(s)
    g = (s[:, 2:] - s[:, :-2]) * np.float32(0.5)
    mag[:, 1:-1] = np.abs(g)
    w = s.shape[1]
    c = mag[:, m:w - m]
    hit = (c >= threshold) & (c > mag[:, m - 1:w - m - 1]) & (c >= mag[:, m + 1:w - m + 1])
    rows, cols = np.nonzero(hit)
    return rows, cols + m


@pytest.mark.parametrize("shape", [(40, 60), (3, 400), (9, 11), (6, 10), (7, 64), (5, 71)])
def test_one_pass_peaks_equal_numpy_even_when_the_buffers_grow(shape):
    # noise has a peak every third or fourth pixel, far above the buffers' first size
    s = np.random.default_rng(3).uniform(0, 127, shape).astype(np.float32)  # (H, W)
    if shape[1] in (64, 71):  # few levels: equal |g| side by side, the ties of the test
        s = np.round(s / 16).astype(np.float32)
    thr = np.float32(2.0)
    got = gradient_peaks(s, thr, 5)
    want = _numpy_peaks(s, thr, 5)
    assert got[0].shape[0] == want[0].shape[0]
    if shape[1] > 11:
        assert got[0].shape[0] > shape[0]  # peaks on most rows to compare
    if shape[1] > 11 and shape[1] not in (64, 71):
        assert got[0].shape[0] > max(256, shape[0] * shape[1] // 16)  # the buffers grew
    for a, b in zip(got, want, strict=True):
        assert a.dtype == np.int64 and np.array_equal(a, b)


def test_walking_connectivity_equals_the_grid():
    rng = np.random.default_rng(5)
    n_lines, width = 30, 25
    taken = rng.random((n_lines, width)) < 0.4
    line, column = np.nonzero(taken)  # sorted by (line, column), one point a place
    sign = rng.choice(np.array([-1, 1], np.int8), line.shape[0])
    walked = connect_sorted(line.astype(np.int64), column.astype(np.int64), sign, n_lines)
    grid = connect(line.astype(np.int64), column.astype(np.int64), sign, n_lines, width)
    assert (walked[0] >= 0).sum() > 50  # many connections to compare
    for a, b in zip(walked, grid, strict=True):
        assert np.array_equal(a, b)
    assert walked[0].dtype == walked[1].dtype == np.int32  # the EdgeSet's links


def test_mean5_inside_and_at_the_border_equals_a_reflected_window():
    g = np.random.default_rng(7).uniform(0, 127, (8, 9)).astype(np.float32)
    padded = np.pad(g.astype(np.float64), 2, mode="reflect")  # = BORDER_REFLECT_101
    rows, cols = np.meshgrid(np.arange(8), np.arange(9), indexing="ij")
    got = mean5_at(g, rows.ravel(), cols.ravel())
    want = [padded[r:r + 5, c:c + 5].mean()
            for r, c in zip(rows.ravel(), cols.ravel(), strict=True)]
    assert np.allclose(got, want, rtol=0, atol=1e-12)


def _span_reference(vert, c, weights):
    """:func:`blurred_span` in plain Python: each output summed tap by tap in float32,
    the reads reflected at the row's ends (``cv2.BORDER_REFLECT_101``)."""
    w, rad = vert.shape[0], weights.shape[0] // 2
    out = np.empty(7, np.float32)
    for j in range(7):
        acc = np.float32(0.0)
        for t in range(weights.shape[0]):
            k = c - 3 - rad + j + t
            k = -k if k < 0 else k
            k = 2 * (w - 1) - k if k > w - 1 else k
            acc = np.float32(acc + np.float32(weights[t] * vert[min(max(k, 0), w - 1)]))
        out[j] = acc
    return out


@pytest.mark.parametrize("taps", [1, 7, 11])
def test_blurred_span_equals_the_sums_tap_by_tap_inside_and_at_the_ends(taps):
    from robostereo.matcher.edge_kernels import blurred_span

    rng = np.random.default_rng(taps)
    vert = rng.uniform(0, 127, 40).astype(np.float32)
    weights = rng.uniform(0.01, 0.3, taps).astype(np.float32)  # no symmetry to lean on
    out = np.empty(7, np.float32)
    for c in range(vert.shape[0]):
        blurred_span(vert, c, weights, out)
        assert out.tobytes() == _span_reference(vert, c, weights).tobytes(), c


@pytest.mark.parametrize(("taps", "width"), [(1, 40), (7, 40), (11, 40), (7, 5), (11, 7)])
def test_blur_row_equals_the_sums_tap_by_tap_at_every_column(taps, width):
    from robostereo.matcher.edge_kernels import blur_row

    rng = np.random.default_rng(taps + width)
    vert = rng.uniform(0, 127, width).astype(np.float32)
    weights = rng.uniform(0.01, 0.3, taps).astype(np.float32)
    out = np.full(width, np.nan, np.float32)
    blur_row(vert, weights, out)
    want = [_span_reference(vert, c, weights)[3] for c in range(width)]  # column c: index 3
    assert out.tobytes() == np.array(want, np.float32).tobytes()


@pytest.mark.parametrize(("taps", "width", "step"), [(5, 30, 1), (7, 30, 1), (7, 200, 60)])
def test_fine_positions_inside_and_at_the_ends_equal_a_plain_python_placement(taps, width,
                                                                               step):
    # rows of many points are blurred whole, rows of a few (step 60) point by point
    from robostereo.matcher.edge_kernels import fine_offset, fine_positions

    rng = np.random.default_rng(11)
    vert = rng.uniform(0, 127, (6, width)).astype(np.float32)
    weights = rng.uniform(0.05, 0.4, taps).astype(np.float32)
    columns = np.arange(2, width - 2, step)
    row = np.repeat(np.arange(1, 5), columns.shape[0]).astype(np.int32)
    column = np.tile(columns, 4).astype(np.int32)
    sign = np.where(rng.random(row.shape[0]) < 0.5, 1, -1).astype(np.int8)
    x = column + rng.uniform(-0.5, 0.5, row.shape[0])
    want = x.copy()
    for i in range(row.shape[0]):
        sg = np.float32(1.0 if sign[i] > 0 else -1.0)
        fo = fine_offset(_span_reference(vert[row[i]], column[i], weights), 3, sg)
        if fo == fo:
            move = column[i] + fo - want[i]
            if abs(move) > 0.05:
                want[i] += move - np.copysign(0.05, move)
    got = x.copy()
    fine_positions(got, row, column, sign, vert[1:], 1, weights, 0.05, 0, row.shape[0])
    assert np.mean(got != x) > 0.3  # points inside and at the ends moved
    assert got.tobytes() == want.tobytes()


def _fma_machine() -> bool:
    from llvmlite import binding

    features = binding.get_host_cpu_features()
    return bool(features.get("fma") and features.get("avx2"))


def test_rgb_to_grey_equals_numpy_rounded_once_per_multiply_add():
    rgb = np.random.default_rng(11).integers(0, 256, (5, 37, 3), np.uint8)
    out = np.full((5, 37), -1.0, np.float32)
    rgb_to_grey(rgb.reshape(5, -1), out, 32)
    # float64 holds each product and sum exactly: one rounding to float32, as an FMA
    r, g, b = (rgb[..., k].astype(np.float64) for k in range(3))
    c0, c1, c2 = (np.float64(np.float32(c)) for c in (0.299, 0.587, 0.114))
    inner = np.float32(r * c0 + (g.astype(np.float32) * np.float32(c1)).astype(np.float64))
    want = np.float32(b * c2 + inner.astype(np.float64))
    assert np.array_equal(out[:, :32], want[:, :32])
    assert (out[:, 32:] == -1.0).all()  # the tail is left to OpenCV
    rounded_twice = np.float32(np.float32(b * c2) + inner)  # an FMA is not a mul and add
    assert not np.array_equal(out[:, :32], rounded_twice[:, :32])


@pytest.mark.skipif(not _fma_machine(), reason="OpenCV's loops use FMA only with AVX2/FMA")
@pytest.mark.parametrize("width", [1, 7, 8, 29, 61, 741])
def test_grey_conversion_gives_opencv_values(width):
    from robostereo.matcher.grey_levels import _colour_to_grey

    rgb = np.random.default_rng(width).integers(0, 256, (6, width, 3), np.uint8)
    want = cv2.cvtColor(rgb.astype(np.float32), cv2.COLOR_RGB2GRAY)
    for got in (_colour_to_grey(rgb, True), _colour_to_grey(rgb, False), _colour_to_grey(rgb)):
        assert np.array_equal(got.view(np.uint32), want.view(np.uint32))


@pytest.mark.parametrize("taps", [3, 7, 13])
def test_blur_column_equals_numpy_rounded_once_per_multiply_add(taps):
    from robostereo.matcher.edge_kernels import blur_column

    rng = np.random.default_rng(taps)
    grey = rng.uniform(0, 127, (taps + 4, 21)).astype(np.float32)
    half = rng.uniform(0.01, 0.3, taps // 2 + 1).astype(np.float32)
    weights = np.concatenate([half[:0:-1], half])  # symmetric, centre half[0]
    rad = taps // 2
    padded = np.pad(grey, ((rad, rad), (0, 0)), mode="reflect")  # = BORDER_REFLECT_101
    for y in (0, rad, grey.shape[0] - 1):
        out = np.empty(21, np.float32)
        blur_column(grey, y, weights, 16, out)
        col = padded[y:y + taps].astype(np.float64)  # rows y - rad .. y + rad
        # columns 0..15: each multiply-add rounded once (float64 holds it exactly)
        acc = np.float32(col[rad] * np.float64(weights[rad]))
        tail = np.float32(np.float32(weights[rad]) * grey[y])
        for k in range(1, rad + 1):
            pair = np.float32(col[rad + k] + col[rad - k])
            acc = np.float32(pair.astype(np.float64) * np.float64(weights[rad + k]) + acc)
            tail = np.float32(tail + np.float32(weights[rad + k] * pair))
        assert out[:16].tobytes() == acc[:16].tobytes(), y
        assert out[16:].tobytes() == tail[16:].tobytes(), y  # the scalar tail: twice


@pytest.mark.skipif(not _fma_machine(), reason="OpenCV's loops use FMA only with AVX2/FMA")
@pytest.mark.parametrize("blur", [0.5, 0.85, 2.0])
def test_fine_positions_from_grey_equal_those_from_opencvs_column_blur(blur):
    from robostereo.matcher.edge_kernels import fine_positions, fine_positions_grey
    from robostereo.matcher.edges import _ONE, fine_weights

    rng = np.random.default_rng(3)
    grey = cv2.GaussianBlur(rng.uniform(0, 127, (30, 83)).astype(np.float32), (0, 0), 1.5)
    weights = fine_weights(blur)
    row = np.repeat(np.arange(30), 20).astype(np.int32)
    column = np.tile(np.arange(3, 80, 4) + 1, 30)[:row.shape[0]].astype(np.int32)
    sign = np.where(rng.random(row.shape[0]) < 0.5, 1, -1).astype(np.int8)
    x = column + rng.uniform(-0.5, 0.5, row.shape[0])
    vert = cv2.sepFilter2D(grey, -1, _ONE, weights, borderType=cv2.BORDER_REFLECT_101)
    want = x.copy()
    fine_positions(want, row, column, sign, vert, 0, weights, 0.05, 0, row.shape[0])
    got = x.copy()
    fine_positions_grey(got, row, column, sign, grey, weights, 0.05, 80)
    assert np.mean(want != x) > 0.1  # many points moved
    assert got.tobytes() == want.tobytes()


@pytest.mark.parametrize("dtype", [np.uint8, np.int8, np.uint16, np.int16])
def test_integer_greys_scale_in_one_pass_as_numpy_in_two(dtype):
    from robostereo.matcher.grey_levels import to_grey

    info = np.iinfo(dtype)
    img = np.random.default_rng(4).integers(info.min, info.max, (6, 13), endpoint=True)
    img = img.astype(dtype)
    for depth in (None, 7, 12):
        scale = np.float32(127 / (2.0 ** (depth or info.bits) - 1)) if depth != 7 else None
        want = img.astype(np.float32)
        if scale is not None:
            want *= scale
        for view in (img, img[:, ::2]):  # contiguous and strided
            got = to_grey(view, bit_depth=depth)
            w = want if view is img else want[:, ::2]
            assert got.dtype == np.float32 and got.tobytes() == np.ascontiguousarray(w).tobytes()
