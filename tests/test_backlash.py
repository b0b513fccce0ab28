"""Backlash and the coast flank under tooth separation (fortran/flank_contact.f90).

Every reference is derived here, never taken from a run:

* free flight across the gap b at a constant relative speed v lasts b / v, an undamped
  contact of the reduced mass mu lasts pi sqrt(mu / k) and returns the speed;
* the average-acceleration rule's discrete energy identity (derived in
  :func:`energy_identity_residual`) with the piecewise force law written out here;
* a gear pulled across the gap by a constant force F meets the coast flank with the
  work F (b + p) = k p^2 / 2 stored in a penetration p, and rests at b + F / k;
* the parabola law's closed form gives the coast flank's stiffness at its phase.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from conftest import rigid_to_elastic_ratio, roundoff_tolerance, single_mesh_table

from pygear import CaseError
from pygear.analysis.time.transient import run_transient
from pygear.kernel.newmark import BandedNewmark, KernelProbe, LawArrays, MeshTerms

STIFFNESS = 1e6  # N/m
GAP = 1e-4  # m
SUN_MESH, RING_MESH = "planetary.sun-planet1", "planetary.ring-planet1"  # run-file labels


def probe(name: str, kind: str, n: int, dof: int) -> KernelProbe:
    """A displacement, velocity or acceleration probe of one DOF."""
    return KernelProbe(name, kind, np.eye(n)[dof])


def two_body_solver(masses, time_step, *, backlash=GAP, mode="iterate", drive=None,
                    tolerance=1e-8) -> BandedNewmark:  # fmt: skip
    """Two bodies on a line joined by one mesh, delta = x1 - x2, pressed when delta > 0."""
    meshes = MeshTerms(
        deflection=np.array([[1.0, -1.0]]),
        mean_stiffness=np.array([STIFFNESS]),
        contact_sign=np.array([1]),
        angle=np.zeros((1, 2)),
        separation=True,
        names=["mesh"],
        backlash=None if backlash is None else [backlash],
    )
    return BandedNewmark(
        np.diag(masses),
        np.zeros((2, 2)),
        STIFFNESS * np.array([[1.0, -1.0], [-1.0, 1.0]]),
        time_step,
        meshes=meshes,
        equivalent_load=mode,
        tolerance=tolerance,
        drive=drive,
        input_weights=np.array([1.0, 0.0]),
    )


def spans(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) sample of every run of True in mask."""
    edges = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
    return list(zip(np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0] - 1))


# --- free flight and an elastic impact -------------------------------------------------------


@pytest.mark.parametrize("mode", ["iterate", "refactor", "predictor"])
def test_free_flight_lasts_gap_over_speed(mode):
    """Released on the drive flank with the bodies parting at v, the mesh is free for
    b / v, on the coast flank for pi sqrt(mu / k), free again for b / v (elastic: the
    speed comes back), then back on the drive flank; each to the time step."""
    speed, dt = 0.5, 1e-6
    solver = two_body_solver([1.0, 1.0], dt, mode=mode)
    probes = [
        KernelProbe("force", "mesh_force", mesh=0),
        KernelProbe("speed", "velocity", np.array([1.0, -1.0])),
    ]
    result = solver.run(3500, probes, q0=np.zeros(2), v0=np.array([-speed / 2, speed / 2]))
    force, relative_speed = result.samples
    flights = spans(force == 0)
    coast = spans(force < 0)
    assert len(flights) == 2 and len(coast) == 1
    flight = GAP / speed
    contact = math.pi * math.sqrt(0.5 / STIFFNESS)  # reduced mass 1/2 kg
    # sample i is the state at i dt: a span of free samples (a, b) lasted between
    # (b - a) dt and (b - a + 2) dt; the first starts on the flank at t = 0
    assert abs((flights[0][1] + 1) * dt - flight) <= dt
    assert abs((flights[1][1] - flights[1][0] + 1) * dt - flight) <= dt
    assert abs((coast[0][1] - coast[0][0] + 1) * dt - contact) <= 2 * dt
    assert flights[1][1] < force.size - 1 and force[-1] > 0  # back on the drive flank
    assert result.counters["coast"] == coast[0][1] - coast[0][0] + 1
    # the contact returns the relative speed it took (energy of the linear phases kept)
    back = relative_speed[flights[1][0] : flights[1][1] + 1]
    np.testing.assert_allclose(back, speed, rtol=1e-4)


# --- energy across impacts -------------------------------------------------------------------


