"""Hard cases stay numerically stable: the banded Newmark kernel on stiff,
stepwise, parametrically excited and separating problems.

References are derived here, never taken from the code's output: the textbook Newmark
recurrence (Newmark 1959; Hughes, *The Finite Element Method*, 9.1), the spectral radius
rho_inf that HHT-alpha and generalized-alpha promise (Chung & Hulbert 1993), the exact
modal solution of a linear model, piecewise harmonic solutions of a piecewise-constant
stiffness, a Floquet (monodromy) computation with scipy's ``solve_ivp``, and the
closed-form steady state of a forced damped oscillator for the separation threshold
(docs/model.md §5, §6; docs/validation.md, integrator checks).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg
from conftest import single_mesh_table
from scipy.integrate import solve_ivp

from pygear.assembly.contact_table import ContactTable
from pygear.kernel.newmark import (
    BandedNewmark,
    KernelProbe,
    LawArrays,
    MeshTerms,
    PhysicalInstabilityError,
    RunResult,
    TransientError,
)

# --- helpers --------------------------------------------------------------------------------


def probe(name: str, kind: str, n: int, dof: int) -> KernelProbe:
    """A displacement, velocity or acceleration probe of one DOF."""
    return KernelProbe(name, kind, np.eye(n)[dof])


def driven_mesh_run(
    table: ContactTable,
    mass: float,
    mean_stiffness: float,
    damping: float,
    mesh_frequency: float,
    time_step: float,
    n_steps: int,
    x0: float,
    *,
    equivalent_load: str = "iterate",
    deflection_limit: float = 1e-3,
    restart_at_jumps: bool = False,
) -> RunResult:
    """A gear pair's relative mesh coordinate x (DOF 1) whose mesh stiffness follows a rotor
    (DOF 0) turning freely at ``mesh_frequency`` cycles per second: with no force on the
    rotor its angle is exactly 2 pi f t, so the table makes k a known function of time.
    Probes: x, x', k."""
    meshes = MeshTerms(
        deflection=np.array([[0.0, 1.0]]),
        mean_stiffness=np.array([mean_stiffness]),
        contact_sign=np.ones(1, dtype=int),
        angle=np.array([[1.0, 0.0]]),
        table=table,
        time_varying=True,
        names=["mesh"],
    )
    solver = BandedNewmark(
        np.diag([1.0, mass]),
        np.diag([0.0, damping]),
        np.diag([0.0, mean_stiffness]),
        time_step,
        meshes=meshes,
        equivalent_load=equivalent_load,
        deflection_limit=deflection_limit,
        restart_at_jumps=restart_at_jumps,
    )
    probes = [
        probe("x", "displacement", 2, 1),
        probe("v", "velocity", 2, 1),
        KernelProbe("k", "mesh_stiffness", mesh=0),
    ]
    return solver.run(
        n_steps, probes, q0=np.array([0.0, x0]), v0=np.array([2 * np.pi * mesh_frequency, 0.0])
    )


def observed_orders(steps: np.ndarray, errors: np.ndarray) -> np.ndarray:
    """log(e_i / e_(i+1)) / log(h_i / h_(i+1)) of successive refinements."""
    return np.log(errors[:-1] / errors[1:]) / np.log(steps[:-1] / steps[1:])


# --- 1. integrator: spectral radius of the kernel's amplification matrix ----------------------

OMEGA_H = np.logspace(-3, 6, 37)
SCHEMES = [("newmark", None, 1.0), ("hht", 0.7, 0.7), ("generalized-alpha", 0.5, 0.5)]


def kernel_amplification(omega_h: float, integrator: str, spectral_radius: float | None):
    """Amplification matrix of the scaled state (u, v / Omega, a / Omega^2) of an undamped
    1-DOF oscillator (m = 1, k = Omega^2, dt = 1), one column per one-step kernel run from
    a unit scaled displacement, velocity or acceleration."""
    solver = BandedNewmark(
        [[1.0]],
        [[0.0]],
        [[omega_h**2]],
        1.0,
        integrator=integrator,
        spectral_radius=spectral_radius,
    )
    probes = [probe(n, k, 1, 0) for n, k in (("u", "displacement"), ("v", "velocity"))]
    probes.append(probe("a", "acceleration", 1, 0))
    scale = np.array([1.0, omega_h, omega_h**2])
    columns = []
    for unit in np.eye(3) * scale:
        result = solver.run(1, probes, q0=unit[:1], v0=unit[1:2], a0=unit[2:])
        columns.append(result.samples[:, 1] / scale)
    return np.array(columns).T


