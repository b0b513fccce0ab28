"""Contact loss and backlash in the steady-state response (AFT harmonic balance with
pseudo-arclength continuation), against Hill's linear balance, long time integrations
sweeping the frequency up and down, and finite-difference monodromies of the flow."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate
import xarray as xr

from pygear import Bearing, Case, Gear, Gearbox, Mesh, ParallelStage, RayleighDamping, Scene
from pygear.analysis.response import response_system, solve_hill, sweep_system
from pygear.analysis.response.continuation import (
    continue_branch,
    continue_response,
    newton,
    separated_response,
)
from pygear.analysis.response.nonlinear import (
    BacklashLaw,
    BacklashProblem,
    case_law,
    oscillator_system,
)
from pygear.assembly.mesh_backlash import line_of_action_backlash

# Kahraman & Singh (1990) single-DOF spur pair, nondimensional: unit mass and mean
# stiffness, x'' + 2 ZETA x' + g(x) = F_M + F_A cos(omega t), gap GAP (their 2b).
ZETA, F_M, F_A, GAP = 0.05, 0.1, 0.02, 2.0
HARMONICS = 16
BAND = (0.77, 0.95)
STEP = 0.0025
"""Frequency step of the stepped-sine time sweeps [rad/s]."""
SETTLE = 30
"""Periods at each frequency of the sweep: the free decay exp(-ZETA omega t) falls by
exp(-2 pi ZETA 30 omega) < 1e-3 over them, so the sweep tracks each stable branch to
well below the 1e-3 checked on amplitudes."""
STEPS_PER_PERIOD = 128


def _acceleration(
    t: float, x: float, v: float, w: float, forcing: float = F_A, gap: float = GAP
) -> float:
    g = x if x > 0 else (x + gap if x < -gap else 0.0)  # pygear's flank law, drive side at 0
    return F_M + forcing * math.cos(w * t) - 2 * ZETA * v - g


def _periods(
    x: float, v: float, w: float, count: int, forcing: float = F_A, gap: float = GAP
) -> tuple[float, float, float]:
    """``count`` periods of classical RK4 with a fixed step locked to the period (each
    period starts at phase 0); returns the state and the peak-to-peak of x over the last
    period."""
    h = 2 * math.pi / w / STEPS_PER_PERIOD
    lo, hi = math.inf, -math.inf

    def acc(t: float, x: float, v: float, w: float) -> float:  # _acceleration, inlined
        g = x if x > 0 else (x + gap if x < -gap else 0.0)
        return F_M + forcing * math.cos(w * t) - 2 * ZETA * v - g

    for p in range(count):
        for n in range(STEPS_PER_PERIOD):
            t = n * h
            a1 = acc(t, x, v, w)
            x2, v2 = x + 0.5 * h * v, v + 0.5 * h * a1
            a2 = acc(t + 0.5 * h, x2, v2, w)
            x3, v3 = x + 0.5 * h * v2, v + 0.5 * h * a2
            a3 = acc(t + 0.5 * h, x3, v3, w)
            x4, v4 = x + h * v3, v + h * a3
            a4 = acc(t + h, x4, v4, w)
            x += h / 6 * (v + 2 * v2 + 2 * v3 + v4)
            v += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
            if p == count - 1:
                lo, hi = min(lo, x), max(hi, x)
    return x, v, hi - lo


@pytest.fixture(scope="module")
def time_sweeps() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Stepped-sine sweeps up then down through BAND, each frequency starting from the
    state the previous one left (a slow sweep, as on a test rig)."""
    up = BAND[0] + STEP * np.arange(round((BAND[1] - BAND[0]) / STEP) + 1)
    x, v, _ = _periods(F_M, 0.0, up[0], 150)
    out = {}
    for name, frequencies in (("up", up), ("down", up[::-1])):
        amplitude = np.empty(frequencies.size)
        for i, w in enumerate(frequencies):
            x, v, amplitude[i] = _periods(x, v, float(w), SETTLE)
        out[name] = (frequencies, amplitude)
    return out


