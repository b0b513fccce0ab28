"""Signal analysis of a run: spectrum, envelope spectrum and demodulated resonance
analysis of one channel, with the strongest peaks named (the seed's Figs. 10-14).

Computing only: figures are drawn by :mod:`pygear.plots.signal`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
import xarray as xr

from .channels import channel_series, run_channels
from .peaks import find_peaks
from .signal import (
    SignalError,
    amplitude_spectrum,
    demodulated_resonance,
    envelope_spectrum,
    fast_length,
)

__all__ = ["RunAnalysis", "analyze_channel", "pick_channel"]


@dataclass
class RunAnalysis:
    """Spectra of one channel and their peak tables."""

    channel: str
    signal: xr.DataArray
    spectra: xr.Dataset
    peaks: dict[str, pd.DataFrame]

    def summary(self) -> dict:
        """The peak tables as plain data (for ``--json``)."""
        return {
            "channel": self.channel,
            **{
                name: [
                    {
                        "frequency_hz": float(row.frequency_hz),
                        "amplitude": float(row.amplitude),
                        "what": str(row.identification),
                        "near_natural_frequency": str(row.near_natural_frequency),
                    }
                    for row in table.itertuples()
                ]
                for name, table in self.peaks.items()
            },
        }


def pick_channel(run: xr.Dataset, channel: str | None) -> str:
    """The channel to analyse: the one named, else the run's first acceleration.

    A channel is named as :mod:`pygear.analysis.signals.channels` reads it: ``<kind>:<label>``
    (``acceleration:planetary.sun.theta_z``), the label alone when one channel has it,
    or the name of a variable over ``time`` alone.

    Raises
    ------
    SignalError
        Naming ``--channel`` and the channels the run holds.
    """
    channels = run_channels(run)
    if channel is not None:
        series = channel_series(run, channel)
        if series is None:
            raise SignalError(
                f"--channel: {channel!r} is not a time series of this run "
                f"(channels: {', '.join(channels) or 'none'})"
            )
        return str(series.attrs["channel"])
    for name, (variable, _, _) in channels.items():
        units = str(run[variable].attrs.get("units", ""))
        if "s^2" in units or "s-2" in units:
            return name
    if not channels:
        raise SignalError("the run holds no time series to analyse")
    return next(iter(channels))


def analyze_channel(
    run: xr.Dataset,
    channel: str | None = None,
    *,
    band: Sequence[float] = (5000.0, 10000.0),
    after: float = 1.0,
    natural_frequencies: Mapping[str, float] | xr.Dataset | None = None,
    mesh_frequency: float | Mapping[str, float] | None = None,
    carrier_frequency: float | None = None,
    peaks: int = 10,
) -> RunAnalysis:
    """Spectrum, envelope spectrum and DRA of one channel after ``after`` seconds.

    Parameters
    ----------
    run : xarray.Dataset
        A run with channels along a uniform ``time`` coordinate.
    channel : str, optional
        Channel name (default: :func:`pick_channel`).
    band : (float, float)
        DRA band [Hz] (the paper's 5-10 kHz).
    after : float
        Start-up to skip [s].
    natural_frequencies, mesh_frequency, carrier_frequency
        References that name the peaks (modal Dataset or mapping; Hz, or Hz per
        stage; Hz).
    peaks : int
        Peaks per table.
    """
    name = pick_channel(run, channel)
    signal = channel_series(run, name)
    # the record from `after`, its last few samples dropped for a fast FFT length
    kept = int(np.count_nonzero(signal["time"].values >= after))
    signal = signal.isel(time=slice(signal.sizes["time"] - kept, None))
    signal = signal.isel(time=slice(0, fast_length(kept)))
    spectrum = amplitude_spectrum(signal, after=after, remove_mean=True)
    envelope = envelope_spectrum(signal, after=after)
    dra = demodulated_resonance(signal, band, after=after)
    spectra = xr.Dataset(
        {"spectrum": spectrum, "envelope_spectrum": envelope.rename(frequency="frequency")}
    )
    spectra["dra_spectrum"] = dra
    spectra.attrs.update({"channel": name, "after_s": after, "band_hz": list(band)})
    bin_width = float(spectrum.frequency[1] - spectrum.frequency[0])
    options = dict(
        natural_frequencies=natural_frequencies,
        mesh_frequency=mesh_frequency,
        sideband_frequency=carrier_frequency,
        min_frequency=3 * bin_width,
    )
    tables = {
        "spectrum": find_peaks(spectrum, peaks, **options),
        "envelope_spectrum": find_peaks(envelope, peaks, **options),
        "dra_spectrum": find_peaks(dra, peaks, **options),
    }
    for key, table in tables.items():  # drop round-off ripples far below the largest peak
        if len(table):
            tables[key] = table[table.amplitude >= 1e-6 * table.amplitude.max()]
    return RunAnalysis(name, signal, spectra, tables)
