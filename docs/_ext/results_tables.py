"""The results page's tables and figures, made from the benchmarks' data files.

Each JSON file in ``docs/results`` holds the figures of one benchmark command (its
``command`` key, with ``measured``: when and how), either written by the benchmark itself
(``python benchmarks/bench_curves.py --write-results docs/results/real_scenes.json``, the
same for ``bench_match.py`` and ``bench_handeye.py``) or copied by hand from a run of the
command it names.  :func:`write_all`, called by ``docs/conf.py`` at every build, turns
them into Markdown fragments and PNG figures in ``docs/guide/_generated``, which the
guide's pages include, so a page cannot quote other figures than its data file holds.
Every fragment ends with the command that produced its figures.

Run as a script to write the fragments into a folder and print their names::

    python docs/_ext/results_tables.py /tmp/fragments
"""

from __future__ import annotations

import json
import statistics
import sys
from collections.abc import Callable, Iterable, Sequence
from decimal import ROUND_HALF_UP, Decimal
from pathlib import Path
from typing import Any

DOCS = Path(__file__).resolve().parents[1]
#: the data files, one per benchmark command
DATA = DOCS / "results"
#: where the fragments and figures go (ignored by git and by Sphinx's source search)
GENERATED = DOCS / "guide" / "_generated"

#: the peers of ``bench_match.py``: data key -> how the pages name it
PEERS = {"sgbm": "`MODE_SGBM`", "sgbm-3way": "`MODE_SGBM_3WAY`", "bm": "StereoBM"}

Data = dict[str, Any]


def load(name: str) -> Data:
    """The data file ``docs/results/<name>.json``."""
    return json.loads((DATA / f"{name}.json").read_text())


# -- formatting -----------------------------------------------------------------------------


def num(x: float | int | None, digits: int = 1) -> str:
    """``x`` with ``digits`` decimals, rounded half up as written by hand ("-" for None)."""
    if x is None:
        return "-"
    q = Decimal(1).scaleb(-digits)
    return str(Decimal(repr(x)).quantize(q, rounding=ROUND_HALF_UP))


def pair(values: Sequence[float] | None, digits: tuple[int, int] = (1, 2)) -> str:
    """``matched / false`` (percent), as ``77.2 / 1.42``."""
    if values is None:
        return "-"
    return f"{num(values[0], digits[0])} / {num(values[1], digits[1])}"


def span(values: Iterable[float], digits: int = 1, unit: str = "") -> str:
    """``lo-hi`` of ``values`` (one value when they are equal)."""
    v = sorted(values)
    lo, hi = num(v[0], digits), num(v[-1], digits)
    return f"{lo}{unit}" if lo == hi else f"{lo}-{hi}{unit}"


def median(values: Iterable[float]) -> Decimal:
    """The median, in decimals (``0.078`` and ``0.089`` give ``0.0835``, not 0.08349...)."""
    return statistics.median(Decimal(repr(v)) for v in values)


def table(headers: Sequence[str], rows: Iterable[Sequence[str]]) -> list[str]:
    """A Markdown pipe table."""

    def line(cells: Sequence[str]) -> str:
        return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"

    return [line(headers), "|" + "---|" * len(headers), *(line(r) for r in rows)]


def source(data: Data, name: str, command: str | None = None) -> list[str]:
    """The line under a table: the command, when and how, and the data file."""
    cmd = command or f"`{data['command']}`"
    return ["", f"*Made by* {cmd}: {data['measured']}. Data: `docs/results/{name}.json`.", ""]


# -- matching on the real scenes ------------------------------------------------------------


def real_scenes() -> list[str]:
    d = load("real_scenes")
    lv = " / ".join(f"{v:g}" for v in d["levels_percent"])
    rows = []
    for s in d["scenes"]:
        w, r, g = s["window"], s["relaxation"], s["sgbm"]
        rows.append([s["scene"],
                     f"{pair((w['matched_percent'], w['false_percent']))} / "
                     f"{num(w['rms_px'], 2)} px",
                     pair((g["matched_percent"], g["false_percent"])),
                     " / ".join(num(c) for c in w["coverage_percent"]),
                     " / ".join(num(c) for c in g["coverage_percent"]),
                     pair((r["matched_percent"], r["false_percent"]))])
    head = ["scene", "robostereo default: matched % / false % / RMS",
            "SGBM default: matched % / false %", f"robostereo at <= {lv} % false",
            f"SGBM's best of 26 settings at <= {lv} % false",
            "the thesis's relaxation: matched % / false %"]
    return [*table(head, rows), *source(d, "real_scenes")]


