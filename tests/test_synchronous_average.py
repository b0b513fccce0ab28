"""Time-synchronous averaging (docs/condition_monitoring.md; Braun 1975; McFadden 1987,
1991, 1994).

Synthetic records whose content is known in closed form, at a known non-constant speed:

- seeded white noise of standard deviation sigma, sampled at the angle steps themselves,
  leaves sigma / sqrt(R) after R revolutions (to the sampling error of an RMS over M
  steps);
- a smooth periodic part on a uniform time grid comes back to the interpolation error
  bounds derived from its derivatives;
- the weights enter as sum w x / sum w, read at the crossing times;
- tachometer pulses land on the exact crossing times; the rebuilt angle converges at
  third order in the pulse spacing; Gaussian jitter attenuates order k by
  exp(-k^2 sigma_theta^2 / 2) (Souders et al. 1990);
- N Hann windows 2 pi k / N wide sum to k / 2 (k >= 2), rectangular ones to k;
- a transducer that hears the planet nearest to it: each planet's average is that
  planet's own tooth pattern (the marked tooth on the marked planet only, at its angle),
  and the sun's average puts a marked sun tooth at 2 pi k / Z_s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from pygear.analysis.condition.synchronous_average import (
    angle_from_tachometer,
    planet_average,
    planet_synchronous_average,
    planet_window,
    sun_average,
    sun_synchronous_average,
    synthetic_tachometer,
    time_synchronous_average,
    weighted_angle_average,
)
from pygear.analysis.signals.signal import SignalError

TWO_PI = 2.0 * math.pi
HARMONICS = ((1, 0.8, 0.3), (7, 0.5, 1.1), (20, 0.3, -0.4))
"""(order k, amplitude a_k, phase) of the periodic part P(theta) = sum a_k cos(k theta + phase)."""
GAUSSIAN_DERIVATIVE = (1.0, 1.0, 1.0, 1.5, 3.0)
"""Bounds on max |d^n/du^n exp(-u^2/2)|, n = 0..4: the Hermite functions He_n(u) e^{-u^2/2}
peak at 1, e^{-1/2}, 1, 1.38 (u = 0.74) and 3 (u = 0)."""


class SpeedLaw:
    """A known speed: omega(t) = W0 (1 + eps sin(2 pi f t)), so
    theta(t) = W0 t + W0 eps (1 - cos 2 pi f t) / (2 pi f).

    |d^n omega / dt^n| <= W0 eps (2 pi f)^n for n >= 1.
    """

    def __init__(self, mean_speed: float, depth: float, frequency: float):
        self.w0, self.eps, self.nu = mean_speed, depth, TWO_PI * frequency

    def theta(self, t):
        return self.w0 * t + self.w0 * self.eps / self.nu * (1.0 - np.cos(self.nu * t))

    def omega(self, t):
        return self.w0 * (1.0 + self.eps * np.sin(self.nu * t))

    def bound(self, n: int) -> float:
        """max |d^n theta / dt^n| for n >= 1."""
        return self.w0 * (1.0 + self.eps) if n == 1 else self.w0 * self.eps * self.nu ** (n - 1)

    def time_at(self, angles):
        """theta^-1 by Newton's method from the mean-speed guess (theta' >= W0 (1 - eps))."""
        t = np.asarray(angles, dtype=float) / self.w0
        for _ in range(60):
            t = t - (self.theta(t) - angles) / self.omega(t)
        assert np.max(np.abs(self.theta(t) - angles)) <= 1e-12 * max(1.0, np.max(angles))
        return t


LAW = SpeedLaw(mean_speed=TWO_PI * 5.0, depth=0.3, frequency=1.3)


def periodic_part(theta):
    return sum(a * np.cos(k * theta + phase) for k, a, phase in HARMONICS)


def derivative_bound(order: int) -> float:
    """max |P^(n)| <= sum a_k k^n."""
    return sum(a * k**order for k, a, _ in HARMONICS)


def fourth_derivative_bound(outer, inner) -> float:
    """Faa di Bruno: |(F o phi)''''| <= F4 p1^4 + 6 F3 p1^2 p2 + F2 (3 p2^2 + 4 p1 p3) + F1 p4
    with Fn >= max |F^(n)| and pn >= max |phi^(n)| (``outer(n)``, ``inner(n)``)."""
    p1, p2, p3, p4 = (inner(n) for n in (1, 2, 3, 4))
    return (
        outer(4) * p1**4
        + 6 * outer(3) * p1**2 * p2
        + outer(2) * (3 * p2**2 + 4 * p1 * p3)
        + outer(1) * p4
    )


# --------------------------------------------------------------------------- the average


def test_noise_left_after_r_revolutions_is_sigma_over_sqrt_r():
    # Sample-synchronous: the time samples are the exact crossing times of the steps
    # 2 pi i / M of the known angle law, so the crossing of each step is a sample time
    # (the Hermite interpolant passes its nodes) and the local cubic returns that sample
    # (to s ~ 1e-13 of an interval: 1e-12 of sigma).  Each step then averages R
    # independent N(0, sigma^2) values: N(0, sigma^2 / R), and the mean square over the
    # M steps is (sigma^2 / R) chi^2_M / M, whose RMS has relative standard deviation
    # 1/sqrt(2M) (= 0.044 for M = 256).  Four of those: a false failure ~6e-5.
    steps, revolutions, sigma = 256, 60, 0.25
    angle = np.arange(revolutions * steps) * (TWO_PI / steps)
    time = LAW.time_at(angle)
    noise = np.random.default_rng(20240611).normal(0.0, sigma, time.size)
    signal = periodic_part(angle) + noise
    result = weighted_angle_average(signal, time, LAW.theta(time), steps, speed=LAW.omega(time))
    assert result.revolutions == revolutions
    np.testing.assert_array_equal(result.weight_sum, revolutions)
    residual = result.average - periodic_part(np.arange(steps) * (TWO_PI / steps))
    rms = math.sqrt(float(np.mean(residual**2)))
    assert abs(rms / (sigma / math.sqrt(revolutions)) - 1.0) <= 4.0 / math.sqrt(2 * steps)
    # and the noise is independent of the step: its mean is 0 to sigma / sqrt(R M) (4x)
    assert abs(float(np.mean(residual))) <= 4.0 * sigma / math.sqrt(revolutions * steps)


@pytest.mark.parametrize("with_speed", [True, False], ids=["speed", "pchip_slopes"])
def test_smooth_periodic_part_to_the_interpolation_bound(with_speed):
    # Uniform time step H, nothing synchronous.  Three errors, each bounded:
    # - the channel's local cubic: <= max|x''''| H^4 / 24 (the Lagrange remainder with
    #   |prod (s - s_m)| <= 1 over the end stencils, 9/16 inside), x = P(theta(t)) and
    #   max|x''''| from Faa di Bruno with the bounds of P^(n) and theta^(n);
    # - the crossing angle, times max|P'|: with the true speed the cubic Hermite error
    #   H^4 max|omega'''| / 384; with PCHIP slopes, slope errors <= H^2 (max|omega''|/3 +
    #   max|omega'|^2 / (4 min omega)) (the one-sided end formula's h^2 f'''/3 covers the
    #   inner harmonic mean's h^2 (f'''/6 + f''^2/(4 f'))) entering as H |e| / 4, with a
    #   factor 1.5 for the terms of next order, smaller by H max|omega'|/min omega ~ 1e-3;
    # - Newton's stop at 1e-14 of the largest angle, times max|P'|.
    # Averaging R revolutions cannot exceed the largest of these errors.
    step_h, steps = 1.0 / 4096.0, 128
    time = np.arange(0.0, 6.0, step_h)
    theta = LAW.theta(time)
    signal = periodic_part(theta)
    result = weighted_angle_average(
        signal, time, theta, steps, speed=LAW.omega(time) if with_speed else None
    )
    channel_bound = fourth_derivative_bound(derivative_bound, LAW.bound) * step_h**4 / 24
    if with_speed:
        angle_bound = step_h**4 * LAW.bound(4) / 384
    else:
        min_speed = LAW.w0 * (1 - LAW.eps)
        slope_error = step_h**2 * (LAW.bound(3) / 3 + LAW.bound(2) ** 2 / (4 * min_speed))
        angle_bound = 1.5 * step_h * slope_error / 4
    newton = 1e-14 * float(theta[-1])
    bound = channel_bound + derivative_bound(1) * (angle_bound + newton)
    error = np.max(np.abs(result.average - periodic_part(np.arange(steps) * TWO_PI / steps)))
    assert bound < 1e-3  # the bound is tight enough to mean something
    assert error <= bound
    assert result.revolutions == math.floor(theta[-1] / TWO_PI)


