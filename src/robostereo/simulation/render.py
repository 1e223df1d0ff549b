"""Rendering by ray casting: the 7-bit grey image with its exact depth and labels.

:func:`render` casts ``s x s`` rays per pixel (:func:`sample_offsets`) from a pinhole
:class:`~robostereo.geometry.camera.Camera` at a :class:`~robostereo.geometry.poses.Pose` into a
:class:`~robostereo.simulation.scenes.Scene`, shades the nearest hits, blurs, adds
sensor noise and quantises; the :class:`Rendering` holds the image together with the
depth and the primitive hit at every pixel centre.  :func:`true_disparity` turns a
depth map into the disparity of a rectified pair.

The camera conventions are those of :mod:`robostereo.geometry.camera`: pixel
``(row i, column j)`` has its centre at ``x = j, y = i`` and a world point ``P`` has
camera coordinates ``R.T @ (P - position)`` with ``R = pose.rotation``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robostereo.errors import InputError, require_finite, require_nonnegative, require_positive
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3, Pose
from robostereo.simulation.primitives import Primitive
from robostereo.simulation.scenes import Scene

__all__ = [
    "Rendering",
    "render",
    "sample_offsets",
    "true_disparity",
]

_Arr = NDArray[np.float64]


@dataclass(frozen=True)
class Rendering:
    """A rendered image with its ground truth.

    Attributes
    ----------
    image : ndarray of uint8, shape (H, W)
        Grey levels ``0 .. camera.grey_levels - 1``.
    depth : ndarray of float64, shape (H, W)
        Depth along the optical axis (mm) of the surface hit by the ray through each
        pixel centre; ``inf`` where the ray hits nothing.
    labels : ndarray of int32, shape (H, W)
        Index in ``scene.primitives`` of the primitive hit by the pixel-centre ray,
        -1 for none.
    intensity : ndarray of float64, shape (H, W)
        The noise-free, unquantised grey level (after supersampling and blur).
    """

    image: NDArray[np.uint8]
    depth: _Arr
    labels: NDArray[np.int32]
    intensity: _Arr


def sample_offsets(supersample: int) -> _Arr:
    """Sub-pixel offsets of the ``s x s`` rays cast per pixel, shape ``(s*s, 2)``.

    The rays form a rotated ("n-rooks") grid: their ``s*s`` x offsets are all
    distinct and evenly spaced, and so are their y offsets, so a vertical or a
    horizontal edge is located to ``1 / s**2`` of a pixel rather than ``1 / s``.
    For odd `s` one ray goes through the pixel centre.

    Examples
    --------
    >>> sample_offsets(2)
    array([[-0.375, -0.375],
           [-0.125,  0.125],
           [ 0.125, -0.125],
           [ 0.375,  0.375]])
    >>> sample_offsets(1)
    array([[0., 0.]])
    """
    s = int(supersample)
    a, b = np.meshgrid(np.arange(s), np.arange(s), indexing="ij")
    a, b = a.ravel(), b.ravel()
    n = s * s
    ox = (a * s + b + 0.5) / n - 0.5
    oy = (b * s + a + 0.5) / n - 0.5
    return np.column_stack([ox, oy])


def _window(prim: Primitive, camera: Camera, pose: Pose) -> tuple[slice, slice]:
    """Pixel rows and columns whose rays may hit `prim` (a conservative box)."""
    full = (slice(0, camera.height), slice(0, camera.width))
    bounds = prim.bounds()
    if bounds is None:
        return full
    (x0, y0, z0), (x1, y1, z1) = bounds
    corners = np.array(
        [[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)], dtype=float
    )
    uv, depth = camera.project(corners, pose)
    if np.any(depth <= 1e-6):
        return full
    c0 = max(math.floor(uv[:, 0].min() - 0.5) - 1, 0)
    c1 = min(math.ceil(uv[:, 0].max() + 0.5) + 2, camera.width)
    r0 = max(math.floor(uv[:, 1].min() - 0.5) - 1, 0)
    r1 = min(math.ceil(uv[:, 1].max() + 0.5) + 2, camera.height)
    if c1 <= c0 or r1 <= r0:
        return slice(0, 0), slice(0, 0)
    return slice(r0, r1), slice(c0, c1)


@functools.lru_cache(maxsize=4)
def _undistorted_grid(camera: Camera, offsets_bytes: bytes) -> _Arr:
    """Undistorted normalised coordinates of every ray, shape (S, H, W, 2) (cached)."""
    offsets = np.frombuffer(offsets_bytes, dtype=np.float64).reshape(-1, 2)
    w, h = camera.width, camera.height
    cx, cy = camera.principal_point
    x = np.arange(w)[None, None, :] + offsets[:, 0, None, None]
    y = np.arange(h)[None, :, None] + offsets[:, 1, None, None]
    shape = (len(offsets), h, w)
    d = np.stack([np.broadcast_to((x - cx) / camera.fx, shape),
                  np.broadcast_to((y - cy) / camera.fy, shape)], axis=-1)
    out = camera.undistort(d, iterations=10)  # contraction ~3 k1 r^2: ample
    out.setflags(write=False)
    return out


def _cast(
    scene: Scene, camera: Camera, pose: Pose, offsets: _Arr, layer: int
) -> tuple[_Arr, NDArray[np.int32], _Arr]:
    """Cast the rays of one offset, ``offsets[layer]``, through every pixel.

    Returns the nearest t, label and radiance, each of shape (1, H, W).
    """
    rays = offsets[layer:layer + 1]
    w, h = camera.width, camera.height
    k_inv = np.linalg.inv(camera.K)
    r = pose.rotation
    o = pose.position
    x = np.arange(w)[None, None, :] + rays[:, 0, None, None]
    y = np.arange(h)[None, :, None] + rays[:, 1, None, None]
    # camera-frame direction K^-1 (x, y, 1); K's last row is (0, 0, 1), so its z is 1
    u = k_inv[0, 0] * x + k_inv[0, 1] * y + k_inv[0, 2]
    v = k_inv[1, 0] * x + k_inv[1, 1] * y + k_inv[1, 2]
    shape = (1, h, w)
    if camera.distortion:  # the ray of a distorted pixel: undistort its normalised position
        n = _undistorted_grid(camera, offsets.tobytes())[layer:layer + 1]
        u, v = n[..., 0], n[..., 1]
    # world direction R @ (u, v, 1): its camera-z component is 1, so t is the depth
    dx = np.broadcast_to(r[0, 0] * u + r[0, 1] * v + r[0, 2], shape)
    dy = np.broadcast_to(r[1, 0] * u + r[1, 1] * v + r[1, 2], shape)
    dz = np.broadcast_to(r[2, 0] * u + r[2, 1] * v + r[2, 2], shape)
    t_best = np.full(shape, np.inf)
    labels = np.full(shape, -1, dtype=np.int32)
    radiance = np.full(shape, scene.background)
    light = np.asarray(scene.light_direction)
    for k, prim in enumerate(scene.primitives):
        rows, cols = _window(prim, camera, pose)
        if rows.stop - rows.start <= 0 or cols.stop - cols.start <= 0:
            continue
        wdx, wdy, wdz = dx[:, rows, cols], dy[:, rows, cols], dz[:, rows, cols]
        t, normal = prim.hit(o, wdx, wdy, wdz)
        tb = t_best[:, rows, cols]
        closer = t < tb
        if not closer.any():
            continue
        tc = t[closer]
        tb[closer] = tc
        labels[:, rows, cols][closer] = k
        sdx, sdy, sdz = wdx[closer], wdy[closer], wdz[closer]
        nx, ny, nz = (np.broadcast_to(np.asarray(n, dtype=float), t.shape)[closer] for n in normal)
        facing = np.where(nx * sdx + ny * sdy + nz * sdz > 0, -1.0, 1.0)
        cos = facing * (nx * light[0] + ny * light[1] + nz * light[2])
        albedo = prim.albedo_at(o[0] + tc * sdx, o[1] + tc * sdy)
        radiance[:, rows, cols][closer] = albedo * (
            scene.ambient + scene.light_intensity * np.maximum(cos, 0.0)
        )
    return t_best, labels, radiance


def render(
    scene: Scene,
    camera: Camera,
    pose: Pose,
    *,
    supersample: int = 3,
    blur_sigma_px: float = 0.6,
    noise_sigma: float = 0.0,
    rng: np.random.Generator | None = None,
    vignetting: float = 0.0,
) -> Rendering:
    """Render what `camera` at `pose` sees of `scene`, with depth and labels.

    Parameters
    ----------
    scene : Scene
    camera : Camera
        Pinhole camera; its ``grey_levels`` (at most 256) set the quantisation.
    pose : Pose
        Camera pose (optical centre and yaw).
    supersample : int
        ``s``: ``s x s`` rays per pixel on a rotated grid (:func:`sample_offsets`),
        averaged (a box pixel filter).
    blur_sigma_px : float
        Standard deviation of a Gaussian lens blur in pixels (0 for none).
    noise_sigma : float
        Standard deviation of additive Gaussian sensor noise, grey levels
        (0 for none; needs `rng`).
    rng : numpy.random.Generator or None
        Source of the sensor noise.
    vignetting : float
        Relative fall-off of the light towards the image corners, in ``[0, 1)``: the
        irradiance is multiplied by ``1 - vignetting * (r / r_corner)^2`` (0 for none).

    Other real-camera effects: lens distortion is the camera's
    (:attr:`robostereo.geometry.camera.Camera.distortion`), defocus is `blur_sigma_px`, surface
    texture a :class:`NoiseTexture` on the table or on a :class:`Box`.

    Returns
    -------
    Rendering
        ``image`` (H, W) uint8, ``depth`` (H, W) float64 (mm, ``inf`` for no hit),
        ``labels`` (H, W) int32 (-1 for no hit), ``intensity`` (H, W) float64.

    Notes
    -----
    1. Cast ``s*s`` rays per pixel from the optical centre; ray directions are
       ``R @ K^-1 (x, y, 1)`` so the ray parameter is the depth.  Each primitive is
       intersected only by the rays inside the image box its bounding box projects
       to; the nearest hit in front of the camera wins.
    2. Shade hits as Lambertian: ``albedo * (ambient + I * max(0, n . l))`` with the
       normal turned towards the camera (no shadows); misses get ``background``.
    3. Average the rays of each pixel, scale by ``grey_levels - 1``.
    4. Blur with a Gaussian of `blur_sigma_px` (borders reflected).
    5. Add ``N(0, noise_sigma^2)`` noise from `rng`, round, clip to the grey range.
    6. Depth and labels come from the single ray through each pixel centre (the
       centre ray of the grid when ``s`` is odd, an extra cast otherwise).

    References
    ----------
    Kim (1989), the thesis, 4.1 (the camera and the 0..127 grey levels of the XGS
    system).

    Examples
    --------
    >>> from robostereo.geometry.camera import SEED_CAMERA
    >>> from robostereo.simulation import TablePlane
    >>> scene = Scene((TablePlane(z=0.0, albedo=0.5),), light_direction=(0, 0, 1))
    >>> r = render(scene, SEED_CAMERA, Pose(0.0, 0.0, 1000.0), supersample=1)
    >>> r.image.shape, int(r.image[0, 0]), float(r.depth[240, 254])
    ((481, 509), 60, 1000.0)
    """
    if not isinstance(scene, Scene):
        raise InputError(f"scene must be a Scene, got {type(scene).__name__}")
    if not isinstance(camera, Camera):
        raise InputError(f"camera must be a Camera, got {type(camera).__name__}")
    if not isinstance(pose, Pose | SE3):
        raise InputError(f"pose must be a Pose or an SE3, got {type(pose).__name__}")
    if isinstance(supersample, bool) or int(supersample) != supersample or supersample < 1:
        raise InputError(f"supersample must be an integer >= 1, got {supersample}")
    supersample = int(supersample)
    require_nonnegative("blur_sigma_px", blur_sigma_px)
    require_nonnegative("noise_sigma", noise_sigma)
    require_finite("vignetting", vignetting)
    if not 0.0 <= vignetting < 1.0:
        raise InputError(f"vignetting must be in [0, 1), got {vignetting}")
    if noise_sigma > 0 and not isinstance(rng, np.random.Generator):
        raise InputError("rng must be a numpy.random.Generator when noise_sigma > 0")
    levels = camera.grey_levels
    if not 2 <= levels <= 256:
        raise InputError(f"camera.grey_levels must be in [2, 256] for uint8, got {levels}")

    offsets = sample_offsets(supersample)
    # one layer of rays (one offset, every pixel) at a time: the temporaries stay the size
    # of an image rather than s*s images, and the sum runs in the order a mean would
    centre = (supersample * supersample) // 2 if supersample % 2 == 1 else None
    total = np.zeros((camera.height, camera.width))
    for k in range(len(offsets)):
        t, labels, radiance = _cast(scene, camera, pose, offsets, k)
        total += np.clip(radiance[0], 0.0, 1.0)
        if k == centre:
            depth, label_map = t[0], labels[0]
    if centre is None:
        t0, l0, _ = _cast(scene, camera, pose, np.zeros((1, 2)), 0)
        depth, label_map = t0[0], l0[0]
    intensity = total / len(offsets) * (levels - 1)
    if vignetting > 0:
        cx, cy = camera.principal_point
        xs = (np.arange(camera.width) - cx)[None, :]
        ys = (np.arange(camera.height) - cy)[:, None]
        r2 = xs * xs + ys * ys
        intensity = intensity * (1.0 - vignetting * r2 / r2.max())
    if blur_sigma_px > 0:
        radius = max(1, math.ceil(4.0 * blur_sigma_px))
        intensity = cv2.GaussianBlur(
            intensity,
            (2 * radius + 1, 2 * radius + 1),
            sigmaX=blur_sigma_px,
            sigmaY=blur_sigma_px,
            borderType=cv2.BORDER_REFLECT_101,
        )
    noisy = intensity
    if noise_sigma > 0:
        assert rng is not None
        noisy = intensity + rng.normal(0.0, noise_sigma, intensity.shape)
    image = np.clip(np.rint(noisy), 0, levels - 1).astype(np.uint8)
    return Rendering(
        image=image,
        depth=np.ascontiguousarray(depth),
        labels=np.ascontiguousarray(label_map),
        intensity=intensity,
    )


def true_disparity(depth: ArrayLike, camera: Camera, baseline_mm: float) -> _Arr:
    """Ground-truth disparity ``d = fx * D / depth`` (pixels) of a rectified pair.

    For a left image rendered at the viewpoint ``-D/2`` along the camera's x axis
    (the baseline, ``phi = alpha``) and the right one at ``+D/2``, the point seen at
    left pixel ``(x, y)`` is at ``x - d`` in the right image, ``d = x_left - x_right``.
    ``inf`` depth (no surface) gives 0.

    Parameters
    ----------
    depth : array_like, shape (H, W)
        Depth map of the left view (:attr:`Rendering.depth`), millimetres.
    camera : Camera
    baseline_mm : float
        Baseline ``D``, millimetres.

    Returns
    -------
    ndarray, shape (H, W)

    References
    ----------
    Kim (1989), the thesis, eq. (8) as corrected in the thesis notes:
    ``z = D s / (x_l - x_r)``.

    Examples
    --------
    >>> from robostereo.geometry.camera import SEED_CAMERA
    >>> float(true_disparity([[1000.0]], SEED_CAMERA, 20.0)[0, 0].round(3))
    29.07
    """
    require_positive("baseline_mm", baseline_mm)
    z = np.asarray(depth, dtype=float)
    with np.errstate(divide="ignore"):
        return camera.fx * baseline_mm / z