def false_ratio_span() -> str:
    """How many times less often robostereo's default point is wrong than SGBM's default,
    over the scenes where both are ever wrong (as ``3.6-10``)."""
    d = load("real_scenes")
    r = [s["sgbm"]["false_percent"] / s["window"]["false_percent"] for s in d["scenes"]
         if s["window"]["false_percent"] > 0 and s["sgbm"]["false_percent"] > 0]
    lo, hi = f"{min(r):.2g}", f"{max(r):.2g}"
    return lo if lo == hi else f"{lo}-{hi}"


def outlines() -> list[str]:
    d = load("outlines")
    rows = [[s["scene"], pair(s["near"]), pair(s["away"]), pair(s["all"]),
             " / ".join(num(v) for v in s["curve_near_percent"]),
             " / ".join(num(v) for v in s["sgbm_curve_near_percent"]),
             num(s["best_right_near_percent"])] for s in d["scenes"]]
    head = ["scene", "near steps: matched % / false %", "away", "all",
            "near: robostereo's curve at <= 2 / 3 % false",
            "near: SGBM's best settings at <= 2 / 3 %", "near: best disparity right, %"]
    return [*table(head, rows), *source(d, "outlines")]


def contour() -> list[str]:
    d = load("outlines")
    rows = [[s["scene"]] + [f"{pair(s[k])} -> {pair(s['contour'][k])}"
                            for k in ("near", "away", "all")] for s in d["scenes"]]
    return [*table(["scene", "near steps", "away", "all"], rows),
            *source(d, "outlines", f"`{d['command']}` without and with `--contour`")]


def calibration() -> list[str]:
    d = load("calibration")
    rows = [[s["scene"], num(s["ece"], 3), " / ".join(num(c) for c in s["coverage_percent"]),
             pair(s["default"]), num(s["threshold"], 3),
             *(pair(s["at_threshold"][k]) for k in ("all", "near", "away"))]
            for s in d["scenes"]]
    head = ["held out", "ECE", "coverage at <= 2 / 3 / 5 % false",
            "at 20/21: matched % / false %", "threshold chosen held out",
            "there: all", "near steps", "away"]
    return [*table(head, rows), *source(d, "calibration")]


def _checks(kind: str) -> list[str]:
    d = load("checks")
    part = d[kind]
    rows = []
    for s in part["scenes"]:
        cells = []
        for off, on in zip(s["off"], s["on"], strict=True):
            cells.append(f"{pair(off)} (not warned)" if on is None
                         else f"{pair(off)} -> {pair(on)}")
        rows.append([s["scene"], pair(d["as_they_are"][s["scene"]]), *cells])
    out = [*table(["scene", "as they are", *part["cases"]], rows), ""]
    if "not_warned" in part:
        out += [f"Not warned: {part['not_warned']}.", ""]
    return out + source(d, "checks")[1:]


def exposure() -> list[str]:
    return _checks("exposure")


def rows_check() -> list[str]:
    return _checks("rows")


def checks_cost() -> list[str]:
    cost = load("checks")["cost"]
    return [cost[0].upper() + cost[1:] + "."]


# -- speed and memory ---------------------------------------------------------------------


def _own_range(p: str) -> bool:
    """A real scene at its own disparity range (not widened, not synthetic)."""
    return " " not in p


def speed() -> list[str]:
    d = load("speed")
    second = d.get("second_run", {}).get("all_cores_ratio_sgbm-3way", {})
    every = {r["pair"]: r for r in d.get("all_cores", [])}
    rows = []
    for r in d["per_core"]:
        a = every.get(r["pair"], {"robostereo_ms": None, "ratio": {}})
        rows.append([r["pair"], str(r["edges"]), num(r["robostereo_ms"]),
                     *(num(r["ratio"][k], 2) for k in PEERS),
                     num(a["robostereo_ms"]), num(a["ratio"].get("sgbm-3way"), 2),
                     num(a["ratio"].get("bm"), 2), num(second.get(r["pair"]), 2)])
    head = ["pair", "edge points", "per core: robostereo ms",
            *(f"x {v}" for v in PEERS.values()), "all cores: robostereo ms",
            "x `MODE_SGBM_3WAY`", "x StereoBM", "all cores x `MODE_SGBM_3WAY`, second run"]
    out = [*table(head, rows), *source(d, "speed")]
    if second:
        out[-2] += f" The last column: {d['second_run']['measured']}."
    return out