def test_weights_enter_as_weighted_mean_at_the_crossing_times():
    # Sample-synchronous as above, with a slowly growing amplitude c(t) and weights
    # w(t): step j of revolution r is read at t_rj, so the average is
    # sum_r w(t_rj) c(t_rj) P(theta_j) / sum_r w(t_rj) exactly, and the weight sum is
    # sum_r w(t_rj).  Round-off: ~R eps of the sums, and the s ~ 1e-13 offset of the
    # crossing from the sample: 1e-10 relative allows both with margin.
    steps, revolutions = 64, 12
    angle = np.arange(revolutions * steps) * (TWO_PI / steps)
    time = LAW.time_at(angle)
    amplitude = 1.0 + time / time[-1]
    weights = 1.0 + 0.9 * np.sin(TWO_PI * time / (0.7 * time[-1]))
    signal = amplitude * periodic_part(angle)
    result = weighted_angle_average(signal, time, LAW.theta(time), steps, weights)
    table_w = weights.reshape(revolutions, steps)
    table_c = amplitude.reshape(revolutions, steps)
    expected_sum = table_w.sum(axis=0)
    expected = (table_w * table_c).sum(axis=0) / expected_sum * periodic_part(angle[:steps])
    np.testing.assert_allclose(result.weight_sum, expected_sum, rtol=1e-10)
    np.testing.assert_allclose(result.average, expected, rtol=1e-10, atol=1e-10)


