"""Synthetic occluder pairs: textured objects before a slanted plane, exact at outlines.

A rectified pair for measuring matchers where objects end: a textured background plane
whose disparity is linear in ``x`` and ``y`` (slanted), and textured fronto-parallel
polygons (occluders) before it at chosen depth gaps, with contours that are vertical,
horizontal and diagonal.  Each pixel is the mean over ``supersample x supersample``
points of its area (exact sub-pixel boundaries up to that sampling), so an outline's
intensity edge lies where the geometry puts it.  The ground truth is exact: the left
disparity at every pixel centre, the occlusion mask (left pixels whose scene point the
right view does not see: the half-occluded band beside each object's left contour,
as wide as the depth gap in disparity) and the silhouette boundaries along each row.

Every texture is a function of the surface's own left-view coordinates (value noise,
bilinear over a random grid, sharpened by a tanh into blotches), so the right view
shows the same surface points moved by their disparity: ``left(x, y) = right(x - d, y)``
wherever both see the point.
Deterministic from ``seed``.  Pure numpy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError, require_int, require_nonnegative, require_positive

__all__ = ["Occluder", "OccluderPair", "occluder_pair"]

#: the shapes :func:`occluder_pair` places, left to right: their contours' orientations
SHAPES: tuple[str, ...] = ("rectangle", "diamond", "hexagon")


@dataclass(frozen=True)
class Occluder:
    """A fronto-parallel textured polygon.

    Attributes
    ----------
    vertices : ndarray, shape (K, 2)
        ``(x, y)`` of the polygon in the left image, pixels (any simple polygon).
    disparity : float
        Its constant disparity, pixels.
    """

    vertices: NDArray[np.float64]
    disparity: float

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3 or not np.isfinite(v).all():
            raise InputError(f"vertices must be a finite (K >= 3, 2) array, got shape {v.shape}")
        require_positive("disparity", self.disparity)

    def contains(self, x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whether points ``(x, y)`` lie inside (even-odd rule), any shape of arrays.

        >>> o = Occluder(np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]]), 5.0)
        >>> o.contains(np.array([1.0, 5.0]), np.array([1.0, 1.0])).tolist()
        [True, False]
        """
        v = np.asarray(self.vertices, dtype=float)
        inside = np.zeros(np.broadcast(x, y).shape, dtype=bool)
        for (x0, y0), (x1, y1) in zip(v, np.roll(v, -1, axis=0), strict=True):
            if y0 == y1:
                continue
            crosses = (y0 > y) != (y1 > y)
            xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
            inside ^= crosses & (x < xc)
        return inside

    def crossings(self, y: float) -> NDArray[np.float64]:
        """Sorted ``x`` where the row ``y`` crosses the contour (entries and exits alternate).

        >>> o = Occluder(np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]]), 5.0)
        >>> o.crossings(1.0).tolist()
        [0.0, 4.0]
        """
        v = np.asarray(self.vertices, dtype=float)
        x0, y0 = v[:, 0], v[:, 1]
        x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
        ok = (y0 > y) != (y1 > y)
        xc = x0[ok] + (y - y0[ok]) * (x1[ok] - x0[ok]) / (y1[ok] - y0[ok])
        return np.sort(xc)