def speed_phrases() -> dict[str, str]:
    """The figures the README and the results page quote, worked out from the data:
    per core on the six developer scenes at their own ranges, and peak memory on all
    pairs."""
    d = load("speed")
    own = [r for r in d["per_core"] if _own_range(r["pair"])]
    synthetic = [r for r in d["per_core"] if r["pair"].startswith("synthetic")]
    slow = min(own, key=lambda r: r["ratio"]["sgbm-3way"])
    behind = [r for r in own if r["ratio"]["bm"] < 1]
    ahead = [r for r in own if r["ratio"]["bm"] >= 1]
    mem = load("memory")["pairs"]
    return {
        "sgbm": span(r["ratio"]["sgbm"] for r in own) + "x the speed of `MODE_SGBM`",
        "sgbm-3way": span(r["ratio"]["sgbm-3way"] for r in own) + "x `MODE_SGBM_3WAY`",
        "slowest": f"{slow['pair']} is the slowest, {num(slow['ratio']['sgbm-3way'], 2)}x "
                   "`MODE_SGBM_3WAY`",
        "synthetic": "on the dense synthetic texture "
                     + span((r["ratio"]["sgbm-3way"] for r in synthetic), 2) + "x",
        "bm": "StereoBM is " + span(1 / r["ratio"]["bm"] for r in behind) + "x faster",
        "bm ahead": ", ".join(f"{r['pair']} ({num(r['ratio']['bm'], 2)}x robostereo's speed"
                              for r in ahead),
        "memory": span((p["ratio"] for p in mem), 2) + "x `MODE_SGBM`'s",
    }


def speed_summary() -> list[str]:
    p = speed_phrases()
    return [f"Per core, on the six developer scenes at their own ranges, robostereo runs at "
            f"{p['sgbm']} and {p['sgbm-3way']} ({p['slowest']}; {p['synthetic']}); "
            f"{p['bm']} than robostereo on all of them but {p['bm ahead']} there). "
            f"Peak memory added is {p['memory']} on all {len(load('memory')['pairs'])} "
            "pairs."]


def memory() -> list[str]:
    d = load("memory")
    rows = [[p["pair"], num(p["robostereo_mib"]), num(p["sgbm_mib"]), f"{num(p['ratio'], 2)}x"]
            for p in d["pairs"]]
    return [*table(["pair", "robostereo MiB", "`MODE_SGBM` MiB", "ratio"], rows),
            *source(d, "memory")]


# -- the robot ----------------------------------------------------------------------------


def robot_scara() -> list[str]:
    d = load("robot")["scara"]
    t = d["thesis"]
    z, zt = d["block_mean_z_mm"], d["block_true_z_mm"]
    pr, pw, tp = d["pulley_relaxation"], d["pulley_window"], t["pulley"]
    within = "every point within its bound" if d["all_within_bound"] else "not all within"
    rows = [
        ["block mean z, two heights", f"{num(z[0], 2)} mm and {num(z[1], 2)} mm "
         f"(true {num(zt[0], 2)}, {num(zt[1], 2)})",
         f"{num(t['block_mean_z_mm'][0])} and {num(t['block_mean_z_mm'][1])} mm"],
        ["measured lift", f"{num(d['lift_mm'], 2)} mm (true {num(d['lift_true_mm'], 2)})",
         f"{num(t['lift_mm'])} mm"],
        ["largest |z error| / its eq. 9 bound",
         f"{num(d['max_abs_error_mm'], 2)} mm / {num(d['bound_mm'])} mm; {within}",
         f"{t['max_abs_error_mm']} mm / {t['bound_mm']} mm"],
        [f"block width (true {num(d['block_width_true_mm'], 2)} mm)",
         f"{num(d['block_width_mm'][0], 2)} .. {num(d['block_width_mm'][1], 2)} mm",
         f"{num(t['block_width_mm'][0])} .. {num(t['block_width_mm'][1])} mm"],
        [f"hub-pulley, after {pr['iterations']} iterations",
         f"{num(pr['matched_percent'])} % matched, {num(pr['false_percent'], 2)} % false "
         f"({pr['edge_points']} edge points)",
         f"{tp['matched_percent']} % matched, {num(tp['false_percent'], 2)} % false "
         f"({tp['edge_points']})"],
        ["hub-pulley, robostereo's default matcher (window)",
         f"{num(pw['matched_percent'], 2)} % matched, {num(pw['false_percent'], 2)} % false",
         ""],
    ]
    return [*table(["", "robostereo (simulated)", "thesis (real AdeptOne)"], rows),
            *source(d, "robot")]


