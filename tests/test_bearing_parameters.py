"""A case's rolling bearings as scene parameters and their defects' planet, refused in
one line when wrong."""

from __future__ import annotations

import dataclasses

import pytest

from pygear.analysis.time.transient import transient_problem
from pygear.errors import CaseError
from pygear.model.case import Scene, get_parameter, load_case, replace_parameter
from pygear.model.rolling_bearing import BearingDefect, RollingBearing

PIN = RollingBearing(
    "PB", "roller", elements=14, pitch_diameter=0.05, element_diameter=0.008,
    roller_length=0.008, diametral_clearance=5e-6, location="planetary.planet",
)  # fmt: skip


@pytest.fixture(scope="module")
def case():
    return dataclasses.replace(load_case("sequential_planetary"), rolling_bearings=(PIN,))


def test_rolling_bearing_fields_are_scene_parameters(case):
    spall = (BearingDefect("outer", width=1e-3, depth=5e-6, planet=3),)
    changed = replace_parameter(case, "rolling_bearings.PB.defects", spall)
    assert get_parameter(changed, "rolling_bearings.PB.defects") == spall
    assert get_parameter(changed, "rolling_bearings.PB.diametral_clearance") == 5e-6
    with pytest.raises(CaseError, match=r"rolling bearings: PB"):
        get_parameter(case, "rolling_bearings.XX.defects")
    with pytest.raises(CaseError, match=r"diametral_clearance"):
        replace_parameter(case, "rolling_bearings.PB.diametral_clearance", 0.01)


def test_defect_planet_is_whole_and_positive():
    with pytest.raises(CaseError, match=r"defect\.planet must be a whole number >= 1"):
        BearingDefect("outer", width=1e-3, depth=5e-6, planet=0)


def test_a_planet_the_stage_lacks_is_refused_before_the_run(case):
    """The stage has 3 planets: a defect on planet 4 names none."""
    spalled = replace_parameter(
        case,
        "rolling_bearings.PB.defects",
        (BearingDefect("inner", width=1e-3, depth=5e-6, planet=4),),
    )
    base = case.scene("steady_sensor")
    scene = Scene(
        "spall", analyses=("transient",), dof_set="planar",
        effects=("rolling_bearing_contact",), transient=base.transient,
    )  # fmt: skip
    with pytest.raises(CaseError, match=r"planet 4 names no planet of 'planetary.planet'"):
        transient_problem(spalled, scene)
