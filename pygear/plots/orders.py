"""Figures of a computed order tracking (plotting only; the numbers come from
:func:`pygear.analysis.signals.order_tracking.track_orders`): the order-speed colour map with the
stages' mesh orders drawn as lines, the order spectrum of the whole record, and the
order slices against the reference speed."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

from .layout import fit_below_labels, new_figure, place_point_labels, result_title

__all__ = ["plot_order_map", "plot_order_slices", "plot_order_spectrum", "shown_order_limit"]

DPI = 110
"""Resolution the figures are drawn at [pixels per inch]; save them at the same."""

MESH_HARMONICS_SHOWN = 8
"""The figures reach past this many harmonics of the highest mesh order only when the
analysis itself stops earlier (the mesh harmonics are what a gear stage excites)."""

MARGINS_INCH = {"left": 0.9, "right": 0.3, "bottom": 0.6, "top": 0.85}
"""Fixed margins [in]: tick and axis labels, the figure's two-line title above the
panel's own."""


def shown_order_limit(result: xr.Dataset) -> float:
    """Highest order drawn: the analysis' ``max_order``, or just past the
    :data:`MESH_HARMONICS_SHOWN`-th harmonic of the highest mesh order if that is lower."""
    top = float(result.attrs["max_order"])
    mesh = np.asarray(result["mesh_order"].values, dtype=float)
    if mesh.size:
        top = min(top, (MESH_HARMONICS_SHOWN + 0.5) * float(mesh.max()))
    return top


def _figure(width: float, height: float, right: float = MARGINS_INCH["right"]) -> Figure:
    figure = new_figure(width, height, DPI)
    figure.subplots_adjust(
        left=MARGINS_INCH["left"] / width,
        right=1 - right / width,
        bottom=MARGINS_INCH["bottom"] / height,
        top=1 - MARGINS_INCH["top"] / height,
    )
    return figure


def _title(figure: Figure, what: str, result: xr.Dataset, run_attrs) -> None:
    figure.suptitle(
        f"{what} of {result.attrs['channel']}\n{result_title(run_attrs or result.attrs)}",
        fontsize=10,
        y=1 - 0.06 / figure.get_figheight(),
    )


def _order_label(result: xr.Dataset) -> str:
    return f"order of {result.attrs['reference']} [cycles per revolution]"


