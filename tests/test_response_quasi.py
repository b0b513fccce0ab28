"""The multi-frequency (quasi-periodic) balance of gearboxes of several stages.

References, each independent of the balance:

- a time integration (DOP853) of a two-stage torsional gearbox whose two meshes vary at
  incommensurate mesh frequencies (ratio the golden mean), in physical coordinates,
  run to steady state;
- the single-frequency Hill solve of :mod:`pygear.analysis.response.hill` when only one
  stage varies (its own code path: a real LU, per-harmonic modal solves);
- the static solution of the model's own matrices when no mesh varies.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import solve_ivp

from pygear.analysis.response import dynamic_factors_at, response_system, solve_hill
from pygear.analysis.response.quasi import lattice, solve_quasi, torus_phases, torus_samples
from pygear.analysis.response.system import ResponseSystem
from pygear.model.case import load_case

GOLDEN = (1 + math.sqrt(5)) / 2
MASSES = np.array([2.0, 1.5, 1.2, 3.0])  # kg (equivalent, along the lines of action)
SPRINGS = (4e7, 6e7, 5e7)  # N/m: input shaft, intermediate shaft, output shaft
MEAN = np.array([2e8, 1.5e8])  # N/m, mean mesh stiffnesses
LOAD = 1e3  # N on gear 1, reacted by the output shaft
# stiffness variation of each mesh over its own period: (order, cosine, sine) relative
VARIATION = ([(1, 0.22, 0.05), (2, 0.06, -0.04), (3, 0.02, 0.01)],
             [(1, 0.18, -0.07), (2, 0.05, 0.03)])  # fmt: skip


def _stiffness(mesh: int, tau: np.ndarray) -> np.ndarray:
    """k_m at phase tau (periods of the mesh) in closed form [N/m]."""
    out = np.ones_like(tau)
    for n, a, b in VARIATION[mesh]:
        out = out + a * np.cos(2 * math.pi * n * tau) + b * np.sin(2 * math.pi * n * tau)
    return MEAN[mesh] * out


def _matrices(coupled_damping: bool):
    """M, K0 (mean meshes), C, the mesh vectors and F of the chain ground - gear 1 = mesh 1
    = gear 2 - shaft - gear 3 = mesh 2 = gear 4 - ground."""
    k_in, k_mid, k_out = SPRINGS
    b = np.array([[1.0, -1.0, 0.0, 0.0], [0.0, 0.0, 1.0, -1.0]])
    k0 = np.diag([k_in, 0.0, 0.0, k_out])
    k0[1:3, 1:3] += k_mid * np.array([[1.0, -1.0], [-1.0, 1.0]])
    k0 = k0 + b.T @ np.diag(MEAN) @ b
    m = np.diag(MASSES)
    c = 20.0 * m + 2e-5 * k0  # Rayleigh: 3-5 % of critical on the modes
    if coupled_damping:  # a dashpot on the intermediate shaft alone: not proportional
        c[1:3, 1:3] += 400.0 * np.array([[1.0, -1.0], [-1.0, 1.0]])
    f = np.array([LOAD, 0.0, 0.0, 0.0])
    return m, k0, c, b, f


def _system(coupled_damping: bool = False, samples: int = 1024) -> ResponseSystem:
    m, k0, c, b, f = _matrices(coupled_damping)
    values, vectors = scipy.linalg.eigh(k0, m)
    tau = np.arange(samples) / samples
    stiffness = np.stack([_stiffness(0, tau), _stiffness(1, tau)], axis=1)
    return ResponseSystem(
        eigenvalues=values,
        damping=vectors.T @ c @ vectors,
        mesh_rows=b @ vectors,
        force=vectors.T @ f,
        mean_stiffness=MEAN.copy(),
        stiffness=stiffness,
        contact_sign=np.array([1, 1]),
        mesh_order=np.array([1, 1]),
        fundamental_per_rad_s=1.0,
        names=["stage1.mesh", "stage2.mesh"],
        stages=["stage1", "stage2"],
        planets=[0, 0],
        modes=vectors,
        mesh_group=np.array([0, 1]),
        group_fundamentals=np.array([1.0, GOLDEN]),
    )


def _integrate(omegas: np.ndarray, coupled_damping: bool, times: np.ndarray) -> np.ndarray:
    """Mesh deflections at ``times`` from rest at the static deflection, DOP853."""
    m, k0, c, b, f = _matrices(coupled_damping)
    m_inv = np.diag(1.0 / MASSES)
    fixed = k0 - b.T @ np.diag(MEAN) @ b

    def rhs(t, state):
        q, v = state[:4], state[4:]
        k = np.array([_stiffness(g, np.array(omegas[g] * t / (2 * math.pi))) for g in (0, 1)])
        force = f - fixed @ q - b.T @ (k * (b @ q)) - c @ v
        return np.concatenate([v, m_inv @ force])

    start = np.concatenate([np.linalg.solve(k0, f), np.zeros(4)])
    run = solve_ivp(rhs, (0.0, times[-1]), start, method="DOP853", rtol=1e-9, atol=1e-15,
                    t_eval=times)  # fmt: skip
    assert run.success
    return b @ run.y[:4]


def _signal(solution, times: np.ndarray) -> np.ndarray:
    """delta_m(t) from the lattice amplitudes."""
    phase = np.exp(1j * np.outer(times, solution.lattice.points @ solution.omegas))
    return np.real(phase @ solution.deflection).T


@pytest.mark.slow
def test_two_stage_balance_equals_time_integration():
    """At two speeds (mesh 1 at 180 and 420 Hz, mesh 2 at 1.618 times that, around the
    chain's modes) the balanced mesh deflections equal the steady state of a DOP853
    integration over 20 ms after 0.5 s of settling, with a damping that couples the modes
    (the balance's pole path).

    Tolerance: the truncation, estimated by the balance's own residual (below 1e-6 for
    these smooth laws at H = 16, M = 16; asserted), plus 1e-7 of the static deflection
    for the integration (rtol 1e-9) and the start's transient (the slowest mode decays
    as e^-(zeta w t), below 1e-8 after 0.5 s).  Measured: errors of 5e-10 and 6e-11
    against residuals of 4.5e-10 and 4.8e-11 at rtol 1e-11."""
    coupled_damping = True
    system = _system(coupled_damping)
    static = np.abs(system.static_deflection()).max()
    times = np.linspace(0.50, 0.52, 401)
    for mesh_hz in (180.0, 420.0):
        omegas = 2 * math.pi * mesh_hz * np.array([1.0, GOLDEN])
        solution = solve_quasi(system, omegas, [16, 16], 16)
        assert solution.residual < 1e-6
        reference = _integrate(omegas, coupled_damping, times)
        error = np.abs(_signal(solution, times) - reference).max() / static
        assert error < 1e-7 + 2 * solution.residual, (mesh_hz, error)
        # the dynamic part is not small: the test would see a wrong combination term
        assert np.ptp(reference[0]) > 0.05 * static


def test_one_varying_stage_is_the_single_frequency_balance():
    """With stage 2 at constant stiffness, the lattice's axis of stage 1 is Hill's
    single-frequency solution (to GMRES's 1e-11 and LU round-off), and every other
    point carries nothing."""
    system = _system()
    frozen = system.group_system(0)  # stage 2 at its mean stiffness
    frozen.mesh_group, frozen.group_fundamentals = system.mesh_group, system.group_fundamentals
    omegas = 2 * math.pi * 300.0 * np.array([1.0, GOLDEN])
    quasi = solve_quasi(frozen, omegas, [16, 16], 4)
    single = solve_hill(system.group_system(0), omegas[0], 16, method="direct")
    axis = quasi.lattice.index(np.stack([np.arange(-16, 17), np.zeros(33, int)], axis=1))
    scale = np.abs(single.deflection).max()
    assert np.abs(quasi.deflection[axis] - single.deflection).max() < 1e-9 * scale
    others = np.setdiff1d(np.arange(quasi.lattice.size), axis)
    assert np.abs(quasi.deflection[others]).max() < 1e-9 * scale


def test_one_varying_stage_of_a_gearbox_model():
    """The same on the NREL 5 MW gearbox's own model (a damping that couples the modes:
    the balance goes through the first-order poles, Hill's solve through a dense modal
    solve per harmonic): only stage 1 varying, at 12 rpm."""
    system = response_system(load_case("nrel5mw_gearbox"), samples=1024)
    frozen = system.group_system(0)
    frozen.mesh_group, frozen.group_fundamentals = system.mesh_group, system.group_fundamentals
    omegas = system.group_omegas(12.0)
    quasi = solve_quasi(frozen, omegas, [16, 4, 4], 2)
    single = solve_hill(system.group_system(0), omegas[0], 16, method="direct")
    axis = quasi.lattice.index(np.stack([np.arange(-16, 17), *(np.zeros((2, 33), int))], axis=1))
    scale = np.abs(single.deflection).max()
    # the poles' eigenvectors (condition ~1e3 here) bound the agreement
    assert np.abs(quasi.deflection[axis] - single.deflection).max() < 1e-8 * scale
    assert quasi.residual == pytest.approx(single.residual, rel=0.5)


def test_constant_stiffness_gearbox_is_the_static_solution():
    """No mesh varies: the lattice holds the static deflection alone, equal to the model's
    own K0 q = F (least squares: K0 is singular in the rigid rotation, which no mesh
    deflects) to round-off, every other point exactly zero, K_v = 1."""
    case = load_case("yang2016_gearbox")
    system = response_system(case, time_varying=False, samples=256)
    assert system.groups == 3
    solution = solve_quasi(system, system.group_omegas(900.0), [8, 8, 8], 4)
    model = system.model
    q = np.linalg.lstsq(model.stiffness, _load(system), rcond=None)[0]
    expected = np.array([m.deflection @ q for m in model.meshes])
    # both solves are backward stable: forward error <= kappa n eps (Higham 2002, sec. 7.1)
    cond = system.eigenvalues.max() / system.eigenvalues.min()
    tolerance = cond * model.stiffness.shape[0] * np.finfo(float).eps
    assert np.abs(solution.deflection[0] - expected).max() < tolerance * np.abs(expected).max()
    assert not np.any(solution.deflection[1:])


def _load(system: ResponseSystem) -> np.ndarray:
    """The static load F on the reduced DOFs, rebuilt from the modal force: M Psi f."""
    return system.model.mass @ (system.modes @ system.force)


def test_torus_samples_fill_the_torus():
    """The Kronecker grid's phases average every nonzero lattice frequency out (Weyl):
    the mean of e^{i k . theta} over 4096 points is below 2e-2 for |k| <= 4."""
    theta = torus_samples(3, 4096)
    points = lattice((4, 4, 4), 4).points[1:]
    assert np.abs(torus_phases(theta, points).mean(axis=0)).max() < 2e-2
    direct = np.exp(1j * theta @ points.T)
    assert np.allclose(torus_phases(theta, points), direct, atol=1e-12)


def test_dynamic_factors_of_a_gearbox_by_rating_mesh():
    """dynamic_factors_at on a gearbox of three stages: the rating's five meshes."""
    factors = dynamic_factors_at(load_case("yang2016_gearbox"), 900.0, harmonics=8, keys="rating")
    assert set(factors) == {"stage1.sun_mesh", "stage1.ring_mesh", "stage2.sun_mesh",
                            "stage2.ring_mesh", "parallel.mesh"}  # fmt: skip
    assert all(v > 1 for v in factors.values())


