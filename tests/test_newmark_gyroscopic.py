"""Gyroscopic and unbalance loads in the Newmark kernel (module newmark_gyroscopic).

The references are independent of the kernel: the rigid-disc overhung rotor's whirl
frequencies from its complex frequency equation, derived here, and the Jeffcott rotor's
run-up integrated with SciPy's ``solve_ivp`` at tight tolerance (Lewis 1932 for the
passage through a critical speed).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pygear.kernel.newmark import BandedNewmark, KernelProbe
from pygear.kernel.newmark_rotor import RotorTerms, Unbalance
from pygear.kernel.newmark_storage import cholmod_available

PATHS = ["banded_cholesky", "dense_inverse", "dense_refined"] + (
    ["sparse_cholesky"] if cholmod_available() else []
)

# an overhung disc on a massless cantilever shaft, clamped at z = 0, disc at z = L
YOUNG, LENGTH, DIAMETER = 211e9, 0.5, 0.025
MASS, DISC_DIAMETER = 20.0, 0.3
BENDING = YOUNG * np.pi * DIAMETER**4 / 64
POLAR = MASS * DISC_DIAMETER**2 / 8  # uniform thin disc: I_p = m D^2 / 8
DIAMETRAL = POLAR / 2  # thin disc
K11, K12, K22 = 12 * BENDING / LENGTH**3, -6 * BENDING / LENGTH**2, 4 * BENDING / LENGTH


def overhung_disc() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, K and G over (x, y, theta_x, theta_y) of the disc; theta_y = dx/dz and
    theta_x = -dy/dz, so the x-theta_y and y-theta_x couplings differ in sign; the disc's
    angular momentum I_p Omega (theta_y, -theta_x, 1) gives I_d theta_x'' + I_p Omega
    theta_y' = M_x and I_d theta_y'' - I_p Omega theta_x' = M_y."""
    mass = np.diag([MASS, MASS, DIAMETRAL, DIAMETRAL])
    stiffness = np.array([[K11, 0, 0, K12], [0, K11, -K12, 0], [0, -K12, K22, 0], [K12, 0, 0, K22]])
    gyroscopic = np.zeros((4, 4))
    gyroscopic[2, 3], gyroscopic[3, 2] = POLAR, -POLAR
    return mass, stiffness, gyroscopic


def whirl_frequencies(speed: float) -> np.ndarray:
    """Roots of (k11 - m w^2)(k22 - I_d w^2 + I_p Omega w) = k12^2 [rad/s].

    With z = x + i y and the complex slope phi = theta_y - i theta_x the disc's equations
    are m z'' + k11 z + k12 phi = 0 and I_d phi'' - i Omega I_p phi' + k12 z + k22 phi = 0;
    z, phi ~ exp(i w t) gives the quartic; w > 0 whirls forward (with the spin), w < 0
    backward.
    """
    quartic = np.polymul([-MASS, 0.0, K11], [-DIAMETRAL, POLAR * speed, K22])
    quartic[-1] -= K12**2
    roots = np.roots(quartic)
    assert np.all(abs(roots.imag) < 1e-9 * abs(roots).max())
    return np.sort(roots.real)


def state_probes(n: int) -> list[KernelProbe]:
    unit = np.eye(n)
    return [KernelProbe(f"q{i}", "displacement", unit[i]) for i in range(n)] + [
        KernelProbe(f"v{i}", "velocity", unit[i]) for i in range(n)
    ]


def trapezoidal_frequencies(signal: np.ndarray, count: int, step: float) -> np.ndarray:
    """Continuous frequencies [rad/s] of the ``count`` complex exponentials in a sampled
    trapezoidal-rule response: the matrix pencil gives each mode's factor per step mu,
    and the trapezoidal rule maps i w to mu = (1 + i w h / 2) / (1 - i w h / 2) exactly,
    so w = (2 / h) tan(arg mu / 2)."""
    rows = 10 * count  # the pencil's window: a few times the modes sought
    hankel = np.array([signal[i : i + rows] for i in range(signal.size - rows)])
    _, _, vh = np.linalg.svd(hankel, full_matrices=False)
    basis = vh[:count].T  # rows of vh span the modes [mu^j]_j
    mu = np.linalg.eigvals(np.linalg.pinv(basis[:-1]) @ basis[1:])
    return np.sort(2.0 / step * np.tan(np.angle(mu) / 2))


