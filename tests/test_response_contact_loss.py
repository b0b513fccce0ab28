"""Tooth separation by alternating frequency-time Newton, against the linear balance and
a nonlinear time integration."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_response_stability import _spur_pair

from pygear import Scene
from pygear.analysis.response import response_system, solve_hill
from pygear.analysis.response.contact_loss import _signals, contact_loss_balance


@pytest.fixture(scope="module")
def pair():
    """The spur pair of the ISO test with contact ratio 1.6 and zeta about 0.02, its
    torsional DOF set (one elastic mode: the time integration stays cheap)."""
    case = _spur_pair(1.6, 0.6, 2e-6)
    case = dataclasses.replace(case, scenes=(Scene("torsional", dof_set="torsional"),))
    system = response_system(case, case.scenes[0])
    assert system.size == 1
    main = int(np.argmax(system.mesh_energy_share()))
    resonance = system.natural_frequencies[main] / (system.fundamental_per_rad_s * math.pi / 30)
    return system, resonance


def test_without_separation_the_linear_solution_stands(pair):
    """At 0.8 of the resonance speed the linear mesh force stays positive: Newton takes
    no step and returns the linear harmonics unchanged."""
    system, resonance = pair
    omega = system.omega(0.8 * resonance)
    linear = solve_hill(system, omega, 32, method="direct")
    solution, iterations = contact_loss_balance(system, omega, 32)
    assert iterations == 0
    assert np.array_equal(solution.deflection, linear.deflection)


def test_separated_steady_state_closes_a_period_of_time_integration(pair):
    """At 1.1 of the resonance speed the linear force turns negative (-0.12 of its
    mean); the contact-loss balance converges (residual 1e-10), its force never pulls,
    the teeth part for part of the period, and integrating the nonlinear equations over
    one period from its state (DOP853, rtol 1e-10, the stiffness of the nearest sample)
    returns the same mesh deflections to 2e-3 of the largest.

    Budget: with H = 64 the measured difference is 1.1e-3 (the teeth apart 16 % of the
    period); the force's kink where the teeth part makes the deflection's third
    derivative jump, so the truncation falls only as 1/H (on the planar pair at half the
    resonance speed: 0.0069 at H = 64, 0.0034 at H = 128)."""
    system, resonance = pair
    omega = system.omega(1.1 * resonance)
    h = 64
    solution, _ = contact_loss_balance(system, omega, h)
    assert solution.residual < 1e-10
    deflection = _signals(system, solution.deflection)
    contact = system.contact_sign * deflection > 0
    assert 0.05 < 1 - contact.mean() < 0.5  # the teeth part for part of the period

    n, samples = system.size, system.stiffness.shape[0]
    period = 2 * math.pi / omega
    k = np.arange(-h, h + 1)
    y0 = np.real(solution.coordinates.sum(axis=0))
    v0 = np.real(((1j * k * omega)[:, None] * solution.coordinates).sum(axis=0))

    def rates(t, x):
        q, v = x[:n], x[n:]
        i = int(math.floor(t / period * samples + 0.5)) % samples
        d = system.mesh_rows @ q
        spring = system.stiffness[i] * d * (system.contact_sign * d > 0)
        load = spring - system.mean_stiffness * d
        return np.concatenate([v, system.force - system.damping @ v - system.eigenvalues * q
                               - system.mesh_rows.T @ load])  # fmt: skip

    times = np.linspace(0, period, 9)
    run = solve_ivp(rates, (0, period), np.concatenate([y0, v0]), method="DOP853",
                    rtol=1e-10, atol=1e-16, t_eval=times, max_step=period / 512)  # fmt: skip
    balanced = deflection[(times[:-1] / period * samples).astype(int)]
    integrated = (system.mesh_rows @ run.y[:n, :-1]).T
    scale = np.abs(balanced).max()
    assert np.abs(integrated - balanced).max() <= 2e-3 * scale
    closure = system.mesh_rows @ (run.y[:n, -1] - y0)
    assert np.abs(closure).max() <= 2e-3 * scale
