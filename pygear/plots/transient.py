"""Figures of a run's speeds (like the seed's Figure 9) and of its loads: mesh forces and
the drive and load torques (plotting only; nothing computes).

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

__all__ = ["plot_loads", "plot_speeds"]

DPI = 120
"""Resolution the figure is drawn at [pixels per inch]; save it at the same."""

MARGINS_INCH = {"left": 0.95, "right": 0.15, "bottom": 0.5, "top": 0.8}
"""Fixed margins [in]: two-line y labels with tick labels, the time axis, the figure's
title above the columns' two-line titles."""


LOAD_QUANTITIES = {
    "mesh_force": "force [N]",
    "drive_torque": "torque [N m]",
    "load_torque": "torque [N m]",
}
"""Channels of the loads figure and their axis units (a rotational bearing spring's
force is a moment; the drivetrain figures show translational ones)."""


def _run_series(
    dataset: xr.Dataset, quantities: dict[str, str]
) -> tuple[dict[str, tuple[xr.DataArray, str]], float]:
    """A run's series of the given quantities against time by label, each with its axis
    unit, and its t_s [s] (NaN when the run has none): the one place this module reads a
    run's variables.

    Series grouped in one variable over (``time``, a label dimension such as ``member``
    or ``mesh``) give one series per label; a variable over ``time`` alone is named by
    its ``target`` attribute, or by its quantity.
    """
    series: dict[str, tuple[xr.DataArray, str]] = {}
    for name, variable in dataset.data_vars.items():
        quantity = variable.attrs.get("quantity")
        if quantity not in quantities or "time" not in variable.dims:
            continue
        if variable.dims == ("time",):
            label = str(variable.attrs.get("target") or quantity or name)
            series[label] = (variable, quantities[quantity])
        elif variable.ndim == 2:
            (labels,) = (dim for dim in variable.dims if dim != "time")
            for label in variable[labels].values:
                one = variable.sel({labels: label})
                if np.any(np.isfinite(one.values)):  # NaN: a label not recorded
                    series[str(label)] = (one, quantities[quantity])
    t_s = float(dataset["t_s"]) if "t_s" in dataset else np.nan
    return series, t_s


def plot_speeds(datasets: Sequence[xr.Dataset], *, until: float | None = None) -> Figure:
    """Speeds against time, one column per run and one row per body (seed Figure 9).

    Parameters
    ----------
    datasets : sequence of xarray.Dataset
        Runs from :func:`pygear.analysis.time.transient.run_transient` (e.g. one per scene).
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
    return _plot_series(datasets, {"speed": "speed [rpm]"}, "Speeds", until)


def plot_loads(datasets: Sequence[xr.Dataset], *, until: float | None = None) -> Figure:
    """Mesh forces and the drive and load torques against time, one column per run and
    one row per mesh or torque (the loads a gearbox carries through a transient).

    Parameters and result as :func:`plot_speeds`.
    """
    return _plot_series(datasets, LOAD_QUANTITIES, "Loads", until)


def _plot_series(
    datasets: Sequence[xr.Dataset], quantities: dict[str, str], what: str, until: float | None
) -> Figure:
    """One column per run and one row per series of the quantities."""
    runs = [_run_series(dataset, quantities) for dataset in datasets]
    rows: list[str] = []
    for series, _ in runs:
        rows += [label for label in series if label not in rows]
    if not rows:
        names = ", ".join(f"Probe({q!r}, ...)" for q in quantities)
        raise ValueError(f"no {what.lower()} channels to plot (add {names} to the scene)")
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
    for column, (dataset, (series, t_s)) in enumerate(zip(datasets, runs)):
        for row, label in enumerate(rows):
            axis = axes[row, column]
            axis.set_xlim(start, end)
            if label in series:
                values, unit = series[label]
                shown = values.sel(time=slice(start, end))
                plot_envelope(axis, shown["time"].values, shown.values, linewidth=0.8)
                if np.isfinite(t_s):
                    axis.axvline(t_s, color="0.6", ls=":", lw=0.8)
                axis.set_ylabel(f"{label}\n{unit}", fontsize=8)
            else:
                axis.set_visible(False)
            axis.tick_params(labelsize=8)
            axis.grid(alpha=0.3)
        title = result_title(dataset.attrs, case=len(cases) > 1)
        if np.isfinite(t_s):
            title += f"\nt_s = {t_s:.4g} s (dotted)"
        axes[0, column].set_title(title, fontsize=8)
        axes[-1, column].set_xlabel("time [s]")
    figure.suptitle(f"{what} against time: {', '.join(cases)}", fontsize=10, y=1 - 0.08 / height)
    return figure
