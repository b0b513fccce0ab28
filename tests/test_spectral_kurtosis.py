"""Tests of pygear.analysis.condition.spectral_kurtosis.

References follow from the definitions (Antoni 2006, 2007; Bogert, Healy & Tukey 1963)
applied to signals built by hand: seeded Gaussian noise, whose spectral kurtosis is 0
with a sampling spread derived below, sines at bin centres, whose STFT magnitude is
constant, decaying resonance bursts in a known band, and a signal plus its echo.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pygear.analysis.condition import spectral_kurtosis as sk
from pygear.analysis.signals.signal import SignalError

ROUND_OFF = 1e-12
"""Relative tolerance for results exact in exact arithmetic: FFTs of at most 2^16 points
and means over at most 2^9 frames lose O(log2(N) eps) and O(K eps) relative, under
1e-13; 1e-12 leaves a factor of 10."""


def gaussian_spread(samples: int) -> float:
    """Sampling standard deviation of <|z|^4> / <|z|^2>^2 - 2 over ``samples``
    independent circular complex Gaussians ``z``.

    With P = |z|^2 exponential of mean 1: E P^2 = 2, E P^3 = 6, E P^4 = 24, so
    var P^2 = 20, var P = 1, cov(P^2, P) = 4; the delta method on g = a / b^2 at
    (a, b) = (2, 1) (gradient (1, -4)) gives K var g = 20 - 2*4*4 + 16*1 = 4, i.e.
    2 / sqrt(K) (its O(1/K) bias, -2/K, is far smaller).
    """
    return 2.0 / math.sqrt(samples)


# --------------------------------------------------------------------------- spectral kurtosis


def test_spectral_kurtosis_of_stationary_gaussian_noise_is_zero() -> None:
    window, frames = 256, 512
    noise = np.random.default_rng(5).standard_normal(window * frames)
    # no overlap: the frames hold disjoint samples, so the K = 512 estimates of each bin
    # are independent; for bins 2 .. window/2 - 2 the Hann-windowed DFT of white noise is
    # circular complex Gaussian (E[X^2] involves the squared window's DFT, which is
    # non-zero only at lags 0, +/-1, +/-2 bins, so it vanishes away from DC and Nyquist)
    result = sk.spectral_kurtosis(noise, 1000.0, window_length=window, overlap=0.0)
    assert result.sizes["frequency"] == window // 2 + 1
    assert result["frequency"].values[1] == pytest.approx(1000.0 / window, rel=ROUND_OFF)
    assert result.attrs["units"] == "1" and result["frequency"].attrs["units"] == "Hz"
    interior = result.values[2 : window // 2 - 1]
    spread = gaussian_spread(frames)
    # each bin within 6 spreads (127 bins: a 6-sigma excursion has odds ~1e-7)
    assert np.max(np.abs(interior)) < 6.0 * spread
    # bins 3 apart are uncorrelated (the Hann window couples only lags <= 2), hence
    # independent: their mean has spread 2 / sqrt(K * bins)
    spaced = interior[::3]
    assert abs(np.mean(spaced)) < 6.0 * spread / math.sqrt(spaced.size)


def test_spectral_kurtosis_of_a_stationary_sine_is_minus_one() -> None:
    # a sine at bin 37 of a 256-point window: the periodic Hann window's spectrum is
    # zero beyond +/-1 bin, so bins 36..38 see the positive-frequency part alone and
    # |X| is the same in every frame: <|X|^4> / <|X|^2>^2 = 1, SK = -1
    rate, window = 2560.0, 256
    time = np.arange(40 * window) / rate
    sine = 1.7 * np.sin(2.0 * np.pi * (37 * rate / window) * time + 0.4)
    result = sk.spectral_kurtosis(sine, rate, window_length=window, overlap=0.75)
    np.testing.assert_allclose(result.values[36:39], -1.0, atol=ROUND_OFF)


# --------------------------------------------------------------------------- kurtogram


def test_kurtogram_levels_follow_the_one_third_binary_tree() -> None:
    third = math.log2(3.0) - 1.0  # 0.585, which Antoni's figures label .6
    expected = [0.0, 1.0, 1.0 + third, 2.0, 2.0 + third, 3.0]
    np.testing.assert_allclose(sk.kurtogram_levels(3), expected, rtol=ROUND_OFF)
    noise = np.random.default_rng(1).standard_normal(8192)
    dataset, _ = sk.fast_kurtogram(noise, 1000.0, max_level=3)
    # bandwidth fs / 2^(level + 1): 500, 250, 166.7, 125, 83.3, 62.5 Hz
    widths = 1000.0 / 2.0 ** (np.array(expected) + 1.0)
    np.testing.assert_allclose(dataset["bandwidth"].values, widths, rtol=1e-9)
    np.testing.assert_array_equal(dataset["band_count"].values, [1, 2, 3, 4, 6, 8])
    assert dataset.sizes["frequency"] == 3 * 2**3
    assert dataset["kurtosis"].attrs["units"] == "1"
    assert dataset["frequency"].attrs["units"] == "Hz"


def test_kurtogram_of_gaussian_noise_is_near_zero_everywhere() -> None:
    count, max_level = 2**16, 4
    noise = np.random.default_rng(9).standard_normal(count)
    dataset, _ = sk.fast_kurtogram(noise, 1.0, max_level=max_level)
    # the narrowest bands hold count / 2^(max_level + 1) = 2048 bins, of which the
    # 7/8 outside the tapered ends (1/16 each) are kept: spread 2 / sqrt(1792) = 0.047
    # (gaussian_spread); 52 bands, each within 6 spreads
    kept = count // 2 ** (max_level + 1) * 7 // 8
    assert np.max(np.abs(dataset["kurtosis"].values)) < 6.0 * gaussian_spread(kept)


def test_kurtogram_best_band_holds_the_resonance_of_buried_bursts() -> None:
    rate, count = 20000.0, 2**16
    time = np.arange(count) / rate
    resonance, decay, period = 6000.0, 1e-3, 0.01
    # a tooth or bearing impact every 10 ms rings the 6 kHz resonance down in 1 ms
    bursts = np.zeros(count)
    for start in np.arange(0.002, time[-1], period):
        after = time >= start
        ring = time[after] - start
        bursts[after] += np.exp(-ring / decay) * np.sin(2.0 * np.pi * resonance * ring)
    rng = np.random.default_rng(3)
    # buried: the bursts' RMS (0.16) is half the noise's and a tenth of the tones'
    signal = (
        bursts
        + 0.3 * rng.standard_normal(count)
        + 2.0 * np.sin(2.0 * np.pi * 50.0 * time)
        + 1.0 * np.sin(2.0 * np.pi * 1234.5 * time)
    )
    dataset, best = sk.fast_kurtogram(signal, rate)
    assert best.low <= resonance <= best.high
    assert best.kurtosis == pytest.approx(dataset.attrs["best_kurtosis"])
    assert best.kurtosis == pytest.approx(float(dataset["kurtosis"].max()))
    # and it stands out of the noise: above 6 spreads of the narrowest default band
    # (256 bins, 224 kept)
    assert best.kurtosis > 6.0 * gaussian_spread(224)


# --------------------------------------------------------------------------- cepstrum


def test_cepstrum_of_a_signal_and_its_echo_peaks_at_the_delay() -> None:
    rate, count, delay, gain = 8192.0, 8192, 300, 0.5
    source = np.random.default_rng(4).standard_normal(count)
    # a circular echo: its spectrum is exactly X (1 + a exp(-i w tau)), whose log
    # magnitude adds sum_k (-1)^(k+1) (a^k / k) cos(k w tau): a / 2 = 0.25 at tau
    echoed = source + gain * np.roll(source, delay)
    cepstrum = sk.real_cepstrum(echoed, rate)
    assert cepstrum["quefrency"].attrs["units"] == "s"
    positive = cepstrum.values[1 : count // 2]
    assert int(np.argmax(positive)) + 1 == delay
    assert float(cepstrum["quefrency"][delay]) == pytest.approx(delay / rate, rel=ROUND_OFF)
    # the noise's own cepstrum at any quefrency n > 0 is (1/N) sum_k log|X_k| cos(...):
    # log|X_k| of white Gaussian noise has variance pi^2 / 24 (half the log of an
    # exponential variable), and N/2 independent pairs give a spread sqrt(pi^2/(24 N))
    spread = math.sqrt(math.pi**2 / (24.0 * count))
    assert abs(cepstrum.values[delay] - gain / 2.0) < 6.0 * spread


# --------------------------------------------------------------------------- bad input


NOISE = np.random.default_rng(0).standard_normal(4096)


@pytest.mark.parametrize(
    ("call", "parameter"),
    [
        (lambda: sk.spectral_kurtosis(NOISE.reshape(2, -1), 1.0), "signal"),
        (lambda: sk.spectral_kurtosis(NOISE[:300], 1.0), "signal"),  # 2 frames need 384
        (lambda: sk.spectral_kurtosis(NOISE, 0.0), "sample_rate"),
        (lambda: sk.spectral_kurtosis(NOISE, 1.0, window_length=100.5), "window_length"),
        (lambda: sk.spectral_kurtosis(NOISE, 1.0, overlap=1.0), "overlap"),
        (lambda: sk.fast_kurtogram(NOISE, 1.0, max_level=8), "max_level"),  # 4096/2^9 < 32
        (lambda: sk.fast_kurtogram(NOISE[:100], 1.0), "signal"),
        (lambda: sk.fast_kurtogram(np.ones(4096), 1.0), "signal"),
        (lambda: sk.real_cepstrum(np.where(NOISE > 3.0, np.inf, NOISE), 1.0), "signal"),
        (lambda: sk.real_cepstrum(NOISE, float("nan")), "sample_rate"),
        (lambda: sk.kurtogram_levels(0), "max_level"),
    ],
)
def test_bad_input_gives_a_one_line_error_naming_the_parameter(call, parameter) -> None:
    with pytest.raises(SignalError) as caught:
        call()
    message = str(caught.value)
    assert message.startswith(f"{parameter}:"), message
    assert "\n" not in message