@pytest.fixture(scope="module")
def branch():
    system = oscillator_system(ZETA, F_M, F_A)
    law = BacklashLaw(np.array([GAP]))
    dataset = continue_response(system, law, (0.7, 1.0), harmonics=HARMONICS)
    return system, law, dataset


def _jump(frequencies: np.ndarray, amplitude: np.ndarray) -> float:
    """First frequency of a sweep whose peak-to-peak left the previous one's branch (a
    change over a quarter of the range; a step on a branch changes it by < 1 %)."""
    change = np.abs(np.diff(amplitude))
    return float(frequencies[1:][np.argmax(change > 0.25 * np.ptp(amplitude))])


def test_jumps_match_time_integration_sweeps(branch, time_sweeps):
    """The continuation's folds are the jump frequencies of the slow sweeps.

    An up sweep leaves the lower branch at its fold: the jump shows at the first sweep
    frequency past it, so the fold lies within one step STEP below the jump; near a
    saddle-node the orbit lingers (slow passage), so the jump may show one step later
    still: 2 STEP, which is 5 % of the hysteresis band.  A down sweep alike, above."""
    _, _, dataset = branch
    up_jump, down_jump = dataset.attrs["up_sweep_jumps"], dataset.attrs["down_sweep_jumps"]
    assert up_jump.size == 1 and down_jump.size == 1  # one softening loop
    reference_up = _jump(*time_sweeps["up"])
    reference_down = _jump(*time_sweeps["down"])
    assert reference_up - 2 * STEP <= up_jump[0] <= reference_up
    assert reference_down <= down_jump[0] <= reference_down + 2 * STEP
    band = up_jump[0] - down_jump[0]
    assert band > 20 * STEP  # a real hysteresis loop, not a step artefact
    # softening: the up sweep jumps at the higher frequency
    assert up_jump[0] > down_jump[0]


def test_outer_branches_match_the_sweeps_and_are_stable(branch, time_sweeps):
    """At 0.85 rad/s, inside the loop, the sweep up sits on the lower branch and the
    sweep down on the upper: their peak-to-peak DTE equals the balance's on the two
    stable branches (RK4 at 128 steps a period and the settling leave < 1e-3; H = 16
    leaves < 1e-4, the orbit's force being continuous), and a third solution between
    them is the unstable one no sweep shows."""
    system, law, dataset = branch
    problem = BacklashProblem(system, law, HARMONICS)
    speed = dataset.speed.values
    w = 0.85
    crossings = np.flatnonzero(np.sign(speed[:-1] - w) != np.sign(speed[1:] - w))
    assert crossings.size == 3
    found = []
    for i in crossings:
        x, _, ok = newton(
            lambda z: problem.residual(z, w)[:2],
            dataset.deflection_coefficients.values[i].reshape(-1),
            tolerance=1e-12,
        )
        assert ok
        deflection = problem.signals(x, 4096)[0][:, 0]
        stable = np.abs(problem.multipliers(x, w)[0]) < 1
        found.append((float(np.ptp(deflection)), bool(stable), int(dataset.stable.values[i])))
    found.sort()
    (low, s_low, d_low), (mid, s_mid, d_mid), (high, s_high, d_high) = found
    frequencies, amplitude = time_sweeps["up"]
    assert low == pytest.approx(amplitude[np.argmin(np.abs(frequencies - w))], abs=1e-3)
    frequencies, amplitude = time_sweeps["down"]
    assert high == pytest.approx(amplitude[np.argmin(np.abs(frequencies - w))], abs=1e-3)
    assert (s_low, s_mid, s_high) == (True, False, True)
    assert (d_low, d_mid, d_high) == (1, 0, 1)


