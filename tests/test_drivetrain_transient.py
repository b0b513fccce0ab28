"""Transients of a whole drivetrain (pygear.assembly.drivetrain_model): the NREL 5 MW
drivetrain's run-up and emergency stop through the kernel's automatic path.

References, never the run's own output:

* the drivetrain's torsional modes by shift-invert Lanczos on CHOLMOD
  (pygear.analysis.modes.drivetrain_modal, itself checked against the two-inertia closed form
  in tests/test_drivetrain.py): after the generator torque's step the train rings at
  its first torsional frequency;
* the static deflection under the rated torques with inertia relief: started there, the
  train does not swing (started undeflected, it swings by the rated twist);
* Newton's second law for the rigid rotation: a brake acting against the generator's
  rotation slows it, whichever way the parallel stage turns it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pygear import TorqueLaw, load_case
from pygear.analysis.modes.drivetrain_modal import drivetrain_modes
from pygear.analysis.time.transient import run_transient, transient_problem
from pygear.assembly.drivetrain import assemble_drivetrain


@pytest.fixture(scope="module")
def case():
    return load_case("nrel5mw_drivetrain")


def _scene(case, name: str, **changes):
    scene = case.scene(name)
    settings = dataclasses.replace(scene.transient, **changes)
    return dataclasses.replace(scene, transient=settings, analyses=("transient",))


@pytest.fixture(scope="module")
def emergency_stop(case):
    return run_transient(case, case.scene("emergency_stop"))


def _crossing_times(time: np.ndarray, signal: np.ndarray) -> np.ndarray:
    """Upward zero crossings of a signal, linearly interpolated [s]."""
    up = np.nonzero((signal[:-1] < 0) & (signal[1:] >= 0))[0]
    return time[up] - signal[up] * (time[up + 1] - time[up]) / (signal[up + 1] - signal[up])


def test_transient_runs_on_the_whole_drivetrain(case):
    """The transient's model is the drivetrain (shaft nodes and the gearbox block, the
    rotor and the generator named as bodies), and the kernel says which path ran."""
    problem = transient_problem(case, _scene(case, "runup", duration=0.01, mean_window=0.01))
    drivetrain = assemble_drivetrain(case, case.scene("runup"))
    assert problem.model.size == drivetrain.size
    assert problem.model.attributes["drivetrain"] == 1
    assert any(label.startswith("main_shaft_") for label in problem.model.dof_labels)
    assert problem.solver.linear_solver in ("dense_refined", "sparse_cholesky", "banded_cholesky")
    assert problem.solver.linear_solver_reason.startswith("automatic")


def test_emergency_stop_rings_at_the_torsional_mode(case, emergency_stop):
    """After the grid loss (t = 0.5 s) the generator's speed swings about its drift at the
    drivetrain's first elastic torsional frequency.  The swing is measured as the
    difference of the generator's speed (referred to the rotor) and the rotor's, whose
    mean drift cancels; its period from the upward zero crossings after 0.75 s (four to
    five periods) against the modal frequency: within 3 %, which covers the damped
    frequency's shift (sqrt(1 - zeta^2), 0.1 % at zeta = 5 %) and the time-varying mesh
    stiffness's modulation of the mean."""
    modes = drivetrain_modes(assemble_drivetrain(case, case.scene("emergency_stop")), 4)
    elastic = modes.frequencies_hz[modes.frequencies_hz > 0.1]
    first = float(elastic[0])
    speeds = emergency_stop.speed
    time = emergency_stop.time.values
    ratio = float(
        np.median(speeds.sel(member="generator").values[:100])
        / np.median(speeds.sel(member="rotor").values[:100])
    )
    twist_rate = speeds.sel(member="generator").values / ratio - speeds.sel(member="rotor").values
    after = time > 0.75
    swing = twist_rate[after] - np.polyval(
        np.polyfit(time[after], twist_rate[after], 2), time[after]
    )
    crossings = _crossing_times(time[after], swing)
    assert crossings.size >= 4
    period = float(np.median(np.diff(crossings)))
    assert 1.0 / period == pytest.approx(first, rel=0.03)


def test_emergency_stop_reverses_the_mesh_torque(emergency_stop):
    """Rated operation loads every mesh on its drive flank; the torsional swing after
    the grid loss exceeds the mean torque, so the teeth part and the coast flanks carry
    load (the torque reversal of a grid loss).  The run counts mesh-steps in free flight
    and on the coast flank, and the first stage's sun mesh force turns negative."""
    before = emergency_stop.time.values < 0.5
    force = emergency_stop.mesh_force.sel(mesh="stage1.sun-planet1").values
    assert force[before].min() > 0
    assert force[~before].min() < 0
    assert emergency_stop.attrs["solver_coast"] > 0
    assert emergency_stop.attrs["solver_separated"] > 0


