"""The Campbell diagram figure (plotting only; nothing here computes a result)."""

from __future__ import annotations

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from ..io import save_figure  # noqa: E402
from .modal import CLASS_COLOURS  # noqa: E402

__all__ = ["plot_campbell"]

OTHER_COLOUR = "tab:gray"
"""Colour of mode classes without one of their own (mixed, planet-coupled, ...)."""


def _dominant(values: np.ndarray) -> str:
    """The most frequent entry of a row of labels (ties: the first)."""
    labels, counts = np.unique(values.astype(str), return_counts=True)
    return str(labels[int(np.argmax(counts))])


def plot_campbell(campbell: xr.Dataset, path: str | os.PathLike) -> None:
    """Tracked frequencies against speed, coloured by mode class (solid: forward whirl,
    dashed: backward, dotted: neither), the excitation lines, the crossings (marker
    size by excitability) and the unstable ranges (shaded)."""
    speeds = campbell.speed.values
    frequency = campbell.frequency.values
    fig, ax = plt.subplots(figsize=(11, 6))
    top = max(float(np.nanmax(frequency)) if frequency.size else 1.0, 1.0) * 1.05
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
    for name, order, kind in zip(
        campbell.excitation.values,
        campbell.excitation_order.values,
        campbell.excitation_kind.values,
    ):
        line = order * np.abs(speeds) / 60.0
        ax.plot(speeds, line, color="0.55" if kind == "mesh" else "0.8", linewidth=0.7)
        visible = np.flatnonzero(line <= top)
        if visible.size:
            k = visible[-1]
            ax.annotate(str(name), (speeds[k], line[k]), fontsize=6, color="0.4")
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
    ax.set_ylim(0, top)
    ax.set_xlim(speeds[0], speeds[-1])
    ax.set_xlabel(f"speed of {campbell.attrs.get('reference', 'the reference')} [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"Campbell diagram: {campbell.attrs.get('case', '')}", fontsize=10)
    modes = range(frequency.shape[1])
    classes = sorted({_dominant(campbell.mode_class.values[:, m]) for m in modes})
    handles = [Line2D([], [], color=CLASS_COLOURS.get(c, OTHER_COLOUR), label=c) for c in classes]
    handles += [
        Line2D([], [], color="k", linestyle="-", label="forward whirl"),
        Line2D([], [], color="k", linestyle="--", label="backward whirl"),
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
    fig.tight_layout()
    save_figure(fig, path, dpi=130)
    plt.close(fig)
