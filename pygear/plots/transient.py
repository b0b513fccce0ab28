"""Figure of a run-up's speeds, like the seed's Figure 9 (plotting only; nothing computes).

Each speed is cut to the extremes of each pixel column (:mod:`pygear.plots.decimation`)
and the panels sit at fixed margins, so the figure costs the same for any record length.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from .decimation import plot_envelope  # noqa: E402

__all__ = ["plot_speeds"]

DPI = 120
"""Resolution the figure is drawn and saved at [pixels per inch]."""

MARGINS_INCH = {"left": 0.95, "right": 0.15, "bottom": 0.5, "top": 0.3}
"""Fixed margins [in]: two-line y labels with tick labels, the time axis, the titles."""


def _speed_channels(dataset: xr.Dataset) -> list[str]:
    return [
        name
        for name, variable in dataset.data_vars.items()
        if variable.attrs.get("quantity") == "speed" and variable.dims == ("time",)
    ]


def plot_speeds(
    datasets: Sequence[xr.Dataset],
    path: str | os.PathLike,
    *,
    until: float = 2.0,
    format: str | None = None,
) -> None:
    """Speeds against time, one column per run and one row per body (seed Figure 9).

    Parameters
    ----------
    datasets : sequence of xarray.Dataset
        Runs from :func:`pygear.analysis.transient.run_transient` (e.g. one per formulation).
    path : path-like
        Target image.
    until : float
        Last time shown [s] (the paper shows the first 2 s).
    format : str, optional
        Image format when ``path`` has no telling suffix.
    """
    rows = []
    for dataset in datasets:
        rows += [name for name in _speed_channels(dataset) if name not in rows]
    if not rows:
        raise ValueError("no speed channels to plot (add Probe('speed', body) to the scene)")
    width, height = 4.5 * len(datasets), 2.2 * len(rows)
    figure, axes = plt.subplots(
        len(rows), len(datasets), figsize=(width, height), dpi=DPI, sharex=True, squeeze=False
    )
    figure.subplots_adjust(
        left=MARGINS_INCH["left"] / width,
        right=1 - MARGINS_INCH["right"] / width,
        bottom=MARGINS_INCH["bottom"] / height,
        top=1 - MARGINS_INCH["top"] / height,
        wspace=0.35,
        hspace=0.25,
    )
    for column, dataset in enumerate(datasets):
        shown = dataset.sel(time=slice(0.0, until))
        t_s = float(dataset.t_s) if "t_s" in dataset else np.nan
        for row, name in enumerate(rows):
            axis = axes[row, column]
            if name in shown:
                time = shown.time.values
                axis.set_xlim(time[0], time[-1])
                plot_envelope(axis, time, shown[name].values, linewidth=0.8)
                if np.isfinite(t_s):
                    axis.axvline(t_s, color="0.6", ls=":", lw=0.8)
                axis.set_ylabel(f"{shown[name].attrs.get('target', name)}\n[rpm]", fontsize=8)
            else:
                axis.set_visible(False)
            if row == 0:
                axis.set_title(
                    f"{dataset.attrs.get('formulation', '')}: t_s = {t_s:.4g} s", fontsize=9
                )
            axis.grid(alpha=0.3)
        axes[-1, column].set_xlabel("time [s]")
    figure.savefig(path, dpi=DPI, format=format)
    plt.close(figure)
