"""Sensors on the ring: windows, the structure's modes, noise, and the sideband rules of
equally spaced planets (McFadden & Smith 1985; Inalpolat & Kahraman 2009)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pygear import CaseError, Probe, StructuralMode
from pygear.analysis.condition.sensor_signal import (
    add_noise,
    structural_response,
    transmission_window,
)
from pygear.analysis.time.transient import run_transient
from pygear.model.case import load_case, replace_parameter


@pytest.mark.parametrize("planets", [3, 4, 5])
def test_windows_of_equally_spaced_planets_sum_to_one(planets):
    """Planets 2 pi / N apart: cos^2 windows of width 4 pi / N overlap by half, and
    cos^2(pi d / W) + cos^2(pi (d - W/2) / W) = cos^2 + sin^2 = 1; rectangular windows of
    width 2 pi / N tile the circle."""
    carrier = np.linspace(0.0, 4 * math.pi, 5001) + 1e-3  # off the rectangles' edges
    for shape, width in (("hann", 4 * math.pi / planets), ("rectangular", 2 * math.pi / planets)):
        total = sum(
            transmission_window(carrier + 2 * math.pi * n / planets - 1.0, width, shape)
            for n in range(planets)
        )
        np.testing.assert_allclose(total, 1.0, atol=1e-12)  # round-off of cos^2 only


def test_window_is_zero_beyond_half_its_width_and_wraps():
    width = math.radians(90)
    angles = np.radians([0.0, 44.9, 45.1, 180.0, 360.0 - 44.9, 720.0])
    hann = transmission_window(angles, width, "hann")
    rectangular = transmission_window(angles, width, "rectangular")
    assert hann[0] == pytest.approx(1.0) and hann[5] == pytest.approx(1.0)  # two turns on
    assert hann[2] == 0.0 and hann[3] == 0.0
    assert hann[1] == pytest.approx(math.cos(math.pi * math.radians(44.9) / width) ** 2)
    assert list(rectangular) == [1.0, 1.0, 0.0, 0.0, 1.0, 1.0]


def _sine_amplitude(signal: np.ndarray, frequency: float, rate: float) -> float:
    t = np.arange(signal.size) / rate
    basis = np.column_stack(
        [np.cos(2 * math.pi * frequency * t), np.sin(2 * math.pi * frequency * t)]
    )
    coefficients = np.linalg.lstsq(basis, signal, rcond=None)[0]
    return float(np.hypot(*coefficients))


@pytest.mark.parametrize("gain", [1.0, -0.5])
def test_structural_mode_amplifies_its_resonance_as_the_closed_form(gain):
    """H(w_n) = 1 + g (-w_n^2) / (2 j zeta w_n^2) = 1 + j g / (2 zeta): the bilinear
    transform pre-warped at w_n keeps w_n's response exact."""
    rate, frequency, zeta = 20e3, 2500.0, 0.05
    mode = StructuralMode(frequency=frequency, damping_ratio=zeta, gain=gain)
    t = np.arange(40000) / rate
    response = structural_response(np.sin(2 * math.pi * frequency * t), rate, (mode,))
    # steady part: the start transient decays as exp(-zeta w_n t); after 1 s it is e^-785
    amplitude = _sine_amplitude(response[20000:], frequency, rate)
    assert amplitude == pytest.approx(abs(1 + 1j * gain / (2 * zeta)), rel=1e-9)
    # far below the mode the flat path is left alone: |H - 1| ~ g (f / f_n)^2 = 4e-6 g
    low = structural_response(np.sin(2 * math.pi * 5.0 * t), rate, (mode,))
    assert _sine_amplitude(low[20000:], 5.0, rate) == pytest.approx(1.0, abs=1e-5)


def test_structural_mode_above_nyquist_is_refused():
    mode = StructuralMode(frequency=12e3, damping_ratio=0.05, gain=1.0)
    with pytest.raises(CaseError, match="Nyquist"):
        structural_response(np.zeros(10), 20e3, (mode,))


def test_noise_has_the_stated_signal_to_noise_ratio():
    """The noise power is P / 10^(SNR/10); its estimate from n samples has relative
    standard deviation sqrt(2/n) = 0.45 % at n = 1e5: allow 2 %."""
    rng = np.random.default_rng(1)
    signal = np.sin(np.linspace(0, 2000 * math.pi, 100000)) + 0.1 * rng.normal(size=100000)
    noisy = add_noise(signal, 10.0, seed=7)
    ratio = np.mean(signal**2) / np.mean((noisy - signal) ** 2)
    assert 10 * math.log10(ratio) == pytest.approx(10.0, abs=10 * math.log10(1.02))
    np.testing.assert_array_equal(add_noise(signal, 10.0, seed=7), noisy)  # seeded
    assert add_noise(signal, None, seed=7) is signal  # off by default


