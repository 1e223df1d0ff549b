"""N-view test captures of the tests' own, unlike the simulator's scenes, with their truth.

A textured box (60 x 90 x 40 mm, yawed 20 deg) stands on a textured ground; a 640 x 480
camera (fx = 800 px, 8-bit grey, radial distortion ``k1`` recorded in its
:class:`~robostereo.geometry.camera.Camera`, as a calibration would give it) looks at the
box's top centre from `distance_mm`, optionally tilted off vertical, and is moved through a
pattern of viewpoints (:func:`robostereo.robot.views.viewpoints.view_offsets`: a line or a
cross).  Each view is rendered with the project's ray caster
(:func:`robostereo.simulation.render`) with defocus blur and sensor noise.  What it varies,
as a real arm and DTU's captures do and the simulator's scenes do not:

* the texture (:data:`TEXTURES`): fine or coarse smooth noise, stripes, or a printed sheet
  of blobs on the ground;
* the distance, 300-1000 mm, and the lens's ``k1`` in ``[-0.1, 0]``;
* the arm's path: each viewpoint off the ideal pattern by `jitter_deg` (a rotation about a
  random axis) and `jitter_mm` (a move in a random direction), the capture recording the
  pose the arm went to; and the arm's error: the true pose off the recorded one by
  `error_deg` and `error_mm` (the capture records the nominal pose, the image shows the
  true one);
* turns of the views about their optical axes, spread evenly over ``[-turn/2, +turn/2]``
  along the pattern (the outer views `turn_deg` apart), and views aimed at the box
  (``aim``: converging, as on an arc).

:func:`render_views` returns the :class:`~robostereo.robot.views.viewpoints.ViewsCapture`
and a :class:`ViewsTruth` to score located world points with: the distance of a point to
the nearest true surface (box faces and ground), the true depth along a ray, samples of the
box's top outline, and which points every view sees.  Deterministic per seed; a 5-view
capture renders in 2-4 s of CPU.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import gaussian_filter
from scipy.spatial.transform import Rotation

from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3
from robostereo.robot.views.viewpoints import ViewsCapture, view_offsets
from robostereo.simulation import Box, ImagePlane, NoiseTexture, Rendering, Scene, TablePlane
from robostereo.simulation import render as ray_cast

WIDTH, HEIGHT = 640, 480
FOCAL_PX = 800.0
BOX_SIZE = (60.0, 90.0, 40.0)
"""The box's extent along its own x, y and its height, mm."""
BOX_YAW_DEG = 20.0
TEXTURES = ("noise", "coarse", "stripes", "print")
"""``noise``: smooth noise of 2 mm cells on box and ground; ``coarse``: of 8 mm cells;
``stripes``: oblique stripes about 22 mm apart on both; ``print``: a sheet printed with
blobs (1 mm pixels) 0.5 mm above the ground, the box with fine noise."""
RENDER = {"supersample": 3, "blur_sigma_px": 0.7, "noise_sigma": 1.5}
PRINT_Z = 0.5


@dataclass(frozen=True)
class RenderSpec:
    """What to render: the scene, the lens, the path and the pattern.

    Attributes
    ----------
    texture : str
        One of :data:`TEXTURES`.
    distance_mm : float
        From the mid viewpoint's optical centre to the box's top centre.
    k1 : float
        Radial distortion of the lens (recorded in the capture's camera).
    jitter_deg, jitter_mm : float
        Each viewpoint off the ideal pattern (recorded: the arm went there and says so).
    error_deg, error_mm : float
        Each view's true pose off the recorded one (not recorded: the arm's error).
    turn_deg : float
        The outer views' turns about their optical axes differ by this; the others between.
    tilt_deg : float
        The mid view's optical axis off vertical (towards world +x).
    aim : bool
        Turn every view to look at the box's top centre (else they keep the mid view's
        orientation: a pure translation, the thesis's motion).
    pattern : {'line', 'cross'}
    count : int
    span_mm : float
        End to end of the pattern (of each arm of a cross).
    seed : int
    """

    texture: str = "noise"
    distance_mm: float = 400.0
    k1: float = -0.1
    jitter_deg: float = 1.0
    jitter_mm: float = 2.0
    error_deg: float = 0.0
    error_mm: float = 0.0
    turn_deg: float = 0.0
    tilt_deg: float = 0.0
    aim: bool = False
    pattern: str = "line"
    count: int = 5
    span_mm: float = 80.0
    seed: int = 0


