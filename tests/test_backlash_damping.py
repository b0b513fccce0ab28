"""The mesh damper under tooth separation: it acts only while a flank is in contact.

C holds each mesh's damper c b b^T (beta kbar of Rayleigh damping); the kernel takes it
out while the flanks are apart (fortran/newmark.f90).  Every reference is derived here,
never taken from a run:

* in free flight no force acts between two free bodies, so their relative speed stays
  what it was when they parted;
* a contact of the linear spring-damper k, c on the reduced mass mu lasts half a damped
  period and returns the speed times exp(-pi zeta / sqrt(1 - zeta^2));
* the average-acceleration rule's discrete energy identity with the damper's
  trapezoidal work counted only where the flanks touch;
* the mesh force channel is k delta + c delta' from the displacement and velocity
  channels while the flanks touch, 0 across the gap.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from test_backlash import GAP, STIFFNESS, piecewise_mesh_force, probe, spans

from pygear.analysis.time.transient import run_transient
from pygear.kernel.newmark import BandedNewmark, KernelProbe, LawArrays, MeshTerms
from pygear.kernel.sparse_cholesky import sparse_cholesky_available

ZETA = 0.1  # damping ratio of the contact on the reduced mass 1/2 kg
EPS = np.finfo(float).eps


def damped_pair(
    masses, time_step, damping, *, mode="iterate", drive=None, tolerance=1e-8, solver="auto"
):
    """Two bodies on a line joined by one mesh with a damper c along delta = x1 - x2."""
    b = np.array([[1.0, -1.0]])
    meshes = MeshTerms(
        deflection=b,
        mean_stiffness=np.array([STIFFNESS]),
        contact_sign=np.array([1]),
        angle=np.zeros((1, 2)),
        separation=True,
        names=["mesh"],
        backlash=[GAP],
        damping=[damping],
    )
    return BandedNewmark(
        np.diag(masses),
        damping * b.T @ b,
        STIFFNESS * b.T @ b,
        time_step,
        meshes=meshes,
        equivalent_load=mode,
        tolerance=tolerance,
        drive=drive,
        input_weights=np.array([1.0, 0.0]),
        linear_solver=solver,
    )


def touching(delta: np.ndarray) -> np.ndarray:
    """A flank in contact (module flank_contact: free for -b <= delta <= 0)."""
    return (delta > 0) | (delta < -GAP)


# --- free flight and one damped contact ----------------------------------------------------


@pytest.mark.parametrize("mode", ["iterate", "refactor", "predictor"])
def test_free_flight_keeps_the_speed_and_a_contact_restitutes_it(mode):
    """Parting at v from the drive flank, the bodies cross the gap at exactly v (no
    force acts between them), stay on the coast flank for half a damped period and
    leave it at e v, e = exp(-pi zeta / sqrt(1 - zeta^2)), which they keep across the
    gap.  A damper across the open gap would slow the flight by exp(-c t / mu): 5 %
    over the first one.

    Tolerances: the flights are force-free, so the speed is kept to the rounding of
    v + dt a with a = 0 (a few eps).  The contact starts and ends between steps; in
    the steps that hold its two ends the trapezoidal rule misplaces the damper's
    jump c v by up to a step each, and the damper may engage a step late (the step
    that enters contact may have no end state with the damper on, fortran/newmark.f90):
    at most 3 c v dt of impulse, 3 c dt / mu of v.  The average-acceleration rule's
    own error on the damped oscillation over the contact is (omega dt)^2 / 12 relative
    (2e-7 here)."""
    speed, dt, mu = 0.5, 1e-6, 0.5
    damping = 2 * ZETA * math.sqrt(STIFFNESS * mu)
    solver = damped_pair([1.0, 1.0], dt, damping, mode=mode)
    probes = [
        probe("x1", "displacement", 2, 0),
        probe("x2", "displacement", 2, 1),
        KernelProbe("speed", "velocity", np.array([1.0, -1.0])),
        KernelProbe("force", "mesh_force", mesh=0),
    ]
    result = solver.run(4000, probes, q0=np.zeros(2), v0=np.array([-speed / 2, speed / 2]))
    x1, x2, relative_speed, force = result.samples
    delta = x1 - x2
    free = spans(~touching(delta))
    coast = spans(delta < -GAP)
    assert len(coast) == 1 and len(free) == 2
    # the first flight: every sample after the start, up to the last one inside the gap
    first = relative_speed[1 : free[0][1] + 1]
    np.testing.assert_allclose(first, -speed, rtol=0, atol=8 * EPS * speed)
    restitution = math.exp(-math.pi * ZETA / math.sqrt(1 - ZETA**2))
    second = relative_speed[free[1][0] + 1 : free[1][1] + 1]
    assert second.size > 10
    np.testing.assert_allclose(second, second[0], rtol=0, atol=8 * EPS * speed)
    assert second[0] == pytest.approx(restitution * speed, rel=3 * damping * dt / mu + 1e-6)
    # the contact lasts half a damped period (to a step at either end)
    omega = math.sqrt(STIFFNESS / mu)
    half_period = math.pi / (omega * math.sqrt(1 - ZETA**2))
    assert abs((coast[0][1] - coast[0][0] + 1) * dt - half_period) <= 2 * dt
    # no force across the gap: exactly zero at every free sample
    assert np.all(force[~touching(delta)] == 0.0)


def test_a_step_without_a_consistent_damper_state_engages_it_a_step_late():
    """Closing at v on a gap g with g < v dt < g (mu + c dt / 2) / (mu + c dt / 4), the
    step that reaches the flank has no end state whose damper matches its flank.  For
    the relative coordinate with a0 = 0 the average-acceleration rule gives, with the
    damper on, mu d + k dt^2 (d - g) / 4 + c dt d / 2 = mu dt v + c dt v / 4 for the
    step's travel d, which stays short of g: the teeth end apart, where the damper is
    off; with it off they end pressed in.  The kernel then keeps the damper off for
    that step: the teeth end pressed in by p = mu (v dt - g) / (mu + k dt^2 / 4) (the
    same rule with the spring alone) and the channel reports k p, the spring's force;
    from the next step on the damper acts (k delta + c delta').

    Tolerance: p and the channel's k p round at eps of v dt and g before they cancel
    (v dt - g is a tenth of them), 64 eps with margin; the next step's force to the
    same round-off of its terms."""
    speed, dt, mu = 0.5, 1e-6, 0.5
    damping = mu / dt  # c dt / mu = 1: the window is g < v dt < 1.2 g
    gap_left = speed * dt / 1.1
    solver = damped_pair([1.0, 1.0], dt, damping)
    probes = [
        probe("x1", "displacement", 2, 0),
        probe("x2", "displacement", 2, 1),
        KernelProbe("speed", "velocity", np.array([1.0, -1.0])),
        KernelProbe("force", "mesh_force", mesh=0),
    ]
    result = solver.run(
        5, probes,
        q0=np.array([-gap_left / 2, gap_left / 2]), v0=np.array([speed / 2, -speed / 2]),
    )  # fmt: skip
    x1, x2, rate, force = result.samples
    assert force[0] == 0.0  # starts apart
    pressed = mu * (speed * dt - gap_left) / (mu + STIFFNESS * dt**2 / 4)
    assert x1[1] - x2[1] == pytest.approx(pressed, rel=64 * EPS * speed * dt / pressed)
    assert force[1] == pytest.approx(STIFFNESS * pressed, rel=64 * EPS * speed * dt / pressed)
    delta = x1[2] - x2[2]
    assert delta > 0
    expected = STIFFNESS * delta + damping * rate[2]
    assert force[2] == pytest.approx(expected, abs=16 * EPS * damping * abs(speed))


# --- the mesh force channel includes the damper ------------------------------------------------


def reversal_run(damping, *, tolerance=1e-10, solver="auto"):
    """The two-body torque reversal of test_backlash, with a mesh damper."""
    masses, dt = (2.0, 1.0), 1e-6
    force = 100.0  # N; static drive-flank deflection F m2 / (m1 + m2) / k = 33 um
    drive = LawArrays(
        "table", times=(0.0, 2e-3, 6e-3, 7e-3, 1.0), torques=(0.0, force, force, -force, -force)
    )
    solver = damped_pair(masses, dt, damping, drive=drive, tolerance=tolerance, solver=solver)
    probes = [
        probe("x1", "displacement", 2, 0),
        probe("x2", "displacement", 2, 1),
        probe("v1", "velocity", 2, 0),
        probe("v2", "velocity", 2, 1),
        KernelProbe("drive", "drive_torque"),
        KernelProbe("force", "mesh_force", mesh=0),
    ]
    return masses, dt, solver.run(40000, probes)


# c small enough that the bodies rattle on the coast flank (3 % of critical)
REVERSAL_DAMPING = 2 * 0.03 * math.sqrt(STIFFNESS * 2.0 / 3.0)


def test_mesh_force_channel_is_spring_plus_damper_in_contact_and_zero_across_the_gap():
    """The reported mesh force is k delta + c delta' (drive flank) and k (delta + b) +
    c delta' (coast flank), from the displacement and velocity channels, and exactly 0
    while the flanks are apart.

    Tolerance: the channels and the kernel's force round the same sums differently, by
    a few eps of the terms (k |x|, c |v|) before they cancel.  Where the teeth touch
    within a step the damper may engage a step late (fortran/newmark.f90); such a
    sample reports the spring's force alone, and there is at most one per impact."""
    damping = REVERSAL_DAMPING
    _, _, result = reversal_run(damping)
    x1, x2, v1, v2, _, force = result.samples
    delta, rate = x1 - x2, v1 - v2
    contact = touching(delta)
    impacts = spans(delta < -GAP)
    assert len(impacts) >= 3  # the coast flank is struck again and again
    assert np.all(force[~contact] == 0.0)
    assert force.min() < 0
    spring = STIFFNESS * np.where(delta > 0, delta, delta + GAP)
    expected = spring + damping * rate
    size = STIFFNESS * (np.abs(x1) + np.abs(x2) + GAP) + damping * (np.abs(v1) + np.abs(v2))
    exact = np.abs(force - expected) <= 16 * EPS * size
    late = np.abs(force - spring) <= 16 * EPS * size
    assert np.all(exact[contact] | late[contact])
    entries = [first for first, _ in spans(contact)]
    assert np.count_nonzero(contact & ~exact) <= len(entries)
    assert np.all(np.isin(np.nonzero(contact & ~exact)[0], entries))


# --- energy across damped impacts ---------------------------------------------------------------


def damped_energy_residual(masses, damping, x, v, drive):
    """Per-step residual of the average-acceleration energy identity with the mesh damper,
    its scale, the damper's trapezoidal work per step and where it engages late.

    As in test_backlash.energy_identity_residual, with M a = F - f(q) - f_d at both ends
    the kinetic energy grows by the trapezoidal work of the load less that of the mesh
    forces; the damper's force f_d = c delta' (0 while the flanks are apart) does the
    work (d1 - d0)(f_d0 + f_d1)/2 = dt (r0 + r1)(c0 r0 + c1 r1)/4 >= 0 when c0 = c1, the
    trapezoidal rule's integral of c r^2 over the step."""
    kinetic = 0.5 * (masses[0] * v[0] ** 2 + masses[1] * v[1] ** 2)
    delta, rate = x[0] - x[1], v[0] - v[1]
    force = piecewise_mesh_force(delta, GAP)
    damper = np.where(touching(delta), damping * rate, 0.0)
    mesh_work = np.diff(delta) * 0.5 * (force[1:] + force[:-1])
    dissipated = np.diff(delta) * 0.5 * (damper[1:] + damper[:-1])
    load_work = np.diff(x[0]) * 0.5 * (drive[1:] + drive[:-1])
    residual = np.diff(kinetic) + mesh_work + dissipated - load_work
    size = np.abs(x[:, 1:]) + np.abs(x[:, :-1])
    scale = (
        kinetic[1:] + kinetic[:-1]
        + (size[0] + size[1]) * 0.5 * (np.abs(force[1:]) + np.abs(force[:-1]))
        + (size[0] + size[1]) * 0.5 * (np.abs(damper[1:]) + np.abs(damper[:-1]))
        + size[0] * 0.5 * (np.abs(drive[1:]) + np.abs(drive[:-1]))
    )  # fmt: skip
    late = late_damper_work(np.diff(delta), touching(delta), damper)
    return residual, scale, dissipated, late


def late_damper_work(step, contact, damper):
    """The damper work a step may lack where the damper engaged a step late: a step that
    ends on a flank it started off may end with the damper off (fortran/newmark.f90), so
    neither that step's end force nor the next step's start force did work.

    step, contact and damper are (steps) and (samples) arrays, or (steps, meshes) and
    (samples, meshes) ones: deflection changes, flanks touching and damper forces."""
    entering = contact[1:] & ~contact[:-1]
    at_end = np.where(entering, np.abs(step) * 0.5 * np.abs(damper[1:]), 0.0)
    entered = np.zeros_like(entering)
    entered[1:] = entering[:-1]
    at_start = np.where(entered, np.abs(step) * 0.5 * np.abs(damper[:-1]), 0.0)
    late = at_end + at_start
    return late if late.ndim == 1 else late.sum(axis=1)


SOLVERS = [
    "banded_cholesky",
    "dense_inverse",
    "dense_refined",
    pytest.param(
        "sparse_cholesky",
        marks=pytest.mark.skipif(
            not sparse_cholesky_available(), reason="this build has no CHOLMOD"
        ),
    ),
]


@pytest.mark.parametrize("solver", SOLVERS)
def test_damped_impacts_keep_the_newmark_energy_identity(solver):
    """Kinetic + potential + dissipated - input work stays constant through the
    reversal's impacts with the mesh damper on, step by step and in total; the
    dissipation is counted only over the contact intervals (and is positive there).

    Tolerances per step: the iteration's lag, tolerance x k max|delta| |d1 - d0| of work
    (the convergence test, as in test_backlash); round-off, 10 eps of the size of each
    term before it cancels; and in a step that enters contact, and the step after, the
    damper's work at that state, |d1 - d0| c |r| / 2, which a damper engaging a step
    late (fortran/newmark.f90) does not do.  The total's tolerance is the sum of the
    steps'.  The damper lives in the lagged load, so each of the kernel's linear solvers
    (band, dense inverse, CHOLMOD) must close the identity alike."""
    damping, tolerance = REVERSAL_DAMPING, 1e-10
    masses, _, result = reversal_run(damping, tolerance=tolerance, solver=solver)
    x, v, drive = result.samples[0:2], result.samples[2:4], result.samples[4]
    residual, scale, dissipated, late = damped_energy_residual(masses, damping, x, v, drive)
    delta = x[0] - x[1]
    lag = tolerance * STIFFNESS * np.abs(delta).max() * np.abs(np.diff(delta))
    bound = lag + 10 * EPS * scale + late
    assert np.all(np.abs(residual) <= bound)
    assert abs(residual.sum()) <= bound.sum()
    # the damper dissipates (trapezoid of c r^2 >= 0 where it acts at both ends) and
    # only in contact: nothing in the steps that start and end apart
    both = touching(delta[1:]) & touching(delta[:-1])
    neither = ~touching(delta[1:]) & ~touching(delta[:-1])
    assert np.all(dissipated[both] >= 0)
    assert np.all(dissipated[neither] == 0)
    assert dissipated.sum() > 0.01 * np.abs(np.diff(delta) * drive[1:]).sum()
    assert len(spans(delta < -GAP)) >= 3


# --- the gearbox: the torque-reversal scene with damping ------------------------------------------

SUN_MESH = "planetary.sun-planet1"


@pytest.mark.parametrize(
    "stiffness, beta, mode",
    [
        (1e10, None, "refactor"),  # NREL-like mesh stiffness, the case's beta
        (None, 2e-5, "iterate"),  # the case's mesh stiffness, strong damping
    ],
)
def test_torque_reversal_scene_reaches_the_coast_flank_with_damping(
    study_case, stiffness, beta, mode
):
    """The case's torque_reversal scene with Rayleigh damping on: after the drive
    reverses the sun's teeth cross the backlash and strike the coast flank (negative
    mesh force, coast steps counted), and while their deflection lies inside the gap
    the mesh force is exactly 0 (no damper force across it).  Before the damper
    followed the contact, both settings gave no coast step and a minimum force of 0.

    The open gap is taken from the deflection channel a margin of 1e-6 of the gap away
    from either flank: the channel and the kernel's force round b . q alike, but the
    channel gets the rigid rotation of a rebased run added back (rounded at eps of the
    rotation, far below 1e-6 of a 0.09 mm gap)."""
    scene = study_case.scene("torque_reversal")
    parameters = dict(scene.parameters)
    if stiffness is not None:
        parameters["planetary.sun_mesh.stiffness"] = stiffness
        parameters["planetary.ring_mesh.stiffness"] = stiffness
    if beta is not None:
        parameters["damping.stiffness_coefficient"] = beta
    transient = dataclasses.replace(scene.transient, equivalent_load=mode)
    scene = dataclasses.replace(scene, parameters=parameters, transient=transient)
    case = study_case.for_scene(scene)
    assert case.damping.stiffness_coefficient > 0
    run = run_transient(case, scene)
    assert run.attrs["solver_coast"] > 0
    force = run.mesh_force.sel(mesh=SUN_MESH).values
    deflection = run.mesh_deflection.sel(mesh=SUN_MESH).values
    assert force.min() < 0
    assert run.time.values[np.argmax(force < 0)] > 0.02  # only after the reversal
    # the drive flank's side: where the full drive torque holds the teeth before it reverses
    driven = (run.time.values > 0.01) & (run.time.values < 0.02)
    sign = np.sign(np.median(deflection[driven]))
    mesh = case.gearbox.stages[0].sun_mesh
    gap = mesh.backlash * math.cos(mesh.pressure_angle)
    compression = sign * deflection
    margin = 1e-6 * gap
    open_gap = (compression < -margin) & (compression > -gap + margin)
    assert open_gap.sum() > 10
    assert np.all(force[open_gap] == 0.0)


def test_gearbox_energy_identity_holds_through_damped_impacts(study_case):
    """The torque_reversal scene (constant mesh stiffness, tooth separation, the case's
    Rayleigh damping) keeps the average-acceleration energy identity step by step over
    the whole state: the kinetic energy grows by the trapezoidal work of the drive less
    that of the elastic and damping forces, with K0 and C split into the meshes' springs
    and dampers (kbar b b^T, c b b^T, each acting only while its flanks touch, written
    out here from the backlash) and the rest (bearings, alpha M).  This extends the
    linear balance of test_gearbox_transient.test_energy_balance_closes to impacts.

    Tolerances per step: the iteration's lag, tolerance x max kbar |delta| times the
    meshes' |d1 - d0| (the convergence test); round-off, 4 n eps of the size of every
    product before it cancels (a matrix-vector product and a dot product of length n
    each round by at most n eps of their absolute terms), with the positions' size, as
    the displacement channels carry the rigid rotation; and the late damper's work at
    an entry state (fortran/newmark.f90)."""
    from pygear.analysis.time.transient import transient_problem
    from pygear.assembly.dof_rows import dof_row
    from pygear.model.transient_settings import Probe

    scene = study_case.scene("torque_reversal")
    transient = dataclasses.replace(
        scene.transient, full_state=True, sample_rate=None, probes=(Probe("drive_torque"),)
    )
    scene = dataclasses.replace(scene, effects=("tooth_separation",), transient=transient)
    case = study_case.for_scene(scene)
    problem = transient_problem(case, scene)
    run = run_transient(case, scene, problem=problem)
    assert run.attrs["solver_coast"] > 0
    model = problem.model
    q = full_state(run, "displacement", model.dof_labels)
    v = full_state(run, "velocity", model.dof_labels)
    b = np.array([mesh.deflection for mesh in model.meshes])
    stiffness = np.array([mesh.mean_stiffness for mesh in model.meshes])
    damping = np.array([mesh.damping for mesh in model.meshes])
    assert np.all(damping == case.damping.stiffness_coefficient * stiffness)
    assert np.all(damping > 0)
    stage = case.gearbox.stages[0]
    gap = np.array([
        (stage.sun_mesh if mesh.name.startswith("sun") else stage.ring_mesh).backlash
        * math.cos(stage.sun_mesh.pressure_angle)
        for mesh in model.meshes
    ])  # fmt: skip
    sign = problem.contact_sign
    other_stiffness = model.stiffness - (b.T * stiffness) @ b
    other_damping = model.damping - (b.T * damping) @ b

    delta, rate = q @ b.T, v @ b.T
    compression = sign * delta
    contact = (compression > 0) | (compression < -gap)
    spring = np.where(compression < -gap, stiffness * (delta + sign * gap), stiffness * delta)
    spring = np.where(contact, spring, 0.0)
    damper = np.where(contact, damping * rate, 0.0)
    drive = np.outer(
        run.drive_torque.values, problem.drive_sign * dof_row(model, problem.input_label)
    )

    def mean(x):
        return 0.5 * (x[1:] + x[:-1])

    step, step_delta = np.diff(q, axis=0), np.diff(delta, axis=0)
    kinetic = 0.5 * np.einsum("ti,ij,tj->t", v, model.mass, v)
    residual = (
        np.diff(kinetic)
        + np.einsum("ti,ti->t", step, mean(q @ other_stiffness.T))
        + np.einsum("ti,ti->t", step, mean(v @ other_damping.T))
        + (step_delta * mean(spring + damper)).sum(axis=1)
        - np.einsum("ti,ti->t", step, mean(drive))
    )
    size = np.abs(q[1:]) + np.abs(q[:-1])
    scale = (
        2 * mean(kinetic)
        + np.einsum("ti,ti->t", size, mean(np.abs(q) @ np.abs(other_stiffness).T))
        + np.einsum("ti,ti->t", size, mean(np.abs(v) @ np.abs(other_damping).T))
        + (size @ np.abs(b.T) * mean(np.abs(spring) + np.abs(damper))).sum(axis=1)
        + np.einsum("ti,ti->t", size, mean(np.abs(drive)))
    )  # fmt: skip
    lag = (
        problem.settings.tolerance
        * (stiffness * np.abs(delta).max(axis=0)).max()
        * np.abs(step_delta).sum(axis=1)
    )
    late = late_damper_work(step_delta, contact, damper)
    bound = lag + 4 * q.shape[1] * EPS * scale + late
    assert np.all(np.abs(residual) <= bound)
    dissipated = (step_delta * mean(damper)).sum()
    assert dissipated > 0


def full_state(run, quantity: str, labels: list[str]) -> np.ndarray:
    """The full state's ``quantity`` over (time, DOF) in the model's DOF order."""
    import xarray as xr

    parts = [
        run[f"{kind}_{quantity}"].rename({f"{kind}_dof": "dof"})
        for kind in ("translation", "rotation")
    ]
    return xr.concat(parts, "dof").sel(dof=labels).transpose("time", "dof").values