@pytest.mark.parametrize("speed", [700.0, 1675.0])
def test_lattice_record_equals_the_periodic_one_for_one_group(speed):
    """On a single stage, what the lattice reports equals what the periodic balance
    reports from the same harmonics: the mean force (from all 2^14 stiffness samples in
    both) and the DTE RMS (Parseval against the sampled period) to round-off; the bearing
    peaks (2048 torus points against 8 (2H + 1) samples of the period) to 1e-5; the peaks
    of the mesh force and K_v to 1e-3, since the lattice samples the mesh's own phase on
    16 (2H + 1) -> 2048 points, not on all 16 384, and a peak may fall in between
    (3.7e-4 measured)."""
    from pygear.analysis.response.quasi_sweep import quasi_record
    from pygear.analysis.response.sweep import _speed_record

    system = response_system(load_case("yang2016_planetary"))
    omega = system.omega(speed)
    periodic = _speed_record(system, solve_hill(system, omega, 32, method="direct"))
    lattice_record = quasi_record(system, solve_quasi(system, [omega], [32], 2))

    def close(key: str, tolerance: float) -> None:
        a, b = periodic[key], lattice_record[key]
        assert np.abs(a - b).max() <= tolerance * np.abs(a).max(), key

    close("force_mean", 1e-12)
    close("dte_rms", 1e-12)
    close("bearing", 1e-5)
    for key in ("force_max", "force_min", "dynamic_factor", "dte_pp"):
        close(key, 1e-3)
