"""A capture folder located as ``robostereo locate`` does, scored against its depth maps.

:func:`evaluate_capture_folder` is what ``robostereo evaluate CAP`` runs for a folder
with ``capture.yaml``; the scoring itself is :mod:`robostereo.evaluation.capture_scoring`
(which the robot layer sits above):

1. the folder read; its reference view and the view paired with it chosen: two views,
   the left and the right; N views, the view nearest the centroid of the optical
   centres (the sweep's first reference, the pairs' reference) and the view nearest it;
2. the reference's depth map read (and the other view's, for occlusions) before any
   locating, so a bad map is refused at once;
3. the capture located as ``robostereo locate`` would (two views: the two-view matcher;
   N views: :func:`~robostereo.robot.views.locating.locate_views`), the reference's
   points taken;
4. the pair rectified as the project rectifies it, for StereoSGBM at the same pixels;
5. :func:`~robostereo.evaluation.capture_scoring.evaluate_capture_depth`.

References
----------
Kim (1989), the thesis, 3.6-3.7 (the located points, eq. 9's bound).
"""

from __future__ import annotations

import os
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError
from robostereo.evaluation import (
    CaptureEvaluation,
    CapturePoints,
    SgbmPair,
    capture_depth_files,
    evaluate_capture_depth,
)
from robostereo.robot.capture.capture_folder import read_capture
from robostereo.robot.capture.locate_pair import LocateParameters, locate, rectify_pair
from robostereo.robot.views.locating import locate_views
from robostereo.robot.views.view_pairs import pair_reference
from robostereo.robot.views.views_folder import is_views_folder, read_views_capture
from robostereo.robot.views.views_parameters import ViewsParameters

__all__ = ["evaluate_capture_folder"]


def evaluate_capture_folder(directory: str | os.PathLike[str], *, match: Any = None,
                            matcher: str | None = None, threshold: float | None = None,
                            sgbm: bool = True) -> tuple[CaptureEvaluation, NDArray[Any]]:
    """Locate a capture folder and score its reference view against its depth map.

    Parameters
    ----------
    directory : path
        A two-view or N-view capture folder with depth maps
        (:func:`~robostereo.evaluation.depth_maps.capture_depth_files`).
    match : MatchParameters, optional
        The two-view matcher's parameters (``robostereo locate``'s when None).
    matcher : {'auto', 'pairs', 'sweep'} or None
        N views: :class:`~robostereo.robot.views.views_parameters.ViewsParameters`'
        ``matcher`` (None: ``'auto'``); refused for two views.
    threshold : float, optional
        The edge threshold of the sweep and of the scored edge pixels (None: the
        matcher's, 8).
    sgbm : bool
        Also score StereoSGBM on the same rectified pair.

    Returns
    -------
    evaluation : CaptureEvaluation
    image : ndarray, shape (H, W)
        The reference view's image (for plots).

    Raises
    ------
    InputError
        No depth map for the reference view, a bad one, `matcher` for a two-view folder,
        or the capture's own errors; the message names the file.

    Notes
    -----
    The module's steps 1-5.
    """
    from robostereo.matcher.parameters import MatchParameters

    directory = Path(directory)
    src = str(directory / "capture.yaml")
    m = match if match is not None else MatchParameters()
    if threshold is not None:
        m = replace(m, threshold=float(threshold))
    pair_params = LocateParameters(match=m)
    # -- 1. the folder, its reference and the view paired with it
    nview = is_views_folder(directory)
    if nview:
        views = read_views_capture(directory)
        ref = pair_reference(views)
        dist = np.linalg.norm(views.centres - views.centres[ref], axis=1)
        dist[ref] = np.inf
        other = int(np.argmin(dist))
        pair = views.pair(ref, other)
        names = (views.view_name(ref), views.view_name(other))
    else:
        if matcher is not None:
            raise InputError(f"{src}: --matcher chooses how an N-view folder (views:) is "
                             "matched; this folder has two views (left, right)")
        pair = read_capture(directory)
        ref, other, names = 0, 1, ("left.png", "right.png")
    camera = pair.camera
    # -- 2. the depth maps, before any locating
    files = capture_depth_files(directory)
    depth = files.read(ref, camera.image_size)
    if depth is None:
        key = "its depth" if nview else "depth_left"
        raise InputError(f"{src}: no depth map for the reference view {names[0]} (give "
                         f"{key} or depth/{Path(names[0]).stem}.pfm, .npy or .png)")
    other_depth = files.read(other, camera.image_size)
    # -- 3. located as robostereo locate would; 4. the pair rectified for SGBM
    t0 = time.perf_counter()
    if nview:
        params = ViewsParameters(matcher=matcher or "auto", pair_match=pair_params)
        if threshold is not None:  # the sweep's too, as robostereo locate's
            params = replace(params, threshold=float(m.threshold))
        located = locate_views(views, params=params, source=src)
        points = CapturePoints.from_located(located, ref)
        geometry = pair.geometry()
        rect = rectify_pair(pair.left, pair.right, geometry)
    else:
        two = locate(pair, params=pair_params, source=src)
        points = CapturePoints.from_located(two)
        geometry, rect = two.geometry, two.rectified
    seconds = time.perf_counter() - t0
    sgbm_pair = None
    if sgbm:
        sgbm_pair = SgbmPair(rect.left, rect.right, geometry, pair.stereo_camera(geometry),
                             pair.resolved_disparity_range(geometry), int(pair.bit_depth))
    # -- 5. scored
    ev = evaluate_capture_depth(
        name=directory.resolve().name, directory=str(directory), camera=camera,
        poses=(pair.pose_left, pair.pose_right), image=pair.left, depth=depth,
        other_depth=other_depth, points=points, views=names, seconds=seconds,
        sgbm=sgbm_pair, threshold=float(m.threshold), bit_depth=int(pair.bit_depth))
    return ev, pair.left
