"""Figures of rolling bearings, plotting only: the static load distribution around the
ring (:func:`pygear.analysis.condition.bearing_load.load_distribution`) and the squared
envelope spectrum with the bearing lines looked for and found
(:mod:`pygear.analysis.condition.bearing_envelope`).

Every function returns a :class:`matplotlib.figure.Figure` on an Agg canvas, not
registered with pyplot (save it with :func:`pygear.io.save_figure`).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..analysis.signals.signal import SignalError

__all__ = ["LINE_COLOURS", "plot_bearing_envelope", "plot_load_distribution"]

DPI = 110
"""Resolution the figures are drawn at [pixels per inch]."""
LINE_COLOURS = ("tab:red", "tab:blue", "tab:green", "tab:purple", "tab:orange", "tab:brown")
"""Colours of the bearing lines, in the detection's order (cycled)."""


def _figure(width: float, height: float) -> Figure:
    figure = Figure(figsize=(width, height), dpi=DPI)
    FigureCanvasAgg(figure)
    return figure


def plot_load_distribution(distribution: xr.Dataset, title: str | None = None) -> Figure:
    """Element loads around the ring as radial stems, the load zone shaded.

    Parameters
    ----------
    distribution : xarray.Dataset
        :func:`~pygear.analysis.condition.bearing_load.load_distribution`'s result.
    title : str, optional
        Figure title (default: the bearing, its load and Q_max).
    """
    for name in ("element_load", "element_angle"):
        if name not in distribution:
            raise SignalError(f"distribution: needs {name!r} (a load_distribution result)")
    figure = _figure(5.5, 5.5)
    ax = figure.add_subplot(projection="polar")
    ax.set_theta_zero_location("S")  # the load points down, as a shaft's weight
    angles = np.radians(distribution.element_angle.values)
    loads = distribution.element_load.values
    ax.vlines(angles, 0.0, loads, colors="tab:blue", linewidth=2.0, label="element load Q_j")
    ax.plot(angles, loads, "o", color="tab:blue", markersize=3)
    zone = math.radians(float(distribution.attrs.get("load_zone_deg", 0.0))) / 2.0
    if zone > 0:
        top = float(np.max(loads)) * 1.1 if np.max(loads) > 0 else 1.0
        ax.fill_between(np.linspace(-zone, zone, 91), 0.0, top, color="tab:orange", alpha=0.2,
                        label=f"load zone {math.degrees(2 * zone):.0f} deg")  # fmt: skip
    ax.set_xlabel("element angle from the load direction")
    ax.set_ylabel("Q [N]", labelpad=28)
    ax.legend(loc="upper right", bbox_to_anchor=(1.12, 1.12), fontsize="small")
    attrs = distribution.attrs
    ax.set_title(
        title
        or f"{attrs.get('bearing', 'bearing')}: F_r = {attrs.get('radial_load', math.nan):.4g} N, "
        f"Q_max = {attrs.get('max_element_load', math.nan):.4g} N",
        fontsize="medium",
    )
    return figure


def plot_bearing_envelope(
    spectrum: xr.DataArray,
    detection: xr.Dataset,
    *,
    max_frequency: float | None = None,
    title: str | None = None,
) -> Figure:
    """The squared envelope spectrum with every bearing line's harmonics marked.

    Expected harmonics are dashed vertical lines in the line's colour; a harmonic found
    above the threshold gets a dot on its peak and its SNR in dB.

    Parameters
    ----------
    spectrum : xarray.DataArray
        :func:`~pygear.analysis.condition.bearing_envelope.squared_envelope_spectrum`.
    detection : xarray.Dataset
        :func:`~pygear.analysis.condition.bearing_envelope.detect_lines` of it.
    max_frequency : float, optional
        Right end of the axis [Hz] (default: 1.2 times the highest harmonic looked for).
    title : str, optional
        Figure title.
    """
    if "frequency" not in spectrum.dims or "found_frequency" not in detection:
        raise SignalError("spectrum and detection: need a spectrum over frequency and a "
                          "detect_lines result")  # fmt: skip
    centre = detection.sel(sideband=0)
    expected = centre.expected_frequency.values
    top = max_frequency or 1.2 * float(np.nanmax(expected))
    frequency = spectrum.frequency.values
    shown = frequency <= top
    figure = _figure(9.0, 4.0)
    ax = figure.add_subplot()
    ax.plot(frequency[shown], spectrum.values[shown], color="0.3", linewidth=0.8)
    for n, line in enumerate(detection.line.values):
        colour = LINE_COLOURS[n % len(LINE_COLOURS)]
        row = centre.sel(line=line)
        state = "found" if bool(detection.detected.sel(line=line)) else "not found"
        for k, where in enumerate(row.expected_frequency.values):
            ax.axvline(where, color=colour, linestyle="--", linewidth=0.8,
                       label=f"{line} ({state})" if k == 0 else None)  # fmt: skip
            if bool(row.found.values[k]):
                at, height = float(row.found_frequency[k]), float(row.amplitude[k])
                ax.plot(at, height, "o", color=colour, markersize=4)
                ax.annotate(
                    f"{float(row.snr[k]):.0f} dB",
                    (at, height),
                    xytext=(3, 3),
                    textcoords="offset points",
                    fontsize="x-small",
                    color=colour,
                )
    ax.set_xlim(0.0, top)
    ax.set_xlabel("frequency [Hz]")
    units = str(spectrum.attrs.get("units", "1"))
    ax.set_ylabel(f"squared envelope [{'-' if units == '1' else units}]")
    low, high = detection.attrs.get("band_low"), detection.attrs.get("band_high")
    band = f", band {low:.0f} .. {high:.0f} Hz" if low is not None and high is not None else ""
    whitened = ", pre-whitened" if detection.attrs.get("prewhitened") else ""
    ax.set_title(title or f"squared envelope spectrum{band}{whitened}", fontsize="medium")
    ax.legend(fontsize="small", loc="upper right")
    return figure
