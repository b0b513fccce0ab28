"""Figures of a run's signal analysis (the seed's Figs. 10-14); plotting only.

Cheap by construction: the waveform and the spectra are cut to the extremes of each
pixel column (:mod:`pygear.plots.decimation`), each spectrum only up to its panel's
limit, and the panels sit at fixed margins instead of a layout search.  Peak labels
sit in rows at the top of their panel, each clear of the others and joined to its peak
by a leader line (:func:`pygear.plots.layout.place_point_labels`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ..analysis.signals.analyze import RunAnalysis
from .decimation import plot_envelope
from .layout import (
    fit_below_labels,
    new_figure,
    place_point_labels,
    result_title,
    scaled_units,
)

__all__ = ["plot_run_analysis"]

DPI = 110
"""Resolution the figure is drawn at [pixels per inch]; save it at the same."""

PANEL_INCH, GAP_INCH, TOP_INCH, BOTTOM_INCH = 1.8, 0.8, 0.75, 0.45
"""Fixed layout [in]: each panel's height, the gap between panels (an x label and the
next panel's title), the room for the figure's two-line title, the last x label."""


def _channel_title(channel: str, quantity: str) -> str:
    """``acceleration of planetary.sun.theta_z`` from a channel name ``kind:label`` (a
    grouped run variable's series), else the name with its quantity."""
    kind, _, label = channel.partition(":")
    if label:
        return f"{kind.replace('_', ' ')} of {label}"
    return f"{channel} ({quantity})"


def _peak_labels(table, limit: float, count: int, scale: float) -> list[tuple[float, float, str]]:
    """The ``count`` strongest peaks of ``table`` up to ``limit`` as (frequency,
    amplitude times ``scale``, text); an identified peak is named below its frequency."""
    shown = table[table.frequency_hz <= limit].head(count)
    labels = []
    for row in shown.itertuples():
        text = f"{row.frequency_hz:.0f} Hz"
        if row.identification != "unidentified":
            text += f"\n{row.identification}"
        labels.append((float(row.frequency_hz), scale * float(row.amplitude), text))
    return labels


def plot_run_analysis(
    analysis: RunAnalysis,
    *,
    run_attrs: Mapping[str, Any] | None = None,
    zoom_hz: float = 2500.0,
    peaks: int = 4,
) -> Figure:
    """Waveform, spectrum, zoomed spectrum, DRA and envelope spectrum of one channel.

    Parameters
    ----------
    analysis : RunAnalysis
        From :func:`pygear.analysis.signals.analyze.analyze_channel`.
    run_attrs : mapping, optional
        Attributes of the run the channel comes from (``case``, ``scene``,
        ``formulation``), for the title.
    zoom_hz : float
        Upper limit of the zoomed panels [Hz].
    peaks : int
        Strongest peaks labelled per spectrum panel.

    Returns
    -------
    matplotlib.figure.Figure
        Five panels, (a) the whole waveform and (b)-(e) the spectra, each with its
        strongest peaks labelled.
    """
    signal = analysis.signal
    units = signal.attrs.get("units", "-")
    quantity = str(signal.attrs.get("quantity", "value")).replace("_", " ")
    spectra = analysis.spectra
    frequency = spectra.frequency.values
    panels = 5
    height = TOP_INCH + BOTTOM_INCH + panels * PANEL_INCH + (panels - 1) * GAP_INCH
    figure = new_figure(8.0, height, DPI)
    axes = figure.subplots(panels, 1)
    figure.subplots_adjust(
        left=0.11,
        right=0.97,
        bottom=BOTTOM_INCH / height,
        top=1 - TOP_INCH / height,
        hspace=GAP_INCH / PANEL_INCH,
    )
    time = signal.time.values
    scale, shown_units = scaled_units(float(np.max(np.abs(signal.values), initial=0.0)), units)
    axes[0].set_xlim(time[0], time[-1])
    plot_envelope(axes[0], time, scale * signal.values, linewidth=0.4)
    axes[0].set_xlabel("time [s]")
    axes[0].set_ylabel(f"{quantity} [{shown_units}]")
    axes[0].set_title("(a) waveform", fontsize=9, loc="left")
    band = spectra.attrs.get("band_hz")
    band_text = f"{band[0]:g}-{band[1]:g} Hz" if band is not None and len(band) == 2 else "?"
    spectrum_panels = [
        ("spectrum", frequency.max(), "(b) spectrum"),
        ("spectrum", zoom_hz, f"(c) spectrum below {zoom_hz:g} Hz"),
        ("dra_spectrum", zoom_hz, f"(d) demodulated resonance, band {band_text}"),
        ("envelope_spectrum", zoom_hz, "(e) envelope spectrum"),
    ]
    for ax, (name, limit, title) in zip(axes[1:], spectrum_panels):
        keep = slice(0, int(np.searchsorted(frequency, limit, side="right")))
        values = spectra[name].values[keep]
        scale, shown_units = scaled_units(float(np.max(values, initial=0.0)), units)
        ax.set_xlim(0, limit)
        plot_envelope(ax, frequency[keep], scale * values, linewidth=0.6)
        labels = _peak_labels(analysis.peaks[name], limit, peaks, scale)
        lowest = place_point_labels(ax, labels)
        fit_below_labels(ax, scale * float(np.max(values, initial=0.0)), lowest)
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel(f"amplitude [{shown_units}]")
        ax.set_title(title, fontsize=9, loc="left")
    after = spectra.attrs.get("after_s")
    figure.suptitle(
        f"{_channel_title(analysis.channel, quantity)}\n"
        f"{result_title(run_attrs or {})}"
        + (f"; spectra after {after:g} s" if after is not None else ""),
        fontsize=10,
        y=1 - 0.08 / height,
    )
    return figure