def newmark_recurrence_amplification(omega_h: float, beta: float, gamma: float) -> np.ndarray:
    """The textbook Newmark step of u'' + Omega^2 u = 0 in the scaled state (u, v / Omega,
    a / Omega^2), dt = 1: u1 = u0 + v0 + (1/2 - beta) a0 + beta a1, v1 = v0 + (1 - gamma) a0
    + gamma a1, a1 = -Omega^2 u1."""
    w2 = omega_h**2
    matrix = np.zeros((3, 3))
    for j, (u0, v0, a0) in enumerate(np.eye(3) * np.array([1.0, omega_h, w2])):
        a1 = -w2 * (u0 + v0 + (0.5 - beta) * a0) / (1 + beta * w2)
        u1 = u0 + v0 + (0.5 - beta) * a0 + beta * a1
        v1 = v0 + (1 - gamma) * a0 + gamma * a1
        matrix[:, j] = [u1, v1 / omega_h, a1 / w2]
    return matrix


def spectral_radius(matrix: np.ndarray) -> float:
    return float(np.max(np.abs(np.linalg.eigvals(matrix))))


@pytest.mark.parametrize(("integrator", "rho_setting", "rho_inf"), SCHEMES)
def test_kernel_spectral_radius_at_most_one(integrator, rho_setting, rho_inf):
    """rho(A) <= 1 + 1e-12 for Omega h in [1e-3, 1e6], and rho(A) = rho_inf to 1e-3 at 1e6."""
    radii = np.array(
        [spectral_radius(kernel_amplification(w, integrator, rho_setting)) for w in OMEGA_H]
    )
    assert np.all(radii <= 1 + 1e-12), (OMEGA_H[radii > 1 + 1e-12], radii.max() - 1)
    assert radii[-1] == pytest.approx(rho_inf, abs=1e-3)
    assert radii[0] == pytest.approx(1.0, abs=1e-9)  # no damping of well-resolved modes


@pytest.mark.parametrize("omega_h", [1e-3, 0.1, 1.0, 2 * math.sqrt(3), 10.0, 1e3, 1e6])
def test_test_side_recurrence_reproduces_the_kernel(omega_h):
    """The recurrence of the negative controls, at beta = 1/4, is the kernel's matrix: to
    1e-12 in the displacement and velocity columns; the acceleration column adds terms of
    size (Omega h)^2 / 4 that cancel, so there the round-off is 1e-12 (1 + (Omega h)^2 / 4)."""
    kernel = kernel_amplification(omega_h, "newmark", None)
    recurrence = newmark_recurrence_amplification(omega_h, 0.25, 0.5)
    np.testing.assert_allclose(kernel[:, :2], recurrence[:, :2], rtol=0, atol=1e-12)
    rounding = 1e-12 * (1 + omega_h**2 / 4)
    np.testing.assert_allclose(kernel[:, 2], recurrence[:, 2], rtol=0, atol=rounding)


@pytest.mark.parametrize(
    ("scheme", "beta", "limit"),
    [("linear acceleration", 1 / 6, 2 * math.sqrt(3)), ("central difference", 0.0, 2.0)],
)
def test_conditionally_stable_schemes_fail_the_check(scheme, beta, limit):
    """Negative controls: the same check passes below Omega h = 2 sqrt(3) (beta = 1/6) or 2
    (beta = 0) and fails above."""
    below = [
        spectral_radius(newmark_recurrence_amplification(w, beta, 0.5))
        for w in np.linspace(0.01, 0.99, 25) * limit
    ]
    above = [
        spectral_radius(newmark_recurrence_amplification(w, beta, 0.5))
        for w in np.array([1.01, 1.5, 3.0, 10.0, 1e3]) * limit
    ]
    assert max(below) <= 1 + 1e-12, scheme
    assert min(above) > 1 + 1e-3, scheme


# --- 2. stiff ratios ----------------------------------------------------------------------