def test_a_longer_period_averages_over_it():
    # angle_period 4 pi: the steps cover two revolutions, and a feature at 2 pi + 1 rad
    # of the cycle (a half-order, cos(theta / 2)) keeps its place.  Sample-synchronous:
    # exact to round-off (1e-12 of a unit amplitude).
    steps, cycles = 128, 5
    angle = np.arange(cycles * steps) * (2 * TWO_PI / steps)
    time = LAW.time_at(angle)
    result = weighted_angle_average(
        np.cos(0.5 * angle), time, LAW.theta(time), steps, angle_period=2 * TWO_PI
    )
    assert result.revolutions == cycles
    grid = np.arange(steps) * (2 * TWO_PI / steps)
    np.testing.assert_allclose(result.average, np.cos(0.5 * grid), atol=1e-12)


def test_the_steps_start_at_the_angle_origin():
    # A record starting at 1.3 rad: step j is still the angle 2 pi j / M, so the
    # average of P(theta) is P at the steps, not P shifted by the start.  The samples
    # after the first are the steps themselves: exact to round-off.
    steps, revolutions = 64, 4
    first = math.ceil(1.3 / (TWO_PI / steps))  # the first step after the start
    angle = np.concatenate(
        ([1.3], np.arange(first, first + revolutions * steps) * (TWO_PI / steps))
    )
    time = LAW.time_at(angle)
    result = weighted_angle_average(
        periodic_part(angle), time, LAW.theta(time), steps, speed=LAW.omega(time)
    )
    grid = np.arange(steps) * (TWO_PI / steps)
    np.testing.assert_allclose(result.average, periodic_part(grid), atol=1e-10)


def test_too_short_a_record_or_an_empty_step_is_refused():
    time = np.linspace(0.0, 0.15, 200)  # 0.15 s at 5 rev/s +-30 %: under one revolution
    with pytest.raises(SignalError, match=r"^angle: spans .* less than one angle period"):
        weighted_angle_average(np.ones(200), time, LAW.theta(time), 64)
    time = np.linspace(0.0, 0.25, 2000)  # about one revolution and a quarter
    weights = (time > 0.15).astype(float)  # nothing for the first 0.15 s
    with pytest.raises(SignalError, match=r"^weights: the weight sum is zero in \d+ of 64"):
        weighted_angle_average(np.ones(2000), time, LAW.theta(time), 64, weights)


# --------------------------------------------------------------------------- tachometer


def test_pulses_are_the_exact_crossing_times():
    # With the true speed, the crossing of the Hermite interpolant is off by at most
    # H^4 max|omega'''| / 384 of angle, i.e. that over min omega of time, plus Newton's
    # 1e-14 of the largest angle (also over min omega).
    time = np.arange(0.0, 3.0, 1e-3)
    pulses = synthetic_tachometer(time, LAW.theta(time), 6, speed=LAW.omega(time))
    expected = LAW.time_at(np.arange(pulses.size) * (TWO_PI / 6))
    min_speed = LAW.w0 * (1 - LAW.eps)
    bound = (1e-12 * LAW.bound(4) / 384 + 1e-14 * LAW.theta(3.0)) / min_speed
    assert pulses.size == math.floor(LAW.theta(time[-1]) / (TWO_PI / 6)) + 1
    assert np.max(np.abs(pulses - expected)) <= bound


