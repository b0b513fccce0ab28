"""Rolling bearings in the Newmark kernel (fortran/rolling_bearing.f90): a shaft of
mass m in one bearing, x, y and its rotation theta as DOFs, a constant radial force on
x.  References: the quasi-static load distribution (Newton on the contact energy,
:func:`load_distribution`), Stribeck's 4.37 (Harris & Kotzalas 2007, ch. 7), the
closed-form cage rate and BPFO (Harris & Kotzalas ch. 8; Randall & Antoni 2011,
eqs. 1-4), and the energy of the contact law summed in a bare NumPy loop."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pygear.analysis.condition.bearing_load import (
    contact_constant,
    load_distribution,
    varying_compliance,
)
from pygear.analysis.time.bearing_element import (
    bearing_constants,
    defect_rows,
    static_displacement,
)
from pygear.kernel.bearing_terms import BearingTerms
from pygear.kernel.newmark import BandedNewmark, KernelProbe, LawArrays
from pygear.model.rolling_bearing import BearingDefect, RollingBearing

SKF_6205 = RollingBearing(
    "DE", "ball", elements=9, pitch_diameter=0.03904, element_diameter=0.00794,
    diametral_clearance=10e-6,
)  # fmt: skip
"""The CWRU drive-end bearing's geometry (Randall & Antoni 2011, sec. 6)."""


def shaft_in_bearing(
    bearing: RollingBearing,
    force: float,
    *,
    mass: float = 2.0,
    spring: float | None = None,
    damping_ratio: float = 1.0,
    time_step: float = 1e-5,
    defects: tuple[tuple, ...] = (),
    tolerance: float = 1e-10,
    integrator: str = "newmark",
) -> BandedNewmark:
    """A shaft (x, y, theta) in ``bearing`` under ``force`` on x; the kernel's spring
    k_r (the linearised stiffness along the load unless given) sits in K0 and the
    damper c = 2 zeta sqrt(k_r m) on x and y."""
    if spring is None:
        spring = float(load_distribution(bearing, force).stiffness.values[0, 0])
    inertia = 1e-3
    mass_matrix = np.diag([mass, mass, inertia])
    stiffness = np.diag([spring, spring, 0.0])
    c = 2.0 * damping_ratio * math.sqrt(spring * mass)
    damping = np.diag([c, c, 0.0])
    rows = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [0, 0, 0]])
    ints = np.array([d[0] for d in defects], dtype=np.int32).reshape(-1, 3).T
    reals = np.array([d[1] for d in defects], dtype=float).reshape(-1, 3).T
    terms = BearingTerms(
        (bearing.name,), np.array([bearing.elements]),
        bearing_constants(bearing, spring)[:, None], rows, ints, reals,
    )  # fmt: skip
    return BandedNewmark(
        mass_matrix, damping, stiffness, time_step, bearings=terms, equivalent_load="iterate",
        drive=LawArrays("constant", (force, 0.0, 0.0, 0.0)),
        input_weights=np.array([1.0, 0.0, 0.0]), tolerance=tolerance, integrator=integrator,
    )  # fmt: skip


PROBES = [
    KernelProbe("x", "displacement", np.array([1.0, 0.0, 0.0])),
    KernelProbe("y", "displacement", np.array([0.0, 1.0, 0.0])),
    KernelProbe("vx", "velocity", np.array([1.0, 0.0, 0.0])),
    KernelProbe("vy", "velocity", np.array([0.0, 1.0, 0.0])),
]


def contact_energy(bearing: RollingBearing, x, y, cage) -> np.ndarray:
    """sum_j K/(n+1) <delta_j>^(n+1), a bare loop over the elements."""
    k_n, n = contact_constant(bearing), bearing.load_exponent
    energy = np.zeros_like(np.asarray(x, dtype=float))
    for j in range(bearing.elements):
        psi = cage + 2 * math.pi * j / bearing.elements
        delta = x * np.cos(psi) + y * np.sin(psi) - bearing.diametral_clearance / 2
        energy += k_n / (n + 1) * np.maximum(delta, 0.0) ** (n + 1)
    return energy