@dataclass(frozen=True, eq=False)
class ViewsTruth:
    """The truth of a rendered capture.

    Attributes
    ----------
    spec : RenderSpec
    scene : Scene
    box : Box
    camera : Camera
        The true camera (the capture's: the lens is known exactly).
    true_poses : tuple of SE3
        ``T_world_camera`` each view was rendered from.
    recorded_poses : tuple of SE3
        What the capture holds.
    renderings : tuple of Rendering
        Depth (along each true optical axis) and labels at every pixel centre.
    """

    spec: RenderSpec
    scene: Scene
    box: Box
    camera: Camera
    true_poses: tuple[SE3, ...]
    recorded_poses: tuple[SE3, ...]
    renderings: tuple[Rendering, ...] = field(repr=False)

    def box_distance(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Distance of world points ``(M, 3)`` to the box's surface, mm, shape ``(M,)``."""
        b = self.box
        c, s = math.cos(b.yaw), math.sin(b.yaw)
        p = np.atleast_2d(np.asarray(points, dtype=float))
        dx, dy = p[:, 0] - b.center[0], p[:, 1] - b.center[1]
        half = np.array([b.size[0] / 2, b.size[1] / 2, b.size[2] / 2])
        local = np.column_stack([c * dx + s * dy, -s * dx + c * dy,
                                 p[:, 2] - b.z_base - half[2]])
        q = np.abs(local) - half
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
        inside = -q.max(axis=1)  # inside: the distance to the nearest face
        return np.where(inside < 0, outside, inside)

    def ground_distance(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Distance of world points ``(M, 3)`` to the ground (and print), mm."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        d = np.abs(p[:, 2])
        for prim in self.scene.primitives:
            if isinstance(prim, ImagePlane):
                (x0, y0, _), (x1, y1, _) = prim.bounds()
                gx = np.maximum(np.maximum(x0 - p[:, 0], p[:, 0] - x1), 0.0)
                gy = np.maximum(np.maximum(y0 - p[:, 1], p[:, 1] - y1), 0.0)
                d = np.minimum(d, np.sqrt(gx**2 + gy**2 + (p[:, 2] - prim.z) ** 2))
        return d

    def surface_distance(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """The 3-D error of world points ``(M, 3)``: distance to the nearest true surface
        (box faces, ground), mm, shape ``(M,)``."""
        return np.minimum(self.box_distance(points), self.ground_distance(points))

    def near_box(self, points: NDArray[np.float64], margin_mm: float = 10.0
                 ) -> NDArray[np.bool_]:
        """Points within `margin_mm` of the box and more than 2 mm above the ground."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        return (self.box_distance(p) <= margin_mm) & (p[:, 2] > 2.0)

    def ray_depth(self, origin: NDArray[np.float64], axis: NDArray[np.float64],
                  points: NDArray[np.float64]) -> NDArray[np.float64]:
        """True depth along ``axis`` of the surface hit by the rays from `origin` through
        `points` ``(M, 3)``, mm (``inf`` for none).

        The rays are cast into the true scene: for a located point, ``origin`` and ``axis``
        are its reference camera's (recorded) centre and optical axis, and the located
        depth minus this is its depth error.
        """
        o = np.asarray(origin, dtype=float)
        d = np.atleast_2d(np.asarray(points, dtype=float)) - o
        d = d / (d @ np.asarray(axis, dtype=float))[:, None]  # unit depth along the axis
        best = np.full(len(d), np.inf)
        for prim in self.scene.primitives:
            t, _ = prim.hit(o, d[:, 0], d[:, 1], d[:, 2])
            best = np.minimum(best, t)
        return best

    def pixel_depth_error(self, origin: NDArray[np.float64], rotation: NDArray[np.float64],
                          focal_px: float, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """``|depth error|`` of `points` ``(M, 3)`` at their pixel, mm: the least over the
        ray from `origin` through each point and the eight rays 1 px round it of the
        located depth minus the true depth (``rotation`` ``(3, 3)``: the reference
        camera's axes as columns).

        An edge point lies between pixels; at a depth step (a silhouette) the depth
        along its one exact ray is either side's, so the error is taken at the pixel,
        as ``robostereo evaluate`` takes it from a depth map (its 3 x 3 neighbourhood).
        """
        o = np.asarray(origin, dtype=float)
        R = np.asarray(rotation, dtype=float)
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        depth = (pts - o) @ R[:, 2]
        px = depth / float(focal_px)  # mm a pixel at each point's depth
        best = np.abs(depth - self.ray_depth(o, R[:, 2], pts))
        for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1), (1, -1), (-1, 1)):
            q = pts + (dx * R[:, 0] + dy * R[:, 1])[None, :] * px[:, None]
            best = np.minimum(best, np.abs(depth - self.ray_depth(o, R[:, 2], q)))
        return best

    def depth_errors(self, capture: ViewsCapture, located: Any) -> NDArray[np.float64]:
        """``|depth error|`` of each point of `located` (a ``LocatedViews``), mm: along
        its reference camera's recorded axis, at its pixel (:meth:`pixel_depth_error`,
        as the simulator's ``views_depth_errors`` takes its 3 x 3 pixels)."""
        err = np.zeros(len(located))
        f = float(capture.camera.K[0, 0])
        for r in np.unique(located.reference):
            k = located.reference == r
            pose = capture.poses[int(r)]
            err[k] = self.pixel_depth_error(pose.translation, pose.rotation, f,
                                            located.world[k])
        return err

    def outline(self, step_mm: float = 1.0) -> NDArray[np.float64]:
        """Samples of the box's top outline every `step_mm`, shape ``(K, 3)``."""
        co = self.box.corners()
        top = co[co[:, 2] == co[:, 2].max()]
        ang = np.arctan2(top[:, 1] - top[:, 1].mean(), top[:, 0] - top[:, 0].mean())
        tc = top[np.argsort(ang)]
        pts = []
        for i in range(4):
            a, b = tc[i], tc[(i + 1) % 4]
            k = max(int(np.ceil(np.linalg.norm(b - a) / step_mm)), 1)
            pts.append(a + (b - a) * (np.arange(k) / k)[:, None])
        return np.vstack(pts)

    def seen_by(self, points: NDArray[np.float64], *, tolerance_mm: float = 1.5
                ) -> NDArray[np.bool_]:
        """Which views see each world point: ``(M, N)`` bool.

        Seen: the point projects (true pose, true lens) into the image and the rendered
        depth at the nearest pixel is within `tolerance_mm` (plus a pixel's worth of
        depth change) of the point's.
        """
        p = np.atleast_2d(np.asarray(points, dtype=float))
        out = np.zeros((len(p), len(self.true_poses)), bool)
        for k, (pose, r) in enumerate(zip(self.true_poses, self.renderings, strict=True)):
            uv, z = self.camera.project(p, pose)
            col, row = np.rint(uv[:, 0]).astype(np.intp), np.rint(uv[:, 1]).astype(np.intp)
            ok = (z > 0) & (col >= 0) & (col < WIDTH) & (row >= 0) & (row < HEIGHT)
            seen = np.zeros(len(p), bool)
            i = np.nonzero(ok)[0]
            lo = np.full(len(i), np.inf)
            for dr in (-1, 0, 1):  # a pixel's worth of slope and edge
                for dc in (-1, 0, 1):
                    rr = np.clip(row[i] + dr, 0, HEIGHT - 1)
                    cc = np.clip(col[i] + dc, 0, WIDTH - 1)
                    lo = np.minimum(lo, np.abs(r.depth[rr, cc] - z[i]))
            seen[i] = lo <= tolerance_mm
            out[:, k] = seen
        return out


def camera(k1: float = -0.1) -> Camera:
    """The renders' camera: 640 x 480, fx = fy = 800 px, 8-bit, radial ``k1``."""
    dist = (float(k1), 0.0, 0.0, 0.0) if k1 != 0 else ()
    return Camera(focal_length_mm=4.0, pixel_pitch_mm=(0.005, 0.005),
                  image_size=(WIDTH, HEIGHT), grey_levels=256, distortion=dist)


def _texture(kind: str, rng: np.random.Generator, cell_mm: float) -> NoiseTexture:
    if kind == "stripes":
        i, j = np.mgrid[0:64, 0:64]
        phase = 2 * np.pi * (3 * i + 5 * j) / 64  # a whole number of periods: seamless
        v = np.tanh(8.0 * np.sin(phase))  # near-square: sharp edges
        return NoiseTexture(v / np.abs(v).max(), cell_mm=2.0, amplitude=0.45)
    return NoiseTexture.from_rng(rng, size=128, cell_mm=cell_mm, amplitude=0.45,
                                 smooth_cells=1.0)


def scene(spec: RenderSpec) -> Scene:
    """The textured box on the textured ground for `spec` (its texture and seed)."""
    if spec.texture not in TEXTURES:
        raise ValueError(f"texture must be one of {TEXTURES}, got {spec.texture!r}")
    rng = np.random.default_rng([spec.seed, 34])
    cell = 8.0 if spec.texture == "coarse" else 2.0
    kind = "noise" if spec.texture == "print" else spec.texture
    box = Box(center=(0.0, 0.0), z_base=0.0, size=BOX_SIZE, yaw=math.radians(BOX_YAW_DEG),
              albedo=0.7, texture=_texture(kind, rng, cell))
    prims: list = [TablePlane(z=0.0, albedo=0.5, texture=_texture(kind, rng, cell))]
    if spec.texture == "print":
        half = 0.9 * spec.distance_mm  # wider than every view
        n = int(2 * half)
        blobs = gaussian_filter(rng.standard_normal((n, n)), 3.0) > 0
        prims.append(ImagePlane(origin=(-half, half), image=0.15 + 0.6 * blobs, mm_per_px=1.0,
                                z=PRINT_Z, margin_mm=5.0, margin_albedo=0.5))
    prims.append(box)
    return Scene(tuple(prims), light_direction=(0.3, -0.2, 1.0))


def _unit(rng: np.random.Generator) -> NDArray[np.float64]:
    v = rng.standard_normal(3)
    return v / np.linalg.norm(v)


def _moved(pose: SE3, rng: np.random.Generator, deg: float, mm: float) -> SE3:
    """`pose` turned by `deg` about a random axis and moved `mm` in a random direction
    (both in the camera's frame)."""
    delta = SE3.from_rotvec(mm * _unit(rng), math.radians(deg) * _unit(rng))
    return pose @ delta


def nominal_poses(spec: RenderSpec) -> list[SE3]:
    """The ideal pattern's camera poses (before jitter and error)."""
    target = np.array([0.0, 0.0, BOX_SIZE[2]])
    t = math.radians(spec.tilt_deg)
    eye = target + spec.distance_mm * np.array([math.sin(t), 0.0, math.cos(t)])
    mid = SE3.look_at(eye, target, up=(0.0, 1.0, 0.0))
    offsets = view_offsets(spec.pattern, spec.count, spec.span_mm)  # type: ignore[arg-type]
    out = []
    for k, o in enumerate(offsets):
        c = mid.translation + mid.rotation @ o
        if spec.aim:
            pose = SE3.look_at(c, target, up=tuple(-mid.rotation[:, 1]))
        else:
            pose = SE3(mid.rotation, c)
        frac = k / (spec.count - 1) - 0.5 if spec.count > 1 else 0.0
        roll = SE3.from_rotvec([0.0, 0.0, 0.0], [0.0, 0.0, math.radians(spec.turn_deg) * frac])
        out.append(pose @ roll)
    return out


def render_views(spec: RenderSpec = RenderSpec()) -> tuple[ViewsCapture, ViewsTruth]:
    """Render the capture `spec` describes; its capture and its truth.

    Returns
    -------
    capture : ViewsCapture
        8-bit images, the camera (with `k1`), the recorded poses and a depth range from
        the rendered depths (their extremes, 10 % wider).
    truth : ViewsTruth

    Examples
    --------
    >>> cap, truth = render_views(RenderSpec(count=2))
    >>> len(cap), cap.camera.distortion[0]
    (2, -0.1)
    """
    rng = np.random.default_rng([spec.seed, 34, spec.count, round(spec.span_mm)])
    sc = scene(spec)
    cam = camera(spec.k1)
    recorded, true = [], []
    for pose in nominal_poses(spec):
        went = _moved(pose, rng, spec.jitter_deg, spec.jitter_mm)
        recorded.append(went)
        true.append(_moved(went, rng, spec.error_deg, spec.error_mm))
    renders = [ray_cast(sc, cam, p, rng=rng, **RENDER) for p in true]  # type: ignore[arg-type]
    depths = np.concatenate([r.depth[np.isfinite(r.depth)] for r in renders])
    near, far = float(depths.min()), float(depths.max())
    pad = 0.1 * (far - near)
    images = []
    for r in renders:
        img = np.array(r.image, copy=True)
        img.setflags(write=False)
        images.append(img)
    cap = ViewsCapture(tuple(images), cam, tuple(recorded),
                       depth_range_mm=(max(near - pad, 1.0), far + pad), bit_depth=8,
                       names=tuple(f"view_{k:02d}.png" for k in range(spec.count)),
                       notes={"scene": {"kind": "view_renders", "spec": repr(spec)}})
    box = next(p for p in sc.primitives if isinstance(p, Box))
    truth = ViewsTruth(spec, sc, box, cam, tuple(true), tuple(recorded), tuple(renders))
    return cap, truth


def rotation_deg(a: SE3, b: SE3) -> float:
    """The angle of the rotation between two poses, degrees."""
    return float(np.degrees(Rotation.from_matrix(a.rotation.T @ b.rotation).magnitude()))


def write_with_depth(directory, capture: ViewsCapture, truth: ViewsTruth, *,
                     two_view: bool = False, suffix: str = ".pfm", keys: bool = False,
                     depth_scale: float | None = None):
    """Write `capture` as a capture folder with its true depth maps.

    Two views as a two-view folder (``left.png``, ``right.png``) when `two_view`, else an
    N-view folder.  Each view's rendered depth (along its true optical axis, mm; ``inf``
    where no surface is hit, written as unknown) goes to ``depth/<image stem><suffix>``,
    named by the ``depth_left``/``depth_right`` or per-view ``depth`` keys when `keys`
    (else found by the fallback); `depth_scale` is written as the top-level key.
    """
    from pathlib import Path

    import yaml

    from robostereo.evaluation import write_depth_map
    from robostereo.robot.capture import write_capture
    from robostereo.robot.views.views_folder import write_views_capture

    d = Path(directory)
    if two_view:
        write_capture(d, capture.pair(0, 1))
        stems = ["left", "right"]
    else:
        write_views_capture(d, capture)
        stems = [Path(n).stem for n in capture.names]
    (d / "depth").mkdir()
    scale = 1.0 if depth_scale is None else depth_scale
    for stem, r in zip(stems, truth.renderings, strict=False):
        write_depth_map(d / "depth" / f"{stem}{suffix}", r.depth, scale=scale)
    if keys or depth_scale is not None:
        data = yaml.safe_load((d / "capture.yaml").read_text())
        if keys and two_view:
            data.update({f"depth_{s}": f"depth/{s}{suffix}" for s in stems})
        elif keys:
            for v, stem in zip(data["views"], stems, strict=True):
                v["depth"] = f"depth/{stem}{suffix}"
        if depth_scale is not None:
            data["depth_scale"] = depth_scale
        (d / "capture.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    return d
