"""Figures of a run's signal analysis (the seed's Figs. 10-14); plotting only."""

from __future__ import annotations

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ..analysis.analyze import RunAnalysis  # noqa: E402
from ..io import save_figure  # noqa: E402

__all__ = ["plot_run_analysis"]


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
    fig, axes = plt.subplots(5, 1, figsize=(8, 12))
    axes[0].plot(signal.time.values, signal.values, lw=0.4)
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
        keep = frequency <= limit
        ax.plot(frequency[keep], spectra[name].values[keep], lw=0.6)
        ax.set_xlim(0, limit)
        ax.set_ylabel(f"amplitude [{units}]")
        ax.set_title(title, fontsize=9)
        _label_peaks(ax, analysis.peaks[name], limit)
    axes[-1].set_xlabel("frequency [Hz]")
    fig.tight_layout()
    save_figure(fig, path, dpi=110)  # atomic: no half-written figure
    plt.close(fig)
