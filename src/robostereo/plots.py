"""Figures: matched edge points over an image, and 3-D point views.

Every function draws on a Matplotlib ``ax`` it is given and returns it; none calls
``plt.show()``.  :func:`save_overlay` renders off-screen (Agg) to a PNG file.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "plot_curves",
    "plot_matches",
    "plot_points_3d",
    "save_capture_plots",
    "save_curves",
    "save_figure",
    "save_overlay",
]


def plot_matches(
    ax: Any,
    image: ArrayLike,
    x: ArrayLike,
    y: ArrayLike,
    values: ArrayLike,
    *,
    cmap: str = "turbo",
    vmin: float | None = None,
    vmax: float | None = None,
    size: float = 4.0,
    label: str = "disparity (px)",
    colorbar: bool = True,
) -> Any:
    """Draw points ``(x, y)`` over a grey image, coloured by ``values``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    image : array_like, shape (H, W) or (H, W, 3)
    x, y : array_like, shape (N,)
        Image coordinates of the points.
    values : array_like, shape (N,)
        Colour values (e.g. disparity or depth).

    Returns
    -------
    matplotlib.axes.Axes
    """
    img = np.asarray(image)
    ax.imshow(img, cmap="gray" if img.ndim == 2 else None, interpolation="nearest")
    sc = ax.scatter(np.asarray(x), np.asarray(y), c=np.asarray(values), s=size, cmap=cmap,
                    vmin=vmin, vmax=vmax, linewidths=0)
    if colorbar and np.asarray(x).size:
        ax.figure.colorbar(sc, ax=ax, label=label, shrink=0.8)
    ax.set_xlim(-0.5, img.shape[1] - 0.5)
    ax.set_ylim(img.shape[0] - 0.5, -0.5)
    ax.set_axis_off()
    return ax


def plot_points_3d(ax: Any, xyz: ArrayLike, *, values: ArrayLike | None = None,
                   cmap: str = "viridis", size: float = 3.0) -> Any:
    """Scatter 3-D points ``(N, 3)`` (millimetres) on a 3-D ``ax``, equal axis scales."""
    p = np.asarray(xyz, dtype=float).reshape(-1, 3)
    p = p[np.isfinite(p).all(axis=1)]
    c = p[:, 2] if values is None else np.asarray(values)[: p.shape[0]]
    ax.scatter(p[:, 0], p[:, 1], p[:, 2], c=c, s=size, cmap=cmap, depthshade=False)
    ax.set_xlabel("X (mm)")
    ax.set_ylabel("Y (mm)")
    ax.set_zlabel("Z (mm)")
    if p.shape[0]:
        span = np.ptp(p, axis=0)
        ax.set_box_aspect(np.maximum(span, span.max() * 0.05))
    return ax


def save_figure(fig: Any, path: str | os.PathLike[str]) -> None:
    """Save a figure as PNG atomically (no partial file on failure)."""
    from robostereo.io import atomic_path

    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=110, bbox_inches="tight")


def save_overlay(path: str | os.PathLike[str], image: ArrayLike, x: ArrayLike, y: ArrayLike,
                 values: ArrayLike, *, title: str | None = None, **kwargs: Any) -> None:
    """Write a PNG of the matched points over the image (off-screen rendering)."""
    from matplotlib.figure import Figure

    img = np.asarray(image)
    h, w = img.shape[:2]
    fig = Figure(figsize=(max(4.0, w / 80), max(3.0, h / 80)))
    ax = fig.add_subplot(1, 1, 1)
    plot_matches(ax, img, x, y, values, **kwargs)
    if title:
        ax.set_title(title)
    save_figure(fig, path)


def plot_curves(ax: Any, ev: Any) -> Any:
    """Draw a scene's curves, coverage against false rate, on a Matplotlib ``ax``.

    ``ev`` is a :class:`robostereo.evaluation.scorer.SceneEvaluation`: robostereo's curve (its
    confidence swept) as a line, SGBM's settings as squares, each default operating
    point as a cross; grey lines at the false rates compared.
    """
    from robostereo.evaluation import CURVE_LEVELS

    for name, c in ev.curves.items():
        if name == "sgbm":
            ax.plot(100 * c.false_rate, 100 * c.coverage, "s", ms=4, label="SGBM (settings)")
        else:
            ax.plot(100 * c.false_rate, 100 * c.coverage, "-", lw=1.5,
                    label=f"{name} (confidence swept)")
    for m in ev.methods:
        ax.plot(m.false_percent, m.matched_percent, "k+" if m.method == "sgbm" else "kx",
                ms=9, label=f"{'SGBM' if m.method == 'sgbm' else m.method} default")
    for f in CURVE_LEVELS:
        ax.axvline(100 * f, color="0.8", lw=0.8, zorder=0)
    ax.set_xlim(0, 10)
    rule = {"project": "the project's rule", "silhouette": "the silhouette rule"}[ev.rule]
    ax.set_xlabel(f"false matches (% of matched, {rule})")
    ax.set_ylabel("coverage (% of edge points with ground truth)")
    ax.set_title(f"{ev.name}: {ev.edges_left} left edge points", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    return ax


def save_curves(ev: Any, path: str | os.PathLike[str]) -> None:
    """Write :func:`plot_curves` of a scene evaluation as a PNG (off-screen)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.0, 4.5))
    plot_curves(fig.add_subplot(1, 1, 1), ev)
    save_figure(fig, path)


