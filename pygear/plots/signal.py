"""Figures of a run's signal analysis (the seed's Figs. 10-14); plotting only.

Cheap by construction: the waveform and the spectra are cut to the extremes of each
pixel column (:mod:`pygear.plots.decimation`), each spectrum only up to its panel's
limit, and the panels sit at fixed margins instead of a layout search.
"""

from __future__ import annotations

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..analysis.analyze import RunAnalysis  # noqa: E402
from ..io import save_figure  # noqa: E402
from .decimation import plot_envelope  # noqa: E402

__all__ = ["plot_run_analysis"]

DPI = 110
"""Resolution the figure is drawn and saved at [pixels per inch]."""


def _label_peaks(ax, table, limit: float, count: int = 4) -> None:
    shown = table[table.frequency_hz <= limit].head(count)
    for row in shown.itertuples():
        text = row.identification if row.identification != "unidentified" else ""
        ax.annotate(
            f"{row.frequency_hz:.0f} Hz\n{text}",
            (row.frequency_hz, row.amplitude),
            fontsize=6,
            ha="center",
            va="bottom",
        )


def plot_run_analysis(
    analysis: RunAnalysis, path: str | os.PathLike, *, zoom_hz: float = 2500.0
) -> None:
    """Waveform, spectrum, zoomed spectrum, DRA and envelope spectrum of one channel."""
    signal = analysis.signal
    units = signal.attrs.get("units", "")
    spectra = analysis.spectra
    frequency = spectra.frequency.values
    fig, axes = plt.subplots(5, 1, figsize=(8, 12), dpi=DPI)
    # fixed margins: room for the tick labels, y labels and titles of every panel
    fig.subplots_adjust(left=0.11, right=0.97, bottom=0.05, top=0.97, hspace=0.42)
    time = signal.time.values
    axes[0].set_xlim(time[0], time[-1])
    plot_envelope(axes[0], time, signal.values, linewidth=0.4)
    axes[0].set_xlabel("time [s]")
    axes[0].set_ylabel(f"[{units}]")
    axes[0].set_title(f"(a) waveform of {analysis.channel}", fontsize=9)
    panels = [
        ("spectrum", frequency.max(), "(b) spectrum"),
        ("spectrum", zoom_hz, f"(c) spectrum below {zoom_hz:g} Hz"),
        ("dra_spectrum", zoom_hz, f"(d) DRA, band {spectra.attrs.get('band_hz')} Hz"),
        ("envelope_spectrum", zoom_hz, "(e) envelope spectrum"),
    ]
    for ax, (name, limit, title) in zip(axes[1:], panels):
        keep = slice(0, int(np.searchsorted(frequency, limit, side="right")))
        ax.set_xlim(0, limit)
        plot_envelope(ax, frequency[keep], spectra[name].values[keep], linewidth=0.6)
        ax.set_ylabel(f"amplitude [{units}]")
        ax.set_title(title, fontsize=9)
        _label_peaks(ax, analysis.peaks[name], limit)
    axes[-1].set_xlabel("frequency [Hz]")
    save_figure(fig, path, dpi=DPI)  # atomic: no half-written figure
    plt.close(fig)