@pytest.mark.parametrize(
    ("bearing", "force", "cage_deg"),
    [
        (SKF_6205, 2e3, 0.0),
        (SKF_6205, 500.0, 20.0),  # between two elements, 5 of 9 loaded
        (
            RollingBearing(
                "CRB",
                "roller",
                elements=17,
                pitch_diameter=0.1,
                element_diameter=0.014,
                roller_length=0.014,
                diametral_clearance=-5e-6,
            ),  # fmt: skip
            30e3,
            7.0,
        ),
    ],
)
def test_static_equilibrium_matches_the_load_distribution(bearing, force, cage_deg):
    """Critically damped, the shaft settles where the quasi-static load distribution
    puts it.  The kernel iterates to 1e-10 of the force; after 4000 steps
    (exp(-omega t) < 1e-100) what is left is that tolerance times the compliance."""
    solver = shaft_in_bearing(bearing, force)
    theta = 2.0 * math.radians(cage_deg) / (1.0 - bearing.gamma)  # cage = (1 - gamma) theta / 2
    result = solver.run(4000, PROBES[:2], q0=np.array([0.0, 0.0, theta]))
    expected = load_distribution(bearing, force, cage_angle_deg=cage_deg).displacement.values
    np.testing.assert_allclose(result.samples[:2, -1], expected, rtol=1e-7, atol=1e-7 * expected[0])


def test_stribeck_from_the_kernel_equilibrium():
    """Zero clearance, many balls: Q_max Z / F_r = 1 / J_r(0.5) = 4.37 (Stribeck; Harris
    & Kotzalas 2007, Table 7.1: J_r = 0.2288), Q_max = K_n delta_max^(3/2) from the
    kernel's equilibrium.  Z = 60 differs from the continuous integral by 1e-4."""
    bearing = RollingBearing(
        "S", "ball", elements=60, pitch_diameter=0.3, element_diameter=0.018,
    )  # fmt: skip
    force = 50e3
    result = shaft_in_bearing(bearing, force, mass=10.0).run(4000, PROBES[:1])
    q_max = contact_constant(bearing) * result.samples[0, -1] ** 1.5
    assert q_max * bearing.elements / force == pytest.approx(1 / 0.2288, rel=1e-3)


def test_varying_compliance_at_cage_rate_times_z():
    """A healthy bearing on a shaft turning at 25 Hz under a constant load: the
    displacement varies at Z f_c = BPFO (outer ring and load in the housing), its
    largest line within one bin of the closed form, its amplitude that of the
    quasi-static varying compliance's fundamental within 1.5 % (the response at 90 Hz
    of a 1.3 kHz oscillator is quasi-static to (f / f_n)^2 ~ 0.5 %)."""
    bearing, force, shaft_hz = SKF_6205, 2e3, 25.0
    dt = 1e-5
    solver = shaft_in_bearing(bearing, force, damping_ratio=0.2, time_step=dt)
    steps = 100_000  # 1 s: 0.5 Hz bins after the start-up is dropped
    v0 = np.array([0.0, 0.0, 2 * math.pi * shaft_hz])
    result = solver.run(steps + 20_000, PROBES[:1], v0=v0, decimation=10)
    x = result.samples[0, 2000:]
    rate = 1.0 / (10 * dt)
    spectrum = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size)))
    freq = np.fft.rfftfreq(x.size, 1.0 / rate)
    bpfo = 0.5 * bearing.elements * shaft_hz * (1 - bearing.gamma)
    assert abs(freq[np.argmax(spectrum[1:]) + 1] - bpfo) <= freq[1]
    quasi = varying_compliance(bearing, force, points=721).displacement_x.values[:-1]
    expected = 2 * abs(np.mean(quasi * np.exp(-2j * math.pi * np.arange(quasi.size) / quasi.size)))
    t = np.arange(x.size) / rate
    basis = np.column_stack(
        [np.ones_like(t)]
        + [f(2 * math.pi * k * bpfo * t) for k in (1, 2, 3) for f in (np.cos, np.sin)]
    )
    coefficients = np.linalg.lstsq(basis, x, rcond=None)[0]
    assert math.hypot(*coefficients[1:3]) == pytest.approx(expected, rel=0.015)


def test_outer_race_spall_unloads_once_per_element_pass():
    """A spall on the stationary outer race at the load: the shaft drops toward it each
    time an element rolls into it, 1 / BPFO apart (to a sample of the record)."""
    bearing, force, shaft_hz, dt = SKF_6205, 2e3, 25.0, 1e-5
    defect = BearingDefect("outer", width=1e-3, depth=20e-6)
    radius = 0.5 * (bearing.pitch_diameter + bearing.element_diameter)
    d = bearing.element_diameter
    drop = min(defect.depth, d / 2 - math.sqrt(d * d / 4 - defect.width**2 / 4))
    solver = shaft_in_bearing(
        bearing, force, damping_ratio=0.2, time_step=dt,
        defects=(((1, 1, 1), (0.0, defect.width / radius, drop)),),
    )  # fmt: skip
    v0 = np.array([0.0, 0.0, 2 * math.pi * shaft_hz])
    x = solver.run(60_000, PROBES[:1], v0=v0).samples[0, 10_000:]
    healthy = shaft_in_bearing(bearing, force, damping_ratio=0.2, time_step=dt)
    x0 = healthy.run(60_000, PROBES[:1], v0=v0).samples[0, 10_000:]
    drops = x - x0
    assert drops.max() > 0.5 * drop  # the shaft follows the element into the spall
    entries = np.flatnonzero((drops[1:] > 0.25 * drop) & (drops[:-1] <= 0.25 * drop))
    bpfo = 0.5 * bearing.elements * shaft_hz * (1 - bearing.gamma)
    np.testing.assert_allclose(np.diff(entries) * dt, 1 / bpfo, atol=1.01 * dt)


