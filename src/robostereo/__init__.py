"""robostereo: sparse 3-D edges from stereo pairs, after Kim (1989).

A camera carried by a robot to two viewpoints (or any rectified or calibrated stereo
pair) gives two images; edge points found along epipolar lines are matched (by default
with side-aware census windows over every disparity and a calibrated confidence, or
with the thesis's similarity indices and connectivity relaxation), then triangulated
into 3-D points with a per-point depth error bound.

Glossary
--------
the thesis
    T.-Q. Kim, *A robot vision system for determining 3-D coordinates of object
    points*, M.S. thesis, New Jersey Institute of Technology (1989): the system
    robostereo implements.  "Section 3.2",
    "eq. 9", "table 5-1" and "figure 4-2" in docstrings refer to its sections,
    equations, tables and figures: chapter 2 frames and epipolar lines, chapter 3 the
    algorithms (3.1 edges, 3.2 features, 3.3-3.4 initial probabilities and relaxation,
    3.5 matching region, 3.6 3-D position and eq. 9, the depth error bound), chapter 4
    the AdeptOne set-up, chapter 5 the block and hub-pulley experiments.  Older text
    calls it "the seed"; ``--seed-mode`` and :meth:`MatchParameters.thesis` are its
    matcher settings.  A random-number seed is always called ``seed`` as a parameter.
epipolar frame
    Rotated (rectified) image coordinates in which epipolar lines are rows (section 2.2).
disparity
    ``d = x_left - x_right`` in rectified pixels, positive for points in front.
pose
    An :class:`~robostereo.geometry.poses.SE3` ``T_world_camera``; the SCARA form
    ``Pose(x, y, z, phi)`` (camera looking straight down, yaw ``phi``) is one of them.

Conventions used throughout
---------------------------
* images are ``(H, W)`` arrays; pixel ``(row i, column j)`` has its centre at
  ``x = j, y = i``;
* 2-D points are ``(N, 2)`` arrays of ``(x, y)``;
* world and camera-frame coordinates are millimetres; camera frames have x to the
  image's right, y down the image, z along the optical axis (depth positive).

Layout
------
The library, lowest layer first (a module imports only its own layer or lower ones):

* :mod:`robostereo.errors`: the one error type and its checks;
* :mod:`robostereo.geometry`: camera model, poses, the three rectifications (SCARA yaw,
  general poses, calibrated rigs) behind one interface, triangulation (eq. 9);
* :mod:`robostereo.io` and :mod:`robostereo.datasets`: images, camera and calibration
  files, outputs written all or nothing; scenes with ground truth;
* :mod:`robostereo.matcher`: edges, candidates, relaxation, window costs and kernels,
  confidence, the pipeline (:func:`match_stereo`);
* :mod:`robostereo.simulation`, :mod:`robostereo.evaluation`, :mod:`robostereo.rig`;
* :mod:`robostereo.robot`: arms, capture folders, locating (two and N views), hand-eye,
  planning, the simulated robots.

The application layer, which the library never imports: :mod:`robostereo.experiments`
(the thesis's experiments and the demo), :mod:`robostereo.plots`, :mod:`robostereo.batch`
and the command line :mod:`robostereo.cli`.
"""

from robostereo import _moved

# the 0.1 module paths (robostereo.pipeline, robostereo.camera, ...) for one more release
_moved.install()

from robostereo.errors import InputError, PlausibilityWarning, UnreachablePoseError
from robostereo.evaluation import MatchScore, score_matches
from robostereo.geometry.calibration import StereoCalibration
from robostereo.geometry.camera import Camera
from robostereo.geometry.poses import SE3, Pose
from robostereo.geometry.scara_rectification import EpipolarGeometry
from robostereo.geometry.triangulation import StereoCamera, triangulate
from robostereo.io.calibration_files import read_calibration
from robostereo.io.images import load_image
from robostereo.matcher.candidates import SimilarityWeights
from robostereo.matcher.edge_features import EdgeSet
from robostereo.matcher.edges import detect_edges
from robostereo.matcher.parameters import MatchParameters
from robostereo.matcher.pipeline import MatchResult, match_stereo
from robostereo.matcher.relaxation import RelaxationParameters
from robostereo.rig import RigResult, load_rig_pair, match_rig
from robostereo.robot.capture import (
    Capture,
    Located,
    LocateParameters,
    locate_capture,
    read_capture,
    write_capture,
)
from robostereo.robot.handeye import calibrate_eye_in_hand, load_handeye_yaml
from robostereo.robot.views import (
    LocatedViews,
    ViewsCapture,
    ViewsParameters,
    is_views_folder,
    locate_views,
    read_views_capture,
    write_views_capture,
)

__version__ = "0.1.0"

#: the names ``from robostereo import ...`` gives, by the user's path
__all__ = [  # noqa: RUF022 - grouped by path, not sorted
    # a rectified pair (thesis chapter 3)
    "EdgeSet",
    "MatchParameters",
    "MatchResult",
    "RelaxationParameters",
    "SimilarityWeights",
    "StereoCamera",
    "detect_edges",
    "match_stereo",
    "triangulate",
    # images and a calibrated rig
    "RigResult",
    "StereoCalibration",
    "load_image",
    "load_rig_pair",
    "match_rig",
    "read_calibration",
    # a camera on an arm, two views (thesis chapters 2, 4, 5)
    "SE3",
    "Camera",
    "Capture",
    "EpipolarGeometry",
    "LocateParameters",
    "Located",
    "Pose",
    "calibrate_eye_in_hand",
    "load_handeye_yaml",
    "locate_capture",
    "read_capture",
    "write_capture",
    # N views
    "LocatedViews",
    "ViewsCapture",
    "ViewsParameters",
    "is_views_folder",
    "locate_views",
    "read_views_capture",
    "write_views_capture",
    # scoring and errors
    "InputError",
    "MatchScore",
    "PlausibilityWarning",
    "UnreachablePoseError",
    "__version__",
    "score_matches",
]