def test_angle_from_pulses_converges_at_third_order():
    # PCHIP slopes from the pulse counts carry errors <= h^2 (max|omega''|/3 +
    # max|omega'|^2 / (4 min omega)) for a pulse spacing h (in time; the ends' one-sided
    # formula dominates the inner harmonic mean), and a Hermite cubic turns slope errors e
    # into an angle error <= h max|e| / 4; its own error with exact slopes,
    # h^4 max|omega'''| / 384, is of higher order.  So the error falls by 2^3 = 8 when
    # the pulses double; >= 6 allows the next order (h omega'/omega ~ 0.05 at 32 pulses).
    time = np.arange(0.0, 4.0, 2e-5)
    theta, omega = LAW.theta(time), LAW.omega(time)
    errors = []
    for pulses_per_rev in (32, 64):
        pulses = synthetic_tachometer(time, theta, pulses_per_rev, speed=omega)
        inside = (time >= pulses[0]) & (time <= pulses[-1])
        rebuilt = angle_from_tachometer(pulses, pulses_per_rev, time[inside])
        errors.append(np.max(np.abs(rebuilt - (theta[inside] - LAW.theta(pulses[0])))))
        spacing = (TWO_PI / pulses_per_rev) / (LAW.w0 * (1 - LAW.eps))
        slope_error = spacing**2 * (
            LAW.bound(3) / 3 + LAW.bound(2) ** 2 / (4 * LAW.w0 * (1 - LAW.eps))
        )
        assert errors[-1] <= spacing * slope_error / 4 + spacing**4 * LAW.bound(4) / 384
    assert errors[0] / errors[1] >= 6.0


def test_jitter_attenuates_orders_as_the_gaussian_rule():
    # Constant speed Omega and one pulse per angle step (N = M = 64): each step of the
    # average is the crossing of a pulse, i.e. the jittered pulse time, where the
    # channel reads P(theta_j + Omega e), e ~ N(0, sigma_t^2).  The mean over e of
    # cos(k (theta + Omega e)) is exp(-k^2 sigma_theta^2 / 2) cos(k theta), sigma_theta =
    # Omega sigma_t (Souders, Flach, Hagwood & Yang 1990).  Tolerance on the ratio of the
    # measured order amplitude (DFT of the average) to a_k exp(...):
    # - sampling: the DFT coefficient averages R M independent terms; its deviation has
    #   standard deviation <= sigma_theta sqrt(2 sum a_m^2 m^2) / sqrt(R M) (x' e to
    #   first order, var(x'(theta)) averaged over theta = sum a_m^2 m^2 / 2): 1.5e-3 at
    #   the larger jitter; four of those;
    # - the local cubic at off-sample crossings: a cosine of order 28 sampled 1024 times
    #   a revolution loses at most (9/16)(2 pi 28 / 1024)^4 / 24 = 2e-5;
    # - re-reading the rebuilt angle on the time grid: its kinks at the pulses move a
    #   crossing by ~h^2 |jump of theta''| / 8 ~ 1e-5 rad, a second-order amplitude error.
    # Zero jitter is exact here (the steps fall on samples).  The attenuation of order
    # 28 (1.5 % and 5.7 %) is many tolerances, so it is also seen to grow with jitter.
    pulses_per_rev, samples_per_pulse, revolutions = 64, 16, 1600
    speed = TWO_PI * 10.0
    sample_rate = speed / TWO_PI * pulses_per_rev * samples_per_pulse
    time = np.arange(int((revolutions + 2) / 10.0 * sample_rate)) / sample_rate
    theta = speed * time
    orders = {3: 1.0, 28: 1.0}
    signal = sum(a * np.cos(k * theta) for k, a in orders.items())
    spacing = TWO_PI / pulses_per_rev
    amplitude = {}
    for fraction in (0.0, 1.0 / 16.0, 1.0 / 8.0):
        sigma_theta = fraction * spacing
        pulses = synthetic_tachometer(
            time,
            theta,
            pulses_per_rev,
            jitter=sigma_theta / speed,
            seed=11,
            speed=np.full(time.size, speed),
        )
        inside = (time >= pulses[0]) & (time <= pulses[-1])
        rebuilt = angle_from_tachometer(pulses, pulses_per_rev, time[inside])
        result = weighted_angle_average(signal[inside], time[inside], rebuilt, pulses_per_rev)
        spectrum = np.abs(np.fft.rfft(result.average)) * 2.0 / pulses_per_rev
        sampling = sigma_theta * math.sqrt(2 * sum(a**2 * m**2 for m, a in orders.items()))
        tolerance = 4 * sampling / math.sqrt(result.revolutions * pulses_per_rev) + 1e-4
        for order, a in orders.items():
            predicted = a * math.exp(-0.5 * (order * sigma_theta) ** 2)
            assert abs(spectrum[order] / predicted - 1.0) <= tolerance, (fraction, order)
        amplitude[fraction] = spectrum[28]
    assert amplitude[0.0] > amplitude[1 / 16] > amplitude[1 / 8]