def test_stability_flips_at_the_folds(branch):
    """Along the branch the stable flag changes at the turning points: stable before
    the first fold, unstable between the two (a real multiplier past +1, the
    saddle-node's, arg 0), stable after the second.  At a fold the multiplier is 1 and
    leaves it as the square root of the distance, while the 128-segment monodromy is
    good to ~5e-3: points within 1e-3 of a fold's speed are left undecided."""
    _, _, dataset = branch
    turning = np.flatnonzero(dataset.turning.values)
    assert turning.size == 2
    first, second = turning
    speed = dataset.speed.values
    folds = [*dataset.attrs["up_sweep_jumps"], *dataset.attrs["down_sweep_jumps"]]
    clear = np.min([np.abs(speed / f - 1) for f in folds], axis=0) > 1e-3
    stable = dataset.stable.values.astype(bool)
    part = np.arange(speed.size)
    outer = clear & ((part <= first) | (part > second))
    middle = clear & (part > first) & (part <= second)
    assert outer.sum() > 50 and middle.sum() > 20
    assert stable[outer].all() and not stable[middle].any()
    assert np.abs(dataset.floquet_argument.values[middle]).max() < 1e-9  # real, > 0
    assert dataset.floquet_multiplier.values[middle].max() > 1.3


def _poincare_multipliers(x0: float, v0: float, w: float) -> np.ndarray:
    """Eigenvalues of the period map's Jacobian by central differences of the flow
    (DOP853 at rtol 1e-11: the differences carry ~1e-11 / 1e-5 = 1e-6 of noise)."""

    def flow(state: np.ndarray) -> np.ndarray:
        sol = scipy.integrate.solve_ivp(
            lambda t, y: [y[1], _acceleration(t, y[0], y[1], w)],
            (0.0, 2 * math.pi / w),
            state,
            method="DOP853",
            rtol=1e-11,
            atol=1e-13,
        )
        return sol.y[:, -1]

    eps = 1e-5
    base = np.array([x0, v0])
    jac = np.empty((2, 2))
    for k in range(2):
        d = np.zeros(2)
        d[k] = eps
        jac[:, k] = (flow(base + d) - flow(base - d)) / (2 * eps)
    return np.linalg.eigvals(jac)


@pytest.mark.parametrize("which", ["upper", "middle"])
def test_floquet_multipliers_match_the_flow(branch, which):
    """The multipliers of the contact state's linearisation equal those of the period
    map of the nonlinear flow, differentiated numerically around the balanced orbit.
    The monodromy holds the contact stiffness over 128 segments with a switch inside
    two of them (error ~ (T/128)^2 ~ 2e-3 relative) and the orbit carries the H = 16
    truncation: 1 % on the largest modulus, against a distance of 30 % and more from 1."""
    system, law, dataset = branch
    problem = BacklashProblem(system, law, HARMONICS)
    speed = dataset.speed.values
    w = 0.85
    crossings = np.flatnonzero(np.sign(speed[:-1] - w) != np.sign(speed[1:] - w))
    pp = dataset.dte_peak_to_peak.values[crossings, 0]
    i = crossings[np.argsort(pp)[2 if which == "upper" else 1]]
    x, _, ok = newton(
        lambda z: problem.residual(z, w)[:2],
        dataset.deflection_coefficients.values[i].reshape(-1),
        tolerance=1e-13,
    )
    h = HARMONICS
    a, b = x[1 : h + 1], x[h + 1 :]
    k = np.arange(1, h + 1)
    x0, v0 = x[0] + a.sum(), float((k * w * b).sum())
    expected = np.max(np.abs(_poincare_multipliers(x0, v0, w)))
    got = np.abs(problem.multipliers(x, w)[0])
    assert got == pytest.approx(expected, rel=1e-2)
    assert (got > 1) == (which == "middle")


def test_no_contact_loss_equals_hill_to_round_off():
    """A mesh stiffness with two harmonics and a forcing small enough that the drive
    flanks never part: the flank law is then linear, the AFT products are exact (N = 8
    (2H + 1) > 3H samples) and Newton's first step lands on Hill's condensed solution
    (same equations): equal to round-off, 1e-12 of the deflection."""
    system = oscillator_system(ZETA, F_M, 0.01, (0.2, 0.05))
    for backlash in (1e3, np.inf):
        problem = BacklashProblem(system, BacklashLaw(np.array([backlash])), 8)
        for w in (0.45, 0.9, 1.7):
            x, history, ok = newton(
                lambda z, w=w, p=problem: p.residual(z, w)[:2],
                problem.static_guess(),
                tolerance=1e-15,
            )
            assert ok and len(history) <= 3
            hill = problem.from_hill(solve_hill(system, w, 8).deflection)
            assert np.abs(x - hill).max() <= 1e-12 * np.abs(hill).max()
            assert problem.signals(x)[0].min() > 0  # no separation: the linear regime


