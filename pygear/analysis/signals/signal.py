"""Spectra, envelopes, demodulated resonance and order analysis on FFTW.

Every function takes an :class:`xarray.DataArray` with a uniform ``time``
coordinate in seconds and a ``units`` attribute, and returns xarray objects
whose variables and coordinates all carry ``units`` and ``long_name``.
Extra dimensions (channels, DOFs, ...) are allowed: each series along
``time`` is analysed separately.

FFTs run through FFTW (pyFFTW).  Plans are built once per
``(length, kind, threads, planner_effort)`` and kept in a small
least-recently-used cache; FFTW wisdom is kept in-process between plans.
Peak picking and identification live in :mod:`pygear.analysis.signals.peaks` (which imports
this module, never the reverse).

This module is longer than 600 lines because the spectra, envelopes and order
analysis share one FFTW plan cache and one record preparation (checks of the time
coordinate and units); splitting the cache off is the next step if it grows.
"""

from __future__ import annotations

import functools
import math
import threading
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from .fftw import pyfftw

__all__ = [
    "DEFAULT_PLANNER_EFFORT",
    "DEFAULT_THREADS",
    "MIN_SAMPLES",
    "fast_length",
    "SignalError",
    "amplitude_spectrum",
    "clear_plan_cache",
    "demodulated_resonance",
    "envelope",
    "envelope_spectrum",
    "export_wisdom",
    "import_wisdom",
    "order_spectrum",
    "plan_cache_info",
]

#: Default number of FFTW threads (``threads=None`` uses it; set it to change).
DEFAULT_THREADS: int = 1
#: Default FFTW planner effort (``planner_effort=None`` uses it).
DEFAULT_PLANNER_EFFORT: str = "FFTW_ESTIMATE"
#: Fewest samples a record may have (after ``after`` is applied).
MIN_SAMPLES: int = 16
#: Largest relative deviation of a time step from the mean step.
UNIFORM_TOLERANCE: float = 1e-6
#: Most FFTW plans kept at once (each holds its own aligned buffers).
PLAN_CACHE_SIZE: int = 8

_PLANNER_EFFORTS = ("FFTW_ESTIMATE", "FFTW_MEASURE", "FFTW_PATIENT", "FFTW_EXHAUSTIVE")
_RECTANGULAR = ("boxcar", "rectangular", "rect", "none")


class SignalError(ValueError):
    """Invalid input to a signal-analysis function (names the parameter)."""


# --------------------------------------------------------------------------- FFTW plans


@dataclass
class _Plan:
    fftw: pyfftw.FFTW
    input: np.ndarray
    output: np.ndarray
    lock: threading.Lock


_plans: OrderedDict[tuple[int, str, int, str], _Plan] = OrderedDict()
_plans_lock = threading.Lock()
_plan_stats = {"hits": 0, "misses": 0}
_wisdom: tuple[bytes, ...] | None = None


def _fft_options(threads: int | None, planner_effort: str | None) -> tuple[int, str]:
    threads = DEFAULT_THREADS if threads is None else threads
    effort = DEFAULT_PLANNER_EFFORT if planner_effort is None else planner_effort
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1:
        raise SignalError(f"threads: must be an integer >= 1, got {threads!r}")
    if effort not in _PLANNER_EFFORTS:
        raise SignalError(f"planner_effort: must be one of {_PLANNER_EFFORTS}, got {effort!r}")
    return int(threads), effort


