"""Module paths of release 0.1 that moved, kept importable for one release.

``import robostereo.pipeline`` (or ``from robostereo.camera import Camera``) still works:
the old path is a module assembled from the public names (``__all__``) of the modules
the code moved to, and importing it warns with a :class:`DeprecationWarning` that names
the new home.  New code imports from the new paths; nothing inside robostereo uses the
old ones (``tests/test_layout.py`` checks that).

The table :data:`MOVED` is the whole mapping; :func:`install` puts its finder on
:data:`sys.meta_path` once, from ``robostereo/__init__.py``.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import types
import warnings

__all__ = ["MOVED", "install"]

#: old module path -> the modules whose public names it is made of (first wins)
MOVED: dict[str, tuple[str, ...]] = {
    # the matcher (one folder, kernels apart)
    "robostereo.pipeline": ("robostereo.matcher.pipeline", "robostereo.matcher.parameters"),
    "robostereo.edges": ("robostereo.matcher.edges", "robostereo.matcher.edge_features",
                         "robostereo.matcher.grey_levels"),
    "robostereo.matching": ("robostereo.matcher.candidates",),
    "robostereo.relaxation": ("robostereo.matcher.relaxation",),
    "robostereo.confidence": ("robostereo.matcher.confidence",),
    "robostereo.parallel": ("robostereo.matcher.parallel",),
    "robostereo.window": (
        "robostereo.matcher.window_match",
        "robostereo.matcher.window_costs",
        "robostereo.matcher.pipeline",
        "robostereo.matcher.parameters",
        "robostereo.matcher.window_kernels",
    ),
    # geometry under one roof, file reading in io
    "robostereo.camera": (
        "robostereo.geometry.camera",
        "robostereo.geometry.poses",
        "robostereo.geometry.scara_rectification",
        "robostereo.io.cameras",
    ),
    "robostereo.calibration": (
        "robostereo.geometry.calibration",
        "robostereo.geometry.calibrated_rectification",
        "robostereo.io.calibration_files",
    ),
    "robostereo.triangulation": ("robostereo.geometry.triangulation",),
    "robostereo.robot.poses": ("robostereo.geometry.poses",),
    "robostereo.robot.geometry": ("robostereo.geometry.pose_rectification",),
    # the command line by command group, then (0.2) one module per command
    "robostereo.cli_robot": (
        "robostereo.cli.demo",
        "robostereo.cli.capture_command",
        "robostereo.cli.locate",
        "robostereo.cli.handeye_commands",
        "robostereo.cli.plan",
    ),
    # 0.2: robot/ by job (arms, capture, handeye, views, simulated), evaluation/ a package;
    # robostereo.robot.capture, .handeye, .views, .simulated and robostereo.evaluation are
    # packages now that export every name the old modules did
    "robostereo.robot.scara": (
        "robostereo.robot.arms.scara",
        "robostereo.robot.arms.acquisition",
    ),
    "robostereo.robot.sixaxis": ("robostereo.robot.arms.sixaxis",),
    "robostereo.robot.capture_folder": ("robostereo.robot.capture.capture_folder",),
    "robostereo.robot.handeye_views": ("robostereo.robot.handeye.boards",),
    "robostereo.robot.handeye_refine": ("robostereo.robot.handeye.refine",),
    "robostereo.robot.handeye_checks": ("robostereo.robot.handeye.checks",),
    "robostereo.robot.views_folder": ("robostereo.robot.views.views_folder",),
    "robostereo.robot.multiview": (
        "robostereo.robot.views.locating",
        "robostereo.robot.views.views_parameters",
        "robostereo.robot.views.located_points",
    ),
    "robostereo.robot.multiview_search": (
        "robostereo.robot.views.prepared_views",
        "robostereo.robot.views.ray_search",
        "robostereo.robot.views.point_refinement",
    ),
    "robostereo.robot.multiview_votes": ("robostereo.robot.views.edge_votes",),
    "robostereo.robot.multiview_kernels": ("robostereo.robot.views.views_kernels",),
    "robostereo.robot.pose_check": ("robostereo.robot.views.pose_check",),
    "robostereo.robot.edge_profiles": ("robostereo.robot.views.edge_profiles",),
    "robostereo.robot.edge_profile_kernels": ("robostereo.robot.views.edge_profile_kernels",),
    "robostereo.robot.simulated_scara": ("robostereo.robot.simulated.scara_rig",),
    "robostereo.robot.simulated_views": ("robostereo.robot.simulated.grab_views",),
    "robostereo.robot.views_truth": ("robostereo.robot.simulated.views_truth",),
    "robostereo.evaluation_rules": ("robostereo.evaluation.rules",),
    "robostereo.evaluation_outlines": ("robostereo.evaluation.outlines",),
    "robostereo.evaluation_visibility": ("robostereo.evaluation.visibility",),
    # 0.2: the command line one module per command, each with its N-view run
    "robostereo.cli.matching": (
        "robostereo.cli.match",
        "robostereo.cli.rig_command",
        "robostereo.cli.evaluate",
        "robostereo.cli.batch_command",
    ),
    "robostereo.cli.robot": (
        "robostereo.cli.demo",
        "robostereo.cli.capture_command",
        "robostereo.cli.locate",
        "robostereo.cli.handeye_commands",
        "robostereo.cli.plan",
    ),
    "robostereo.cli.views": (
        "robostereo.cli._views_args",
        "robostereo.cli.demo",
        "robostereo.cli.capture_command",
        "robostereo.cli.locate",
        "robostereo.cli.plan",
    ),
}


class _MovedLoader(importlib.abc.Loader):
    def __init__(self, targets: tuple[str, ...]) -> None:
        self.targets = targets

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        module = types.ModuleType(spec.name, f"Moved to {', '.join(self.targets)}.")
        names: list[str] = []
        for target in reversed(self.targets):  # the first target's names win
            new = importlib.import_module(target)
            for name in getattr(new, "__all__", ()):
                setattr(module, name, getattr(new, name))
                names.append(name)
        module.__all__ = sorted(set(names))
        return module

    def exec_module(self, module: types.ModuleType) -> None:
        warnings.warn(
            f"{module.__name__} moved to {' and '.join(self.targets)}; the old path goes "
            "in the next release",
            DeprecationWarning,
            stacklevel=2,
        )


class _MovedFinder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname: str, path: object = None,
                  target: object = None) -> importlib.machinery.ModuleSpec | None:
        targets = MOVED.get(fullname)
        if targets is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, _MovedLoader(targets))


def install() -> None:
    """Put the finder of the moved paths last on :data:`sys.meta_path` (once).

    Last, so that it answers only for paths no file answers for.
    """
    if not any(isinstance(f, _MovedFinder) for f in sys.meta_path):
        sys.meta_path.append(_MovedFinder())
