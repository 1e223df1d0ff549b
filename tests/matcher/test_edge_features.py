"""The edge points' connectivity pattern types and their differences (seed 3.2) by hand."""

from __future__ import annotations

import numpy as np

from robostereo.matcher.edge_features import pattern_difference, pattern_type


def test_pattern_type_numbering_covers_1_to_16():
    u, v = np.meshgrid([-1, 0, 1], [-1, 0, 1], indexing="ij")
    both = pattern_type(u.ravel(), v.ravel(), True, True)
    assert sorted(both.tolist()) == list(range(1, 10))
    assert pattern_type([-1, 0, 1], 0, True, False).tolist() == [10, 11, 12]
    assert pattern_type(0, [-1, 0, 1], False, True).tolist() == [13, 14, 15]
    assert pattern_type(0, 0, False, False).item() == 16


def test_pattern_difference_by_hand():
    # upper: both at offset 0 -> 0; lower: left -1, right +1 -> 2
    assert pattern_difference(0, -1, True, True, 0, 1, True, True).item() == 2
    # upper: one connected, the other not -> 3; lower: both absent -> 0
    assert pattern_difference(0, 0, True, False, 0, 0, False, False).item() == 3
    assert pattern_difference(1, 1, True, True, -1, 0, False, True).item() == 3 + 1
    assert pattern_difference(-1, -1, True, True, 1, 1, False, False).item() == 6
