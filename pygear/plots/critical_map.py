"""The undamped critical-speed map (plotting only; the map is computed by
:func:`pygear.analysis.modes.critical_speeds.critical_speed_map`)."""

from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from .layout import new_figure

__all__ = ["plot_critical_speed_map"]

DPI = 130
"""Resolution the figure is drawn at [pixels per inch]; save it at the same."""


def plot_critical_speed_map(critical: xr.Dataset) -> Figure:
    """Critical speeds against the bearings' radial stiffness on log axes: forward
    whirl as circles on solid lines, backward and planar as crosses."""
    figure = new_figure(8.0, 5.0, DPI)
    axes = figure.add_subplot(1, 1, 1)
    stiffness = critical.bearing_stiffness.values
    speeds = critical.critical_speed.values
    whirl = critical.whirl.values
    for j, ratio in enumerate(critical.line.values):
        for c in range(speeds.shape[2]):
            values = speeds[:, j, c]
            forward = whirl[:, j, c] == "forward"
            label = f"{c + 1}, line {ratio:g}x" if speeds.shape[1] > 1 else f"critical {c + 1}"
            axes.plot(stiffness, values, "-", lw=0.8, color=f"C{c % 10}", label=label)
            axes.plot(stiffness[forward], values[forward], "o", ms=3, color=f"C{c % 10}")
            axes.plot(stiffness[~forward], values[~forward], "x", ms=4, color=f"C{c % 10}")
    axes.set_xscale("log")
    if np.isfinite(speeds).any() and np.nanmin(speeds) > 0:
        axes.set_yscale("log")
    axes.set_xlabel("bearing radial stiffness [N/m]")
    axes.set_ylabel("critical speed [rpm]")
    axes.set_title(f"{critical.attrs['case']}: undamped critical-speed map (o forward, x backward)")
    axes.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    figure.subplots_adjust(left=0.1, right=0.78, bottom=0.11, top=0.92)
    figure.dpi = DPI
    return figure