def robot_sixaxis() -> list[str]:
    d = load("robot")["sixaxis"]
    s0, rest, tg = d["seeds"][0], d["seeds"][1:], d["targets"]
    within = (f"all {s0['block_points']} block points within their bounds"
              if s0["all_within_bound"] else "not all within their bounds")
    rows = [
        ["measured lift", f"{num(s0['lift_mm'], 2)} mm (true 79.65)",
         f"within {tg['lift_within_mm']} mm"],
        ["largest |z error| / its eq. 9 bound",
         f"{num(s0['max_abs_error_mm'], 2)} mm / {num(s0['bound_mm'], 2)} mm; {within}",
         f"<= {tg['max_abs_error_mm']} mm, all within"],
        ["hand-eye error (Park-Martin, then the joint refinement)",
         f"{num(s0['handeye_mm'], 2)} mm, {num(s0['handeye_deg'], 3)} deg",
         f"{tg['handeye_mm']} mm, {tg['handeye_deg']} deg"],
        ["board reprojection RMS", f"{num(s0['board_rms_px'], 3)} px", ""],
        [f"seeds {rest[0]['seed']}-{rest[-1]['seed']}",
         "lift " + ", ".join(num(s["lift_mm"], 2) for s in rest) + " mm; largest error "
         + ", ".join(num(s["max_abs_error_mm"], 2) for s in rest) + " mm"
         + (", every point within its bound" if all(s["all_within_bound"] for s in rest)
            else "")
         + f"; hand-eye {span(d['seeds_1_3_handeye_mm'], 2)} mm, "
         f"{span(d['seeds_1_3_handeye_deg'], 3)} deg", ""],
    ]
    return [*table(["", "six-axis demo, seed 0", "targets"], rows), *source(d, "robot")]


def views_demo() -> list[str]:
    d = load("views")["demo"]
    rows = []
    for r in d["rows"]:
        what = f"{r['robot']}, {r['views']} on a {r['pattern']}"
        if "note" in r:
            what += f" ({r['note']})"
        err = f"{num(r['max_abs_error_mm'], 2)} mm"
        if "long_edges_max_abs_error_mm" in r:
            err += f" (long edges {num(r['long_edges_max_abs_error_mm'], 2)})"
        rows.append([what, err, "yes" if r["all_within_bound"] else "no",
                     f"{num(r['lift_mm'], 2)} mm", f"{num(r['outline_coverage_percent'])} %",
                     f"{num(r['pulley'][0])} % / {num(r['pulley'][1], 2)} %"])
    head = ["robot, N, pattern", "largest |z error|", "every point within its bound",
            f"lift (true {num(d['lift_true_mm'], 2)} mm)", "outline coverage",
            "pulley matched / false"]
    return [*table(head, rows), *source(d, "views")]


def views_pulley() -> list[str]:
    d = load("views")["pulley_seeds"]
    rows = [[k, *(pair(v) for v in d[k])] for k in ("line", "cross")]
    return [*table(["six-axis, 5 views, seed", *(str(s) for s in d["seeds"])], rows),
            *source(d, "views")]


def views_times() -> list[str]:
    d = load("views")["times"]
    return [f"Five views take {span(d['five_views'])} and nine views {span(d['nine_views'])} "
            "times as long as one two-view locate of the capture's outer pair.",
            *source(d, "views")]


def handeye() -> list[str]:
    d = load("handeye")
    keys = ("closed_form", "refined", "intrinsics_held")

    def cell(v: Sequence[float] | Sequence[Decimal], digits: int = 4) -> str:
        return f"{num(float(v[0]), 3)} mm, {num(float(v[1]), digits)} deg"

    rows = [[f"{r['views']}, seed {r['seed']}", *(cell(r[k]) for k in keys)]
            for r in d["rows"]]
    med = [[median(r[k][i] for r in d["rows"]) for i in (0, 1)] for k in keys]
    rows.append([f"median of the {len(d['rows'])}", *(cell(m, 3) for m in med)])
    return [*table(["views", "closed form", "refined", "true intrinsics held"], rows),
            *source(d, "handeye")]


