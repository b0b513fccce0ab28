"""Rolling bearings as case data (validation, plausibility) and their characteristic
frequencies against published values."""

from __future__ import annotations

import math

import pytest

from pygear.analysis.condition.bearing_kinematics import (
    bearing_frequencies,
    frequency_table,
    read_frequency_table,
    run_frequencies,
)
from pygear.errors import CaseError
from pygear.model.plausibility import PlausibilityWarning
from pygear.model.rolling_bearing import BearingDefect, DistributedFault, RollingBearing

INCH = 0.0254
# SKF 6205-2RS JEM, the drive-end bearing of the Case Western Reserve University bearing
# data set (used in Randall & Antoni 2011 and Smith & Randall 2015): Z = 9, d = 0.3126 in,
# D = 1.537 in; the data centre's fault frequencies in multiples of the shaft speed
CWRU_6205 = dict(elements=9, element_diameter=0.3126 * INCH, pitch_diameter=1.537 * INCH)
CWRU_ORDERS = {"BPFI": 5.4152, "BPFO": 3.5848, "FTF": 0.39828, "2BSF": 4.7135}


def ball(**changes) -> RollingBearing:
    return RollingBearing(**{"name": "DE", "type": "ball", **CWRU_6205, **changes})


def test_published_fault_orders_of_the_cwru_6205():
    found = bearing_frequencies(ball(), inner_hz=1.0).lines
    # the data centre prints 4-5 digits from inch dimensions of 4 digits: 3e-4 relative
    assert found["BPFI"] == pytest.approx(CWRU_ORDERS["BPFI"], rel=3e-4)
    assert found["BPFO"] == pytest.approx(CWRU_ORDERS["BPFO"], rel=3e-4)
    assert found["FTF"] == pytest.approx(CWRU_ORDERS["FTF"], rel=3e-4)
    assert 2 * found["BSF"] == pytest.approx(CWRU_ORDERS["2BSF"], rel=3e-4)


def test_formulas_hold_for_any_ring_turning_and_planet_bearings_see_the_carrier():
    bearing = ball(contact_angle_deg=15.0)
    d, pitch = CWRU_6205["element_diameter"], CWRU_6205["pitch_diameter"]
    gamma = d * math.cos(math.radians(15.0)) / pitch
    z = 9
    # planet bearing: pin (inner) held by the carrier, planet bore (outer) at 3.7 Hz
    # relative to it, carrier at 0.2 Hz: the relative speed alone sets the lines
    found = bearing_frequencies(bearing, inner_hz=0.0, outer_hz=3.7, carrier_hz=0.2)
    f_r = 3.7
    assert found.lines["BPFO"] == pytest.approx(z / 2 * f_r * (1 - gamma), rel=1e-12)
    assert found.lines["BPFI"] == pytest.approx(z / 2 * f_r * (1 + gamma), rel=1e-12)
    assert found.lines["FTF"] == pytest.approx(f_r / 2 * (1 - gamma), rel=1e-12)
    assert found.lines["BSF"] == pytest.approx(
        pitch / (2 * d) * f_r * (1 - gamma**2),
        rel=1e-12,
    )
    # the turning outer race carries its defect through the load zone at f_r; the pin's
    # defect stays in it; both pass the housing sensor at the carrier rate
    assert found.modulation["BPFO"] == pytest.approx(f_r)
    assert found.modulation["BPFI"] == 0.0
    assert found.carrier == pytest.approx(0.2)
    # the cage of a bearing with its inner ring held turns at (1 + gamma) f_o / 2
    assert found.cage == pytest.approx(0.5 * (1 + gamma) * f_r, rel=1e-12)