@pytest.mark.parametrize("path", PATHS)
def test_free_whirl_matches_the_rigid_disc_frequency_equation(path):
    """(b) At 300 rad/s the tip's orbit z = x + i y holds the two forward and the two
    backward whirls of the rigid-disc model."""
    mass, stiffness, gyroscopic = overhung_disc()
    speed, step = 300.0, 2e-5
    solver = BandedNewmark(
        mass,
        np.zeros((4, 4)),
        stiffness,
        step,
        tolerance=1e-12,
        linear_solver=path,
        rotor=RotorTerms(gyroscopic, times=(0.0,), speeds=(speed,)),
    )
    assert solver.linear_solver == path
    run = solver.run(3000, state_probes(4), q0=np.array([1e-4, 0.0, 0.0, 0.0]))
    measured = trapezoidal_frequencies(run.samples[0] + 1j * run.samples[1], 4, step)
    expected = whirl_frequencies(speed)
    # the converged iteration leaves the gyroscopic force 1e-12 off, and the pencil's
    # rounding on 3000 samples is ~1e-10 relative: 1e-8 allows both
    np.testing.assert_allclose(measured, expected, rtol=1e-8)
    # two forward (> 0) and two backward; the forward ones stiffen with speed
    at_rest = whirl_frequencies(0.0)
    assert np.all(expected[2:] > at_rest[2:]) and np.all(-expected[:2] < -at_rest[:2])


@pytest.mark.parametrize("path", PATHS)
def test_gyroscopic_force_does_no_work(path):
    """(a) Undamped, unforced: at constant speed the energy holds to the iteration's
    tolerance; on a speed ramp each step's change is the trapezoidal rule's
    -(h / 4)(Omega_n+1 - Omega_n) v_n^T G v_n+1 (the force's work, zero when the
    speed holds), and v^T G v = 0 at every sample."""
    mass, stiffness, gyroscopic = overhung_disc()
    step, steps = 5e-5, 2000
    for times, speeds in (((0.0,), (400.0,)), ((0.0, steps * step), (0.0, 800.0))):
        solver = BandedNewmark(
            mass,
            np.zeros((4, 4)),
            stiffness,
            step,
            tolerance=1e-13,
            linear_solver=path,
            rotor=RotorTerms(gyroscopic, times=times, speeds=speeds),
        )
        run = solver.run(
            steps, state_probes(4), q0=np.array([1e-4, 0, 0, 2e-4]), v0=np.array([0, 0.01, 0.02, 0])
        )
        q, v = run.samples[:4], run.samples[4:]
        energy = 0.5 * np.einsum("it,ij,jt->t", v, mass, v) + 0.5 * np.einsum(
            "it,ij,jt->t", q, stiffness, q
        )
        omega = np.interp(run.time, times, speeds)
        work = (
            -(step / 4) * np.diff(omega) * np.einsum("it,ij,jt->t", v[:, :-1], gyroscopic, v[:, 1:])
        )
        # per step: the iteration leaves the force tolerance * |f| off over a
        # displacement step |dq|, and the energy's own rounding is a few eps E
        bound = 1e-12 * energy[0]
        np.testing.assert_array_less(abs(np.diff(energy) - work), bound)
        power = np.einsum("it,ij,jt->t", v, gyroscopic, v)
        assert np.all(abs(power) <= 4 * np.finfo(float).eps * POLAR * np.sum(v * v, axis=0))
        if len(times) == 1:
            assert abs(energy[-1] - energy[0]) <= steps * bound
        else:  # the ramp's work is not negligible next to the rounding: the test sees it
            assert abs(energy[-1] - energy[0]) > 100 * steps * bound


# a Jeffcott rotor: point mass on an isotropic shaft, x and y
JEFFCOTT_MASS, JEFFCOTT_STIFFNESS, JEFFCOTT_DAMPING_RATIO = 10.0, 4.0e5, 0.02
UNBALANCE = 1e-4  # m e [kg m]


