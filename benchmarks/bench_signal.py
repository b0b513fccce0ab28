"""Benchmark: amplitude spectrum + envelope of a long record.

Compares, in one run, pygear.analysis.signals.signal (FFTW through pyFFTW, cached plans) with
numpy.fft (rfft + a hand-built analytic signal) and scipy (scipy.fft.rfft +
scipy.signal.hilbert).  Each timing is the median of ``--repeats`` runs after
one warm-up run (which, for pygear, builds the plans; its time is shown apart).

Usage::

    PYTHONPATH=. python benchmarks/bench_signal.py [--samples 4000000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import numpy as np
import scipy.fft
import scipy.signal
import xarray as xr

from pygear.analysis.signals import signal as ps


def hann(length: int) -> np.ndarray:
    return 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(length) / length)


def one_sided(spectrum: np.ndarray, window_sum: float, length: int) -> np.ndarray:
    amplitude = np.abs(spectrum) * (2.0 / window_sum)
    amplitude[0] /= 2.0
    if length % 2 == 0:
        amplitude[-1] /= 2.0
    return amplitude


def with_numpy(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    length = values.size
    window = hann(length)
    amplitude = one_sided(np.fft.rfft(values * window), window.sum(), length)
    half = np.fft.rfft(values)
    full = np.zeros(length, dtype=complex)
    positive = (length + 1) // 2
    full[0] = half[0]
    full[1:positive] = 2.0 * half[1:positive]
    if length % 2 == 0:
        full[length // 2] = half[length // 2]
    return amplitude, np.abs(np.fft.ifft(full))


def with_scipy(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    length = values.size
    window = scipy.signal.get_window("hann", length)
    amplitude = one_sided(scipy.fft.rfft(values * window), window.sum(), length)
    return amplitude, np.abs(scipy.signal.hilbert(values))


def with_pygear(signal: xr.DataArray, threads: int) -> tuple[np.ndarray, np.ndarray]:
    spectrum = ps.amplitude_spectrum(signal, threads=threads)
    return spectrum.values, ps.envelope(signal, threads=threads).values


def median_seconds(work: Callable[[], object], repeats: int) -> tuple[float, float]:
    """(first run, median of the following ``repeats`` runs) in seconds."""
    start = time.perf_counter()
    work()
    first = time.perf_counter() - start
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        work()
        times.append(time.perf_counter() - start)
    return first, statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=4_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--threads", type=int, default=1)
    options = parser.parse_args()

    sample_rate = 20_000.0
    rng = np.random.default_rng(1)
    times = np.arange(options.samples) / sample_rate
    values = np.cos(2 * np.pi * 1330.0 * times) + 0.1 * rng.standard_normal(options.samples)
    signal = xr.DataArray(
        values,
        dims="time",
        coords={"time": times},
        attrs={"units": "m/s^2", "long_name": "benchmark channel"},
    )

    reference = with_numpy(values)
    for name, result in (
        ("pygear", with_pygear(signal, options.threads)),
        ("scipy", with_scipy(values)),
    ):
        for part, ours, theirs in zip(("spectrum", "envelope"), result, reference, strict=True):
            error = np.max(np.abs(ours - theirs)) / np.max(np.abs(theirs))
            assert error < 1e-10, f"{name} {part} differs from numpy by {error:.2e}"

    ps.clear_plan_cache()
    rows = [
        (
            "pygear.analysis.signals.signal (FFTW)",
            *median_seconds(lambda: with_pygear(signal, options.threads), options.repeats),
        ),
        ("numpy.fft", *median_seconds(lambda: with_numpy(values), options.repeats)),
        ("scipy.signal.hilbert", *median_seconds(lambda: with_scipy(values), options.repeats)),
    ]
    base = rows[0][2]
    print(
        f"spectrum + envelope of {options.samples:,} samples, threads={options.threads}, "
        f"median of {options.repeats}"
    )
    print(f"{'method':<22} {'first [s]':>10} {'median [s]':>11} {'ratio':>7}")
    for name, first, median in rows:
        print(f"{name:<22} {first:>10.3f} {median:>11.3f} {median / base:>7.2f}")
    print(f"plans cached: {ps.plan_cache_info()['entries']}")


if __name__ == "__main__":
    main()
