"""Importers: other tools' camera files and images to an N-view capture folder.

Modules
-------
:mod:`~robostereo.robot.importers.imported_views`
    What every importer gives (:class:`ImportedView`: image, ``K``, pose) and the N-view
    capture made of it: views chosen, images and intrinsics scaled together, one camera.
:mod:`~robostereo.robot.importers.idr`
    IDR / NeuS ``cameras.npz`` (``world_mat_K``, ``scale_mat_K``), as DTU is distributed.
:mod:`~robostereo.robot.importers.mvsnet`
    MVSNet folders: ``cams/0000000K_cam.txt``, ``images/``, ``pair.txt``.
:mod:`~robostereo.robot.importers.colmap`
    COLMAP models: ``cameras``, ``images``, ``points3D`` (text; binary through
    :mod:`~robostereo.robot.importers.colmap_binary`).
:mod:`~robostereo.robot.importers.rosbag`
    ROS 1 and ROS 2 bags: images, ``camera_info``, the camera's pose from ``/tf`` and
    ``/tf_static`` (:mod:`~robostereo.robot.importers.tf_frames`); needs ``rosbags``.

Each reader gives the views in millimetres and ``T_world_camera`` poses; the capture is
written by :func:`~robostereo.robot.views.views_folder.write_views_capture`.
"""

from robostereo.robot.importers.colmap import read_colmap
from robostereo.robot.importers.idr import read_idr
from robostereo.robot.importers.imported_views import (
    Imported,
    ImportedView,
    parse_view_selection,
    views_capture_from_imported,
)
from robostereo.robot.importers.mvsnet import read_mvsnet
from robostereo.robot.importers.rosbag import read_rosbag

__all__ = [
    "Imported",
    "ImportedView",
    "parse_view_selection",
    "read_colmap",
    "read_idr",
    "read_mvsnet",
    "read_rosbag",
    "views_capture_from_imported",
]