def jeffcott_runup(path: str, acceleration: float, end_speed: float, step: float):
    """The kernel's run-up from rest at constant angular acceleration: times and z."""
    w_n = np.sqrt(JEFFCOTT_STIFFNESS / JEFFCOTT_MASS)
    c = 2 * JEFFCOTT_DAMPING_RATIO * w_n * JEFFCOTT_MASS
    mass, damping = np.eye(2) * JEFFCOTT_MASS, np.eye(2) * c
    duration = end_speed / acceleration
    solver = BandedNewmark(
        mass,
        damping,
        np.eye(2) * JEFFCOTT_STIFFNESS,
        step,
        tolerance=1e-12,
        linear_solver=path,
        rotor=RotorTerms(
            None,
            times=(0.0, duration),
            speeds=(0.0, end_speed),
            unbalances=(Unbalance(0, 1, UNBALANCE),),
        ),
    )
    run = solver.run(int(round(duration / step)), state_probes(2)[:2])
    return run.time, run.samples[0] + 1j * run.samples[1]


@functools.lru_cache
def jeffcott_reference(acceleration: float, end: float, samples: int) -> np.ndarray:
    """m z'' + c z' + k z = m e (psi'^2 - i psi'') exp(i psi), psi = a t^2 / 2, by
    solve_ivp (DOP853, rtol 1e-11) at ``samples`` instants over [0, end]."""
    times = np.linspace(0.0, end, samples)
    w_n = np.sqrt(JEFFCOTT_STIFFNESS / JEFFCOTT_MASS)
    c = 2 * JEFFCOTT_DAMPING_RATIO * w_n * JEFFCOTT_MASS

    def rate(t, y):
        z, dz = y[0] + 1j * y[1], y[2] + 1j * y[3]
        psi, dpsi = 0.5 * acceleration * t * t, acceleration * t
        force = UNBALANCE * (dpsi**2 - 1j * acceleration) * np.exp(1j * psi)
        ddz = (force - c * dz - JEFFCOTT_STIFFNESS * z) / JEFFCOTT_MASS
        return [dz.real, dz.imag, ddz.real, ddz.imag]

    solution = solve_ivp(
        rate, (0, times[-1]), [0, 0, 0, 0], method="DOP853", t_eval=times, rtol=1e-11, atol=1e-16
    )
    return solution.y[0] + 1j * solution.y[1]


@pytest.mark.parametrize("path", PATHS)
def test_jeffcott_runup_through_the_critical_speed(path):
    """(c) Constant acceleration through w_n = 200 rad/s: the kernel's orbit against an
    independent integration; the peak is lower than the steady-state resonance and
    comes after the critical speed (Lewis 1932), the more so the faster the run-up."""
    w_n = np.sqrt(JEFFCOTT_STIFFNESS / JEFFCOTT_MASS)
    steady_peak = UNBALANCE / JEFFCOTT_MASS / (2 * JEFFCOTT_DAMPING_RATIO)  # e / 2 zeta
    step = 5e-5
    peaks = []
    for acceleration in (400.0, 2000.0):  # dimensionless a / w_n^2 = 0.01 and 0.05
        times, z = jeffcott_runup(path, acceleration, 2 * w_n, step)
        reference = jeffcott_reference(acceleration, times[-1], times.size)
        # the trapezoidal rule's phase error, (w h)^2 / 12 per radian, reaches 3e-5 at
        # 400 rad/s and lags the free part of the orbit by ~1e-4 of its size over the
        # run (measured 1.8e-4); 1e-3 of the peak allows it
        scale = abs(reference).max()
        assert abs(z - reference).max() <= 1e-3 * scale
        peak = int(np.argmax(abs(z)))
        peaks.append((abs(z[peak]), acceleration * times[peak]))
        assert abs(z[peak]) < steady_peak
        assert acceleration * times[peak] > w_n
    (slow_peak, slow_speed), (fast_peak, fast_speed) = peaks
    assert fast_peak < slow_peak and fast_speed > slow_speed


def damped_runup(path: str, integrator: str = "newmark", **rotor) -> tuple[BandedNewmark, object]:
    """The overhung disc with light damping and an unbalance, run up from 0 to 600 rad/s."""
    mass, stiffness, gyroscopic = overhung_disc()
    damping = 1e-4 * stiffness + 2.0 * mass
    terms = {
        "times": (0.0, 0.1),
        "speeds": (0.0, 600.0),
        "unbalances": (Unbalance(0, 1, 2e-4, angle=0.3),),
        **rotor,
    }
    solver = BandedNewmark(
        mass,
        damping,
        stiffness,
        2e-5,
        integrator=integrator,
        spectral_radius=0.9 if integrator != "newmark" else None,
        tolerance=1e-12,
        linear_solver=path,
        rotor=RotorTerms(gyroscopic, **terms),
    )
    return solver, solver.run(5000, state_probes(4))


