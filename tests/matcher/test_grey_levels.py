"""Grey levels on the thesis's 0..127 scale and its 5 x 5 smoothing (seed 3.1)."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from robostereo.matcher.grey_levels import SEED_KERNEL, smooth, to_grey


def test_seed_kernel_is_figure_3_1_normalised():
    raw = SEED_KERNEL * 127  # 16 x 2 + 8 x 10 + 15 = 127 (seed-notes' "126" is a slip)
    assert raw[2, 2] == pytest.approx(15)
    assert raw[1:4, 1:4].sum() == pytest.approx(8 * 10 + 15)
    assert SEED_KERNEL.sum() == pytest.approx(1.0)
    assert np.allclose(raw, raw.T) and np.allclose(raw, raw[::-1, ::-1])


def test_smoothing_keeps_constant_and_spreads_an_impulse():
    assert np.allclose(smooth(np.full((9, 9), 50.0)), 50.0)
    img = np.zeros((9, 9), np.float32)
    img[4, 4] = 127
    out = smooth(img)
    assert out[4, 4] == pytest.approx(15) and out[3, 4] == pytest.approx(10)
    assert out[2, 2] == pytest.approx(2) and out[1, 1] == pytest.approx(0)


def test_colour_converted_in_blocks_equals_the_whole_image_at_once():
    rgb = np.random.default_rng(4).integers(0, 256, (150, 517, 3)).astype(np.uint8)
    assert rgb.shape[0] * rgb.shape[1] > 2 * (1 << 15)  # several blocks, the last partial
    whole = cv2.cvtColor(rgb.astype(np.float32), cv2.COLOR_RGB2GRAY)
    whole *= np.float32(127 / 255)
    assert to_grey(rgb).tobytes() == whole.tobytes()
