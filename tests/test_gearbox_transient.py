"""Run-up of the seed's gearbox (section 6, Tables 7 and 8; docs/model.md §6.3).

References are derived here from the case's own inputs: kinematic ratios from the
base radii, J_eq from the inertias and those ratios, the work-energy balance from
the equation of motion.  The paper's speeds appear in the README beside ours.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from conftest import rigid_to_elastic_ratio, roundoff_tolerance

from pygear import CaseError, Probe, load_case
from pygear.analysis.signals.channels import channel_names, channel_series
from pygear.analysis.time.transient import run_transient, transient_problem
from pygear.assembly import assemble
from pygear.assembly.dof_rows import dof_row
from pygear.runs.outputs import mesh_frequency

GEARBOX = Path(__file__).resolve().parent.parent / "cases" / "yang2016_gearbox"


@pytest.fixture(scope="module")
def gearbox_case():
    return load_case(GEARBOX)


def _short(case, name: str, duration: float, **changes):
    """The case's run-up scene ``name`` shortened to ``duration`` seconds."""
    scene = case.scene(name)
    changes.setdefault("mean_window", min(scene.transient.mean_window, duration))
    settings = dataclasses.replace(scene.transient, duration=duration, **changes)
    return dataclasses.replace(scene, transient=settings, analyses=("transient",))


@pytest.fixture(scope="module")
def short_runs(gearbox_case) -> dict[str, xr.Dataset]:
    """Both run-ups over 0.6 s (t_s = 0.327 s), speeds averaged over the last 0.2 s."""
    return {
        name: run_transient(gearbox_case, _short(gearbox_case, name, 0.6, mean_window=0.2))
        for name in ("runup", "runup_tv")
    }


def _kinematic_speeds(case, carrier_rpm: float) -> dict[str, float]:
    """Every member's speed from the base radii, rings held (docs/model.md §2)."""
    stage1, stage2, parallel = case.gearbox.stages
    speeds = {}
    carrier = carrier_rpm
    for stage in (stage1, stage2):
        ratio = 1 + stage.ring.base_radius / stage.sun.base_radius
        speeds[f"{stage.name}.carrier"] = carrier
        speeds[f"{stage.name}.sun"] = carrier * ratio
        # improved model: a planet's theta_z is its spin relative to the carrier
        speeds[f"{stage.name}.planet1"] = (
            -carrier * stage.ring.base_radius / (stage.planet.base_radius)
        )
        carrier = carrier * ratio  # rigid link: stage 1's sun turns stage 2's carrier
    speeds["parallel.input_gear"] = carrier
    speeds["parallel.output_gear"] = -carrier * (
        parallel.input_gear.base_radius / parallel.output_gear.base_radius
    )
    return speeds


def _equivalent_inertia(case) -> float:
    """Whole-train inertia reduced to stage 1's carrier (improved model, docs/model.md §3.1)."""
    total, factor = 0.0, 1.0  # factor: (stage carrier speed / input speed)^2
    for stage in case.gearbox.stages[:2]:
        ratio = 1 + stage.ring.base_radius / stage.sun.base_radius
        planet = stage.planet
        spin = stage.ring.base_radius / planet.base_radius
        planets = stage.planets * (
            planet.mass * stage.carrier.radius**2 + planet.polar_inertia * spin**2
        )
        total += factor * (
            stage.carrier.polar_inertia + planets + stage.sun.polar_inertia * ratio**2
        )
        factor *= ratio**2
    parallel = case.gearbox.stages[2]
    gear_ratio = parallel.input_gear.base_radius / parallel.output_gear.base_radius
    total += factor * (
        parallel.input_gear.polar_inertia + parallel.output_gear.polar_inertia * gear_ratio**2
    )
    return total


@pytest.mark.parametrize("name", ["runup", "runup_tv"])
def test_speeds_follow_the_kinematic_ratios(short_runs, gearbox_case, name):
    """Tables 7/8: every carrier, sun, planet and parallel gear on its ratio to 0.1 %."""
    run = short_runs[name]
    speeds = dict(zip(run.body.values.tolist(), run.equilibrium_speed.values.tolist()))
    expected = _kinematic_speeds(gearbox_case, speeds["stage1.carrier"])
    for member, value in expected.items():
        assert speeds[member] == pytest.approx(value, rel=1e-3), member
    # the output turns against the input, and the load still brakes it
    assert speeds["parallel.output_gear"] < 0
    assert float(run.load_torque[-1]) > 0


