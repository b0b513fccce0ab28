"""Bad input is refused before any work, with a message naming the parameter and rule."""

from __future__ import annotations

import dataclasses
import math

import pytest
from conftest import case_of, consistent_stage

from pygear import CaseError, Scene
from pygear.assembly import assemble
from pygear.model.case import replace_parameter


@pytest.mark.parametrize(
    ("parameter", "value", "message"),
    [
        ("planetary.sun.mass", 0.0, "planetary.sun.mass must be a positive"),
        ("planetary.sun.mass", -1.0, "planetary.sun.mass must be a positive"),
        ("planetary.planet.polar_inertia", math.nan, "planetary.planet.polar_inertia"),
        ("planetary.ring.tilt_inertia", math.inf, "planetary.ring.tilt_inertia"),
        ("planetary.carrier.radius", 0.0, "planetary.carrier.radius must be a positive"),
        ("planetary.sun.base_radius", -0.01, "planetary.sun.base_radius"),
        ("planetary.sun_bearing.radial", -1e8, "planetary.sun_bearing.radial must be"),
        ("planetary.planet_bearing.tilt", -5.0, "planetary.planet_bearing.tilt"),
        ("planetary.ring_mesh.stiffness", -5e8, "planetary.ring_mesh.stiffness"),
        ("planetary.planets", 0, "planetary.planets must be a whole number >= 1"),
        ("planetary.planets", 2.5, "planetary.planets must be a whole number"),
        ("damping.mass_coefficient", -0.1, "damping.mass_coefficient must be a finite number >= 0"),
        ("formulation", "lumped", "formulation must be one of improved, consistent, lin-parker"),
    ],
)
def test_bad_parameter_is_named(study_case, parameter, value, message):
    with pytest.raises(CaseError, match=message.replace("(", r"\(")):
        replace_parameter(study_case, parameter, value)


def test_colliding_planet_angles(study_case):
    with pytest.raises(CaseError, match=r"planetary.planet_angles_deg: .*collide"):
        replace_parameter(study_case, "planetary.planet_angles_deg", (0.0, 40.0, 200.0))


def test_planet_angle_count(study_case):
    with pytest.raises(CaseError, match="one angle per planet"):
        replace_parameter(study_case, "planetary.planet_angles_deg", (0.0, 120.0))


def test_teeth_that_cannot_be_assembled(study_case):
    # (27 + 96)/4 is not a whole number
    with pytest.raises(CaseError, match=r"\(Z_s \+ Z_r\)/N must be a whole number"):
        replace_parameter(study_case, "planetary.planets", 4)
    # unequal spacing lifts the rule
    unequal = dataclasses.replace(
        study_case.gearbox.stages[0], planets=4, planet_angles_deg=(0.0, 87.8, 180.0, 272.2)
    )
    unequal.validate()


def test_unknown_formulation_and_dof_set(study_case):
    with pytest.raises(CaseError, match="formulation must be one of"):
        assemble(study_case, formulation="rigid")
    with pytest.raises(CaseError, match="--dof-set must be one of spatial, planar, torsional"):
        assemble(study_case, dof_set="axial")
    with pytest.raises(CaseError, match=r"scenes.s.dof_set must be one of"):
        dataclasses.replace(study_case, scenes=(Scene("s", dof_set="3d"),))


def test_unknown_parameter_path(study_case):
    with pytest.raises(CaseError, match="'mass_flow' is not a field"):
        replace_parameter(study_case, "planetary.sun.mass_flow", 1.0)
    with pytest.raises(CaseError, match="must start with a stage name"):
        replace_parameter(study_case, "stage9.sun.mass", 1.0)


def test_bad_input_fails_before_assembly(monkeypatch):
    """Validation runs before any kernel call."""
    import pygear.assembly.matrices as assembly

    calls = []
    monkeypatch.setattr(assembly, "call", lambda *a: calls.append(a))
    stage = dataclasses.replace(consistent_stage(3), planets=-2)
    with pytest.raises(CaseError):
        assemble(case_of(stage))
    assert calls == []