def _get_plan(length: int, kind: str, threads: int, effort: str) -> _Plan:
    """Return the cached plan for ``kind`` ("rfft" or "ifft"), building it once."""
    global _wisdom
    key = (length, kind, threads, effort)
    with _plans_lock:
        plan = _plans.get(key)
        if plan is not None:
            _plans.move_to_end(key)
            _plan_stats["hits"] += 1
            return plan
        _plan_stats["misses"] += 1
        if _wisdom is not None:
            pyfftw.import_wisdom(_wisdom)
        if kind == "rfft":
            source = pyfftw.empty_aligned(length, dtype="float64")
            target = pyfftw.empty_aligned(length // 2 + 1, dtype="complex128")
            direction = "FFTW_FORWARD"
        else:
            source = pyfftw.empty_aligned(length, dtype="complex128")
            target = pyfftw.empty_aligned(length, dtype="complex128")
            direction = "FFTW_BACKWARD"
        fftw = pyfftw.FFTW(source, target, direction=direction, flags=(effort,), threads=threads)
        _wisdom = pyfftw.export_wisdom()
        plan = _Plan(fftw, source, target, threading.Lock())
        _plans[key] = plan
        while len(_plans) > PLAN_CACHE_SIZE:
            _plans.popitem(last=False)
        return plan


def plan_cache_info() -> dict[str, Any]:
    """Return the plan cache state: ``entries``, ``keys``, ``hits`` and ``misses``.

    Keys are ``(length, kind, threads, planner_effort)``.
    """
    with _plans_lock:
        return {"entries": len(_plans), "keys": list(_plans), **_plan_stats}


def clear_plan_cache() -> None:
    """Drop every cached plan and reset the hit/miss counters (wisdom is kept)."""
    with _plans_lock:
        _plans.clear()
        _plan_stats.update(hits=0, misses=0)


def export_wisdom() -> tuple[bytes, ...]:
    """Return the current FFTW wisdom (pass it to :func:`import_wisdom` later)."""
    return pyfftw.export_wisdom()


def import_wisdom(wisdom: tuple[bytes, ...]) -> None:
    """Load FFTW wisdom (from :func:`export_wisdom`) and keep it for future plans."""
    global _wisdom
    pyfftw.import_wisdom(wisdom)
    _wisdom = tuple(wisdom)


def _rfft(values: np.ndarray, weights: np.ndarray | None, threads: int, effort: str) -> np.ndarray:
    """Real-to-complex FFT of ``values * weights`` (a fresh array, length n//2+1)."""
    plan = _get_plan(values.shape[-1], "rfft", threads, effort)
    with plan.lock:
        if weights is None:
            plan.input[:] = values
        else:
            np.multiply(values, weights, out=plan.input)
        plan.fftw.execute()
        return plan.output.copy()


def _envelope_from_rfft(
    spectrum: np.ndarray, length: int, keep: slice | None, threads: int, effort: str
) -> np.ndarray:
    """Magnitude of the analytic signal whose one-sided spectrum is ``spectrum``.

    Negative frequencies are zeroed and positive ones doubled (DC and Nyquist
    kept once), then a complex inverse FFT.  With ``keep`` only those bins
    (all strictly between DC and Nyquist) survive, doubled: a band-pass.
    """
    plan = _get_plan(length, "ifft", threads, effort)
    with plan.lock:
        full = plan.input
        full[:] = 0.0
        if keep is None:
            half = (length + 1) // 2  # first bin that is not a positive frequency
            full[0] = spectrum[0]
            np.multiply(spectrum[1:half], 2.0, out=full[1:half])
            if length % 2 == 0:
                full[length // 2] = spectrum[length // 2]
        else:
            np.multiply(spectrum[keep], 2.0, out=full[keep])
        plan.fftw.execute()
        magnitude = np.abs(plan.output)
    magnitude *= 1.0 / length
    return magnitude


# --------------------------------------------------------------------------- input checks


@dataclass
class _Record:
    """A validated signal: rows of samples along time, and what to rebuild it."""

    signal: xr.DataArray  # trimmed, time moved to the last dimension
    rows: np.ndarray  # shape (series, samples)
    time: np.ndarray
    sample_rate: float
    order: tuple  # original dimension order

    @property
    def length(self) -> int:
        return self.rows.shape[1]


def fast_length(count: int) -> int:
    """The longest record length <= ``count`` whose only prime factors are 2, 3, 5 and 7
    (FFTW's fast sizes); within 0.2 % of ``count`` above 1000 samples, else ``count``.

    A run sampled from t = 1 s to 5 s at 40 kHz has 160 001 samples, a prime: FFTW
    plans and runs it by Rader's algorithm in 150 ms and 18 ms, against 12 ms and 1 ms
    for 160 000.  The analyses of a run (:mod:`pygear.analysis.signals.analyze`) drop the few
    samples at the record's end; the functions here take a record as it is.
    """
    if count < 1000:
        return count
    for length in range(count, int(count * 0.998), -1):
        rest = length
        for prime in (2, 3, 5, 7):
            while rest % prime == 0:
                rest //= prime
        if rest == 1:
            return length
    return count


def _prepare(signal: Any, after: float | None, name: str = "signal") -> _Record:
    """Validate ``signal`` and return its samples with time >= ``after``."""
    if not isinstance(signal, xr.DataArray):
        raise SignalError(f"{name}: must be an xarray.DataArray, got {type(signal).__name__}")
    if "time" not in signal.dims or "time" not in signal.coords:
        raise SignalError(
            f"time: {name} needs a 'time' dimension with a coordinate in seconds "
            f"(it has dimensions {tuple(signal.dims)} and coordinates {tuple(signal.coords)})"
        )
    if "units" not in signal.attrs:
        raise SignalError(f"{name}: needs a 'units' attribute (e.g. 'm/s^2')")
    if not np.issubdtype(signal.dtype, np.number) or np.iscomplexobj(signal):
        raise SignalError(f"{name}: values must be real numbers, got dtype {signal.dtype}")
    time = np.asarray(signal["time"].values)
    if not np.issubdtype(time.dtype, np.number):
        raise SignalError(f"time: coordinate must be numeric seconds, got dtype {time.dtype}")
    time = time.astype(float)
    if after is not None:
        if not isinstance(after, (int, float, np.number)) or not np.isfinite(after):
            raise SignalError(f"after: must be a finite time in seconds, got {after!r}")
        kept = np.flatnonzero(time >= after)
        signal = signal.isel(time=kept)
        time = time[kept]
    count = time.size
    if count < MIN_SAMPLES:
        where = f"with time >= after={after} s" if after is not None else "in the record"
        param = "after" if after is not None else name
        raise SignalError(
            f"{param}: only {count} samples {where}; at least {MIN_SAMPLES} are needed "
            "(the record must hold at least one full window)"
        )
    steps = np.diff(time)
    mean_step = (time[-1] - time[0]) / (count - 1)
    if not np.all(np.isfinite(time)) or mean_step <= 0 or np.any(steps <= 0):
        raise SignalError("time: coordinate must be finite and strictly increasing")
    deviation = float(np.max(np.abs(steps - mean_step)) / mean_step)
    if deviation > UNIFORM_TOLERANCE:
        raise SignalError(
            f"time: sampling is not uniform (largest relative step deviation {deviation:.3g} "
            f"> {UNIFORM_TOLERANCE:g}); resample to a uniform time step first"
        )
    order = signal.dims
    signal = signal.transpose(..., "time")
    rows = np.asarray(signal.values, dtype=float).reshape(-1, count)
    bad = int(np.count_nonzero(~np.isfinite(rows)))
    if bad:
        raise SignalError(f"{name}: contains {bad} NaN or inf values in the analysed part")
    return _Record(signal, rows, time, 1.0 / mean_step, order)


def _window(window: str | None, length: int) -> np.ndarray:
    """Periodic (DFT-even) window of ``length`` samples (read-only, cached)."""
    if window is None or (isinstance(window, str) and window.lower() in _RECTANGULAR):
        return _window_values("boxcar", length)
    if not isinstance(window, str):
        raise SignalError(f"window: must be a window name such as 'hann', got {window!r}")
    try:
        return _window_values(window.lower(), length)
    except ValueError as error:
        raise SignalError(f"window: unknown window {window!r} ({error})") from None


@functools.lru_cache(maxsize=4)
def _window_values(name: str, length: int) -> np.ndarray:
    if name == "boxcar":
        values = np.ones(length)
    elif name in ("hann", "hanning"):
        values = 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(length) / length)
    else:
        from scipy.signal import get_window

        values = np.asarray(get_window(name, length, fftbins=True), dtype=float)
    values.flags.writeable = False
    return values


def _check_band(band: Sequence[float], sample_rate: float, length: int) -> tuple[float, float]:
    try:
        lower, upper = (float(edge) for edge in band)
    except (TypeError, ValueError):
        raise SignalError(f"band: must be (lower, upper) in Hz, got {band!r}") from None
    nyquist = sample_rate / 2.0
    resolution = sample_rate / length
    if not (np.isfinite(lower) and np.isfinite(upper)):
        raise SignalError(f"band: edges must be finite, got {band!r}")
    if lower >= upper:
        raise SignalError(f"band: lower edge {lower:g} Hz must be below upper edge {upper:g} Hz")
    if lower <= 0.0 or upper >= nyquist:
        raise SignalError(
            f"band: ({lower:g}, {upper:g}) Hz must lie inside (0, Nyquist = {nyquist:g} Hz)"
        )
    if upper - lower < 2.0 * resolution:
        raise SignalError(
            f"band: width {upper - lower:g} Hz is narrower than two frequency bins "
            f"(bin width {resolution:g} Hz); widen the band or use a longer record"
        )
    return lower, upper


# --------------------------------------------------------------------------- output building


def _describe(signal: xr.DataArray) -> str:
    return str(signal.attrs.get("long_name", signal.name or "signal"))


def _kept_coords(signal: xr.DataArray) -> dict[str, xr.DataArray]:
    """Coordinates that do not run along time, each with units and long_name."""
    coords = {}
    for name, coord in signal.coords.items():
        if "time" in coord.dims:
            continue
        coord = coord.copy()
        coord.attrs.setdefault("long_name", str(name))
        coord.attrs.setdefault("units", "1" if np.issubdtype(coord.dtype, np.number) else "")
        coords[str(name)] = coord
    return coords


def _axis_result(
    record: _Record,
    values: np.ndarray,
    axis: str,
    axis_values: np.ndarray,
    axis_attrs: dict[str, str],
    name: str,
    long_name: str,
    **attrs: Any,
) -> xr.DataArray:
    """Wrap per-series spectra ``values`` with the record's other dimensions."""
    other = record.signal.dims[:-1]
    shape = tuple(record.signal.sizes[dim] for dim in other) + (values.shape[-1],)
    coords = _kept_coords(record.signal)
    coords[axis] = xr.DataArray(axis_values, dims=axis, attrs=axis_attrs)
    result = xr.DataArray(values.reshape(shape), dims=(*other, axis), coords=coords, name=name)
    result.attrs.update(units=record.signal.attrs["units"], long_name=long_name, **attrs)
    return result.transpose(*[axis if dim == "time" else dim for dim in record.order])


def _frequency_result(
    record: _Record, values: np.ndarray, name: str, long_name: str, **attrs: Any
) -> xr.DataArray:
    frequency = np.arange(values.shape[-1]) * (record.sample_rate / record.length)
    axis_attrs = {"units": "Hz", "long_name": "frequency"}
    return _axis_result(
        record, values, "frequency", frequency, axis_attrs, name, long_name, **attrs
    )


def _one_sided_amplitude(
    rows: np.ndarray, window: str | None, threads: int, effort: str
) -> np.ndarray:
    """Amplitude-corrected one-sided spectrum of each row."""
    length = rows.shape[1]
    weights = _window(window, length)
    scale = 2.0 / float(np.sum(weights))
    weights = None if window is None or np.all(weights == 1.0) else weights
    result = np.empty((rows.shape[0], length // 2 + 1))
    for index, row in enumerate(rows):
        result[index] = np.abs(_rfft(row, weights, threads, effort)) * scale
    result[:, 0] *= 0.5
    if length % 2 == 0:
        result[:, -1] *= 0.5
    return result


# --------------------------------------------------------------------------- public analyses


def amplitude_spectrum(
    signal: xr.DataArray,
    *,
    after: float | None = None,
    window: str | None = "hann",
    remove_mean: bool = False,
    threads: int | None = None,
    planner_effort: str | None = None,
) -> xr.DataArray:
    """One-sided amplitude spectrum, amplitude-corrected for the window.

    A sine of amplitude ``A`` at a bin-centred frequency reads ``A``; the DC
    bin reads the mean.

    Parameters
    ----------
    signal : xarray.DataArray
        Values along a uniform ``time`` coordinate [s], with a ``units`` attribute.
    after : float, optional
        Drop samples with time < ``after`` [s] (e.g. 1.0 to skip the start-up).
    window : str or None, default "hann"
        Window name ("hann", "boxcar"/None, or any :func:`scipy.signal.get_window`
        name), always periodic; the amplitude is divided by its coherent gain.
    remove_mean : bool, default False
        Subtract each series' mean before windowing.
    threads : int, optional
        FFTW threads (default :data:`DEFAULT_THREADS`).
    planner_effort : str, optional
        FFTW planner effort (default :data:`DEFAULT_PLANNER_EFFORT`).

    Returns
    -------
    xarray.DataArray
        Amplitude in the signal's units along ``frequency`` [Hz] (``time``
        replaced by ``frequency``).
    """
    threads, effort = _fft_options(threads, planner_effort)
    record = _prepare(signal, after)
    _window(window, MIN_SAMPLES)
    rows = record.rows - record.rows.mean(axis=1, keepdims=True) if remove_mean else record.rows
    values = _one_sided_amplitude(rows, window, threads, effort)
    return _frequency_result(
        record,
        values,
        "amplitude",
        f"amplitude spectrum of {_describe(record.signal)}",
        window=str(window),
        remove_mean=int(remove_mean),
    )


def envelope(
    signal: xr.DataArray,
    *,
    after: float | None = None,
    threads: int | None = None,
    planner_effort: str | None = None,
) -> xr.DataArray:
    """Envelope: magnitude of the analytic signal, computed with FFTs.

    The one-sided spectrum is doubled (DC and Nyquist kept once), negative
    frequencies are zeroed, and a complex inverse FFT gives the analytic
    signal, as :func:`scipy.signal.hilbert` does.

    Parameters
    ----------
    signal : xarray.DataArray
        Values along a uniform ``time`` coordinate [s], with a ``units`` attribute.
    after : float, optional
        Drop samples with time < ``after`` [s].
    threads, planner_effort
        FFTW options, as in :func:`amplitude_spectrum`.

    Returns
    -------
    xarray.DataArray
        The envelope, same dimensions, coordinates and units as ``signal``.
    """
    threads, effort = _fft_options(threads, planner_effort)
    record = _prepare(signal, after)
    values = _envelope_rows(record.rows, None, threads, effort)
    result = record.signal.copy(data=values.reshape(record.signal.shape))
    result.name = "envelope"
    result["time"].attrs.setdefault("units", "s")
    result["time"].attrs.setdefault("long_name", "time")
    result.attrs = {"units": signal.attrs["units"], "long_name": f"envelope of {_describe(signal)}"}
    return result.transpose(*record.order)


def _envelope_rows(rows: np.ndarray, keep: slice | None, threads: int, effort: str) -> np.ndarray:
    length = rows.shape[1]
    result = np.empty_like(rows)
    for index, row in enumerate(rows):
        spectrum = _rfft(row, None, threads, effort)
        result[index] = _envelope_from_rfft(spectrum, length, keep, threads, effort)
    return result


def envelope_spectrum(
    signal: xr.DataArray,
    *,
    after: float | None = None,
    window: str | None = "hann",
    threads: int | None = None,
    planner_effort: str | None = None,
) -> xr.DataArray:
    """Amplitude spectrum of the envelope with the envelope's mean removed.

    For ``A (1 + m cos 2πf_m t) cos 2πf_c t`` it shows a line of amplitude
    ``m A`` at ``f_m``.  Parameters as in :func:`amplitude_spectrum`.

    Returns
    -------
    xarray.DataArray
        Amplitude in the signal's units along ``frequency`` [Hz].
    """
    return _demodulated(signal, None, after, window, threads, planner_effort)


def demodulated_resonance(
    signal: xr.DataArray,
    band: Sequence[float] = (5000.0, 10000.0),
    *,
    after: float | None = None,
    window: str | None = "hann",
    threads: int | None = None,
    planner_effort: str | None = None,
) -> xr.DataArray:
    """Demodulated resonance analysis (DRA).

    The signal is band-passed in the frequency domain (bins with
    ``lower <= f <= upper`` kept, all others zeroed), its analytic signal and
    envelope are formed, the envelope's mean is removed, and its amplitude
    spectrum is returned.

    Parameters
    ----------
    signal : xarray.DataArray
        Values along a uniform ``time`` coordinate [s], with a ``units`` attribute.
    band : (float, float), default (5000, 10000)
        Resonance band [Hz]; must lie inside (0, Nyquist) and span two bins.
    after, window, threads, planner_effort
        As in :func:`amplitude_spectrum`.

    Returns
    -------
    xarray.DataArray
        Amplitude in the signal's units along ``frequency`` [Hz], with
        attributes ``band_lower`` and ``band_upper`` [Hz].
    """
    return _demodulated(signal, band, after, window, threads, planner_effort)


def _demodulated(
    signal: xr.DataArray,
    band: Sequence[float] | None,
    after: float | None,
    window: str | None,
    threads: int | None,
    planner_effort: str | None,
) -> xr.DataArray:
    """Envelope spectrum, of the whole signal or (DRA) of one band of it."""
    threads, effort = _fft_options(threads, planner_effort)
    record = _prepare(signal, after)
    keep, attrs = None, {"window": str(window)}
    long_name = f"envelope spectrum of {_describe(record.signal)}"
    if band is not None:
        lower, upper = _check_band(band, record.sample_rate, record.length)
        resolution = record.sample_rate / record.length
        keep = slice(
            math.ceil(lower / resolution - 1e-9), math.floor(upper / resolution + 1e-9) + 1
        )
        attrs.update(band_lower=lower, band_upper=upper)
        long_name = (
            f"demodulated resonance spectrum ({lower:g}-{upper:g} Hz) of {_describe(record.signal)}"
        )
    _window(window, MIN_SAMPLES)
    values = _envelope_rows(record.rows, keep, threads, effort)
    values -= values.mean(axis=1, keepdims=True)
    spectrum = _one_sided_amplitude(values, window, threads, effort)
    name = "envelope_amplitude" if band is None else "dra_amplitude"
    return _frequency_result(record, spectrum, name, long_name, **attrs)


def order_spectrum(
    signal: xr.DataArray,
    speed_rpm: xr.DataArray | np.ndarray | float,
    *,
    samples_per_rev: int | None = None,
    after: float | None = None,
    window: str | None = "hann",
    interpolation: str = "cubic",
    threads: int | None = None,
    planner_effort: str | None = None,
) -> xr.DataArray:
    """Amplitude spectrum against shaft order, for run-ups (order tracking).

    The reference shaft's angle is the time integral of ``speed_rpm``
    (trapezoidal); the signal is interpolated at uniform angle steps and its
    amplitude spectrum taken against order (events per revolution).

    Parameters
    ----------
    signal : xarray.DataArray
        Values along a uniform ``time`` coordinate [s], with a ``units`` attribute.
    speed_rpm : xarray.DataArray, numpy.ndarray or float
        Reference shaft speed [rpm], > 0 throughout: a DataArray along ``time``
        (interpolated to the signal's times), an array matching the signal's
        ``time`` coordinate, or a constant.
    samples_per_rev : int, optional
        Angular sampling rate; the order axis reaches ``samples_per_rev / 2``.
        Default: about as many angle samples as time samples.
    after, window, threads, planner_effort
        As in :func:`amplitude_spectrum`.
    interpolation : {"cubic", "linear"}
        How the signal is interpolated at the angle steps.

    Returns
    -------
    xarray.DataArray
        Amplitude in the signal's units along ``order`` [1], with attributes
        ``samples_per_rev`` and ``revolutions``.
    """
    threads, effort = _fft_options(threads, planner_effort)
    record = _prepare(signal, after)
    full_time = np.asarray(signal["time"].values, dtype=float)
    _window(window, MIN_SAMPLES)
    if interpolation not in ("cubic", "linear"):
        raise SignalError(f"interpolation: must be 'cubic' or 'linear', got {interpolation!r}")
    speed = _speed_at(speed_rpm, full_time, record.time)
    revolutions = np.concatenate(
        ([0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(record.time)) / 60.0)
    )
    total = float(revolutions[-1])
    if samples_per_rev is None:
        samples_per_rev = max(2, math.ceil(record.length / total))
    if (
        isinstance(samples_per_rev, bool)
        or not isinstance(samples_per_rev, (int, np.integer))
        or samples_per_rev < 2
    ):
        raise SignalError(f"samples_per_rev: must be an integer >= 2, got {samples_per_rev!r}")
    count = math.floor(total * samples_per_rev + 1e-9)
    if count < MIN_SAMPLES:
        raise SignalError(
            f"samples_per_rev: {total:.4g} revolutions give only {count} angle samples; "
            f"at least {MIN_SAMPLES} are needed (raise samples_per_rev or use a longer record)"
        )
    angle = np.arange(count) / samples_per_rev
    if interpolation == "cubic":
        from scipy.interpolate import make_interp_spline

        resampled = make_interp_spline(revolutions, record.rows, k=3, axis=1)(angle)
    else:
        resampled = np.stack([np.interp(angle, revolutions, row) for row in record.rows])
    values = _one_sided_amplitude(resampled, window, threads, effort)
    orders = np.arange(values.shape[-1]) * (samples_per_rev / count)
    axis_attrs = {"units": "1", "long_name": "order (events per revolution of the reference shaft)"}
    return _axis_result(
        record,
        values,
        "order",
        orders,
        axis_attrs,
        "order_amplitude",
        f"order spectrum of {_describe(record.signal)}",
        samples_per_rev=int(samples_per_rev),
        revolutions=total,
        window=str(window),
    )


def _speed_at(speed_rpm: Any, full_time: np.ndarray, time: np.ndarray) -> np.ndarray:
    """Reference speed [rpm] at ``time``, validated (finite and > 0)."""
    if isinstance(speed_rpm, xr.DataArray):
        if speed_rpm.dims != ("time",) or "time" not in speed_rpm.coords:
            raise SignalError("speed_rpm: a DataArray must be 1-D along a 'time' coordinate")
        source = np.asarray(speed_rpm["time"].values, dtype=float)
        if time[0] < source.min() or time[-1] > source.max():
            raise SignalError("speed_rpm: its time coordinate does not cover the analysed record")
        speed = np.interp(time, source, np.asarray(speed_rpm.values, dtype=float))
    elif np.ndim(speed_rpm) == 0:
        speed = np.full(time.size, float(speed_rpm))
    else:
        values = np.asarray(speed_rpm, dtype=float)
        if values.shape != full_time.shape:
            raise SignalError("speed_rpm: an array must match the signal's time coordinate")
        speed = values[np.searchsorted(full_time, time)]
    if not np.all(np.isfinite(speed)) or np.any(speed <= 0.0):
        raise SignalError("speed_rpm: must be finite and > 0 rpm over the analysed record")
    return speed
