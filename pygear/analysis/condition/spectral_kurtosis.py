"""Spectral kurtosis, the fast kurtogram and the real cepstrum of a time signal.

- :func:`spectral_kurtosis`: the STFT estimator of Antoni (2006), "The spectral
  kurtosis: a useful tool for characterising non-stationary signals", MSSP 20(2),
  282-307, ``SK(f) = <|X(t, f)|^4> / <|X(t, f)|^2>^2 - 2`` (time averages over the
  STFT frames): 0 for stationary Gaussian noise, -1 for a stationary sine, large
  and positive in the bands where transients (bearing or tooth impacts) live.
- :func:`fast_kurtogram`: the kurtosis of the complex envelope of the signal in
  every band of the 1/3-binary tree of Antoni (2007), "Fast computation of the
  kurtogram for the detection of transient faults", MSSP 21(1), 108-124: levels
  ``0, 1, 1.6, 2, 2.6, ...`` with bandwidth ``fs / 2^(level + 1)``.  Antoni computes
  each band's envelope with a tree of quasi-analytic FIR filters and decimators;
  here each band's complex envelope is the inverse FFT of the signal's one-sided
  spectrum restricted to that band (an ideal band-pass, and a decimation to one
  sample per bin, of the whole record at once).  The grid, the kurtosis and the
  choice of the best band are Antoni's; the filters are not, so values differ from
  his filter-bank implementation by the filters' transition bands.
- :func:`real_cepstrum`: ``ifft(log |fft x|)`` (Bogert, Healy & Tukey 1963; Randall,
  "Vibration-based Condition Monitoring", Wiley 2011, ch. 3), whose peaks at a
  quefrency ``tau`` reveal echoes and families of harmonics or sidebands spaced
  ``1 / tau``.

Signals are 1-D arrays of samples at a uniform ``sample_rate`` [Hz]; results are
xarray objects whose variables and coordinates carry ``units`` and ``long_name``.
The definitions and their sources are also in ``docs/condition_monitoring.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from ..signals.signal import SignalError
from .tsa_bands import is_integer

__all__ = [
    "DEFAULT_BAND_SAMPLES",
    "MIN_BAND_SAMPLES",
    "KurtogramBand",
    "fast_kurtogram",
    "kurtogram_levels",
    "real_cepstrum",
    "spectral_kurtosis",
]

#: Fewest spectrum bins (complex-envelope samples) a band of the default kurtogram
#: holds: the sampling spread of a Gaussian band's kurtosis, about 2 / sqrt(M), stays
#: below 2 / sqrt(256) = 0.125, so noise alone does not crown a narrow band.
DEFAULT_BAND_SAMPLES: int = 256
#: Fewest bins a band may hold at any depth asked for (spread 2 / sqrt(32) = 0.35).
MIN_BAND_SAMPLES: int = 32
#: Fraction of the record at each end that the kurtogram tapers (cosine) and leaves out
#: of every band's statistics.
EDGE_FRACTION: float = 1.0 / 16.0
#: Fewest STFT frames a spectral kurtosis averages over.
MIN_FRAMES: int = 2
#: Log-magnitudes are floored at this fraction of the largest magnitude (the FFT's
#: round-off level), so an exactly zero bin gives a finite cepstrum.
CEPSTRUM_FLOOR: float = float(np.finfo(float).eps)


# --------------------------------------------------------------------------- input checks


def _check_signal(signal: Any, minimum: int, why: str) -> np.ndarray:
    values = np.asarray(signal)
    if values.ndim != 1:
        raise SignalError(f"signal: must be a 1-D array of samples, got shape {values.shape}")
    if not np.issubdtype(values.dtype, np.number) or np.iscomplexobj(values):
        raise SignalError(f"signal: values must be real numbers, got dtype {values.dtype}")
    if values.size < minimum:
        raise SignalError(f"signal: only {values.size} samples; {why} needs at least {minimum}")
    values = values.astype(float)
    bad = int(np.count_nonzero(~np.isfinite(values)))
    if bad:
        raise SignalError(f"signal: contains {bad} NaN or inf values")
    return values


def _check_rate(sample_rate: Any) -> float:
    if isinstance(sample_rate, bool) or not isinstance(sample_rate, (int, float, np.number)):
        raise SignalError(f"sample_rate: must be a number in Hz, got {sample_rate!r}")
    if not np.isfinite(sample_rate) or sample_rate <= 0.0:
        raise SignalError(f"sample_rate: must be finite and > 0 Hz, got {sample_rate!r}")
    return float(sample_rate)


# --------------------------------------------------------------------------- spectral kurtosis


def _hann(length: int) -> np.ndarray:
    """Periodic (DFT-even) Hann window."""
    return 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(length) / length)


def spectral_kurtosis(
    signal: Any,
    sample_rate: float,
    *,
    window_length: int = 256,
    overlap: float = 0.5,
) -> xr.DataArray:
    """Spectral kurtosis by the short-time Fourier transform (Antoni 2006).

    ``SK(f) = <|X(t, f)|^4>_t / <|X(t, f)|^2>_t^2 - 2``, with ``X`` the STFT on
    periodic Hann windows of ``window_length`` samples, ``overlap`` of a window apart,
    and ``<.>_t`` the mean over the frames.  A stationary Gaussian signal gives 0 (its
    STFT values are circular complex Gaussian, ``E|X|^4 = 2 (E|X|^2)^2``), a
    stationary sine -1 in the bins it occupies (``|X|`` constant).  The DC and Nyquist
    bins hold real values, for which a Gaussian gives 1 instead of 0.  With ``K``
    independent frames the estimate of a Gaussian bin has a standard deviation of
    ``2 / sqrt(K)``.

    Parameters
    ----------
    signal : array_like
        Samples at ``sample_rate``, 1-D.
    sample_rate : float
        Sampling frequency [Hz].
    window_length : int, optional
        STFT window length in samples (frequency resolution ``sample_rate /
        window_length``).
    overlap : float, optional
        Fraction of a window shared by consecutive frames, ``0 <= overlap < 1``.

    Returns
    -------
    xarray.DataArray
        ``spectral_kurtosis`` over ``frequency`` [Hz] (``window_length // 2 + 1``
        bins); NaN in a bin with no energy at all.
    """
    rate = _check_rate(sample_rate)
    if not is_integer(window_length) or window_length < 4:
        raise SignalError(f"window_length: must be an integer >= 4, got {window_length!r}")
    if isinstance(overlap, bool) or not isinstance(overlap, (int, float, np.number)):
        raise SignalError(f"overlap: must be a fraction in [0, 1), got {overlap!r}")
    if not 0.0 <= overlap < 1.0:
        raise SignalError(f"overlap: must be a fraction in [0, 1), got {overlap!r}")
    step = max(1, int(round(window_length * (1.0 - overlap))))
    minimum = window_length + (MIN_FRAMES - 1) * step
    values = _check_signal(signal, minimum, f"{MIN_FRAMES} frames of {window_length} samples")
    starts = np.arange(0, values.size - window_length + 1, step)
    frames = values[starts[:, None] + np.arange(window_length)] * _hann(window_length)
    power = np.abs(np.fft.rfft(frames, axis=1)) ** 2
    second = np.mean(power, axis=0)
    fourth = np.mean(power**2, axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        kurtosis = np.where(second > 0.0, fourth / second**2 - 2.0, np.nan)
    frequency = np.arange(window_length // 2 + 1) * (rate / window_length)
    return xr.DataArray(
        kurtosis,
        dims="frequency",
        coords={"frequency": ("frequency", frequency, {"units": "Hz", "long_name": "frequency"})},
        name="spectral_kurtosis",
        attrs={
            "units": "1",
            "long_name": "spectral kurtosis (STFT estimator, Antoni 2006)",
            "window": "hann",
            "window_length": int(window_length),
            "overlap": float(overlap),
            "frames": int(starts.size),
            "sample_rate": rate,
        },
    )


# --------------------------------------------------------------------------- fast kurtogram


@dataclass(frozen=True)
class KurtogramBand:
    """One band of the kurtogram: where it lies and the kurtosis of its envelope."""

    centre_frequency: float
    """Centre of the band [Hz]."""
    bandwidth: float
    """Width of the band [Hz], ``sample_rate / 2^(level + 1)``."""
    level: float
    """Level in the 1/3-binary tree (0, 1, log2(3) = 1.58 (read 1.6), 2, ...)."""
    kurtosis: float
    """``<|c|^4> / <|c|^2>^2 - 2`` of the band's complex envelope ``c``."""

    @property
    def low(self) -> float:
        """Lower edge [Hz]."""
        return self.centre_frequency - 0.5 * self.bandwidth

    @property
    def high(self) -> float:
        """Upper edge [Hz]."""
        return self.centre_frequency + 0.5 * self.bandwidth