def _mesh_lines(ax, result: xr.Dataset, limit: float, color: str) -> float:
    """Dashed lines at every stage's mesh order and its harmonics up to ``limit``, each
    stage's fundamental named in rows at the top (clear of each other); returns the
    axes fraction of the lowest name's bottom."""
    labels = []
    for stage, order in zip(result["mesh_stage"].values, result["mesh_order"].values):
        harmonics = np.arange(1, int(limit // order) + 1) * order if order > 0 else []
        for value in harmonics:
            ax.axvline(value, color=color, lw=0.6, ls="--", alpha=0.7)
        if len(harmonics):
            labels.append((float(order), None, f"{stage} mesh {order:.4g}"))
    return place_point_labels(ax, labels, fontsize=7)


def _speed_axis(result: xr.Dataset) -> tuple[np.ndarray, str]:
    """Windows against the reference speed when it rises window by window (a run-up),
    else against the windows' centre times."""
    speed = np.asarray(result["speed"].values, dtype=float)
    if speed.size > 1 and np.all(np.diff(speed) > 0):
        return speed, f"speed of {result.attrs['reference']} [rpm]"
    return np.asarray(result["window_time"].values, dtype=float), "window centre [s]"


def plot_order_map(result: xr.Dataset, *, run_attrs: Mapping[str, Any] | None = None) -> Figure:
    """Order-speed colour map (log amplitude) with the mesh orders and their harmonics.

    Parameters
    ----------
    result : xarray.Dataset
        From :func:`pygear.analysis.signals.order_tracking.track_orders`.
    run_attrs : mapping, optional
        Attributes of the run (``case``, ``scene``, ``formulation``), for the title.
    """
    amplitude = result["order_map_amplitude"]
    orders = result["map_order"].values
    limit = shown_order_limit(result)
    keep = orders <= limit
    rows, label = _speed_axis(result)
    values = np.asarray(amplitude.values[:, keep], dtype=float)
    positive = values[values > 0]
    figure = _figure(9.0, 5.2, right=0.2)
    ax = figure.add_subplot(1, 1, 1)
    if positive.size:
        norm = LogNorm(vmin=max(positive.min(), positive.max() * 1e-5), vmax=positive.max())
        mesh = ax.pcolormesh(orders[keep], rows, np.maximum(values, norm.vmin), norm=norm)
        figure.colorbar(mesh, ax=ax, label=f"amplitude [{amplitude.attrs['units']}]", pad=0.02)
    ax.set_xlim(0, limit)
    _mesh_lines(ax, result, limit, "white")
    ax.set_xlabel(_order_label(result))
    ax.set_ylabel(label)
    ax.set_title(
        f"windows of {result.attrs['window_revolutions']:g} rev "
        f"(max order {float(result.attrs['max_order']):.4g})",
        fontsize=9,
        loc="left",
    )
    _title(figure, "Order map", result, run_attrs)
    return figure


def plot_order_spectrum(
    result: xr.Dataset, *, run_attrs: Mapping[str, Any] | None = None
) -> Figure:
    """Order spectrum of the whole record, with the mesh orders and their harmonics.

    Parameters
    ----------
    result : xarray.Dataset
        From :func:`pygear.analysis.signals.order_tracking.track_orders`.
    run_attrs : mapping, optional
        Attributes of the run (``case``, ``scene``, ``formulation``), for the title.
    """
    spectrum = result["order_amplitude"]
    orders = spectrum["order"].values
    limit = shown_order_limit(result)
    keep = orders <= limit
    shown = np.maximum(spectrum.values[keep], 1e-300)
    figure = _figure(9.0, 4.4)
    ax = figure.add_subplot(1, 1, 1)
    ax.semilogy(orders[keep], shown, lw=0.6)
    ax.set_xlim(0, limit)
    lowest = _mesh_lines(ax, result, limit, "tab:red")
    positive = shown[shown > 1e-300]
    if positive.size:
        floor = max(float(positive.min()), float(positive.max()) * 1e-8)
        fit_below_labels(ax, float(positive.max()), lowest, bottom=floor, log=True)
    ax.set_xlabel(_order_label(result))
    ax.set_ylabel(f"amplitude [{spectrum.attrs['units']}]")
    ax.set_title(
        f"whole record, {float(spectrum.attrs['revolutions']):.3g} revolutions",
        fontsize=9,
        loc="left",
    )
    _title(figure, "Order spectrum", result, run_attrs)
    return figure


def plot_order_slices(result: xr.Dataset, *, run_attrs: Mapping[str, Any] | None = None) -> Figure:
    """Amplitude of each tracked order against the reference speed.

    Parameters
    ----------
    result : xarray.Dataset
        From :func:`pygear.analysis.signals.order_tracking.track_orders`.
    run_attrs : mapping, optional
        Attributes of the run (``case``, ``scene``, ``formulation``), for the title.
    """
    slices = result["order_slice_amplitude"]
    rows, label = _speed_axis(result)
    figure = _figure(8.0, 4.4)
    ax = figure.add_subplot(1, 1, 1)
    for order, values in zip(slices["tracked_order"].values, slices.values):
        ax.plot(rows, values, marker=".", lw=0.8, label=f"order {order:.4g}")
    if slices.sizes["tracked_order"]:
        ax.legend(fontsize=7)
    else:
        ax.text(0.5, 0.5, "no tracked orders", transform=ax.transAxes, ha="center")
    ax.set_xlabel(label)
    ax.set_ylabel(f"amplitude [{slices.attrs['units']}]")
    ax.set_title("tracked orders", fontsize=9, loc="left")
    _title(figure, "Order slices", result, run_attrs)
    return figure
