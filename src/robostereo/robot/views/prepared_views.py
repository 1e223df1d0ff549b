"""The first stages of the N-view locate: the views prepared, the reference's edge points.

:func:`robostereo.robot.views.locating.locate_views` runs these first:

* :func:`prepare_views`: every view undistorted to the pinhole camera of its own
  intrinsics, on the thesis's 0..127 grey scale, smoothed (figure 3-1), with its
  gradient; the poses as rotations and optical centres;
* :func:`reference_edges`: the reference view's edge points on the pixel grid
  (:func:`~robostereo.robot.views.views_kernels.grid_edges`), each placed on the
  fine gradient's peak (or by the two-step fit beside an opposite edge).

The search along their rays is in :mod:`~robostereo.robot.views.ray_search`.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from robostereo.geometry.poses import as_se3
from robostereo.matcher.grey_levels import smooth, to_grey
from robostereo.robot.views.edge_profiles import two_step_edges, view_blurs
from robostereo.robot.views.viewpoints import ViewsCapture
from robostereo.robot.views.views_kernels import central_gradient, edge_near, grid_edges

__all__ = [
    "PreparedViews",
    "ReferenceEdges",
    "prepare_views",
    "reference_edges",
]

_F = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class PreparedViews:
    """Every view undistorted, smoothed and differentiated.

    Attributes
    ----------
    smoothed : float32 (N, H, W)
        Undistorted grey levels on the thesis's 0..127 scale, smoothed (figure 3-1).
    gx, gy : float32 (N, H, W)
        ``(S(x + 1) - S(x - 1)) / 2`` and the same along y.
    fine_gx, fine_gy : float32 (N, H, W)
        The same of the undistorted grey levels before the thesis's smoothing (blurred
        by a Gaussian of ``edge_blur_px`` if that is above 0), which place the sub-pixel
        edge points (:func:`reference_edges`,
        :func:`~robostereo.robot.views.point_refinement.refine_points`); `gx`, `gy`
        themselves when ``edge_blur_px`` is None.
    K, K_inv : (3, 3)
        The pinhole intrinsics the undistorted images share.
    R : (N, 3, 3)
        Camera-to-world rotations.
    C : (N, 3)
        Optical centres, world mm.
    grey : float32 (N, H, W) or None
        Undistorted grey levels, not smoothed, for the two-step fit (None: no such fit;
        :func:`~robostereo.robot.views.edge_profiles.two_step_edges`).
    blur : (N,) or None
        Each view's blur, px (:meth:`blurs`; -1 until a first edge point needs it).
    opposite_px : float
        Farthest opposite edge of the two-step fit, px.
    """

    smoothed: NDArray[np.float32]
    gx: NDArray[np.float32]
    gy: NDArray[np.float32]
    fine_gx: NDArray[np.float32]
    fine_gy: NDArray[np.float32]
    K: _F
    K_inv: _F
    R: _F
    C: _F
    grey: NDArray[np.float32] | None = None
    blur: _F | None = None
    opposite_px: float = 3.0

    def blurs(self, threshold: float) -> _F:
        """:attr:`blur`, estimated at the first call (edges of `threshold`)."""
        assert self.blur is not None and self.grey is not None
        if self.blur[0] < 0:
            self.blur[:] = view_blurs(self.grey, self.gx, self.gy, threshold)
        return self.blur

    def project(self, world: _F, view: int) -> tuple[_F, _F]:
        """Pinhole pixels ``(M, 2)`` and depths ``(M,)`` of world points in `view`."""
        pc = (world - self.C[view]) @ self.R[view]
        z = pc[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            uv = pc[:, :2] / z[:, None]
        return uv * np.diag(self.K)[:2] + self.K[:2, 2], z


def prepare_views(capture: ViewsCapture, edge_blur_px: float | None = 0.7,
                  opposite_px: float | None = None) -> PreparedViews:
    """Undistort, convert, smooth and differentiate every view (see :class:`PreparedViews`).

    Parameters
    ----------
    capture : ViewsCapture
    edge_blur_px : float or None
        Gaussian sigma (pixels) of the images whose gradient places the sub-pixel edge
        points; 0: the undistorted grey levels as they are; None: the thesis's smoothed
        images, as the search uses.
    opposite_px : float or None
        :attr:`PreparedViews.opposite_px`; None: no two-step fit.

    Notes
    -----
    The thesis's 5 x 5 filter (figure 3-1) spreads an edge's gradient over about +-2 px;
    beside a second edge that close (a face seen nearly edge-on) the peak moves towards
    it; the search needs the smoothing, the sub-pixel position does not: on the simulated
    block the smoothed peak moved 0.119 px beside a 2.2 px strip, the unsmoothed 0.034 px
    (same spread).  A light blur (``ViewsParameters.edge_blur_px``) trades a little back.
    """
    cam = capture.camera
    w, h = cam.image_size
    K = cam.K
    undistort = bool(np.any(np.asarray(cam.dist_coeffs) != 0))
    if undistort:
        u, v = np.meshgrid(np.arange(w, dtype=float), np.arange(h, dtype=float))
        cx, cy = cam.principal_point
        n = np.column_stack([((u - cx) / cam.fx).ravel(), ((v - cy) / cam.fy).ravel()])
        d = cam.distort(n)
        map_x = (d[:, 0] * cam.fx + cx).reshape(h, w).astype(np.float32)
        map_y = (d[:, 1] * cam.fy + cy).reshape(h, w).astype(np.float32)
    n_views = len(capture.images)
    sm, gxs, gys = (np.empty((n_views, h, w), np.float32) for _ in range(3))
    fine = edge_blur_px is not None
    greys = np.empty((n_views, h, w), np.float32) if opposite_px is not None else None
    fxs, fys = (np.empty((n_views, h, w), np.float32) for _ in range(2)) if fine else (gxs, gys)
    for i, img in enumerate(capture.images):
        g = to_grey(img, bit_depth=int(capture.bit_depth))
        if undistort:
            g = cv2.remap(g, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        sm[i] = smooth(g)
        central_gradient(sm[i], gxs[i], gys[i])  # half the central differences
        g = np.asarray(g, np.float32)
        if greys is not None:
            greys[i] = g
        if fine:
            if edge_blur_px > 0:  # type: ignore[operator]
                g = cv2.GaussianBlur(g, (0, 0), float(edge_blur_px),  # type: ignore[arg-type]
                                     borderType=cv2.BORDER_REFLECT_101)
            central_gradient(np.ascontiguousarray(g, np.float32), fxs[i], fys[i])
    poses = [as_se3(p) for p in capture.poses]
    blur = np.full(n_views, -1.0) if opposite_px is not None else None
    return PreparedViews(
        smoothed=sm, gx=gxs, gy=gys, fine_gx=fxs, fine_gy=fys, K=K, K_inv=np.linalg.inv(K),
        R=np.stack([p.rotation for p in poses]),
        C=np.stack([p.translation for p in poses]),
        grey=greys if opposite_px is not None else None, blur=blur,
        opposite_px=float(opposite_px) if opposite_px is not None else 3.0)


@dataclass(frozen=True, eq=False)
class ReferenceEdges:
    """A reference view's edge points.

    Attributes
    ----------
    pixel : (M, 2)
        Sub-pixel ``(x, y)`` in the undistorted reference image.
    grid : int (M, 2)
        The pixel ``(x, y)`` each was found at.
    normal : (M, 2)
        Unit gradient direction (dark to bright).
    peak : (M, 2) or None
        The gradient's peaks, if a two-step fit moved `pixel` (for fits of two views).
    """

    pixel: _F
    grid: NDArray[np.intp]
    normal: _F
    peak: _F | None = None

    def __len__(self) -> int:
        return int(self.pixel.shape[0])

    def subset(self, keep: NDArray[np.bool_]) -> ReferenceEdges:
        return ReferenceEdges(self.pixel[keep], self.grid[keep], self.normal[keep],
                              None if self.peak is None else self.peak[keep])


def reference_edges(views: PreparedViews, ref: int, threshold: float,
                    border: int, lines: int = 2) -> ReferenceEdges:
    """Edge points of view `ref` on the pixel grid (``|grad| >= threshold`` in the
    smoothed image), each placed on the fine gradient's peak (within a pixel, along the
    same grid line; :attr:`PreparedViews.fine_gx`) and averaged along the edge over
    `lines` grid lines either side."""
    rows, cols, sub, axes, gx, gy = grid_edges(views.gx[ref], views.gy[ref],
                                              float(threshold), int(border),
                                              int(lines))
    x = np.where(axes == 0, sub, cols)
    y = np.where(axes == 0, rows, sub)
    mag = np.hypot(gx, gy)
    nx, ny = gx / mag, gy / mag
    if views.fine_gx is not views.gx:
        # the same scan axis as the grid's (the one nearer the normal), a pixel either side
        ex, ey, _, _, found = edge_near(views.fine_gx[ref], views.fine_gy[ref],
                                        x.astype(float), y.astype(float), nx, ny, 1,
                                        float(threshold) / 4.0, int(border), int(lines))
        x = np.where(found, ex, x)
        y = np.where(found, ey, y)
    pixel = peak = np.column_stack([x, y]).astype(float)
    if views.grey is not None and views.blur is not None:
        pixel = two_step_edges(views.grey[ref], pixel, np.column_stack([nx, ny]),
                               lambda: float(views.blurs(threshold)[ref]),
                               reach_px=views.opposite_px,
                               threshold=float(threshold))[0]
    return ReferenceEdges(pixel, np.column_stack([cols, rows]).astype(np.intp),
                          np.column_stack([nx, ny]), peak if pixel is not peak else None)