@dataclass(frozen=True)
class OccluderPair:
    """A rendered occluder pair and its exact ground truth.

    Attributes
    ----------
    left, right : ndarray of uint8, shape (H, W)
    disparity : ndarray, shape (H, W)
        Left disparity at each pixel centre (the frontmost surface there).
    occluded : ndarray of bool, shape (H, W)
        Left pixels whose scene point is hidden from the right view.
    mixed_left, mixed_right : ndarray of bool, shape (H, W)
        Pixels whose area covers more than one surface (the outlines, anti-aliased).
    occluders : tuple of Occluder
        Nearest first.
    background : tuple of float
        ``(a, bx, by)``: the plane's disparity ``a + bx x + by y``.
    """

    left: NDArray[np.uint8]
    right: NDArray[np.uint8]
    disparity: NDArray[np.float64]
    occluded: NDArray[np.bool_]
    mixed_left: NDArray[np.bool_]
    mixed_right: NDArray[np.bool_]
    occluders: tuple[Occluder, ...]
    background: tuple[float, float, float]

    def __post_init__(self) -> None:
        shapes = {a.shape for a in (self.left, self.right, self.disparity, self.occluded,
                                    self.mixed_left, self.mixed_right)}
        if len(shapes) != 1:
            raise InputError(f"OccluderPair arrays must share one (H, W) shape, got {shapes}")

    @property
    def disparity_range(self) -> tuple[float, float]:
        """Least and largest disparity of the left view."""
        return float(self.disparity.min()), float(self.disparity.max())

    def background_disparity(self, x: NDArray[np.float64] | float,
                             y: NDArray[np.float64] | float) -> NDArray[np.float64]:
        a, bx, by = self.background
        return np.asarray(a + bx * np.asarray(x) + by * np.asarray(y), dtype=float)

    def boundaries(self, *, step: float = 2.0) -> tuple[NDArray[np.intp], NDArray[np.float64],
                                                        NDArray[np.intp], NDArray[np.float64]]:
        """The exact silhouettes along each pixel row, as
        ``(rows, x, near_side, near_disparity)`` (the fields of
        :class:`robostereo.evaluation.outlines.RowBoundaries`).

        A crossing of an occluder's contour with a row centre counts where no nearer
        occluder covers it and the surface behind is more than ``step`` px farther.
        ``near_side`` is +1 where the occluder lies to the right of the crossing.
        """
        h, w = self.disparity.shape
        out: list[tuple[int, float, int, float]] = []
        for k, occ in enumerate(self.occluders):
            for i in range(h):  # a few crossings per row and occluder
                xs = occ.crossings(float(i))
                for n, xc in enumerate(xs):
                    if not -0.5 <= xc < w - 0.5:
                        continue
                    if any(o.contains(np.array(xc), np.array(float(i)))
                           for o in self.occluders[:k]):
                        continue
                    side = 1 if n % 2 == 0 else -1
                    behind = self._behind(k, xc - side * 1e-6, float(i))
                    if occ.disparity - behind > step:
                        out.append((i, float(xc), side, occ.disparity))
        a = np.array(out, dtype=float).reshape(-1, 4)
        return (a[:, 0].astype(np.intp), a[:, 1], a[:, 2].astype(np.intp), a[:, 3])

    def _behind(self, k: int, x: float, y: float) -> float:
        """Disparity of the surface behind occluder ``k`` at ``(x, y)``."""
        for o in self.occluders[k + 1:]:
            if o.contains(np.array(x), np.array(y)):
                return o.disparity
        return float(self.background_disparity(x, y))


#: a texture: random grid in -1..1, grid spacing, margin, mean and spread of grey levels
Texture = tuple[NDArray[np.float64], float, float, float, float]

#: how sharply value noise is pushed towards its extremes (tanh gain): blotches with
#: edges strong enough for the thesis's gradient threshold after its 5 x 5 smoothing
SHARPNESS = 3.0


def _texture(rng: np.random.Generator, h: int, w: int, cell: float, mean: float,
             spread: float, pad: float) -> Texture:
    """A random value grid over the image and ``pad`` px around it."""
    ny = int(np.ceil((h + 2 * pad) / cell)) + 2
    nx = int(np.ceil((w + 2 * pad) / cell)) + 2
    return rng.uniform(-1, 1, (ny, nx)), cell, pad, mean, spread


