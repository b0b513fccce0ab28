"""Figures of modal results (plotting only; nothing here computes a result): the modal
energy shares of every mode, a mode's shape (:mod:`pygear.plots.mode_shape`) and the
natural frequencies against a stiffness."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .layout import new_figure, result_title
from .mode_shape import plot_mode_shape

__all__ = ["plot_frequency_sweep", "plot_modal_energy", "plot_mode_shape"]

DPI = 120
"""Resolution the figures are drawn at [pixels per inch]; save them at the same."""

CLASS_COLOURS = {
    "rotational": "tab:red",
    "translational": "tab:blue",
    "planet": "tab:green",
    "axial": "tab:orange",
    "tilting": "tab:purple",
}

ENERGY_PANEL_INCH = (2.6, 1.45)
"""Width and height of one mode's bar panel [in]."""
ENERGY_MARGINS_INCH = {"left": 0.6, "right": 0.1, "top": 0.75, "bottom": 0.75, "gap": 0.85}
"""Fixed margins [in]: the y label, the figure's two-line title, the key of the groups
below, and between rows a panel's x label and the next row's two-line titles."""


def _distinct_modes(modal: xr.Dataset) -> list[int]:
    """Mode indices with non-zero frequency, one per repeated frequency."""
    chosen, last = [], None
    for m, f in enumerate(modal.frequency.values):
        if f <= 0 or (last is not None and abs(f - last) <= 1e-6 * f):
            continue
        chosen.append(m)
        last = f
    return chosen


def _mode_name(modal: xr.Dataset, m: int) -> str:
    """``stage: class index``, e.g. ``stage1: rotational 2``."""
    name = f"{modal.mode_class.values[m]} {int(modal.class_index.values[m])}"
    if "stage_name" in modal:
        name = f"{modal.stage_name.values[m]}: {name}"
    return name


def plot_modal_energy(modal: xr.Dataset, *, scene: str | None = None) -> Figure:
    """Bars of the modal kinetic-energy shares of every distinct mode (paper Figs. 4, 5).

    Parameters
    ----------
    modal : xarray.Dataset
        From :func:`pygear.analysis.modes.modal.modal_analysis`.
    scene : str, optional
        The scene the model was assembled for, for the title when the attributes do
        not name one.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per distinct non-zero frequency, titled with the stage holding most
        of the mode's energy, its class and frequency; one colour per energy group.
    """
    modes = _distinct_modes(modal)
    columns = 4
    rows = max(1, math.ceil(len(modes) / columns))
    panel_width, panel_height = ENERGY_PANEL_INCH
    margins = ENERGY_MARGINS_INCH
    width = margins["left"] + columns * panel_width + margins["right"]
    height = margins["top"] + margins["bottom"] + rows * panel_height + (rows - 1) * margins["gap"]
    figure = new_figure(width, height, DPI)
    axes = figure.subplots(rows, columns, sharey=True, squeeze=False)
    # fixed margins [in]: a layout search (tight_layout) drew the figure twice and was
    # most of its cost
    figure.subplots_adjust(
        left=margins["left"] / width,
        right=1 - margins["right"] / width,
        bottom=margins["bottom"] / height,
        top=1 - margins["top"] / height,
        wspace=0.12,
        hspace=margins["gap"] / panel_height,
    )
    groups = [str(g) for g in modal.energy_group.values]
    colours = [f"C{n % 10}" for n in range(len(groups))]
    positions = np.arange(1, len(groups) + 1)
    for ax, m in zip(axes.flat, modes):
        ax.bar(positions, modal.energy_share.values[m], color=colours)
        ax.set_title(f"{_mode_name(modal, m)}\n{modal.frequency.values[m]:.1f} Hz", fontsize=8)
        ax.set_xticks(positions)
        ax.set_ylim(0, 1)
        ax.tick_params(labelsize=7)
        ax.set_xlabel("energy group [-]", fontsize=7, labelpad=1)
    for ax in axes[:, 0]:
        ax.set_ylabel("share of kinetic energy [-]", fontsize=7)
    for ax in list(axes.flat)[len(modes) :]:
        ax.set_visible(False)
    figure.legend(
        handles=[
            Patch(color=c, label=f"{n}: {g}") for n, (g, c) in enumerate(zip(groups, colours), 1)
        ],
        loc="lower center",
        ncol=len(groups),
        fontsize=7,
        frameon=False,
    )
    figure.suptitle(
        f"Modal kinetic energy by group\n{result_title(modal.attrs, scene=scene)}",
        fontsize=9,
        y=1 - 0.05 / height,  # its two lines above the first row's titles at any height
    )
    return figure


def plot_frequency_sweep(sweep: xr.Dataset, *, scene: str | None = None) -> Figure:
    """Natural frequencies against a stiffness parameter, coloured by class (paper Fig. 7).

    Parameters
    ----------
    sweep : xarray.Dataset
        From :func:`pygear.analysis.modes.sensitivity.frequency_sweep`.
    scene : str, optional
        The scene the models were assembled for, for the title when the attributes do
        not name one.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per formulation, sharing the frequency axis.
    """
    formulations = list(sweep.formulation.values) if "formulation" in sweep.dims else [None]
    width, height = 5.5 * len(formulations), 5.0
    figure = new_figure(width, height, DPI)
    axes = figure.subplots(1, len(formulations), sharey=True, squeeze=False)
    figure.subplots_adjust(
        left=0.9 / width, right=1 - 0.2 / width, bottom=0.6 / height, top=1 - 0.9 / height
    )
    values = sweep.value.values
    parameter = sweep.attrs.get("parameter", "parameter")
    for ax, formulation in zip(axes.flat, formulations):
        data = sweep.sel(formulation=formulation) if formulation is not None else sweep
        frequency = data.frequency.values
        classes = data.mode_class.values
        for m in range(frequency.shape[1]):
            ax.plot(values, frequency[:, m], color="0.75", lw=0.8, zorder=1)
        for cls, colour in CLASS_COLOURS.items():
            chosen = classes == cls
            if chosen.any():
                ax.scatter(
                    np.broadcast_to(values[:, None], frequency.shape)[chosen],
                    frequency[chosen],
                    s=6,
                    color=colour,
                    zorder=2,
                )
        ax.set_yscale("log")
        ax.set_xscale("log")
        ax.set_xlabel(f"{parameter} [{sweep.value.attrs.get('units', '-')}]")
        ax.set_title(f"{formulation or sweep.attrs.get('formulation', '')} formulation", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
    axes.flat[0].set_ylabel("natural frequency [Hz]")
    handles = [
        Line2D([], [], color=c, label=k)
        for k, c in CLASS_COLOURS.items()
        if k in set(np.ravel(sweep.mode_class.values))
    ]
    axes.flat[-1].legend(handles=handles, fontsize=8)
    figure.suptitle(
        f"Natural frequencies against {parameter}\n"
        f"{result_title(sweep.attrs, scene=scene)}",  # each panel names its formulation
        fontsize=10,
        y=1 - 0.08 / height,
    )
    return figure
