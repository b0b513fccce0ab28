"""The periodic steady state by harmonic balance against independent derivations.

References: the full model's own matrices solved directly (constant stiffness), the
sparse Hill matrix solved as a whole (the condensed solve), and a time integration of
the same linear time-periodic system over one period closed on itself (the steady state
is the fixed point of the period map, which an integration from rest approaches as
exp(-zeta omega t)); exact exponentials of each interval from ``scipy.linalg.expm``.
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse.linalg

from pygear.analysis.response import (
    forced_response,
    hill_matrix,
    mesh_signals,
    response_system,
    solve_hill,
)
from pygear.model.case import load_case


@pytest.fixture(scope="module")
def study():
    """The study case's model with the time-varying mesh stiffness of its table."""
    return response_system(load_case("yang2016_planetary"))


def test_constant_stiffness_equals_linear_frequency_response(study):
    """At mean stiffness, harmonic k of the balance is (K0 - (k w)^2 M + i k w C)^-1 F_k
    over the model's own reduced DOFs (rigid rotation included), the mesh deflection
    b_m . q_k.  Tolerance: the condition number of the dynamic stiffness times 1e-15,
    about 1e-9 here: the modal transformation and the direct solve round differently."""
    system = study.constant_stiffness()
    model = system.model
    rng = np.random.default_rng(3)
    full_force = model.mass @ rng.standard_normal(model.size)  # any loads at harmonics 1, 2
    forcing = np.array([full_force, 0.5j * full_force])
    system = dataclasses.replace(system, harmonic_force=forcing @ system.modes)
    omega = system.omega(700.0)
    solution = solve_hill(system, omega, 4)
    rows = np.array([m.deflection for m in model.meshes])
    for k in (1, 2):
        w = k * omega
        dynamic = model.stiffness - w * w * model.mass + 1j * w * model.damping
        expected = rows @ np.linalg.solve(dynamic, forcing[k - 1])
        got = solution.deflection[4 + k]
        bound = np.linalg.cond(dynamic) * 1e-15 * np.abs(expected).max()
        assert np.abs(got - expected).max() <= max(bound, 1e-12 * np.abs(expected).max())
    # the static harmonic: K0 q0 = F with the rigid rotation pinned
    assert np.allclose(solution.deflection[4].real, system.static_deflection(), rtol=1e-12)
    assert np.abs(solution.deflection[[0, 1, 7, 8]]).max() == 0.0  # nothing forces 3, 4


def test_condensed_solve_is_hill_block_system(study):
    """The mesh-deflection condensation solves the full Hill block matrix (1): same
    coordinates to round-off of a 17 x 33 = 561-row complex solve (1e-12)."""
    omega, h = study.omega(1000.0), 16
    solution = solve_hill(study, omega, h)
    rhs = np.zeros((2 * h + 1, study.size), dtype=complex)
    rhs[h] = study.force
    full = scipy.sparse.linalg.spsolve(hill_matrix(study, omega, h), rhs.reshape(-1))
    full = full.reshape(2 * h + 1, study.size)
    assert np.abs(full - solution.coordinates).max() <= 1e-12 * np.abs(full).max()


def _period_map_steady_state(system, omega, segments):
    """Mesh deflections at tau = i / segments of the periodic orbit: each interval's exact
    exponential (stiffness at its trapezoidal mean) with the load in an augmented row,
    composed over a period, then x0 = (I - Phi)^-1 p."""
    n = system.size
    samples = system.stiffness.shape[0]
    step = samples // segments
    dk = system.stiffness_variation
    means = (
        dk.reshape(segments, step, -1).sum(axis=1)
        - 0.5 * dk[::step]
        + 0.5 * np.roll(dk, -step, axis=0)[::step]
    ) / step
    a = np.zeros((segments, 2 * n + 1, 2 * n + 1))
    a[:, :n, n : 2 * n] = np.eye(n)
    stiffness = np.diag(system.eigenvalues) + np.einsum(
        "mi,sm,mj->sij", system.mesh_rows, means, system.mesh_rows
    )
    a[:, n : 2 * n, :n] = -stiffness
    a[:, n : 2 * n, n : 2 * n] = -system.damping
    a[:, n : 2 * n, 2 * n] = system.force
    exponentials = scipy.linalg.expm(a * (2 * math.pi / omega / segments))
    running = np.eye(2 * n + 1)
    maps = [running]
    for e in exponentials[:-1]:
        running = e @ running
        maps.append(running)
    period = exponentials[-1] @ running
    x0 = np.linalg.solve(np.eye(2 * n) - period[: 2 * n, : 2 * n], period[: 2 * n, 2 * n])
    states = np.array([m[: 2 * n, : 2 * n] @ x0 + m[: 2 * n, 2 * n] for m in maps])
    return states[:, :n] @ system.mesh_rows.T


