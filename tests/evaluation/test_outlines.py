"""Tests for the near/away figures (robostereo.evaluation.outlines) and their report."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from robostereo.cli import main
from robostereo.errors import InputError
from robostereo.evaluation import evaluate_scene, format_evaluation
from robostereo.evaluation.outlines import (
    MethodPoints,
    OffsetSummary,
    RowBoundaries,
    outline_figures,
    row_boundaries,
    silhouette_offsets,
    surface_distances,
)
from robostereo.geometry.triangulation import StereoCamera


def test_row_boundaries_lie_between_known_pixels_with_a_jump() -> None:
    gt = np.array([[4.0, 4.0, 9.0, 9.0, 6.5, np.inf, 1.0],
                   [4.0, 4.0, 4.0, 6.0, 6.0, 6.0, 6.0]])
    b = row_boundaries(gt)
    assert b.rows.tolist() == [0, 0] and b.x.tolist() == [1.5, 3.5]
    assert b.near_side.tolist() == [1, -1] and b.near_disparity.tolist() == [9.0, 9.0]


def test_silhouette_offsets_are_positive_outside_the_object() -> None:
    # object (disparity 20) to the right of x = 10 in row 0, to the left of x = 30 in row 1
    b = RowBoundaries(np.array([0, 1]), np.array([10.0, 30.0]), np.array([1, -1]),
                      np.array([20.0, 20.0]))
    rows = [0, 0, 1, 1, 1, 0]
    x = [9.3, 10.5, 31.0, 29.0, 30.2, 14.5]
    d = [20.2, 19.5, 20.0, 12.0, np.nan, 20.0]
    idx, off = silhouette_offsets(rows, x, d, b)
    # 9.3: 0.7 outside; 10.5: 0.5 inside; 31.0: 1.0 outside (object on the left);
    # 29.0 has the far disparity, 30.2 no match, 14.5 is beyond the 4 px reach
    assert idx.tolist() == [0, 1, 2]
    assert off == pytest.approx([0.7, -0.5, 1.0])
    o = OffsetSummary.of(off)
    assert (o.count, o.over_1px) == (3, 0.0) and o.median_abs_px == pytest.approx(0.7)
    with pytest.raises(InputError, match="1-D of one length"):
        silhouette_offsets([0], [1.0, 2.0], [1.0], b)


def test_surface_distance_of_points_on_and_off_a_ground_truth_plane() -> None:
    cam = StereoCamera(800.0, 800.0, 100.0, cx=20.0, cy=15.0)
    gt = np.full((30, 40), 16.0)  # Z = 800 * 100 / 16 = 5000 mm
    gt[:, :5] = np.nan
    dist = surface_distances(cam, [15, 15, 10], [20.0, 20.0, 30.0], [16.0, 20.0, np.nan], gt)
    assert dist[0] == pytest.approx(0.0, abs=1e-9)
    assert dist[1] == pytest.approx(5000.0 - 4000.0, abs=1e-6)  # straight behind the plane
    assert np.isnan(dist[2])


def test_outline_figures_split_the_points_and_both_rules() -> None:
    # one silhouette: foreground 20 on columns < 10 of rows 0..19, background 12
    gt = np.full((20, 40), 12.0)
    gt[:, :10] = 20.0
    rows = np.repeat(np.arange(20), 2)
    x = np.tile([10.9, 30.0], 20)  # the contour edge (1.4 px outside) and a far one
    d = np.tile([20.0, 12.0], 20)
    conf = np.tile([0.9, 0.95], 20)
    of = outline_figures(rows, x, gt, [MethodPoints("m", d, d, conf)])
    assert (of.near_points, of.away_points) == (20, 20)
    p, s = of.figures("m", "project"), of.figures("m", "silhouette")
    assert (p.near.false, s.near.false, p.away.false, s.away.false) == (20, 0, 0, 0)
    assert p.ece_near == pytest.approx(0.9) and s.ece_near == pytest.approx(0.1)
    assert s.coverage_near == (1.0, 1.0, 1.0) and p.coverage_near == (0.0, 0.0, 0.0)
    o = of.offsets["m"]
    assert (o.count, o.over_1px) == (20, 1.0) and o.median_abs_px == pytest.approx(1.4)
    doc = of.as_dict()
    assert list(doc["rules"]) == ["project", "silhouette"]
    assert doc["rules"]["silhouette"]["m"]["near"]["false_percent"] == 0.0
    with pytest.raises(InputError, match="no figures"):
        of.figures("m", "kitti")


def test_evaluate_reports_both_rules_near_and_away(real_scenes) -> None:
    scene = real_scenes["motorcycle"]
    ev = evaluate_scene(scene, curve=False)
    of = ev.outlines
    assert of is not None and of.near_points > 500 and of.away_points > 1000
    ours = ev.methods[0]
    for method in ("robostereo", "sgbm"):
        p, s = of.figures(method, "project"), of.figures(method, "silhouette")
        assert p.near.counted + p.away.counted == ev.methods[0].counted
        assert s.near.false <= p.near.false and s.away.false <= p.away.false
    p = of.figures("robostereo", "project")
    assert p.near.matched + p.away.matched == ours.matched
    assert p.near.false + p.away.false == ours.false
    # away from steps the matcher is far better than near them (the outline problem)
    assert p.near.matched_fraction < p.away.matched_fraction
    assert 0 <= p.ece_near < 0.2 and 0 <= p.ece_away < 0.2
    # 3-D distances from the calibration: millimetres, the 95th above the median
    near, away = of.distances_mm["robostereo"]["near"], of.distances_mm["robostereo"]["away"]
    assert 0 < near[0] < near[1] and 0 < away[0] < away[1] < 200.0
    assert of.offsets["robostereo"].count > 50
    text = format_evaluation(ev)
    assert "silhouette  robostereo" in text and "3-D distance to the ground-truth" in text


def test_cli_evaluate_json_keeps_its_keys_and_adds_outlines(data_dir: Path, capsys) -> None:
    assert main(["evaluate", str(data_dir / "tsukuba"), "--json", "--no-curves"]) == 0
    doc = json.loads(capsys.readouterr().out)[0]
    keys = list(doc)
    assert keys[:11] == ["scene", "path", "width", "height", "min_disparity",
                         "max_disparity", "edges_left", "edges_right", "methods",
                         "coverage_at_false", "outlines"]
    assert doc["rule"] == "project"  # the rule of "methods" and "coverage_at_false"
    o = doc["outlines"]
    assert o["definition"] == {"step_px": 2.0, "radius_px": 4, "connectivity": 4}
    for rule in ("project", "silhouette"):
        for method in ("robostereo", "sgbm"):
            near = o["rules"][rule][method]["near"]
            assert near["counted"] == o["near_points"] and 0 <= near["false_percent"] <= 100
    assert o["distance_3d_mm"] == {}  # tsukuba has no calibration
    v = o["visibility"]
    pts = v["near_points"]
    assert pts["all"] == o["near_points"] == pts["visible"] + pts["hidden"] + pts["unknown"]
    assert 0 < pts["hidden"] < pts["visible"]
    assert v["agreement_zbuffer_cross_check"] is None  # tsukuba has no right ground truth
    miss = v["not_accepted"]["robostereo"]["near"]
    near = o["rules"]["silhouette"]["robostereo"]["near"]
    assert miss["counted"] == pts["all"] and miss["accepted"] == near["matched"]
    assert sum(miss[k] for k in ("hidden", "visibility_unknown", "no_candidate",
                                 "best_right_refused", "best_wrong")) == (
        miss["counted"] - miss["accepted"])
    vis = v["near_silhouette_rule"]["robostereo"]["visible"]
    assert vis["counted"] == pts["visible"] and vis["matched"] <= near["matched"]


def test_evaluate_scene_scores_by_the_rule_asked(real_scenes) -> None:
    scene = real_scenes["cloth3"]
    p = evaluate_scene(scene, curve=False, outlines=False)
    s = evaluate_scene(scene, curve=False, outlines=False, rule="silhouette")
    assert s.outlines is None
    for mp, ms in zip(p.methods, s.methods, strict=True):
        assert (ms.counted, ms.matched) == (mp.counted, mp.matched) and ms.false <= mp.false
    assert sum(mp.false - ms.false for mp, ms in zip(p.methods, s.methods, strict=True)) > 0
    assert s.curves["robostereo"].coverage_at(0.02) >= p.curves["robostereo"].coverage_at(0.02)


def test_method_points_and_offset_summaries_check_themselves() -> None:
    with pytest.raises(InputError, match="1-D arrays of one length"):
        MethodPoints("m", np.zeros(3), best=np.zeros(4))
    with pytest.raises(InputError, match="2 sweep runs but 1 labels"):
        MethodPoints("m", np.zeros(3), sweep=(np.zeros(3), np.zeros(3)), sweep_labels=(0.0,))
    with pytest.raises(InputError, match="over_1px"):
        OffsetSummary(3, 0.5, 1.5)
    assert OffsetSummary.of([]).count == 0