def _pair_case() -> Case:
    """One spur pair, 23:41 teeth of 4 mm module at 20 deg (as in the stability tests)."""

    def gear(teeth: int) -> Gear:
        radius = 4e-3 * teeth * math.cos(math.radians(20)) / 2
        mass = 3.0 * (teeth / 23) ** 2
        inertia = 0.5 * mass * (radius / math.cos(math.radians(20))) ** 2
        return Gear(mass=mass, polar_inertia=inertia, tilt_inertia=inertia / 2,
                    base_radius=radius, teeth=teeth)  # fmt: skip

    bearing = Bearing(radial=5e8, axial=5e8, tilt=1e10, torsional=0.0)
    stage = ParallelStage(
        name="pair", input_gear=gear(23), output_gear=gear(41), input_bearing=bearing,
        output_bearing=bearing, overlap_ratio=0.0, base_helix_angle_deg=0.0,
        mesh=Mesh(stiffness=3e8, pressure_angle_deg=20.0, contact_ratio=1.6,
                  end_to_peak=0.9, backlash=0.1e-3),
    )  # fmt: skip
    return Case(name="pair", gearbox=Gearbox(stages=(stage,)), formulation="improved",
                damping=RayleighDamping(0.0, 2e-6),
                scenes=(Scene("modal", dof_set="planar"),))  # fmt: skip


def test_gearbox_model_without_contact_loss_equals_hill():
    """Through a pygear spur-pair model (its contact-table stiffness with the jumps of
    a 1.6 contact ratio, bearings, several modes): with the AFT at the stiffness
    samples, the circular convolution folds nothing into harmonics 0..H, so the
    balance equals Hill's to round-off wherever the teeth stay in contact."""
    case = _pair_case()
    system = response_system(case, case.scenes[0], samples=2**12)
    problem = BacklashProblem(system, BacklashLaw(np.array([1e-4])), 8, samples=2**12)
    for speed in (300.0, 700.0):
        w = system.omega(speed)
        x, _, ok = newton(
            lambda z, w=w: problem.residual(z, w)[:2], problem.static_guess(), tolerance=1e-22
        )
        assert ok
        hill = problem.from_hill(solve_hill(system, w, 8).deflection)
        assert np.abs(x - hill).max() <= 1e-10 * np.abs(hill).max()
        assert problem.signals(x)[0].min() > 0


@pytest.mark.parametrize("damper", [None, 0.1])
def test_jacobian_matches_central_differences(damper):
    """The analytic AFT Jacobian and frequency derivative against central differences
    of the residual, on a smoothed law (eps = 0.02) with contact loss and coast impacts,
    with the mesh damper on throughout or parting with the teeth: the differences'
    error is O(d^2 g'''') ~ (1e-6)^2 / eps^3, far under the 1e-6 asked."""
    system = oscillator_system(ZETA, F_M, 0.3, (0.2,))
    dampers = None if damper is None else np.array([damper])
    law = BacklashLaw(np.array([0.3]), smoothing=0.02, mesh_damping=dampers)
    problem = BacklashProblem(system, law, 6)
    rng = np.random.default_rng(3)
    x = problem.static_guess() + 0.3 * rng.standard_normal(problem.size)
    deflection = problem.signals(x)[0][:, 0]
    assert deflection.max() > 0 and deflection.min() < -0.3  # all three flank states
    w = 0.9
    _, jac, dw = problem.residual(x, w)
    d = 1e-6
    numeric = np.empty_like(jac)
    for k in range(problem.size):
        e = np.zeros(problem.size)
        e[k] = d
        numeric[:, k] = (problem.residual(x + e, w)[0] - problem.residual(x - e, w)[0]) / (2 * d)
    assert np.abs(jac - numeric).max() <= 1e-6 * np.abs(jac).max()
    numeric_w = (problem.residual(x, w + d)[0] - problem.residual(x, w - d)[0]) / (2 * d)
    assert np.abs(dw - numeric_w).max() <= 1e-6 * np.abs(dw).max()