def stiff_drivetrain() -> tuple[np.ndarray, np.ndarray]:
    """Motor - soft shaft - pinion - mesh (1e10 N/m on 50 mm base radii) - wheel - soft
    shaft - load, torsional: M and K."""
    inertia = np.array([10.0, 1e-3, 1e-3, 10.0])  # kg m^2
    shaft, mesh, radius = 100.0, 1e10, 0.05  # N m/rad, N/m, m
    stiffness = np.zeros((4, 4))
    for (i, j), k, (ci, cj) in (
        ((0, 1), shaft, (1.0, -1.0)),
        ((1, 2), mesh, (radius, radius)),
        ((2, 3), shaft, (1.0, -1.0)),
    ):
        b = np.zeros(4)
        b[[i, j]] = ci, cj
        stiffness += k * np.outer(b, b)
    return np.diag(inertia), stiffness


@pytest.fixture(scope="module")
def stiff_run():
    """Generalized-alpha (rho_inf = 0.8), dt = slowest period / 50, 10 slow periods, from
    the lowest mode at 1 mrad plus the mesh mode at 1 nrad."""
    mass, stiffness = stiff_drivetrain()
    omega2, modes = scipy.linalg.eigh(stiffness, mass)
    omega = np.sqrt(np.clip(omega2, 0.0, None))
    dt = 2 * np.pi / omega[1] / 50
    solver = BandedNewmark(
        mass,
        np.zeros((4, 4)),
        stiffness,
        dt,
        integrator="generalized-alpha",
        spectral_radius=0.8,
    )
    probes = [
        probe(f"{k}{i}", k, 4, i)
        for k in ("displacement", "velocity", "acceleration")
        for i in range(4)
    ]
    amplitude = np.array([0.0, 1e-3, 0.0, 1e-9])
    result = solver.run(500, probes, q0=modes @ amplitude)
    q, v, a = result.samples[:4], result.samples[4:8], result.samples[8:]
    return dict(
        mass=mass,
        stiffness=stiffness,
        modes=modes,
        omega=omega,
        dt=dt,
        q=q,
        v=v,
        a=a,
        time=result.time,
        amplitude=amplitude,
    )


def test_stiff_model_frequency_ratio_and_step(stiff_run):
    omega, dt = stiff_run["omega"], stiff_run["dt"]
    assert omega[0] == pytest.approx(0.0, abs=1e-6)
    assert omega[-1] / omega[1] >= 1e4
    assert dt > 100 * 2 * np.pi / omega[-1]  # far larger than the fastest period


def test_stiff_model_energy_stays_bounded(stiff_run):
    """The high mode's start-up overshoot (HHT and generalized-alpha overshoot the velocity
    by O(Omega h)) is bounded by (Omega_max h)^2 E0 and is gone within 100 steps; after it
    the energy never exceeds E0 (it is not monotone: generalized-alpha dissipates a
    quadratic form of its own state, not E, which wobbles by 1e-5 E0)."""
    m, k, q, v = (stiff_run[n] for n in ("mass", "stiffness", "q", "v"))
    energy = 0.5 * np.einsum("it,ij,jt->t", v, m, v) + 0.5 * np.einsum("it,ij,jt->t", q, k, q)
    overshoot_bound = (stiff_run["omega"][-1] * stiff_run["dt"]) ** 2
    assert np.all(np.isfinite(energy))
    assert energy.max() <= overshoot_bound * energy[0]
    assert np.all(energy[100:] <= energy[0] * (1 + 1e-9))


def test_stiff_model_low_mode_amplitude(stiff_run):
    """Lowest mode's amplitude sqrt(eta^2 + (eta'/omega)^2) equals the exact (constant)
    modal amplitude to 1e-3 over 10 periods."""
    modes, mass, omega = stiff_run["modes"], stiff_run["mass"], stiff_run["omega"]
    eta = modes[:, 1] @ mass @ stiff_run["q"]
    eta_dot = modes[:, 1] @ mass @ stiff_run["v"]
    amplitude = np.hypot(eta, eta_dot / omega[1])
    assert np.max(np.abs(amplitude / stiff_run["amplitude"][1] - 1)) <= 1e-3


def test_stiff_model_high_mode_decays_at_rho_inf(stiff_run):
    """The mesh mode (Omega h ~ 9e3) loses a factor rho_inf = 0.8 per step (to 1 %).  Its
    three eigenvalues nearly coincide at -rho_inf there, so the norm of its scaled state
    (eta, eta' h, eta'' h^2) goes as n^p rho^n: log norm is fitted by n log rho + p log n
    + c over steps 40 .. 140 (a plain exponential fit gives 0.81)."""
    modes, mass, dt = stiff_run["modes"], stiff_run["mass"], stiff_run["dt"]
    state = np.array([modes[:, 3] @ mass @ stiff_run[n] for n in ("q", "v", "a")])
    norm = np.sqrt(state[0] ** 2 + (state[1] * dt) ** 2 + (state[2] * dt**2) ** 2)
    steps = np.arange(40, 141)
    basis = np.column_stack([steps, np.log(steps), np.ones(steps.size)])
    log_rho = np.linalg.lstsq(basis, np.log(norm[steps]), rcond=None)[0][0]
    assert math.exp(log_rho) == pytest.approx(0.8, rel=0.01)
    assert norm[140] < 1e-12 * norm[0]


