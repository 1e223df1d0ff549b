"""Figural continuity kernels against plain Python on random contours and a hand-made one."""

from __future__ import annotations

import itertools

import numpy as np

from robostereo.matcher.contour_kernels import chain_support, contour_support, linked_support


def _contours(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Random vertical chains: up/down links of ``n`` points in shuffled order."""
    order = rng.permutation(n)
    up = np.full(n, -1, np.int64)
    down = np.full(n, -1, np.int64)
    for a, b in itertools.pairwise(order):
        if rng.uniform() < 0.85:  # chains broken now and then
            down[a], up[b] = b, a
    return up, down


def _walk(nxt: np.ndarray, i: int, reach: int) -> list[int]:
    out = []
    for _ in range(reach):
        i = int(nxt[i])
        if i < 0:
            break
        out.append(i)
    return out


def test_contour_support_equals_plain_python():
    rng = np.random.default_rng(3)
    n = 400
    up, down = _contours(rng, n)
    d = np.round(rng.normal(20, 1.0, n), 1)
    d[rng.uniform(size=n) < 0.1] = np.nan
    w = rng.uniform(size=n)
    sup, reached = contour_support(up, down, d, w, 5, 1.0)
    for i in range(n):
        nb = _walk(up, i, 5) + _walk(down, i, 5)
        assert reached[i] == len(nb)
        expect = sum(w[j] for j in nb if abs(d[j] - d[i]) <= 1.0)
        assert np.isclose(sup[i], expect)
    assert np.any(sup > 0) and np.any(reached > sup)  # both cases met


def test_linked_support_equals_plain_python():
    rng = np.random.default_rng(4)
    n, m = 300, 250
    up, down = _contours(rng, n)
    rup, rdown = _contours(rng, m)
    right = rng.integers(-1, m, n).astype(np.int64)
    # make some left contours matched point to point onto right contours
    for i in range(n):
        if right[i] >= 0 and up[i] >= 0 and rup[right[i]] >= 0 and rng.uniform() < 0.7:
            right[up[i]] = rup[right[i]]
    w = np.ones(n)
    sup = linked_support(up, down, right, rup, rdown, w, 3)
    for i in range(n):
        expect = 0.0
        if right[i] >= 0:
            for nl, nr in ((up, rup), (down, rdown)):
                j, q = i, int(right[i])
                for _ in range(3):
                    j = int(nl[j])
                    q = int(nr[q]) if j >= 0 else -1
                    if j < 0 or q < 0:
                        break
                    expect += w[j] * (right[j] == q)
        assert sup[i] == expect
    assert sup.max() >= 2


def test_a_contour_supports_its_disparity_and_not_an_outlier():
    # one contour of 9 points, line by line; point 4 is off by 3 px
    n = 9
    up = np.array([-1, *range(n - 1)], np.int64)
    down = np.array([*range(1, n), -1], np.int64)
    d = np.full(n, 12.0) + 0.1 * np.arange(n)
    d[4] = 15.0
    strong = np.ones(n, bool)
    strong[[3, 5]] = False
    sup, _ = contour_support(up, down, d, strong.astype(float), 2, 1.0)
    assert sup[4] == 0.0
    assert sup[0] == 2.0  # below it 1 and 2, both strong and agreeing
    assert sup[3] == 2.0  # 1 and 2 agree; 4 does not; 5 agrees but is weak
    length, anchors = chain_support(up, down, d, strong, 4, 1.0)
    assert length[4] == 0 and anchors[4] == 0  # both ways break at once
    # from 2 the walk up meets strong 1; the walk down meets weak 3, then breaks at 4
    assert length[2] == 2 and anchors[2] == 1
    assert length[6] == 2 and anchors[6] == 1  # up: 5 (weak), then breaks; down: 7