def kurtogram_levels(max_level: int) -> np.ndarray:
    """Levels of Antoni's (2007) 1/3-binary tree down to the integer ``max_level``.

    ``0, 1, 1 + log2(3) - 1, 2, 2 + log2(3) - 1, ..., max_level``: ``2 max_level``
    levels.  Level ``k`` splits ``[0, fs/2]`` into ``2^k`` bands of width
    ``fs / 2^(k+1)``; the level between ``k`` and ``k + 1`` into ``3 * 2^(k-1)`` bands
    (width ``fs / (3 * 2^k)``), which the kurtogram's figures label ``k.6``.
    """
    if not is_integer(max_level) or max_level < 1:
        raise SignalError(f"max_level: must be an integer >= 1, got {max_level!r}")
    third = math.log2(3.0) - 1.0
    levels = [0.0]
    for level in range(1, int(max_level) + 1):
        levels.append(float(level))
        if level < max_level:
            levels.append(level + third)
    return np.array(levels)


def _band_count(level: float) -> int:
    """Number of bands ``2^level`` at a level of the tree (an integer by construction)."""
    return int(round(2.0**level))


def _edge_taper(length: int, edge: int) -> np.ndarray:
    """Ones with a raised-cosine rise over the first and fall over the last ``edge``."""
    taper = np.ones(length)
    rise = 0.5 - 0.5 * np.cos(np.pi * (np.arange(edge) + 0.5) / edge)
    taper[:edge] = rise
    taper[length - edge :] = rise[::-1]
    return taper