# --- 3. stepwise (rectangular) mesh stiffness ---------------------------------------------

# eps = 1.5 and lambda = 1: every pair carries kbar / eps, two pairs for frac(s) < 0.5,
# one for frac(s) >= 0.5 (docs/model.md §5.1), so k(t) is a rectangular wave 4/3, 2/3 kbar
STEP_MASS, STEP_MEAN = 1.0, (2 * np.pi * 3.0) ** 2
STEP_MESH_FREQUENCY = 3.1
STEP_HALF = 0.5 / STEP_MESH_FREQUENCY  # time between switches
STEP_LEVELS = (4 / 3 * STEP_MEAN, 2 / 3 * STEP_MEAN)
STEP_X0 = 1e-4


def piecewise_harmonic(times: np.ndarray, segments: int) -> np.ndarray:
    """Exact x(t) of m x'' + k(t) x = 0, x(0) = x0, x'(0) = 0, k = STEP_LEVELS alternating
    every STEP_HALF: a harmonic solution per segment, x and x' continuous."""
    x, v = STEP_X0, 0.0
    out = np.full(times.shape, np.nan)
    for j in range(segments):
        omega = math.sqrt(STEP_LEVELS[j % 2] / STEP_MASS)
        inside = (times >= j * STEP_HALF) & (times < (j + 1) * STEP_HALF)
        tau = times[inside] - j * STEP_HALF
        out[inside] = x * np.cos(omega * tau) + v / omega * np.sin(omega * tau)
        c, s = math.cos(omega * STEP_HALF), math.sin(omega * STEP_HALF)
        x, v = x * c + v / omega * s, -x * omega * s + v * c
    return out


def rectangular_run(time_step: float, n_steps: int, **options) -> RunResult:
    table = single_mesh_table(STEP_MEAN, 1.5, "parabola", end_to_peak=1.0)
    return driven_mesh_run(
        table,
        STEP_MASS,
        STEP_MEAN,
        0.0,
        STEP_MESH_FREQUENCY,
        time_step,
        n_steps,
        STEP_X0,
        **options,
    )


def naive_steps(n: int) -> float:
    """Steps with the switches 0.1, 0.2, 0.3 of a step past a step start at every level."""
    return STEP_HALF / (n + 0.1)


@pytest.fixture(scope="module")
def naive_runs():
    steps = np.array([naive_steps(100 * 2**j) for j in range(5)])
    return steps, [rectangular_run(h, int(3.5 * STEP_HALF / h)) for h in steps]


def test_rectangular_stiffness_is_the_table(naive_runs):
    _, runs = naive_runs
    k = runs[0].samples[2]
    cycle = STEP_MESH_FREQUENCY * runs[0].time
    expected = np.where(cycle - np.floor(cycle) < 0.5, *STEP_LEVELS)
    np.testing.assert_allclose(k, expected, rtol=1e-12)


def test_switch_inside_steps_drops_to_first_order(naive_runs):
    steps, runs = naive_runs
    errors = np.array(
        [np.max(np.abs(r.samples[0] - piecewise_harmonic(r.time, 4))) / STEP_X0 for r in runs]
    )
    orders = observed_orders(steps, errors)
    assert np.all((orders[-2:] >= 0.9) & (orders[-2:] <= 1.1)), orders


