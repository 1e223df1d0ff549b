"""Old path of release 0.1, kept as a file for the transition only.

``robostereo/__init__.py`` imports ``robostereo.camera`` before it installs the finder
of the moved paths (:mod:`robostereo._moved`), so this one old path must still be a
file: it installs the finder first (which then serves ``robostereo.calibration``,
``robostereo.triangulation``, ``robostereo.robot.poses`` and
``robostereo.robot.geometry``, whose files are gone) and carries the public names of
the modules that :data:`robostereo._moved.MOVED` lists for ``robostereo.camera`` (the
first listed wins).  Delete this file once the package installs the finder before its
first import; the finder then serves this path too.
"""

from robostereo import _moved

_moved.install()

from robostereo.geometry.camera import *  # noqa: E402, F403
from robostereo.geometry.poses import *  # noqa: E402, F403
from robostereo.geometry.scara_rectification import *  # noqa: E402, F403
from robostereo.io.cameras import *  # noqa: E402, F403
