"""Tests of pygear.analysis.condition.gear_indicators and pygear.analysis.condition.tsa_bands.

Every reference follows from the definitions (Stewart 1977; Zakrajsek et al. 1993;
Lebold et al. 2000) applied by hand to signals built from known components: sums of
cosines at integer orders of one revolution, whose discrete means are exact, and
seeded Gaussian noise, whose normalized moments are 3, 15 and 105 with sampling
spreads derived below.  No reference comes from the code under test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from pygear.analysis.condition import gear_indicators as gi
from pygear.analysis.signals.signal import SignalError

ROUND_OFF = 1e-12
"""Relative tolerance for results that are exact in exact arithmetic: an rFFT/irFFT
pair and sums over at most 65536 samples lose O(log2(N) eps) and O(N eps) relative,
at most 65536 * 2.2e-16 = 1.5e-11 in the worst case and ~1e-14 in practice (random
round-off grows as sqrt(N)); 1e-12 leaves a factor of 100 over the practical bound."""


def angles(count: int) -> np.ndarray:
    """One revolution sampled at ``count`` uniform steps."""
    return 2.0 * np.pi * np.arange(count) / count


def tone(theta: np.ndarray, order: int, amplitude: float, phase: float = 0.0) -> np.ndarray:
    return amplitude * np.cos(order * theta + phase)


# --------------------------------------------------------------------------- bands


def test_bands_remove_exactly_their_orders_and_keep_the_rest() -> None:
    count, mesh = 512, 21
    theta = angles(count)
    rng = np.random.default_rng(7)
    groups = {
        "mean": [0],
        "shaft": [1, 2, 3],
        "mesh": [mesh, 2 * mesh],
        "sidebands": [mesh - 1, mesh + 1, 2 * mesh - 1, 2 * mesh + 1],
        "other": [5, 9, mesh + 4, 3 * mesh - 5, 200],
    }
    parts = {}
    for name, orders in groups.items():
        parts[name] = sum(
            tone(theta, order, rng.uniform(0.5, 2.0), rng.uniform(0, 2 * np.pi)) for order in orders
        )
    tsa = sum(parts.values())
    scale = ROUND_OFF * np.max(np.abs(tsa))

    regular = gi.regular_signal(tsa, mesh)
    residual = gi.residual_signal(tsa, mesh)
    difference = gi.difference_signal(tsa, mesh)

    np.testing.assert_allclose(
        regular, parts["shaft"] + parts["mesh"] + parts["sidebands"], 0, scale
    )
    np.testing.assert_allclose(residual, parts["sidebands"] + parts["other"], 0, scale)
    np.testing.assert_allclose(difference, parts["other"], 0, scale)
    # the three bands and the mean add back to the revolution
    np.testing.assert_allclose(parts["mean"] + regular + difference, tsa, 0, scale)


def test_band_parameters_choose_the_orders() -> None:
    count, mesh = 512, 21
    theta = angles(count)
    shaft_2, shaft_3 = tone(theta, 2, 1.0), tone(theta, 3, 0.7, 0.2)
    second_mesh, second_upper = tone(theta, 2 * mesh, 1.3, 0.4), tone(theta, 2 * mesh + 1, 0.6)
    tsa = tone(theta, mesh, 2.0) + shaft_2 + shaft_3 + second_mesh + second_upper
    scale = ROUND_OFF * np.max(np.abs(tsa))

    # one shaft order and one mesh harmonic: orders 2, 3, 2Z and 2Z+1 are left over
    difference = gi.difference_signal(tsa, mesh, shaft_harmonics=1, mesh_harmonics=1)
    np.testing.assert_allclose(difference, shaft_2 + shaft_3 + second_mesh + second_upper, 0, scale)
    residual = gi.residual_signal(tsa, mesh, shaft_harmonics=2, mesh_harmonics=1)
    np.testing.assert_allclose(residual, shaft_3 + second_mesh + second_upper, 0, scale)


def test_mesh_band_envelope_of_an_amplitude_modulated_mesh_tone() -> None:
    # A cos(Z t) (1 + m cos t) = A cos(Z t) + (A m / 2)[cos((Z-1) t) + cos((Z+1) t)]: the
    # band Z +/- s (s >= 1) holds all of it and its envelope is A (1 + m cos t); order 3
    # and the second mesh harmonic lie outside the band and must not show.
    count, mesh, amplitude, depth = 1024, 24, 1.7, 0.4
    theta = angles(count)
    modulated = amplitude * np.cos(mesh * theta) * (1.0 + depth * np.cos(theta))
    tsa = modulated + tone(theta, 3, 2.0) + tone(theta, 2 * mesh, 1.5, 0.3)
    envelope = gi.mesh_band_envelope(tsa, mesh)
    expected = amplitude * (1.0 + depth * np.cos(theta))
    np.testing.assert_allclose(envelope, expected, 0, ROUND_OFF * np.max(np.abs(tsa)))


# --------------------------------------------------------------------------- statistics


def test_sine_kurtosis_crest_factor_and_rms() -> None:
    # the mean of cos^2 and cos^4 over N samples of whole periods is exactly 1/2 and 3/8
    # when N > 4 samples per period, so kurtosis = (3/8) / (1/2)^2 = 1.5; the peak is
    # sampled at t = 0, so the crest factor is 1 / (1/sqrt 2) = sqrt 2
    theta, amplitude = angles(1000), 3.5
    sine = tone(theta, 5, amplitude)
    assert gi.kurtosis(sine) == pytest.approx(1.5, rel=ROUND_OFF)
    assert gi.crest_factor(sine) == pytest.approx(math.sqrt(2.0), rel=ROUND_OFF)
    assert gi.rms(sine) == pytest.approx(amplitude / math.sqrt(2.0), rel=ROUND_OFF)


def test_gaussian_difference_signal_has_moments_3_15_105() -> None:
    count, mesh = 65536, 37
    theta = angles(count)
    noise = np.random.default_rng(2024).standard_normal(count)
    tsa = tone(theta, mesh, 4.0) + tone(theta, 2 * mesh, 1.0, 0.3) + tone(theta, 1, 2.0) + noise
    # With 5 mesh harmonics, 18 of the 32768 orders are removed: the difference signal
    # is the noise projected off 0.05 % of its spectrum, still Gaussian, its samples
    # correlated at the 1e-3 level (negligible next to the spreads below).
    # Sampling standard deviations of the normalized moments g_p = m_p / m_2^(p/2) of N
    # Gaussian samples, by the delta method with the Gaussian moments
    # mu_2k = (2k-1)!! (mean removal adds nothing: the odd moments vanish):
    #   N var(g_p) = var(x^p) - 2 c cov(x^p, x^2) + c^2 var(x^2),  c = (p/2) mu_p
    #   p = 4: 96 - 2*6*12 + 36*2               = 24        (the familiar sqrt(24/N))
    #   p = 6: 10170 - 2*45*90 + 45^2*2         = 6120
    #   p = 8: 2016000 - 2*420*840 + 420^2*2    = 1663200
    # The O(1/N) biases (-6/N, ..., -1260/N) are far inside these spreads.  Six
    # standard deviations: a seeded draw fails only if the code is wrong.
    fm4 = gi.fm4(tsa, mesh, mesh_harmonics=5)
    m6a = gi.m6a(tsa, mesh, mesh_harmonics=5)
    m8a = gi.m8a(tsa, mesh, mesh_harmonics=5)
    assert abs(fm4 - 3.0) < 6.0 * math.sqrt(24.0 / count)
    assert abs(m6a - 15.0) < 6.0 * math.sqrt(6120.0 / count)
    assert abs(m8a - 105.0) < 6.0 * math.sqrt(1663200.0 / count)


def test_localized_tooth_impulse_raises_fm4() -> None:
    count, mesh = 4096, 32
    theta = angles(count)
    noise = 0.05 * np.random.default_rng(11).standard_normal(count)
    healthy = tone(theta, mesh, 1.0) + tone(theta, 2 * mesh, 0.3, 0.5) + noise
    # one tooth (of 32, 128 samples each) strikes: a Gaussian pulse 3 samples wide
    tooth = np.arange(count) - 17 * count // mesh
    faulty = healthy + np.exp(-0.5 * (tooth / 3.0) ** 2)
    spread = math.sqrt(24.0 / count)  # sampling std of the Gaussian kurtosis, as above
    assert abs(gi.fm4(healthy, mesh) - 3.0) < 6.0 * spread
    # by hand: sum p^2 = 3 sqrt(pi) = 5.3 and sum p^4 = 3 sqrt(pi/2) = 3.8 against the
    # noise's N sigma^2 = 10.2, so FM4 ~ N (3.8 + ...) / (5.3 + 10.2)^2 ~ 66; ask for
    # more than 3 + 100 spreads (10.7), far above any healthy value
    assert gi.fm4(faulty, mesh) > 3.0 + 100.0 * spread


# --------------------------------------------------------------------------- indicators


def test_fm0_of_a_pure_mesh_tone_is_two() -> None:
    # peak-to-peak 2A over the amplitude A of the only mesh harmonic; N / (2Z) = 16 is an
    # integer, so both the maximum (t = 0) and the minimum (Z t = pi) are samples
    count, mesh, amplitude = 1024, 32, 2.5
    theta = angles(count)
    assert gi.fm0(tone(theta, mesh, amplitude), mesh) == pytest.approx(2.0, rel=ROUND_OFF)
    # A cos u + B cos 2u with A >= 4B: max A + B at u = 0, min B - A at u = pi (the
    # quadratic A c + B (2c^2 - 1) in c = cos u has its vertex at c <= -1), so
    # FM0 = 2A / (A + B)
    second = 0.5
    tsa = tone(theta, mesh, amplitude) + tone(theta, 2 * mesh, second)
    expected = 2.0 * amplitude / (amplitude + second)
    assert gi.fm0(tsa, mesh) == pytest.approx(expected, rel=ROUND_OFF)


def test_energy_ratio_of_known_components() -> None:
    count, mesh = 1024, 30
    theta = angles(count)
    mesh_amp, shaft_amp, second_amp, other_amp = 2.0, 0.8, 0.6, 0.3
    tsa = (
        tone(theta, mesh, mesh_amp)
        + tone(theta, 1, shaft_amp, 0.2)
        + tone(theta, 2 * mesh, second_amp, 1.0)
        + tone(theta, 7, other_amp, 0.4)
    )
    # difference = order 7 only, regular = orders 1, Z and 2Z: RMS of a sum of distinct
    # integer orders is sqrt(sum A^2 / 2)
    expected = other_amp / math.sqrt(mesh_amp**2 + shaft_amp**2 + second_amp**2)
    assert gi.energy_ratio(tsa, mesh) == pytest.approx(expected, rel=ROUND_OFF)


def test_sideband_level_factor_of_known_components() -> None:
    count, mesh = 1024, 30
    theta = angles(count)
    mesh_amp, lower, upper, other = 2.0, 0.25, 0.4, 0.7
    tsa = (
        tone(theta, mesh, mesh_amp)
        + tone(theta, mesh - 1, lower, 0.3)
        + tone(theta, mesh + 1, upper, 1.1)
        + tone(theta, 7, other)
        + 5.0  # a mean: the standard deviation ignores it
    )
    std = math.sqrt((mesh_amp**2 + lower**2 + upper**2 + other**2) / 2.0)
    expected = (lower + upper) / std
    assert gi.sideband_level_factor(tsa, mesh) == pytest.approx(expected, rel=ROUND_OFF)


def residual_case() -> tuple[np.ndarray, int, float, float]:
    """A TSA whose residual is a cos(7t) + b cos(22t + 0.3), with Z = 21.

    Orders 7 and 22 have no relation p*7 +/- q*22 = 0 with p + q <= 4 (3*7 = 21 is not
    22), so the residual's variance is (a^2 + b^2)/2 and its 4th moment
    3/8 (a^4 + b^4) + 6 (a^2/2)(b^2/2) = 3/8 (a^4 + b^4) + 3/2 a^2 b^2 exactly.
    """
    count, mesh, a, b = 512, 21, 0.8, 0.5
    theta = angles(count)
    tsa = (
        tone(theta, mesh, 3.0)
        + tone(theta, 2 * mesh, 1.0, 0.2)
        + tone(theta, 2, 1.5)
        + tone(theta, 7, a)
        + tone(theta, mesh + 1, b, 0.3)
    )
    return tsa, mesh, a, b


def test_na4_with_and_without_history_equals_the_hand_formula() -> None:
    tsa, mesh, a, b = residual_case()
    variance = (a**2 + b**2) / 2.0
    fourth = 3.0 / 8.0 * (a**4 + b**4) + 1.5 * a**2 * b**2
    assert gi.na4(tsa, mesh) == pytest.approx(fourth / variance**2, rel=ROUND_OFF)
    history = [0.2, 0.31]
    mean_variance = (history[0] + history[1] + variance) / 3.0
    expected = fourth / mean_variance**2
    assert gi.na4(tsa, mesh, history=history) == pytest.approx(expected, rel=ROUND_OFF)
    # gear_indicators reads the same variances from earlier results
    earlier = [{"residual_variance": v, "envelope_variance": 1.0} for v in history]
    result = gi.gear_indicators(tsa, mesh, history=earlier)
    assert result["na4"] == pytest.approx(expected, rel=ROUND_OFF)
    assert result["residual_variance"] == pytest.approx(variance, rel=ROUND_OFF)


def test_nb4_of_a_modulated_mesh_tone_equals_the_hand_formula() -> None:
    # envelope A (1 + m cos t): centred A m cos t, variance (A m)^2 / 2, 4th moment
    # 3/8 (A m)^4; alone its kurtosis is 1.5
    count, mesh, amplitude, depth = 1024, 24, 1.7, 0.4
    theta = angles(count)
    tsa = amplitude * np.cos(mesh * theta) * (1.0 + depth * np.cos(theta))
    tsa = tsa + tone(theta, 3, 2.0)
    assert gi.nb4(tsa, mesh) == pytest.approx(1.5, rel=ROUND_OFF)
    swing = amplitude * depth
    history = [0.05]
    expected = 3.0 / 8.0 * swing**4 / ((history[0] + swing**2 / 2.0) / 2.0) ** 2
    assert gi.nb4(tsa, mesh, history=history) == pytest.approx(expected, rel=ROUND_OFF)


def test_gear_indicators_returns_every_indicator() -> None:
    tsa, mesh, _, _ = residual_case()
    result = gi.gear_indicators(tsa, mesh)
    assert set(result) == set(gi.INDICATORS)
    assert all(isinstance(value, float) for value in result.values())
    # a pure mesh tone has an empty difference signal: FM4 is 0/0, reported as NaN
    pure = gi.gear_indicators(tone(angles(256), 16, 1.0), 16)
    assert math.isnan(pure["fm4"]) and pure["fm0"] == pytest.approx(2.0, rel=ROUND_OFF)


def test_dataset_wrapper_over_channels_with_a_trend() -> None:
    count, mesh = 1024, 24
    theta = angles(count)
    amplitudes = np.array([1.0, 3.0])
    depth = 0.4
    rows = amplitudes[:, None] * np.cos(mesh * theta) * (1.0 + depth * np.cos(theta))
    tsa = xr.DataArray(
        rows,
        dims=("channel", "angle"),
        coords={"channel": ["a", "b"], "angle": ("angle", theta, {"units": "rad"})},
        attrs={"units": "m/s^2", "long_name": "TSA"},
    )
    first = gi.gear_indicators_dataset(tsa, mesh)
    assert set(first.data_vars) == set(gi.INDICATORS)
    assert first["rms"].attrs["units"] == "m/s^2" and first["fm4"].attrs["units"] == "1"
    assert all("long_name" in first[name].attrs for name in first.data_vars)
    np.testing.assert_allclose(first["nb4"], 1.5, rtol=ROUND_OFF)
    # A cos(Z t) + (A m / 2)[cos((Z-1) t) + cos((Z+1) t)]: sidebands A m over the std
    # sqrt((A^2 + 2 (A m / 2)^2) / 2), whatever the channel's amplitude A
    slf = depth / math.sqrt((1.0 + depth**2 / 2.0) / 2.0)
    np.testing.assert_allclose(first["sideband_level_factor"], slf, rtol=ROUND_OFF)
    # a second record with the first as history: per channel the envelope variance
    # (A m)^2 / 2 is the same in both records, so NB4 is again 1.5
    second = gi.gear_indicators_dataset(tsa, mesh, history=[first])
    np.testing.assert_allclose(second["nb4"], 1.5, rtol=ROUND_OFF)
    # a doubled record against that history: mean variance (v + 4v)/2 = 2.5 v, 4th
    # moment 16 m4, so NB4 = 16 * 1.5 / 2.5^2 = 3.84
    doubled = gi.gear_indicators_dataset(
        (2.0 * tsa).assign_attrs(units="m/s^2"), mesh, history=[first]
    )
    np.testing.assert_allclose(doubled["nb4"], 16.0 * 1.5 / 2.5**2, rtol=ROUND_OFF)


# --------------------------------------------------------------------------- bad input


REVOLUTION = np.cos(8 * angles(64)) + 0.1 * np.cos(3 * angles(64))
NAN_REVOLUTION = np.where(np.arange(64) == 5, np.nan, REVOLUTION)


@pytest.mark.parametrize(
    ("call", "parameter"),
    [
        (lambda: gi.fm4(np.ones((2, 64)), 8), "tsa"),
        (lambda: gi.fm4(np.ones(8), 2), "tsa"),
        (lambda: gi.fm4(NAN_REVOLUTION, 8), "tsa"),
        (lambda: gi.fm4(REVOLUTION + 0j, 8), "tsa"),
        (lambda: gi.fm4(REVOLUTION, 31), "mesh_order"),  # Z + 1 = 32 is the Nyquist order
        (lambda: gi.fm4(REVOLUTION, 1), "mesh_order"),
        (lambda: gi.fm4(REVOLUTION, 8.0), "mesh_order"),
        (lambda: gi.fm4(REVOLUTION, 8, mesh_harmonics=4), "mesh_harmonics"),  # 4*8+1 > 31
        (lambda: gi.fm4(REVOLUTION, 8, shaft_harmonics=-1), "shaft_harmonics"),
        (lambda: gi.nb4(REVOLUTION, 8, sidebands=8), "sidebands"),  # would reach order 0
        (lambda: gi.na4(REVOLUTION, 8, history=[-1.0]), "history"),
        (lambda: gi.na4(REVOLUTION, 8, history=["x"]), "history"),
        (lambda: gi.gear_indicators(REVOLUTION, 8, history=[{"fm4": 3.0}]), "history"),
        (lambda: gi.gear_indicators_dataset(REVOLUTION, 8), "tsa"),
        (lambda: gi.gear_indicators_dataset(xr.DataArray(REVOLUTION), 8), "tsa"),
        (
            lambda: gi.gear_indicators_dataset(
                xr.DataArray(np.ones((2, 64)), dims=("a", "b"), attrs={"units": "g"}), 8
            ),
            "dim",
        ),
        (
            lambda: gi.gear_indicators_dataset(
                xr.DataArray(
                    REVOLUTION,
                    dims="angle",
                    coords={"angle": np.sort(np.random.default_rng(0).uniform(0, 6, 64))},
                    attrs={"units": "g"},
                ),
                8,
            ),
            "tsa",
        ),
    ],
)
def test_bad_input_gives_a_one_line_error_naming_the_parameter(call, parameter) -> None:
    with pytest.raises(SignalError) as caught:
        call()
    message = str(caught.value)
    assert isinstance(caught.value, ValueError)
    assert message.startswith(f"{parameter}:"), message
    assert "\n" not in message