def piecewise_mesh_force(delta: np.ndarray, backlash: float) -> np.ndarray:
    """Force along delta of a mesh of constant stiffness: drive flank for delta > 0, free
    inside the gap, coast flank beyond it."""
    force = np.where(delta > 0, STIFFNESS * delta, 0.0)
    return np.where(delta < -backlash, STIFFNESS * (delta + backlash), force)


def energy_identity_residual(masses, x, v, drive) -> tuple[np.ndarray, np.ndarray]:
    """Per-step residual of the average-acceleration energy identity, and its scale.

    With q1 - q0 = dt (v0 + v1)/2 and v1 - v0 = dt (a0 + a1)/2 (beta = 1/4, gamma = 1/2),
    (v1 - v0) M (v1 + v0)/2 = (q1 - q0) M (a0 + a1)/2 exactly; with M a = F - f(q) at
    both ends (no damping) the kinetic energy grows by the trapezoidal work of the load F
    less that of the mesh force f:  dT + (d1 - d0)(f0 + f1)/2 - (x1 - x0)(F0 + F1)/2 = 0.
    """
    kinetic = 0.5 * (masses[0] * v[0] ** 2 + masses[1] * v[1] ** 2)
    delta = x[0] - x[1]
    force = piecewise_mesh_force(delta, GAP)
    mesh_work = np.diff(delta) * 0.5 * (force[1:] + force[:-1])
    load_work = np.diff(x[0]) * 0.5 * (drive[1:] + drive[:-1])
    residual = np.diff(kinetic) + mesh_work - load_work
    # every difference is rounded at the size of what it is taken of: the kinetic
    # energies, and the positions (delta = x1 - x2 and dx1 carry eps |x| each)
    size = np.abs(x[:, 1:]) + np.abs(x[:, :-1])
    scale = (
        kinetic[1:] + kinetic[:-1]
        + (size[0] + size[1]) * 0.5 * (np.abs(force[1:]) + np.abs(force[:-1]))
        + size[0] * 0.5 * (np.abs(drive[1:]) + np.abs(drive[:-1]))
    )  # fmt: skip
    return residual, scale


def test_torque_reversal_keeps_the_newmark_energy_identity():
    """A drive that reverses sends the bodies across the gap and rattles them on the coast
    flank (undamped: many impacts).  Every step closes the discrete energy identity with
    the piecewise force written out in this test.

    What it may leave open: the step's acceleration is solved with the lagged mesh load
    of the last iterate, which differs from the accepted state's by at most tolerance x
    k max|delta| (the convergence test); per step that is at most tolerance k max|delta|
    |d1 - d0| of work.  Round-off adds eps of the size of each term before it cancels
    (kinetic energies, positions times forces; 10 eps with margin)."""
    masses, dt, tolerance = (2.0, 1.0), 1e-6, 1e-10
    force = 100.0  # N; static drive-flank deflection F m2 / (m1 + m2) / k = 33 um
    drive = LawArrays(
        "table", times=(0.0, 2e-3, 6e-3, 7e-3, 1.0), torques=(0.0, force, force, -force, -force)
    )
    solver = two_body_solver(masses, dt, drive=drive, tolerance=tolerance)
    probes = [
        probe("x1", "displacement", 2, 0),
        probe("x2", "displacement", 2, 1),
        probe("v1", "velocity", 2, 0),
        probe("v2", "velocity", 2, 1),
        KernelProbe("drive", "drive_torque"),
        KernelProbe("force", "mesh_force", mesh=0),
    ]
    result = solver.run(60000, probes)
    x, v = result.samples[0:2], result.samples[2:4]
    impacts = len(spans(result.samples[5] < 0))
    assert impacts >= 5  # the coast flank is struck again and again
    residual, scale = energy_identity_residual(masses, x, v, result.samples[4])
    delta = x[0] - x[1]
    lag = tolerance * STIFFNESS * np.abs(delta).max() * np.abs(np.diff(delta))
    assert np.all(np.abs(residual) <= lag + 10 * np.finfo(float).eps * scale)


# --- the coast flank bounds the deflection ---------------------------------------------------


def gear_on_mesh(time_step, pull, *, backlash=GAP, damping=0.0, mass=1.0) -> BandedNewmark:
    """One gear against a fixed one: delta = x, the drive flank pressed for x > 0, a
    constant force -pull on the gear (towards the coast flank)."""
    meshes = MeshTerms(
        deflection=np.ones((1, 1)),
        mean_stiffness=np.array([STIFFNESS]),
        contact_sign=np.ones(1, dtype=int),
        angle=np.zeros((1, 1)),
        separation=True,
        names=["mesh"],
        backlash=None if backlash is None else [backlash],
    )
    return BandedNewmark(
        [[mass]], [[damping]], [[STIFFNESS]], time_step, meshes=meshes,
        equivalent_load="iterate", drive=LawArrays("constant", (-pull, 0, 0, 0)),
        input_weights=np.ones(1),
    )  # fmt: skip