def test_newton_converges_quadratically_on_a_smooth_case():
    """Plain Newton (no line search) on the smoothed law (eps = 0.01), from the solution
    at a frequency 1 % away, where the drive flanks part every period: quadratic
    convergence, r_{k+1} <= C r_k^2 with C bounded (C < 100) down to r_k ~ 1e-6, where a
    linear rate rho would show as C = rho / r_k > 1e5 rho."""
    system = oscillator_system(ZETA, F_M, F_A)
    problem = BacklashProblem(system, BacklashLaw(np.array([GAP]), smoothing=0.01), HARMONICS)
    dataset = continue_response(system, problem.law, (1.2, 0.95), harmonics=HARMONICS,
                                stability=False)  # fmt: skip
    x = dataset.deflection_coefficients.values[-1].reshape(-1)  # upper branch near 0.95
    w = float(dataset.frequency.values[-1]) * 1.01
    residuals = []
    for _ in range(8):
        r, jac, _ = problem.residual(x, w)
        residuals.append(float(np.abs(r).max()))
        if residuals[-1] < 1e-15:
            break
        x = x - np.linalg.solve(jac, r)
    assert residuals[-1] < 1e-15 and len(residuals) <= 6
    assert problem.signals(x)[0].min() < 0  # the flanks do part
    pairs = [(a, b) for a, b in zip(residuals, residuals[1:]) if b > 1e-13]
    assert min(a for a, _ in pairs) < 1e-5  # the asymptotic regime is reached
    assert max(b / a**2 for a, b in pairs) < 100


def test_gearbox_orbit_multipliers_match_the_flow():
    """The spur-pair model at 50 N m loses contact through its main resonance (the
    static mesh deflection 3.9 um against a 94 um normal backlash); its upper branch at
    7500 rpm is unstable by period doubling (a multiplier near -1.37).  The balance's
    multipliers against forward differences of the period map of the modal equations,
    integrated by DOP853 with the sampled stiffness: the orbit is truncated at H = 16
    (it closes on itself to ~1e-2 under the integrator, the stiffness jumping at the
    tooth-pair changes), so 2 % on the multiplier, whose distance from -1 is 37 %."""
    case = _pair_case()
    system = response_system(case, case.scenes[0], samples=2**12, torque=50.0)
    law = BacklashLaw(line_of_action_backlash(case, system.model, "tooth_separation"))
    assert law.backlash[0] == pytest.approx(0.1e-3 * math.cos(math.radians(20)))
    dataset = continue_response(system, law, (9000.0, 7500.0), harmonics=16, stability=False)
    problem = BacklashProblem(system, law, 16)
    w = system.omega(7500.0)
    x, _, ok = newton(
        lambda z: problem.residual(z, w)[:2],
        dataset.deflection_coefficients.values[-1].reshape(-1),
        tolerance=1e-18,
    )
    assert ok and problem.signals(x)[0].min() < 0  # the teeth part
    got = problem.multipliers(x, w)[0]
    modal = problem.modal_coefficients(x, w)
    k = np.arange(1, 17)[:, None]
    start = np.concatenate(
        [modal[0].real + 2 * modal[1:].real.sum(0), 2 * np.real(1j * k * w * modal[1:]).sum(0)]
    )
    rows, lam, damping, force = (system.mesh_rows, system.eigenvalues, system.damping,
                                 system.force)  # fmt: skip
    kbar, samples, sign = system.mean_stiffness, system.stiffness[:, 0], system.contact_sign
    backlash, n = law.backlash, lam.size

    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        y, v = z[:n], z[n:]
        delta = rows @ y
        tau = (w * t / (2 * math.pi)) % 1.0 * samples.size
        i = int(tau)
        stiffness = samples[i % samples.size] + (tau - i) * (
            samples[(i + 1) % samples.size] - samples[i % samples.size]
        )
        c = sign * delta
        r = sign * stiffness * (np.maximum(c, 0) + np.minimum(c + backlash, 0)) - kbar * delta
        return np.concatenate([v, force - damping @ v - lam * y - rows.T @ r])

    def period(z0: np.ndarray) -> np.ndarray:
        sol = scipy.integrate.solve_ivp(
            rhs, (0.0, 2 * math.pi / w), z0, method="DOP853", rtol=1e-10, atol=1e-16
        )
        return sol.y[:, -1]

    end = period(start)
    assert np.abs(end - start).max() < 2e-2 * np.abs(start).max()  # the orbit closes
    scale = np.concatenate([np.full(n, 1e-9), np.full(n, 1e-9 * w)])
    jac = np.empty((2 * n, 2 * n))
    for col in range(2 * n):
        e = np.zeros(2 * n)
        e[col] = scale[col]
        jac[:, col] = (period(start + e) - end) / scale[col]
    flow = np.linalg.eigvals(jac)
    expected = flow[np.argmax(np.abs(flow))]
    assert expected.real < -1.2 and abs(expected.imag) < 1e-6  # period doubling
    assert got.real == pytest.approx(expected.real, rel=2e-2)
    assert abs(got.imag) < 1e-9