def _sample(tex: Texture, x: NDArray[np.float64], y: NDArray[np.float64]
            ) -> NDArray[np.float64]:
    """Sharpened bilinear value noise at ``(x, y)`` (left-view coordinates of the
    surface): ``mean + spread tanh(k n) / tanh(k)``, ``n`` the bilinear noise."""
    grid, cell, pad, mean, spread = tex
    u = np.clip((x + pad) / cell, 0, grid.shape[1] - 1.001)
    v = np.clip((y + pad) / cell, 0, grid.shape[0] - 1.001)
    j, i = np.floor(u).astype(np.intp), np.floor(v).astype(np.intp)
    fu, fv = u - j, v - i
    top = grid[i, j] * (1 - fu) + grid[i, j + 1] * fu
    bot = grid[i + 1, j] * (1 - fu) + grid[i + 1, j + 1] * fu
    n = top * (1 - fv) + bot * fv
    return mean + spread * np.tanh(SHARPNESS * n) / np.tanh(SHARPNESS)


def _shape(kind: str, cx: float, cy: float, r: float, rng: np.random.Generator
           ) -> NDArray[np.float64]:
    if kind == "rectangle":  # vertical and horizontal contours
        hw, hh = r * rng.uniform(0.6, 0.8), r * rng.uniform(0.8, 1.0)
        return np.array([[cx - hw, cy - hh], [cx + hw, cy - hh], [cx + hw, cy + hh],
                         [cx - hw, cy + hh]])
    if kind == "diamond":  # contours at 45 degrees
        return np.array([[cx, cy - r], [cx + r, cy], [cx, cy + r], [cx - r, cy]])
    if kind == "hexagon":  # vertical sides and contours at 60 degrees from the row
        a = np.deg2rad(np.arange(0, 360, 60) + 30.0)
        return np.stack([cx + r * np.cos(a), cy + r * np.sin(a)], axis=1)
    raise InputError(f"shape must be one of {', '.join(SHAPES)}, got {kind!r}")


