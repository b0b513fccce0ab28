"""Floquet multipliers against the Meissner equation's closed form, and the main
resonance of a spur pair against ISO 6336-1's n_E1."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.optimize

from pygear import Bearing, Case, Gear, Gearbox, Mesh, ParallelStage, RayleighDamping, Scene
from pygear.analysis.response import floquet_multipliers, forced_response, response_system

K0, EPSILON = 1.0, 0.1  # x'' + c x' + K0 (1 +- EPSILON) x = 0, unit mass


def _segment(stiffness: float, damping: float, time: float) -> np.ndarray:
    """Exact transfer matrix of x'' + c x' + k x = 0 over ``time`` (underdamped)."""
    sigma = damping / 2
    wd = math.sqrt(stiffness - sigma**2)
    c, s = math.cos(wd * time), math.sin(wd * time)
    return math.exp(-sigma * time) * np.array(
        [[c + sigma / wd * s, s / wd], [-stiffness / wd * s, c - sigma / wd * s]]
    )


def _closed_form(frequency: float, damping: float = 0.0) -> np.ndarray:
    """Monodromy of the rectangular wave: stiff half period, then soft half period."""
    half = math.pi / frequency
    return _segment(K0 * (1 - EPSILON), damping, half) @ _segment(K0 * (1 + EPSILON), damping, half)


def _multipliers(frequency: float, damping: float = 0.0) -> np.ndarray:
    stiffness = np.array([[[K0 * (1 + EPSILON)]], [[K0 * (1 - EPSILON)]]])
    return floquet_multipliers(stiffness, np.array([[damping]]), 2 * math.pi / frequency)


@pytest.mark.parametrize("frequency", [1.2, 1.9, 2.0, 2.1, 3.3])
@pytest.mark.parametrize("damping", [0.0, 0.05])
def test_meissner_multipliers_match_transfer_matrices(frequency, damping):
    """Two intervals of constant stiffness: the monodromy is exact, so the multipliers
    match the closed-form product's eigenvalues to round-off (1e-12, the Taylor
    exponential's truncation being 2e-14)."""
    expected = np.linalg.eigvals(_closed_form(frequency, damping))
    got = _multipliers(frequency, damping)
    assert np.sort(np.abs(got)) == pytest.approx(np.sort(np.abs(expected)), abs=1e-12)
    # Liouville: det Phi = exp(-c T) whatever the stiffness
    assert np.prod(got).real == pytest.approx(math.exp(-damping * 2 * math.pi / frequency))


def _first_tongue() -> tuple[float, float]:
    """Boundaries of the first instability tongue (excitation near 2 omega_0): where the
    closed-form trace reaches -2, bracketed on either side of 2 omega_0."""

    def trace(frequency: float) -> float:
        return float(np.trace(_closed_form(frequency))) + 2.0

    centre = 2 * math.sqrt(K0)
    low = scipy.optimize.brentq(trace, 0.8 * centre, centre, xtol=1e-14)
    high = scipy.optimize.brentq(trace, centre, 1.2 * centre, xtol=1e-14)
    return low, high


def test_first_instability_tongue():
    """Inside the tongue one multiplier leaves the unit circle, just outside both stay
    on it (undamped: |mu| = 1 to 1e-9); the boundaries agree with the first-order
    estimate 2 omega_0 (1 +- EPSILON / pi) to O(EPSILON^2): the square wave's first
    harmonic is h = 4 EPSILON / pi, and Mathieu's x'' + omega_0^2 (1 + h cos Omega t) x = 0
    is unstable for |Omega - 2 omega_0| < h omega_0 / 2 (Landau & Lifshitz, Mechanics,
    §27)."""
    low, high = _first_tongue()
    assert np.abs(_multipliers(0.5 * (low + high))).max() > 1 + 1e-3
    for outside in (low * (1 - 1e-4), high * (1 + 1e-4)):
        assert np.abs(_multipliers(outside)).max() == pytest.approx(1.0, abs=1e-9)
    centre = 2 * math.sqrt(K0)
    for boundary, sign in ((low, -1), (high, 1)):
        estimate = centre * (1 + sign * EPSILON / math.pi)
        assert abs(boundary - estimate) / centre < EPSILON**2


BEARING = 1e12  # N/m: stiff bearings, so the pair is nearly ISO's torsional model
MESH = 4e8  # N/m