@pytest.mark.parametrize("name", ["runup", "runup_tv"])
def test_t_s_follows_the_damped_theory(short_runs, gearbox_case, name):
    """t_s = -ln(1 - alpha J_eq w0 / T_D) / alpha to 1 %, J_eq from the inertias."""
    settings = gearbox_case.scene(name).transient
    alpha = gearbox_case.damping.mass_coefficient
    omega_0 = settings.speed_reference_rpm * math.pi / 30
    j_eq = _equivalent_inertia(gearbox_case)
    theory = -math.log(1 - alpha * j_eq * omega_0 / settings.drive.torque) / alpha
    assert float(short_runs[name].t_s) == pytest.approx(theory, rel=0.01)
    assert short_runs[name].attrs["speed_ratio"] == pytest.approx(
        abs(_kinematic_speeds(gearbox_case, 1.0)["parallel.output_gear"]), rel=1e-9
    )


def test_parallel_mesh_carries_the_load_torque(short_runs, gearbox_case):
    """Time-varying stiffness changes the parallel mesh force's ripple, not its mean:
    F cos(beta_b) r_b2 = T_L + alpha I_2 |w_2| + I_2 |dw_2/dt| for the output gear over
    a window (F acts along the helical line of action, tilted by the base helix angle)."""
    run = short_runs["runup_tv"]
    parallel = gearbox_case.gearbox.stages[2]
    inertia = parallel.output_gear.polar_inertia
    window = run.sel(time=slice(float(run.time[-1]) - 0.2, None))
    mesh = window.mesh_force.sel(mesh="parallel.input-output")
    normal_force = float(np.abs(mesh).mean())
    force = normal_force * math.cos(math.radians(parallel.base_helix_angle_deg))
    speed = np.abs(window.speed.sel(member="parallel.output_gear").values) * math.pi / 30
    span = float(window.time[-1] - window.time[0])
    acceleration = (speed[-1] - speed[0]) / span
    torque = float(window.load_torque.mean())
    damping = gearbox_case.damping.mass_coefficient * inertia * float(speed.mean())
    expected = (torque + damping + inertia * acceleration) / parallel.output_gear.base_radius
    assert force == pytest.approx(expected, rel=2e-3)
    ripple = mesh.std()
    assert float(ripple) > 1e-3 * normal_force  # the helical mesh's stiffness does vary


def _state(run, quantity: str, labels: list[str]) -> np.ndarray:
    """The full state's ``quantity`` over (time, DOF) in the model's DOF order: the
    file's translations and rotations (one unit each) put back together."""
    parts = [
        run[f"{kind}_{quantity}"].rename({f"{kind}_dof": "dof"})
        for kind in ("translation", "rotation")
    ]
    return xr.concat(parts, "dof").sel(dof=labels).transpose("time", "dof").values


def test_energy_balance_closes(gearbox_case):
    """Kinetic plus strain energy at the end equals the drive's work minus the load's
    work and the Rayleigh dissipation (constant stiffness), in the discrete form the
    average-acceleration rule satisfies exactly: dE = dq . (f_n + f_n+1)/2 - dq . C v-bar."""
    scene = _short(gearbox_case, "runup", 0.4)
    scene = dataclasses.replace(
        scene,
        transient=dataclasses.replace(
            scene.transient,
            sample_rate=None,
            full_state=True,
            probes=(Probe("drive_torque"), Probe("load_torque")),
        ),
    )
    problem = transient_problem(gearbox_case, scene)
    run = run_transient(gearbox_case, scene, problem=problem)
    model = problem.model
    q, v = (_state(run, quantity, model.dof_labels) for quantity in ("displacement", "velocity"))
    input_row = dof_row(model, problem.input_label)
    output_row = -dof_row(model, problem.output_label)  # the law brakes the reversed output
    force = np.outer(run.drive_torque.values, input_row) - np.outer(
        run.load_torque.values, output_row
    )
    step = np.diff(q, axis=0)
    mean_force = 0.5 * (force[1:] + force[:-1])
    mean_velocity = 0.5 * (v[1:] + v[:-1])
    external = np.einsum("ij,ij->", step, mean_force)
    dissipated = np.einsum("ij,jk,ik->", step, model.damping, mean_velocity)

    def energy(i: int) -> float:
        return 0.5 * v[i] @ model.mass @ v[i] + 0.5 * q[i] @ model.stiffness @ q[i]

    drive_work = np.einsum(
        "ij,ij->",
        step,
        0.5 * np.outer(run.drive_torque.values[1:] + run.drive_torque.values[:-1], input_row),
    )
    assert float(run.t_s) < 0.4 and external < drive_work  # the load did work
    assert dissipated > 0
    balance = energy(-1) - energy(0) - (external - dissipated)
    assert abs(balance) <= 1e-8 * drive_work  # measured: 5e-10