def test_started_loaded_the_train_does_not_swing(case):
    """Before the stop both torques are steady.  Started in the static deflection with
    inertia relief, the twist rate (generator referred to the rotor, minus the rotor)
    stays below 2 % of the swing the same start undeflected makes: the loaded start
    holds the rated twist from t = 0 instead of reaching it by a torsional oscillation."""

    def swing(start_loaded: bool) -> float:
        scene = _scene(
            case,
            "emergency_stop",
            duration=0.45,
            mean_window=0.1,
            start_loaded=start_loaded,
        )
        scene = dataclasses.replace(scene, effects=("time_varying_mesh_stiffness",))
        run = run_transient(case, scene)
        speeds = run.speed
        ratio = float(speeds.sel(member="generator")[0] / speeds.sel(member="rotor")[0])
        twist = speeds.sel(member="generator").values / ratio - speeds.sel(member="rotor").values
        return float(np.ptp(twist))

    loaded, undeflected = swing(True), swing(False)
    assert undeflected > 0.05  # rpm: the rated twist reached by swinging
    assert loaded < 0.02 * undeflected


def test_a_brake_slows_the_generator_whichever_way_it_turns(case):
    """The parallel stage turns the generator against the rotor.  A brake (a constant
    load torque, no drive, started in its static deflection so that nothing swings)
    acts against the generator's actual rotation: its speed's magnitude falls, and the
    rotor decelerates at T_brake i / J_eff within 1 %, J_eff the train's inertia
    referred to the rotor (its rigid-body mode's kinetic energy per unit rotor speed
    squared, from the model's matrices, not the run); the 1 % covers the mesh
    stiffness's variation, which the static start takes at its mean."""
    brake = 20_000.0  # N m on the generator
    scene = _scene(
        case,
        "emergency_stop",
        duration=0.4,
        mean_window=0.1,
        start_loaded=True,
        drive=None,
        load=TorqueLaw.constant(brake),
    )
    scene = dataclasses.replace(scene, effects=())
    run = run_transient(case, scene)
    generator = run.speed.sel(member="generator").values
    rotor = run.speed.sel(member="rotor").values
    time = run.time.values
    assert np.polyfit(time, np.abs(generator), 1)[0] < 0
    problem = transient_problem(case, scene)
    from pygear.assembly.dof_rows import dof_row, rigid_rotation

    model = problem.model
    rigid = rigid_rotation(model)
    rotor_speed = float(dof_row(model, "rotor.theta_z") @ rigid)
    generator_speed = float(dof_row(model, "generator.theta_z") @ rigid)
    inertia = float(rigid @ model.mass @ rigid) / rotor_speed**2  # kg m^2 at the rotor
    ratio = abs(generator_speed / rotor_speed)
    expected = brake * ratio / inertia * 30 / math.pi  # rpm/s at the rotor
    slope = np.polyfit(time, rotor, 1)[0]
    assert -slope == pytest.approx(expected, rel=0.01)


def test_modal_below_gives_exactly_the_modes_below(capsys):
    """``pygear modal --below 200Hz`` on the torsional drivetrain: every mode below
    200 Hz and none above, each within 1e-8 of a dense generalized eigensolution of the
    same matrices (a different algorithm: Cholesky reduction and a dense symmetric
    eigensolver); rounding of both is near eps times the largest eigenvalue, far below
    1e-8 of these frequencies."""
    import json

    from pygear.cli import main
    from pygear.linalg import generalized_eigh

    case = load_case("nrel5mw_drivetrain")
    model = assemble_drivetrain(case, dof_set="torsional")
    values = generalized_eigh(
        model.stiffness.toarray(), model.mass.toarray(), eigenvalues_only=True
    )
    dense = np.sqrt(np.clip(values, 0.0, None)) / (2 * math.pi)
    assert (
        main(
            ["modal", "nrel5mw_drivetrain", "--dof-set", "torsional", "--below", "200Hz", "--json"]
        )
        == 0
    )
    found = np.array(json.loads(capsys.readouterr().out)["frequencies_hz"])
    expected = dense[dense < 200.0]
    assert found.size == expected.size >= 3
    np.testing.assert_allclose(found[1:], expected[1:], rtol=1e-8)
    assert abs(found[0]) < 1e-3  # the free rotation


def test_spatial_stop_planet_bearings_carry_the_carrier_torque(case):
    """The spatial emergency stop (144 DOFs): before the stop the three planets'
    tangential bearing forces carry the carrier's torque, 3 F_eta r_c = T_D - J_rotor
    alpha, with the rigid-body deceleration alpha = (T_D - i T_L) / J_eff from the
    model's matrices (its rigid mode's kinetic energy), not from the run; within 0.5 %,
    which covers the mean's ripple at the mesh frequencies over the 0.4 s window and the
    planets' own tangential inertia (m_p r_c alpha, 1e-5 of the force).  After the stop
    the force reverses with the meshes."""
    from pygear.assembly.dof_rows import dof_row, rigid_rotation

    scene = case.scene("emergency_stop_spatial")
    problem = transient_problem(case, scene)
    assert problem.model.dof_set == "spatial" and problem.model.size > 100
    run = run_transient(case, scene, problem=problem)
    model = problem.model
    rigid = rigid_rotation(model)
    rotor = float(dof_row(model, "rotor.theta_z") @ rigid)
    generator = float(dof_row(model, "generator.theta_z") @ rigid)
    inertia = float(rigid @ model.mass @ rigid) / rotor**2
    ratio = abs(generator / rotor)
    module = __import__("pygear.model.case_files", fromlist=["load_case_module"])
    constants = module.load_case_module("nrel5mw_drivetrain")[1]
    drive, load = constants.G.RATED_ROTOR_TORQUE, constants.RATED_GENERATOR_TORQUE
    alpha = (drive - ratio * load) / inertia
    carrier_torque = drive - case.drivetrain.rotor.polar_inertia * alpha
    time = run.time.values
    before = (time > 0.1) & (time < 0.5)
    tangential = run.bearing_force.sel(bearing="stage1.planet1_bearing.eta").values
    stage = case.gearbox.stages[0]
    planets = len(stage.planet_angles)
    carried = planets * tangential[before].mean() * stage.carrier.radius
    assert carried == pytest.approx(carrier_torque, rel=5e-3)
    assert tangential[time > 0.5].min() < 0 < tangential[before].min()


