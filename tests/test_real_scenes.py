"""The real Middlebury scenes of ../shared/data/stereo against OpenCV's StereoSGBM.

Both are scored by the project's evaluation rule at the same pixels: the left edge
points whose ground truth is known.
"""

from __future__ import annotations

import time

import pytest

from robostereo.evaluation import sample_dense, score_matches, sgbm_disparity
from robostereo.pipeline import match_stereo


@pytest.mark.parametrize("name", ["tsukuba", "venus"])
def test_matched_and_false_against_sgbm(real_scenes, name):
    scene = real_scenes[name]
    lo, hi = scene.disparity_range
    t0 = time.perf_counter()
    res = match_stereo(scene.left, scene.right, (lo, hi))
    t1 = time.perf_counter()
    dense = sgbm_disparity(scene.left, scene.right, (lo, hi))
    t2 = time.perf_counter()
    e = res.left_edges
    ours = score_matches(e.row, e.x, res.disparity_of(res.match), scene.gt_disparity)
    sgbm = score_matches(e.row, e.x, sample_dense(dense, e.row, e.x), scene.gt_disparity)
    print(
        f"\n{name}: {len(e)} edge points ({ours.counted} with ground truth); "
        f"robostereo {100 * ours.matched_fraction:.1f}% matched, "
        f"{100 * ours.false_fraction:.2f}% false, rms {ours.rms:.3f} px, "
        f"{1000 * (t1 - t0):.1f} ms | SGBM {100 * sgbm.matched_fraction:.1f}% matched, "
        f"{100 * sgbm.false_fraction:.2f}% false, rms {sgbm.rms:.3f} px, "
        f"{1000 * (t2 - t1):.1f} ms"
    )
    assert ours.counted > 1000
    assert ours.matched_fraction >= 0.80
    assert ours.false_fraction < sgbm.false_fraction


def test_relaxation_earns_its_coverage(real_scenes):
    """Matched rises over the iterations while false stays below SGBM's."""
    scene = real_scenes["tsukuba"]
    res = match_stereo(scene.left, scene.right, scene.disparity_range)
    e = res.left_edges
    scores = [
        score_matches(e.row, e.x, res.disparity_of(res.matches_after(k)), scene.gt_disparity)
        for k in range(res.relaxation.iterations + 1)
    ]
    matched = [s.matched_fraction for s in scores]
    assert matched[-1] > matched[0] + 0.2
    assert all(s.false_fraction < 0.015 for s in scores)
