r"""Bearing diagnostics by envelope analysis (Randall & Antoni 2011, "Rolling element
bearing diagnostics - a tutorial", MSSP 25(2), 485-520, sec. 3-4).

The procedure:

1. :func:`prewhiten` - cepstral pre-whitening (Sawalhi & Randall 2011; Borghesani
   et al. 2013): the real cepstrum with every quefrency but zero set to zero, i.e. the
   spectrum's magnitude set to 1 with its phase kept, ``x_w = ifft(X / |X|)``.  Gear
   mesh harmonics and the structure's resonances, which stand far above the bearing's
   broadband impulses in the spectrum, are flattened to the same level as the rest;
   impulses survive (their phase lines up), so the bearing's modulation comes forward.
   Or first :func:`discrete_random_separation` (Antoni & Randall 2004): the gear's
   discrete components predicted from the signal a delay earlier and subtracted.
2. :func:`squared_envelope_spectrum` in a band: the band the fast kurtogram selects
   (:func:`~pygear.analysis.condition.spectral_kurtosis.fast_kurtogram`, Antoni 2007),
   no narrower than the lines to be seen need.  The squared envelope |a(t)|^2 of the
   band's analytic signal a, its mean removed, Hann-windowed; its amplitude spectrum
   shows a line at every repetition rate of the impulses (BPFO, BPFI, ...) and its
   harmonics, and sidebands at the rates that modulate them (Randall & Antoni, sec. 3.3:
   the squared envelope has a better signal-to-noise ratio than the envelope).
3. :func:`detect_lines` - the spectrum's largest bin within +-``tolerance`` (slip,
   1-2 %; at least one bin) of each harmonic k f and each sideband k f +- m f_mod,
   its SNR the ratio of that bin to the median of the bins around it (the local
   background) in dB (20 log10 of the amplitude ratio).  A line counts as detected when
   its fundamental and at least one more harmonic exceed ``threshold_db``.

Signals are 1-D arrays at a uniform ``sample_rate``; results are xarray objects with
``units`` and ``long_name``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from ..signals.signal import SignalError
from .spectral_kurtosis import _check_rate, _check_signal, fast_kurtogram

__all__ = [
    "DEFAULT_THRESHOLD_DB",
    "bearing_envelope_analysis",
    "detect_lines",
    "discrete_random_separation",
    "prewhiten",
    "squared_envelope_spectrum",
]

DEFAULT_THRESHOLD_DB: float = 10.0
"""SNR a line must exceed.  In the squared envelope spectrum of Gaussian noise a bin's
amplitude is Rayleigh distributed: it exceeds 10 dB (3.16 times) over the median with
probability exp(-(3.16 * 1.177)^2 / 2) = 1e-3; the largest of ~10 bins searched about a
line does so with ~1 %, and a fundamental and a second harmonic both with ~1e-4."""
DEFAULT_TOLERANCE: float = 0.02
"""Relative search half-width about a line: the 1-2 % slip of Randall & Antoni (2011)."""
BACKGROUND_BINS: int = 40
"""Bins on each side of a line whose median is the background (search window left out)."""


def _attrs(units: str, long_name: str) -> dict[str, str]:
    return {"units": units, "long_name": long_name}


def prewhiten(signal: Any, sample_rate: float) -> xr.DataArray:
    """Cepstral pre-whitening: ``ifft(X / |X|)``, the signal with a flat spectrum.

    Equivalent to setting every quefrency of the real cepstrum except zero to zero and
    going back with the signal's own phase (Sawalhi & Randall 2011).  Bins of zero
    magnitude stay zero.  The mean is removed first.

    Returns
    -------
    xarray.DataArray
        ``prewhitened`` over ``time`` [s]: dimensionless, unit spectral magnitude.
    """
    rate = _check_rate(sample_rate)
    values = _check_signal(signal, 16, "pre-whitening")
    spectrum = np.fft.rfft(values - np.mean(values))
    magnitude = np.abs(spectrum)
    floor = np.finfo(float).eps * max(float(np.max(magnitude)), np.finfo(float).tiny)
    flat = np.where(magnitude > floor, spectrum / np.maximum(magnitude, floor), 0.0)
    whitened = np.fft.irfft(flat, n=values.size)
    return xr.DataArray(
        whitened,
        dims="time",
        coords={"time": ("time", np.arange(values.size) / rate, _attrs("s", "time"))},
        name="prewhitened",
        attrs={"units": "1", "long_name": "cepstrally pre-whitened signal (unit magnitude)"},
    )


def discrete_random_separation(
    signal: Any, sample_rate: float, *, window: int = 4096, delay: int | None = None
) -> xr.Dataset:
    """Discrete-random separation (DRS; Antoni & Randall 2004, MSSP 18, 103-117).

    The discrete (deterministic) part of a signal, gear mesh harmonics and their
    sidebands, stays coherent with the signal ``delay`` samples earlier; the random part
    (noise, and a bearing's impacts, whose 1-2 % slip decorrelates them at the
    resonance's frequencies) does not.  The transfer function from the delayed to the
    present signal, H(f) = sum_k conj(D_k) X_k / sum_k |D_k|^2 over Hann-windowed
    segments of ``window`` samples (50 % overlap), filters the delayed signal into the
    discrete part; the random part is the rest.

    Parameters
    ----------
    signal : array_like
        Samples, 1-D, at least ``delay + 4 window``.
    sample_rate : float
        [Hz].
    window : int
        Segment length (the filter's frequency resolution is sample_rate / window).
    delay : int, optional
        Delay in samples, longer than the random part's memory (an impact's ring-down);
        default ``window // 4``.

    Returns
    -------
    xarray.Dataset
        ``random`` and ``discrete`` over ``time`` [s], in the signal's units.
    """
    from scipy.signal import fftconvolve

    rate = _check_rate(sample_rate)
    if not (isinstance(window, int) and window >= 64):
        raise SignalError(f"window: must be an integer >= 64 samples, got {window!r}")
    delay = window // 4 if delay is None else delay
    if not (isinstance(delay, int) and delay >= 1):
        raise SignalError(f"delay: must be an integer >= 1 sample, got {delay!r}")
    values = _check_signal(signal, delay + 4 * window, "a discrete-random separation")
    taper = 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(window) / window)
    cross = np.zeros(window, dtype=complex)
    power = np.zeros(window)
    for start in range(delay, values.size - window + 1, window // 2):
        present = np.fft.fft(taper * values[start : start + window])
        past = np.fft.fft(taper * values[start - delay : start - delay + window])
        cross += np.conj(past) * present
        power += np.abs(past) ** 2
    transfer = cross / np.maximum(power, np.finfo(float).tiny)
    response = np.fft.fftshift(np.fft.ifft(transfer).real)  # zero lag at window // 2
    delayed = np.concatenate((np.zeros(delay), values[:-delay]))
    discrete = fftconvolve(delayed, response)[window // 2 : window // 2 + values.size]
    time = ("time", np.arange(values.size) / rate, _attrs("s", "time"))
    return xr.Dataset(
        {
            "random": ("time", values - discrete, _attrs("1", "random part (DRS)")),
            "discrete": ("time", discrete, _attrs("1", "discrete part (DRS)")),
        },
        coords={"time": time},
        attrs={"window": window, "delay": delay, "sample_rate": rate},
    )


def squared_envelope_spectrum(
    signal: Any, sample_rate: float, band: tuple[float, float] | None = None
) -> xr.DataArray:
    """Amplitude spectrum of the squared envelope of ``signal`` in ``band``.

    The band's analytic signal a(t) is the inverse FFT of twice the one-sided spectrum's
    bins in [low, high) (an ideal band-pass, as the kurtogram's bands); |a|^2 minus its
    mean is Hann-windowed and its one-sided amplitude spectrum (2 |FFT| / sum(window))
    returned up to the band's width (no squared envelope of the band holds more).

    Parameters
    ----------
    signal : array_like
        Samples, 1-D.
    sample_rate : float
        [Hz].
    band : (float, float), optional
        [Hz], 0 <= low < high <= Nyquist; default the whole spectrum.

    Returns
    -------
    xarray.DataArray
        ``squared_envelope_spectrum`` over ``frequency`` [Hz], in the signal's units
        squared; ``band_low``, ``band_high`` as attributes.
    """
    rate = _check_rate(sample_rate)
    values = _check_signal(signal, 64, "an envelope spectrum")
    nyquist = 0.5 * rate
    low, high = (0.0, nyquist) if band is None else (float(band[0]), float(band[1]))
    if not (math.isfinite(low) and math.isfinite(high) and 0.0 <= low < high <= nyquist):
        raise SignalError(f"band: must satisfy 0 <= low < high <= {nyquist:g} Hz, got {band!r}")
    count = values.size
    spectrum = np.fft.fft(values - np.mean(values))
    frequency = np.fft.fftfreq(count, 1.0 / rate)
    keep = (frequency >= low) & (frequency < high) & (frequency > 0.0)
    analytic = np.fft.ifft(np.where(keep, 2.0 * spectrum, 0.0))
    squared = analytic.real**2 + analytic.imag**2
    window = 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(count) / count)
    amplitude = 2.0 * np.abs(np.fft.rfft((squared - np.mean(squared)) * window)) / np.sum(window)
    lines = np.arange(amplitude.size) * rate / count
    inside = lines <= high - low
    return xr.DataArray(
        amplitude[inside],
        dims="frequency",
        coords={"frequency": ("frequency", lines[inside], _attrs("Hz", "frequency"))},
        name="squared_envelope_spectrum",
        attrs={
            "units": "(signal units)^2",
            "long_name": "amplitude spectrum of the squared envelope in the band",
            "band_low": low,
            "band_high": high,
        },
    )


def _peak(spectrum: np.ndarray, step: float, target: float, tolerance: float):
    """(frequency, amplitude, SNR in dB) of the largest bin near ``target``."""
    centre = target / step
    half = max(1.0, tolerance * target / step)
    first, last = int(math.floor(centre - half)), int(math.ceil(centre + half))
    if first < 1 or last >= spectrum.size:
        return math.nan, math.nan, math.nan
    top = first + int(np.argmax(spectrum[first : last + 1]))
    around = np.r_[
        spectrum[max(1, first - BACKGROUND_BINS) : first],
        spectrum[last + 1 : last + 1 + BACKGROUND_BINS],
    ]
    background = float(np.median(around)) if around.size else math.nan
    amplitude = float(spectrum[top])
    snr = 20.0 * math.log10(amplitude / background) if background > 0 else math.inf
    return top * step, amplitude, snr


def detect_lines(
    spectrum: xr.DataArray,
    lines: Mapping[str, float],
    *,
    modulation: Mapping[str, float] | None = None,
    harmonics: int = 3,
    sidebands: int = 1,
    tolerance: float = DEFAULT_TOLERANCE,
    threshold_db: float = DEFAULT_THRESHOLD_DB,
) -> xr.Dataset:
    """Find each line, its harmonics and its sidebands in an envelope spectrum.

    Parameters
    ----------
    spectrum : xarray.DataArray
        An amplitude spectrum over a uniform ``frequency`` from 0 [Hz].
    lines : mapping
        ``{"BPFO": Hz, ...}``, the expected fundamentals.
    modulation : mapping, optional
        ``{"BPFI": Hz, ...}``: the rate whose sidebands k f +- m f_mod (m = 1 ..
        ``sidebands``) are looked for about each harmonic (0 or missing: none).
    harmonics : int
        Harmonics k = 1 .. ``harmonics`` looked for.
    tolerance : float
        Search half-width relative to the frequency looked for (at least one bin).
    threshold_db : float
        SNR a peak must exceed to count.

    Returns
    -------
    xarray.Dataset
        Over (``line``, ``harmonic``, ``sideband``; sideband 0 the harmonic itself, -m and
        +m its sidebands): ``expected_frequency``, ``found_frequency`` [Hz],
        ``amplitude``, ``snr`` [dB], ``found`` (SNR above the threshold); over ``line``:
        ``detected`` (fundamental and another harmonic found) and ``snr_fundamental``.
    """
    if not lines:
        raise SignalError("lines: give at least one bearing frequency to look for")
    if not (isinstance(harmonics, int) and harmonics >= 1):
        raise SignalError(f"harmonics: must be an integer >= 1, got {harmonics!r}")
    if not (isinstance(sidebands, int) and sidebands >= 0):
        raise SignalError(f"sidebands: must be an integer >= 0, got {sidebands!r}")
    values = np.asarray(spectrum.values, dtype=float)
    frequency = np.asarray(spectrum["frequency"].values, dtype=float)
    step = float(frequency[1] - frequency[0])
    names = list(lines)
    offsets = np.arange(-sidebands, sidebands + 1)
    shape = (len(names), harmonics, offsets.size)
    expected, found, amplitude, snr = (np.full(shape, np.nan) for _ in range(4))
    for i, name in enumerate(names):
        base = float(lines[name])
        if not (math.isfinite(base) and base > 0):
            raise SignalError(f"lines[{name!r}]: must be a positive frequency in Hz, got {base!r}")
        rate = float((modulation or {}).get(name, 0.0) or 0.0)
        for k in range(harmonics):
            for j, m in enumerate(offsets):
                if m != 0 and not rate > 0:
                    continue
                target = (k + 1) * base + m * rate
                expected[i, k, j] = target
                if target <= 0:
                    continue
                # sidebands are searched within the line's own slip, not the sideband's
                width = tolerance * (k + 1) * base / target
                found[i, k, j], amplitude[i, k, j], snr[i, k, j] = _peak(
                    values, step, target, min(width, 0.5 * rate / target) if m else tolerance
                )
    hit = np.nan_to_num(snr, nan=-np.inf) > threshold_db
    centre = sidebands
    detected = hit[:, 0, centre] & (np.count_nonzero(hit[:, 1:, centre], axis=1) >= 1)
    if harmonics == 1:
        detected = hit[:, 0, centre]
    hz = {"units": "Hz"}
    return xr.Dataset(
        {
            "expected_frequency": (
                ("line", "harmonic", "sideband"),
                expected,
                {**hz, "long_name": "expected"},
            ),
            "found_frequency": (
                ("line", "harmonic", "sideband"),
                found,
                {**hz, "long_name": "largest bin near it"},
            ),
            "amplitude": (
                ("line", "harmonic", "sideband"),
                amplitude,
                {"units": spectrum.attrs.get("units", "1"), "long_name": "amplitude of the bin"},
            ),
            "snr": (
                ("line", "harmonic", "sideband"),
                snr,
                {"units": "dB", "long_name": "20 log10(amplitude / median of the bins around)"},
            ),
            "found": (
                ("line", "harmonic", "sideband"),
                hit,
                {"units": "1", "long_name": f"SNR above {threshold_db:g} dB"},
            ),
            "detected": (
                ("line",),
                detected,
                {"units": "1", "long_name": "fundamental and another harmonic found"},
            ),
            "snr_fundamental": (
                ("line",),
                snr[:, 0, centre],
                {"units": "dB", "long_name": "SNR of the line"},
            ),
        },
        coords={
            "line": ("line", names, {"units": "1", "long_name": "bearing line"}),
            "harmonic": ("harmonic", np.arange(1, harmonics + 1), {"units": "1", "long_name": "k"}),
            "sideband": ("sideband", offsets, {"units": "1", "long_name": "m of k f + m f_mod"}),
        },
        attrs={"threshold_db": threshold_db, "tolerance": tolerance, "bin_width": step},
    )


def bearing_envelope_analysis(
    signal: Any,
    sample_rate: float,
    lines: Mapping[str, float],
    *,
    modulation: Mapping[str, float] | None = None,
    whiten: bool = True,
    separate: bool = False,
    band: tuple[float, float] | None = None,
    harmonics: int = 3,
    sidebands: int = 1,
    threshold_db: float = DEFAULT_THRESHOLD_DB,
) -> tuple[xr.DataArray, xr.Dataset]:
    """Separation, pre-whitening, kurtogram band, squared envelope spectrum, detection.

    ``separate``: the random part of :func:`discrete_random_separation` first (gear
    components removed); ``whiten``: then :func:`prewhiten`.

    The band, unless given, is the fast kurtogram's best band among those at least
    ``(harmonics + 1) * max(lines + modulation)`` wide (the widest line family to be
    seen must fit in the band's squared envelope spectrum, Randall & Antoni sec. 4).

    Returns
    -------
    spectrum : xarray.DataArray
        The squared envelope spectrum (:func:`squared_envelope_spectrum`), with the band,
        its kurtosis and ``prewhitened`` as attributes.
    detection : xarray.Dataset
        :func:`detect_lines` of it.
    """
    rate = _check_rate(sample_rate)
    values = _check_signal(signal, 1024, "a bearing envelope analysis")
    if separate:
        values = discrete_random_separation(values, rate).random.values
    record = prewhiten(values, rate).values if whiten else values - np.mean(values)
    kurtosis = math.nan
    if band is None:
        widest = max(
            (harmonics + 1) * (float(f) + float((modulation or {}).get(k, 0.0) or 0.0))
            for k, f in lines.items()
        )
        if not widest < 0.5 * rate:
            raise SignalError(
                f"lines: {harmonics} harmonics of {max(lines.values()):g} Hz do not fit below "
                f"the Nyquist frequency {0.5 * rate:g} Hz"
            )
        levels = int(math.floor(math.log2(rate / (2.0 * widest))))
        deepest = int(math.floor(math.log2(values.size / 32))) - 1
        _, best = fast_kurtogram(record, rate, max_level=max(1, min(levels, deepest)))
        band, kurtosis = (best.low, best.high), best.kurtosis
    spectrum = squared_envelope_spectrum(record, rate, band)
    spectrum.attrs.update(prewhitened=int(whiten), separated=int(separate), band_kurtosis=kurtosis)
    if whiten:
        spectrum.attrs["units"] = "1"
    detection = detect_lines(
        spectrum, lines, modulation=modulation, harmonics=harmonics, sidebands=sidebands,
        threshold_db=threshold_db,
    )  # fmt: skip
    detection.attrs.update(band_low=band[0], band_high=band[1], prewhitened=int(whiten))
    return spectrum, detection