@pytest.mark.parametrize("speed", [1675.0, 2400.0])
def test_periodic_solution_equals_time_integration(study, speed):
    """Time-varying stiffness: the balanced mesh forces equal the steady state of a
    time integration to 1e-4 of the largest mesh force, at 1675 rpm (the ring-planet
    dynamic factor's peak, by the 1662 rpm mode) and 2400 rpm.

    Budget: the balance with 128 harmonics leaves a residual (the deflection of
    harmonics 129-256) below 9e-5 of the static deflection at these speeds, asserted
    here; the integration's own error, from holding the stiffness on 1024 intervals
    (second order), is a third of its change from 512 intervals, measured here."""
    omega = study.omega(speed)
    solution = solve_hill(study, omega, 128)
    assert solution.residual < 9e-5
    _, force = mesh_signals(study, solution)
    stride = study.stiffness.shape[0] // 1024
    fine = _period_map_steady_state(study, omega, 1024)
    coarse = _period_map_steady_state(study, omega, 512)
    stiffness = study.contact_sign * study.stiffness[::stride]
    reference = stiffness * fine
    scale = np.abs(force).max()
    integration_error = np.abs(stiffness[::2] * (fine[::2] - coarse)).max() / 3 / scale
    assert integration_error < 3e-5
    error = np.abs(force[::stride] - reference).max() / scale
    assert error <= 1e-4


def test_dynamic_factor_is_one_at_constant_stiffness():
    """No excitation but the static load: every mesh force is constant, K_v = 1 and
    K_gamma = 1 for the symmetric stage, to round-off (1e-12)."""
    dataset = forced_response(
        load_case("yang2016_planetary"), [200.0, 900.0], time_varying=False, stability=False
    )
    assert np.abs(dataset.dynamic_factor.values - 1).max() < 1e-12
    assert np.abs(dataset.load_sharing.values - 1).max() < 1e-12
    assert not dataset.separation.values.any()
    assert (dataset.dte_rms.values < 1e-12 * dataset.dte_peak_to_peak.values.max() + 1e-20).all()


def test_bearing_forces_balance_the_mesh_forces():
    """At constant stiffness the state is static: a symmetric stage's central members
    carry no net radial force (their bearings none), and each planet pin balances its two
    mesh forces, equal in magnitude (planet torque balance) and inclined by the pressure
    angle to the tangent on either side: |F_pin| = 2 F_mesh cos(alpha).  Tolerance 1e-9
    of the pin force: the translations of the planar model round at that level."""
    case = load_case("yang2016_planetary")
    dataset = forced_response(case, [500.0], time_varying=False, stability=False)
    alpha = case.gearbox.stages[0].sun_mesh.pressure_angle
    force = dataset.bearing_force_max.isel(speed=0)
    names = [str(b) for b in dataset.bearing.values]
    pins = [b for b in names if re.search(r"\.planet\d+_bearing$", b)]
    central = [b for b in names if b not in pins]
    assert len(pins) == 3 and len(central) == 3
    mesh = float(dataset.mesh_force_mean.sel(mesh="sun-planet1", speed=500.0))
    assert float(dataset.mesh_force_mean.sel(mesh="ring-planet1", speed=500.0)) == (
        pytest.approx(mesh, rel=1e-9)
    )
    expected = 2 * mesh * math.cos(alpha)
    for pin in pins:
        assert float(force.sel(bearing=pin)) == pytest.approx(expected, rel=1e-9)
    for member in central:
        assert float(force.sel(bearing=member)) < 1e-9 * expected


@pytest.mark.parametrize("speed", [300.0, 1675.0, 2400.0])
def test_iterative_solve_equals_direct(study, speed):
    """GMRES (relative residual of (2) at most 1e-10) and the real LU give the same
    harmonics to 1e-8 of the largest: the condensed matrix's condition number at these
    speeds is below 1e2 (21, 38 and 11), so 1e-10 of residual is at most 1e-8 of solution."""
    omega = study.omega(speed)
    direct = solve_hill(study, omega, 64, method="direct")
    iterative = solve_hill(study, omega, 64, method="iterative")
    scale = np.abs(direct.deflection).max()
    assert np.abs(iterative.deflection - direct.deflection).max() <= 1e-8 * scale
    assert iterative.residual == pytest.approx(direct.residual, rel=1e-8)
