"""Object outlines on synthetic occluder pairs: both rules near/away, silhouette offsets.

Run:  python benchmarks/bench_outlines.py [--pairs N] [--height H] [--width W]

N occluder pairs (:func:`robostereo.simulation.occluders.occluder_pair`, seeds 0..N-1:
a rectangle, a diamond and a hexagon at disparity gaps 4, 8 and 14 px before a slanted
plane, exact ground truth) are matched by robostereo's defaults and by StereoSGBM's
default (read at the same edge points).  Printed per pair and pooled:

* % matched and % false near depth steps (within 4 px of a ground-truth jump of more
  than 2 px between 4-neighbours) and away, by the project's rule and by the silhouette
  rule (:mod:`robostereo.evaluation.rules`);
* the pooled coverage at <= 1.65, 2 and 3 % false by the silhouette rule, near and away,
  and robostereo's ECE near and away;
* the silhouette offsets of robostereo's matched edges (those matched with the nearer
  surface's disparity within 4 px of a boundary): signed median, median ``|offset|`` and
  the fraction above 1 px, against the exact boundaries and against boundaries read off
  the ground-truth rows (:func:`robostereo.evaluation.outlines.row_boundaries`, as on
  real scenes), to show what pixel-sampled ground truth adds;
* the edge localisation alone: the signed offsets of *every* left edge point within
  1.5 px of an exact boundary, matched or not
  (:func:`robostereo.evaluation.outlines.boundary_offsets`), so that a bias of the
  localisation at steps between two textured surfaces is told from the acceptance's
  choice of which silhouette edges it keeps;
* near steps over all edge points and over those the right view sees (by the pairs'
  exact occlusion masks, and by the ground truth z-buffered,
  :mod:`robostereo.evaluation.visibility`), and the near-step points robostereo does
  not accept sorted by why: hidden in the other view, visibility unknown, no candidate,
  best disparity right but refused, best disparity wrong.
"""

from __future__ import annotations

import argparse

import numpy as np