def test_coast_flank_stops_the_teeth_at_backlash_plus_contact_deflection():
    """Pulled from the drive flank at rest by F, the gear crosses the gap and presses the
    coast flank in by p with F (b + p) = k p^2 / 2 (no damping), so |delta| peaks at
    b + p; with damping it rests at b + F / k, the coast flank's static deflection.
    Without a coast flank (infinite backlash, the law before backlash) it flies on.

    Tolerances: the peak falls between samples, (omega dt)^2 / 8 = 1.3e-7 of p, and the
    step that enters contact adds k (v dt)^2 / 2 = 5e-9 J to F (b + p) = 5.8e-3 J."""
    pull, dt = 50.0, 1e-6
    static = pull / STIFFNESS
    penetration = static + math.sqrt(static**2 + 2 * static * GAP)
    undamped = gear_on_mesh(dt, pull).run(20000, [probe("x", "displacement", 1, 0)])
    peak = -undamped.samples[0].min()
    assert peak == pytest.approx(GAP + penetration, abs=1e-5 * penetration)

    damping = 2 * 0.2 * math.sqrt(STIFFNESS)  # 20 % of critical in contact
    damped = gear_on_mesh(1e-5, pull, damping=damping).run(
        20000, [probe("x", "displacement", 1, 0)]
    )
    assert -damped.samples[0].min() <= GAP + penetration
    assert -damped.samples[0, -1] == pytest.approx(GAP + static, abs=1e-4 * static)

    open_ended = gear_on_mesh(dt, pull, backlash=None).run(
        20000, [probe("x", "displacement", 1, 0)]
    )
    assert -open_ended.samples[0, -1] > 10 * (GAP + penetration)  # 1/2 F t^2 / m = 5 mm


# --- the coast flank's stiffness -------------------------------------------------------------

EPS, END_TO_PEAK = 1.6, 0.6


def parabola_mesh_stiffness(cycle: np.ndarray) -> np.ndarray:
    """Mesh stiffness of the parabola law (docs/model.md §5.2) at mesh cycles s: the pairs at
    p = frac(s) + k < eps, each k_pk [1 - (1 - lambda)(2 p / eps - 1)^2] with
    k_pk = 3 k-bar / (eps (2 + lambda))."""
    peak = 3 * STIFFNESS / (EPS * (2 + END_TO_PEAK))
    total = np.zeros_like(cycle)
    for k in range(int(math.ceil(EPS)) + 1):
        p = cycle % 1.0 + k
        pair = peak * (1 - (1 - END_TO_PEAK) * (2 * p / EPS - 1) ** 2)
        total += np.where(p < EPS, pair, 0.0)
    return total


@pytest.mark.parametrize("coast_phase", [None, 0.3])
def test_coast_flank_stiffness_is_the_table_at_the_coast_phase(coast_phase):
    """A rotor turning freely at f sets the mesh cycle s = f t; a gear held on the coast
    flank by a constant force sees k(s + c), the parabola law at the coast phase c
    (default 0), while it is there."""
    frequency, dt, pull, mass = 400.0, 1e-5, 50.0, 1e-3
    meshes = MeshTerms(
        deflection=np.array([[0.0, 1.0]]),
        mean_stiffness=np.array([STIFFNESS]),
        contact_sign=np.ones(1, dtype=int),
        angle=np.array([[1.0, 0.0]]),
        table=single_mesh_table(STIFFNESS, EPS, "parabola", end_to_peak=END_TO_PEAK),
        time_varying=True,
        separation=True,
        names=["mesh"],
        backlash=[GAP],
        coast_phase=None if coast_phase is None else [coast_phase],
    )
    solver = BandedNewmark(
        np.diag([1.0, mass]), np.diag([0.0, 2 * 0.2 * math.sqrt(STIFFNESS * mass)]),
        np.diag([0.0, STIFFNESS]), dt, meshes=meshes, equivalent_load="iterate",
        drive=LawArrays("constant", (-pull, 0, 0, 0)), input_weights=np.array([0.0, 1.0]),
    )  # fmt: skip
    probes = [KernelProbe("k", "mesh_stiffness", mesh=0), KernelProbe("f", "mesh_force", mesh=0)]
    result = solver.run(
        2000, probes,
        q0=np.array([0.0, -(GAP + pull / STIFFNESS)]), v0=np.array([2 * np.pi * frequency, 0.0]),
    )  # fmt: skip
    stiffness, force = result.samples
    on_coast = force < 0
    assert on_coast[1:].all()  # held there the whole run
    cycle = frequency * result.time + (coast_phase or 0.0)
    # the law jumps where a pair enters or leaves (frac(s) = 0 or eps - 1): skip samples
    # whose cycle lies within round-off of a jump
    fraction = cycle % 1.0
    clear = np.minimum.reduce([fraction, 1 - fraction, np.abs(fraction - (EPS - 1))]) > 1e-9
    expected = parabola_mesh_stiffness(cycle)
    index = np.nonzero(on_coast & clear)[0][1:]  # sample 0 is the start, before a step
    np.testing.assert_allclose(stiffness[index], expected[index], rtol=1e-9)


