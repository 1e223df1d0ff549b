"""robostereo: sparse 3-D edges from stereo pairs, after Kim (1989).

A camera carried by a SCARA robot to two viewpoints (or any rectified or calibrated
stereo pair) gives two images; edge points found along epipolar lines are matched
(by default with side-aware census windows over every disparity and a calibrated
confidence, or with the seed's similarity indices and connectivity relaxation), then
triangulated into 3-D points with a per-point depth error bound.

Conventions used throughout
---------------------------
* images are ``(H, W)`` arrays; pixel ``(row i, column j)`` has its centre at
  ``x = j, y = i``;
* 2-D points are ``(N, 2)`` arrays of ``(x, y)``;
* disparity is ``d = x_left - x_right`` (pixels, positive for points in front);
* world and camera-frame coordinates are millimetres; camera frames have x to the
  image's right, y down the image, z along the optical axis (depth positive).

One module per stage: :mod:`~robostereo.edges`, :mod:`~robostereo.window` and
:mod:`~robostereo.confidence` (the default matcher), :mod:`~robostereo.matching`,
:mod:`~robostereo.relaxation` (the seed's), :mod:`~robostereo.triangulation`,
:mod:`~robostereo.pipeline` (all of them in one call), :mod:`~robostereo.camera`
(camera, poses, epipolar frames), :mod:`~robostereo.robot` (arm models, capture folders),
:mod:`~robostereo.simulation`,
:mod:`~robostereo.calibration`, :mod:`~robostereo.datasets`,
:mod:`~robostereo.evaluation`, :mod:`~robostereo.io`, :mod:`~robostereo.plots` and the
command line in :mod:`~robostereo.cli`.
"""

from robostereo import _moved
from robostereo.camera import Camera, EpipolarGeometry, Pose
from robostereo.edges import EdgeSet, detect_edges
from robostereo.errors import InputError, UnreachablePoseError
from robostereo.evaluation import MatchScore, score_matches
from robostereo.matching import SimilarityWeights
from robostereo.pipeline import MatchParameters, MatchResult, match_stereo
from robostereo.relaxation import RelaxationParameters
from robostereo.triangulation import StereoCamera, triangulate

__version__ = "0.1.0"

_moved.install()

__all__ = [
    "Camera",
    "EdgeSet",
    "EpipolarGeometry",
    "InputError",
    "MatchParameters",
    "MatchResult",
    "MatchScore",
    "Pose",
    "RelaxationParameters",
    "SimilarityWeights",
    "StereoCamera",
    "UnreachablePoseError",
    "__version__",
    "detect_edges",
    "match_stereo",
    "score_matches",
    "triangulate",
]
