"""Figures of a computed order tracking (plotting only; the numbers come from
:func:`pygear.analysis.order_tracking.track_orders`): the order-speed colour map with the
stages' mesh orders drawn as lines, the order spectrum of the whole record, and the
order slices against the reference speed."""

from __future__ import annotations

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402

from ..io import save_figure  # noqa: E402

__all__ = ["plot_order_map", "plot_order_slices", "plot_order_spectrum", "shown_order_limit"]

MESH_HARMONICS_SHOWN = 8
"""The figures reach past this many harmonics of the highest mesh order only when the
analysis itself stops earlier (the mesh harmonics are what a gear stage excites)."""


def shown_order_limit(result: xr.Dataset) -> float:
    """Highest order drawn: the analysis' ``max_order``, or just past the
    :data:`MESH_HARMONICS_SHOWN`-th harmonic of the highest mesh order if that is lower."""
    top = float(result.attrs["max_order"])
    mesh = np.asarray(result["mesh_order"].values, dtype=float)
    if mesh.size:
        top = min(top, (MESH_HARMONICS_SHOWN + 0.5) * float(mesh.max()))
    return top


def _mesh_lines(ax, result: xr.Dataset, limit: float, color: str) -> None:
    """Dashed lines at every stage's mesh order and its harmonics up to ``limit``."""
    for stage, order in zip(result["mesh_stage"].values, result["mesh_order"].values):
        harmonics = np.arange(1, int(limit // order) + 1) * order if order > 0 else []
        for h, value in enumerate(harmonics, start=1):
            ax.axvline(value, color=color, lw=0.6, ls="--", alpha=0.7)
            if h == 1:
                ax.annotate(
                    f"{stage} mesh {order:.4g}",
                    (value, 1.0),
                    xycoords=("data", "axes fraction"),
                    fontsize=7,
                    ha="left",
                    va="bottom",
                )


def _speed_axis(result: xr.Dataset) -> tuple[np.ndarray, str]:
    """Windows against the reference speed when it rises window by window (a run-up),
    else against the windows' centre times."""
    speed = np.asarray(result["speed"].values, dtype=float)
    if speed.size > 1 and np.all(np.diff(speed) > 0):
        return speed, f"speed of {result.attrs['reference']} [rpm]"
    return np.asarray(result["window_time"].values, dtype=float), "window centre [s]"


def plot_order_map(result: xr.Dataset, path: str | os.PathLike) -> None:
    """Order-speed colour map (log amplitude) with the mesh orders and their harmonics."""
    amplitude = result["order_map_amplitude"]
    orders = result["map_order"].values
    limit = shown_order_limit(result)
    keep = orders <= limit
    rows, label = _speed_axis(result)
    values = np.asarray(amplitude.values[:, keep], dtype=float)
    positive = values[values > 0]
    fig, ax = plt.subplots(figsize=(9, 5))
    if positive.size:
        norm = LogNorm(vmin=max(positive.min(), positive.max() * 1e-5), vmax=positive.max())
        mesh = ax.pcolormesh(orders[keep], rows, np.maximum(values, norm.vmin), norm=norm)
        fig.colorbar(mesh, ax=ax, label=f"amplitude [{amplitude.attrs['units']}]")
    _mesh_lines(ax, result, limit, "white")
    ax.set_xlabel(f"order of {result.attrs['reference']}")
    ax.set_ylabel(label)
    ax.set_title(
        f"{result.attrs['channel']}: windows of {result.attrs['window_revolutions']:g} rev "
        f"(max order {float(result.attrs['max_order']):.4g})",
        fontsize=9,
        pad=14,
    )
    fig.tight_layout()
    save_figure(fig, path, dpi=110)  # atomic: no half-written figure
    plt.close(fig)


def plot_order_spectrum(result: xr.Dataset, path: str | os.PathLike) -> None:
    """Order spectrum of the whole record, with the mesh orders and their harmonics."""
    spectrum = result["order_amplitude"]
    orders = spectrum["order"].values
    limit = shown_order_limit(result)
    keep = orders <= limit
    fig, ax = plt.subplots(figsize=(9, 4))
    ax.semilogy(orders[keep], np.maximum(spectrum.values[keep], 1e-300), lw=0.6)
    _mesh_lines(ax, result, limit, "tab:red")
    ax.set_xlim(0, limit)
    ax.set_xlabel(f"order of {result.attrs['reference']}")
    ax.set_ylabel(f"amplitude [{spectrum.attrs['units']}]")
    ax.set_title(
        f"order spectrum of {result.attrs['channel']} over "
        f"{float(spectrum.attrs['revolutions']):.3g} revolutions",
        fontsize=9,
        pad=14,
    )
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def plot_order_slices(result: xr.Dataset, path: str | os.PathLike) -> None:
    """Amplitude of each tracked order against the reference speed."""
    slices = result["order_slice_amplitude"]
    rows, label = _speed_axis(result)
    fig, ax = plt.subplots(figsize=(8, 4))
    for order, values in zip(slices["tracked_order"].values, slices.values):
        ax.plot(rows, values, marker=".", lw=0.8, label=f"order {order:.4g}")
    if slices.sizes["tracked_order"]:
        ax.legend(fontsize=7)
    else:
        ax.text(0.5, 0.5, "no tracked orders", transform=ax.transAxes, ha="center")
    ax.set_xlabel(label)
    ax.set_ylabel(f"amplitude [{slices.attrs['units']}]")
    ax.set_title(f"order slices of {result.attrs['channel']}", fontsize=9)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)
