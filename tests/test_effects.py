"""Effects as the scene's contract (PHYSICS.md 7, issue #5): pruning is exact, an effect
left out costs nothing, every output records what was in force, contradictions are refused."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import CASES, case_of, consistent_stage

from pygear import CaseError, Scene
from pygear.assembly import assemble
from pygear.cli import main
from pygear.modal import modal_analysis
from pygear.transient import run_transient

TV = "time_varying_mesh_stiffness"


def _short(scene: Scene, **changes) -> Scene:
    """The run-up shortened to 0.2 s (8000 steps at the paper's 2.5e-5 s)."""
    transient = dataclasses.replace(scene.transient, duration=0.2, mean_window=0.05)
    return dataclasses.replace(scene, transient=transient, **changes)


@pytest.fixture(scope="module")
def planar_and_spatial(study_case):
    runup = _short(study_case.scene("runup"))
    planar = run_transient(study_case, dataclasses.replace(runup, dof_set="planar"))
    spatial = run_transient(study_case, dataclasses.replace(runup, dof_set="spatial"))
    return planar, spatial


def test_planar_run_equals_spatial_run_in_plane(planar_and_spatial):
    """A spur stage's out-of-plane DOFs are decoupled (PHYSICS.md 7): the planar run's
    in-plane answers equal the spatial run's to 1e-9, with time-varying stiffness on."""
    planar, spatial = planar_and_spatial
    assert planar.attrs["dof_count"] == 18 and spatial.attrs["dof_count"] == 36
    channels = [n for n, v in planar.data_vars.items() if v.dims == ("time",)]
    assert len(channels) == 10
    for name in channels:
        a, b = planar[name].values, spatial[name].values
        scale = max(np.abs(b).max(), 1e-300)
        if name == "planetary_ring_y_acceleration":
            # in phase, equally spaced planets excite no translation: round-off on both
            # sides; compare against the sun's acceleration scale instead
            scale = np.abs(spatial["planetary_sun_theta_z_acceleration"].values).max()
        assert np.abs(a - b).max() <= 1e-9 * scale, name
    speeds = planar.equilibrium_speed.values
    np.testing.assert_allclose(speeds, spatial.equilibrium_speed.values, rtol=0, atol=1e-9 * 540)
    assert float(planar.t_s) == pytest.approx(float(spatial.t_s), rel=1e-9)


def test_constant_stiffness_never_evaluates_the_contact_table(study_case):
    """Counted in the kernel: the predictor evaluates the table once at the start and
    once per step with time-varying stiffness, never at constant stiffness."""
    runup = _short(study_case.scene("runup"))
    steps = runup.transient.steps
    varying = run_transient(study_case, runup)
    constant = run_transient(study_case, dataclasses.replace(runup, effects=()))
    assert varying.attrs["solver_contact_evaluations"] == steps + 1
    assert constant.attrs["solver_contact_evaluations"] == 0
    assert constant.attrs["equivalent_load"] == "linear"
    assert "table never evaluated" in constant.attrs["effects_in_force"]


def test_every_output_records_dof_set_count_and_effects(study_case, planar_and_spatial):
    planar, _ = planar_and_spatial
    for attrs in (planar.attrs, modal_analysis(assemble(study_case)).attrs):
        assert attrs["dof_set"] == "planar"
        assert attrs["dof_count"] == 18 and attrs["dof_count_spatial"] == 36
        for effect in ("time_varying_mesh_stiffness", "tooth_separation", "helical_coupling"):
            assert effect in attrs["effects_in_force"]
    assert "time_varying_mesh_stiffness: on" in planar.attrs["effects_in_force"]
    assert "equivalent_load: predictor" in planar.attrs["effects_in_force"]


def test_open_dof_set_picks_planar_for_spur_and_says_why(study_case):
    """Left open, a spur stage is planar (the smallest exact set); torsional only on request."""
    model = assemble(study_case, Scene("open", analyses=("modal",), formulation="improved"))
    assert model.dof_set == "planar" and "spur" in model.dof_set_reason
    asked = Scene("t", analyses=("modal",), dof_set="torsional")
    assert assemble(study_case, asked).dof_set == "torsional"


def test_helical_coupling_is_kept_by_the_gearbox_pick():
    from pygear import load_case

    gearbox = load_case(CASES / "yang2016_gearbox")
    model = assemble(gearbox, Scene("h", analyses=("modal",), effects=("helical_coupling",)))
    assert model.dof_set == "per-stage"
    assert "helical_coupling: on (parallel)" in modal_analysis(model).attrs["effects_in_force"]


@pytest.mark.parametrize(
    "scene, message",
    [
        (Scene("s", effects=("gyroscopic",)), "scenes.s.effects must be one of"),
        (
            Scene("s", dof_set="torsional", effects=("helical_coupling",)),
            "'helical_coupling' couples in-plane and out-of-plane DOFs",
        ),
        (
            Scene("s", dof_set="planar", effects=("helical_coupling",)),
            "scenes.s.dof_set must be 'spatial' or left open",
        ),
        (
            Scene(
                "s",
                dof_set="torsional",
                effects=("speed_dependent_planet_terms",),
                carrier_speed_rpm=120.0,
            ),
            "which the torsional DOF set drops",
        ),
        (
            Scene("s", effects=("speed_dependent_planet_terms",)),
            "scenes.s.carrier_speed_rpm must be non-zero",
        ),
        (Scene("s", effects=(TV, TV)), "each effect may be listed once"),
    ],
)
def test_contradicting_effects_are_refused(scene, message):
    with pytest.raises(CaseError, match=message.replace("(", r"\(").replace(")", r"\)")):
        scene.validate("scenes.s")


def test_helical_coupling_needs_a_helical_stage():
    with pytest.raises(CaseError, match="'helical_coupling' needs a helical stage"):
        dataclasses.replace(
            case_of(consistent_stage(3)),
            scenes=(Scene("s", effects=("helical_coupling",)),),
        )


def test_cli_refuses_a_bad_tolerance(capsys):
    for bad in ("0", "-1%", "abc"):
        assert main(["accuracy", str(CASES / "yang2016_planetary"), f"--tolerance={bad}"]) == 2
        assert "--tolerance" in capsys.readouterr().err
