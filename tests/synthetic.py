"""Synthetic rectified pairs with known fractional disparity, for tests and benchmarks."""

from __future__ import annotations

import numpy as np


def step_profile(
    rng: np.random.Generator, width: float, *, min_run: float = 7.0, max_run: float = 16.0,
    contrast: tuple[float, float] = (70.0, 100.0),
) -> tuple[np.ndarray, np.ndarray]:
    """Random piecewise-constant 1-D profile: edge positions and the levels between them.

    Successive levels differ by ``contrast`` grey levels (0..255 scale), so every edge's
    gradient stands well clear of the threshold and of the noise.
    """
    edges = np.cumsum(rng.uniform(min_run, max_run, int(width / min_run) + 4)) - max_run
    levels = np.empty(edges.shape[0] + 1)
    levels[0] = rng.uniform(40, 215)
    for i in range(1, levels.shape[0]):
        step = rng.uniform(*contrast) * rng.choice([-1.0, 1.0])
        nxt = levels[i - 1] + step
        if not 20 <= nxt <= 235:
            nxt = levels[i - 1] - step
        levels[i] = nxt
    return edges, levels


def render_profile(edges: np.ndarray, levels: np.ndarray, width: int, shift: float) -> np.ndarray:
    """Area-sampled profile on pixels ``0..width-1`` with the pattern moved by ``-shift``.

    Pixel ``j`` covers ``[j - 0.5, j + 0.5]``; the value is the exact mean of the
    piecewise-constant profile over it (anti-aliased, so edges move by fractions).
    """
    e = edges - shift
    lo = np.arange(width) - 0.5
    # integral of the profile from -inf reference: sum of level * covered length
    cuts = np.clip(e[None, :], lo[:, None], lo[:, None] + 1.0)  # (W, E)
    bounds = np.concatenate([lo[:, None], cuts, lo[:, None] + 1.0], axis=1)
    lengths = np.diff(bounds, axis=1)  # (W, E+1)
    return lengths @ levels


def synthetic_pair(rng: np.random.Generator, *, height: int = 120, width: int = 320,
                   disparities: tuple[float, ...] = (7.3, 11.65, 9.05),
                   noise: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A textured pair of vertical edges in horizontal bands of known fractional disparity.

    Returns ``left``, ``right`` (``uint8``, ``(H, W)``) and the ground-truth disparity
    ``(H, W)`` (NaN on the rows where bands meet and where the partner pixel would
    lie outside the right image).
    """
    left = np.zeros((height, width))
    right = np.zeros((height, width))
    gt = np.full((height, width), np.nan)
    band = height // len(disparities)
    for k, d in enumerate(disparities):
        edges, levels = step_profile(rng, width + 40)
        rows = slice(k * band, (k + 1) * band)
        left[rows] = render_profile(edges, levels, width, 0.0)
        right[rows] = render_profile(edges, levels, width, d)
        gt[k * band + 3:(k + 1) * band - 3] = d
        gt[k * band:(k + 1) * band, : int(np.ceil(d)) + 6] = np.nan  # partner off the edge zone
    left += rng.normal(0, noise, left.shape)
    right += rng.normal(0, noise, right.shape)
    return (np.clip(np.rint(left), 0, 255).astype(np.uint8),
            np.clip(np.rint(right), 0, 255).astype(np.uint8), gt)