def matching_summary() -> str:
    """Where robostereo's curve covers fewer edge points than SGBM's best setting."""
    d = load("real_scenes")
    levels = d["levels_percent"]
    short = []
    for s in d["scenes"]:
        w, g = s["window"]["coverage_percent"], s["sgbm"]["coverage_percent"]
        at = [i for i in range(len(levels)) if float(num(w[i])) < float(num(g[i]))]
        if at:
            short.append(f"{s['scene']} at <= " + " and ".join(f"{levels[i]:g}" for i in at)
                         + " % (" + "; ".join(f"{num(w[i])} against {num(g[i])}" for i in at)
                         + ")")
    lv = ", ".join(f"{v:g}" for v in levels[:-1]) + f" and {levels[-1]:g}"
    but = f", but {'; '.join(short)}" if short else ""
    return (f"at equal false rates robostereo covers at least as many edge points as "
            f"OpenCV's StereoSGBM at its best setting on every scene at <= {lv} % false{but}; "
            f"at its default it is wrong {false_ratio_span()} times less often than SGBM's "
            "default where SGBM's is wrong at all")


def glance() -> list[str]:
    """The page's summary: one bullet per part, every figure from the data files."""
    out = load("outlines")["scenes"]
    rob, six = load("robot")["scara"], load("robot")["sixaxis"]["seeds"][0]
    views = {(r["robot"], r["views"], r["pattern"]): r for r in load("views")["demo"]["rows"]}
    five, cross, two = (views[("SCARA", 5, "line")], views[("SCARA", 5, "cross")],
                        views[("SCARA", 2, "line")])
    he = load("handeye")["rows"]
    refined = [median(r["refined"][i] for r in he) for i in (0, 1)]
    th = rob["thesis"]
    return [
        f"- **Real scenes** (Middlebury, the project's rule): {matching_summary()}.",
        "- **Near object outlines** (silhouette rule): the default point matches "
        + span(s["near"][0] for s in out) + " % of the edge points near depth steps at "
        + span((s["near"][1] for s in out), 2) + " % false, against "
        + span(s["away"][0] for s in out) + " % away from them at "
        + span((s["away"][1] for s in out), 2) + " % false.",
        "- **Speed and memory**: " + speed_summary()[0][0].lower() + speed_summary()[0][1:],
        f"- **The thesis's experiments, simulated** (`{rob['command']}`): the block's lift of "
        f"{num(rob['lift_true_mm'], 2)} mm measured as {num(rob['lift_mm'], 2)} mm, the "
        f"largest depth error {num(rob['max_abs_error_mm'], 2)} mm against its eq. 9 bound "
        f"of {num(rob['bound_mm'])} mm (the thesis: {th['max_abs_error_mm']} against "
        f"{th['bound_mm']} mm); on a six-axis arm with the hand-eye it calibrated, "
        f"{num(six['max_abs_error_mm'], 2)} mm against {num(six['bound_mm'], 2)} mm.",
        f"- **Many viewpoints**: five views on a line over 80 mm locate the block with a "
        f"largest error of {num(five['max_abs_error_mm'], 2)} mm and the hub-pulley "
        f"{num(five['pulley'][0])} % matched at {num(five['pulley'][1], 2)} % false; a cross "
        f"of five sees {num(cross['outline_coverage_percent'])} % of the block's outline "
        f"(two views: {num(two['outline_coverage_percent'])} %).",
        f"- **Hand-eye calibration**: a median error of {num(float(refined[0]), 3)} mm and "
        f"{num(float(refined[1]), 3)} deg after the joint refinement on "
        f"{len(he)} sets of simulated and rendered views.",
    ]


#: fragment name -> the function that makes its lines
FRAGMENTS: dict[str, Callable[[], list[str]]] = {
    "glance": glance,
    "real_scenes": real_scenes,
    "outlines": outlines,
    "contour": contour,
    "calibration": calibration,
    "exposure": exposure,
    "rows_check": rows_check,
    "checks_cost": checks_cost,
    "speed": speed,
    "speed_summary": speed_summary,
    "memory": memory,
    "robot_scara": robot_scara,
    "robot_sixaxis": robot_sixaxis,
    "views_demo": views_demo,
    "views_pulley": views_pulley,
    "views_times": views_times,
    "handeye": handeye,
}


