"""Synthetic turbulent wind (Kaimal, IEC 61400-1 ed.3) and the rotor torque it drives.

References: the Kaimal spectrum and the normal turbulence model written out here from
IEC 61400-1 ed.3 (eq. 11 and B.14), not taken from the module; the rotor's rated point
from NREL/TP-500-38060 (5.296610 MW mechanical at 12.1 rpm).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pygear.analysis.time.wind import NREL5MW_ROTOR, kaimal_wind, rotor_torque_series
from pygear.errors import CaseError


def _iec_kaimal(f, v_hub, i_ref, z_hub=90.0):
    sigma = i_ref * (0.75 * v_hub + 5.6)
    length = 8.1 * (42.0 if z_hub > 60.0 else 0.7 * z_hub)
    return 4.0 * sigma**2 * length / v_hub / (1.0 + 6.0 * f * length / v_hub) ** (5.0 / 3.0)


def test_periodogram_matches_the_kaimal_formula():
    # 40 seeds of 600 s at 4 Hz, class B at 12 m/s.  Each periodogram ordinate of a
    # Gaussian process is S(f) times a chi-square(2)/2 variable (std = mean), so a band
    # of >= 25 bins averaged over 40 seeds (>= 1000 ordinates) has a relative standard
    # error <= 1/sqrt(1000) = 3.2 %: the 16 % tolerance is 5 standard errors.
    rate, duration, v_hub, seeds = 4.0, 600.0, 12.0, 40
    n = int(rate * duration)
    df = rate / n
    f = np.fft.rfftfreq(n, 1.0 / rate)
    power = np.zeros(f.size)
    variance = []
    for seed in range(seeds):
        u = kaimal_wind(v_hub, duration, rate, seed, turbulence_class="B")
        assert u.shape == (n,)
        fluctuation = u - v_hub
        power += 2.0 * np.abs(np.fft.rfft(fluctuation)) ** 2 / (n**2 * df) / seeds
        variance.append(np.mean(fluctuation**2))
    target = _iec_kaimal(f[1:-1], v_hub, 0.14)
    measured = power[1:-1]
    edges = np.unique(np.r_[0, np.geomspace(25, measured.size, 12).astype(int)])
    for lo, hi in zip(edges[:-1], edges[1:]):
        ratio = measured[lo:hi].mean() / target[lo:hi].mean()
        assert abs(ratio - 1.0) < 0.16, (f[1 + lo], ratio)
    # the variance: sum of S df over the drawn bins (the Kaimal integral between the
    # first and the last bin); 40 seeds of a 600 s record whose integral scale is
    # L/V = 28 s: about 40 x 11 independent stretches, a few % scatter; 10 % tolerance
    assert np.mean(variance) == pytest.approx(np.sum(target) * df, rel=0.10)
    sigma_1 = 0.14 * (0.75 * v_hub + 5.6)
    assert np.sum(target) * df < sigma_1**2  # the record is too short for the lowest band


def test_seed_draws_the_same_series_and_another_seed_another():
    a = kaimal_wind(10.0, 60.0, 2.0, 7)
    np.testing.assert_array_equal(a, kaimal_wind(10.0, 60.0, 2.0, 7))
    assert not np.allclose(a, kaimal_wind(10.0, 60.0, 2.0, 8))


def test_steady_wind_below_rated_gives_the_optimal_point_torque():
    # constant 8 m/s: lambda_opt = 7.5 (the table's peak, Cp = 0.482), Omega =
    # lambda U / R, T = rho A Cp U^3 / (2 Omega); only round-off differs
    u, rho, radius = 8.0, 1.225, 63.0
    series = rotor_torque_series(np.full(400, u), sample_rate=20.0)
    omega = 7.5 * u / radius
    expected = 0.5 * rho * math.pi * radius**2 * 0.482 * u**3 / omega
    np.testing.assert_allclose(series.rotor_torque.values, expected, rtol=1e-12)
    np.testing.assert_allclose(series.rotor_speed.values, omega * 30 / math.pi, rtol=1e-12)


def test_mean_torque_above_rated_is_rated_power_over_rated_speed():
    # class B at 18 m/s, 4 seeds of 1 h at 4 Hz.  The slow wind (tau = 5 s) stays above
    # rated (11.4 m/s) but for rare dips, so the quasi-steady torque is P/Omega; the fast
    # part g (U - U_f)/U_f has zero mean, and its sample mean over 4 h (g ~ 0.1-1,
    # sigma_fast/U ~ 0.09, some 500 independent stretches of 28 s) scatters by < 0.5 %:
    # a 2 % tolerance
    rated = 5.296610e6 / (12.1 * math.pi / 30.0)
    means = []
    for seed in range(4):
        wind = kaimal_wind(18.0, 3600.0, 4.0, seed, turbulence_class="B")
        series = rotor_torque_series(wind, 4.0, NREL5MW_ROTOR)
        means.append(float(series.rotor_torque.mean()))
        assert series.rotor_torque.std() > 0.01 * rated  # the turbulence is there
    assert np.mean(means) == pytest.approx(rated, rel=0.02)


def test_bad_turbulence_class_is_refused():
    with pytest.raises(CaseError, match="turbulence_class must be one of A, B, C"):
        kaimal_wind(10.0, 60.0, 2.0, 1, turbulence_class="D")