def test_jitter_that_reorders_pulses_is_refused():
    time = np.linspace(0.0, 2.0, 4000)
    spacing = (TWO_PI / 32) / (LAW.w0 * (1 + LAW.eps))  # the shortest pulse spacing [s]
    with pytest.raises(SignalError, match=r"^jitter: .* out of order"):
        synthetic_tachometer(time, LAW.theta(time), 32, jitter=spacing, seed=1)
    pulses = synthetic_tachometer(time, LAW.theta(time), 32)
    with pytest.raises(SignalError, match=r"^time: 1 times lie outside the pulses' span"):
        angle_from_tachometer(pulses, 32, [pulses[0] - 1e-3, pulses[1]])


# --------------------------------------------------------------------------- planet windows


@pytest.mark.parametrize("planets", [2, 3, 4, 5])
def test_hann_windows_of_equally_spaced_planets_sum_to_a_constant(planets):
    # Hann windows L = 2 pi k / N wide, spaced 2 pi / N: raised cosines overlapping by
    # (k - 1)/k sum to k / 2 (for k = 2: cos^2 u + cos^2(u - pi/2) = 1).  Round-off: N
    # cosines of O(1): 1e-14.  At k = 1 they do not: the sum is cos^2(pi N delta / 2 pi)
    # on each planet's span, 1 at a planet and 0 midway between two.
    carrier = np.linspace(-3 * math.pi, 3 * math.pi, 20001)
    positions = [TWO_PI * p / planets for p in range(planets)]
    for k in range(2, planets + 1):
        width = TWO_PI * k / planets
        total = sum(planet_window(carrier, phi, 0.4, width) for phi in positions)
        np.testing.assert_allclose(total, k / 2, atol=1e-14)
    total = sum(planet_window(carrier, phi, 0.4, TWO_PI / planets) for phi in positions)
    assert total.max() == pytest.approx(1.0, abs=1e-6) and total.min() < 1e-6
    # rectangular windows 2 pi / N wide tile the circle: exactly one planet at a time
    # (at random carrier angles: a boundary hit within round-off has probability ~1e-15)
    carrier = np.random.default_rng(3).uniform(-10.0, 10.0, 5000)
    total = sum(
        planet_window(carrier, phi, 0.4, TWO_PI / planets, "rectangular") for phi in positions
    )
    np.testing.assert_array_equal(total, 1.0)


def test_a_planet_window_is_centred_on_the_sensor():
    # the planet at phi on the carrier is at theta_c + phi: over the sensor when
    # theta_c = sensor - phi, so the weight is 1 there, cos^2(pi/4) = 1/2 a quarter
    # width on either side, and 0 from half a width on (also a revolution later).
    phi, sensor, width = 2.0, 0.5, 1.2
    at_sensor = sensor - phi
    weights = planet_window(
        np.array([at_sensor, at_sensor + width / 4, at_sensor - width / 4, at_sensor + 0.61])
        + np.array([0.0, 0.0, TWO_PI, -TWO_PI]),
        phi,
        sensor,
        width,
    )
    np.testing.assert_allclose(weights, [1.0, 0.5, 0.5, 0.0], atol=1e-15)


# --------------------------------------------------------------------------- planets and sun