def test_energy_jumps_by_half_dk_delta_squared(naive_runs):
    """E = m v^2/2 + k x^2/2 is constant between switches (to round-off and the iteration
    tolerance), jumps by dK x_n x_(n+1) / 2 over a switching step (the discrete form of
    dK delta^2 / 2), and that jump tends to the exact dK x(t_s)^2 / 2 (1 % at 1600 steps
    per switch interval)."""
    _, runs = naive_runs
    result = runs[-1]
    x, v, k = result.samples
    energy = 0.5 * STEP_MASS * v**2 + 0.5 * k * x**2
    change = np.diff(energy)
    switch = np.nonzero(np.diff(k))[0]
    assert switch.size == 3
    others = np.delete(change, switch)
    assert np.max(np.abs(others)) <= 1e-9 * energy[0]
    discrete = 0.5 * np.diff(k)[switch] * x[switch] * x[switch + 1]
    np.testing.assert_allclose(change[switch], discrete, rtol=1e-8)
    instants = STEP_HALF * np.arange(1, 4)
    exact = 0.5 * np.diff(k)[switch] * piecewise_harmonic(instants * (1 + 1e-12), 4) ** 2
    np.testing.assert_allclose(change[switch], exact, rtol=0.01)


def test_restart_at_the_switches_keeps_second_order():
    """Steps landing on the switches, the run restarted at each (the start solves the
    acceleration with the new stiffness): observed order in [1.9, 2.1]."""
    steps, errors = [], []
    for n in (100 * 2**j for j in range(4)):
        h = STEP_HALF / n
        x, v = STEP_X0, 0.0
        times, values = [0.0], [STEP_X0]
        for segment in range(4):
            solver = BandedNewmark([[STEP_MASS]], [[0.0]], [[STEP_LEVELS[segment % 2]]], h)
            result = solver.run(n, [probe("x", "displacement", 1, 0)], q0=[x], v0=[v])
            times.extend(segment * STEP_HALF + result.time[1:])
            values.extend(result.samples[0, 1:])
            x, v = result.q[0], result.v[0]
        times = np.array(times)
        exact = piecewise_harmonic(times * (1 + 1e-12), 5)  # end values inside the segment
        steps.append(h)
        errors.append(np.max(np.abs(np.array(values) - exact)) / STEP_X0)
    orders = observed_orders(np.array(steps), np.array(errors))
    assert np.all((orders >= 1.9) & (orders <= 2.1)), orders


@pytest.mark.parametrize("equivalent_load", ["iterate", "predictor"])
def test_steps_landing_on_the_switches_keep_second_order_with_restarts(equivalent_load):
    """Steps landing on the switches, with the acceleration restarted at each stiffness
    jump (``restart_at_jumps``): second order against the exact piecewise-harmonic
    solution.  Without the restart the step after a jump starts from the old
    stiffness's acceleration, an O(dt) velocity error per switch (orders 0.5 to 1.5)."""
    steps = np.array([STEP_HALF / (100 * 2**j) for j in range(4)])
    errors, restarts = [], []
    for h in steps:
        result = rectangular_run(
            h,
            int(round(3.5 * STEP_HALF / h)),
            restart_at_jumps=True,
            equivalent_load=equivalent_load,
        )
        exact = piecewise_harmonic(result.time * (1 + 1e-12), 4)
        errors.append(np.max(np.abs(result.samples[0] - exact)) / STEP_X0)
        restarts.append(result.counters["restarts"])
    orders = observed_orders(steps, np.array(errors))
    assert np.all((orders >= 1.9) & (orders <= 2.1)), orders
    assert restarts == [3] * len(steps)  # one per switch: 0.5, 1.0, 1.5 half-periods


def test_landing_steps_without_restart_lose_second_order():
    """The negative control: the same landing steps without the restart."""
    steps = np.array([STEP_HALF / (100 * 2**j) for j in range(4)])
    errors = []
    for h in steps:
        result = rectangular_run(h, int(round(3.5 * STEP_HALF / h)))
        exact = piecewise_harmonic(result.time * (1 + 1e-12), 4)
        errors.append(np.max(np.abs(result.samples[0] - exact)) / STEP_X0)
    orders = observed_orders(steps, np.array(errors))
    assert np.all(orders < 1.7), orders


# --- 4. parametric instability (Mathieu's first principal region) -----------------------

PARAM_MASS, PARAM_FREQUENCY, PARAM_ZETA, PARAM_DEPTH = 1.0, 100.0, 0.002, 0.2
PARAM_OMEGA = 2 * np.pi * PARAM_FREQUENCY
PARAM_MEAN = PARAM_MASS * PARAM_OMEGA**2
PARAM_CURVE_POSITIONS = np.linspace(0.0, 1.0, 1025)
PARAM_CURVE = 1 + PARAM_DEPTH * np.cos(2 * np.pi * PARAM_CURVE_POSITIONS)  # unit mean


