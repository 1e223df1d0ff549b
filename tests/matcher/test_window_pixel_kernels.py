"""The census and Sobel kernels against plain references."""

from __future__ import annotations

import numpy as np
import pytest

from robostereo.matcher.window_costs import census_transform
from robostereo.matcher.window_pixel_kernels import census_padded, census_row, sobel, sobel_row


@pytest.mark.parametrize("width", [1, 5, 31, 133])
def test_the_unrolled_census_is_the_generic_one(width):
    """Rows narrower than a vector, and wide ones whose vector loop leaves a tail: the
    two words made apart and joined are the generic census, every bit."""
    g = np.random.default_rng(3).integers(0, 4, (23, width)).astype(np.float32)  # ties
    padded = np.pad(g, ((2, 2), (3, 3)), mode="edge")
    assert np.array_equal(census_transform(g), census_padded(padded, 23, width, 3, 2))


def test_rows_are_the_rows_of_the_whole_image():
    """The pass's census and Sobel rows, borders included, are those of the image."""
    g = np.random.default_rng(5).uniform(0, 127, (9, 17)).astype(np.float32)
    whole_census, whole_sobel = census_transform(g), sobel(g)
    c, s, buf = np.empty(17, np.uint64), np.empty(17, np.int16), np.empty((5, 23), np.float32)
    for y in range(9):
        census_row(g, y, c, buf)
        sobel_row(g, y, s)
        assert np.array_equal(c, whole_census[y]) and np.array_equal(s, whole_sobel[y])
