"""Bearing envelope analysis on synthetic signals generated here with known parameters:
defect impulses ringing a resonance, gear mesh harmonics and noise (Randall & Antoni
2011, sec. 2 and 5: the model of a localized fault's vibration)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lfilter

from pygear.analysis.condition.bearing_envelope import (
    bearing_envelope_analysis,
    detect_lines,
    discrete_random_separation,
    prewhiten,
    squared_envelope_spectrum,
)
from pygear.analysis.condition.bearing_kinematics import bearing_frequencies
from pygear.analysis.condition.bearing_load import defect_excitation
from pygear.analysis.signals.signal import SignalError
from pygear.model.rolling_bearing import BearingDefect, RollingBearing

RATE = 20000.0  # Hz
DURATION = 2.0  # s: 0.5 Hz lines
SHAFT = 25.0  # Hz
RESONANCE = 3500.0  # Hz, 5 % damping
MESH = 1150.0  # Hz: its 3rd harmonic lies in the resonance's band
BPFO, BPFI = 87.3, 131.4  # Hz, not multiples of the shaft rate


def ring(excitation: np.ndarray, frequency: float = RESONANCE, zeta: float = 0.05) -> np.ndarray:
    """Impulse response of a single-DOF resonance (impulse-invariant, exact at samples)."""
    omega = 2 * math.pi * frequency
    damped, step = omega * math.sqrt(1 - zeta**2), 1 / RATE
    r = math.exp(-zeta * omega * step)
    numerator = [0.0, r * math.sin(damped * step)]
    return lfilter(numerator, [1.0, -2 * r * math.cos(damped * step), r * r], excitation)


def fault_signal(rate_hz, *, modulation=0.0, gear=0.0, noise=0.5, seed=0, jitter=0.01):
    """Unit-RMS impulses at ``rate_hz`` (1 % random spacing: slip) ringing the resonance,
    their size modulated 1 + 0.9 cos(2 pi f_mod t) (a load zone), plus ``gear`` times a
    unit-RMS set of three mesh harmonics amplitude-modulated at the shaft rate, plus
    white noise of RMS ``noise``."""
    rng = np.random.default_rng(seed)
    count = int(RATE * DURATION)
    times = np.arange(int(DURATION * rate_hz) + 1) / rate_hz
    times = np.clip(times + rng.normal(0.0, jitter / rate_hz, times.size), 0.0, None)
    sizes = 1.0 + 0.9 * np.cos(2 * math.pi * modulation * times) if modulation else 1.0
    impulses = np.zeros(count)
    index = np.round(times * RATE).astype(int)
    keep = index < count
    np.add.at(impulses, index[keep], np.broadcast_to(sizes, times.shape)[keep])
    signal = ring(impulses)
    signal /= np.std(signal)
    t = np.arange(count) / RATE
    if gear:
        mesh = sum(np.cos(2 * math.pi * h * MESH * t + h) / h for h in (1, 2, 3))
        mesh *= 1.0 + 0.5 * np.cos(2 * math.pi * SHAFT * t)
        signal += gear * mesh / np.std(mesh)
    return signal + noise * rng.normal(size=count)


def test_outer_race_fault_gives_bpfo_and_harmonics_to_the_resolution():
    signal = fault_signal(BPFO, gear=3.0)
    spectrum, found = bearing_envelope_analysis(signal, RATE, {"BPFO": BPFO, "BPFI": BPFI})
    step = spectrum.attrs.get("bin_width", found.attrs["bin_width"])
    assert step == pytest.approx(1 / DURATION)
    assert bool(found.detected.sel(line="BPFO"))
    line = found.sel(line="BPFO", sideband=0)
    # every harmonic's largest bin within one bin of k BPFO (the jitter averages out)
    assert np.all(np.abs(line.found_frequency - line.expected_frequency) <= step)
    assert np.all(line.found.values)
    # no false call: the inner-race line is absent from this signal
    assert not bool(found.detected.sel(line="BPFI"))
    # the band the kurtogram picked holds the resonance the impulses ring
    assert found.attrs["band_low"] <= RESONANCE <= found.attrs["band_high"]


def test_inner_race_fault_gives_bpfi_with_shaft_rate_sidebands():
    signal = fault_signal(BPFI, modulation=SHAFT, gear=3.0)
    modulation = {"BPFI": SHAFT, "BPFO": 0.0}
    _, found = bearing_envelope_analysis(
        signal, RATE, {"BPFO": BPFO, "BPFI": BPFI}, modulation=modulation
    )
    assert bool(found.detected.sel(line="BPFI"))
    assert not bool(found.detected.sel(line="BPFO"))
    first = found.sel(line="BPFI", harmonic=1)
    # the load zone's modulation 1 + 0.9 cos puts lines at BPFI +- f_shaft
    assert first.found.sel(sideband=-1) and first.found.sel(sideband=1)
    for side in (-1, 1):
        assert abs(float(first.found_frequency.sel(sideband=side)) - (BPFI + side * SHAFT)) <= 0.5


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_prewhitening_separates_a_strong_gear_from_the_bearing(seed):
    # a gear 30 times the bearing's RMS, its 3rd harmonic in the resonance band, in one
    # wide band (no kurtogram to dodge it): whitening flattens the mesh lines
    signal = fault_signal(BPFO, gear=30.0, seed=seed)
    band = (0.0, 0.5 * RATE)
    raw_spectrum, raw = bearing_envelope_analysis(signal, RATE, {"BPFO": BPFO}, whiten=False,
                                                  band=band)  # fmt: skip
    _, white = bearing_envelope_analysis(signal, RATE, {"BPFO": BPFO}, band=band)
    gain = float(white.snr_fundamental[0] - raw.snr_fundamental[0])
    # observed 18 .. 27 dB over the seeds; 15 dB is a factor 5.6 in amplitude
    assert gain > 15.0
    assert bool(white.detected[0])
    # before whitening the gear is the envelope's strongest line: its modulation and its
    # harmonics' differences, all multiples of the shaft rate (MESH = 46 SHAFT)
    frequency = raw_spectrum.frequency.values
    strongest = frequency[1:][np.argmax(raw_spectrum.values[1:])]
    assert min(strongest % SHAFT, -strongest % SHAFT) <= 1 / DURATION


def test_prewhitening_leaves_unit_magnitude_and_the_phase():
    rng = np.random.default_rng(3)
    signal = np.cumsum(rng.normal(size=4096))  # a red spectrum
    whitened = prewhiten(signal, RATE)
    spectrum = np.fft.rfft(whitened.values)
    assert np.allclose(np.abs(spectrum[1:]), 1.0, atol=1e-9)
    original = np.fft.rfft(signal - signal.mean())
    assert np.allclose(np.angle(spectrum[1:-1] * np.conj(original[1:-1])), 0.0, atol=1e-9)
    assert whitened["time"].attrs["units"] == "s" and whitened.attrs["units"] == "1"


def test_squared_envelope_line_of_a_modulated_tone_is_its_closed_form():
    # (1 + m cos w_m t) cos w_c t: squared envelope (1 + m cos)^2 has 2 m at f_m
    t = np.arange(int(RATE * DURATION)) / RATE
    m = 0.3
    signal = (1 + m * np.cos(2 * math.pi * 40.0 * t)) * np.cos(2 * math.pi * 3000.0 * t)
    spectrum = squared_envelope_spectrum(signal, RATE, (2000.0, 4000.0))
    # the Hann window's scalloping is nil on a bin (40 Hz is bin 80)
    assert float(spectrum.sel(frequency=40.0)) == pytest.approx(2 * m, rel=1e-6)
    assert float(spectrum.sel(frequency=80.0)) == pytest.approx(m**2 / 2, rel=1e-6)
    assert spectrum.frequency.values[-1] <= 2000.0


def test_a_defect_history_from_the_contact_law_is_found_at_bpfo():
    # the blocked force of an outer-race spall (bearing_load) rung through the resonance
    bearing = RollingBearing("DE", "ball", elements=9, pitch_diameter=0.039,
                             element_diameter=0.0079)  # fmt: skip
    bpfo = bearing_frequencies(bearing, SHAFT).lines["BPFO"]
    history = defect_excitation(
        bearing, 2e3, inner_hz=SHAFT, duration=DURATION, sample_rate=RATE,
        defects=(BearingDefect("outer", width=0.5e-3, depth=10e-6),),
    )  # fmt: skip
    force = history.blocked_force_x.values
    signal = ring(np.diff(force, prepend=force[0]))
    signal = signal / np.std(signal) + 0.5 * np.random.default_rng(4).normal(size=signal.size)
    _, found = bearing_envelope_analysis(signal, RATE, {"BPFO": bpfo, "BPFI": BPFI})
    assert bool(found.detected.sel(line="BPFO"))
    assert not bool(found.detected.sel(line="BPFI"))


def test_bad_requests_are_one_line():
    signal = np.random.default_rng(0).normal(size=4096)
    with pytest.raises(SignalError, match=r"^band: must satisfy 0 <= low < high <= 10000 Hz"):
        squared_envelope_spectrum(signal, RATE, (3000.0, 20000.0))
    spectrum = squared_envelope_spectrum(signal, RATE)
    with pytest.raises(SignalError, match=r"^lines\['BPFO'\]: must be a positive frequency"):
        detect_lines(spectrum, {"BPFO": -1.0})
    with pytest.raises(SignalError, match=r"^lines: 3 harmonics of 4000 Hz do not fit"):
        bearing_envelope_analysis(signal, RATE, {"BPFO": 4000.0})


def test_discrete_random_separation_takes_out_the_gear_and_keeps_the_bearing():
    signal = fault_signal(BPFO, gear=30.0, seed=0)
    parts = discrete_random_separation(signal, RATE)
    frequency = np.fft.rfftfreq(signal.size, 1 / RATE)
    before, after = (np.abs(np.fft.rfft(x)) for x in (signal, parts.random.values))
    for harmonic in (1, 2, 3):  # observed 22, 30 and 29 dB down
        at = np.argmin(np.abs(frequency - harmonic * MESH))
        assert 20 * np.log10(before[at] / after[at]) > 15.0
    # no whitening, one wide band: BPFO from 3 dB (hidden) to 21 dB (observed)
    band = (0.0, 0.5 * RATE)
    _, raw = bearing_envelope_analysis(signal, RATE, {"BPFO": BPFO}, whiten=False, band=band)
    _, drs = bearing_envelope_analysis(
        signal, RATE, {"BPFO": BPFO}, whiten=False, separate=True, band=band
    )
    assert not bool(raw.detected[0]) and bool(drs.detected[0])
    assert float(drs.snr_fundamental[0] - raw.snr_fundamental[0]) > 10.0