def parametric_run(mesh_frequency: float, periods: int, **options) -> RunResult:
    """k(t) = kbar c(frac(f_m t)), c the tabulated 1 + mu cos(2 pi p) (one pair, eps = 1),
    x(0) = 1 um; 200 steps per mesh period."""
    table = single_mesh_table(PARAM_MEAN, 1.0, "tabulated", curve=PARAM_CURVE)
    dt = 1 / (200 * mesh_frequency)
    damping = 2 * PARAM_ZETA * PARAM_OMEGA * PARAM_MASS
    return driven_mesh_run(
        table,
        PARAM_MASS,
        PARAM_MEAN,
        damping,
        mesh_frequency,
        dt,
        200 * periods,
        1e-6,
        **options,
    )


def floquet_growth_rate(mesh_frequency: float) -> float:
    """ln(max |Floquet multiplier|) / T of m x'' + c x' + k(t) x = 0 over one mesh period,
    with k the same piecewise-linear interpolant of the curve (scipy, DOP853)."""
    period = 1 / mesh_frequency
    damping = 2 * PARAM_ZETA * PARAM_OMEGA * PARAM_MASS

    def rhs(t, y):
        k = PARAM_MEAN * np.interp((t * mesh_frequency) % 1.0, PARAM_CURVE_POSITIONS, PARAM_CURVE)
        return [y[1], -(k * y[0] + damping * y[1]) / PARAM_MASS]

    monodromy = np.column_stack(
        [
            solve_ivp(
                rhs,
                (0, period),
                y0,
                method="DOP853",
                rtol=1e-11,
                atol=1e-14,
                max_step=period / 1024,
            ).y[:, -1]
            for y0 in ([1.0, 0.0], [0.0, 1.0])
        ]
    )
    return math.log(spectral_radius(monodromy)) / period


def envelope_growth_rate(result: RunResult, first: float = 0.25) -> float:
    """Slope of log |x| at its half-cycle peaks after the first quarter of the run [1/s]."""
    x, t = result.samples[0], result.time
    start = int(first * x.size)
    crossings = np.nonzero(np.sign(x[start:-1]) * np.sign(x[start + 1 :]) < 0)[0] + start + 1
    peaks = [a + np.argmax(np.abs(x[a:b])) for a, b in zip(crossings[:-1], crossings[1:])]
    return float(np.polyfit(t[peaks], np.log(np.abs(x[peaks])), 1)[0])


def test_parametric_resonance_grows_at_the_floquet_rate():
    """Mesh frequency = 2 f_n (centre of the first region): growth rate to 1 % of Floquet's."""
    mesh_frequency = 2 * PARAM_FREQUENCY
    expected = floquet_growth_rate(mesh_frequency)
    assert expected > 25.0  # about mu omega_n / 4 - zeta omega_n = 30.2 1/s
    measured = envelope_growth_rate(parametric_run(mesh_frequency, 40))
    assert measured == pytest.approx(expected, rel=0.01)


@pytest.mark.parametrize("ratio", [0.8, 1.2])
def test_outside_the_region_nothing_grows(ratio):
    """f_m = 2 f_n (1 -+ 0.2), outside the region (|f_m / 2 f_n - 1| < mu / 4): Floquet
    multipliers inside the unit circle, and the run's amplitude does not grow."""
    mesh_frequency = 2 * PARAM_FREQUENCY * ratio
    assert floquet_growth_rate(mesh_frequency) < 0
    x = np.abs(parametric_run(mesh_frequency, 40).samples[0])
    quarter = x.size // 4
    assert x[-quarter:].max() <= x[:quarter].max()


def test_physical_growth_is_reported_as_such():
    """A parametric resonance that crosses the deflection limit raises
    PhysicalInstabilityError with the measured growth (the Floquet rate to 1 %)."""
    mesh_frequency = 2 * PARAM_FREQUENCY
    with pytest.raises(PhysicalInstabilityError, match="grew physically") as error:
        parametric_run(mesh_frequency, 100)
    diagnostic = error.value.diagnostic
    assert diagnostic.physical and diagnostic.steps_per_period >= 100
    assert diagnostic.rate == pytest.approx(floquet_growth_rate(mesh_frequency), rel=0.01)