def test_run_frequencies_take_planet_speeds_relative_to_the_carrier():
    planet = ball(name="PL", location="stage1.planet")
    shaft = ball(name="HS", location="parallel.output_gear")
    speeds = {"stage1.carrier": 12.0, "stage1.planet1": -30.0, "parallel.output_gear": 1165.0}
    elsewhere = ball(name="X", location="none")
    table = frequency_table(run_frequencies((planet, shaft, elsewhere), speeds))
    assert list(table.rolling_bearing.values) == ["PL", "HS"]
    assert table.bearing_shaft_frequency.sel(rolling_bearing="PL") == pytest.approx(0.5)
    assert table.bearing_carrier_frequency.sel(rolling_bearing="PL") == pytest.approx(0.2)
    assert table.bearing_frequency.sel(rolling_bearing="HS", bearing_line="BPFO") == pytest.approx(
        CWRU_ORDERS["BPFO"] * 1165.0 / 60.0, rel=3e-4
    )
    assert table.bearing_frequency.attrs["units"] == "Hz"
    back = {f.name: f for f in read_frequency_table(table)}
    assert back["HS"].lines["BPFI"] == pytest.approx(CWRU_ORDERS["BPFI"] * 1165 / 60, rel=3e-4)
    assert back["HS"].modulation["BPFI"] == pytest.approx(1165 / 60)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"type": "needle"}, r"\.type must be one of ball, roller"),
        ({"elements": 2}, r"\.elements must be a whole number >= 3"),
        ({"elements": 9.0}, r"\.elements must be a whole number"),
        ({"element_diameter": 0.05}, r"\.element_diameter must be below pitch_diameter"),
        ({"pitch_diameter": -1.0}, r"\.pitch_diameter must be a positive finite number"),
        ({"contact_angle_deg": 90.0}, r"\.contact_angle_deg must be in \[0, 90\)"),
        ({"diametral_clearance": 0.01}, r"\.diametral_clearance must be finite with \|P_d\|"),
        ({"diametral_clearance": math.nan}, r"\.diametral_clearance must be finite"),
        ({"roller_length": 0.01}, r"\.roller_length must be None for a ball bearing"),
        ({"type": "roller"}, r"\.roller_length must be given for a roller bearing"),
        ({"inner_conformity": 0.5}, r"\.inner_conformity must be in \(0\.5, 5\]"),
        ({"poisson_ratio": 0.5}, r"\.poisson_ratio must be in \[0, 0\.5\)"),
        ({"turning_ring": "cage"}, r"\.turning_ring must be one of inner, outer"),
    ],
)
def test_bad_geometry_is_one_line_naming_the_parameter(changes, message):
    with pytest.raises(CaseError, match=r"^rolling_bearings\['DE'\]" + message):
        ball(**changes)


def test_a_diameter_in_mm_warns_naming_the_parameter_and_range():
    with pytest.warns(PlausibilityWarning, match=r"pitch_diameter = 39\.04 m is outside"):
        ball(pitch_diameter=39.04, element_diameter=7.94)


def test_defects_are_checked_alone_and_against_the_bearing():
    with pytest.raises(CaseError, match=r"^defect\.location must be one of outer, inner"):
        BearingDefect("cage", width=1e-3, depth=1e-5)
    with pytest.raises(CaseError, match=r"^defect\.depth must be a positive finite number"):
        BearingDefect("outer", width=1e-3, depth=0.0)
    with pytest.raises(CaseError, match=r"^defect\.profile must be one of rectangular, cosine"):
        BearingDefect("outer", width=1e-3, depth=1e-5, profile="square")
    wide = BearingDefect("outer", width=0.02, depth=1e-5)
    with pytest.raises(CaseError, match=r"^defects\[0\]\.width must be below the element spacing"):
        wide.validate("defects[0]", ball())
    with pytest.raises(CaseError, match=r"^defects\[0\]\.element must be below the bearing's 9"):
        BearingDefect("element", width=1e-3, depth=1e-5, element=9).validate("defects[0]", ball())
    with pytest.raises(CaseError, match=r"^fault\.wear must be a finite number >= 0"):
        DistributedFault("outer", wear=-1e-6)


def test_nrel_planet_bearings_fit_their_published_envelopes():
    from pygear.model.case_files import load_case_module

    _, module = load_case_module("nrel5mw_gearbox")
    # Nejad et al. (2016) Tables VI, IX: outer x bore x width [m] of the planet CRBs
    envelopes = {"PL": (0.600, 0.400, 0.272), "IMS-PL": (0.520, 0.380, 0.140)}
    bearings = {b.name: b for b in module.rolling_bearings}
    assert set(bearings) == {"PL-A", "PL-B", "IMS-PL-A", "IMS-PL-B"}
    assert set(bearings) <= {b.name for b in module.rating.bearings}
    for name, bearing in bearings.items():
        outer, bore, width = envelopes[name.rsplit("-", 1)[0]]
        assert bearing.pitch_diameter == pytest.approx((outer + bore) / 2)
        assert bearing.element_diameter < (outer - bore) / 2  # inside the section
        assert bearing.rows * bearing.roller_length < width
        spacing = math.pi * bearing.pitch_diameter / bearing.elements
        assert bearing.element_diameter < spacing  # rollers fit around the pitch circle
        assert bearing.planet and bearing.turning == "outer"
