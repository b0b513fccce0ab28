"""The Campbell diagram figure (plotting only; nothing here computes a result).

Each excitation line is named where it is clear of the names placed before it: from
the end of its visible part back along the line (:func:`pygear.plots.layout.place_first_clear`).
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from .layout import new_figure, place_first_clear, result_title
from .modal import CLASS_COLOURS

__all__ = ["plot_campbell"]

DPI = 130
"""Resolution the figure is drawn at [pixels per inch]; save it at the same."""

OTHER_COLOUR = "tab:gray"
"""Colour of mode classes without one of their own (mixed, planet-coupled, ...)."""

MARGINS_INCH = {"left": 0.8, "right": 2.4, "bottom": 0.6, "top": 0.75}
"""Fixed margins [in]: tick and axis labels, the key right of the axes, the two-line title."""

LABEL_SPOTS = 40
"""Places tried along an excitation line for its name, from the end back."""


def _dominant(values: np.ndarray) -> str:
    """The most frequent entry of a row of labels (ties: the first)."""
    labels, counts = np.unique(values.astype(str), return_counts=True)
    return str(labels[int(np.argmax(counts))])


def _label_spots(speeds: np.ndarray, line: np.ndarray, top: float) -> list[dict]:
    """Where an excitation line's name may go: points of its visible part from the end
    back, the name above-left of the point, then above-right."""
    fine = np.linspace(speeds[0], speeds[-1], 4 * LABEL_SPOTS)
    values = np.interp(fine, speeds, line)
    visible = np.flatnonzero(values <= top)[::-1]
    spots = []
    for k in visible[:: max(1, len(visible) // LABEL_SPOTS)]:
        for ha, dx in (("right", -2), ("left", 2)):
            spots.append(
                {
                    "xy": (fine[k], values[k]),
                    "xytext": (dx, 2),
                    "textcoords": "offset points",
                    "ha": ha,
                    "va": "bottom",
                }
            )
    return spots


def plot_campbell(campbell: xr.Dataset, *, scene: str | None = None) -> Figure:
    """Tracked frequencies against speed, coloured by mode class (solid: forward whirl,
    dashed: backward, dotted: neither), the excitation lines, the crossings (marker
    size by excitability) and the unstable ranges (shaded).

    Parameters
    ----------
    campbell : xarray.Dataset
        From :func:`pygear.analysis.modes.campbell.campbell_diagram`.
    scene : str, optional
        The scene, for the title when the attributes do not name one.

    Returns
    -------
    matplotlib.figure.Figure
        One panel, its key to the right.
    """
    speeds = campbell.speed.values
    frequency = campbell.frequency.values
    width, height = 11.0, 6.0
    figure = new_figure(width, height, DPI)
    ax = figure.add_subplot(1, 1, 1)
    figure.subplots_adjust(
        left=MARGINS_INCH["left"] / width,
        right=1 - MARGINS_INCH["right"] / width,
        bottom=MARGINS_INCH["bottom"] / height,
        top=1 - MARGINS_INCH["top"] / height,
    )
    top = max(float(np.nanmax(frequency)) if frequency.size else 1.0, 1.0) * 1.05
    ax.set_ylim(0, top)
    ax.set_xlim(speeds[0], speeds[-1])
    for m in range(frequency.shape[1]):
        if np.all(campbell.stability.values[:, m] == 3):
            continue  # a free rigid-body motion stays at 0 Hz
        cls = _dominant(campbell.mode_class.values[:, m])
        whirl = _dominant(campbell.whirl.values[:, m])
        style = {"forward": "-", "backward": "--"}.get(whirl, ":")
        ax.plot(
            speeds,
            frequency[:, m],
            style,
            color=CLASS_COLOURS.get(cls, OTHER_COLOUR),
            linewidth=1.2,
        )
    placed = []
    for name, order, kind in zip(
        campbell.excitation.values,
        campbell.excitation_order.values,
        campbell.excitation_kind.values,
    ):
        line = order * np.abs(speeds) / 60.0
        ax.plot(speeds, line, color="0.55" if kind == "mesh" else "0.8", linewidth=0.7)
        place_first_clear(
            ax, str(name), _label_spots(speeds, line, top), placed, fontsize=6, color="0.3"
        )
    if campbell.sizes.get("crossing", 0):
        share = np.nan_to_num(campbell.crossing_excitability.values)
        ax.scatter(
            campbell.crossing_speed.values,
            campbell.crossing_frequency.values,
            s=8 + 120 * share,
            facecolors="none",
            edgecolors="k",
            linewidths=0.7,
            zorder=3,
        )
    for start, stop in zip(campbell.unstable_start.values, campbell.unstable_stop.values):
        ax.axvspan(start, stop, color="tab:red", alpha=0.15, linewidth=0)
    ax.set_xlabel(f"speed of {campbell.attrs.get('reference', 'the reference')} [rpm]")
    ax.set_ylabel("frequency [Hz]")
    figure.suptitle(
        f"Campbell diagram\n{result_title(campbell.attrs, scene=scene)}",
        fontsize=10,
        y=1 - 0.08 / height,
    )
    modes = range(frequency.shape[1])
    classes = sorted({_dominant(campbell.mode_class.values[:, m]) for m in modes})
    handles = [Line2D([], [], color=CLASS_COLOURS.get(c, OTHER_COLOUR), label=c) for c in classes]
    handles += [
        Line2D([], [], color="k", linestyle="-", label="forward whirl"),
        Line2D([], [], color="k", linestyle="--", label="backward whirl"),
        Line2D([], [], color="0.55", lw=0.7, label="mesh excitation"),
        Line2D([], [], color="0.8", lw=0.7, label="shaft excitation"),
        Line2D(
            [],
            [],
            marker="o",
            color="k",
            linestyle="",
            markerfacecolor="none",
            label="crossing (size: excitability)",
        ),
    ]
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return figure
