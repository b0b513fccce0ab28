"""Pareto plot of an accuracy study: error against wall time per metric kind.

Plotting only; :mod:`pygear.analysis.time.accuracy` computes.  One panel per kind of metric (t_s,
equilibrium speeds, mesh-force RMS, ...), one marker per setting (colour: fidelity,
size: time step), the Pareto front of the formulation drawn as a line, the tolerance
as a dashed line and the cheapest setting that meets it circled.
"""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.ticker import NullFormatter

from ..analysis.time.accuracy import recommendation
from .layout import new_figure, result_title

__all__ = ["plot_pareto"]

FLOOR = 1e-9
"""Errors below this are drawn at it (a log axis has no zero) [-]."""

DPI = 110
"""Resolution the figure is drawn at [pixels per inch]; save it at the same."""


def plot_pareto(ds: xr.Dataset, formulation: str | None = None) -> Figure:
    """Error against wall time, one panel per judged metric kind, for one formulation.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`pygear.runs.accuracy.accuracy_study`.
    formulation : str, optional
        Which formulation (default: the first).

    Returns
    -------
    matplotlib.figure.Figure
        One log-log panel per metric kind; the fidelities' key below them.
    """
    formulation = formulation or str(ds.formulation.values[0])
    sub = ds.sel(formulation=formulation)
    judged = sub.judged.values.astype(bool)
    kinds = list(dict.fromkeys(k for k, j in zip(sub.metric_kind.values, judged) if j))
    columns = min(3, max(len(kinds), 1))
    rows = max(1, math.ceil(len(kinds) / columns))
    fig = new_figure(4.2 * columns, 3.4 * rows + 0.4, DPI)
    axes = fig.subplots(rows, columns, squeeze=False)
    colours = matplotlib.colormaps["tab20"](np.linspace(0, 1, max(sub.sizes["fidelity"], 2)))
    sizes = 12 + 60 * np.linspace(1, 0, sub.sizes["time_step"])
    tolerance = ds.attrs["tolerance"]
    for ax, kind in zip(axes.flat, kinds):
        chosen = judged & (sub.metric_kind.values == kind)
        errors = np.nan_to_num(sub.error.values[..., chosen], nan=np.inf).max(-1)
        wall = sub.wall_time.values
        ok = np.isfinite(errors) & np.isfinite(wall)
        for j, fid in enumerate(sub.fidelity.values):
            keep = ok[j]
            ax.scatter(
                wall[j, keep],
                np.maximum(errors[j, keep], FLOOR),
                s=sizes[keep],
                color=colours[j],
                label=str(fid),
                alpha=0.85,
            )
        _front(ax, wall[ok], np.maximum(errors[ok], FLOOR))
        ax.axhline(tolerance, color="k", linestyle="--", linewidth=0.8)
        best = recommendation(ds, formulation, kind)
        if best["fidelity"]:
            ax.scatter(
                best["wall_time"],
                max(best["max_error"], FLOOR),
                s=220,
                facecolors="none",
                edgecolors="red",
                linewidths=1.5,
            )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_title(kind.replace("_", " "), fontsize=9)
        ax.set_xlabel("wall time per run [s]")
        ax.set_ylabel("largest error [-]")
    for ax in list(axes.flat)[len(kinds) :]:
        ax.axis("off")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7, frameon=False)
    best = recommendation(ds, formulation)
    title = f"Error against cost\n{result_title(ds.attrs, formulation=formulation)}"
    if best["fidelity"]:
        title += f" (all metrics: {best['fidelity']} at dt = {best['time_step']:g} s)"
    fig.suptitle(title, fontsize=10)
    legend_rows = math.ceil(sub.sizes["fidelity"] / 3)
    height = fig.get_figheight()
    fig.tight_layout(rect=(0, (0.2 + 0.16 * legend_rows) / height, 1, 1 - 0.55 / height))
    return fig


def _front(ax, wall: np.ndarray, error: np.ndarray) -> None:
    """The Pareto front: settings no other beats in both wall time and error."""
    order = np.argsort(wall)
    best, xs, ys = math.inf, [], []
    for i in order:
        if error[i] < best:
            best = error[i]
            xs.append(wall[i])
            ys.append(error[i])
    if xs:
        ax.step(xs, ys, where="post", color="0.4", linewidth=0.8)
