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


def _texture(rng: np.random.Generator, height: int, width: int) -> np.ndarray:
    """Random rectangles of constant grey over fine noise, 0..255 scale, ``(H, W)``."""
    from scipy.ndimage import gaussian_filter

    tex = gaussian_filter(rng.normal(0.0, 1.0, (height, width)), 1.0) * 25.0 + 128.0
    for _ in range(int(height * width / 400)):
        h, w = rng.integers(4, 30, 2)
        y, x = rng.integers(-h // 2, height), rng.integers(-w // 2, width)
        tex[max(y, 0):y + h, max(x, 0):x + w] += rng.uniform(-70, 70)
    return np.clip(tex, 5, 250)


def layered_pair(rng: np.random.Generator, *, height: int = 160, width: int = 320,
                 background: tuple[float, float] = (5.0, 12.0),
                 foreground: tuple[float, float] = (16.0, 26.0), n_boxes: int = 3,
                 noise: float = 1.5) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A slanted textured background plane with fronto-parallel textured boxes before it.

    Unlike :func:`synthetic_pair` it has occlusions and depth edges whose two sides move
    differently, and texture that is not all edges.  Disparities are fractional: both
    views are rendered at 4x horizontal resolution and area-averaged.

    Returns ``left``, ``right`` (``uint8``, ``(H, W)``) and the ground-truth disparity of
    the left view ``(H, W)`` (known everywhere, occluded pixels included, as
    Middlebury's maps are).
    """
    from scipy.ndimage import map_coordinates

    ss = 4
    pad = int(foreground[1]) + 4
    tex_w = width + 2 * pad
    tb = _texture(rng, height, tex_w)
    boxes = []
    for _ in range(n_boxes):
        bh, bw = rng.integers(height // 5, height // 2), rng.integers(width // 8, width // 3)
        boxes.append((int(rng.integers(0, height - bh)), int(bh), float(rng.uniform(0, width - bw)),
                      float(bw), float(rng.uniform(*foreground)), _texture(rng, height, tex_w)))
    boxes.sort(key=lambda b: -b[4])  # nearest (largest disparity) first
    a = background[0]
    b = (background[1] - background[0]) / width  # d_b(x) = a + b x
    ys = np.arange(height)[:, None] * np.ones((1, width * ss))
    xs = np.broadcast_to((np.arange(width * ss) + 0.5) / ss - 0.5, ys.shape)

    def sample(tex: np.ndarray, x: np.ndarray) -> np.ndarray:
        return map_coordinates(tex, [ys, x + pad], order=1, mode="nearest")

    def render(right: bool) -> tuple[np.ndarray, np.ndarray]:
        # left-view coordinate of the background seen at xs, and its disparity
        xb = (xs + a) / (1.0 - b) if right else xs
        img = sample(tb, xb)
        disp = a + b * xb
        done = np.zeros(xs.shape, bool)
        for y0, bh, x0, bw, d, tex in boxes:
            xl = xs + d if right else xs
            inside = (ys >= y0) & (ys < y0 + bh) & (xl >= x0) & (xl < x0 + bw) & ~done
            img = np.where(inside, sample(tex, xl), img)
            disp = np.where(inside, d, disp)
            done |= inside
        return img.reshape(height, width, ss).mean(axis=2), disp

    left, disp = render(False)
    right, _ = render(True)
    gt = disp.reshape(height, width, ss)[:, :, ss // 2]
    left = left + rng.normal(0, noise, left.shape)
    right = right + rng.normal(0, noise, right.shape)
    return (np.clip(np.rint(left), 0, 255).astype(np.uint8),
            np.clip(np.rint(right), 0, 255).astype(np.uint8), gt)