def test_spur_gearbox_is_planar_and_exact(gearbox_case):
    """A spur-only gearbox: the scene picks planar DOFs by itself, and the run gives the
    spatial run's in-plane response (time-varying stiffness) to round-off in each channel."""
    parallel = dataclasses.replace(
        gearbox_case.gearbox.stages[2], base_helix_angle_deg=0.0, overlap_ratio=0.0
    )
    spur = dataclasses.replace(
        gearbox_case,
        gearbox=dataclasses.replace(
            gearbox_case.gearbox, stages=(*gearbox_case.gearbox.stages[:2], parallel)
        ),
    )
    scene = _short(spur, "runup_tv", 0.05, mean_window=0.01)
    planar = transient_problem(spur, scene)
    assert planar.model.dof_set == "planar"
    spatial_scene = dataclasses.replace(scene, dof_set="spatial")
    spatial = transient_problem(spur, spatial_scene)
    assert spatial.model.size > planar.model.size
    runs = [
        run_transient(spur, s, problem=p) for s, p in ((scene, planar), (spatial_scene, spatial))
    ]
    # round-off bound (conftest.roundoff_tolerance): the fastest pair, the parallel one,
    # turns furthest against its deflection
    pair = spur.gearbox.stages[2]
    turned = float(np.abs(runs[1].speed.sel(member="parallel.input_gear")).max()) * np.pi / 30
    turned *= 0.05
    force = runs[1].mesh_force.sel(mesh="parallel.input-output").values
    force = float(np.sqrt(np.mean(force**2)))
    tolerance = roundoff_tolerance(
        runs[1].attrs["steps"],
        rigid_to_elastic_ratio(pair.input_gear.base_radius, turned, force, pair.mesh.stiffness),
    )
    assert tolerance < 1e-5  # still far below any coupling's effect
    for name in channel_names(runs[0]):
        values, reference = (channel_series(run, name).values for run in runs)
        scale = np.abs(reference).max()
        assert np.abs(values - reference).max() <= tolerance * scale, name


def test_mesh_frequencies_of_every_stage(short_runs, gearbox_case):
    """Z_r n_c / 60 per planetary stage, Z_1 n_1 / 60 for the parallel pair."""
    run = short_runs["runup"]
    frequencies = mesh_frequency(gearbox_case, run)
    speeds = dict(zip(run.body.values.tolist(), run.equilibrium_speed.values.tolist()))
    stage1, stage2, parallel = gearbox_case.gearbox.stages
    assert frequencies["stage1"] == pytest.approx(
        stage1.ring.teeth * speeds["stage1.carrier"] / 60, rel=1e-3
    )
    assert frequencies["stage2"] == pytest.approx(
        stage2.ring.teeth * speeds["stage2.carrier"] / 60, rel=1e-3
    )
    assert frequencies["parallel"] == pytest.approx(
        parallel.input_gear.teeth * speeds["parallel.input_gear"] / 60, rel=1e-9
    )


def test_parallel_pair_without_teeth_is_refused(gearbox_case):
    """Time-varying stiffness needs the pair's tooth numbers, asked for by path."""
    parallel = gearbox_case.gearbox.stages[2]
    toothless = dataclasses.replace(
        parallel, input_gear=dataclasses.replace(parallel.input_gear, teeth=None)
    )
    case = dataclasses.replace(
        gearbox_case,
        gearbox=dataclasses.replace(
            gearbox_case.gearbox, stages=(*gearbox_case.gearbox.stages[:2], toothless)
        ),
    )
    with pytest.raises(CaseError, match=r"parallel\.input_gear\.teeth must be a whole number"):
        transient_problem(case, _short(case, "runup_tv", 0.01))
    assert assemble(case, None).size == 50  # the constant-stiffness model needs none
