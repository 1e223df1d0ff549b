"""The scenes of the thesis's experiments: primitives under a directional light.

:class:`Scene` holds the primitives (:mod:`robostereo.simulation.primitives`,
:mod:`robostereo.simulation.targets`), a directional light and an ambient term;
:func:`seed_block_scene` builds the precision block of the thesis's accuracy test (5.2,
table 5-1) and :func:`hub_pulley_scene` the toothed hub pulley of its effectiveness test
(5.1), each with the truth the experiments compare against (:class:`BlockScene`,
:class:`PulleyScene`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from robostereo.errors import InputError, require_finite, require_nonnegative, require_positive
from robostereo.geometry.poses import Pose
from robostereo.simulation.primitives import Box, Cylinder, Disc, Primitive, TablePlane
from robostereo.simulation.surfaces import NoiseTexture, xy_pair
from robostereo.simulation.targets import Checkerboard, ImagePlane

__all__ = [
    "BlockScene",
    "PulleyScene",
    "Scene",
    "hub_pulley_scene",
    "seed_block_scene",
]


@dataclass(frozen=True)
class Scene:
    """Primitives, a directional light and an ambient term.

    The radiance of a surface point with albedo ``a`` and unit normal ``n``
    (turned towards the camera) is
    ``a * (ambient + light_intensity * max(0, n . l))`` with ``l`` the unit
    direction towards the light; 1.0 maps to the camera's top grey level.
    No shadows are cast.

    Parameters
    ----------
    primitives : tuple
        :class:`TablePlane`, :class:`Disc`, :class:`Cylinder` and :class:`Box`
        objects; the label of a primitive is its index in this tuple.
    light_direction : tuple of float
        Direction towards the light (normalised on construction).
    light_intensity : float
        Directional light strength, ``>= 0``.
    ambient : float
        Ambient light, ``>= 0``.
    background : float
        Radiance of rays that hit nothing, in ``[0, 1]``.
    """

    primitives: tuple[Primitive, ...]
    light_direction: tuple[float, float, float] = (0.3, -0.2, 1.0)
    light_intensity: float = 0.8
    ambient: float = 0.15
    background: float = 0.0

    def __post_init__(self) -> None:
        prims = tuple(self.primitives)
        for p in prims:
            if not isinstance(p, TablePlane | Disc | Cylinder | Box | Checkerboard | ImagePlane):
                raise InputError(
                    "primitives must be TablePlane, Disc, Cylinder, Box, Checkerboard or "
                    "ImagePlane objects, "
                    f"got {type(p).__name__}"
                )
        object.__setattr__(self, "primitives", prims)
        ld = np.asarray(self.light_direction, dtype=float)
        if ld.shape != (3,) or not np.all(np.isfinite(ld)) or np.linalg.norm(ld) == 0:
            raise InputError(
                f"light_direction must be a non-zero (x, y, z), got {self.light_direction}"
            )
        ld = ld / np.linalg.norm(ld)
        object.__setattr__(self, "light_direction", tuple(float(v) for v in ld))
        for name in ("light_intensity", "ambient"):
            require_nonnegative(name, getattr(self, name))
        require_finite("background", self.background)
        if not 0.0 <= self.background <= 1.0:
            raise InputError(f"background must be in [0, 1], got {self.background}")


@dataclass(frozen=True, kw_only=True)
class BlockScene(Scene):
    """The thesis's precision block on a table (see :func:`seed_block_scene`).

    Attributes
    ----------
    top_z : float
        Height of the block's top face, millimetres.
    left_x, right_x : float
        World x of the block's left and right faces, millimetres.
    front_y, back_y : float
        World y of the block's faces at low and high y, millimetres.
    width : float
        ``right_x - left_x``, millimetres.
    view_pose : Pose
        The mid-baseline camera pose of the thesis's view of the block.
    block_label, table_label : int
        Labels of the block and the table in a :class:`Rendering`.
    """

    top_z: float
    left_x: float
    right_x: float
    front_y: float
    back_y: float
    width: float
    view_pose: Pose
    block_label: int = 1
    table_label: int = 0


@dataclass(frozen=True, kw_only=True)
class PulleyScene(Scene):
    """A hub pulley on a table (see :func:`hub_pulley_scene`).

    Attributes
    ----------
    center : tuple of float
        ``(x, y)`` of the pulley's axis, millimetres.
    top_z : float
        Height of the highest face (the hub's top), millimetres.
    outer_radius : float
        Radius of the rim, millimetres.
    view_pose : Pose
        A camera pose centred above the pulley.
    """

    center: tuple[float, float]
    top_z: float
    outer_radius: float
    view_pose: Pose


def seed_block_scene(
    *,
    lift_mm: float = 0.0,
    camera_height_mm: float = 1050.0,
    center_xy: tuple[float, float] = (0.0, 0.0),
    offset_xy: tuple[float, float] = (-43.3, -22.5),
    width_mm: float = 23.6,
    length_mm: float = 80.0,
    height_mm: float = 50.0,
    block_albedo: float = 0.85,
    table_albedo: float = 0.3,
    texture_rng: np.random.Generator | None = None,
) -> BlockScene:
    """The precision rectangular block of the thesis's accuracy test (5.2, table 5-1).

    A block `width_mm` wide along world X and `length_mm` long along Y stands on
    a table at ``z = 0``; its top is at ``height_mm + lift_mm``.  The view pose is
    the mid-baseline camera position at `camera_height_mm` above the table, so the
    block's top is ``camera_height_mm - height_mm - lift_mm`` below the camera
    (1000 mm with the defaults, 920.35 mm with ``lift_mm=79.65``).

    Parameters
    ----------
    lift_mm : float
        Raise of the block's top towards the camera (the thesis: 79.65 mm between the two
        data sets); realised as a taller block.  Must be ``> -height_mm``.
    camera_height_mm : float
        Height of the view pose above the table, millimetres.
    center_xy : tuple of float
        World ``(x, y)`` of the centre of the block's footprint.
    offset_xy : tuple of float
        Position of the block centre relative to the view pose's ``(x, y)``.  The
        default puts the block left of and below the image centre as in table 5-1
        (faces at x = -55.1 and -31.5 mm, epipolar y from about +62 to -17 mm);
        ``(0, 0)`` centres it.
    width_mm, length_mm, height_mm : float
        Block size along X, along Y and height (at ``lift_mm = 0``).
    block_albedo, table_albedo : float
        Reflectances: a bright block on a darker table.
    texture_rng : numpy.random.Generator or None
        If given, the table gets a :class:`NoiseTexture` drawn from it.

    Returns
    -------
    BlockScene
        Label 0 is the table, label 1 the block.

    Notes
    -----
    With the thesis's camera (``fx`` = 1453.5 px) the block is about 34 px wide and,
    with ``fy`` = 1824.8 px, 146 px tall at 1000 mm, crossing 18 rows at a spacing
    of 8 rows.  The thesis reports the second data set *farther* from the camera
    (mean z 1007.6 then 1086.3 mm) although it says the object was lifted; here a
    positive `lift_mm` brings the top nearer, a negative one takes it away.

    References
    ----------
    Kim (1989), the thesis, chapter 5.2 and table 5-1.

    Examples
    --------
    >>> s = seed_block_scene()
    >>> s.top_z, round(s.left_x, 2), round(s.right_x, 2), s.width
    (50.0, -11.8, 11.8, 23.6)
    >>> s.view_pose  # the block's faces at x = -55.1 and -31.5 mm from the view pose
    Pose(x=43.3, y=22.5, z=1050.0, phi=0.0)
    >>> seed_block_scene(lift_mm=79.65).top_z
    129.65
    """
    require_finite("lift_mm", lift_mm)
    require_positive("camera_height_mm", camera_height_mm)
    for name, v in (("width_mm", width_mm), ("length_mm", length_mm), ("height_mm", height_mm)):
        require_positive(name, v)
    if height_mm + lift_mm <= 0:
        raise InputError(f"lift_mm must be > -height_mm = {-height_mm}, got {lift_mm}")
    cx, cy = xy_pair("center_xy", center_xy)
    ox, oy = xy_pair("offset_xy", offset_xy)
    top = height_mm + lift_mm
    if top >= camera_height_mm:
        raise InputError(
            f"camera_height_mm must exceed the block top {top} mm, got {camera_height_mm}"
        )
    texture = None if texture_rng is None else NoiseTexture.from_rng(texture_rng)
    table = TablePlane(z=0.0, albedo=table_albedo, texture=texture)
    block = Box(center=(cx, cy), z_base=0.0, size=(width_mm, length_mm, top), albedo=block_albedo)
    return BlockScene(
        primitives=(table, block),
        top_z=top,
        left_x=cx - width_mm / 2,
        right_x=cx + width_mm / 2,
        front_y=cy - length_mm / 2,
        back_y=cy + length_mm / 2,
        width=width_mm,
        view_pose=Pose(cx - ox, cy - oy, camera_height_mm, 0.0),
    )


def hub_pulley_scene(
    *,
    center_xy: tuple[float, float] = (0.0, 0.0),
    camera_height_mm: float = 1070.0,
    scale: float = 1.0,
    teeth: int = 40,
    table_albedo: float = 0.2,
    texture_rng: np.random.Generator | None = None,
) -> PulleyScene:
    """A toothed hub pulley (the thesis's "gear in an auto part", 5.1) on a table.

    From the outside in (millimetres at ``scale = 1``, all parts concentric with
    `center_xy`, standing on the table at ``z = 0``):

    * `teeth` gear teeth, boxes 8 deep and 7 wide yawed to point radially,
      r 88..96, 45 high;
    * the rim, a tube r 76..88, 45 high, with two dark belt grooves on its top face
      (annuli r 80..82.5 and 84..86.5);
    * the web, an annulus r 24..76 at z = 20 with eight 7-mm lightening holes on
      the r 56 circle (the table shows through), a bright machined ring r 65..69
      and a dark ring r 42..45;
    * the boss, a tube r 24..38, 32 high, with a dark ring r 29..33 on top;
    * the hub, a tube r 10..24, 70 high, whose bore shows the table.

    Parameters
    ----------
    center_xy : tuple of float
        World ``(x, y)`` of the pulley's axis.
    camera_height_mm : float
        Height of the view pose above the table (1000 mm above the hub's top by
        default).
    scale : float
        Scale factor on every dimension of the part.
    teeth : int
        Number of gear teeth (0 for a plain rim).
    table_albedo : float
        Reflectance of the table.
    texture_rng : numpy.random.Generator or None
        If given, the table gets a :class:`NoiseTexture` drawn from it.

    Returns
    -------
    PulleyScene
        Label 0 is the table; the teeth are the last `teeth` primitives.

    Notes
    -----
    With the thesis's camera at the default view pose the pulley spans about
    280 x 350 pixels and gives several hundred edge points along every 8th row
    at gradient threshold 8 (the thesis found 818 and 815 on its part).

    References
    ----------
    Kim (1989), the thesis, chapter 5.1 (figures 5-1, 5-2).

    Examples
    --------
    >>> s = hub_pulley_scene(center_xy=(300.0, 100.0))
    >>> s.top_z, s.outer_radius, len(s.primitives)
    (70.0, 96.0, 50)
    >>> s.view_pose
    Pose(x=300.0, y=100.0, z=1070.0, phi=0.0)
    """
    cx, cy = xy_pair("center_xy", center_xy)
    require_positive("scale", scale)
    require_positive("camera_height_mm", camera_height_mm)
    if isinstance(teeth, bool) or int(teeth) != teeth or teeth < 0:
        raise InputError(f"teeth must be a whole number >= 0, got {teeth}")
    k = float(scale)
    c = (cx, cy)
    top = 70 * k
    if top >= camera_height_mm:
        raise InputError(
            f"camera_height_mm must exceed the pulley top {top} mm, got {camera_height_mm}"
        )
    lift = 0.01 * k  # paint-thin rings sit this far above their face
    holes = tuple(
        (56 * k * math.cos(a), 56 * k * math.sin(a), 7 * k)
        for a in np.deg2rad(np.arange(8) * 45.0 + 22.5)
    )
    texture = None if texture_rng is None else NoiseTexture.from_rng(texture_rng)
    prims: list[Primitive] = [
        TablePlane(z=0.0, albedo=table_albedo, texture=texture),
        # rim with two belt grooves on its top face
        Cylinder(c, 0.0, 88 * k, 45 * k, inner_radius=76 * k, albedo=0.75),
        Disc(c, 45 * k + lift, 82.5 * k, inner_radius=80 * k, albedo=0.3),
        Disc(c, 45 * k + lift, 86.5 * k, inner_radius=84 * k, albedo=0.3),
        # web with lightening holes and two machined rings
        Disc(c, 20 * k, 76 * k, inner_radius=24 * k, holes=holes, albedo=0.5),
        Disc(c, 20 * k + lift, 69 * k, inner_radius=65 * k, albedo=0.9),
        Disc(c, 20 * k + lift, 45 * k, inner_radius=42 * k, albedo=0.2),
        # boss and hub
        Cylinder(c, 0.0, 38 * k, 32 * k, inner_radius=24 * k, albedo=0.7),
        Disc(c, 32 * k + lift, 33 * k, inner_radius=29 * k, albedo=0.25),
        Cylinder(c, 0.0, 24 * k, 70 * k, inner_radius=10 * k, albedo=0.85),
    ]
    for a in np.arange(int(teeth)) * (2 * math.pi / max(int(teeth), 1)):
        r = 91.75 * k  # r 87.5..96: the teeth overlap the rim by 0.5 mm
        prims.append(
            Box(
                (cx + r * math.cos(a), cy + r * math.sin(a)),
                0.0,
                (8.5 * k, 7 * k, 45 * k),
                yaw=float(a),
                albedo=0.75,
            )
        )
    return PulleyScene(
        primitives=tuple(prims),
        center=c,
        top_z=top,
        outer_radius=96 * k,
        view_pose=Pose(cx, cy, camera_height_mm, 0.0),
    )