@pytest.mark.parametrize("integrator", ["newmark", "generalized-alpha"])
def test_every_path_gives_the_same_runup(integrator):
    """(e) Banded, dense and sparse paths agree on a damped run-up with gyroscopics and an
    unbalance (generalized-alpha too, which weighs the loads at t_n by alpha_f): they
    round differently (a product with a computed inverse, triangular solves, CHOLMOD's
    ordering), on a model whose condition number is ~1e5; 1e-9 of the largest value
    allows that rounding carried over 5000 steps."""
    runs = {path: damped_runup(path, integrator)[1].samples for path in PATHS}
    reference = runs["banded_cholesky"]
    for path, samples in runs.items():
        for row, ref in zip(samples, reference):
            assert abs(row - ref).max() <= 1e-9 * abs(ref).max(), path


def test_the_runs_rotation_as_the_speed_source():
    """A free spin DOF started at 500 rad/s turns the disc: the gyroscopic force at its
    own speed w . v gives the response of the prescribed constant 500 rad/s."""
    mass, stiffness, gyroscopic = overhung_disc()
    spin = 0.7  # the spin DOF's inertia [kg m^2]
    mass5 = np.zeros((5, 5))
    mass5[:4, :4], mass5[4, 4] = mass, spin
    stiffness5 = np.zeros((5, 5))
    stiffness5[:4, :4] = stiffness
    gyroscopic5 = np.zeros((5, 5))
    gyroscopic5[:4, :4] = gyroscopic
    q0 = np.array([1e-4, 0.0, 0.0, 0.0, 0.0])
    runs = []
    for terms in (
        RotorTerms(gyroscopic5, source="rotation", speed_weights=np.eye(5)[4]),
        RotorTerms(gyroscopic5, times=(0.0,), speeds=(500.0,)),
    ):
        solver = BandedNewmark(
            mass5, np.zeros((5, 5)), stiffness5, 2e-5, tolerance=1e-12, rotor=terms
        )
        v0 = np.array([0.0, 0.0, 0.0, 0.0, 500.0])
        runs.append(solver.run(2000, state_probes(5)[:4], q0=q0, v0=v0).samples)
    np.testing.assert_allclose(runs[0], runs[1], rtol=0, atol=1e-10 * abs(runs[1]).max())


def test_without_rotor_terms_a_linear_step_is_one_solve():
    """No rotor terms: the linear path solves once per step; with them it iterates."""
    mass, stiffness, gyroscopic = overhung_disc()
    plain = BandedNewmark(mass, np.zeros((4, 4)), stiffness, 2e-5)
    assert plain.run(100, q0=np.array([1e-4, 0, 0, 0])).counters["iterations"] == 100
    spun = BandedNewmark(
        mass,
        np.zeros((4, 4)),
        stiffness,
        2e-5,
        rotor=RotorTerms(gyroscopic, times=(0.0,), speeds=(300.0,)),
    )
    assert spun.run(100, q0=np.array([1e-4, 0, 0, 0])).counters["iterations"] > 100


def test_unbalance_needs_a_speed_profile():
    with pytest.raises(ValueError, match="unbalances need a prescribed speed profile"):
        RotorTerms(
            None, source="rotation", speed_weights=np.ones(2), unbalances=(Unbalance(0, 1, 1e-4),)
        )


def test_a_step_too_long_for_the_speed_is_named():
    """h Omega = 20: the gyroscopic iteration cannot contract, and the error says why."""
    from pygear.kernel.newmark import TransientError

    mass, stiffness, gyroscopic = overhung_disc()
    solver = BandedNewmark(
        mass,
        np.zeros((4, 4)),
        stiffness,
        1e-2,
        rotor=RotorTerms(gyroscopic, times=(0.0,), speeds=(2000.0,)),
    )
    with pytest.raises(TransientError, match="gyroscopic force did not converge.*time_step"):
        solver.run(10, q0=np.array([1e-4, 0, 0, 0]))