def save_capture_plots(ev: Any, image: ArrayLike, directory: str | os.PathLike[str]
                       ) -> list[str]:
    """Write a capture evaluation's plots: ``NAME_depth_errors.png`` (each method's 3-D
    errors against the depth map, a histogram) and ``NAME_coverage.png`` (the reference
    image with the edge pixels both views see, covered by robostereo or not).

    ``ev`` is a :class:`robostereo.evaluation.capture_scoring.CaptureEvaluation`, `image`
    its reference view's grabbed image.  Returns the files written.
    """
    from pathlib import Path

    from matplotlib.figure import Figure

    d = Path(directory)
    fig = Figure(figsize=(6.0, 4.0))
    ax = fig.add_subplot(1, 1, 1)
    errs = {k: v[np.isfinite(v)] for k, v in ev.errors.items()}
    top = max([float(np.percentile(v, 99)) for v in errs.values() if v.size] + [1.0])
    bins = np.linspace(0.0, top, 60)
    for k, v in errs.items():
        ax.hist(np.clip(v, 0, top), bins=bins, histtype="step", lw=1.5,
                label=f"{'SGBM' if k == 'sgbm' else k} ({v.size} points)")
    ax.set_xlabel("3-D error against the depth map, mm (clipped at the 99th percentile)")
    ax.set_ylabel("points")
    ax.set_title(f"{ev.name}: reference {ev.reference}", fontsize=10)
    ax.legend(fontsize=8)
    errors_png = d / f"{ev.name}_depth_errors.png"
    save_figure(fig, errors_png)
    img = np.asarray(image)
    h, w = img.shape[:2]
    fig = Figure(figsize=(max(4.0, w / 80), max(3.0, h / 80)))
    ax = fig.add_subplot(1, 1, 1)
    ax.imshow(img, cmap="gray")
    e, cov = ev.edge_pixels, ev.covered.get("robostereo", np.zeros(0, bool))
    if len(e):
        ax.plot(e[~cov, 0], e[~cov, 1], ",", color="red")
        ax.plot(e[cov, 0], e[cov, 1], ",", color="lime")
    n = len(e)
    share = f"{100 * cov.mean():.1f} %" if n else "-"
    ax.set_title(f"{ev.name}: edge pixels both views see, covered (green) {share}",
                 fontsize=10)
    ax.set_axis_off()
    coverage_png = d / f"{ev.name}_coverage.png"
    save_figure(fig, coverage_png)
    return [str(errors_png), str(coverage_png)]
