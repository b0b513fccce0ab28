"""Multistage gearbox: stages as super elements, couplings, per-stage DOF pruning and
the seed's section 6 (Yang, Jiang & Han 2016, Tables 5 and 6)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from conftest import consistent_stage

from pygear import (
    Bearing,
    Body,
    Case,
    CaseError,
    Gearbox,
    RigidLink,
    ShaftInertia,
    TorsionalSpring,
    load_case,
)
from pygear.analysis.modes.modal import modal_analysis
from pygear.assembly import assemble

GEARBOX = Path(__file__).resolve().parent.parent / "cases" / "yang2016_gearbox"
# Yang, Jiang & Han (2016) Tables 5 and 6: the stages in the gearbox
STAGE1_TRANSLATIONAL = [727.3, 1091.5, 1893.2, 2342.6, 7192.8, 10441]
STAGE1_PLANET = [1808.6, 5963.8, 6989.7]
STAGE2_TRANSLATIONAL = [743.2, 1102.7, 1896.5, 2276.5, 6989.0, 9651.7]


@pytest.fixture(scope="module")
def gearbox_case() -> Case:
    return load_case(GEARBOX)


@pytest.fixture(scope="module")
def gearbox_modal(gearbox_case):
    return modal_analysis(assemble(gearbox_case))


def stage_frequencies(modal, stage, cls):
    chosen = (modal.stage_name.values == stage) & (modal.mode_class.values == cls)
    values = []
    for f in modal.frequency.values[chosen]:
        if not values or abs(f - values[-1]) > 1e-6 * f:
            values.append(float(f))
    return np.array(values)


def test_gearbox_picks_planar_for_its_spur_stages(gearbox_case):
    model = assemble(gearbox_case)
    assert model.dof_set == "per-stage"
    assert not any(
        label.startswith("stage1.") and label.endswith((".z", ".theta_x"))
        for label in model.dof_labels
    )
    assert "parallel.input_gear.z" in model.dof_labels


def test_per_stage_pruning_is_exact(gearbox_case):
    """Every frequency of the pruned model is a frequency of the full spatial model."""
    pruned = modal_analysis(assemble(gearbox_case)).frequency.values
    spatial = modal_analysis(assemble(gearbox_case, dof_set="spatial")).frequency.values
    assert spatial.size > pruned.size
    for f in pruned[1:]:
        assert np.min(np.abs(spatial / f - 1)) < 1e-9


def test_stage1_frequencies_in_gearbox(gearbox_modal):
    translational = stage_frequencies(gearbox_modal, "stage1", "translational")
    np.testing.assert_allclose(translational, STAGE1_TRANSLATIONAL, rtol=0.005)
    np.testing.assert_allclose(
        stage_frequencies(gearbox_modal, "stage1", "planet"), STAGE1_PLANET, rtol=0.005
    )


def test_stage_translational_unchanged_rotational_changed(gearbox_case, gearbox_modal):
    study = load_case(GEARBOX.parent / "yang2016_planetary")
    alone = modal_analysis(assemble(study, formulation="improved", dof_set="planar"))
    np.testing.assert_allclose(
        stage_frequencies(gearbox_modal, "stage2", "translational"),
        stage_frequencies(alone, "planetary", "translational"),
        rtol=1e-9,
    )
    np.testing.assert_allclose(
        stage_frequencies(gearbox_modal, "stage2", "translational"),
        STAGE2_TRANSLATIONAL,
        rtol=0.005,
    )
    in_gearbox = stage_frequencies(gearbox_modal, "stage2", "rotational")
    independent = stage_frequencies(alone, "planetary", "rotational")
    assert in_gearbox[0] == 0.0
    assert abs(in_gearbox[1] / independent[1] - 1) > 0.01  # coupling moves rotational modes


def test_couplings_tie_and_spring(gearbox_case):
    model = assemble(gearbox_case)
    assert "stage2.carrier.theta_z" not in model.dof_labels  # tied to stage 1's sun
    column = model.dof_labels.index("stage1.sun.theta_z")
    tied = model.full_labels.index("stage2.carrier.theta_z")
    assert model.reduction[tied, column] == 1.0
    # the revolution of stage 2's planets follows through both ties
    phi = model.full_labels.index("stage2.planet1.phi")
    assert model.reduction[phi, column] == 1.0
    assert "couplings.stage2_to_parallel.stiffness" in model.stiffness_parameters()


def test_kinematic_null_space_follows_the_ratios(gearbox_case):
    """The one rigid-body mode turns every member at its kinematic ratio."""
    model = assemble(gearbox_case)
    modal = modal_analysis(model)
    shape = model.reduction @ modal.shape.values[:, 0]
    value = dict(zip(model.full_labels, shape))
    stage = gearbox_case.gearbox.stage("stage1")
    ratio = 1 + stage.ring.base_radius / stage.sun.base_radius
    carrier = value["stage1.carrier.theta_z"]
    assert value["stage1.sun.theta_z"] / carrier == pytest.approx(ratio, rel=1e-9)
    assert value["stage2.sun.theta_z"] / carrier == pytest.approx(ratio**2, rel=1e-9)
    # equal radii: the parallel pair turns at the same speed in the opposite sense
    assert value["parallel.output_gear.theta_z"] / carrier == pytest.approx(-(ratio**2), rel=1e-9)


def test_spur_gearbox_planar_equals_spatial():
    first, second = consistent_stage(3, name="one"), consistent_stage(4, name="two")
    second = dataclasses.replace(
        second, axial_position=0.4, ring_bearing=dataclasses.replace(second.ring_bearing)
    )
    case = Case(
        name="spur",
        gearbox=Gearbox(
            stages=(first, second), couplings=(RigidLink("one.sun.theta_z", "two.carrier.theta_z"),)
        ),
    )
    planar = assemble(case)
    assert planar.dof_set == "planar"
    spatial = modal_analysis(assemble(case, dof_set="spatial"))
    in_plane = spatial.where(
        spatial.mode_class.isin(["rotational", "translational", "planet"]), drop=True
    )
    np.testing.assert_allclose(
        in_plane.frequency.values[1:], modal_analysis(planar).frequency.values[1:], rtol=1e-9
    )


def rotor_case(**changes) -> Case:
    stage = consistent_stage(3, name="stage")
    rotor = ShaftInertia(
        "rotor",
        Body(mass=50.0, polar_inertia=5.0, tilt_inertia=3.0),
        Bearing(radial=1e9, axial=1e9, tilt=1e7, torsional=0.0),
        axial_position=-0.5,
    )
    gearbox = Gearbox(
        stages=(rotor, stage),
        couplings=(
            TorsionalSpring(
                "main_shaft", "rotor.body.theta_z", "stage.carrier.theta_z", stiffness=2e6
            ),
        ),
    )
    return Case(name="rotor", gearbox=dataclasses.replace(gearbox, **changes))


def test_rotor_inertia_node_lowers_first_mode():
    modal = modal_analysis(assemble(rotor_case()))
    assert modal.frequency.values[0] == 0.0
    assert "rotor" in set(modal.stage_name.values)


@pytest.mark.parametrize(
    ("couplings", "message"),
    [
        ((RigidLink("rotor.body.theta_z", "stage.moon.theta_z"),), "has no member 'moon'"),
        ((RigidLink("rotor.body.theta_z", "stage.sun.spin"),), "has no DOF 'spin'"),
        ((RigidLink("rotor.body.theta_z", "gear9.sun.theta_z"),), "no stage named 'gear9'"),
        (
            (
                RigidLink("rotor.body.theta_z", "stage.carrier.theta_z"),
                RigidLink("stage.carrier.theta_z", "stage.sun.theta_z", ratio=2.0),
                RigidLink("stage.sun.theta_z", "rotor.body.theta_z"),
            ),
            "close a loop",
        ),
        ((), "stage 'stage' has no path to the drive"),
    ],
)
def test_bad_couplings(couplings, message):
    with pytest.raises(CaseError, match=message):
        rotor_case(couplings=couplings)


def test_disconnected_part_is_refused():
    """A ring left free of torque adds a second rigid-body motion."""
    case = rotor_case()
    stage = case.gearbox.stage("stage")
    free_ring = dataclasses.replace(
        stage, ring_bearing=dataclasses.replace(stage.ring_bearing, torsional=0.0)
    )
    case = dataclasses.replace(
        case, gearbox=dataclasses.replace(case.gearbox, stages=(case.gearbox.stages[0], free_ring))
    )
    with pytest.raises(CaseError, match="2 free rigid-body motions, 1 expected"):
        assemble(case)


def parallel_only(helix_deg: float) -> Case:
    gearbox_case = load_case(GEARBOX)
    pair = gearbox_case.gearbox.stage("parallel")
    held = dataclasses.replace(
        pair,
        base_helix_angle_deg=helix_deg,
        output_bearing=dataclasses.replace(pair.output_bearing, torsional=1e7),
    )
    return Case(name="pair", gearbox=Gearbox(stages=(held,), rigid_body_modes=0))


@pytest.mark.parametrize("helix_deg", [0.0, 10.0, 20.0, -20.0])
def test_helical_mesh_axial_force_under_torque(helix_deg):
    """Torque T on the input gear: the mesh force N along the contact normal has the
    tangential part T/r_b and the axial part (T/r_b) tan(beta_b), carried by the axial
    bearing (static equilibrium, independent of stiffnesses)."""
    case = parallel_only(helix_deg)
    model = assemble(case, dof_set="spatial")
    torque = 100.0
    load = np.zeros(model.size)
    load[model.dof_labels.index("parallel.input_gear.theta_z")] = torque
    q = model.reduction @ np.linalg.solve(model.stiffness, load)
    pair = case.gearbox.stage("parallel")
    axial = pair.input_bearing.axial * q[model.full_labels.index("parallel.input_gear.z")]
    tangential = torque / pair.input_gear.base_radius
    expected = tangential * np.tan(np.radians(helix_deg))
    assert abs(axial) == pytest.approx(abs(expected), rel=1e-9, abs=1e-9 * tangential)


def test_modal_cli_names_stages_and_compares(capsys):
    import json

    from pygear.cli import main

    assert main(["modal", str(GEARBOX), "--json", "--compare-stage", "stage2"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert len(result["stage"]) == len(result["frequencies_hz"]) == len(result["mode_class"])
    assert set(result["stage"]) == {"stage1", "stage2", "parallel"}
    table = result["stage_comparison"]["translational"]
    np.testing.assert_allclose(table["in_gearbox_hz"], table["independent_hz"], rtol=1e-9)
    rotational = result["stage_comparison"]["rotational"]
    assert rotational["in_gearbox_hz"][1] != pytest.approx(rotational["independent_hz"][1])