def test_linear_sweep_hook_continues_where_the_teeth_part(tmp_path):
    """The hook for the linear sweep: nothing where the linear solution keeps the teeth
    together (5000-6500 rpm), and where it parts them, a softening loop whose up-sweep
    fold lies past the first speed the linear sweep separates (on the lower branch the
    balance is the linear one until the teeth part) and whose down-sweep fold lies
    below it; every point of the loop's return branch has the teeth parting."""
    case = _pair_case()
    system = response_system(case, case.scenes[0], samples=2**12, torque=50.0)
    law = case_law(case, system)
    assert law.backlash == pytest.approx([0.1e-3 * math.cos(math.radians(20))])
    assert law.mesh_damping is None  # the linear model's damper stays on in the gap
    switched = case_law(case, system, smoothing=4e-8, switched_dampers=True)
    assert switched.mesh_damping == pytest.approx([2e-6 * 3e8])  # beta kbar, the kernel's
    with pytest.raises(ValueError, match="smoothing"):
        case_law(case, system, switched_dampers=True)
    quiet = sweep_system(system, np.linspace(5000.0, 6500.0, 7), harmonics=16, stability=False)
    assert separated_response(system, quiet, law) is None
    speeds = np.linspace(6500.0, 7500.0, 41)
    linear = sweep_system(system, speeds, harmonics=16, stability=False)
    onset = speeds[np.argmax(linear.separation.values[:, 0])]
    dataset = separated_response(system, linear, law, stability=False)
    (up,), (down,) = dataset.attrs["up_sweep_jumps"], dataset.attrs["down_sweep_jumps"]
    assert onset - (speeds[1] - speeds[0]) <= up and down < onset
    first, second = np.flatnonzero(dataset.turning.values)
    assert dataset.separation.values[first + 1 : second + 1, 0].all()
    assert dataset.speed.values[-1] >= 7500.0 and dataset.attrs["finished"]
    assert "stable" not in dataset  # no multipliers asked: no flag that would read 0
    dataset.to_netcdf(tmp_path / "branch.nc")  # every attribute is one NetCDF takes
    back = xr.open_dataset(tmp_path / "branch.nc")
    assert np.atleast_1d(back.attrs["up_sweep_jumps"]) == pytest.approx([up])
    back.close()