def test_numerical_failure_is_not_reported_as_physical():
    """The explicit (predictor) mesh term at one step per mesh period, Omega_n h = 10,
    diverges although Floquet says the model is stable: a plain TransientError naming the
    predictor, and the same step with iteration stays bounded."""
    mesh_frequency = 2 * PARAM_FREQUENCY * 0.6
    assert floquet_growth_rate(mesh_frequency) < 0
    table = single_mesh_table(PARAM_MEAN, 1.0, "tabulated", curve=PARAM_CURVE)
    damping = 2 * PARAM_ZETA * PARAM_OMEGA * PARAM_MASS
    arguments = (table, PARAM_MASS, PARAM_MEAN, damping, mesh_frequency, 1 / mesh_frequency, 200)
    with pytest.raises(TransientError, match="predictor") as error:
        driven_mesh_run(*arguments, 1e-6, equivalent_load="predictor")
    assert not isinstance(error.value, PhysicalInstabilityError)
    bounded = driven_mesh_run(*arguments, 1e-6, equivalent_load="iterate")
    assert np.max(np.abs(bounded.samples[0])) <= 1e-6 * (1 + 1e-9)


# --- 5. tooth separation ---------------------------------------------------------------------

SEP_MASS, SEP_FREQUENCY, SEP_ZETA = 1.0, 50.0, 0.05
SEP_OMEGA = 2 * np.pi * SEP_FREQUENCY
SEP_STIFFNESS = SEP_MASS * SEP_OMEGA**2
SEP_DAMPING = 2 * SEP_ZETA * SEP_OMEGA * SEP_MASS
SEP_PRELOAD, SEP_RATIO, SEP_DURATION = 10.0, 0.9, 0.5
SEP_FORCING = SEP_RATIO * SEP_OMEGA


def steady_state_response() -> tuple[float, float]:
    """|H| [m/N] and the phase lag of m x'' + c x' + k x = F1 sin(w t)."""
    r = SEP_RATIO
    gain = 1 / (SEP_STIFFNESS * math.hypot(1 - r**2, 2 * SEP_ZETA * r))
    return gain, math.atan2(2 * SEP_ZETA * r, 1 - r**2)


def predicted_separation_load() -> float:
    """Started on the steady state, x = F0/k + F1 |H| sin(w t - phi) touches 0 first at
    F1 = F0 / (k |H|) = F0 sqrt((1 - r^2)^2 + (2 zeta r)^2)."""
    return SEP_PRELOAD / (SEP_STIFFNESS * steady_state_response()[0])


def separation_run(
    amplitude: float, time_step: float, *, separation: bool = True, mode: str = "iterate"
) -> RunResult:
    """Contact-only mesh (compression x > 0) under F0 + F1 sin(w t) from the linear steady
    state; the force table has a point on every step of the finest run."""
    table_step = 1 / (SEP_FREQUENCY * 800)
    table_times = np.arange(int(round(SEP_DURATION / table_step)) + 1) * table_step
    drive = LawArrays(
        "table",
        times=table_times,
        torques=SEP_PRELOAD + amplitude * np.sin(SEP_FORCING * table_times),
    )
    meshes = MeshTerms(
        deflection=np.ones((1, 1)),
        mean_stiffness=np.array([SEP_STIFFNESS]),
        contact_sign=np.ones(1, dtype=int),
        angle=np.zeros((1, 1)),
        separation=separation,
        names=["mesh"],
    )
    solver = BandedNewmark(
        [[SEP_MASS]],
        [[SEP_DAMPING]],
        [[SEP_STIFFNESS]],
        time_step,
        meshes=meshes,
        equivalent_load=mode,
        drive=drive,
        input_weights=np.ones(1),
    )
    gain, lag = steady_state_response()
    x0 = SEP_PRELOAD / SEP_STIFFNESS - amplitude * gain * math.sin(lag)
    v0 = amplitude * gain * SEP_FORCING * math.cos(lag)
    probes = [probe("x", "displacement", 1, 0), KernelProbe("k", "mesh_stiffness", mesh=0)]
    return solver.run(int(round(SEP_DURATION / time_step)), probes, q0=[x0], v0=[v0])


