"""Figures of rotor results (plotting only; nothing here computes a result): the
Campbell diagram of a rotor or drivetrain model with its 1x lines and critical speeds,
the Bode and polar plots of an unbalance response, and a rotor run's orbit radii over
its speed."""

from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from .layout import new_figure

__all__ = ["plot_rotor_campbell", "plot_rotor_run", "plot_unbalance_response"]

DPI = 130
"""Resolution the figures are drawn at [pixels per inch]; save them at the same."""

WHIRL_STYLES = {"forward": "-", "backward": "--", "planar": ":", "none": ":"}
"""Line style of a tracked mode by its whirl at the highest speed."""


def plot_rotor_campbell(campbell: xr.Dataset) -> Figure:
    """Tracked frequencies over speed (solid forward, dashed backward whirl), the shafts'
    1x lines and the critical speeds (circles)."""
    figure = new_figure(8.0, 5.0, DPI)
    axes = figure.add_subplot(1, 1, 1)
    speeds = campbell.speed.values
    frequency = campbell.frequency.values
    for m in range(frequency.shape[1]):
        style = WHIRL_STYLES.get(str(campbell.whirl.values[-1, m]), "-")
        axes.plot(speeds, frequency[:, m], style, lw=1.2, label=f"mode {m + 1}")
    ratios = sorted({float(r.split(": ")[1]) for r in campbell.attrs["speed_ratios"].split(", ")})
    for ratio in ratios:
        axes.plot(speeds, abs(ratio) * np.abs(speeds) / 60.0, color="k", lw=0.8)
    axes.plot(
        campbell.critical_speed.values,
        campbell.critical_frequency.values,
        "o",
        mfc="none",
        color="tab:red",
        label="critical speed",
    )
    top = float(np.nanmax(frequency)) * 1.05 if frequency.size else 1.0
    axes.set_ylim(0.0, top)
    axes.set_xlabel("rotor speed [rpm]")
    axes.set_ylabel("frequency [Hz]")
    axes.set_title(f"{campbell.attrs['case']}: Campbell diagram (solid forward, dashed backward)")
    axes.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    figure.subplots_adjust(left=0.09, right=0.78, bottom=0.11, top=0.92)
    figure.dpi = DPI
    return figure


def plot_unbalance_response(response: xr.Dataset) -> Figure:
    """Bode (amplitude and phase of x over speed) and polar (x in the complex plane)
    plots of every disc and bearing."""
    figure = new_figure(11.0, 5.5, DPI)
    amplitude = figure.add_subplot(2, 2, 1)
    phase = figure.add_subplot(2, 2, 3, sharex=amplitude)
    polar = figure.add_subplot(1, 2, 2)
    speeds = response.speed.values
    for location in response.location.values:
        chosen = response.sel(location=location)
        amplitude.semilogy(speeds, chosen.x_amplitude.values, label=str(location))
        phase.plot(speeds, chosen.x_phase.values)
        radians = np.radians(chosen.x_phase.values)
        values = chosen.x_amplitude.values
        polar.plot(values * np.cos(radians), values * np.sin(radians))
    amplitude.set_ylabel("|x| [m]")
    amplitude.legend(fontsize="small")
    phase.set_ylabel("phase of x [deg]")
    phase.set_xlabel("rotor speed [rpm]")
    polar.set_xlabel("Re x [m]")
    polar.set_ylabel("Im x [m]")
    polar.set_aspect("equal", adjustable="datalim")
    polar.set_title("polar plot of x")
    figure.suptitle(f"{response.attrs['case']}: unbalance {response.attrs['unbalance']}")
    figure.subplots_adjust(left=0.08, right=0.97, bottom=0.1, top=0.9, hspace=0.3, wspace=0.25)
    figure.dpi = DPI
    return figure


def plot_rotor_run(run: xr.Dataset) -> Figure:
    """Each disc's orbit radius over the rotor speed of a rotor transient (a run-up's
    passage through its critical speeds), and over time."""
    figure = new_figure(8.0, 6.0, DPI)
    by_speed = figure.add_subplot(2, 1, 1)
    by_time = figure.add_subplot(2, 1, 2)
    for disc in run.disc.values:
        radius = run.orbit_radius.sel(disc=disc).values * 1e6
        by_speed.plot(run.speed.values, radius, lw=0.8, label=str(disc))
        by_time.plot(run.time.values, radius, lw=0.8, label=str(disc))
    by_speed.set_xlabel("rotor speed [rpm]")
    by_time.set_xlabel("time [s]")
    for axes in (by_speed, by_time):
        axes.set_ylabel("orbit radius [um]")
        axes.grid(True, alpha=0.3)
    by_speed.legend(loc="best", fontsize=8)
    figure.suptitle(f"{run.attrs['case']}: scene {run.attrs['scene']}")
    figure.subplots_adjust(left=0.1, right=0.97, bottom=0.08, top=0.92, hspace=0.35)
    figure.dpi = DPI
    return figure