class Stage:
    """A planetary stage with a held ring: Z_s + 2 Z_p = Z_r, N planets equally spaced
    ((Z_s + Z_r) / N whole).  With the carrier at theta_c, planet q (at phi_q) turns
    relative to the carrier by beta_q = (Z_r / Z_p)(theta_c + phi_q) + b_q (rolling on
    the ring, against the carrier, counted in its running direction) and the sun by
    theta_s - theta_c = (Z_r / Z_s) theta_c.  The transducer at ``SENSOR`` hears only
    the planet nearest to it (|wrap(theta_c + phi_q - sensor)| < pi / N)."""

    ring, planet, sun, planets = 99, 36, 27, 3
    sensor = 0.7
    spin_offsets = (0.3, 1.1, 2.5)
    mesh_phases = (0.0, 1.0, 2.0)
    marked_planet, marked_planet_tooth, marked_sun_tooth = 1, 11, 5
    bump_height = 2.0

    def __init__(self):
        self.law = SpeedLaw(mean_speed=TWO_PI * 2.0, depth=0.2, frequency=0.37)
        self.step = 1.0 / 20000.0
        self.time = np.arange(0.0, 5.0, self.step)  # 8 carrier revolutions and more
        self.carrier = self.law.theta(self.time)
        # the carrier's angle origin 0.4 rad behind planet 0: the positions are not
        # symmetric about it, so a sign error in them moves every planet
        self.positions = [0.4 + TWO_PI * q / self.planets for q in range(self.planets)]
        self.spin = [
            self.ring / self.planet * (self.carrier + phi) + b
            for phi, b in zip(self.positions, self.spin_offsets)
        ]
        self.sun_angle = self.carrier * (1.0 + self.ring / self.sun)
        offsets = [
            np.abs(np.mod(self.carrier + phi - self.sensor + math.pi, TWO_PI) - math.pi)
            for phi in self.positions
        ]
        self.heard = np.argmin(np.array(offsets), axis=0)
        # the planet windows stop 3 samples of carrier travel short of the hearing
        # boundaries, so that no crossing whose four-sample cubic reaches across a
        # switch between planets carries weight (see the tests' tolerance)
        margin = 3 * self.step * self.law.bound(1)
        self.width = TWO_PI / self.planets - 2 * margin

    def bump_width(self, teeth: int) -> float:
        return TWO_PI / teeth / 6  # a sixth of a tooth pitch

    def bump(self, angle, centre, width):
        offset = np.mod(angle - centre + math.pi, TWO_PI) - math.pi
        return self.bump_height * np.exp(-0.5 * (offset / width) ** 2)

    def planet_pattern(self, q: int, beta):
        """Planet q's signal at its angle beta: tooth meshing, plus the marked tooth."""
        value = np.cos(self.planet * beta + self.mesh_phases[q])
        if q == self.marked_planet:
            centre = TWO_PI * self.marked_planet_tooth / self.planet
            value = value + self.bump(beta, centre, self.bump_width(self.planet))
        return value

    def sun_pattern(self, alpha):
        """The sun's signal at its angle alpha relative to the meshing planet."""
        centre = TWO_PI * self.marked_sun_tooth / self.sun
        return np.cos(self.sun * alpha) + self.bump(alpha, centre, self.bump_width(self.sun))

    def heard_signal(self, pattern_of_planet):
        return np.choose(self.heard, [pattern_of_planet(q) for q in range(self.planets)])

    def channel_bound(self, teeth: int, ratio: float) -> float:
        """max|x''''| H^4 / 24 for x = cos(Z a) + bump(a), a = ratio theta_c + const."""
        width = self.bump_width(teeth)

        def outer(n):
            return teeth**n + self.bump_height * GAUSSIAN_DERIVATIVE[n] / width**n

        def inner(n):
            return ratio * self.law.bound(n)

        return fourth_derivative_bound(outer, inner) * self.step**4 / 24


@pytest.fixture(scope="module")
def stage():
    return Stage()


def _pchip_angle_bound(stage: Stage, ratio: float, teeth: int) -> float:
    """The crossing angle's error with PCHIP slopes (see the smooth-part test), times
    max|pattern'| = Z + bump_height / width."""
    h, law = stage.step, stage.law
    min_speed = ratio * law.w0 * (1 - law.eps)
    slope_error = h**2 * ratio * (law.bound(3) / 3 + ratio * law.bound(2) ** 2 / (4 * min_speed))
    slope_bound = teeth + stage.bump_height / stage.bump_width(teeth)
    return slope_bound * (1.5 * h * slope_error / 4 + 1e-14 * ratio * stage.carrier[-1])


def test_each_planet_average_is_that_planets_own_pattern(stage):
    # While planet q's window is open the transducer hears planet q alone, so every
    # sample averaged in step j of planet q is planet q's pattern at beta_j: the average
    # is that pattern, whatever the weights, to the interpolation errors (the local
    # cubic's bound, and the crossing angle's with PCHIP slopes, as in the smooth-part
    # test).  A wrong window (sign of the position or of the sensor) mixes another
    # planet's pattern in, at O(1).
    signal = stage.heard_signal(lambda q: stage.planet_pattern(q, stage.spin[q]))
    steps = stage.planet * 16
    grid = np.arange(steps) * (TWO_PI / steps)
    ratio = stage.ring / stage.planet
    tolerance = stage.channel_bound(stage.planet, ratio) + _pchip_angle_bound(
        stage, ratio, stage.planet
    )
    assert tolerance < 1e-3
    marked_step = stage.marked_planet_tooth * 16
    for q, phi in enumerate(stage.positions):
        result = planet_average(
            signal, stage.time, stage.carrier, stage.spin[q], phi, stage.sensor, stage.width, steps
        )
        assert np.max(np.abs(result.average - stage.planet_pattern(q, grid))) <= tolerance
        tooth_part = result.average - np.cos(stage.planet * grid + stage.mesh_phases[q])
        if q == stage.marked_planet:  # the marked tooth, at 2 pi k / Z_p
            assert int(np.argmax(tooth_part)) == marked_step
            assert tooth_part[marked_step] == pytest.approx(stage.bump_height, abs=tolerance)
        else:  # and nothing of it on the other planets
            assert np.max(np.abs(tooth_part)) <= tolerance