def test_spatial_run_carries_each_shafts_gyroscopics_at_its_speed(case):
    """The spatial stop's kernel holds the drivetrain's gyroscopic matrix (each shaft's
    elements and discs times its speed over the rotor's) and turns it at the rotor's
    own speed in the run: per unit rotor speed each shaft's block is its speed ratio
    (about -96 for the high-speed shaft) times its own G at unit spin."""
    from pygear.assembly.dof_rows import dof_row

    problem = transient_problem(case, case.scene("emergency_stop_spatial"))
    solver, model = problem.solver, problem.model
    arguments = solver.rotor_arguments
    assert arguments["source"] == 2 and arguments["n_entries"] > 0  # the run's rotation
    drivetrain = assemble_drivetrain(case, case.scene("emergency_stop_spatial"))
    ratios = drivetrain.speed_ratios
    assert min(ratios.values()) < -90  # the generator side turns the other way, faster
    # the kernel's entries are G's strictly upper entries, in its own DOF order
    g = drivetrain.gyroscopic.toarray()
    rebuilt = np.zeros_like(g)
    rows = solver.order[arguments["row"][: arguments["n_entries"]] - 1]
    columns = solver.order[arguments["column"][: arguments["n_entries"]] - 1]
    rebuilt[rows, columns] = arguments["value"][: arguments["n_entries"]]
    rebuilt -= rebuilt.T
    np.testing.assert_array_equal(rebuilt, 0.5 * (g - g.T))
    speed = np.zeros(model.size)
    speed[solver.order[arguments["speed_index"] - 1]] = arguments["speed_value"]
    np.testing.assert_array_equal(speed, dof_row(model, "rotor.theta_z"))
    # each shaft's block is its ratio times its G at unit spin of its own
    from pygear.assembly.drivetrain import build_structure

    unit = build_structure(case.drivetrain, dict.fromkeys(ratios, 1.0))[0].assemble()
    checked = 0
    for shaft in case.drivetrain.shafts:
        own = [
            label
            for label in drivetrain.labels[: drivetrain.gearbox_offset]
            if label.startswith(f"{shaft.name}_")
        ]
        here = [drivetrain.labels.index(label) for label in own]
        there = [unit.labels.index(label) for label in own]
        block = unit.gyroscopic.toarray()[np.ix_(there, there)]
        np.testing.assert_allclose(
            g[np.ix_(here, here)], ratios[shaft.name] * block, rtol=1e-12, atol=0
        )
        checked += bool(np.any(block))
    assert checked >= 2


@pytest.mark.parametrize("equivalent_load", ["iterate", "refactor"])
def test_spatial_stop_with_gyroscopics_agrees_on_every_kernel_path(
    case, equivalent_load, monkeypatch
):
    """The spatial stop's first 1000 steps (meshes, tooth separation and the shafts'
    gyroscopics iterated together; refactor mode refactors four times, which the dense
    path follows by its Woodbury update of the operator the gyroscopic share goes
    through): banded, dense and sparse agree to 1e-9 of each channel's largest value,
    what their different rounding (measured 2e-11) carried over the steps allows."""
    scene = case.scene("emergency_stop_spatial")
    settings = dataclasses.replace(
        scene.transient, duration=0.05, mean_window=0.01, equivalent_load=equivalent_load
    )
    scene = dataclasses.replace(scene, transient=settings)
    runs = {}
    from pygear.kernel.newmark_storage import cholmod_available

    paths = ["banded_cholesky", "dense_inverse", "dense_refined"] + [
        "sparse_cholesky"
    ] * cholmod_available()
    for path in paths:
        monkeypatch.setenv("PYGEAR_LINEAR_SOLVER", path)
        problem = transient_problem(case, scene)
        assert problem.solver.linear_solver == path and problem.solver.rotor_arguments
        runs[path] = problem.solver.run(settings.steps, problem.probes).samples
    reference = runs["banded_cholesky"]
    for path, samples in runs.items():
        for row, expected in zip(samples, reference):
            assert abs(row - expected).max() <= 1e-9 * abs(expected).max(), path