@pytest.mark.parametrize(
    "change, words",
    [
        (dict(direction="axial"), ["direction", "radial, tangential"]),
        (dict(window_width_deg=400.0), ["window_width_deg", "(0, 360]"]),
        (dict(stage="stage9"), ["sensors.ring_sensor.stage", "not a planetary stage"]),
        (dict(name="ring sensor"), ["name", "letter"]),
        (dict(noise_snr_db=float("nan")), ["noise_snr_db"]),
        (dict(structure=(StructuralMode(0.0, 0.05, 1.0),)), ["structure[0].frequency"]),
    ],
)
def test_bad_sensor_is_refused_in_one_line(change, words):
    case = load_case("yang2016_planetary")
    sensor = dataclasses.replace(case.sensors[0], **change)
    with pytest.raises(CaseError) as error:
        dataclasses.replace(case, sensors=(sensor,))
    message = str(error.value)
    assert "\n" not in message and all(word in message for word in words)


def test_probe_of_an_unknown_sensor_names_the_sensors():
    case = load_case("yang2016_planetary")
    scene = case.scene("runup_sensor")
    transient = dataclasses.replace(scene.transient, probes=(Probe("sensor", "housing_top"),))
    with pytest.raises(CaseError, match="not a sensor of the case .sensors: ring_sensor"):
        dataclasses.replace(case, scenes=(dataclasses.replace(scene, transient=transient),))


def test_scene_parameters_reach_a_sensor():
    case = load_case("yang2016_planetary")
    noisy = replace_parameter(case, "sensors.ring_sensor.noise_snr_db", 20.0)
    assert noisy.sensors[0].noise_snr_db == 20.0
    with pytest.raises(CaseError, match="sensors: ring_sensor"):
        replace_parameter(case, "sensors.top.noise_snr_db", 20.0)


def _carrier_orders(run, revolutions: int) -> np.ndarray:
    """Amplitudes of the sensor channel at whole carrier orders over the run's last
    ``revolutions`` turns, resampled at uniform carrier angle (cubic, 4096 per turn)."""
    from scipy.interpolate import CubicSpline

    angle = run.rotation_displacement.sel(rotation_dof="planetary.carrier.theta_z").values
    signal = run.sensor_acceleration.sel(sensor="ring_sensor").values
    end = math.floor(angle[-1] / (2 * math.pi)) * 2 * math.pi
    grid = end - revolutions * 2 * math.pi + np.arange(revolutions * 4096) * 2 * math.pi / 4096
    spectrum = np.abs(np.fft.rfft(CubicSpline(angle, signal)(grid))) / grid.size * 2
    return spectrum[::revolutions]  # whole orders


def _check_rule(orders: np.ndarray, centre: int, planets: int = 3) -> dict[int, float]:
    """dB of every order in centre +- 10 below the largest multiple of ``planets`` there."""
    span = range(centre - 10, centre + 11)
    dominant = max(orders[o] for o in span if o % planets == 0)
    return {o: 20 * math.log10(orders[o] / dominant) for o in span if o % planets}


def test_study_case_sensor_hears_only_multiples_of_the_planet_count():
    """Z_r = 96, three equally spaced planets in phase: around each mesh harmonic 96 m the
    sensor hears the carrier orders 96 m + 3k only (McFadden & Smith 1985); the others
    stay 20 dB below the strongest of them."""
    case = load_case("yang2016_planetary")
    scene = case.scene("steady_sensor")
    run = run_transient(case.for_scene(scene), scene)
    assert run.equilibrium_speed.sel(body="planetary.carrier") == pytest.approx(120.0, rel=1e-5)
    orders = _carrier_orders(run.sel(time=slice(1.0, None)), revolutions=5)
    for harmonic in range(1, 7):
        suppressed = _check_rule(orders, 96 * harmonic)
        assert max(suppressed.values()) < -20.0, (harmonic, suppressed)


def test_sequentially_phased_stage_suppresses_its_mesh_order():
    """Z_r = 97 with three planets: a mesh harmonic 97 m that is no multiple of 3 is heard
    at least 20 dB below the nearest multiples of 3 (McFadden & Smith 1985, the
    asymmetric sidebands; Inalpolat & Kahraman 2009, sequentially phased sets), and so is
    every other order that is no multiple of 3."""
    case = load_case("sequential_planetary")
    run = run_transient(case, case.scene("steady_sensor"))
    orders = _carrier_orders(run.sel(time=slice(2.0, None)), revolutions=4)
    for harmonic in (1, 2, 4, 5):  # 97 m not a multiple of 3
        suppressed = _check_rule(orders, 97 * harmonic)
        assert suppressed[97 * harmonic] < -20.0, (harmonic, suppressed)
        assert max(suppressed.values()) < -20.0, (harmonic, suppressed)


def test_study_run_up_records_its_sensor_as_ring_sensor_acceleration():
    """The study case's run-up keeps its sensor as the channel ring_sensor_acceleration;
    the steady scene records it into the grouped sensor_acceleration(sensor)."""
    case = load_case("yang2016_planetary")
    for name in ("runup_sensor", "steady_sensor"):
        scene = case.scene(name)
        short = dataclasses.replace(scene.transient, duration=0.01, mean_window=0.01)
        scene = dataclasses.replace(scene, transient=short)
        run = run_transient(case.for_scene(scene), scene)
        if name == "runup_sensor":
            assert run["ring_sensor_acceleration"].attrs["target"] == "ring_sensor"
            assert "sensor_acceleration" not in run
        else:
            assert list(run.sensor_acceleration.sensor.values) == ["ring_sensor"]
            assert "ring_sensor_acceleration" not in run