def test_the_sun_average_finds_a_marked_sun_tooth(stage):
    # The sun tooth meshing with planet q is at alpha_q = theta_s - theta_c - phi_q =
    # 2 pi k / Z_s, and the transducer hears it through planet q while q's window is
    # open: every planet contributes the sun's pattern at the same alpha, so the
    # average is that pattern to the interpolation errors (as for the planets).  Reading
    # a planet's contribution at an angle other than alpha_q (a sign error in phi_q or
    # in theta_c) would put the planets' copies of the marked tooth apart, each at a
    # fraction of its height.
    signal = stage.heard_signal(
        lambda q: stage.sun_pattern(stage.sun_angle - stage.carrier - stage.positions[q])
    )
    steps = stage.sun * 16
    grid = np.arange(steps) * (TWO_PI / steps)
    ratio = stage.ring / stage.sun
    tolerance = stage.channel_bound(stage.sun, ratio) + _pchip_angle_bound(stage, ratio, stage.sun)
    assert tolerance < 1e-3
    result = sun_average(
        signal,
        stage.time,
        stage.sun_angle,
        stage.carrier,
        stage.positions,
        stage.sensor,
        stage.width,
        steps,
    )
    assert np.max(np.abs(result.average - stage.sun_pattern(grid))) <= tolerance
    tooth_part = result.average - np.cos(stage.sun * grid)
    assert int(np.argmax(tooth_part)) == stage.marked_sun_tooth * 16
    # every planet adds the whole revolutions of the sun relative to it
    relative_turns = (stage.sun_angle[-1] - stage.carrier[-1]) / TWO_PI
    assert stage.planets * (math.floor(relative_turns) - 1) <= result.revolutions
    assert result.revolutions <= stage.planets * math.floor(relative_turns)


# --------------------------------------------------------------------------- xarray


def _on_time(values, time, **attrs):
    return xr.DataArray(values, dims="time", coords={"time": time}, attrs=attrs)


def test_the_tsa_as_a_data_array():
    # A pygear run's channels: the carrier's angle as its probe writes it (target
    # ``planetary.carrier.theta_z``) and its speed in rpm.  Sample-synchronous, so the
    # average is P at the steps to round-off; the speed in rpm is converted (a wrong
    # factor would fail the Hermite crossings' monotonicity or move them off the
    # samples by far more than 1e-10).
    steps, revolutions = 64, 5
    angle = np.arange(revolutions * steps) * (TWO_PI / steps)
    time = LAW.time_at(angle)
    channel = _on_time(
        periodic_part(angle), time, units="m/s^2", long_name="ring acceleration"
    ).rename("ring_acceleration")
    reference = _on_time(
        LAW.theta(time),
        time,
        units="rad",
        quantity="displacement",
        target="planetary.carrier.theta_z",
    )
    speed = _on_time(LAW.omega(time) * 30.0 / math.pi, time, units="rpm")
    tsa = time_synchronous_average(channel, reference, steps, speed=speed)
    assert tsa.dims == ("angle",) and tsa.name == "ring_acceleration"
    np.testing.assert_allclose(tsa["angle"].values, np.arange(steps) * TWO_PI / steps)
    assert tsa["angle"].attrs["units"] == "rad" and tsa["angle"].attrs["long_name"]
    assert tsa.attrs["units"] == "m/s^2" and "ring acceleration" in tsa.attrs["long_name"]
    assert tsa.attrs["revolutions"] == revolutions
    assert tsa.attrs["member"] == "planetary.carrier"
    np.testing.assert_array_equal(tsa["weight_sum"].values, revolutions)
    np.testing.assert_allclose(tsa.values, periodic_part(tsa["angle"].values), atol=1e-10)


def test_the_planet_and_sun_averages_as_data_arrays(stage):
    # as the array tests, on xarray channels: the same tolerance
    ratio = stage.ring / stage.planet
    tolerance = stage.channel_bound(stage.planet, ratio) + _pchip_angle_bound(
        stage, ratio, stage.planet
    )
    q = stage.marked_planet
    signal = stage.heard_signal(lambda p: stage.planet_pattern(p, stage.spin[p]))
    channel = _on_time(signal, stage.time, units="m/s^2").rename("ring_acceleration")
    carrier = _on_time(stage.carrier, stage.time, units="rad")
    spin = _on_time(stage.spin[q], stage.time, units="rad", member="planetary.planet_1")
    tsa = planet_synchronous_average(
        channel, carrier, spin, stage.positions[q], stage.sensor, stage.width, 576
    )
    assert tsa.dims == ("angle",) and tsa.attrs["member"] == "planetary.planet_1"
    assert tsa.attrs["window"] == "hann" and tsa.attrs["width_rad"] == stage.width
    assert tsa.attrs["revolutions"] >= 1 and np.all(tsa["weight_sum"].values > 0)
    pattern = stage.planet_pattern(q, tsa["angle"].values)
    assert np.max(np.abs(tsa.values - pattern)) <= tolerance

    ratio = stage.ring / stage.sun
    tolerance = stage.channel_bound(stage.sun, ratio) + _pchip_angle_bound(stage, ratio, stage.sun)
    signal = stage.heard_signal(
        lambda p: stage.sun_pattern(stage.sun_angle - stage.carrier - stage.positions[p])
    )
    sun = _on_time(stage.sun_angle, stage.time, units="rad")
    tsa = sun_synchronous_average(
        channel.copy(data=signal), sun, carrier, stage.positions, stage.sensor, stage.width, 432
    )
    assert tsa.attrs["planet_positions_rad"] == stage.positions
    assert np.max(np.abs(tsa.values - stage.sun_pattern(tsa["angle"].values))) <= tolerance


