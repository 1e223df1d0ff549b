"""A simulated camera: analytic scenes rendered by ray casting, with ground truth.

The simulator stands in for the thesis's PULNiX camera on the AdeptOne robot
(the thesis's chapters 4 and 5): a pinhole :class:`~robostereo.geometry.camera.Camera` at a
:class:`~robostereo.geometry.poses.Pose` looks down on a scene of analytic primitives
(a table plane, boxes, vertical cylinders and tubes, horizontal discs and annuli
with holes) lit by a directional light and an ambient term.  :func:`render`
returns the 7-bit grey image together with the exact depth and the primitive
hit at every pixel centre, so that edges, disparities and 3-D points measured
from the images can be checked against the truth.

Modules
-------
:mod:`~robostereo.simulation.primitives`
    The analytic solid primitives (:class:`TablePlane`, :class:`Disc`,
    :class:`Cylinder`, :class:`Box`) and ``Primitive``, any primitive.
:mod:`~robostereo.simulation.targets`
    The flat printed targets: :class:`Checkerboard` and :class:`ImagePlane` (e.g. a
    ChArUco board).
:mod:`~robostereo.simulation.surfaces`
    What the primitives share: the checks of their parameters and the table's
    :class:`NoiseTexture`.
:mod:`~robostereo.simulation.scenes`
    :class:`Scene` (primitives and lighting) and the thesis's scenes:
    :func:`seed_block_scene` and :func:`hub_pulley_scene`.
:mod:`~robostereo.simulation.render`
    Ray casting: :func:`render`, :class:`Rendering`, :func:`sample_offsets`,
    :func:`true_disparity`.
:mod:`~robostereo.simulation.occluders`
    Rectified pairs of textured polygons before a slanted textured plane, rendered by
    area coverage with exact disparity, occlusion mask and silhouette boundaries
    (:func:`occluder_pair`), for measuring matchers at object outlines.

The simulated robots that carry the camera are in :mod:`robostereo.robot`
(:mod:`~robostereo.robot.simulated.scara_rig`, :mod:`~robostereo.robot.simulated.sixaxis_rig`).

World coordinates are millimetres with Z up; the table top is at ``z = 0`` in the
scenes built here.  The camera conventions are those of :mod:`robostereo.geometry.camera`.
"""

from robostereo.simulation.occluders import Occluder, OccluderPair, occluder_pair
from robostereo.simulation.primitives import Box, Cylinder, Disc, TablePlane
from robostereo.simulation.render import Rendering, render, sample_offsets, true_disparity
from robostereo.simulation.scenes import (
    BlockScene,
    PulleyScene,
    Scene,
    hub_pulley_scene,
    seed_block_scene,
)
from robostereo.simulation.surfaces import NoiseTexture
from robostereo.simulation.targets import Checkerboard, ImagePlane

__all__ = [
    "BlockScene",
    "Box",
    "Checkerboard",
    "Cylinder",
    "Disc",
    "ImagePlane",
    "NoiseTexture",
    "Occluder",
    "OccluderPair",
    "PulleyScene",
    "Rendering",
    "Scene",
    "TablePlane",
    "hub_pulley_scene",
    "occluder_pair",
    "render",
    "sample_offsets",
    "seed_block_scene",
    "true_disparity",
]
