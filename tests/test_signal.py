"""Tests of pygear.analysis.signals.signal and pygear.analysis.signals.peaks.

References come from closed-form results (amplitudes of tones, sidebands and
envelopes), from numpy.fft / scipy.signal reimplementations written here, or
from the construction of the test signal, never from pygear's own output.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import scipy.signal
import xarray as xr

from pygear.analysis.signals import signal as ps
from pygear.analysis.signals.peaks import find_peaks, local_maxima, peak_table_text


def make_signal(values: np.ndarray, sample_rate: float, start: float = 0.0) -> xr.DataArray:
    """A test acceleration channel sampled uniformly from ``start``."""
    time = start + np.arange(values.shape[-1]) / sample_rate
    return xr.DataArray(
        values,
        dims="time",
        coords={"time": ("time", time, {"units": "s", "long_name": "time"})},
        attrs={"units": "m/s^2", "long_name": "test acceleration"},
        name="acceleration",
    )


def value_at(spectrum: xr.DataArray, frequency: float) -> float:
    return float(spectrum.sel(frequency=frequency, method="nearest"))


def numpy_amplitude(values: np.ndarray, window: np.ndarray) -> np.ndarray:
    """One-sided, window-corrected amplitude spectrum written with numpy.fft."""
    amplitude = np.abs(np.fft.rfft(values * window)) * 2.0 / window.sum()
    amplitude[0] /= 2.0
    if values.size % 2 == 0:
        amplitude[-1] /= 2.0
    return amplitude


def assert_close(actual: np.ndarray, expected: np.ndarray, rtol: float) -> None:
    """Relative agreement, measured against the largest value of the reference."""
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=rtol * np.max(np.abs(expected)))


# --------------------------------------------------------------------------- spectra


def test_sine_at_bin_centre_reads_its_amplitude_and_frequency() -> None:
    sample_rate, amplitude, frequency, offset = 4096.0, 2.75, 437.0, 0.4
    time = np.arange(2 * 4096) / sample_rate
    values = offset + amplitude * np.sin(2 * np.pi * frequency * time + 0.3)
    spectrum = ps.amplitude_spectrum(make_signal(values, sample_rate), after=1.0)

    assert spectrum.sizes["frequency"] == 4096 // 2 + 1  # one second kept: 1 Hz bins
    assert float(spectrum.frequency[1]) == pytest.approx(1.0, rel=1e-12)
    tone = spectrum.where(spectrum.frequency > 10.0, 0.0)
    peak = int(np.argmax(tone.values))
    assert float(spectrum.frequency[peak]) == pytest.approx(frequency, rel=1e-6)
    assert float(spectrum[peak]) == pytest.approx(amplitude, rel=1e-6)
    # the mean is not removed by default: the DC bin reads it
    assert float(spectrum[0]) == pytest.approx(offset, rel=1e-6)
    removed = ps.amplitude_spectrum(make_signal(values, sample_rate), after=1.0, remove_mean=True)
    assert float(removed[0]) < 1e-9


def test_amplitude_modulated_carrier_sidebands_and_envelope_line() -> None:
    sample_rate, carrier, modulation, amplitude, depth = 8192.0, 1000.0, 50.0, 2.0, 0.4
    time = np.arange(8192) / sample_rate
    values = (
        (1 + depth * np.cos(2 * np.pi * modulation * time))
        * amplitude
        * np.cos(2 * np.pi * carrier * time)
    )
    signal = make_signal(values, sample_rate)

    spectrum = ps.amplitude_spectrum(signal)
    assert value_at(spectrum, carrier) == pytest.approx(amplitude, rel=1e-3)
    for sideband in (carrier - modulation, carrier + modulation):
        assert value_at(spectrum, sideband) == pytest.approx(depth * amplitude / 2, rel=1e-3)

    envelope_spectrum = ps.envelope_spectrum(signal)
    assert value_at(envelope_spectrum, modulation) == pytest.approx(depth * amplitude, rel=1e-3)
    assert float(envelope_spectrum[0]) < 1e-9 * amplitude  # envelope mean removed

    envelope = ps.envelope(signal)
    expected = amplitude * (1 + depth * np.cos(2 * np.pi * modulation * time))
    assert_close(envelope.values, expected, 1e-9)


def test_dra_recovers_modulation_hidden_in_raw_spectrum() -> None:
    sample_rate, mesh_frequency = 32768.0, 192.0
    rng = np.random.default_rng(20240611)
    time = np.arange(2 * 32768) / sample_rate
    strong_tones = 20.0 * np.sin(2 * np.pi * 50.0 * time) + 8.0 * np.sin(2 * np.pi * 120.0 * time)
    resonance = (
        0.5
        * (1 + 0.5 * np.cos(2 * np.pi * mesh_frequency * time))
        * np.cos(2 * np.pi * 7000.0 * time)
    )
    noise = 0.3 * rng.standard_normal(time.size)
    signal = make_signal(strong_tones + resonance + noise, sample_rate)

    raw = ps.amplitude_spectrum(signal, after=1.0)
    floor = float(np.median(raw.sel(frequency=slice(150.0, 250.0))))
    assert value_at(raw, mesh_frequency) < 4.0 * floor  # nothing at 192 Hz in the raw spectrum
    raw_peaks = find_peaks(raw, 5, min_frequency=5.0)
    assert np.all(np.abs(raw_peaks["frequency_hz"] - mesh_frequency) > 5.0)

    dra = ps.demodulated_resonance(signal, (5000.0, 10000.0), after=1.0)
    resolution = float(dra.frequency[1] - dra.frequency[0])
    strongest = float(dra.frequency[np.argmax(dra.values[1:]) + 1])
    assert abs(strongest - mesh_frequency) <= resolution
    assert value_at(dra, mesh_frequency) > 20.0 * float(np.median(dra))
    assert dra.attrs["band_lower"] == 5000.0 and dra.attrs["band_upper"] == 10000.0


@pytest.mark.parametrize("length", [1000, 1001])
def test_agrees_with_numpy_and_scipy(length: int) -> None:
    sample_rate = 2000.0
    rng = np.random.default_rng(length)
    values = rng.standard_normal(length) + 0.7
    signal = make_signal(values, sample_rate)
    hann = scipy.signal.get_window("hann", length, fftbins=True)

    assert_close(ps.amplitude_spectrum(signal).values, numpy_amplitude(values, hann), 1e-10)
    assert_close(
        ps.amplitude_spectrum(signal, window="boxcar").values,
        numpy_amplitude(values, np.ones(length)),
        1e-10,
    )
    assert_close(ps.envelope(signal).values, np.abs(scipy.signal.hilbert(values)), 1e-10)

    envelope = np.abs(scipy.signal.hilbert(values))
    expected = numpy_amplitude(envelope - envelope.mean(), hann)
    assert_close(ps.envelope_spectrum(signal).values, expected, 1e-10)

    lower, upper = 300.0, 700.0
    frequency = np.fft.fftfreq(length, 1.0 / sample_rate)
    passed = np.where((frequency >= lower) & (frequency <= upper), 2.0 * np.fft.fft(values), 0.0)
    band_envelope = np.abs(np.fft.ifft(passed))
    assert_close(
        ps.demodulated_resonance(signal, (lower, upper)).values,
        numpy_amplitude(band_envelope - band_envelope.mean(), hann),
        1e-10,
    )


def test_threads_give_the_same_result() -> None:
    values = np.random.default_rng(3).standard_normal(4096)
    signal = make_signal(values, 1000.0)
    one = ps.amplitude_spectrum(signal, threads=1)
    two = ps.amplitude_spectrum(signal, threads=2, planner_effort="FFTW_MEASURE")
    assert_close(two.values, one.values, 1e-12)


def test_multichannel_and_metadata() -> None:
    sample_rate = 1024.0
    time = np.arange(1024) / sample_rate
    values = np.stack([np.sin(2 * np.pi * 100.0 * time), 3.0 * np.sin(2 * np.pi * 200.0 * time)])
    signal = xr.DataArray(
        values.T,
        dims=("time", "channel"),
        coords={"time": ("time", time, {"units": "s"}), "channel": ["ring", "sun"]},
        attrs={"units": "m/s^2", "long_name": "acceleration"},
    )
    spectrum = ps.amplitude_spectrum(signal)
    assert spectrum.dims == ("frequency", "channel")
    assert float(spectrum.sel(channel="ring", frequency=100.0)) == pytest.approx(1.0, rel=1e-9)
    assert float(spectrum.sel(channel="sun", frequency=200.0)) == pytest.approx(3.0, rel=1e-9)
    envelope = ps.envelope(signal)
    assert envelope.dims == ("time", "channel")
    assert envelope["time"].attrs == {"units": "s", "long_name": "time"}
    assert signal["time"].attrs == {"units": "s"}  # the input is left alone

    dataset = xr.Dataset(
        {
            "spectrum": spectrum,
            "envelope_spectrum": ps.envelope_spectrum(signal),
            "dra": ps.demodulated_resonance(signal, (300.0, 400.0)),
        }
    )
    for variable in [*dataset.data_vars.values(), *dataset.coords.values()]:
        assert "units" in variable.attrs and "long_name" in variable.attrs, variable.name
    assert dataset["frequency"].attrs["units"] == "Hz"
    assert dataset["spectrum"].attrs["units"] == "m/s^2"


# --------------------------------------------------------------------------- orders


def test_order_spectrum_of_runup_chirp_shows_its_order() -> None:
    sample_rate, order = 8192.0, 12
    start_rpm, ramp_rpm_per_s, duration = 600.0, 600.0, 2.0
    time = np.arange(int(duration * sample_rate) + 1) / sample_rate
    speed_rpm = start_rpm + ramp_rpm_per_s * time
    revolutions = (start_rpm * time + 0.5 * ramp_rpm_per_s * time**2) / 60.0  # 40 at the end
    signal = make_signal(1.5 * np.cos(2 * np.pi * order * revolutions), sample_rate)

    speed = xr.DataArray(
        speed_rpm, dims="time", coords={"time": signal.time}, attrs={"units": "rpm"}
    )
    for reference in (speed, speed_rpm):
        spectrum = ps.order_spectrum(signal, reference, samples_per_rev=64)
        assert spectrum.dims == ("order",)
        assert spectrum.attrs["revolutions"] == pytest.approx(40.0, rel=1e-9)
        assert float(spectrum.order[1]) == pytest.approx(1.0 / 40.0, rel=1e-9)
        strongest = float(spectrum.order[np.argmax(spectrum.values)])
        assert strongest == pytest.approx(order, rel=1e-9)
        assert float(spectrum.max()) == pytest.approx(1.5, rel=1e-3)

    # the same chirp in the time domain is smeared over 120..360 Hz
    assert float(ps.amplitude_spectrum(signal).max()) < 0.5


# --------------------------------------------------------------------------- peaks


def tone_spectrum(frequency: float) -> xr.DataArray:
    time = np.arange(8192) / 8192.0
    return ps.amplitude_spectrum(make_signal(np.cos(2 * np.pi * frequency * time), 8192.0))


def test_peak_identification_prefers_closest_reference() -> None:
    peaks = find_peaks(
        tone_spectrum(1330.0), 1, natural_frequencies={"rotational 2": 1334.0}, mesh_frequency=190.0
    )
    assert len(peaks) == 1
    row = peaks.iloc[0]
    assert row["frequency_hz"] == pytest.approx(1330.0)
    assert row["amplitude"] == pytest.approx(1.0, rel=1e-9)
    assert row["identification"] == "mesh harmonic 7"
    assert row["near_natural_frequency"] == "rotational 2 (1334.0 Hz)"

    natural = find_peaks(
        tone_spectrum(1334.0), 1, natural_frequencies={"rotational 2": 1334.0}, mesh_frequency=190.0
    ).iloc[0]
    assert natural["identification"] == "rotational 2 (1334.0 Hz)"
    assert natural["kind"] == "natural frequency"

    sideband = find_peaks(
        tone_spectrum(1328.0), 1, mesh_frequency=190.0, sideband_frequency=2.0
    ).iloc[0]
    assert sideband["identification"] == "mesh harmonic 7 \u2212 1\u00d7carrier"

    lone = find_peaks(
        tone_spectrum(3000.0), 1, natural_frequencies={"rotational 2": 1334.0}, mesh_frequency=190.0
    ).iloc[0]
    assert lone["identification"] == "unidentified"  # 2850 and 3040 Hz are > 1 % away

    text = peak_table_text(peaks, title="sun acceleration")
    lines = text.splitlines()
    assert lines[0] == "sun acceleration" and len(lines) == 4
    assert "mesh harmonic 7" in lines[3] and "rotational 2 (1334.0 Hz)" in lines[3]
    assert "[m/s^2]" in lines[1] and "[Hz]" in lines[1]


def test_peaks_from_modal_dataset_and_ordering() -> None:
    modes = xr.Dataset(
        {
            "frequency": ("mode", [0.0, 743.2, 743.2, 1334.0, 1102.7, 1102.7]),
            "mode_class": (
                "mode",
                [
                    "rotational",
                    "translational",
                    "translational",
                    "rotational",
                    "translational",
                    "translational",
                ],
            ),
        }
    )
    time = np.arange(8192) / 8192.0
    values = 2.0 * np.cos(2 * np.pi * 1102.0 * time) + np.cos(2 * np.pi * 1334.0 * time)
    peaks = find_peaks(
        ps.amplitude_spectrum(make_signal(values, 8192.0)), 2, natural_frequencies=modes
    )
    assert list(peaks["identification"]) == [
        "translational 2 (1102.7 Hz)",
        "rotational 2 (1334.0 Hz)",
    ]
    assert list(peaks["amplitude"]) == pytest.approx([2.0, 1.0], rel=1e-9)


# --------------------------------------------------------------------------- bad input


def good_signal(seconds: float = 1.0, sample_rate: float = 32768.0) -> xr.DataArray:
    time = np.arange(int(seconds * sample_rate)) / sample_rate
    return make_signal(np.sin(2 * np.pi * 440.0 * time), sample_rate)


def with_values(signal: xr.DataArray, index: int, value: float) -> xr.DataArray:
    changed = signal.copy(deep=True)
    changed[index] = value
    return changed


def uneven_time(signal: xr.DataArray) -> xr.DataArray:
    time = signal.time.values.copy()
    time[100] += 1e-4 * (time[1] - time[0])
    return signal.assign_coords(time=("time", time, {"units": "s"}))


BAD_INPUTS = {
    "band above Nyquist": (lambda: ps.demodulated_resonance(good_signal(), (5000, 20000)), "band"),
    "band from zero": (lambda: ps.demodulated_resonance(good_signal(), (0, 1000)), "band"),
    "band reversed": (lambda: ps.demodulated_resonance(good_signal(), (8000, 6000)), "band"),
    "band too narrow": (lambda: ps.demodulated_resonance(good_signal(), (5000, 5001)), "band"),
    "band not a pair": (lambda: ps.demodulated_resonance(good_signal(), (5000,)), "band"),
    "after leaves few samples": (
        lambda: ps.amplitude_spectrum(good_signal(), after=0.9997),
        "after",
    ),
    "record too short": (lambda: ps.envelope(make_signal(np.ones(10), 100.0)), "signal"),
    "uneven time": (lambda: ps.amplitude_spectrum(uneven_time(good_signal())), "time"),
    "NaN": (lambda: ps.envelope_spectrum(with_values(good_signal(), 7, np.nan)), "signal"),
    "inf": (lambda: ps.amplitude_spectrum(with_values(good_signal(), 7, np.inf)), "signal"),
    "no time coordinate": (lambda: ps.amplitude_spectrum(good_signal().drop_vars("time")), "time"),
    "no time dimension": (lambda: ps.amplitude_spectrum(good_signal().rename(time="t")), "time"),
    "no units": (
        lambda: ps.amplitude_spectrum(good_signal().drop_attrs()),
        "signal: needs a 'units'",
    ),
    "not a DataArray": (lambda: ps.amplitude_spectrum(np.ones(100)), "signal"),
    "threads": (lambda: ps.amplitude_spectrum(good_signal(), threads=0), "threads"),
    "planner effort": (lambda: ps.envelope(good_signal(), planner_effort="FAST"), "planner_effort"),
    "window": (lambda: ps.amplitude_spectrum(good_signal(), window="no-such-window"), "window"),
    "speed": (lambda: ps.order_spectrum(good_signal(), -100.0), "speed_rpm"),
    "speed length": (lambda: ps.order_spectrum(good_signal(), np.ones(5)), "speed_rpm"),
    "samples per rev": (
        lambda: ps.order_spectrum(good_signal(), 60.0, samples_per_rev=4),
        "samples_per_rev",
    ),
    "peak count": (lambda: find_peaks(tone_spectrum(100.0), 0), "n"),
    "peak tolerance": (lambda: find_peaks(tone_spectrum(100.0), rel_tol=0.0), "rel_tol"),
    "mesh frequency": (
        lambda: find_peaks(tone_spectrum(100.0), mesh_frequency=-1.0),
        "mesh_frequency",
    ),
    "natural frequencies": (
        lambda: find_peaks(tone_spectrum(100.0), natural_frequencies=[1.0]),
        "natural_frequencies",
    ),
}


@pytest.mark.parametrize("case", list(BAD_INPUTS), ids=list(BAD_INPUTS))
def test_bad_input_raises_naming_the_parameter(case: str) -> None:
    call, expected = BAD_INPUTS[case]
    start = expected if ":" in expected else f"{expected}:"  # message starts with the parameter
    with pytest.raises(ps.SignalError, match=f"^{re.escape(start)}"):
        call()


def test_validation_happens_before_any_fft() -> None:
    signal = good_signal()
    ps.clear_plan_cache()
    with pytest.raises(ValueError, match="band"):
        ps.demodulated_resonance(signal, (5000, 5001))
    with pytest.raises(ValueError, match="time"):
        ps.amplitude_spectrum(uneven_time(signal))
    assert ps.plan_cache_info()["misses"] == 0


# --------------------------------------------------------------------------- plans


def test_plans_are_built_once_per_length() -> None:
    ps.clear_plan_cache()
    signal = good_signal(0.25)
    first = ps.amplitude_spectrum(signal)
    info = ps.plan_cache_info()
    assert (info["entries"], info["misses"], info["hits"]) == (1, 1, 0)

    second = ps.amplitude_spectrum(signal)
    info = ps.plan_cache_info()
    assert (info["entries"], info["misses"], info["hits"]) == (1, 1, 1)
    np.testing.assert_array_equal(first.values, second.values)

    ps.envelope(signal)  # same length: reuses the real plan, adds the complex inverse
    info = ps.plan_cache_info()
    assert info["entries"] == 2 and info["misses"] == 2
    assert {key[1] for key in info["keys"]} == {"rfft", "ifft"}

    ps.amplitude_spectrum(good_signal(0.125))  # a new length: one new plan
    assert ps.plan_cache_info()["entries"] == 3


def test_wisdom_round_trip() -> None:
    wisdom = ps.export_wisdom()
    assert isinstance(wisdom, tuple) and all(isinstance(part, bytes) for part in wisdom)
    ps.import_wisdom(wisdom)
    assert ps.amplitude_spectrum(good_signal(0.125)).sizes["frequency"] == 2049


# --------------------------------------------------------------------------- local maxima


@pytest.mark.parametrize(
    ("values", "expected"),
    [
        ([0, 2, 1], [1]),  # a sample above both neighbours
        ([0, 3, 3, 0], [1]),  # a plateau of two: the left of the two middles
        ([0, 3, 3, 3, 0], [2]),  # a plateau of three: its middle
        ([3, 1, 2, 1, 0], [2]),  # the first sample never counts
        ([0, 1, 2], []),  # nor the last
        ([0, 3, 3], []),  # nor a plateau that reaches an end
        ([0, 2, 2, 3, 0], [3]),  # a shoulder on the way up is no maximum
        ([1, 1, 1, 1], []),
        ([], []),
        ([5.0], []),
    ],
)
def test_local_maxima_by_hand(values, expected) -> None:
    assert local_maxima(np.asarray(values, dtype=float)).tolist() == expected


def test_local_maxima_agree_with_scipy_find_peaks() -> None:
    """Series of small integers, full of plateaus and ties, against the unconditioned
    ``scipy.signal.find_peaks`` (an implementation independent of pygear's)."""
    rng = np.random.default_rng(7)
    for _ in range(2000):
        values = rng.integers(0, 4, size=rng.integers(0, 30)).astype(float)
        expected, _ = scipy.signal.find_peaks(values)
        np.testing.assert_array_equal(local_maxima(values), expected)
    noise = rng.standard_normal(50_000)
    np.testing.assert_array_equal(local_maxima(noise), scipy.signal.find_peaks(noise)[0])


@pytest.mark.parametrize("count", [999, 1000, 1009, 160001, 200003, 1048577])
def test_fast_length_is_seven_smooth_and_close(count: int) -> None:
    """The run analyses' record length: the largest n <= count with prime factors 2, 3, 5,
    7 only, within 0.2 % (small records are left whole)."""
    length = ps.fast_length(count)
    if count < 1000:
        assert length == count
        return
    rest = length
    for prime in (2, 3, 5, 7):
        while rest % prime == 0:
            rest //= prime
    assert rest == 1 and count * 0.998 <= length <= count
    # no 7-smooth number lies between it and count
    for between in range(length + 1, count + 1):
        value = between
        for prime in (2, 3, 5, 7):
            while value % prime == 0:
                value //= prime
        assert value != 1
