"""Edge points and their features (seed 3.1-3.2) against hand-computed values."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from synthetic import render_profile

from robostereo.errors import InputError
from robostereo.evaluation.outlines import RowBoundaries, boundary_offsets
from robostereo.matcher.edges import detect_edges
from robostereo.matcher.grey_levels import smooth, to_grey
from robostereo.simulation.occluders import occluder_pair


def test_grey_scale_is_the_same_contrast_at_any_bit_depth():
    g8 = np.zeros((12, 40), np.uint8)
    g8[:, 20:] = 160
    g16 = g8.astype(np.uint16) * 257
    rgb = np.repeat(g8[:, :, None], 3, axis=2)
    e8, e16, ec = detect_edges(g8), detect_edges(g16), detect_edges(rgb)
    assert len(e8) == len(e16) == len(ec) == 12
    assert np.allclose(e8.x, e16.x) and np.allclose(e8.x, ec.x)
    assert np.allclose(e8.magnitude, e16.magnitude, rtol=1e-5)
    assert to_grey(np.array([[255]], np.uint8))[0, 0] == 127.0
    assert to_grey(np.array([[100]], np.uint8), bit_depth=7)[0, 0] == 100.0


def test_step_magnitude_and_position_by_hand():
    # a step of h grey levels (0..127 scale) between columns 19 and 20: the smoothed row
    # follows the column sums of the kernel, 10, 34, 39, 34, 10 (/127)
    h = 40.0
    img = np.zeros((11, 40), np.float32)
    img[:, 20:] = h
    e = detect_edges(img, bit_depth=7)
    # g(19) = (S(20) - S(18)) / 2 = h * (39 + 34) / 127 / 2, and g(20) the same
    expected_peak = h * (34 + 39) / 127 / 2
    assert e.x[0] == pytest.approx(19.5, abs=1e-6)
    assert e.column[0] in (19, 20)
    assert e.magnitude.min() >= expected_peak - 1e-4
    assert e.sign[0] == 1
    assert np.all(e.mean_grey >= 0) and np.all(e.mean_grey <= h)


@pytest.mark.parametrize("pos", [20.1, 20.37, 20.5, 20.81, 21.0])
def test_subpixel_position_of_area_sampled_steps(pos):
    row = render_profile(np.array([pos]), np.array([30.0, 110.0]), 48, 0.0)
    img = np.tile(row, (7, 1)).astype(np.float32)
    e = detect_edges(img, bit_depth=7)
    # the area-sampled step at ``pos`` crosses half height at ``pos`` (pixel centres)
    assert np.all(np.abs(e.x - pos) < 0.05)
    assert np.all(detect_edges(img, bit_depth=7, subpixel=False).x == np.round(e.x))


def test_threshold_constant_and_weak_images():
    assert len(detect_edges(np.full((20, 30), 77, np.uint8))) == 0
    weak = np.zeros((10, 30), np.uint8)
    weak[:, 15:] = 20  # 10 grey levels on the seed's scale: gradient ~2.9 < 8
    assert len(detect_edges(weak)) == 0
    assert len(detect_edges(weak, threshold=2.0)) == 10


def test_pattern_types_of_a_slanted_edge():
    # an edge that moves one column right per row: above at -1, below at +1 -> type 3;
    # the first row has only a lower neighbour (13..15), the last only an upper (10..12)
    img = np.zeros((11, 40), np.uint8)
    for r in range(11):
        img[r, 15 + r:] = 200
    e = detect_edges(img)
    assert e.pattern[3:8].tolist() == [3] * 5
    assert 13 <= e.pattern[0] <= 15 and 10 <= e.pattern[-1] <= 12
    assert e.up[0] == -1 and e.down[-1] == -1
    assert np.all(e.up[1:] == np.arange(10)) and np.all(e.down[:-1] == np.arange(1, 11))


def test_connectivity_needs_the_same_contrast_sign():
    img = np.zeros((6, 40), np.uint8)
    img[:3, 20:] = 200          # rising edge on rows 0-2
    img[3:, :20] = 200          # falling edge at the same column on rows 3-5
    e = detect_edges(img)
    rows = e.row
    assert e.down[rows == 2][0] == -1 and e.up[rows == 3][0] == -1


def test_row_step_samples_lines():
    img = np.zeros((40, 30), np.uint8)
    img[:, 15:] = 200
    e = detect_edges(img, row_step=10, row_offset=5)
    assert e.row.tolist() == [5, 15, 25, 35] and e.line.tolist() == [0, 1, 2, 3]


@pytest.mark.parametrize(
    ("image", "message"),
    [
        (np.zeros((0, 10), np.uint8), "empty"),
        (np.zeros((4, 4, 2), np.uint8), "shape"),
        (np.full((8, 8), np.nan), "NaN"),
        (np.zeros((3, 30), np.uint8), "at least 5 x 5"),
    ],
)
def test_bad_images_raise_one_line_errors(image, message):
    with pytest.raises(InputError, match=message) as info:
        detect_edges(image)
    assert "\n" not in str(info.value)


def test_bad_parameters():
    img = np.zeros((10, 10), np.uint8)
    with pytest.raises(InputError, match="threshold"):
        detect_edges(img, threshold=float("nan"))
    with pytest.raises(InputError, match="row_step"):
        detect_edges(img, row_step=0)


def test_valid_mask_suppresses_edges_of_the_fill():
    # a rectified image whose right part has no source, filled with black: the fill's
    # border is an edge in the image but not in the scene
    img = np.full((12, 60), 100, np.uint8)
    img[:, 20:] = 180            # a real edge at 19.5
    img[:, 45:] = 0              # the fill starts at column 45
    valid = np.ones(img.shape, bool)
    valid[:, 45:] = False
    plain = detect_edges(img)
    masked = detect_edges(img, valid=valid)
    assert sorted(set(np.round(plain.x, 3).tolist())) == [19.5, 44.5]
    assert np.allclose(masked.x, 19.5) and len(masked) == 12
    with pytest.raises(InputError, match="valid mask"):
        detect_edges(img, valid=valid[:, :10])


def test_outlines_between_textured_surfaces_are_located_without_bias(held_out_occluders) -> None:
    """On held-out occluder pairs (exact sub-pixel outlines, texture on both sides), the
    edge points within 1.5 px of an outline lie a signed median within 0.1 px of it
    and a median within 0.4 px: the texture beside a step scatters the gradient's peak
    but does not pull it into the object or out of it.  Placed towards the lightly
    blurred image's peak (the matcher's default), the scatter is smaller."""
    scatter = {}
    for blur in (None, 0.85):
        offsets = []
        for p in held_out_occluders:
            e = detect_edges(p.left, edge_blur_px=blur)
            _, off, _ = boundary_offsets(e.row, e.x, RowBoundaries(*p.boundaries()))
            offsets.append(off)
        o = np.concatenate(offsets)
        assert o.size > 300
        assert abs(np.median(o)) <= 0.1
        assert np.median(np.abs(o)) <= 0.4
        scatter[blur] = float(np.median(np.abs(o)))
    assert scatter[0.85] <= scatter[None] - 0.03


@pytest.mark.parametrize("gap", [2.5, 3.0])
def test_an_edge_beside_another_is_pulled_less_on_the_lightly_blurred_image(gap) -> None:
    """A step with a second edge of the other sign ``gap`` px beside it: the 5 x 5
    smoothed gradient's peak is pulled away from the second edge (0.17-0.28 px
    measured), the edge placed towards the peak on the image blurred by 0.85 px less
    (0.11-0.18 px: that peak's 0.06-0.13 px plus the dead zone's 0.05); the edge points
    found are the same."""
    pulls = {None: [], 0.85: []}
    for x0 in np.linspace(30.0, 31.0, 11):
        row = render_profile(np.array([x0, x0 + gap]), np.array([30.0, 110.0, 70.0]), 80, 0.0)
        img = np.tile(row / 127.0, (9, 1))
        found = {}
        for blur in pulls:
            e = detect_edges(img, edge_blur_px=blur)
            k = np.argmin(np.abs(e.x - x0) + 100 * (e.row != 4))
            pulls[blur].append(e.x[k] - x0)
            found[blur] = (e.column.tolist(), e.sign.tolist())
        assert found[None] == found[0.85]
    smoothed, fine = np.abs(pulls[None]), np.abs(pulls[0.85])
    assert np.mean(smoothed) >= 0.12
    assert np.mean(fine) <= np.mean(smoothed) - 0.04 and np.max(fine) <= 0.2


def test_a_lone_step_is_placed_alike_on_either_image() -> None:
    """With nothing beside it, an anti-aliased step is placed within 0.03 px of its
    true position on the smoothed and on the lightly blurred (or unblurred) image."""
    for x0 in np.linspace(30.0, 31.0, 11):
        row = render_profile(np.array([x0]), np.array([30.0, 110.0]), 80, 0.0)
        img = np.tile(row / 127.0, (9, 1))
        for blur in (None, 0.0, 0.85):
            e = detect_edges(img, edge_blur_px=blur)
            assert len(e) == 9 and np.abs(e.x - x0).max() <= 0.03


def test_the_edge_blur_moves_only_the_positions() -> None:
    """The same edge points with the same features, each moved by at most a pixel and
    a half (the peak within a pixel of its column, its vertex within half a pixel), many
    not at all (a move within the dead zone is not taken)."""
    p = occluder_pair(7, height=60, width=160)
    a, b = detect_edges(p.left), detect_edges(p.left, edge_blur_px=0.85)
    for name in ("column", "row", "sign", "magnitude", "pattern", "up", "down",
                 "mean_grey", "grey_before", "grey_after"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    moved = np.abs(a.x - b.x)
    assert moved.max() <= 1.5 and 0.2 < np.mean(moved > 0) < 0.9
    assert np.array_equal(detect_edges(p.left, subpixel=False, edge_blur_px=0.85).x,
                          a.column.astype(float))


@pytest.mark.parametrize(("blur", "row_step", "row_offset"),
                         [(0.85, 1, 0), (0.85, 3, 2), (1.7, 1, 0), (0.0, 1, 0)])
def test_the_blur_made_strip_by_strip_places_edges_as_the_whole_image_would(
        blur, row_step, row_offset) -> None:
    """The fine placement blurs strips of rows in turn (no blurred image is held):
    on an image of several strips, the last partial, every point lands where the
    blur of the whole image at once puts it."""
    from robostereo.matcher.edge_kernels import FINE_DEAD_ZONE_PX, fine_positions
    from robostereo.matcher.edges import fine_weights

    img = np.random.default_rng(8).integers(0, 256, (203, 90)).astype(np.uint8)
    plain = detect_edges(img, row_step=row_step, row_offset=row_offset)
    fine = detect_edges(img, row_step=row_step, row_offset=row_offset, edge_blur_px=blur)
    assert len(plain) > 300 and np.all(np.diff(plain.row) >= 0)
    w = fine_weights(blur)
    whole = cv2.sepFilter2D(to_grey(img), -1, np.ones(1, np.float32), w,
                            borderType=cv2.BORDER_REFLECT_101)
    x = plain.x.copy()
    fine_positions(x, plain.row, plain.column, plain.sign, whole, 0, w, FINE_DEAD_ZONE_PX,
                   0, len(x))
    assert np.array_equal(fine.x, x)
    if blur > 0:
        assert np.mean(fine.x != plain.x) > 0.2  # it moved points: the check has teeth


@pytest.mark.parametrize(("strip_rows", "row_step", "row_offset", "masked", "stripes"),
                         [(64, 1, 0, False, False), (5, 1, 0, False, False),
                          (7, 3, 2, True, False), (1, 2, 1, False, False),
                          (64, 70, 3, True, False), (64, 1, 0, False, True),
                          (3, 1, 0, True, True)])
def test_edges_found_strip_by_strip_equal_the_whole_smoothed_image(
        monkeypatch, strip_rows, row_step, row_offset, masked, stripes) -> None:
    """The edge stage smooths strips of rows in turn (no smoothed image is held): with
    strips of every height down to one row, the last one partial, the edge points and
    all their features are those of the whole image smoothed at once; also where the
    first strips foretell too few points (no edges above, an edge every three pixels
    below), so that the room made for them grows."""
    import robostereo.matcher.edges as edges_module
    from robostereo.matcher.edge_kernels import edge_points
    from robostereo.matcher.edges import BORDER, usable_pixels

    img = np.random.default_rng(9).integers(0, 256, (203, 90)).astype(np.uint8)
    if stripes:
        img = np.tile(np.repeat(np.arange(30) % 2 * 200, 3), (203, 1)).astype(np.uint8)
        img[::7] = img[::7] // 2  # lines of another contrast
        img[:100] = 90  # no edge points in the first strips
    valid = np.ones(img.shape, bool)
    valid[:, :20] = valid[90:100] = False
    grey = to_grey(img)
    n_lines = len(range(row_offset, img.shape[0], row_step))
    usable = usable_pixels(valid) if masked else np.ones((1, 1), np.bool_)
    src = np.ascontiguousarray(smooth(grey)[row_offset::row_step])
    whole = edge_points(src, grey, np.float32(8.0), BORDER, row_offset, row_step, True,
                        n_lines, usable, masked)
    monkeypatch.setattr(edges_module, "_EDGE_STRIP_ROWS", strip_rows)
    e = detect_edges(img, row_step=row_step, row_offset=row_offset,
                     valid=valid if masked else None)
    assert len(e) >= 10
    if stripes:
        assert len(e) > 1024  # beyond the least room first made: it grew
    names = ("line", "column", "row", "x", "sign", "magnitude", "up", "down", "up_offset",
             "down_offset", "pattern", "mean_grey", "grey_before", "grey_after")
    for name, expected in zip(names, whole, strict=True):
        assert np.array_equal(getattr(e, name), expected), name


def test_edge_sets_keep_int32_indices_and_float32_where_computed_in_float32() -> None:
    """The dtypes of an EdgeSet (52 bytes a point): indices int32, the features that
    come from float32 arithmetic float32 and equal to it, the position and the 5 x 5
    mean (summed in float64) float64."""
    img = np.random.default_rng(10).integers(0, 256, (60, 80)).astype(np.uint8)
    e = detect_edges(img, edge_blur_px=0.85)
    assert len(e) > 50
    kinds = {"line": np.int32, "row": np.int32, "column": np.int32, "up": np.int32,
             "down": np.int32, "magnitude": np.float32, "grey_before": np.float32,
             "grey_after": np.float32, "x": np.float64, "mean_grey": np.float64,
             "sign": np.int8, "pattern": np.int8, "up_offset": np.int8,
             "down_offset": np.int8}
    for name, dtype in kinds.items():
        assert getattr(e, name).dtype == dtype, name
    s = smooth(to_grey(img))
    assert np.array_equal(e.grey_before, s[e.row, np.maximum(e.column - 4, 0)])
    assert not np.all(e.x == np.round(e.x))  # sub-pixel positions kept in float64


@pytest.mark.parametrize("blur", [-0.1, 10.5, float("nan"), "1", True])
def test_an_edge_blur_outside_0_10_is_refused(blur) -> None:
    with pytest.raises(InputError, match="edge_blur_px"):
        detect_edges(np.zeros((9, 20), np.uint8), edge_blur_px=blur)


def test_rows_are_the_lines_array_only_where_every_row_is_a_line():
    """Row step 1 from row 0: ``row`` is ``line`` itself (no second array); any other
    sampling keeps its own rows, ``line * row_step + row_offset``."""
    img = np.random.default_rng(4).integers(0, 255, (40, 60)).astype(np.uint8)
    e = detect_edges(img)
    assert e.row is e.line and len(e) > 50
    for step, offset in ((2, 0), (1, 3)):
        s = detect_edges(img, row_step=step, row_offset=offset)
        assert not np.shares_memory(s.row, s.line)
        assert np.array_equal(s.row, s.line * step + offset) and len(s) > 20
