"""Unit mistakes and impossible values (issue #27.7): refused or warned before any work.

A value that is no finite number or physically impossible is a CaseError naming the
parameter; a possible value outside the plausible range of any real gearbox (the table
of pygear.model.plausibility) is a PlausibilityWarning naming the parameter, the value
and the range with its unit.  The mistakes are those of the issue: a Young's modulus in
MPa typed as Pa, a shaft in mm typed as m, a backlash in mm typed as m, a 5 m face on a
3 mm module, a NaN carrier radius.  References: steel E = 206 GPa (2.06e5 MPa); a
backlash can never reach the circular pitch pi m (the mating tooth would have no
thickness); ISO 6336 face widths are some 6 to 30 modules.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import pytest

from pygear import CaseError, Shaft, ShaftSection, load_case
from pygear.model.case import replace_parameter
from pygear.model.plausibility import PLAUSIBLE, PlausibilityWarning, implausibility

ROOT = Path(__file__).resolve().parent.parent
CASES = ("nrel5mw_gearbox", "nrel5mw_drivetrain", "sequential_planetary", "yang2016_gearbox",
         "yang2016_planetary")  # fmt: skip


@pytest.fixture(scope="module")
def geometry_case():
    """The sequentially phased stage: 3 mm module, 30 mm face, potential-energy meshes."""
    return load_case(ROOT / "cases" / "sequential_planetary")


@pytest.mark.parametrize("name", CASES)
def test_shipped_cases_raise_no_plausibility_warning(name):
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        load_case(ROOT / "cases" / name).validate()


def test_young_modulus_in_mpa_warns_naming_parameter_value_and_range(geometry_case):
    with pytest.warns(PlausibilityWarning) as caught:
        replace_parameter(geometry_case, "planetary.sun_mesh.young_modulus", 206e3)
    message = str(caught[0].message)
    assert message.startswith("planetary.sun_mesh.young_modulus = 206000.0 Pa is outside")
    assert "1e+09 .. 1e+12 Pa" in message and "MPa" in message


def test_steel_in_pa_gives_no_warning(geometry_case):
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        replace_parameter(geometry_case, "planetary.sun_mesh.young_modulus", 206e9)


def test_shaft_in_mm_typed_as_m_warns():
    with pytest.warns(PlausibilityWarning, match=r"^s\.outer_diameter = 700\.0 m is outside"):
        ShaftSection(2.0, 700.0).validate("s")
    shaft = Shaft("main", (ShaftSection(2.0, 0.7),), young_modulus=2.06e5,
                  shear_modulus=7.9e10, density=7850.0)  # fmt: skip
    with pytest.warns(PlausibilityWarning, match=r"^main\.young_modulus = 206000\.0 Pa"):
        shaft.validate("main")


@pytest.mark.parametrize("backlash", [0.1, 1.0, 10e-3])
def test_backlash_of_a_circular_pitch_or_more_is_an_error(geometry_case, backlash):
    # pi m = 9.42 mm on the 3 mm module: 10 mm leaves the mating tooth no thickness
    with pytest.raises(CaseError, match=r"^planetary\.sun_mesh\.backlash must be below the "
                       r"circular pitch pi m_t = 9\.42"):  # fmt: skip
        replace_parameter(geometry_case, "planetary.sun_mesh.backlash", backlash)


def test_large_backlash_warns_and_a_usual_one_does_not(geometry_case):
    with pytest.warns(PlausibilityWarning, match=r"^planetary\.ring_mesh\.backlash / m_t"):
        replace_parameter(geometry_case, "planetary.ring_mesh.backlash", 1.5e-3)  # 0.5 m
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        replace_parameter(geometry_case, "planetary.ring_mesh.backlash", 0.15e-3)  # 0.05 m


def test_face_width_of_five_metres_on_a_3_mm_module_warns(geometry_case):
    sun = geometry_case.gearbox.stages[0].sun
    wide = dataclasses.replace(sun.geometry, face_width=5.0)
    with pytest.warns(PlausibilityWarning, match=r"face_width / normal_module .* 1666\.6"):
        replace_parameter(geometry_case, "planetary.sun.geometry", wide)


def test_nan_carrier_radius_is_an_error_not_a_request_to_derive(geometry_case):
    with pytest.raises(CaseError, match=r"^planetary\.carrier\.radius must be a positive finite "
                       r"number \(got nan\)"):  # fmt: skip
        replace_parameter(geometry_case, "planetary.carrier.radius", math.nan)


def test_left_out_carrier_radius_is_still_derived(geometry_case):
    stage = geometry_case.gearbox.stages[0]
    carrier = dataclasses.replace(stage.carrier, radius=None)
    changed = replace_parameter(geometry_case, "planetary.carrier", carrier)
    # zero-shift pair: a = m (Z_s + Z_p) / 2 = 3 mm * 63 / 2
    assert changed.gearbox.stages[0].carrier.radius == pytest.approx(94.5e-3, rel=1e-12)


def test_every_range_is_ordered_and_holds_the_nrel_and_steel_values():
    for quantity, limits in PLAUSIBLE.items():
        assert 0 <= limits.low < limits.high, quantity
        assert limits.unit and limits.reason, quantity
    # published values that must lie inside: steel 206 GPa, NREL 5 MW rotor 1.1e5 kg and
    # 3.9e7 kg m^2 (Jonkman 2009), its 45 mm stage-1 module (Nejad et al. 2016)
    for quantity, value in (("young_modulus", 206e9), ("mass", 1.1e5), ("inertia", 3.9e7),
                            ("module", 45e-3), ("face_width_ratio", 491 / 45)):  # fmt: skip
        assert implausibility(quantity, value) is None, quantity
