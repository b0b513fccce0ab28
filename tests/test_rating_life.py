"""Duty cycles and lives: rainflow counts of ASTM E1049-85's example, Miner sums of block
spectra by hand, ISO 6336-6's S-N curve, ISO 281 lives and mean loads by hand."""

from __future__ import annotations

import math
from collections import defaultdict

import pytest

from pygear.analysis.rating import bearing_life as iso281
from pygear.analysis.rating.duty import (
    cycles_to_failure,
    load_spectrum_from_series,
    miner_damage,
    rainflow_cycles,
)
from pygear.analysis.rating.gearbox_rating import load_sharing_from_forces
from pygear.errors import CaseError
from pygear.model.rating import DutyCycle, RollingBearingData


def test_rainflow_counts_astm_e1049_example():
    # ASTM E1049-85 (2017) section 5.4.4, Fig. 6 and Table 4: the history
    # -2, 1, -3, 5, -1, 3, -4, 4, -2 holds range 3: 0.5, range 4: 1.5, range 6: 0.5,
    # range 8: 1.0 and range 9: 0.5 cycles (and no other ranges)
    counts: dict[float, float] = defaultdict(float)
    for rng, _, count in rainflow_cycles([-2, 1, -3, 5, -1, 3, -4, 4, -2]):
        counts[rng] += count
    assert dict(counts) == {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


def test_rainflow_refuses_a_short_series():
    with pytest.raises(CaseError, match="at least two finite values"):
        rainflow_cycles([1.0])


def test_miner_sum_of_a_two_level_block_by_hand():
    # Basquin curve N = 1e6 (100/S)^5; blocks of 1000 cycles at 200 MPa and 10 000 at
    # 150 MPa: D = 1000 / (1e6/32) + 10000 / (1e6 (2/3)^5) = 0.032 + 0.0759375
    damage = miner_damage([200.0, 150.0], [1000.0, 10000.0],
                          lambda s: 1e6 * (100.0 / s) ** 5)
    assert damage == pytest.approx(0.032 + 10000.0 / (1e6 * (2.0 / 3.0) ** 5), rel=1e-12)


def test_iso6336_sn_curve_inverts_the_life_factor_by_hand():
    # case-carburized root (ISO 6336-3 Table 4): Y_NT = 2.5 at 1e3, 1 at 3e6, 0.85 at
    # 1e10, straight in log-log.  A stress 1.3 x the reference lies on the first line:
    # N = 1e3 (1.3/2.5)^(1/k), k = ln(1/2.5)/ln(3e6/1e3); 0.9 x on the second line:
    # N = 3e6 0.9^(1/k2), k2 = ln 0.85 / ln(1e10/3e6)
    k1 = math.log(1.0 / 2.5) / math.log(3e6 / 1e3)
    k2 = math.log(0.85) / math.log(1e10 / 3e6)
    assert cycles_to_failure("case_carburized", 1.3, 1.0, root=True) == pytest.approx(
        1e3 * (1.3 / 2.5) ** (1.0 / k1), rel=1e-12)
    assert cycles_to_failure("case_carburized", 0.9, 1.0, root=True) == pytest.approx(
        3e6 * 0.9 ** (1.0 / k2), rel=1e-12)
    # beyond 1e10 the last line goes on (no endurance limit in a damage sum)
    assert cycles_to_failure("case_carburized", 0.8, 1.0, root=True) > 1e10
    # above the static limit: the first knee
    assert cycles_to_failure("case_carburized", 3.0, 1.0, root=True) == 1e3
    # a two-level block on this curve, by hand
    n1 = 1e3 * (1.3 / 2.5) ** (1.0 / k1)
    n2 = 3e6 * 0.9 ** (1.0 / k2)
    damage = miner_damage([1.3, 0.9], [1e4, 1e8],
                          lambda s: cycles_to_failure("case_carburized", s, 1.0, root=True))
    assert damage == pytest.approx(1e4 / n1 + 1e8 / n2, rel=1e-12)


def test_time_series_becomes_tooth_contacts_at_level():
    # each sample stands for half the interval to each neighbour: the 100 kN samples at
    # 0, 1, 2 s hold 0.5 + 1 + 0.75 = 2.25 s, the 50 kN ones at 2.5, 3 s hold 0.5 +
    # 0.25 = 0.75 s; at 20 contacts per second: 45 and 15 load cycles
    time = [0.0, 1.0, 2.0, 2.5, 3.0]
    force = [1e5, 1e5, 1e5, 5e4, 5e4]
    levels, cycles = load_spectrum_from_series(time, force, 20.0, bins=2)
    assert levels == pytest.approx([5e4, 1e5], rel=1e-9)
    assert cycles == pytest.approx([15.0, 45.0], rel=1e-12)


def test_load_sharing_from_planet_forces():
    assert load_sharing_from_forces([1.1e5, 1.0e5, 0.9e5]) == pytest.approx(1.1, rel=1e-12)


def test_l10_under_constant_load_is_c_over_p_to_the_p():
    assert iso281.basic_life(30e3, 3e3, "ball") == pytest.approx(1000.0, rel=1e-12)
    assert iso281.basic_life(100e3, 10e3, "roller") == pytest.approx(10 ** (10 / 3), rel=1e-12)


def test_equivalent_load_picks_the_branch_by_e():
    # F_a/F_r = 0.5 > e = 0.3: P = 0.4 F_r + 1.6 F_a; 0.2 <= e: P = F_r + Y1 F_a
    assert iso281.equivalent_load(10e3, 5e3, 0.3, 0.4, 1.6) == pytest.approx(12e3)
    assert iso281.equivalent_load(10e3, 2e3, 0.3, 0.4, 1.6, 0.5) == pytest.approx(11e3)


def test_variable_load_mean_by_hand():
    # P_m = (sum P^p N / sum N)^(1/p), roller p = 10/3
    p = 10.0 / 3.0
    loads, revs = [10e3, 20e3, 5e3], [1e6, 2e5, 5e6]
    hand = ((10e3**p * 1e6 + 20e3**p * 2e5 + 5e3**p * 5e6) / 6.2e6) ** (1.0 / p)
    assert iso281.mean_load(loads, revs, "roller") == pytest.approx(hand, rel=1e-12)


def test_a_iso_by_hand_and_its_trends():
    # ISO 281 cl. 9.3, radial roller bearing, 1 <= kappa <= 4
    # e_C C_u / P = 0.5 x 20 kN / 200 kN = 0.05
    hand = 0.1 * (1.0 - (2.5671 - 1.2777 / 1.5**0.071739) ** 0.83 * 0.05**0.4) ** -9.185
    assert hand < 50.0  # below the cap, so the formula is what is compared
    assert iso281.a_iso("roller", 1.5, 0.5, 20e3, 200e3) == pytest.approx(hand, rel=1e-12)
    cleaner = iso281.a_iso("roller", 1.5, 0.8, 20e3, 200e3)
    thinner = iso281.a_iso("roller", 0.5, 0.5, 20e3, 200e3)
    assert cleaner > hand > thinner
    assert iso281.a_iso("ball", 4.0, 1.0, 1e5, 1e3) == 50.0  # the standard's cap


def test_nrel_planet_bearing_life_by_hand():
    # PL-A carries half of the planet pin's load 2 F_t, F_t = 2 T_sun / (3 d_sun) at the
    # rated 5 MW and 12.1 rpm; it turns at the planet's speed relative to the carrier
    from pygear.analysis.rating.gearbox_rating import rate_gearbox
    from pygear.model.rating import load_rating

    case, rating = load_rating("nrel5mw_gearbox")
    result = rate_gearbox(case, rating)
    t_carrier = 5e6 / (12.1 * math.pi / 30.0)
    t_sun = t_carrier / (1.0 + 56.0 / 19.0)
    f_t = 2.0 * t_sun / (3.0 * 19 * 0.045)
    n_planet = 12.1 * (56.0 / 19.0) * 19.0 / 17.0
    bearing = next(b for b in rating.bearings if b.name == "PL-A")
    l10_h = (bearing.C / f_t) ** (10.0 / 3.0) * 1e6 / (60.0 * n_planet)
    assert result.bearings["PL-A"]["P"] == pytest.approx(f_t, rel=1e-9)
    assert result.bearings["PL-A"]["L10_h"] == pytest.approx(l10_h, rel=1e-9)


def test_duty_cycle_of_the_rated_point_reproduces_the_constant_load_damage():
    # one bin at the rated torque for the whole life with K_A = 1 is the static rating
    # at K_A = 1: ISO 6336-6 replaces K_A by the spectrum
    import dataclasses

    from pygear.analysis.rating.gearbox_rating import rate_gearbox
    from pygear.model.rating import load_rating

    case, rating = load_rating("nrel5mw_gearbox")
    rating = dataclasses.replace(rating, application_factor=1.0, bearings=())
    static = rate_gearbox(case, rating)
    spectrum = DutyCycle((rating.rated_torque,), (rating.service_life_h,))
    duty = rate_gearbox(case, rating, duty_cycle=spectrum)
    for gear, values in static.damage.items():
        assert duty.damage[gear]["pitting"] == pytest.approx(values["pitting"], rel=1e-9)
        assert duty.damage[gear]["bending"] == pytest.approx(values["bending"], rel=1e-9)


def test_bearing_and_duty_inputs_are_checked():
    with pytest.raises(CaseError, match=r"radial_load must be given"):
        RollingBearingData("HS-A", "roller", 1e6, 2e6, location="parallel.output_gear")
    with pytest.raises(CaseError, match=r"duty_cycle\.hours must have one value per"):
        DutyCycle((1.0, 2.0), (1.0,))
    with pytest.raises(CaseError, match=r"kind must be one of"):
        RollingBearingData("X", "needle", 1e6, 2e6, location="stage1.planet")


def test_a_misspelt_mesh_or_stage_is_refused():
    import dataclasses

    from pygear.analysis.rating.gearbox_rating import rate_gearbox
    from pygear.model.rating import load_rating

    case, rating = load_rating("nrel5mw_gearbox")
    typo = dataclasses.replace(rating, load_sharing={"stage_1": 1.2})
    with pytest.raises(CaseError, match=r"rating\.load_sharing names \['stage_1'\]"):
        rate_gearbox(case, typo)
    with pytest.raises(CaseError, match=r"dynamic_factors names \['stage1\.sun'\]"):
        rate_gearbox(case, rating, dynamic_factors={"stage1.sun": 1.1})


def test_dynamic_factor_from_outside_enters_as_given():
    # the hook for pygear response: K_v per mesh replaces method B, marked "response",
    # and sigma_H scales as sqrt(K_v) with the other factors of that mesh held
    from pygear.analysis.rating.gearbox_rating import rate_gearbox
    from pygear.model.rating import load_rating

    case, rating = load_rating("nrel5mw_gearbox")
    plain = rate_gearbox(case, rating, dynamic_factors={"stage2.sun_mesh": 1.1})
    harder = rate_gearbox(case, rating, dynamic_factors={"stage2.sun_mesh": 1.44})
    mesh = {m.name: m for m in harder.meshes}["stage2.sun_mesh"]
    assert mesh.rating.mesh["K_v"].value == 1.44
    assert mesh.rating.mesh["K_v"].source == "response"
    before = {m.name: m for m in plain.meshes}["stage2.sun_mesh"].rating
    ratio = mesh.rating.gears[0]["sigma_H"].value / before.gears[0]["sigma_H"].value
    held = (mesh.rating.mesh["K_Halpha"].value / before.mesh["K_Halpha"].value)
    assert ratio == pytest.approx(math.sqrt(1.44 / 1.1 * held), rel=1e-12)


def test_nrel_tapered_bearing_equivalent_load_by_hand():
    # HS-B takes a quarter of the pinion's radial resultant and its whole axial force
    # (the case's ASSUMED split); F_a/F_r > e = 0.40, so P = 0.4 F_r + 1.49 F_a.  The
    # pinion's forces by hand: T_pinion = T / i, F_t = 2 T_pinion / d, F_r = F_t tan
    # alpha_wt (inv alpha_wt = 2 tan alpha_n (x1 + x2)/(z1 + z2) + inv alpha_t), F_a =
    # F_t tan beta
    from pygear.analysis.rating.gearbox_rating import rate_gearbox
    from pygear.model.rating import load_rating

    case, rating = load_rating("nrel5mw_gearbox")
    result = rate_gearbox(case, rating)
    ratio = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)
    beta = math.radians(10.0)
    alpha_t = math.atan(math.tan(math.radians(20.0)) / math.cos(beta))
    target = 2 * math.tan(math.radians(20.0)) * (0.480 + 0.669) / (24 + 95) + (
        math.tan(alpha_t) - alpha_t)
    alpha_wt = 0.5
    for _ in range(60):
        alpha_wt -= (math.tan(alpha_wt) - alpha_wt - target) / math.tan(alpha_wt) ** 2
    f_t = 2 * rating.rated_torque / ratio / (24 * 0.014 / math.cos(beta))
    radial = 0.25 * math.hypot(f_t, f_t * math.tan(alpha_wt))
    axial = f_t * math.tan(beta)
    assert axial / radial > 0.40
    p_hand = 0.4 * radial + 1.49 * axial
    assert result.bearings["HS-B"]["P"] == pytest.approx(p_hand, rel=1e-9)
    assert result.bearings["HS-B"]["speed"] == pytest.approx(12.1 * ratio, rel=1e-9)