def occluder_pair(
    seed: int = 0,
    *,
    height: int = 180,
    width: int = 360,
    gaps: tuple[float, ...] = (4.0, 8.0, 14.0),
    shapes: tuple[str, ...] = SHAPES,
    background: tuple[float, float] = (6.0, 12.0),
    supersample: int = 4,
    cell: float = 4.0,
) -> OccluderPair:
    """Render an occluder pair with its exact ground truth.

    Parameters
    ----------
    seed : int
        Random-number seed: textures, sizes, sub-pixel positions, grey levels.
    height, width : int
        Image size, pixels.
    gaps : tuple of float
        Depth gap in disparity of each occluder over the background at its centre
        (pixels); one occluder per gap, placed left to right.
    shapes : tuple of str
        The occluders' shapes in turn (``"rectangle"``, ``"diamond"``, ``"hexagon"``).
    background : tuple of float
        The plane's disparity at the left and right image borders (its slant in ``x``;
        it also tilts by a quarter of that over the height).
    supersample : int
        Points per pixel side for area coverage (4: 16 per pixel).
    cell : float
        Texture grain: the value noise's grid spacing, pixels (4).

    Returns
    -------
    OccluderPair

    Notes
    -----
    1. Occluders are laid out in equal columns, centred with a random sub-pixel jitter,
       radius a fraction of the column; disparity = background at the centre + gap.
    2. Each view's sample points (pixel centre + ``((k + 0.5) / s - 0.5)`` offsets)
       are mapped back to the left-view coordinates of each surface, nearest first
       (occluder ``x_l = x_r + d``; plane ``x_l = (x_r + a + by y) / (1 - bx)``); the
       first surface that contains its point colours the sample by its texture.
    3. Pixel values are sample means, rounded to 8 bits; the ground truth is evaluated
       at pixel centres.

    Examples
    --------
    >>> p = occluder_pair(1, height=40, width=120, gaps=(6.0,), shapes=("rectangle",))
    >>> p.left.shape, p.left.dtype.name, bool(p.occluded.any())
    ((40, 120), 'uint8', True)
    """
    height = require_int("height", height, minimum=16)
    width = require_int("width", width, minimum=32)
    s = require_int("supersample", supersample, minimum=1)
    require_positive("cell", cell)
    if not gaps or not shapes:
        raise InputError("gaps and shapes must not be empty")
    for g in gaps:
        require_positive("gaps", g)
    for b in background:
        require_nonnegative("background", b)
    rng = np.random.default_rng(seed)
    bx = (background[1] - background[0]) / width
    by = 0.25 * (background[1] - background[0]) / height
    a = background[0]
    col = width / len(gaps)
    occ = []
    for k, gap in enumerate(gaps):
        cx = col * (k + 0.5) + rng.uniform(-0.5, 0.5)
        cy = height / 2 + rng.uniform(-0.5, 0.5)
        r = min(col * 0.32, height * 0.38) * rng.uniform(0.9, 1.0)
        occ.append(Occluder(_shape(shapes[k % len(shapes)], cx, cy, r, rng),
                            float(a + bx * cx + by * cy + gap)))
    occ.sort(key=lambda o: -o.disparity)
    pad = max(gaps) + background[1] + 4 * cell
    bg_tex = _texture(rng, height, width, cell, 90.0, 55.0, pad)
    textures = []
    for _ in occ:  # each object brighter or darker than the background on average
        mean = 90.0 + rng.choice([-1.0, 1.0]) * rng.uniform(45.0, 60.0)
        textures.append(_texture(rng, height, width, cell, mean, 30.0, pad))
    off = (np.arange(s) + 0.5) / s - 0.5
    ys = (np.arange(height)[:, None] + off[None, :]).reshape(-1)
    xs = (np.arange(width)[:, None] + off[None, :]).reshape(-1)
    yy, xx = np.meshgrid(ys, xs, indexing="ij")  # (H s, W s)

    def view(right: bool) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
        val = np.full(xx.shape, np.nan)
        layer = np.full(xx.shape, len(occ), dtype=np.intp)
        for k, (o, tex) in enumerate(zip(occ, textures, strict=True)):
            xl = xx + o.disparity if right else xx
            hit = (layer == len(occ)) & o.contains(xl, yy)
            val[hit] = _sample(tex, xl[hit], yy[hit])
            layer[hit] = k
        rest = layer == len(occ)
        xl = (xx + a + by * yy) / (1 - bx) if right else xx
        val[rest] = _sample(bg_tex, xl[rest], yy[rest])
        return val, layer

    def pixels(v: NDArray[np.float64]) -> NDArray[np.float64]:
        return v.reshape(height, s, width, s).mean(axis=(1, 3))

    def mixed(layer: NDArray[np.intp]) -> NDArray[np.bool_]:
        lay = layer.reshape(height, s, width, s)
        return np.asarray((lay.min(axis=(1, 3)) != lay.max(axis=(1, 3))), dtype=bool)

    lv, ll = view(False)
    rv, rl = view(True)
    yc, xc = np.mgrid[0:height, 0:width].astype(float)
    disp = a + bx * xc + by * yc
    front = np.full(xc.shape, len(occ), dtype=np.intp)
    for k, o in enumerate(occ):
        here = (front == len(occ)) & o.contains(xc, yc)
        disp[here] = o.disparity
        front[here] = k
    occluded = np.zeros(xc.shape, dtype=bool)
    for k, o in enumerate(occ):  # hidden when a nearer occluder covers the right position
        xr = xc - disp
        occluded |= (front > k) & o.contains(xr + o.disparity, yc)
    def to8(v: NDArray[np.float64]) -> NDArray[np.uint8]:
        return np.clip(np.rint(pixels(v)), 0, 255).astype(np.uint8)

    return OccluderPair(left=to8(lv), right=to8(rv), disparity=disp, occluded=occluded,
                        mixed_left=mixed(ll), mixed_right=mixed(rl), occluders=tuple(occ),
                        background=(float(a), float(bx), float(by)))