# -- figures ------------------------------------------------------------------------------


def coverage_figure(path: Path) -> None:
    """Coverage at <= 2, 3 and 5 % false, robostereo against SGBM's best setting."""
    import matplotlib.pyplot as plt
    import numpy as np

    d = load("real_scenes")
    scenes = [s["scene"] for s in d["scenes"]]
    y = np.arange(len(scenes))
    fig, axes = plt.subplots(1, len(d["levels_percent"]), figsize=(10, 3.5),
                             layout="constrained", sharey=True)
    for i, (ax, level) in enumerate(zip(axes, d["levels_percent"], strict=True)):
        for k, (key, label) in enumerate((("window", "robostereo"),
                                          ("sgbm", "SGBM, best of 26 settings"))):
            ax.barh(y - 0.2 + 0.4 * k, [s[key]["coverage_percent"][i] for s in d["scenes"]],
                    height=0.4, label=label, color=f"C{k}")
        ax.set_title(f"at <= {level:g} % false")
        ax.set_xlim(0, 100)
        ax.set_xlabel("coverage (%)")
    axes[0].set_yticks(y, scenes)
    axes[0].invert_yaxis()
    fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncols=2)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def speed_figure(path: Path) -> None:
    """Per core: each peer's time over robostereo's; peak memory over ``MODE_SGBM``'s."""
    import matplotlib.pyplot as plt
    import numpy as np

    d, mem = load("speed"), {p["pair"]: p["ratio"] for p in load("memory")["pairs"]}
    rows = d["per_core"]
    y = np.arange(len(rows))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained", sharey=True,
                                 width_ratios=(2, 1))
    for k, (key, label) in enumerate(PEERS.items()):
        ax.barh(y - 0.27 + 0.27 * k, [r["ratio"][key] for r in rows], height=0.27,
                label=label.strip("`"))
    ax.axvline(1, color="k", lw=0.8)
    ax.set_xlabel("peer's time / robostereo's, one thread each (> 1: robostereo faster)")
    ax.set_yticks(y, [r["pair"] for r in rows])
    ax.invert_yaxis()
    ax.legend(fontsize="small", loc="lower right")
    bx.barh(y, [mem.get(r["pair"], np.nan) for r in rows], height=0.5, color="C3")
    bx.axvline(1, color="k", lw=0.8)
    bx.set_xlabel("peak memory added / MODE_SGBM's")
    fig.savefig(path, dpi=100)
    plt.close(fig)


def calibration_figure(path: Path) -> None:
    """The confidence's reliability: mean confidence against the fraction right."""
    import matplotlib.pyplot as plt

    bins = load("calibration")["reliability"]["bins"]
    fig, ax = plt.subplots(figsize=(4, 4), layout="constrained")
    ax.plot([0, 1], [0, 1], color="0.6", lw=0.8, label="calibrated")
    ax.plot([b[0] for b in bins], [b[1] for b in bins], "o-", label="robostereo")
    ax.set_xlabel("mean confidence of the bin")
    ax.set_ylabel("fraction right (silhouette rule)")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.legend(loc="upper left")
    fig.savefig(path, dpi=100)
    plt.close(fig)


#: figure file name -> the function that draws it
FIGURES: dict[str, Callable[[Path], None]] = {
    "coverage.png": coverage_figure,
    "speed.png": speed_figure,
    "calibration.png": calibration_figure,
}


def write_all(out: Path = GENERATED, figures: bool = True) -> list[Path]:
    """Write every fragment (``<name>.md``) and, with ``figures``, every figure into
    ``out``; a fragment whose text is unchanged is left alone.  Returns the files."""
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, make in FRAGMENTS.items():
        path = out / f"{name}.md"
        text = "\n".join(make()).rstrip("\n") + "\n"
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
        paths.append(path)
    if figures:
        import matplotlib

        matplotlib.use("Agg")
        for name, draw in FIGURES.items():
            draw(out / name)
            paths.append(out / name)
    return paths


if __name__ == "__main__":
    for p in write_all(Path(sys.argv[1]) if len(sys.argv) > 1 else GENERATED):
        print(p)