from robostereo.evaluation import (
    OUTLINE_LEVELS,
    RULES,
    coverage_curve,
    depth_step_mask,
    expected_calibration_error,
    near_steps,
    rule_errors,
    sample_dense,
    score_matches,
    sgbm_disparity,
    sgbm_sweep,
)
from robostereo.evaluation.outlines import (
    MethodPoints,
    OffsetSummary,
    RowBoundaries,
    boundary_offsets,
    row_boundaries,
    settings_curve,
    silhouette_offsets,
)
from robostereo.evaluation.visibility import (
    BREAKDOWN,
    HIDDEN,
    VISIBLE,
    Visibility,
    format_visibility_figures,
    left_visibility,
    visibility_figures,
)
from robostereo.matcher.pipeline import match_stereo
from robostereo.simulation.occluders import occluder_pair


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--pairs", type=int, default=8, help="occluder pairs, seeds 0..N-1 (8)")
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--width", type=int, default=360)
    args = ap.parse_args(argv)
    pooled: dict[str, list[np.ndarray]] = {k: [] for k in
                                            ("row", "x", "d", "best", "conf", "sg",
                                             "exact", "rows_off", "located")}
    sweeps: list[tuple[np.ndarray, ...]] = []
    labels: tuple[float, ...] = ()
    print(f"{'pair':>4} {'method':<10} {'rule':<10}  near: {'n':>4} {'matched':>8} {'false':>7}"
          f"   away: {'n':>5} {'matched':>8} {'false':>7}")
    gts, offset_rows, exact_states, z_states = [], 0, [], []
    for seed in range(args.pairs):
        p = occluder_pair(seed, height=args.height, width=args.width)
        gt = p.disparity
        res = match_stereo(p.left, p.right, p.disparity_range)
        e = res.left_edges
        d = res.accepted_disparity()
        sg = sample_dense(sgbm_disparity(p.left, p.right, p.disparity_range), e.row, e.x)
        sw, labels = sgbm_sweep(p.left, p.right, p.disparity_range, e.row, e.x)
        near = near_steps(e.row, e.x, depth_step_mask(gt))
        for method, dd in (("robostereo", d), ("SGBM", sg)):
            for rule in RULES:
                a = score_matches(e.row, e.x, dd, gt, rule=rule, subset=near)
                b = score_matches(e.row, e.x, dd, gt, rule=rule, subset=~near)
                print(f"{seed:>4} {method:<10} {rule:<10}        {a.counted:>4} "
                      f"{100 * a.matched_fraction:>7.1f}% {100 * a.false_fraction:>6.2f}%"
                      f"         {b.counted:>5} {100 * b.matched_fraction:>7.1f}% "
                      f"{100 * b.false_fraction:>6.2f}%")
        _, exact = silhouette_offsets(e.row, e.x, d, RowBoundaries(*p.boundaries()))
        _, from_rows = silhouette_offsets(e.row, e.x, d, row_boundaries(gt))
        _, located, _ = boundary_offsets(e.row, e.x, RowBoundaries(*p.boundaries()))
        # pool the pairs side by side in one wide ground truth (rows stay rows)
        offset = offset_rows
        gts.append(gt)
        exact_states.append(np.where(p.occluded, HIDDEN, VISIBLE).astype(np.int8))
        z_states.append(left_visibility(gt).state)
        offset_rows += gt.shape[1] + 8
        for k, v in (("row", e.row), ("x", e.x + offset), ("d", d), ("best", res.edge_disparity),
                     ("conf", res.edge_confidence), ("sg", sg), ("exact", exact),
                     ("rows_off", from_rows), ("located", located)):
            pooled[k].append(np.asarray(v, dtype=float))
        sweeps.append(sw)
    h = max(g.shape[0] for g in gts)
    wide = np.full((h, offset_rows), np.nan)
    wide_states = [np.full((h, offset_rows), -1, dtype=np.int8) for _ in range(2)]
    col = 0
    for k, g in enumerate(gts):
        wide[: g.shape[0], col: col + g.shape[1]] = g
        for w, st in zip(wide_states, (exact_states[k], z_states[k]), strict=True):
            w[: g.shape[0], col: col + g.shape[1]] = st
        col += g.shape[1] + 8
    cat = {k: np.concatenate(v) for k, v in pooled.items()}
    rows, x = cat["row"].astype(int), cat["x"]
    near = near_steps(rows, x, depth_step_mask(wide))
    sweep = tuple(np.concatenate([s[k] for s in sweeps]) for k in range(len(labels)))
    lv = "".join(f"{'<=' + format(100 * f, 'g') + '%':>8s}" for f in OUTLINE_LEVELS)
    print(f"\npooled over {args.pairs} pairs, silhouette rule: coverage at  near{lv}    "
          f"away{lv}")
    for method in ("robostereo", "SGBM"):
        cov = []
        for sub in (near, ~near):
            if method == "robostereo":
                c = coverage_curve(rows, x, cat["best"], cat["conf"], wide, rule="silhouette",
                                   subset=sub)
            else:
                c = settings_curve(sweep, labels, rows, x, wide, rule="silhouette", subset=sub)
            cov.append("".join(f"{100 * c.coverage_at(f):7.1f}%" for f in OUTLINE_LEVELS))
        print(f"{method:<50}{cov[0]}        {cov[1]}")
    for rule in RULES:
        known, err = rule_errors(rows, x, cat["best"], wide, rule=rule)
        take = known & np.isfinite(err) & np.isfinite(cat["conf"])
        eces = [expected_calibration_error(cat["conf"][take & sub], err[take & sub] <= 1.0)
                for sub in (near, ~near)]
        print(f"robostereo ECE ({rule} rule): near {eces[0]:.3f}, away {eces[1]:.3f}")
    for label, key in (("exact boundaries", "exact"), ("boundaries from GT rows", "rows_off")):
        o = OffsetSummary.of(cat[key])
        signed = float(np.median(cat[key])) if cat[key].size else float("nan")
        print(f"silhouette offsets, {label}: {o.count} edges, signed median {signed:+.2f} px "
              f"(+ = outside the object), median |offset| {o.median_abs_px:.2f} px, "
              f"{100 * o.over_1px:.1f} % > 1 px")
    points = [MethodPoints("robostereo", cat["d"], cat["best"], cat["conf"]),
              MethodPoints("sgbm", cat["sg"])]
    for label, st in (("exact occlusion masks", wide_states[0]),
                      ("ground truth z-buffered", wide_states[1])):
        vis = Visibility(state=st, zbuffer_hidden=st == HIDDEN,
                         out_of_view=np.zeros(st.shape, dtype=bool))
        vf = visibility_figures(rows, x, wide, near, vis, points, levels=OUTLINE_LEVELS)
        print(f"\npooled, visibility by the {label}:")
        print("\n".join(format_visibility_figures(vf)))
        b = vf.missing["robostereo"]["near"]
        print("  as % of the near-step points: " + ", ".join(
            f"{k} {100 * b.counts[k] / max(b.counted, 1):.1f}" for k in BREAKDOWN))
    o = OffsetSummary.of(cat["located"])
    print(f"edge localisation, every edge within 1.5 px of an exact boundary: {o.count} edges, "
          f"signed median {float(np.median(cat['located'])):+.2f} px, median |offset| "
          f"{o.median_abs_px:.2f} px, {100 * o.over_1px:.1f} % > 1 px")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