# --------------------------------------------------------------------------- bad input

TIME = np.linspace(0.0, 2.0, 4001)
THETA = LAW.theta(TIME)
ONES = np.ones(TIME.size)


def _tsa(**change):
    arguments = dict(signal=ONES, time=TIME, angle=THETA, samples_per_revolution=64)
    arguments.update(change)
    return weighted_angle_average(**arguments)


def _planet(**change):
    arguments = dict(
        signal=ONES,
        time=TIME,
        carrier_angle=THETA,
        planet_spin_angle=3 * THETA,
        planet_position_rad=0.0,
        sensor_angle_rad=0.0,
        width_rad=2.0,
        samples_per_revolution=64,
    )
    arguments.update(change)
    return planet_average(**arguments)


def _sun(**change):
    arguments = dict(
        signal=ONES,
        time=TIME,
        sun_angle=4 * THETA,
        carrier_angle=THETA,
        planet_positions_rad=[0.0, 2.0, 4.0],
        sensor_angle_rad=0.0,
        width_rad=2.0,
        samples_per_revolution=64,
    )
    arguments.update(change)
    return sun_average(**arguments)


BAD_INPUTS = [
    ("time", lambda: _tsa(time=TIME[::-1])),
    ("time", lambda: _tsa(time=TIME[:3], angle=THETA[:3], signal=ONES[:3])),
    ("angle", lambda: _tsa(angle=-THETA)),
    ("angle", lambda: _tsa(angle=THETA[:-1])),
    ("signal", lambda: _tsa(signal=np.where(TIME > 1, np.nan, 1.0))),
    ("signal", lambda: _tsa(signal=np.ones((2, TIME.size)))),
    ("samples_per_revolution", lambda: _tsa(samples_per_revolution=1)),
    ("samples_per_revolution", lambda: _tsa(samples_per_revolution=64.0)),
    ("weights", lambda: _tsa(weights=-ONES)),
    ("angle_period", lambda: _tsa(angle_period=0.0)),
    ("speed", lambda: _tsa(speed=-ONES)),
    ("pulses_per_revolution", lambda: synthetic_tachometer(TIME, THETA, 0)),
    ("jitter", lambda: synthetic_tachometer(TIME, THETA, 8, jitter=-1e-3)),
    ("pulse_times", lambda: angle_from_tachometer([0.2, 0.1, 0.3], 8, [0.25])),
    ("width_rad", lambda: _planet(width_rad=7.0)),
    ("shape", lambda: _planet(shape="triangle")),
    ("planet_position_rad", lambda: _planet(planet_position_rad=float("inf"))),
    ("sensor_angle_rad", lambda: _planet(sensor_angle_rad="north")),
    ("planet_spin_angle", lambda: _planet(planet_spin_angle=-THETA)),
    ("carrier_angle", lambda: planet_window([0.0, np.nan], 0.0, 0.0, 1.0)),
    ("sun_angle", lambda: _sun(sun_angle=0.5 * THETA)),
    ("planet_positions_rad", lambda: _sun(planet_positions_rad=[])),
    ("channel", lambda: time_synchronous_average(ONES, _on_time(THETA, TIME), 64)),
    (
        "angle",
        lambda: time_synchronous_average(_on_time(ONES, TIME), _on_time(THETA, TIME + 1), 64),
    ),
    (
        "angle",
        lambda: time_synchronous_average(
            _on_time(ONES, TIME), _on_time(THETA, TIME, units="deg"), 64
        ),
    ),
]


@pytest.mark.parametrize(("parameter", "call"), BAD_INPUTS)
def test_bad_input_gets_a_one_line_error_naming_the_parameter(parameter, call):
    with pytest.raises(SignalError) as raised:
        call()
    message = str(raised.value)
    assert message.startswith(f"{parameter}: ") and "\n" not in message
    assert isinstance(raised.value, ValueError)
