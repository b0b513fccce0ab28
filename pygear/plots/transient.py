"""Figure of a run-up's speeds, like the seed's Figure 9 (plotting only; nothing computes).

Each speed is cut to the extremes of each pixel column (:mod:`pygear.plots.decimation`)
and the panels sit at fixed margins, so the figure costs the same for any record length.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from .decimation import plot_envelope
from .layout import new_figure, result_title

__all__ = ["plot_speeds"]

DPI = 120
"""Resolution the figure is drawn at [pixels per inch]; save it at the same."""

MARGINS_INCH = {"left": 0.95, "right": 0.15, "bottom": 0.5, "top": 0.8}
"""Fixed margins [in]: two-line y labels with tick labels, the time axis, the figure's
title above the columns' two-line titles."""


def _run_speeds(dataset: xr.Dataset) -> tuple[dict[str, xr.DataArray], float]:
    """A run's speeds against time [rpm] by body (``stage.member``), and its t_s [s]
    (NaN when the run has none): the one place this module reads a run's variables.

    Speeds grouped in one variable over (``time``, a label dimension such as
    ``member``) give one series per label; a speed variable over ``time`` alone is
    named by its ``target`` attribute.
    """
    speeds: dict[str, xr.DataArray] = {}
    for name, variable in dataset.data_vars.items():
        if variable.attrs.get("quantity") != "speed" or "time" not in variable.dims:
            continue
        if variable.dims == ("time",):
            speeds[str(variable.attrs.get("target", name))] = variable
        elif variable.ndim == 2:
            (labels,) = (dim for dim in variable.dims if dim != "time")
            for label in variable[labels].values:
                series = variable.sel({labels: label})
                if np.any(np.isfinite(series.values)):  # NaN: a label not recorded
                    speeds[str(label)] = series
    t_s = float(dataset["t_s"]) if "t_s" in dataset else np.nan
    return speeds, t_s


def plot_speeds(datasets: Sequence[xr.Dataset], *, until: float | None = None) -> Figure:
    """Speeds against time, one column per run and one row per body (seed Figure 9).

    Parameters
    ----------
    datasets : sequence of xarray.Dataset
        Runs from :func:`pygear.analysis.transient.run_transient` (e.g. one per scene).
    until : float, optional
        Last time shown [s]; default the end of the longest run (the paper's Figure 9
        shows the first 2 s of its 5 s run).

    Returns
    -------
    matplotlib.figure.Figure
        Rows share the time axis; a dotted line marks t_s, the first instant the input
        reaches the reference speed.  The figure's title names the case, each column's
        the scene and the formulation.
    """
    runs = [_run_speeds(dataset) for dataset in datasets]
    rows: list[str] = []
    for speeds, _ in runs:
        rows += [body for body in speeds if body not in rows]
    if not rows:
        raise ValueError("no speed channels to plot (add Probe('speed', body) to the scene)")
    start = min(float(dataset["time"][0]) for dataset in datasets)
    end = until if until is not None else max(float(dataset["time"][-1]) for dataset in datasets)
    if not end > start:
        raise ValueError(f"until must be later than the runs' start {start:g} s (got {end!r})")
    width, height = 4.5 * len(datasets), 2.2 * len(rows) + MARGINS_INCH["top"] - 0.3
    figure = new_figure(width, height, DPI)
    axes = figure.subplots(len(rows), len(datasets), sharex=True, squeeze=False)
    figure.subplots_adjust(
        left=MARGINS_INCH["left"] / width,
        right=1 - MARGINS_INCH["right"] / width,
        bottom=MARGINS_INCH["bottom"] / height,
        top=1 - MARGINS_INCH["top"] / height,
        wspace=0.35,
        hspace=0.25,
    )
    cases = list(dict.fromkeys(str(dataset.attrs.get("case", "")) for dataset in datasets))
    for column, (dataset, (speeds, t_s)) in enumerate(zip(datasets, runs)):
        for row, body in enumerate(rows):
            axis = axes[row, column]
            axis.set_xlim(start, end)
            if body in speeds:
                shown = speeds[body].sel(time=slice(start, end))
                plot_envelope(axis, shown["time"].values, shown.values, linewidth=0.8)
                if np.isfinite(t_s):
                    axis.axvline(t_s, color="0.6", ls=":", lw=0.8)
                axis.set_ylabel(f"{body}\nspeed [rpm]", fontsize=8)
            else:
                axis.set_visible(False)
            axis.tick_params(labelsize=8)
            axis.grid(alpha=0.3)
        title = result_title(dataset.attrs, case=len(cases) > 1)
        if np.isfinite(t_s):
            title += f"\nt_s = {t_s:.4g} s (dotted)"
        axes[0, column].set_title(title, fontsize=8)
        axes[-1, column].set_xlabel("time [s]")
    figure.suptitle(f"Speeds against time: {', '.join(cases)}", fontsize=10, y=1 - 0.08 / height)
    return figure
