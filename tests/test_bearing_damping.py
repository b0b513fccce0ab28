"""Contact damping of rolling bearings in the Newmark kernel (fortran/rolling_bearing.f90):
a viscous damper c_c on every rolling-element contact, on the contact's approach rate,
acting only while that element is loaded.  References: the restitution of a
Kelvin-Voigt contact, e = exp(-pi zeta / sqrt(1 - zeta^2)) (a linear spring and damper
in parallel, left when the deflection returns to zero: half a damped period of the
free oscillator), the contact energy summed in a bare NumPy loop, and the quasi-static
load distribution."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pygear.analysis.condition.bearing_load import contact_constant, load_distribution
from pygear.analysis.time.bearing_element import bearing_constants
from pygear.errors import CaseError
from pygear.kernel.bearing_terms import BearingTerms
from pygear.kernel.newmark import BandedNewmark, KernelProbe, LawArrays
from pygear.model.rolling_bearing import RollingBearing

PROBES = [
    KernelProbe("x", "displacement", np.array([1.0, 0.0, 0.0])),
    KernelProbe("y", "displacement", np.array([0.0, 1.0, 0.0])),
    KernelProbe("vx", "velocity", np.array([1.0, 0.0, 0.0])),
    KernelProbe("vy", "velocity", np.array([0.0, 1.0, 0.0])),
]
ROWS = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [0, 0, 0]])


def shaft(param: np.ndarray, elements: int, mass: float, force: float, dt: float):
    """A free shaft (x, y, theta) of ``mass`` in one bearing of constants ``param``
    (its spring param[6] in K0, no other damping), ``force`` on x."""
    spring = float(param[6])
    terms = BearingTerms(
        ("B",), np.array([elements]), param[:, None], ROWS,
        np.zeros((3, 0), dtype=np.int32), np.zeros((3, 0)),
    )  # fmt: skip
    return BandedNewmark(
        np.diag([mass, mass, 1e-3]), np.zeros((3, 3)), np.diag([spring, spring, 0.0]), dt,
        bearings=terms, equivalent_load="iterate",
        drive=LawArrays("constant", (force, 0.0, 0.0, 0.0)),
        input_weights=np.array([1.0, 0.0, 0.0]), tolerance=1e-12,
    )  # fmt: skip


def restitution(zeta: float, dt: float) -> float:
    """Three elements with a linear contact law (n = 1, K = 1e8 N/m, the linearised
    contact) and 20 um clearance; a 1 kg shaft crosses the clearance at 0.1 m/s and
    strikes element 0 alone (the others stand at 120 and 240 deg), with
    c_c = 2 zeta sqrt(K m): the speed it flies back with over the speed it came."""
    mass, k, clearance, speed = 1.0, 1e8, 20e-6, 0.1
    c = 2.0 * zeta * math.sqrt(k * mass)
    param = np.array([k, 1.0, clearance, 1.0, 0.5, 0.5, k, c])
    # 100 us to the contact, ~330 us in it; the far elements (x = -2g) at ~760 us
    result = shaft(param, 3, mass, 0.0, dt).run(round(650e-6 / dt), PROBES,
                                                v0=np.array([speed, 0.0, 0.0]))  # fmt: skip
    x, y, vx, _ = result.samples
    touched = np.nonzero(x > clearance / 2)[0]
    assert touched.size * dt > 300e-6
    after = touched[-1] + round(20e-6 / dt)
    assert x[after] < clearance / 2 and x[-1] > -clearance  # flying free
    np.testing.assert_allclose(y, 0.0, atol=1e-15)
    return -vx[after] / speed


@pytest.mark.parametrize("zeta", [0.02, 0.1, 0.3])
def test_impact_restitution_is_the_kelvin_voigt_contacts(zeta):
    """The restitution against e = exp(-pi zeta / sqrt(1 - zeta^2)) at two steps.  The
    damper engages one step late (an element that touches within a step switches
    twice in its iteration): the impulse c_c v dt it misses is 2 zeta omega dt of the
    impact's m v; the trapezoidal rule adds (omega dt)^2 ~ 1e-4 at 1e-6 s.  So the
    error is bounded by 2 zeta omega dt + 2e-4 (measured 1e-4 .. 2e-3 at 1e-6 s,
    1e-4 .. 5e-4 at 2.5e-7 s)."""
    omega = 1e4  # sqrt(K / m) [rad/s]
    e = math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta**2))
    for dt in (1e-6, 2.5e-7):
        assert restitution(zeta, dt) == pytest.approx(e, rel=2 * zeta * omega * dt + 2e-4)


def hertz_energy(bearing: RollingBearing, x, y) -> np.ndarray:
    """sum_j K/(n+1) <delta_j>^(n+1) at cage angle 0, a bare loop over the elements."""
    k_n, n = contact_constant(bearing), bearing.load_exponent
    energy = np.zeros_like(np.asarray(x, dtype=float))
    for j in range(bearing.elements):
        psi = 2 * math.pi * j / bearing.elements
        delta = x * np.cos(psi) + y * np.sin(psi) - bearing.diametral_clearance / 2
        energy += k_n / (n + 1) * np.maximum(delta, 0.0) ** (n + 1)
    return energy


DROPPED = RollingBearing(
    "C", "ball", elements=9, pitch_diameter=0.03904, element_diameter=0.00794,
    diametral_clearance=50e-6,
)  # fmt: skip


def dropped(damping: float, steps: int):
    """A 2 kg shaft dropped from DROPPED's centre under 2 kN, contact damping
    ``damping`` [N s/m]: x, y, vx, vy and the energy kinetic + contact - work."""
    force, mass = 2e3, 2.0
    bearing = dataclasses.replace(DROPPED, contact_damping=damping)
    spring = float(load_distribution(bearing, force).stiffness.values[0, 0])
    solver = shaft(bearing_constants(bearing, spring), bearing.elements, mass, force, 2e-6)
    x, y, vx, vy = solver.run(steps, PROBES).samples
    energy = 0.5 * mass * (vx**2 + vy**2) + hertz_energy(bearing, x, y) - force * x
    return x, y, vx, vy, energy


def test_damped_hertz_contacts_only_take_energy_out():
    """Hertz contacts with c_c = 2e3 N s/m (a damping ratio of ~0.1 of the loaded
    contact): the energy never rises above any earlier value by more than the
    trapezoidal rule's error over an impact (1e-3 of the drop's work, as bounded
    undamped in test_bearing_kernel), the shaft loses most of the drop's work within
    40 ms and rests at the load distribution's deflection (1e-3: the remaining
    vibration)."""
    x, _, _, _, energy = dropped(2e3, 20_000)
    scale = 2e3 * DROPPED.diametral_clearance / 2
    rise = energy - np.minimum.accumulate(energy)
    assert rise.max() < 1e-3 * scale
    assert energy[-1] - energy[0] < -0.9 * scale
    static = float(load_distribution(DROPPED, 2e3).radial_deflection)
    assert x[-2000:].mean() == pytest.approx(static, rel=1e-3)


def test_zero_contact_damping_is_the_undamped_run():
    """A damper of 1e-9 N s/m (the damped code path, its force ~1e-10 N against
    2 kN) against none through the first two impacts: the histories agree to 1e-9 of
    the largest displacement (round-off of the two paths, grown through the bounce)."""
    x0, y0, *_ = dropped(0.0, 3000)
    x1, y1, *_ = dropped(1e-9, 3000)
    assert x0.max() > DROPPED.diametral_clearance / 2  # the impacts happened
    np.testing.assert_allclose(x1, x0, rtol=0, atol=1e-9 * np.abs(x0).max())
    np.testing.assert_allclose(y1, y0, rtol=0, atol=1e-9 * np.abs(x0).max())


@pytest.mark.parametrize("value", [-1.0, float("nan"), float("inf")])
def test_bad_contact_damping_is_refused_in_one_line(value):
    with pytest.raises(CaseError, match=r"contact_damping must be finite and >= 0"):
        dataclasses.replace(DROPPED, contact_damping=value)


def test_contact_damping_reaches_the_kernel_from_a_scene_parameter():
    """The study stage with a roller bearing on every pin: the scene parameter
    ``rolling_bearings.PB.contact_damping`` is every planet's kernel constant, and the
    run with it keeps the undamped run's mean pin deflection (a damper carries no
    static load; 1e-3 of it: the two runs' vibration about the mean differs)."""
    from pygear.analysis.time.transient import run_transient, transient_problem
    from pygear.model.case import Scene, load_case_module
    from pygear.model.transient_settings import Probe, TorqueLaw

    _, study = load_case_module("yang2016_planetary")
    pin = RollingBearing(
        "PB", "roller", elements=14, pitch_diameter=0.05, element_diameter=0.008,
        roller_length=0.008, diametral_clearance=5e-6, location="planetary.planet",
    )  # fmt: skip
    case = dataclasses.replace(study.case, rolling_bearings=(pin,))
    settings = dataclasses.replace(
        study.STEADY_SENSOR, duration=0.3, mean_window=0.3,
        drive=TorqueLaw.constant(200.0),
        load=TorqueLaw.generator(rated_drive_torque=200.0, exponent=study.LOAD_EXPONENT),
        equivalent_load="iterate", start_loaded=True,
        probes=(Probe("displacement", "planetary.planet1.zeta"),),
    )  # fmt: skip
    means = []
    for damping in (0.0, 500.0):
        scene = Scene(
            "damped", analyses=("transient",), formulation="improved", dof_set="planar",
            effects=("rolling_bearing_contact",), transient=settings,
            parameters={"rolling_bearings.PB.contact_damping": damping},
        )  # fmt: skip
        problem = transient_problem(case.for_scene(scene), scene)
        terms = problem.solver.bearings
        assert terms.size == 3
        np.testing.assert_array_equal(terms.param[7], damping)
        run = run_transient(case.for_scene(scene), scene, problem=problem)
        zeta = run.translation_displacement.values[0]
        assert np.isfinite(zeta).all()
        means.append(zeta[zeta.size // 2 :].mean())
    assert means[1] == pytest.approx(means[0], rel=1e-3)