# --- the gearbox: no reversal means today's run; the torque-reversal scene ----------------------


def short_runup(study_case, backlash):
    """The study case's run-up, 0.1 s, with tooth separation and the given backlash."""
    scene = study_case.scene("runup")
    # iterate: the flank follows the accepted state (the predictor's flank is that of the
    # predicted one, which dips below zero deflection in the first steps from rest)
    transient = dataclasses.replace(
        scene.transient, duration=0.1, mean_window=0.05, equivalent_load="iterate"
    )
    scene = dataclasses.replace(
        scene,
        effects=("time_varying_mesh_stiffness", "tooth_separation"),
        transient=transient,
        parameters={
            "planetary.sun_mesh.backlash": backlash,
            "planetary.ring_mesh.backlash": backlash,
        },
    )
    return study_case.for_scene(scene), scene


def test_zero_backlash_without_reversal_is_the_one_sided_run(study_case, monkeypatch):
    """In a run-up the drive flanks stay pressed: with backlash 0 the coast flank never
    engages and the run equals the one-sided contact law's (infinite backlash, the law
    without a coast flank) to round-off (conftest.roundoff_tolerance)."""
    case, scene = short_runup(study_case, 0.0)
    zero = run_transient(case, scene)
    monkeypatch.setattr(
        "pygear.analysis.time.transient.line_of_action_backlash", lambda *arguments: None
    )
    one_sided = run_transient(case, scene)
    assert zero.attrs["solver_coast"] == 0 and one_sided.attrs["solver_coast"] == 0
    stage = study_case.gearbox.stages[0]
    angle = float(np.abs(one_sided.speed.sel(member="planetary.sun")).max()) * np.pi / 30 * 0.1
    force = float(np.sqrt(np.mean(one_sided.mesh_force.sel(mesh=SUN_MESH).values ** 2)))
    amplification = rigid_to_elastic_ratio(
        stage.sun.base_radius, angle, force, stage.sun_mesh.stiffness
    )
    tolerance = roundoff_tolerance(one_sided.attrs["steps"], amplification)
    for name in ("speed", "mesh_force"):  # every member and mesh probed
        a, b = zero[name].values, one_sided[name].values
        assert np.abs(a - b).max() <= tolerance * np.abs(b).max()


def test_separation_without_backlash_is_refused(study_case):
    """Tooth separation with no backlash would leave the coast flanks' place unknown."""
    from pygear.analysis.time.transient import transient_problem

    scene = study_case.scene("runup")
    scene = dataclasses.replace(scene, effects=("tooth_separation",))
    with pytest.raises(CaseError, match=r"planetary\.sun_mesh\.backlash is needed by the "):
        transient_problem(study_case, scene)


def test_torque_reversal_scene_strikes_the_coast_flanks(study_case):
    """The case's torque_reversal scene: the sun and ring meshes reach their coast flanks
    (negative force) after the drive reverses, and their deflection never passes the
    normal backlash j_wt cos(alpha_wt) by more than the contact deflection |F| / k_min."""
    scene = study_case.scene("torque_reversal")
    case = study_case.for_scene(scene)
    run = run_transient(case, scene)
    assert run.attrs["solver_coast"] > 0
    stage = case.gearbox.stages[0]
    for mesh, component in ((SUN_MESH, stage.sun_mesh), (RING_MESH, stage.ring_mesh)):
        force = run.mesh_force.sel(mesh=mesh).values
        deflection = np.abs(run.mesh_deflection.sel(mesh=mesh).values)
        assert force.min() < 0  # the coast flank pushes
        assert run.time.values[np.argmax(force < 0)] > 0.02  # only after the reversal
        gap = component.backlash * math.cos(component.pressure_angle)
        # the parabola law's smallest mesh stiffness over a cycle is above half its mean
        contact = np.abs(force).max() / (0.5 * component.stiffness)
        assert deflection.max() <= gap + contact
        assert deflection.max() > gap  # it did cross the gap