def _cubic(x: np.ndarray, p: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """R = x^3 - x - p: an S-shaped branch with folds at x = -+1/sqrt(3)."""
    return x**3 - x - p, np.array([[3 * x[0] ** 2 - 1]]), np.array([-1.0])


def test_continuation_locates_folds_of_an_s_curve():
    """p = x^3 - x folds at p = +-2 / (3 sqrt 3) (closed form): the branch from x = -2
    passes both, crossing each by a step of at most fold_step = 2e-3, and the Hermite
    interpolant places them within 1e-9 (its error is O(h^4): ~1e-12 at that step; a
    step of 0.1 across the fold left 5e-5), the first a largest p (an up sweep jumps
    there), the second a smallest."""
    branch = continue_branch(
        _cubic, np.array([-2.0]), -6.0, 6.0, x_scale=1.0, p_scale=1.0, step_max=0.1
    )
    assert branch.finished
    fold = 2 / (3 * math.sqrt(3))
    (first, second) = branch.turning
    assert first["kind"] == 1 and first["parameter"] == pytest.approx(fold, abs=1e-9)
    assert second["kind"] == -1 and second["parameter"] == pytest.approx(-fold, abs=1e-9)
    assert first["state"][0] == pytest.approx(-1 / math.sqrt(3), abs=1e-2)


def test_continuation_passes_a_corner():
    """x = 1 - p up to p = 1 and 0.3 (p - 1) past it: the branch turns by 62 degrees
    at p = 1 whatever the step (more than MAX_TURN): it is followed through the corner
    to the end, on the exact branch, and a corner is no fold."""

    def corner(x: np.ndarray, p: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        slope = -1.0 if p < 1 else 0.3
        return x - slope * (p - 1), np.eye(1), np.array([-slope])

    branch = continue_branch(corner, np.array([1.0]), 0.0, 2.0, x_scale=1.0, p_scale=1.0)
    assert branch.finished and branch.turning == []
    p = branch.parameter
    assert np.abs(branch.states[:, 0] - np.where(p < 1, 1 - p, 0.3 * (p - 1))).max() < 1e-12


def test_coast_flank_impacts_match_a_long_run():
    """With a gap of 0.2 and F_a = 0.1 the teeth cross the backlash and strike the coast
    flanks every period (double-sided impacts, x < -0.2).  Newton from the linear
    solution finds the orbit at 0.8 rad/s (H = 32; the only one there, a continuation
    from 1.5 rad/s crosses 0.8 once); started under RK4 and run 200 periods (a
    transient decays by exp(-2 pi 0.05 0.8 200) ~ 1e-22), it comes back to itself
    within 2e-4 and keeps its peak-to-peak within 1e-3 (the truncation at H = 32 of an
    orbit with kinks, and RK4's O(h^2) error at each kink crossing)."""
    forcing, gap, w = 0.1, 0.2, 0.8
    system = oscillator_system(ZETA, F_M, forcing)
    problem = BacklashProblem(system, BacklashLaw(np.array([gap])), 32)
    x, _, ok = newton(
        lambda z: problem.residual(z, w)[:2], problem.linear_solution(w), tolerance=1e-13
    )
    assert ok
    deflection = problem.signals(x, 4096)[0][:, 0]
    assert deflection.min() < -gap  # coast flank contact
    k = np.arange(1, 33)
    x0, v0 = x[0] + x[1:33].sum(), float((k * w * x[33:]).sum())
    end, _, amplitude = _periods(x0, v0, w, 200, forcing, gap)
    assert abs(end - x0) < 2e-4
    assert amplitude == pytest.approx(np.ptp(deflection), abs=1e-3)


def _switched_flow_multipliers(
    x0: float, v0: float, w: float, eps: float
) -> tuple[np.ndarray, float]:
    """Multipliers of the period map of x'' + 2 ZETA g'(x) x' + g(x) = F_M + F_A cos wt,
    g the smoothed flank law: the whole damper (the mesh's) acts only in contact.
    Central differences of DOP853 at rtol 1e-11; also how far one period from the
    start lands from it."""

    def rhs(t: float, y: np.ndarray) -> list[float]:
        x, v = y
        root, coast = math.sqrt(x * x + eps * eps), x + GAP
        root_b = math.sqrt(coast * coast + eps * eps)
        g = 0.5 * (x + root) + 0.5 * (coast - root_b)
        slope = 0.5 * (1 + x / root) + 0.5 * (1 - coast / root_b)
        return [v, F_M + F_A * math.cos(w * t) - 2 * ZETA * slope * v - g]

    def flow(state: np.ndarray) -> np.ndarray:
        sol = scipy.integrate.solve_ivp(
            rhs, (0.0, 2 * math.pi / w), state, method="DOP853", rtol=1e-11, atol=1e-13
        )
        return sol.y[:, -1]

    base, eps_fd = np.array([x0, v0]), 1e-5
    jac = np.array([(flow(base + e) - flow(base - e)) / (2 * eps_fd) for e in eps_fd * np.eye(2)])
    return np.linalg.eigvals(jac.T), float(np.abs(flow(base) - base).max())


def test_switched_mesh_damper_matches_the_flow():
    """The kernel's damper, on only while the flanks touch (all of the oscillator's
    damping is the mesh's: c_m = 2 ZETA), with eps = 0.01: at 0.85 rad/s the orbits
    on the lower branch (from the linear solution) and on the upper one (from the
    always-on damper's upper orbit) close on themselves under DOP853 to 1e-4, and the
    multipliers of the contact state's linearisation, damping switched per instant,
    equal the flow's within 0.5 % (128 segments, H = 16).  Without damping in the gap
    the upper orbit swings wider than with the damper on throughout."""
    eps, w = 0.01, 0.85
    system = oscillator_system(ZETA, F_M, F_A)
    always = BacklashProblem(system, BacklashLaw(np.array([GAP]), smoothing=eps), HARMONICS)
    law = BacklashLaw(np.array([GAP]), smoothing=eps, mesh_damping=np.array([2 * ZETA]))
    problem = BacklashProblem(system, law, HARMONICS)
    dataset = continue_response(system, always.law, (1.0, w), harmonics=HARMONICS,
                                stability=False)  # fmt: skip
    upper_always = dataset.deflection_coefficients.values[-1].reshape(-1)
    upper_always, _, ok = newton(lambda z: always.residual(z, w)[:2], upper_always, tolerance=1e-13)
    assert ok
    h, k = HARMONICS, np.arange(1, HARMONICS + 1)
    amplitudes = []
    for start in (problem.linear_solution(w), upper_always):
        x, _, ok = newton(lambda z: problem.residual(z, w)[:2], start, tolerance=1e-13)
        assert ok
        x0, v0 = x[0] + x[1 : h + 1].sum(), float((k * w * x[h + 1 :]).sum())
        flow, closure = _switched_flow_multipliers(x0, v0, w, eps)
        assert closure < 1e-4
        expected = flow[np.argmax(np.abs(flow))]
        got = problem.multipliers(x, w)[0]
        assert abs(got - expected) < 5e-3 * abs(expected)
        amplitudes.append(float(np.ptp(problem.signals(x, 2048)[0])))
    assert amplitudes[1] > 3 * amplitudes[0]  # two distinct orbits
    assert amplitudes[1] > np.ptp(always.signals(upper_always, 2048)[0])


def test_hook_starts_from_the_top_when_the_bottom_has_no_start():
    """At 0.5 rad/s a strong excitation (F_a = 0.2, gap 0.2) puts the oscillator in a
    superharmonic resonance where Newton from the linear solution finds nothing (the
    direct call says so); the hook then continues down from the top speed instead."""
    system = oscillator_system(ZETA, F_M, 0.2)
    law = BacklashLaw(np.array([0.2]))
    with pytest.raises(RuntimeError, match="no solution at the start"):
        continue_response(system, law, (0.5, 0.6), harmonics=16, stability=False)
    linear = xr.Dataset(
        {"separation": (("speed", "mesh"), np.ones((2, 1), dtype=np.int8))},
        coords={"speed": [0.5, 0.6]},
    )
    dataset = separated_response(system, linear, law, harmonics=16, stability=False)
    assert dataset.speed.values[0] == pytest.approx(0.6) and dataset.speed.values[-1] <= 0.5
    assert dataset.attrs["finished"]
