"""Loads inside a rolling bearing against Harris & Kotzalas (2007), Stribeck, Hertz's
closed forms and Palmgren's line-contact formula."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pygear.analysis.condition.bearing_kinematics import bearing_frequencies
from pygear.analysis.condition.bearing_load import (
    contact_constant,
    defect_excitation,
    element_loads,
    hertz_point_compliance,
    load_distribution,
    radial_integral,
    varying_compliance,
)
from pygear.errors import CaseError
from pygear.model.rolling_bearing import BearingDefect, RollingBearing

# Harris & Kotzalas (2007), Table 7.1: the radial integral J_r(epsilon) of point contact
HARRIS_JR = {0.1: 0.1156, 0.2: 0.1590, 0.3: 0.1892, 0.4: 0.2117, 0.5: 0.2288, 0.6: 0.2416,
             0.7: 0.2505, 0.8: 0.2559, 0.9: 0.2576, 1.0: 0.2546, 1.25: 0.2289, 2.5: 0.1339,
             5.0: 0.0711}  # fmt: skip


def ball(**changes) -> RollingBearing:
    values = dict(name="B", type="ball", elements=60, pitch_diameter=0.2, element_diameter=0.012)
    return RollingBearing(**{**values, **changes})


def roller(**changes) -> RollingBearing:
    values = dict(name="R", type="roller", elements=20, pitch_diameter=0.2,
                  element_diameter=0.02, roller_length=0.02)  # fmt: skip
    return RollingBearing(**{**values, **changes})


@pytest.mark.parametrize("epsilon", sorted(HARRIS_JR))
def test_radial_integral_matches_harris_table(epsilon):
    # the table prints 4 decimals: half a unit of the last
    assert radial_integral(epsilon) == pytest.approx(HARRIS_JR[epsilon], abs=5.1e-5)


def test_stribeck_max_element_load_at_zero_clearance():
    load = 2.0e4
    found = load_distribution(ball(), load)
    z = 60
    # Harris: Q_max = F_r / (Z J_r(0.5)), J_r = 0.2288, Stribeck's 4.37 F_r / Z.  60
    # discrete elements approximate the integral to ~1e-5 (the integrand is smooth but
    # for its C2 kink at +-90 deg); the table's 4 digits allow 2.2e-4
    assert found.attrs["max_element_load"] == pytest.approx(load / (z * 0.2288), rel=3e-4)
    assert found.attrs["max_element_load"] * z / load == pytest.approx(4.37, rel=1e-3)
    assert found.attrs["epsilon"] == pytest.approx(0.5, abs=1e-12)
    assert found.attrs["load_zone_deg"] == pytest.approx(180.0)
    # equilibrium: the element loads add up to the load, nothing across it
    angles = np.radians(found.element_angle.values)
    assert np.sum(found.element_load.values * np.cos(angles)) == pytest.approx(load, rel=1e-9)
    assert abs(np.sum(found.element_load.values * np.sin(angles))) < 1e-8 * load


@pytest.mark.parametrize("clearance", [10e-6, 30e-6, -10e-6])
def test_load_zone_follows_harris_epsilon_method(clearance):
    bearing = ball(diametral_clearance=clearance)
    load = 2.0e4
    found = load_distribution(bearing, load)
    delta_r = found.attrs["radial_deflection"]
    epsilon = 0.5 * (1 - clearance / (2 * delta_r))
    assert found.attrs["epsilon"] == pytest.approx(epsilon, rel=1e-12)
    # Harris eq. 7.x: F_r = Z Q_max J_r(epsilon); Q_max = K (delta_r - P_d / 2)^1.5
    k = contact_constant(bearing)
    q_max = k * (delta_r - clearance / 2) ** 1.5
    assert found.attrs["max_element_load"] == pytest.approx(q_max, rel=1e-6)
    assert load == pytest.approx(60 * q_max * radial_integral(epsilon), rel=1e-3)
    # the loaded elements lie within the load zone +-psi_l, cos psi_l = P_d / (2 delta_r)
    psi_l = math.degrees(math.acos(max(-1.0, clearance / (2 * delta_r))))
    angles = (found.element_angle.values + 180.0) % 360.0 - 180.0
    loaded = np.abs(angles[found.element_load.values > 0])
    assert np.all(loaded < psi_l + 1e-9)
    assert found.attrs["loaded_elements"] == pytest.approx(60 * psi_l / 180.0, abs=1.01)
    assert (clearance > 0) == (found.attrs["load_zone_deg"] < 180.0)


def test_hertz_ellipse_joins_the_circle_and_agrees_with_hamrock_brewe():
    e_star = 2.075e11 / (2 * (1 - 0.09))
    radius = 6e-3
    # a sphere of radius R on a flat: delta = (9 Q^2 / (16 E*^2 R))^(1/3) (Hertz)
    circle = (9 / (16 * e_star**2 * radius)) ** (1 / 3)
    a = 1 / (2 * radius)
    assert hertz_point_compliance(a, a * (1 + 1e-6), e_star) == pytest.approx(circle, rel=1e-5)
    # Hamrock & Brewe (1983) curve fits, within ~2 % of the exact ellipse for 1 < B/A < 100
    for ratio in (3.0, 10.0, 30.0):
        r = 1 / (2 * a * (1 + ratio))
        k = 1.0339 * ratio**0.6360
        ell = 1.0003 + 0.5968 / ratio
        f = 1.5277 + 0.6023 * math.log(ratio)
        fit = f * (9 / (2 * ell * r) / (math.pi * k * 2 * e_star) ** 2) ** (1 / 3)
        assert hertz_point_compliance(a, a * ratio, e_star) == pytest.approx(fit, rel=0.02)


def test_roller_law_is_palmgrens_in_its_units():
    bearing = roller()
    load = 1.0e4  # N on one roller of 20 mm
    # Palmgren: delta = 3.84e-5 Q^0.9 / l^0.8 mm per contact, two contacts in series
    delta_mm = 2 * 3.84e-5 * load**0.9 / 20.0**0.8
    delta = (load / contact_constant(bearing)) ** 0.9
    assert delta * 1e3 == pytest.approx(delta_mm, rel=1e-12)


@pytest.mark.parametrize("bearing", [ball(), roller()], ids=["ball", "roller"])
def test_stiffness_is_n_f_over_delta_at_zero_clearance(bearing):
    # zero clearance: the loaded set is fixed, F = K delta^n S with S independent of
    # delta, so dF/d delta = n F / delta exactly
    load = 3.0e4
    found = load_distribution(bearing, load)
    n = bearing.load_exponent
    kxx = float(found.stiffness.sel(direction="x", direction_to="x"))
    assert kxx == pytest.approx(n * load / found.attrs["radial_deflection"], rel=1e-8)


def test_stiffness_with_clearance_is_the_slope_of_load_over_deflection():
    bearing = roller(diametral_clearance=40e-6)
    step = 1e-4
    low, high = (load_distribution(bearing, 5e4 * (1 + s)) for s in (-step, step))
    slope = 2 * step * 5e4 / (high.attrs["radial_deflection"] - low.attrs["radial_deflection"])
    found = load_distribution(bearing, 5e4)
    # central difference: error O(step^2) relative, far below 1e-5
    assert float(found.stiffness[0, 0]) == pytest.approx(slope, rel=1e-5)


def test_varying_compliance_line_is_cage_rate_times_z():
    bearing = roller(elements=13, diametral_clearance=20e-6)
    inner = 25.0
    bpfo = bearing_frequencies(bearing, inner).lines["BPFO"]
    rate, duration = 4000.0, 4.0
    history = defect_excitation(bearing, 3e4, inner_hz=inner, duration=duration, sample_rate=rate)
    stiffness = history.stiffness_xx.values
    spectrum = np.abs(np.fft.rfft(stiffness - stiffness.mean()))
    frequency = np.fft.rfftfreq(stiffness.size, 1 / rate)
    assert abs(frequency[np.argmax(spectrum)] - bpfo) <= 1 / duration
    # over one element spacing the stiffness comes back to where it started
    pattern = varying_compliance(bearing, 3e4).stiffness_xx.values
    assert pattern[0] == pytest.approx(pattern[-1], rel=1e-9)
    assert np.ptp(pattern) > 1e-3 * pattern.mean()


def test_outer_race_defect_unloads_the_element_crossing_it_at_bpfo():
    bearing = ball(elements=9, pitch_diameter=0.039, element_diameter=0.0079)
    inner, rate = 30.0, 20000.0
    bpfo = bearing_frequencies(bearing, inner).lines["BPFO"]
    defect = BearingDefect("outer", width=1.0e-3, depth=20e-6)
    history = defect_excitation(bearing, 2e3, inner_hz=inner, duration=0.5,
                                sample_rate=rate, defects=(defect,))  # fmt: skip
    healthy = defect_excitation(bearing, 2e3, inner_hz=inner, duration=0.5, sample_rate=rate)
    drop = healthy.blocked_force_x.values - history.blocked_force_x.values
    starts = np.flatnonzero(np.diff((drop > 1e-6 * 2e3).astype(int)) == 1)
    # one drop per element passing the defect in the load zone's centre: 1 / BPFO apart
    # to a sample (the entry instant is rounded to the sample grid)
    assert np.allclose(np.diff(starts) / rate, 1 / bpfo, atol=1.01 / rate)
    # the element crossing a 1 mm gap drops d/2 - sqrt(d^2/4 - w^2/4) = 31.9 um > 20 um:
    # it loses all its load while inside (deflection ~3 um here)
    assert np.max(drop) > 0.2 * 2e3


def test_bad_load_is_one_line():
    with pytest.raises(CaseError, match=r"^radial_load must be a positive finite force in N"):
        load_distribution(ball(), -1.0)
    with pytest.raises(CaseError, match=r"^duration must be a positive finite number"):
        defect_excitation(ball(), 1e3, inner_hz=10.0, duration=0.0, sample_rate=1e3)


def test_element_law_broadcasts_over_instants():
    bearing = ball(elements=9)
    angles = np.linspace(0, 2 * np.pi, 9, endpoint=False) + np.array([[0.0], [0.1], [0.2]])
    loads, force, stiffness, _ = element_loads(bearing, np.full(3, 1e-6), np.zeros(3), angles)
    assert loads.shape == (3, 9) and force.shape == (3, 2) and stiffness.shape == (3, 2, 2)
    single = element_loads(bearing, 1e-6, 0.0, angles[1])[1]
    assert np.allclose(force[1], single, rtol=1e-14)


def test_element_defect_strikes_at_twice_bsf_inside_the_load_zone_once_per_cage_turn():
    bearing = ball(elements=9, pitch_diameter=0.039, element_diameter=0.0079)
    inner, rate = 30.0, 20000.0
    lines = bearing_frequencies(bearing, inner).lines
    defect = BearingDefect("element", width=0.5e-3, depth=10e-6)
    kwargs = dict(inner_hz=inner, duration=1.0, sample_rate=rate)
    drop = (
        defect_excitation(bearing, 2e3, **kwargs).blocked_force_x.values
        - defect_excitation(bearing, 2e3, defects=(defect,), **kwargs).blocked_force_x.values
    )
    starts = np.flatnonzero(np.diff((drop > 1e-3 * 2e3).astype(int)) == 1) / rate
    gaps = np.diff(starts)
    # the defect meets the outer and the inner race once each per spin turn: 1 / (2 BSF)
    # apart (to a sample) while the element is loaded; the longer gaps are the unloaded
    # half of the cage's turn: one per cage turn, 11.96 in the 1 s record (FTF)
    short = gaps[gaps < 0.25 / lines["FTF"]]
    assert np.allclose(short, 1 / (2 * lines["BSF"]), atol=1.01 / rate)
    assert np.count_nonzero(gaps >= 0.25 / lines["FTF"]) in (11, 12)