def test_impacts_at_clearance_closure_keep_the_energy():
    """A shaft dropped from the bearing's centre across 50 um of clearance, undamped:
    it falls, strikes the elements and bounces for 20 000 steps.  With average
    acceleration the discrete energy (kinetic + contact - work of the force) holds to
    the iteration's tolerance per step; it is checked to 1e-3 of the work done to the
    first contact (the trapezoidal rule's error of the Hertz force over one impact
    step bounds the rest), and the deepest point against the energy balance
    U(x_max) = F x_max solved by bisection (2e-3: the deepest sample may miss the
    deepest instant by a step)."""
    bearing = RollingBearing(
        "C", "ball", elements=9, pitch_diameter=0.03904, element_diameter=0.00794,
        diametral_clearance=50e-6,
    )  # fmt: skip
    force = 2e3
    spring = float(load_distribution(bearing, force).stiffness.values[0, 0])
    solver = shaft_in_bearing(
        bearing, force, spring=spring, damping_ratio=0.0, time_step=2e-6, tolerance=1e-12
    )
    result = solver.run(20_000, PROBES)
    x, y, vx, vy = result.samples
    energy = 0.5 * 2.0 * (vx**2 + vy**2) + contact_energy(bearing, x, y, 0.0) - force * x
    scale = force * bearing.diametral_clearance / 2
    assert np.abs(energy - energy[0]).max() < 1e-3 * scale
    low, high = bearing.diametral_clearance / 2, 1e-3
    for _ in range(100):
        mid = 0.5 * (low + high)
        if contact_energy(bearing, mid, 0.0, 0.0) < force * mid:
            low = mid
        else:
            high = mid
    assert x.max() == pytest.approx(low, rel=2e-3)
    # the bounce sideways (rounding breaks the symmetry about x; the bouncing orbit is
    # unstable across it) stays inside the ring the energy allows
    assert np.hypot(x, y).max() <= low * (1 + 2e-3)


STIFF = RollingBearing(
    "H", "ball", elements=9, pitch_diameter=0.03904, element_diameter=0.00794,
    diametral_clearance=20e-6,
)  # fmt: skip


def dropped_energy(time_step: float, steps: int, integrator: str = "newmark"):
    """A light shaft (0.05 kg: f_n ~ 16 kHz in contact) dropped across STIFF's
    clearance under 5 kN, undamped: its discrete energy history and the run's counters."""
    force, mass = 5e3, 0.05
    solver = shaft_in_bearing(
        STIFF, force, mass=mass, damping_ratio=0.0, time_step=time_step, integrator=integrator
    )
    result = solver.run(steps, PROBES)
    x, y, vx, vy = result.samples
    energy = 0.5 * mass * (vx**2 + vy**2) + contact_energy(STIFF, x, y, 0.0) - force * x
    assert np.all(np.isfinite(result.samples))
    return energy, result, force


def test_impact_energy_error_is_second_order():
    """The energy error of average acceleration through the impacts is the trapezoidal
    rule's on the Hertz force: a quarter of the step takes it down at least 8 times
    (second order allows 16; measured 10-25)."""
    coarse, _, _ = dropped_energy(2e-5, 500)
    fine, _, _ = dropped_energy(5e-6, 2000)
    assert np.abs(fine).max() < np.abs(coarse).max() / 8


@pytest.mark.parametrize("integrator", ["newmark", "generalized-alpha"])
def test_stiff_contact_long_run_stays_bounded(integrator):
    """200 000 steps of 2e-5 s (omega dt ~ 2 in contact), impacts at every bounce: the
    iteration converges every step; with average acceleration the energy error, a
    sum of each impact's trapezoidal-rule error with either sign, stays a bounded
    fraction of the drop's work F x_max (measured 0.17 and 0.25 of its 0.47 J on two
    builds whose rounding differs: the bouncing orbit is chaotic; 0.4 allowed);
    generalized-alpha damps the bounce out and rests at the quasi-static equilibrium's
    energy."""
    energy, result, force = dropped_energy(2e-5, 200_000, integrator)
    x = result.samples[0]
    work = force * x.max()
    assert result.counters["max_iterations"] < 50
    if integrator == "newmark":
        assert np.abs(energy).max() < 0.4 * work
    else:
        rest = load_distribution(STIFF, force).displacement.values[0]
        expected = float(contact_energy(STIFF, rest, 0.0, 0.0)) - force * rest
        assert energy[-1] == pytest.approx(expected, rel=1e-6)
        assert energy.max() < 0.01 * work  # the numerical damping only takes energy