def exact_separation(amplitude: float) -> tuple[float, int]:
    """Peak compression and number of contact-state changes of the exact (event-located,
    solve_ivp) solution: k x acts only while x > 0, damping always."""
    gain, lag = steady_state_response()
    state = [
        SEP_PRELOAD / SEP_STIFFNESS - amplitude * gain * math.sin(lag),
        amplitude * gain * SEP_FORCING * math.cos(lag),
    ]
    t, in_contact, peak, changes = 0.0, True, state[0], 0

    def rhs(time, y, contact):
        force = SEP_PRELOAD + amplitude * math.sin(SEP_FORCING * time)
        spring = SEP_STIFFNESS * y[0] if contact else 0.0
        return [y[1], (force - SEP_DAMPING * y[1] - spring) / SEP_MASS]

    def touch(time, y, contact):
        return y[0]

    touch.terminal = True
    while t < SEP_DURATION:
        touch.direction = -1 if in_contact else 1
        sol = solve_ivp(
            rhs,
            (t, SEP_DURATION),
            state,
            args=(in_contact,),
            events=touch,
            rtol=1e-11,
            atol=1e-16,
            max_step=1e-4,
            dense_output=True,
        )
        grid = np.linspace(sol.t[0], sol.t[-1], 20001)
        peak = max(peak, float(np.max(sol.sol(grid)[0])))
        if sol.status != 1:
            break
        t, state = float(sol.t_events[0][0]), sol.y_events[0][0]
        state = [0.0, state[1]]
        in_contact = not in_contact
        changes += 1
    return peak, changes


def test_below_the_threshold_the_response_is_linear():
    load = 0.99 * predicted_separation_load()
    dt = 1 / (SEP_FREQUENCY * 400)
    with_separation = separation_run(load, dt)
    linear = separation_run(load, dt, separation=False)
    assert with_separation.counters["separated"] == 0
    difference = np.abs(with_separation.samples[0] - linear.samples[0])
    assert difference.max() <= 1e-8 * np.abs(linear.samples[0]).max()


def test_contact_loss_starts_at_the_predicted_load():
    """Bisection on F1 (400 steps per period): the first load with a separated step is
    within 1 % of F0 sqrt((1 - r^2)^2 + (2 zeta r)^2)."""
    predicted = predicted_separation_load()
    dt = 1 / (SEP_FREQUENCY * 400)
    low, high = 0.9 * predicted, 1.1 * predicted
    assert separation_run(low, dt).counters["separated"] == 0
    assert separation_run(high, dt).counters["separated"] > 0
    while high - low > 1e-4 * predicted:
        middle = 0.5 * (low + high)
        if separation_run(middle, dt).counters["separated"]:
            high = middle
        else:
            low = middle
    assert high == pytest.approx(predicted, rel=0.01)


@pytest.mark.parametrize("mode", ["iterate", "refactor", "predictor"])
def test_separation_is_clean_and_converges(mode):
    """F1 = 1.5 x threshold: finite, no chattering (the contact state changes exactly as
    often as the exact solution's, every open or closed spell lasts more than one step,
    a handful of iterations per step), and the peak compression converges to the exact
    one as dt halves (to 1e-3 at 800 steps per period)."""
    load = 1.5 * predicted_separation_load()
    exact_peak, exact_changes = exact_separation(load)
    assert exact_changes >= 10
    peaks = []
    for steps_per_period in (50, 100, 200, 400, 800):
        result = separation_run(load, 1 / (SEP_FREQUENCY * steps_per_period), mode=mode)
        assert np.all(np.isfinite(result.samples))
        open_steps = (result.samples[1] == 0).astype(int)
        changes = np.nonzero(np.diff(open_steps))[0]
        assert changes.size == exact_changes
        assert np.min(np.diff(changes)) > 1
        assert result.counters["max_iterations"] <= 6
        peaks.append(result.samples[0].max())
    differences = np.abs(np.diff(peaks))
    assert np.all(differences[1:] < differences[:-1])
    assert peaks[-1] == pytest.approx(exact_peak, rel=1e-3)


def test_restart_is_refused_where_it_does_not_apply(study_case):
    """The restart solves the equation of motion at a step instant: average
    acceleration only, and not with tooth separation."""
    from pygear import CaseError
    from pygear.analysis.time.transient import transient_problem

    scene = study_case.scene("runup")
    hht = dataclasses.replace(
        scene.transient, integrator="hht", restart_at_jumps=True, duration=0.01, mean_window=0.01
    )
    with pytest.raises(CaseError, match=r"restart_at_jumps needs integrator 'newmark'"):
        hht.validate("scenes.runup.transient")
    separating = dataclasses.replace(
        scene,
        effects=("time_varying_mesh_stiffness", "tooth_separation"),
        transient=dataclasses.replace(
            scene.transient, restart_at_jumps=True, duration=0.01, mean_window=0.01
        ),
    )
    with pytest.raises(CaseError, match="does not combine with the tooth_separation effect"):
        transient_problem(study_case, separating)