def _envelope_kurtosis(band: np.ndarray, length: int, edge: int) -> float:
    """Kurtosis of the complex envelope whose spectrum is ``band`` (one-sided bins).

    The envelope is the band's inverse FFT: ``M`` samples, sample ``m`` at time
    ``m * length / M`` of the record; those within ``edge`` samples of an end are left
    out.
    """
    envelope = np.fft.ifft(band)
    time = np.arange(band.size) * (length / band.size)
    envelope = envelope[(time >= edge) & (time < length - edge)]
    power = envelope.real**2 + envelope.imag**2
    second = float(np.mean(power))
    if second <= 0.0:
        return float("nan")
    return float(np.mean(power**2)) / second**2 - 2.0


def fast_kurtogram(
    signal: Any, sample_rate: float, *, max_level: int | None = None
) -> tuple[xr.Dataset, KurtogramBand]:
    """The fast kurtogram (Antoni 2007) and its best band.

    The mean is removed, then for every level of :func:`kurtogram_levels` and every
    band ``[i, i + 1) * fs / 2^(level + 1)`` the band's complex envelope ``c`` is the
    inverse FFT of the one-sided spectrum's bins in that band (an ideal band-pass
    filter and a decimation to the band's own rate, in place of Antoni's filter bank),
    and its kurtosis ``<|c|^4> / <|c|^2>^2 - 2``: 0 for Gaussian noise, large where
    repeated transients dominate the band.

    FFT-domain filtering is circular: where the record's two ends meet, a tone that
    does not fit a whole number of periods into the record jumps, and that step would
    pose as a transient in every band near the tone.  So the record's ends are tapered
    (raised cosine over :data:`EDGE_FRACTION` of the record at each end) and the
    envelope samples there are left out of the statistics.  With ``M`` samples kept in
    a band of stationary Gaussian noise, those are close to independent circular
    complex Gaussians, and the estimate's standard deviation is about ``2 / sqrt(M)``
    (right-skewed for small ``M``).

    Parameters
    ----------
    signal : array_like
        Samples at ``sample_rate``, 1-D, at least ``4 * MIN_BAND_SAMPLES``.
    sample_rate : float
        Sampling frequency [Hz].
    max_level : int, optional
        Deepest (integer) level; default the deepest whose ``2^level`` bands each hold
        at least :data:`DEFAULT_BAND_SAMPLES` bins (and at least 1); at most the
        deepest whose bands hold :data:`MIN_BAND_SAMPLES`.

    Returns
    -------
    dataset : xarray.Dataset
        ``kurtosis`` over (``level``, ``frequency``): ``frequency`` is a grid of
        ``3 * 2^max_level`` cells across ``[0, fs/2]`` [Hz] (their centres), every
        band covering its cells, as in Antoni's figures; ``bandwidth`` [Hz] and
        ``band_count`` per level; the best band as attributes.
    best : KurtogramBand
        The band of largest kurtosis (the widest, then the lowest, of equal ones).
    """
    rate = _check_rate(sample_rate)
    values = _check_signal(signal, 4 * MIN_BAND_SAMPLES, "a kurtogram (levels 0 and 1)")
    deepest = int(math.floor(math.log2(values.size / MIN_BAND_SAMPLES))) - 1
    if max_level is None:
        max_level = max(1, int(math.floor(math.log2(values.size / DEFAULT_BAND_SAMPLES))) - 1)
    elif not is_integer(max_level) or not 1 <= max_level <= deepest:
        raise SignalError(
            f"max_level: must be an integer in 1..{deepest} for {values.size} samples "
            f"(each of the 2^max_level bands needs {MIN_BAND_SAMPLES} bins), got {max_level!r}"
        )
    levels = kurtogram_levels(max_level)
    edge = int(values.size * EDGE_FRACTION)
    spectrum = np.fft.rfft((values - np.mean(values)) * _edge_taper(values.size, edge))
    bins = np.arange(spectrum.size)
    cells = 3 * 2**max_level
    grid = np.empty((levels.size, cells))
    best: KurtogramBand | None = None
    for row, level in enumerate(levels):
        count = _band_count(level)
        width = rate / (2.0 * count)
        # bin j at frequency j fs / N lies in band floor(2 j count / N); Nyquist in the last
        band_of = np.minimum(2 * bins * count // values.size, count - 1)
        edges = np.searchsorted(band_of, np.arange(count + 1))
        kurtosis = np.array(
            [
                _envelope_kurtosis(spectrum[edges[i] : edges[i + 1]], values.size, edge)
                for i in range(count)
            ]
        )
        grid[row] = np.repeat(kurtosis, cells // count)
        top = int(np.nanargmax(kurtosis)) if np.any(np.isfinite(kurtosis)) else -1
        if top >= 0 and (best is None or kurtosis[top] > best.kurtosis):
            best = KurtogramBand((top + 0.5) * width, width, float(level), float(kurtosis[top]))
    if best is None:
        raise SignalError("signal: has no energy once its mean is removed (constant signal)")
    counts = np.array([_band_count(level) for level in levels])
    frequency = (np.arange(cells) + 0.5) * (rate / (2.0 * cells))
    dataset = xr.Dataset(
        {
            "kurtosis": xr.DataArray(
                grid,
                dims=("level", "frequency"),
                attrs={
                    "units": "1",
                    "long_name": "kurtosis of the band's complex envelope (fast kurtogram)",
                },
            )
        },
        coords={
            "level": ("level", levels, {"units": "1", "long_name": "level of the 1/3-binary tree"}),
            "frequency": (
                "frequency",
                frequency,
                {"units": "Hz", "long_name": "centre of a frequency cell"},
            ),
            "bandwidth": (
                "level",
                rate / (2.0 * counts),
                {"units": "Hz", "long_name": "bandwidth"},
            ),
            "band_count": ("level", counts, {"units": "1", "long_name": "bands at the level"}),
        },
        attrs={
            "sample_rate": rate,
            "max_level": int(max_level),
            "method": "FFT-domain ideal band-pass per band (not Antoni's filter bank)",
            "best_centre_frequency": best.centre_frequency,
            "best_bandwidth": best.bandwidth,
            "best_level": best.level,
            "best_kurtosis": best.kurtosis,
        },
    )
    return dataset, best


# --------------------------------------------------------------------------- cepstrum


def real_cepstrum(signal: Any, sample_rate: float) -> xr.DataArray:
    """Real cepstrum ``ifft(log |fft x|)`` over quefrency [s].

    A signal plus its echo ``x(t) + a x(t - tau)`` (``|a| < 1``) has the log-spectrum
    of ``x`` plus ``log |1 + a exp(-i w tau)| = sum_k (-1)^(k+1) (a^k / k) cos(k w tau)``,
    so its cepstrum holds ``a / 2`` at quefrency ``tau`` (and ``-a^2 / 4`` at
    ``2 tau``, ...) over the cepstrum of ``x`` (Bogert, Healy & Tukey 1963).
    Magnitudes are floored at :data:`CEPSTRUM_FLOOR` times the largest, the FFT's
    round-off level, so an exactly zero bin stays finite.

    Parameters
    ----------
    signal : array_like
        Samples at ``sample_rate``, 1-D, at least 16.
    sample_rate : float
        Sampling frequency [Hz].

    Returns
    -------
    xarray.DataArray
        ``real_cepstrum`` (dimensionless: a log of magnitude ratios, apart from the
        quefrency-0 term) over ``quefrency`` ``n / sample_rate`` [s], ``N`` values; the
        second half mirrors the first (negative quefrencies).
    """
    rate = _check_rate(sample_rate)
    values = _check_signal(signal, 16, "a cepstrum")
    magnitude = np.abs(np.fft.fft(values))
    peak = float(np.max(magnitude))
    if peak == 0.0:
        raise SignalError("signal: is all zeros; its cepstrum is undefined")
    cepstrum = np.fft.ifft(np.log(np.maximum(magnitude, CEPSTRUM_FLOOR * peak))).real
    quefrency = np.arange(values.size) / rate
    return xr.DataArray(
        cepstrum,
        dims="quefrency",
        coords={"quefrency": ("quefrency", quefrency, {"units": "s", "long_name": "quefrency"})},
        name="real_cepstrum",
        attrs={"units": "1", "long_name": "real cepstrum", "sample_rate": rate},
    )