def test_turning_shaft_long_run_settles():
    """A turning shaft with clearance (the load zone opens and closes as the elements
    pass) and 5 % damping, 3 s: the response settles into the periodic motion the cage
    drives; its peak-to-peak over the last second equals that over the second before
    to 1e-6 (no growth; the transient decayed by exp(-0.05 omega t) ~ 1e-100)."""
    bearing = RollingBearing(
        "C", "ball", elements=9, pitch_diameter=0.03904, element_diameter=0.00794,
        diametral_clearance=30e-6,
    )  # fmt: skip
    solver = shaft_in_bearing(bearing, 1e3, damping_ratio=0.05, time_step=1e-5)
    v0 = np.array([0.0, 0.0, 2 * math.pi * 25.0])
    x = solver.run(300_000, PROBES[:1], v0=v0, decimation=5).samples[0]
    second = 20_000
    later, last = x[-2 * second : -second], x[-second:]
    assert np.ptp(last) == pytest.approx(np.ptp(later), rel=1e-6)
    assert np.ptp(last) > 1e-9  # it does vary: the elements pass the load zone


def test_waviness_and_wear_shift_the_equilibrium_as_the_contact_energy_says():
    """Outer-race waviness (order 3, 2 um, at 30 deg) and 3 um of wear (clearance
    P_d + 2 w): the kernel's equilibrium is the minimum of the contact energy
    U = sum K/(n+1) <delta_j>^(n+1) - F x with delta_j = x cos psi_j + y sin psi_j
    - P_d/2 - w + A cos(N (psi_j - phi)), found here by SciPy's minimiser (to 1e-6 of
    the displacement)."""
    from scipy.optimize import minimize

    from pygear.model.rolling_bearing import DistributedFault

    fault = DistributedFault("outer", 3, 2e-6, 30.0, wear=3e-6)
    bearing = dataclasses.replace(SKF_6205, faults=(fault,))
    force = 2e3
    spring = float(load_distribution(SKF_6205, force).stiffness.values[0, 0])
    rows = tuple(defect_rows(bearing, 1))  # the waviness as the case's runs pass it
    assert rows == (((1, 1, 2), (math.radians(30.0), 3.0, 2e-6)),)
    solver = shaft_in_bearing(bearing, force, spring=spring, defects=rows)
    x, y = solver.run(4000, PROBES[:2]).samples[:, -1]

    k_n, n = contact_constant(SKF_6205), SKF_6205.load_exponent
    psi = 2 * math.pi * np.arange(SKF_6205.elements) / SKF_6205.elements
    crest = 2e-6 * np.cos(3 * (psi - math.radians(30.0)))

    def energy(q):
        delta = q[0] * np.cos(psi) + q[1] * np.sin(psi) - 5e-6 - 3e-6 + crest
        return (k_n / (n + 1) * np.sum(np.maximum(delta, 0) ** (n + 1)) - force * q[0]) * 1e3

    best = minimize(energy, [3e-5, 0.0], method="Nelder-Mead",
                    options={"xatol": 1e-13, "fatol": 1e-16, "maxiter": 20000})  # fmt: skip
    np.testing.assert_allclose([x, y], best.x, atol=1e-6 * abs(best.x[0]))
    assert abs(y) > 1e-8  # the waviness pushes the shaft sideways: something to match


@pytest.mark.parametrize("force", [500.0, 2e3])
def test_loaded_start_solves_the_bearing_law(force):
    """A run's loaded start with rolling bearings (``static_displacement``, Newton on
    K q + N(q) = f from the springs' deflection) lands where the quasi-static load
    distribution puts the shaft, to 1e-8."""
    spring = float(load_distribution(SKF_6205, 2e3).stiffness.values[0, 0])
    rows = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [0, 0, 0]])
    terms = BearingTerms(
        ("DE",), np.array([9]), bearing_constants(SKF_6205, spring)[:, None], rows,
        np.zeros((3, 0), int), np.zeros((3, 0)),
    )  # fmt: skip
    stiffness = np.diag([spring, spring, 1.0])  # the shaft's angle held for the solve
    load = np.array([force, 0.0, 0.0])
    q = static_displacement(terms, stiffness, load, np.linalg.solve(stiffness, load))
    expected = load_distribution(SKF_6205, force).displacement.values
    np.testing.assert_allclose(q[:2], expected, rtol=1e-8, atol=1e-8 * expected[0])