def _spur_pair(contact_ratio: float, end_to_peak: float, beta: float) -> Case:
    """One spur pair, 23:41 teeth of 4 mm module at 20 deg, steel discs."""

    def gear(teeth: int) -> Gear:
        radius = 4e-3 * teeth * math.cos(math.radians(20)) / 2
        mass = 3.0 * (teeth / 23) ** 2
        inertia = 0.5 * mass * (radius / math.cos(math.radians(20))) ** 2
        return Gear(mass=mass, polar_inertia=inertia, tilt_inertia=inertia / 2,
                    base_radius=radius, teeth=teeth)  # fmt: skip

    bearing = Bearing(radial=BEARING, axial=BEARING, tilt=1e10, torsional=0.0)
    stage = ParallelStage(
        name="pair", input_gear=gear(23), output_gear=gear(41), input_bearing=bearing,
        output_bearing=bearing, overlap_ratio=0.0, base_helix_angle_deg=0.0,
        mesh=Mesh(stiffness=MESH, pressure_angle_deg=20.0, contact_ratio=contact_ratio,
                  end_to_peak=end_to_peak),
    )  # fmt: skip
    return Case(name="pair", gearbox=Gearbox(stages=(stage,)), formulation="improved",
                damping=RayleighDamping(0.0, beta),
                scenes=(Scene("modal", dof_set="planar"),))  # fmt: skip


def test_main_resonance_of_a_spur_pair_at_iso_n_e1():
    """ISO 6336-1 (method B): n_E1 = 30000 / (pi z1) sqrt(c_gamma_alpha / m_red) [rpm], in SI
    30 / (pi z1) sqrt(k / m_red) with m_red of the gears' J / r_b^2.

    The model's mesh mode differs from ISO's single-DOF one only by the bearings'
    compliance in series with the mesh, about k / k_bearing = 4e-4 in frequency.  The
    dynamic factor's peak over speed (contact ratio 2 and a flat parabola: a stiffness
    within 2 % of its mean, light damping zeta = 0.002) lies where the mesh frequency
    meets a natural frequency of the varying stiffness: between the frozen-time
    frequencies sqrt(k_min / k-bar) and sqrt(k_max / k-bar) of the model's, give or
    take the speed step."""
    case = _spur_pair(2.0, 0.9, 2e-7)
    stage = case.gearbox.stages[0]
    masses = [g.polar_inertia / g.base_radius**2 for g in (stage.input_gear, stage.output_gear)]
    reduced = masses[0] * masses[1] / (masses[0] + masses[1])
    n_e1 = 30 / (math.pi * 23) * math.sqrt(MESH / reduced)
    system = response_system(case, case.scenes[0])
    main = int(np.argmax(system.mesh_energy_share()))
    model_speed = system.natural_frequencies[main] / (
        system.fundamental_per_rad_s * system.mesh_order[0] * math.pi / 30
    )
    # each bearing k_b in series with the mesh along the line of action, softened by
    # its gear's translating mass at the mode (k_b - omega^2 m): f drops by at most
    # k / (k_b - omega^2 m_max) (half of the two bearings' 2 k / k_b, in a square root)
    omega = 2 * math.pi * system.natural_frequencies[main]
    heaviest = max(stage.input_gear.mass, stage.output_gear.mass)
    assert abs(model_speed / n_e1 - 1) <= MESH / (BEARING - omega**2 * heaviest)

    speeds = np.linspace(0.98, 1.02, 81) * n_e1
    dataset = forced_response(case, speeds, scene=case.scenes[0], harmonics=8, stability=False)
    peak = float(speeds[int(np.argmax(dataset.dynamic_factor.values[:, 0]))])
    k = system.stiffness[:, 0]
    step = (speeds[1] - speeds[0]) / model_speed
    low = math.sqrt(k.min() / k.mean()) - step
    high = math.sqrt(k.max() / k.mean()) + step
    assert low <= peak / model_speed <= high
    assert dataset.dynamic_factor.values.max() > 3  # a resonance, not a flat curve
    assert dataset.attrs["main_resonance_speed_rpm"] == pytest.approx(model_speed, rel=1e-12)


def test_unstable_second_tongue_flagged():
    """A rectangular-looking stiffness (contact ratio 1.6: +-30 %) opens the second
    parametric tongue at the main resonance; with light damping the Floquet multiplier
    leaves the unit circle there and the speed is flagged unstable, while 20 % away
    it is stable."""
    case = _spur_pair(1.6, 0.6, 2e-7)
    system = response_system(case, case.scenes[0])
    main = int(np.argmax(system.mesh_energy_share()))
    model_speed = system.natural_frequencies[main] / (system.fundamental_per_rad_s * math.pi / 30)
    speeds = np.array([0.8, 0.97, 0.99, 1.01, 1.2]) * model_speed
    dataset = forced_response(case, speeds, scene=case.scenes[0], harmonics=8)
    assert dataset.stable.values[0] == 1 and dataset.stable.values[-1] == 1
    assert dataset.stable.values[1:4].min() == 0
    assert dataset.floquet_multiplier.values[1:4].max() > 1.0
